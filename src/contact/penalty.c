// The implicit step's contact penalty (penalty.h).
#include "contact/penalty.h"
#include "contact/barrier_contact.h"
#include "core/det_math.h"
#include "math/barrier.h"

#include <math.h>

static bool fmPenaltyMeets(const fmBody* b, const fmCollider* c)
{
	return c->inUse && fmFiltersMeet(b->filter, c->def.filter);
}

// One term on the point sum_j weight[j] x[vertex[j]] (one vertex, or an edge's point): its
// @p energy (J), the @p force (N) it pushes the point with along the outward unit @p normal and
// its curvature k (N/m) along it. A penalty's, at depth d behind where the point should be:
// k d^2 / 2, k d and k; a collider barrier's: kappa G, -kappa G' and kappa G''.
typedef struct fmPenaltyTerm
{
	int vertex[2];
	double weight[2];
	int count;
	double k;
	double energy;
	double force;
	fmVec3 normal;
} fmPenaltyTerm;

// G(d), G'(d) and G''(d) of the colliders' barrier (penalty.h) per unit kappa, continued as the
// quadratic at FM_BARRIER_FLOOR dHat below it; zero from dHat on.
static void fmColliderBarrier(double d, double dHat, double out[3])
{
	double at = fmMax(d, FM_BARRIER_FLOOR * dHat), sHat = dHat * dHat, s = at * at;
	double b1 = fmBarrier_First(s, sHat), delta = d - at;
	double g0 = fmBarrier(s, sHat), g1 = 2.0 * at * b1;
	double g2 = fmMax(0.0, 2.0 * b1 + 4.0 * s * fmBarrier_Second(s, sHat));
	out[0] = g0 + g1 * delta + 0.5 * g2 * delta * delta;
	out[1] = g1 + g2 * delta;
	out[2] = g2;
}

// The barrier's kappa over the vertex mass: FM_BARRIER_STIFFNESS / (h^2 dHat^2).
static double fmColliderBarrierStiffness(double dHat, double h)
{
	return FM_BARRIER_STIFFNESS / (h * h * dHat * dHat);
}

double fmColliderBarrier_Push(double d, double dHat, double h)
{
	if (!(d < dHat) || !(dHat > 0.0))
		return 0.0;
	double g[3];
	fmColliderBarrier(d, dHat, g);
	return -g[1] * fmColliderBarrierStiffness(dHat, h) * h;
}

// Calls @p visit for every surface vertex inside a collider (depth -d; with the barrier: within
// dHat of one) or within the thickness of its frozen plane of another body (depth
// thickness - d), and every surface edge within the thickness of its frozen edge plane.
typedef void fmPenaltyVisit(void* context, const fmPenaltyTerm* term);

static void fmVertexTerm(fmPenaltyVisit* visit, void* context, int i, double k, double depth,
                         fmVec3 n)
{
	fmPenaltyTerm t = {{i, i}, {1.0, 0.0}, 1, k, 0.5 * k * depth * depth, k * depth, n};
	visit(context, &t);
}

// Vertex i's sink in this solve (m, <= 0).
static double fmSinkOf(const fmContactPenalty* p, int i)
{
	return p->sink != NULL ? p->sink[i] : 0.0;
}

// Vertex i against collider @p c at signed distance @p d (m) with outward normal @p n: the
// barrier's term when it holds the colliders, else the penalty's inside.
static void fmColliderTerm(const fmContactPenalty* p, const fmBody* b, int i, double d, fmVec3 n,
                           fmPenaltyVisit* visit, void* context)
{
	if (!p->barrier)
	{
		if (d < 0.0)
			fmVertexTerm(visit, context, i, p->stiffness * b->mesh.mass[i], -d, n);
		return;
	}
	d -= fmSinkOf(p, i);
	if (!(d < p->thickness))
		return;
	double g[3], kappa = fmColliderBarrierStiffness(p->thickness, p->step) * b->mesh.mass[i];
	fmColliderBarrier(d, p->thickness, g);
	fmPenaltyTerm t = {{i, i}, {1.0, 0.0}, 1, kappa * g[2], kappa * g[0], -kappa * g[1], n};
	visit(context, &t);
}

static void fmEdgeTerms(const fmContactPenalty* p, const fmBody* b, const double* x,
                        fmPenaltyVisit* visit, void* context)
{
	for (int e = 0; e < b->contact.edgePlaneCount; ++e)
	{
		const fmEdgePlane* plane = &b->contact.edgePlanes[e];
		if (b->state.pinned[plane->a] == FM_PIN_ALL && b->state.pinned[plane->b] == FM_PIN_ALL)
			continue;
		double s = plane->s;
		fmVec3 q = fmAdd(fmScale(1.0 - s, fmLoad(x, plane->a)), fmScale(s, fmLoad(x, plane->b)));
		double depth = p->thickness - (fmDot(plane->normal, q) - plane->offset);
		double k = p->stiffness * ((1.0 - s) * b->mesh.mass[plane->a] + s * b->mesh.mass[plane->b]);
		fmPenaltyTerm t = {
		    {plane->a, plane->b}, {1.0 - s, s}, 2, k, 0.5 * k * depth * depth, k * depth,
		    plane->normal};
		if (depth > 0.0)
			visit(context, &t);
	}
}

void fmContactPenalty_Prepare(fmContactPenalty* p, fmBody* b, double speed)
{
	double* gap = b->contact.colliderGap;
	if (gap == NULL || b->contact.surfaceVertex == NULL)
		return;
	double* sink = gap + b->mesh.vertexCount;
	for (int s = 0; s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		fmVec3 x = fmLoad(p->xStart, i);
		gap[i] = INFINITY;
		sink[i] = 0.0;
		for (int k = 0; k < p->colliderCount; ++k)
		{
			const fmCollider* c = &p->colliders[k];
			fmVec3 n;
			if (!fmPenaltyMeets(b, c))
				continue;
			double d = fmCollider_Distance(c, x, &n);
			double push = fmMax(0.0, fmDot(fmCollider_VelocityAt(c, x), n));
			gap[i] = fmMin(gap[i], d);
			sink[i] = fmMin(sink[i], d + (speed + push) * p->step);
		}
	}
	p->gap = gap;
	p->sink = p->barrier ? sink : NULL;
}

double fmContactPenalty_Sink(const fmBody* b, int i)
{
	return b->contact.colliderGap != NULL ? b->contact.colliderGap[b->mesh.vertexCount + i] : 0.0;
}

bool fmContactPenalty_Touches(const fmContactPenalty* p, const fmBody* b)
{
	for (int s = 0; p->gap != NULL && s < b->contact.surfaceVertexCount; ++s)
		if (p->gap[b->contact.surfaceVertex[s]] < (p->barrier ? p->thickness : 0.0))
			return true;
	return false;
}

// The least vertex i at @p x can be from any collider it meets (m): its gap at the step's start
// less how far it has moved since (a distance moves no faster than the point); -INFINITY
// without the gaps.
static double fmLeastGap(const fmContactPenalty* p, const double* x, int i)
{
	if (p->gap == NULL)
		return -INFINITY;
	return p->gap[i] - fmLength(fmSub(fmLoad(x, i), fmLoad(p->xStart, i)));
}

static void fmPenaltyPairs(const fmContactPenalty* p, const fmBody* b, const double* x,
                           fmPenaltyVisit* visit, void* context)
{
	if (p == NULL || b->contact.surfaceVertex == NULL)
		return;
	for (int s = 0; s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		if (b->state.pinned[i] == FM_PIN_ALL)
			continue;
		const double* plane = b->contact.plane ? b->contact.plane + 4 * (size_t)i : NULL;
		if (plane != NULL && !isnan(plane[3]))
		{
			fmVec3 n = fmMakeVec3(plane[0], plane[1], plane[2]);
			double depth = p->thickness - (fmDot(n, fmLoad(x, i)) - plane[3]);
			if (depth > 0.0)
				fmVertexTerm(visit, context, i, p->stiffness * b->mesh.mass[i], depth, n);
		}
		// Out of every collider's reach (the barrier's dHat; the penalty's surface): no term.
		if (fmLeastGap(p, x, i) >= (p->barrier ? p->thickness : 0.0))
			continue;
		for (int k = 0; k < p->colliderCount; ++k)
		{
			const fmCollider* c = &p->colliders[k];
			if (!fmPenaltyMeets(b, c))
				continue;
			fmVec3 n;
			double d = fmCollider_Distance(c, fmLoad(x, i), &n);
			fmColliderTerm(p, b, i, d, n, visit, context);
		}
	}
	fmEdgeTerms(p, b, x, visit, context);
}

// ---- friction ----------------------------------------------------------------------------------

// Vertex i's friction data (normal, limit mu lambda, surface velocity), or NULL when none.
static const double* fmFrictionOf(const fmBody* b, int i)
{
	const double* f =
	    b->contact.friction ? b->contact.friction + (size_t)FM_FRICTION_STRIDE * i : NULL;
	return f != NULL && f[3] > 0.0 && b->state.pinned[i] != FM_PIN_ALL ? f : NULL;
}

// The tangential part of @p gain times vertex i's motion relative to the collider's surface, plus
// the stretch its static friction ended the last step with: the slip u (gain
// FM_FRICTION_GAIN) or the spring's stretch now (gain 1).
static fmVec3 fmSlipWith(const double* f, fmVec3 x, fmVec3 x0, double h, double gain)
{
	fmVec3 n = fmMakeVec3(f[0], f[1], f[2]);
	fmVec3 d = fmSub(fmSub(x, x0), fmScale(h, fmMakeVec3(f[4], f[5], f[6])));
	d = fmMulAdd(fmMakeVec3(f[8], f[9], f[10]), gain, d);
	return fmMulAdd(d, -fmDot(d, n), n);
}

static fmVec3 fmSlip(const double* f, fmVec3 x, fmVec3 x0, double h)
{
	return fmSlipWith(f, x, x0, h, FM_FRICTION_GAIN);
}

// The slip width of vertex i's static friction (m): FM_FRICTION_SLIP_SPEED h, widened where the
// stick spring 2 mu lambda / eps would be stiffer than the record's cap f[11] times m / h^2 (a
// stiff stick only costs Newton iterations: measured, docs/contact.md).
static double fmSlipWidth(const fmBody* b, int i, const double* f, double h)
{
	return fmMax(FM_FRICTION_SLIP_SPEED * h, 2.0 * f[3] * h * h / (f[11] * b->mesh.mass[i]));
}

// A stick collider's friction (f[7] set by contact_collider.c): infinite friction as the limit
// of the widened slip width, whose stick spring 2 mu lambda / eps is the normal penalty's
// kappa m / h^2 at any mu: the quadratic spring k/2 |u|^2 with that k, without a Coulomb limit.
// Returns k (N/m), 0 for a Coulomb contact.
static double fmStickStiffness(const fmBody* b, int i, const double* f, double h)
{
	return f[7] != 0.0 ? FM_PENALTY_KAPPA * b->mesh.mass[i] / (h * h) : 0.0;
}

// f0(y) / limit: IPC's C1 friction potential with slip width eps.
static double fmFrictionPotential(double y, double eps)
{
	return y >= eps ? y : y * y * (1.0 / eps - y / (3.0 * eps * eps)) + eps / 3.0;
}

// f1(y) / y: the force's magnitude per unit slip, over the limit.
static double fmFrictionRatio(double y, double eps)
{
	return y >= eps ? 1.0 / y : 2.0 / eps - y / (eps * eps);
}

fmVec3 fmContactFriction_Force(const fmBody* b, int i, const double* x, const double* xStart,
                               double h)
{
	const double* f = fmFrictionOf(b, i);
	if (f == NULL)
		return fmMakeVec3(0.0, 0.0, 0.0);
	fmVec3 u = fmSlip(f, fmLoad(x, i), fmLoad(xStart, i), h);
	double stick = fmStickStiffness(b, i, f, h);
	if (stick > 0.0)
		return fmScale(-stick, u);
	double eps = fmSlipWidth(b, i, f, h);
	return fmScale(-f[3] * fmFrictionRatio(fmLength(u), eps), u);
}

fmVec3 fmContactFriction_Stretch(const fmBody* b, int i, const double* x, const double* xStart,
                                 double h)
{
	const double* f = fmFrictionOf(b, i);
	if (f == NULL)
		return fmMakeVec3(0.0, 0.0, 0.0);
	fmVec3 u = fmSlipWith(f, fmLoad(x, i), fmLoad(xStart, i), h, 1.0);
	double y = fmLength(u), eps = fmSlipWidth(b, i, f, h);
	return fmStickStiffness(b, i, f, h) > 0.0 || y <= eps ? u : fmScale(eps / y, u);
}

// The friction potential's energy, with its gradient added to @p gradient when not NULL.
static double fmFrictionEnergy(const fmContactPenalty* p, const fmBody* b, const double* x,
                               double* gradient)
{
	double energy = 0.0;
	for (int s = 0; s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		const double* f = fmFrictionOf(b, i);
		if (f == NULL)
			continue;
		fmVec3 u = fmSlip(f, fmLoad(x, i), fmLoad(p->xStart, i), p->step);
		double y = fmLength(u), eps = fmSlipWidth(b, i, f, p->step);
		double stick = fmStickStiffness(b, i, f, p->step);
		// Over the gain: the force, gain times its derivative in u, is the spring's and Coulomb's.
		energy += (stick > 0.0 ? 0.5 * stick * y * y : f[3] * fmFrictionPotential(y, eps)) /
		          FM_FRICTION_GAIN;
		if (gradient)
		{
			double r = stick > 0.0 ? stick : f[3] * fmFrictionRatio(y, eps);
			gradient[3 * i] += r * u.x;
			gradient[3 * i + 1] += r * u.y;
			gradient[3 * i + 2] += r * u.z;
		}
	}
	return energy;
}

// Vertex i's friction Hessian block (positive semi-definite: IPC's, whose eigenvalue along the
// slip, 2 / eps - 2 y / eps^2 or 0, is never negative; a stick contact's: k (I - n n^T)).
static void fmFrictionBlock(const fmContactPenalty* p, const fmBody* b, const double* x, int i,
                            const double* f, double block[9])
{
	double eps = fmSlipWidth(b, i, f, p->step);
	fmVec3 n = fmMakeVec3(f[0], f[1], f[2]);
	fmVec3 u = fmSlip(f, fmLoad(x, i), fmLoad(p->xStart, i), p->step);
	double y = fmLength(u), along = y >= eps  ? -1.0 / (y * y * y)
	                                : y > 0.0 ? -1.0 / (eps * eps * y)
	                                          : 0.0;
	double ratio = fmFrictionRatio(y, eps), stick = fmStickStiffness(b, i, f, p->step);
	const double nn[3] = {n.x, n.y, n.z}, uu[3] = {u.x, u.y, u.z};
	const double gain = FM_FRICTION_GAIN; // the energy over the gain, u's derivative gain P
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c)
			block[3 * r + c] =
			    gain * (stick > 0.0
			                ? stick * ((r == c) - nn[r] * nn[c])
			                : f[3] * (ratio * ((r == c) - nn[r] * nn[c]) + along * uu[r] * uu[c]));
}

typedef struct fmEnergyVisit
{
	double energy;
	double* gradient;
} fmEnergyVisit;

static void fmVisitEnergy(void* context, const fmPenaltyTerm* t)
{
	fmEnergyVisit* e = context;
	e->energy += t->energy;
	for (int j = 0; e->gradient && j < t->count; ++j)
	{
		double f = t->force * t->weight[j];
		e->gradient[3 * t->vertex[j]] -= f * t->normal.x;
		e->gradient[3 * t->vertex[j] + 1] -= f * t->normal.y;
		e->gradient[3 * t->vertex[j] + 2] -= f * t->normal.z;
	}
}

double fmContactPenalty_Energy(const fmContactPenalty* p, const fmBody* b, const double* x,
                               double* gradient)
{
	fmEnergyVisit e = {0.0, gradient};
	fmPenaltyPairs(p, b, x, fmVisitEnergy, &e);
	return p != NULL && b->contact.surfaceVertex != NULL
	           ? e.energy + fmFrictionEnergy(p, b, x, gradient)
	           : e.energy;
}

typedef struct fmHessianVisit
{
	const fmBsrMatrix* pattern; // NULL: one block per vertex, the diagonal blocks only
	double* values;
} fmHessianVisit;

// The Gauss-Newton Hessian k w w^T (x) n n^T: an edge's point couples its two vertices, whose
// block the pattern has (a surface edge is a tet's edge). The coupling blocks are required: the
// Newton step of an edge pressed by another body's plane must move both ends together
// (docs/decisions.md, "Edge penalty Hessian").
static void fmVisitHessian(void* context, const fmPenaltyTerm* t)
{
	fmHessianVisit* h = context;
	const double u[3] = {t->normal.x, t->normal.y, t->normal.z};
	for (int j = 0; j < t->count; ++j)
		for (int l = 0; l < t->count; ++l)
		{
			int row = t->vertex[j], column = t->vertex[l];
			if (h->pattern == NULL && l != j)
				continue;
			int slot = h->pattern ? fmBsr_Find(h->pattern, row, column) : row;
			if (slot < 0)
				continue;
			double* block = h->values + 9 * (size_t)slot;
			double k = t->k * t->weight[j] * t->weight[l];
			for (int r = 0; r < 3; ++r)
				for (int c = 0; c < 3; ++c)
					block[3 * r + c] += k * u[r] * u[c];
		}
}

void fmContactPenalty_AddHessian(const fmContactPenalty* p, const fmBody* b, const double* x,
                                 const fmBsrMatrix* pattern, double* values)
{
	fmHessianVisit h = {pattern, values};
	fmPenaltyPairs(p, b, x, fmVisitHessian, &h);
	for (int s = 0; p != NULL && s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		const double* f = fmFrictionOf(b, i);
		if (f == NULL)
			continue;
		double block[9], *out = values + 9 * (size_t)(pattern ? pattern->diagonal[i] : i);
		fmFrictionBlock(p, b, x, i, f, block);
		for (int k = 0; k < 9; ++k)
			out[k] += block[k];
	}
}

typedef struct fmProductVisit
{
	const double* dx;
	double* y;
} fmProductVisit;

// The product with fmVisitHessian's matrix: k w (n . sum_l w_l dx_l) n.
static void fmVisitProduct(void* context, const fmPenaltyTerm* t)
{
	fmProductVisit* v = context;
	fmVec3 n = t->normal;
	double along = 0.0;
	for (int l = 0; l < t->count; ++l)
	{
		const double* d = v->dx + 3 * t->vertex[l];
		along += t->weight[l] * (n.x * d[0] + n.y * d[1] + n.z * d[2]);
	}
	for (int j = 0; j < t->count; ++j)
	{
		double* y = v->y + 3 * t->vertex[j];
		double f = t->k * t->weight[j] * along;
		y[0] += f * n.x;
		y[1] += f * n.y;
		y[2] += f * n.z;
	}
}

void fmContactPenalty_AddProduct(const fmContactPenalty* p, const fmBody* b, const double* at,
                                 const double* dx, double* y)
{
	fmProductVisit v = {dx, y};
	fmPenaltyPairs(p, b, at, fmVisitProduct, &v);
	for (int s = 0; p != NULL && s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		const double* f = fmFrictionOf(b, i);
		if (f == NULL)
			continue;
		double block[9];
		fmFrictionBlock(p, b, at, i, f, block);
		for (int r = 0; r < 3; ++r)
			y[3 * i + r] += block[3 * r] * dx[3 * i] + block[3 * r + 1] * dx[3 * i + 1] +
			                block[3 * r + 2] * dx[3 * i + 2];
	}
}

typedef struct fmWorkVisit
{
	const double* x;
	const double* xStart;
	double work;
} fmWorkVisit;

static void fmVisitWork(void* context, const fmPenaltyTerm* t)
{
	fmWorkVisit* v = context;
	fmVec3 moved = fmMakeVec3(0.0, 0.0, 0.0);
	for (int j = 0; j < t->count; ++j)
		moved = fmMulAdd(moved, t->weight[j],
		                 fmSub(fmLoad(v->x, t->vertex[j]), fmLoad(v->xStart, t->vertex[j])));
	v->work += fmMax(0.0, t->force * fmDot(t->normal, moved));
}

double fmContactPenalty_Work(const fmContactPenalty* p, const fmBody* b, const double* xStart)
{
	fmWorkVisit v = {b->state.x, xStart, 0.0};
	fmPenaltyPairs(p, b, b->state.x, fmVisitWork, &v);
	// Friction's work: what a moving surface's drag puts in, force times the surface's own motion
	// (its positive part). Against a resting surface friction only takes energy out, and its
	// anchored spring only gives back what it stored: neither is work done on the body.
	for (int s = 0; p != NULL && s < b->contact.surfaceVertexCount; ++s)
	{
		int i = b->contact.surfaceVertex[s];
		const double* f = fmFrictionOf(b, i);
		if (f == NULL)
			continue;
		fmVec3 force = fmContactFriction_Force(b, i, b->state.x, xStart, p->step);
		fmVec3 carried = fmScale(p->step, fmMakeVec3(f[4], f[5], f[6]));
		v.work += fmMax(0.0, fmDot(force, carried));
	}
	return v.work;
}

static double fmPenaltyTermEnergy(const void* context, const double* x, const double* xStart,
                                  double* gradient)
{
	(void)xStart;
	const fmContactPenalty* p = context;
	return fmContactPenalty_Energy(p, p->body, x, gradient);
}

static void fmPenaltyTermHessian(const void* context, const double* x, const fmBsrMatrix* pattern,
                                 double* values)
{
	const fmContactPenalty* p = context;
	fmContactPenalty_AddHessian(p, p->body, x, pattern, values);
}

static void fmPenaltyTermProduct(const void* context, const double* x, const double* dx, double* y)
{
	const fmContactPenalty* p = context;
	fmContactPenalty_AddProduct(p, p->body, x, dx, y);
}

// The share of its distance a line-search step may close between a vertex and a collider.
#define FM_COLLIDER_ETA 0.9

// The largest t <= @p t keeping vertex i, at @p x outside collider @p c (less its @p sink), at a
// tenth of its distance or more along x + s dx, s in [0, t] (penalty.h).
static double fmColliderBound(const fmCollider* c, fmVec3 x, fmVec3 dx, double sink, double t)
{
	fmVec3 n;
	double d = fmCollider_Distance(c, x, &n) - sink, length = fmLength(dx);
	if (!(d > 0.0) || t * length <= FM_COLLIDER_ETA * d)
		return t; // inside (the barrier's quadratic pushes it out), or out of reach
	double closing = c->def.shape == fm_shapeMesh ? length : -fmDot(n, dx);
	return closing * t > FM_COLLIDER_ETA * d ? FM_COLLIDER_ETA * d / closing : t;
}

static double fmPenaltyStepBound(const void* context, const double* x, const double* dx)
{
	const fmContactPenalty* p = context;
	const fmBody* b = p->body;
	double t = 1.0;
	for (int s = 0; p->barrier && b->contact.surfaceVertex && s < b->contact.surfaceVertexCount;
	     ++s)
	{
		int i = b->contact.surfaceVertex[s];
		if (b->state.pinned[i] == FM_PIN_ALL ||
		    t * fmLength(fmLoad(dx, i)) <= FM_COLLIDER_ETA * fmLeastGap(p, x, i))
			continue; // the step cannot take it a tenth of the way to any collider
		for (int k = 0; k < p->colliderCount; ++k)
			if (fmPenaltyMeets(b, &p->colliders[k]))
				t = fmColliderBound(&p->colliders[k], fmLoad(x, i), fmLoad(dx, i), fmSinkOf(p, i),
				                    t);
	}
	return t;
}

fmNewtonTerm fmContactPenalty_Term(const fmContactPenalty* penalty)
{
	return (fmNewtonTerm){penalty, fmPenaltyTermEnergy, fmPenaltyTermHessian, fmPenaltyTermProduct,
	                      penalty->barrier ? fmPenaltyStepBound : NULL};
}
