// Additive continuous collision detection (see ccd.h). With the stencil's common motion removed
// (it moves nothing apart), l bounds how fast the distance can close: |dp| + max |dt_i| for a
// point and a triangle, max |da_i| + max |db_j| for two edges. From a gap g = (d^2 - m^2) / (d + m)
// over the minimum distance m, advancing by eta g / l can never close it; repeated until the gap
// is below (1 - eta) of where it started, the time reached is the time of impact.
#include "math/ccd.h"

#include "core/det_math.h"
#include "math/distance.h"

#include <math.h>

// Advances before a closing the bound cannot resolve counts as an impact where it stands.
#define FM_CCD_MAX_ADVANCES 10000

static double fmStencilDistance2(bool edgeEdge, const fmVec3 x[4])
{
	return edgeEdge ? fmDistance_EdgeEdge(x) : fmDistance_PointTriangle(x);
}

// The bound of the closing speed l, the stencil's own motion (common translation removed).
static double fmClosingBound(bool edgeEdge, const fmVec3 dx[4], fmVec3 own[4])
{
	fmVec3 mean = fmScale(0.25, fmAdd(fmAdd(dx[0], dx[1]), fmAdd(dx[2], dx[3])));
	for (int k = 0; k < 4; ++k)
		own[k] = fmSub(dx[k], mean);
	double l[4] = {fmLength(own[0]), fmLength(own[1]), fmLength(own[2]), fmLength(own[3])};
	if (edgeEdge)
		return fmMax(l[0], l[1]) + fmMax(l[2], l[3]);
	return l[0] + fmMax(l[1], fmMax(l[2], l[3]));
}

static double fmGap(double d2, double m)
{
	return (d2 - m * m) / (sqrt(d2) + m);
}

double fmCcd_Additive(bool edgeEdge, const fmVec3 x[4], const fmVec3 dx[4], double minDistance,
                      double eta, double tMax)
{
	double d2 = fmStencilDistance2(edgeEdge, x);
	if (!(d2 > minDistance * minDistance))
		return 0.0;
	fmVec3 own[4], at[4] = {x[0], x[1], x[2], x[3]};
	double l = fmClosingBound(edgeEdge, dx, own);
	if (!(l > 0.0))
		return INFINITY;
	const double stop = (1.0 - eta) * fmGap(d2, minDistance);
	double t = 0.0;
	for (int advance = 0; advance < FM_CCD_MAX_ADVANCES; ++advance)
	{
		double step = eta * fmGap(d2, minDistance) / l;
		for (int k = 0; k < 4; ++k)
			at[k] = fmMulAdd(at[k], step, own[k]);
		d2 = fmStencilDistance2(edgeEdge, at);
		if (advance > 0 && !(fmGap(d2, minDistance) >= stop))
			return t;
		t += step;
		if (t > tMax)
			return INFINITY;
	}
	return t;
}
