// The implicit step's contact penalty (penalty.h).
#include "penalty.h"

#include <math.h>

static bool fmPenaltyMeets(const fmBody* b, const fmCollider* c)
{
	return c->inUse && (b->filter.categoryBits & c->def.filter.maskBits) != 0 &&
	       (c->def.filter.categoryBits & b->filter.maskBits) != 0;
}

// Calls @p visit for every surface vertex inside a collider (depth -d) or within the thickness
// of its frozen plane of another body (depth thickness - d), with the outward normal.
typedef void fmPenaltyVisit(void* context, int vertex, double k, double depth, fmVec3 normal);

static void fmPenaltyPairs(const fmContactPenalty* p, const fmBody* b, const double* x,
                           fmPenaltyVisit* visit, void* context)
{
	if (p == NULL || b->surfaceVertex == NULL)
		return;
	for (int s = 0; s < b->surfaceVertexCount; ++s)
	{
		int i = b->surfaceVertex[s];
		if (b->pinned[i] == FM_PIN_ALL)
			continue;
		const double* plane = b->contactPlane ? b->contactPlane + 4 * (size_t)i : NULL;
		if (plane != NULL && !isnan(plane[3]))
		{
			fmVec3 n = fmMakeVec3(plane[0], plane[1], plane[2]);
			double depth = p->thickness - (fmDot(n, fmLoad(x, i)) - plane[3]);
			if (depth > 0.0)
				visit(context, i, p->stiffness * b->mass[i], depth, n);
		}
		for (int k = 0; k < p->colliderCount; ++k)
		{
			const fmCollider* c = &p->colliders[k];
			if (!fmPenaltyMeets(b, c))
				continue;
			fmVec3 n;
			double depth = -fmCollider_Distance(c, fmLoad(x, i), &n);
			if (depth > 0.0)
				visit(context, i, p->stiffness * b->mass[i], depth, n);
		}
	}
}

typedef struct fmEnergyVisit
{
	double energy;
	double* gradient;
} fmEnergyVisit;

static void fmVisitEnergy(void* context, int i, double k, double depth, fmVec3 n)
{
	fmEnergyVisit* e = context;
	e->energy += 0.5 * k * depth * depth;
	if (e->gradient)
	{
		e->gradient[3 * i] -= k * depth * n.x;
		e->gradient[3 * i + 1] -= k * depth * n.y;
		e->gradient[3 * i + 2] -= k * depth * n.z;
	}
}

double fmContactPenalty_Energy(const fmContactPenalty* p, const fmBody* b, const double* x,
                               double* gradient)
{
	fmEnergyVisit e = {0.0, gradient};
	fmPenaltyPairs(p, b, x, fmVisitEnergy, &e);
	return e.energy;
}

typedef struct fmHessianVisit
{
	const int* diagonal;
	double* values;
} fmHessianVisit;

static void fmVisitHessian(void* context, int i, double k, double depth, fmVec3 n)
{
	(void)depth;
	fmHessianVisit* h = context;
	double* block = h->values + 9 * (size_t)(h->diagonal ? h->diagonal[i] : i);
	const double u[3] = {n.x, n.y, n.z};
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c)
			block[3 * r + c] += k * u[r] * u[c];
}

void fmContactPenalty_AddHessian(const fmContactPenalty* p, const fmBody* b, const double* x,
                                 const int* diagonal, double* values)
{
	fmHessianVisit h = {diagonal, values};
	fmPenaltyPairs(p, b, x, fmVisitHessian, &h);
}

typedef struct fmProductVisit
{
	const double* dx;
	double* y;
} fmProductVisit;

static void fmVisitProduct(void* context, int i, double k, double depth, fmVec3 n)
{
	(void)depth;
	fmProductVisit* v = context;
	double along = k * (n.x * v->dx[3 * i] + n.y * v->dx[3 * i + 1] + n.z * v->dx[3 * i + 2]);
	v->y[3 * i] += along * n.x;
	v->y[3 * i + 1] += along * n.y;
	v->y[3 * i + 2] += along * n.z;
}

void fmContactPenalty_AddProduct(const fmContactPenalty* p, const fmBody* b, const double* at,
                                 const double* dx, double* y)
{
	fmProductVisit v = {dx, y};
	fmPenaltyPairs(p, b, at, fmVisitProduct, &v);
}

typedef struct fmWorkVisit
{
	const double* x;
	const double* xStart;
	double work;
} fmWorkVisit;

static void fmVisitWork(void* context, int i, double k, double depth, fmVec3 n)
{
	fmWorkVisit* v = context;
	fmVec3 moved = fmSub(fmLoad(v->x, i), fmLoad(v->xStart, i));
	v->work += fmax(0.0, k * depth * fmDot(n, moved));
}

double fmContactPenalty_Work(const fmContactPenalty* p, const fmBody* b, const double* xStart)
{
	fmWorkVisit v = {b->x, xStart, 0.0};
	fmPenaltyPairs(p, b, b->x, fmVisitWork, &v);
	return v.work;
}
