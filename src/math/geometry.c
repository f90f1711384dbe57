// Closest points and bounding boxes (geometry.h).
#include "math/geometry.h"
#include "core/det_math.h"

#include <math.h>

// The fraction along ab of the point nearest p, 0 for a zero-length edge.
static double fmAlongEdge(fmVec3 p, fmVec3 a, fmVec3 b)
{
	fmVec3 ab = fmSub(b, a);
	double length2 = fmDot(ab, ab);
	double t = length2 > 0.0 ? fmDot(fmSub(p, a), ab) / length2 : 0.0;
	return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

// A flat triangle (collinear or coincident corners): the nearest point of its three edges.
static void fmClosestOnFlatTriangle(fmVec3 p, const fmVec3 corner[3], double w[3])
{
	double best = INFINITY;
	for (int k = 0; k < 3; ++k)
	{
		fmVec3 a = corner[k], b = corner[(k + 1) % 3];
		double t = fmAlongEdge(p, a, b);
		fmVec3 d = fmSub(p, fmMulAdd(a, t, fmSub(b, a)));
		if (fmDot(d, d) < best)
		{
			best = fmDot(d, d);
			w[k] = 1.0 - t, w[(k + 1) % 3] = t, w[(k + 2) % 3] = 0.0;
		}
	}
}

// The point of triangle abc nearest p, as barycentric weights (Ericson, Real-Time Collision
// Detection, 5.1.5); a flat triangle's nearest point is on one of its edges.
void fmClosestOnTriangle(fmVec3 p, fmVec3 a, fmVec3 b, fmVec3 c, double w[3])
{
	fmVec3 ab = fmSub(b, a), ac = fmSub(c, a), ap = fmSub(p, a);
	fmVec3 n = fmCross(ab, ac);
	if (!(fmDot(n, n) > 0.0)) // the regions below assume a triangle with an area
	{
		const fmVec3 corner[3] = {a, b, c};
		fmClosestOnFlatTriangle(p, corner, w);
		return;
	}
	double d1 = fmDot(ab, ap), d2 = fmDot(ac, ap);
	if (d1 <= 0.0 && d2 <= 0.0)
	{
		w[0] = 1.0, w[1] = 0.0, w[2] = 0.0;
		return;
	}
	fmVec3 bp = fmSub(p, b);
	double d3 = fmDot(ab, bp), d4 = fmDot(ac, bp);
	if (d3 >= 0.0 && d4 <= d3)
	{
		w[0] = 0.0, w[1] = 1.0, w[2] = 0.0;
		return;
	}
	double vc = d1 * d4 - d3 * d2;
	if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
	{
		double t = d1 - d3 > 0.0 ? d1 / (d1 - d3) : 0.0;
		w[0] = 1.0 - t, w[1] = t, w[2] = 0.0;
		return;
	}
	fmVec3 cp = fmSub(p, c);
	double d5 = fmDot(ab, cp), d6 = fmDot(ac, cp);
	if (d6 >= 0.0 && d5 <= d6)
	{
		w[0] = 0.0, w[1] = 0.0, w[2] = 1.0;
		return;
	}
	double vb = d5 * d2 - d1 * d6;
	if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
	{
		double t = d2 - d6 > 0.0 ? d2 / (d2 - d6) : 0.0;
		w[0] = 1.0 - t, w[1] = 0.0, w[2] = t;
		return;
	}
	double va = d3 * d6 - d5 * d4;
	if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
	{
		double sum = (d4 - d3) + (d5 - d6);
		double t = sum > 0.0 ? (d4 - d3) / sum : 0.0;
		w[0] = 0.0, w[1] = 1.0 - t, w[2] = t;
		return;
	}
	if (!(va + vb + vc > 0.0))
	{
		const fmVec3 corner[3] = {a, b, c};
		fmClosestOnFlatTriangle(p, corner, w);
		return;
	}
	double denominator = 1.0 / (va + vb + vc);
	w[1] = vb * denominator;
	w[2] = vc * denominator;
	w[0] = 1.0 - w[1] - w[2];
}

// Whether the segment o + t d, t in [0, 1], crosses the box [lo, hi] (slab test).
bool fmSegmentHitsBox(fmVec3 o, fmVec3 d, fmVec3 lo, fmVec3 hi)
{
	const double origin[3] = {o.x, o.y, o.z}, dir[3] = {d.x, d.y, d.z};
	const double low[3] = {lo.x, lo.y, lo.z}, high[3] = {hi.x, hi.y, hi.z};
	double enter = 0.0, leave = 1.0;
	for (int e = 0; e < 3; ++e)
	{
		if (dir[e] == 0.0)
		{
			if (origin[e] < low[e] || origin[e] > high[e])
				return false;
			continue;
		}
		double t0 = (low[e] - origin[e]) / dir[e], t1 = (high[e] - origin[e]) / dir[e];
		enter = fmMax(enter, fmMin(t0, t1));
		leave = fmMin(leave, fmMax(t0, t1));
	}
	return enter <= leave;
}

// Fraction along o + t d where it crosses triangle abc (either side), or -1.
double fmSegmentTriangle(fmVec3 o, fmVec3 d, fmVec3 a, fmVec3 b, fmVec3 c)
{
	fmVec3 e1 = fmSub(b, a), e2 = fmSub(c, a), p = fmCross(d, e2);
	double det = fmDot(e1, p);
	if (fabs(det) < 1e-300)
		return -1.0;
	double inv = 1.0 / det;
	fmVec3 s = fmSub(o, a);
	double u = fmDot(s, p) * inv;
	if (u < 0.0 || u > 1.0)
		return -1.0;
	fmVec3 q = fmCross(s, e1);
	double v = fmDot(d, q) * inv;
	if (v < 0.0 || u + v > 1.0)
		return -1.0;
	double t = fmDot(e2, q) * inv;
	return t >= 0.0 && t <= 1.0 ? t : -1.0;
}
