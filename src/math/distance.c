// Squared distances of contact primitives and their derivatives (see distance.h). The types are
// found with the closest points (Ericson, Real-Time Collision Detection, 5.1.5 and 5.1.9); the
// derivatives come from second-order automatic differentiation of each type's formula (ad2.h).
#include "math/distance.h"

#include "math/ad2.h"
#include "math/geometry.h"

#include <string.h>

// Edges closer to parallel than this (|da x db|^2 against |da|^2 |db|^2) are treated as
// parallel: the line-line formula is then left for a point-line one.
#define FM_PARALLEL_EDGES 1e-10

static fmDistanceStencil fmStencil(fmDistanceType type, int count, int a, int b, int c, int d)
{
	fmDistanceStencil s = {type, count, {a, b, c, d}};
	return s;
}

fmDistanceStencil fmDistance_PointTriangleType(const fmVec3 x[4])
{
	double w[3];
	fmClosestOnTriangle(x[0], x[1], x[2], x[3], w);
	int zeros = (w[0] == 0.0) + (w[1] == 0.0) + (w[2] == 0.0);
	if (zeros == 0)
		return fmStencil(fm_distancePointPlane, 4, 0, 1, 2, 3);
	if (zeros == 2) // a corner: the one whose weight is not zero
		return fmStencil(fm_distancePointPoint, 2, 0, w[0] != 0.0 ? 1 : w[1] != 0.0 ? 2 : 3, -1,
		                 -1);
	int k = w[0] == 0.0 ? 0 : w[1] == 0.0 ? 1 : 2; // the edge opposite corner k
	return fmStencil(fm_distancePointLine, 3, 0, 1 + (k + 1) % 3, 1 + (k + 2) % 3, -1);
}

static double fmClamp01(double v)
{
	return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

// The segments' nearest parameters s on a, t on b (Ericson 5.1.9), parallel edges with s = 0.
static void fmSegmentParameters(const fmVec3 x[4], double* s, double* t)
{
	fmVec3 da = fmSub(x[1], x[0]), db = fmSub(x[3], x[2]), r = fmSub(x[0], x[2]);
	double a = fmDot(da, da), e = fmDot(db, db), f = fmDot(db, r);
	double c = fmDot(da, r), b = fmDot(da, db), denom = a * e - b * b;
	if (!(a > 0.0) || !(e > 0.0))
	{
		*s = a > 0.0 ? fmClamp01(-c / a) : 0.0;
		*t = a > 0.0 || !(e > 0.0) ? 0.0 : fmClamp01(f / e);
		return;
	}
	*s = denom > FM_PARALLEL_EDGES * a * e ? fmClamp01((b * f - c * e) / denom) : 0.0;
	*t = (b * *s + f) / e;
	if (*t < 0.0)
		*t = 0.0, *s = fmClamp01(-c / a);
	else if (*t > 1.0)
		*t = 1.0, *s = fmClamp01((b - c) / a);
}

void fmDistance_EdgeEdgeClosest(const fmVec3 x[4], double* s, double* t)
{
	fmSegmentParameters(x, s, t);
}

fmDistanceStencil fmDistance_EdgeEdgeType(const fmVec3 x[4])
{
	double s, t;
	fmSegmentParameters(x, &s, &t);
	bool sEnd = s == 0.0 || s == 1.0, tEnd = t == 0.0 || t == 1.0;
	int a = s == 1.0 ? 1 : 0, b = t == 1.0 ? 3 : 2;
	if (sEnd && tEnd)
		return fmStencil(fm_distancePointPoint, 2, a, b, -1, -1);
	if (sEnd) // corner a of edge a against edge b's line
		return fmStencil(fm_distancePointLine, 3, a, 2, 3, -1);
	if (tEnd)
		return fmStencil(fm_distancePointLine, 3, b, 0, 1, -1);
	return fmStencil(fm_distanceLineLine, 4, 0, 1, 2, 3);
}

// The type's formula on points given as AD variables (numbered by their stencil index).
static fmAd fmTypeFormula(const fmDistanceStencil* st, const fmAdVec3 p[4])
{
	const fmAdVec3 *a = &p[st->vertex[0]], *b = &p[st->vertex[1]];
	if (st->type == fm_distancePointPoint)
	{
		fmAdVec3 d = fmAdVec3_Sub(a, b);
		return fmAdVec3_Dot(&d, &d);
	}
	if (st->type == fm_distancePointLine) // |(e0 - p) x (e1 - p)|^2 / |e1 - e0|^2
	{
		const fmAdVec3* c = &p[st->vertex[2]];
		fmAdVec3 u = fmAdVec3_Sub(b, a), v = fmAdVec3_Sub(c, a), e = fmAdVec3_Sub(c, b);
		fmAdVec3 n = fmAdVec3_Cross(&u, &v);
		fmAd num = fmAdVec3_Dot(&n, &n), den = fmAdVec3_Dot(&e, &e);
		return fmAd_Div(&num, &den);
	}
	const fmAdVec3 *c = &p[st->vertex[2]], *d = &p[st->vertex[3]];
	// point-plane: ((p - t0) . n)^2 / |n|^2, n = (t1 - t0) x (t2 - t0); line-line:
	// ((b0 - a0) . n)^2 / |n|^2, n = (a1 - a0) x (b1 - b0)
	bool plane = st->type == fm_distancePointPlane;
	fmAdVec3 u = plane ? fmAdVec3_Sub(c, b) : fmAdVec3_Sub(b, a);
	fmAdVec3 v = plane ? fmAdVec3_Sub(d, b) : fmAdVec3_Sub(d, c);
	fmAdVec3 w = plane ? fmAdVec3_Sub(a, b) : fmAdVec3_Sub(c, a);
	fmAdVec3 n = fmAdVec3_Cross(&u, &v);
	fmAd along = fmAdVec3_Dot(&w, &n), nn = fmAdVec3_Dot(&n, &n);
	fmAd num = fmAd_Mul(&along, &along);
	return fmAd_Div(&num, &nn);
}

// The same formulas in plain doubles (the value alone).
static double fmTypeValue(const fmDistanceStencil* st, const fmVec3 x[4])
{
	fmVec3 a = x[st->vertex[0]], b = x[st->vertex[1]];
	if (st->type == fm_distancePointPoint)
		return fmDot(fmSub(a, b), fmSub(a, b));
	if (st->type == fm_distancePointLine)
	{
		fmVec3 c = x[st->vertex[2]], n = fmCross(fmSub(b, a), fmSub(c, a)), e = fmSub(c, b);
		return fmDot(n, n) / fmDot(e, e);
	}
	fmVec3 c = x[st->vertex[2]], d = x[st->vertex[3]];
	bool plane = st->type == fm_distancePointPlane;
	fmVec3 n = plane ? fmCross(fmSub(c, b), fmSub(d, b)) : fmCross(fmSub(b, a), fmSub(d, c));
	double along = fmDot(plane ? fmSub(a, b) : fmSub(c, a), n);
	return along * along / fmDot(n, n);
}

double fmDistance_Squared(const fmDistanceStencil* stencil, const fmVec3 x[4], double* gradient,
                          double* hessian)
{
	if (gradient == NULL && hessian == NULL)
		return fmTypeValue(stencil, x);
	fmAdVec3 p[4];
	for (int k = 0; k < 4; ++k)
		p[k] = fmAdVec3_Variables(x[k], k);
	fmAd s = fmTypeFormula(stencil, p);
	fmAd_Export(&s, 12, gradient, hessian);
	return s.v;
}

double fmDistance_PointTriangle(const fmVec3 x[4])
{
	fmDistanceStencil st = fmDistance_PointTriangleType(x);
	return fmTypeValue(&st, x);
}

double fmDistance_EdgeEdge(const fmVec3 x[4])
{
	fmDistanceStencil st = fmDistance_EdgeEdgeType(x);
	return fmTypeValue(&st, x);
}
