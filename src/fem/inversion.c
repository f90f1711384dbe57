// Inversion-free steps (see inversion.h). Along x + t d a tet's edge matrix is Ds + t Dq, whose
// determinant is the cubic a t^3 + b t^2 + c t + det Ds; the step limit is the first root in
// (0, 1] of that cubic minus keep det Ds, found by bracketing between the cubic's critical points
// and bisecting (no closed form: it loses roots to rounding near double and triple roots).
#include "fem/inversion.h"

#include "core/det_math.h"

#include <math.h>

typedef struct fmCubic
{
	double a, b, c, d;
} fmCubic;

static double fmCubicAt(const fmCubic* p, double t)
{
	return ((p->a * t + p->b) * t + p->c) * t + p->d;
}

// The cubic of det(Ds + t Dq) for the tet's edges v and their motions q.
static fmCubic fmTetCubic(const fmVec3 v[3], const fmVec3 q[3])
{
	fmVec3 qq = fmCross(q[0], q[1]), vq = fmAdd(fmCross(v[0], q[1]), fmCross(q[0], v[1]));
	fmVec3 vv = fmCross(v[0], v[1]);
	fmCubic p = {fmDot(q[2], qq), fmDot(v[2], qq) + fmDot(q[2], vq),
	             fmDot(q[2], vv) + fmDot(v[2], vq), fmDot(v[2], vv)};
	return p;
}

// The first root in (0, 1] of @p p, which is positive at 0; INFINITY when none.
static double fmFirstRoot(const fmCubic* p)
{
	// The critical points split [0, 1] into stretches where the cubic is monotone.
	double cuts[4] = {0.0, 1.0, 1.0, 1.0};
	int count = 1;
	double qa = 3.0 * p->a, qb = 2.0 * p->b, qc = p->c;
	double disc = qb * qb - 4.0 * qa * qc;
	if (qa != 0.0 && disc >= 0.0)
	{
		double r = sqrt(disc), t1 = (-qb - r) / (2.0 * qa), t2 = (-qb + r) / (2.0 * qa);
		double lo = fmMin(t1, t2), hi = fmMax(t1, t2);
		if (lo > 0.0 && lo < 1.0)
			cuts[count++] = lo;
		if (hi > 0.0 && hi < 1.0)
			cuts[count++] = hi;
	}
	else if (qa == 0.0 && qb != 0.0 && -qc / qb > 0.0 && -qc / qb < 1.0)
		cuts[count++] = -qc / qb;
	cuts[count++] = 1.0;
	for (int k = 0; k + 1 < count; ++k)
	{
		double lo = cuts[k], hi = cuts[k + 1];
		if (!(fmCubicAt(p, hi) <= 0.0))
			continue;
		for (int it = 0; it < 60; ++it) // f(lo) > 0 >= f(hi): bisect to the double's precision
		{
			double mid = 0.5 * (lo + hi);
			*(fmCubicAt(p, mid) > 0.0 ? &lo : &hi) = mid;
		}
		return lo;
	}
	return INFINITY;
}

static void fmTetEdges(const fmElasticMesh* mesh, const double* x, int t, fmVec3 v[3])
{
	const int* n = mesh->tets + 4 * t;
	fmVec3 x0 = fmLoad(x, n[0]);
	for (int k = 0; k < 3; ++k)
		v[k] = fmSub(fmLoad(x, n[k + 1]), x0);
}

double fmInversion_StepLimit(const fmElasticMesh* mesh, const double* x, const double* direction,
                             double keep)
{
	double limit = 1.0;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmVec3 v[3], q[3];
		fmTetEdges(mesh, x, t, v);
		fmTetEdges(mesh, direction, t, q);
		fmCubic p = fmTetCubic(v, q);
		if (!(p.d > 0.0))
			continue; // flat or inverted already: not this filter's to keep
		p.d -= keep * p.d;
		// On [0, 1] the cubic is at least d - (|a| + |b| + |c|): with a margin far above its
		// evaluation's rounding, it has no root there (a short step against the tet's size, the
		// usual case: the same limit without the search).
		if (p.d > 1.000001 * (fabs(p.a) + fabs(p.b) + fabs(p.c)))
			continue;
		limit = fmMin(limit, fmFirstRoot(&p));
	}
	return limit;
}

bool fmInversion_Any(const fmElasticMesh* mesh, const double* from, const double* to)
{
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmVec3 v[3], w[3];
		fmTetEdges(mesh, from, t, v);
		fmTetEdges(mesh, to, t, w);
		if (fmDot(v[2], fmCross(v[0], v[1])) > 0.0 && !(fmDot(w[2], fmCross(w[0], w[1])) > 0.0))
			return true;
	}
	return false;
}

bool fmInversion_Needed(const fmElasticMesh* mesh)
{
	for (int k = 0; k < mesh->materialCount; ++k)
		if (mesh->materials[k].model == fm_neoHookean || mesh->materials[k].model == fm_mooneyRivlin)
			return true;
	return mesh->material.model == fm_neoHookean || mesh->material.model == fm_mooneyRivlin;
}
