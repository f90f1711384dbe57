// The mathematics of barrier contact, each against an independent computation: the barrier's
// derivatives against finite differences and its limits; the squared distances of every type
// against the exact minimum over the primitives found another way; their gradients and Hessians
// against finite differences; additive CCD against dense sampling (never a contact before the
// time it returns) and against analytic impacts (not too early either); the sweep over body boxes
// against testing every pair.
#include "contact/body_sweep.h"
#include "core/det_math.h"
#include "math/barrier.h"
#include "math/ccd.h"
#include "math/distance.h"
#include "math/geometry.h"
#include "test.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

// ---- helpers -----------------------------------------------------------------------------------

// A fixed-seed generator (xorshift64*), uniform in [lo, hi).
static double uniform(uint64_t* state, double lo, double hi)
{
	*state ^= *state >> 12;
	*state ^= *state << 25;
	*state ^= *state >> 27;
	uint64_t r = *state * 2685821657736338717ull;
	return lo + (hi - lo) * (double)(r >> 11) * (1.0 / 9007199254740992.0);
}

static fmVec3 randomPoint(uint64_t* state, double size)
{
	return fmMakeVec3(uniform(state, -size, size), uniform(state, -size, size),
	                  uniform(state, -size, size));
}

static void randomStencil(uint64_t* state, fmVec3 x[4])
{
	for (int k = 0; k < 4; ++k)
		x[k] = randomPoint(state, 1.0);
}

// The squared distance of p to segment ab, by clamped projection.
static double pointSegment2(fmVec3 p, fmVec3 a, fmVec3 b)
{
	fmVec3 ab = fmSub(b, a);
	double t = fmDot(fmSub(p, a), ab) / fmDot(ab, ab);
	t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
	fmVec3 d = fmSub(p, fmMulAdd(a, t, ab));
	return fmDot(d, d);
}

// Point-triangle, another way: the plane when the projection falls inside (barycentric signs),
// else the nearest of the three edges.
static double pointTriangle2(const fmVec3 x[4])
{
	fmVec3 n = fmCross(fmSub(x[2], x[1]), fmSub(x[3], x[1]));
	double h = fmDot(fmSub(x[0], x[1]), n) / fmDot(n, n);
	fmVec3 q = fmMulAdd(x[0], -h, n);
	bool inside = true;
	for (int k = 0; k < 3; ++k)
	{
		fmVec3 a = x[1 + k], b = x[1 + (k + 1) % 3];
		inside = inside && fmDot(fmCross(fmSub(b, a), fmSub(q, a)), n) >= 0.0;
	}
	if (inside)
		return h * h * fmDot(n, n);
	return fmMin(pointSegment2(x[0], x[1], x[2]),
	             fmMin(pointSegment2(x[0], x[2], x[3]), pointSegment2(x[0], x[3], x[1])));
}

// Edge-edge, another way: the minimum of a convex quadratic over the unit square is at the
// interior stationary point (when inside) or on the square's border, whose four sides are the
// endpoints against the other segment.
static double edgeEdge2(const fmVec3 x[4])
{
	double best = fmMin(fmMin(pointSegment2(x[0], x[2], x[3]), pointSegment2(x[1], x[2], x[3])),
	                    fmMin(pointSegment2(x[2], x[0], x[1]), pointSegment2(x[3], x[0], x[1])));
	fmVec3 u = fmSub(x[1], x[0]), v = fmSub(x[3], x[2]), w = fmSub(x[0], x[2]);
	double a = fmDot(u, u), b = fmDot(u, v), c = fmDot(v, v), d = fmDot(u, w), e = fmDot(v, w);
	double det = a * c - b * b;
	if (det > 1e-12 * a * c)
	{
		double s = (b * e - c * d) / det, t = (a * e - b * d) / det;
		if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0)
		{
			fmVec3 gap = fmSub(fmMulAdd(x[0], s, u), fmMulAdd(x[2], t, v));
			best = fmMin(best, fmDot(gap, gap));
		}
	}
	return best;
}

// ---- the barrier -------------------------------------------------------------------------------

TEST(barrier_derivatives_match_finite_differences_and_vanish_at_the_reach)
{
	const double sHat = 1e-4;
	for (int k = 1; k < 40; ++k)
	{
		double s = sHat * k / 40.0, h = 1e-6 * s;
		double first = (fmBarrier(s + h, sHat) - fmBarrier(s - h, sHat)) / (2.0 * h);
		double second = (fmBarrier_First(s + h, sHat) - fmBarrier_First(s - h, sHat)) / (2.0 * h);
		CHECK_REL(fmBarrier_First(s, sHat), first, 1e-6, 1e-12);
		CHECK_REL(fmBarrier_Second(s, sHat), second, 1e-6, 1e-6);
		CHECK(fmBarrier(s, sHat) > 0.0);
		CHECK(fmBarrier_First(s, sHat) < 0.0); // it pushes apart
		CHECK(fmBarrier_Second(s, sHat) > 0.0);
	}
	// C2 at the reach: value and both derivatives go to 0 from below it, and are 0 beyond.
	double near = sHat * (1.0 - 1e-6);
	CHECK(fmBarrier(near, sHat) < 1e-20);
	CHECK(fabs(fmBarrier_First(near, sHat)) < 1e-14);
	CHECK(fabs(fmBarrier_Second(near, sHat)) < 1e-5);
	CHECK(fmBarrier(2.0 * sHat, sHat) == 0.0 && fmBarrier_First(2.0 * sHat, sHat) == 0.0);
	// Decreasing, unbounded as the distance closes (logarithmically), infinite at contact.
	for (int k = 1; k < 40; ++k)
		CHECK(fmBarrier(sHat * (k - 1 + 0.5) / 40.0, sHat) > fmBarrier(sHat * k / 40.0, sHat));
	CHECK(fmBarrier(1e-300 * sHat, sHat) > 1000.0 * fmBarrier(0.5 * sHat, sHat));
	CHECK(isinf(fmBarrier(0.0, sHat)) && isinf(fmBarrier(-1.0, sHat)));
}

// ---- distances ---------------------------------------------------------------------------------

TEST(squared_distances_are_the_exact_minimum_over_the_primitives)
{
	uint64_t seed = 0x9e3779b97f4a7c15ull;
	int types[2][4] = {{0}};
	for (int trial = 0; trial < 4000; ++trial)
	{
		fmVec3 x[4];
		randomStencil(&seed, x);
		double pt = fmDistance_PointTriangle(x), ee = fmDistance_EdgeEdge(x);
		CHECK_REL(pt, pointTriangle2(x), 1e-9, 1e-12);
		CHECK_REL(ee, edgeEdge2(x), 1e-9, 1e-12);
		types[0][fmDistance_PointTriangleType(x).type] += 1;
		types[1][fmDistance_EdgeEdgeType(x).type] += 1;
	}
	// Every type the pairs can have was seen (point-triangle has no line-line; edge-edge no
	// point-plane).
	CHECK(types[0][fm_distancePointPoint] > 0 && types[0][fm_distancePointLine] > 0 &&
	      types[0][fm_distancePointPlane] > 0 && types[0][fm_distanceLineLine] == 0);
	CHECK(types[1][fm_distancePointPoint] > 0 && types[1][fm_distancePointLine] > 0 &&
	      types[1][fm_distanceLineLine] > 0 && types[1][fm_distancePointPlane] == 0);
}

TEST(parallel_edges_take_a_point_line_distance)
{
	fmVec3 x[4] = {fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0), fmMakeVec3(0.25, 0.5, 0),
	               fmMakeVec3(0.75, 0.5, 0)};
	fmDistanceStencil st = fmDistance_EdgeEdgeType(x);
	CHECK(st.type == fm_distancePointLine);
	CHECK_NEAR(fmDistance_EdgeEdge(x), 0.25, 1e-15);
	// Crossing edges 0.1 apart: the lines' distance.
	fmVec3 y[4] = {fmMakeVec3(-1, 0, 0), fmMakeVec3(1, 0, 0), fmMakeVec3(0, -1, 0.1),
	               fmMakeVec3(0, 1, 0.1)};
	CHECK(fmDistance_EdgeEdgeType(y).type == fm_distanceLineLine);
	CHECK_NEAR(fmDistance_EdgeEdge(y), 0.01, 1e-15);
}

// Central differences of the value against the gradient, and of the gradient against the
// Hessian, for the stencil's own type held fixed.
static double derivativeError(const fmDistanceStencil* st, const fmVec3 x[4])
{
	double g[12], H[144], worst = 0.0, scale = 0.0;
	fmDistance_Squared(st, x, g, H);
	for (int i = 0; i < 144; ++i)
		scale = fmMax(scale, fabs(H[i]));
	for (int i = 0; i < 12; ++i)
	{
		const double h = 1e-6;
		fmVec3 up[4], down[4];
		memcpy(up, x, sizeof up);
		memcpy(down, x, sizeof down);
		((double*)&up[i / 3])[i % 3] += h;
		((double*)&down[i / 3])[i % 3] -= h;
		double gu[12], gd[12];
		double fu = fmDistance_Squared(st, up, gu, NULL),
		       fd = fmDistance_Squared(st, down, gd, NULL);
		worst = fmMax(worst, fabs((fu - fd) / (2.0 * h) - g[i]) / fmMax(scale, 1e-3));
		for (int j = 0; j < 12; ++j)
		{
			worst = fmMax(worst,
			              fabs((gu[j] - gd[j]) / (2.0 * h) - H[12 * i + j]) / fmMax(scale, 1e-3));
			worst = fmMax(worst, fabs(H[12 * i + j] - H[12 * j + i]) / fmMax(scale, 1e-3));
		}
	}
	return worst;
}

TEST(distance_gradients_and_hessians_match_finite_differences)
{
	uint64_t seed = 12345;
	int checked[4] = {0};
	for (int trial = 0; trial < 400; ++trial)
	{
		fmVec3 x[4];
		randomStencil(&seed, x);
		fmDistanceStencil pt = fmDistance_PointTriangleType(x), ee = fmDistance_EdgeEdgeType(x);
		double errorPt = derivativeError(&pt, x), errorEe = derivativeError(&ee, x);
		CHECK(errorPt < 1e-5);
		CHECK(errorEe < 1e-5);
		checked[pt.type] += 1;
		checked[ee.type] += 1;
		// The value is the same with and without the derivatives.
		double g[12];
		CHECK_REL(fmDistance_Squared(&pt, x, g, NULL), fmDistance_Squared(&pt, x, NULL, NULL),
		          1e-13, 1e-15);
	}
	for (int t = 0; t < 4; ++t)
		CHECK(checked[t] > 10);
	// The gradient of a point-plane distance is along the normal, with the point's share 2 h n.
	fmVec3 y[4] = {fmMakeVec3(0.2, 0.3, 0.5), fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0),
	               fmMakeVec3(0, 1, 0)};
	fmDistanceStencil st = fmDistance_PointTriangleType(y);
	double g[12];
	CHECK(st.type == fm_distancePointPlane);
	CHECK_NEAR(fmDistance_Squared(&st, y, g, NULL), 0.25, 1e-15);
	CHECK_NEAR(g[0], 0.0, 1e-15);
	CHECK_NEAR(g[1], 0.0, 1e-15);
	CHECK_NEAR(g[2], 1.0, 1e-15);
}

// ---- additive CCD ------------------------------------------------------------------------------

// The smallest squared distance over @p samples times in [0, t] of the stencil's motion.
static double closestAlong(bool edgeEdge, const fmVec3 x[4], const fmVec3 dx[4], double t,
                           int samples)
{
	double least = INFINITY;
	for (int k = 0; k <= samples; ++k)
	{
		fmVec3 at[4];
		for (int i = 0; i < 4; ++i)
			at[i] = fmMulAdd(x[i], t * k / samples, dx[i]);
		least = fmMin(least, edgeEdge ? fmDistance_EdgeEdge(at) : fmDistance_PointTriangle(at));
	}
	return least;
}

// Whether the motion over [0, t] passes a point through a triangle's face or an edge through
// another: the signed volume of the four points changes sign between two samples where the pair's
// nearest points are interior (a crossing), not where they are corners or sides (passing by).
static bool crossesAlong(bool edgeEdge, const fmVec3 x[4], const fmVec3 dx[4], double t,
                         int samples)
{
	double before = 0.0;
	bool interiorBefore = false;
	for (int k = 0; k <= samples; ++k)
	{
		fmVec3 at[4];
		for (int i = 0; i < 4; ++i)
			at[i] = fmMulAdd(x[i], t * k / samples, dx[i]);
		double volume =
		    fmDot(fmCross(fmSub(at[1], at[0]), fmSub(at[3], at[2])), fmSub(at[2], at[0]));
		if (!edgeEdge)
			volume = fmDot(fmCross(fmSub(at[2], at[1]), fmSub(at[3], at[1])), fmSub(at[0], at[1]));
		fmDistanceStencil st =
		    edgeEdge ? fmDistance_EdgeEdgeType(at) : fmDistance_PointTriangleType(at);
		bool interior = st.type == fm_distanceLineLine || st.type == fm_distancePointPlane;
		if (k > 0 && volume * before < 0.0 && (interior || interiorBefore))
			return true;
		before = volume;
		interiorBefore = interior;
	}
	return false;
}

TEST(additive_ccd_never_lets_primitives_meet_before_its_time)
{
	uint64_t seed = 777;
	int impacts = 0, crossings = 0;
	for (int trial = 0; trial < 3000; ++trial)
	{
		bool edgeEdge = trial % 2 == 1;
		fmVec3 x[4], dx[4];
		randomStencil(&seed, x);
		for (int k = 0; k < 4; ++k)
			dx[k] = randomPoint(&seed, 1.5);
		double start = edgeEdge ? fmDistance_EdgeEdge(x) : fmDistance_PointTriangle(x);
		if (start < 1e-6)
			continue;
		double toi = fmCcd_Additive(edgeEdge, x, dx, 0.0, 0.9, 1.0);
		double until = isinf(toi) ? 1.0 : toi;
		impacts += !isinf(toi);
		// No contact and no crossing before the time returned; a crossing within [0, 1] means an
		// impact was found.
		CHECK(closestAlong(edgeEdge, x, dx, until, 400) > 0.0);
		CHECK(!crossesAlong(edgeEdge, x, dx, until, 400));
		crossings += crossesAlong(edgeEdge, x, dx, 1.0, 400);
		if (crossesAlong(edgeEdge, x, dx, 1.0, 400))
			CHECK(!isinf(toi));
		CHECK(toi >= 0.0);
	}
	CHECK(impacts > 100);
	CHECK(crossings > 50); // the trials include real crossings
}

TEST(additive_ccd_finds_a_head_on_impact_near_its_time)
{
	// A point 1 m above a triangle's middle, falling at 2 m/s: the impact is at t = 0.5.
	fmVec3 x[4] = {fmMakeVec3(0.25, 0.25, 1.0), fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0),
	               fmMakeVec3(0, 1, 0)};
	fmVec3 dx[4] = {fmMakeVec3(0, 0, -2.0), fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, 0),
	                fmMakeVec3(0, 0, 0)};
	double toi = fmCcd_Additive(false, x, dx, 0.0, 0.9, 1.0);
	CHECK(toi < 0.5 && toi > 0.44); // stops at a tenth of the gap: 0.1 m short, t = 0.45
	// Two edges crossing at right angles, 0.4 m apart, closing at 1 m/s: impact at t = 0.4.
	fmVec3 y[4] = {fmMakeVec3(-1, 0, 0), fmMakeVec3(1, 0, 0), fmMakeVec3(0, -1, 0.4),
	               fmMakeVec3(0, 1, 0.4)};
	fmVec3 dy[4] = {fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, -1.0),
	                fmMakeVec3(0, 0, -1.0)};
	double toiEdges = fmCcd_Additive(true, y, dy, 0.0, 0.9, 1.0);
	CHECK(toiEdges < 0.4 && toiEdges > 0.35);
	// A minimum distance stops it earlier; a motion that misses gives no impact; a start within
	// the minimum distance gives 0.
	CHECK(fmCcd_Additive(false, x, dx, 0.2, 0.9, 1.0) < 0.4);
	fmVec3 away[4] = {fmMakeVec3(0, 0, 2.0), fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, 0),
	                  fmMakeVec3(0, 0, 0)};
	CHECK(isinf(fmCcd_Additive(false, x, away, 0.0, 0.9, 1.0)));
	CHECK(fmCcd_Additive(false, x, dx, 1.5, 0.9, 1.0) == 0.0);
}

// Flat triangles (two corners at one point, or three on a line) have a distance: the nearest of
// their edges, finite, never NaN.
TEST(flat_triangles_have_a_finite_distance)
{
	fmVec3 p = fmMakeVec3(0.3, 0.4, 0.5);
	fmVec3 coincident[4] = {p, fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0)};
	fmVec3 collinear[4] = {p, fmMakeVec3(0, 0, 0), fmMakeVec3(0.5, 0, 0), fmMakeVec3(1, 0, 0)};
	double d = fmDistance_PointTriangle(coincident), e = fmDistance_PointTriangle(collinear);
	CHECK_NEAR(d, 0.4 * 0.4 + 0.5 * 0.5, 1e-15);
	CHECK_NEAR(e, 0.4 * 0.4 + 0.5 * 0.5, 1e-15);
	double w[3];
	fmClosestOnTriangle(fmMakeVec3(0.5, 1.0, 0.0), fmMakeVec3(0, 0, 0), fmMakeVec3(0, 0, 0),
	                    fmMakeVec3(1, 0, 0), w);
	CHECK(isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2]));
	CHECK_NEAR(w[0] + w[1] + w[2], 1.0, 1e-15);
}

// ---- the sweep over body boxes -----------------------------------------------------------------

// Whether two closed boxes overlap (touching counts), tested directly.
static bool boxesOverlap(fmVec3 al, fmVec3 ah, fmVec3 bl, fmVec3 bh)
{
	return al.x <= bh.x && bl.x <= ah.x && al.y <= bh.y && bl.y <= ah.y && al.z <= bh.z &&
	       bl.z <= ah.z;
}

// The sweep finds every pair of overlapping boxes, each once, and lists them per slot in slot
// order, against testing every pair: boxes of every size, some touching exactly (snapped to a
// coarse grid), some empty (a body without a surface), slots with gaps (dead bodies).
TEST(body_sweep_pairs_every_overlapping_box_once)
{
	enum
	{
		slots = 300
	};
	static fmVec3 lower[slots], upper[slots];
	static int live[slots];
	static unsigned char expected[slots][slots];
	uint64_t state = 0x9e3779b97f4a7c15ull;
	fmBodySweep sweep;
	memset(&sweep, 0, sizeof sweep);
	for (int round = 0; round < 20; ++round)
	{
		int count = 0;
		for (int s = 0; s < slots; ++s)
		{
			fmVec3 c = randomPoint(&state, 10.0);
			double size = round % 2 ? uniform(&state, 0.0, 3.0) : floor(uniform(&state, 0.0, 4.0));
			c = round % 2 ? c : fmMakeVec3(floor(c.x), floor(c.y), floor(c.z));
			lower[s] = c;
			upper[s] = fmAdd(c, fmMakeVec3(size, size * 0.5, size));
			if (uniform(&state, 0.0, 1.0) < 0.05) // empty
			{
				lower[s] = fmMakeVec3(INFINITY, INFINITY, INFINITY);
				upper[s] = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
			}
			CHECK(fmBodySweep_Sweepable(lower[s], upper[s]));
			if (uniform(&state, 0.0, 1.0) < 0.9)
				live[count++] = s;
		}
		memset(expected, 0, sizeof expected);
		for (int i = 0; i < count; ++i)
			for (int j = i + 1; j < count; ++j)
				if (boxesOverlap(lower[live[i]], upper[live[i]], lower[live[j]], upper[live[j]]))
					expected[live[i]][live[j]] = expected[live[j]][live[i]] = 1;
		CHECK(fmBodySweep_Pairs(&sweep, live, count, lower, upper));
		CHECK(fmBodySweep_Lists(&sweep, slots));
		int pairs = 0;
		for (int s = 0; s < slots; ++s)
			for (int t = 0; t < slots; ++t)
				pairs += expected[s][t];
		CHECK(2 * sweep.pairCount == pairs);
		for (int s = 0; s < slots; ++s)
		{
			int n = 0;
			for (int t = 0; t < slots; ++t)
				if (expected[s][t])
				{
					int k = sweep.listStart[s] + n++;
					CHECK(k < sweep.listStart[s + 1] && sweep.list[k] == t);
				}
			CHECK(sweep.listStart[s] + n == sweep.listStart[s + 1]);
		}
	}
	CHECK(!fmBodySweep_Sweepable(fmMakeVec3(NAN, 0, 0), fmMakeVec3(1, 1, 1)));
	CHECK(!fmBodySweep_Sweepable(fmMakeVec3(-INFINITY, 0, 0), fmMakeVec3(1, 1, 1)));
	fmBodySweep_Free(&sweep);
}
