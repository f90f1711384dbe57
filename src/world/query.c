// World queries (query.h). fmWorld_CastRay: each body whose bounding box the ray crosses is
// tested triangle by triangle (Moller-Trumbore), each collider by its segment cast; the nearest
// hit wins (ties: the lower body slot, then triangle, then collider). fmWorld_OverlapSphere:
// each body's nearest surface point (and a parity test for a centre inside it), each collider's
// signed distance.
#include "world/query.h"
#include "core/det_math.h"

#include "contact/collider.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "math/geometry.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

static void fmBodyBox(const fmBody* b, fmVec3* lo, fmVec3* hi)
{
	*lo = *hi = fmLoad(b->state.x, 0);
	for (int i = 1; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
}

// The nearest hit on body @p slot's surface closer than hit->fraction.
static void fmCastAtBody(const fmWorld* w, int slot, fmVec3 o, fmVec3 d, fmRayHit* hit)
{
	const fmBody* b = &w->bodies[slot];
	fmVec3 lo, hi;
	fmBodyBox(b, &lo, &hi);
	if (!fmSegmentHitsBox(o, d, lo, hi))
		return;
	for (int t = 0; t < b->mesh.triangleCount; ++t)
	{
		const int* tri = b->mesh.surface + 3 * t;
		fmVec3 a = fmLoad(b->state.x, tri[0]), bb = fmLoad(b->state.x, tri[1]),
		       c = fmLoad(b->state.x, tri[2]);
		double f = fmSegmentTriangle(o, d, a, bb, c);
		if (!(f >= 0.0 && f < hit->fraction))
			continue;
		fmVec3 n = fmCross(fmSub(bb, a), fmSub(c, a));
		double length = fmLength(n);
		fmVec3 p = fmMulAdd(o, f, d);
		int nearest = 0;
		for (int k = 1; k < 3; ++k)
			if (fmLength(fmSub(fmLoad(b->state.x, tri[k]), p)) <
			    fmLength(fmSub(fmLoad(b->state.x, tri[nearest]), p)))
				nearest = k;
		memset(hit, 0, sizeof *hit);
		hit->body = fmWorldBodyId(w, slot);
		hit->triangle = t;
		hit->vertex = b->userVertex[tri[nearest]];
		hit->point = p;
		hit->normal = length > 0.0 ? fmScale(1.0 / length, n) : fmMakeVec3(0.0, 1.0, 0.0);
		hit->fraction = f;
	}
}

// The collider slot the queries' k-th look goes to: the table's, then the floor's.
static int fmQuerySlot(const fmWorld* w, int k)
{
	return k < w->colliderCapacity ? k : FM_FLOOR_SLOT;
}

static bool fmCastRayIn(fmWorldId worldId, fmVec3 origin, fmVec3 translation, fmFilter filter,
                        fmRayHit* hit)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && hit != NULL);
	if (w == NULL || hit == NULL)
		return false;
	memset(hit, 0, sizeof *hit);
	hit->fraction = INFINITY;
	hit->triangle = hit->vertex = -1;
	bool finite = fabs(origin.x) <= FM_MAX_COORDINATE && fabs(origin.y) <= FM_MAX_COORDINATE &&
	              fabs(origin.z) <= FM_MAX_COORDINATE && fabs(translation.x) <= 1e12 &&
	              fabs(translation.y) <= 1e12 && fabs(translation.z) <= 1e12;
	if (!finite)
		return false;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		if (fmBody_IsLive(&w->bodies[slot]) && fmFiltersMeet(filter, w->bodies[slot].filter))
			fmCastAtBody(w, slot, origin, translation, hit);
	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		int slot = fmQuerySlot(w, k);
		const fmCollider* c = fmWorldCollider(w, slot);
		double f;
		fmVec3 n;
		if (!c->inUse || !fmFiltersMeet(filter, c->def.filter) ||
		    !fmCollider_CastSegment(c, origin, fmAdd(origin, translation), 0.0, &f, &n) ||
		    !(f < hit->fraction))
			continue;
		memset(hit, 0, sizeof *hit);
		hit->collider = fmWorldColliderId(w, slot);
		hit->triangle = hit->vertex = -1;
		hit->point = fmMulAdd(origin, f, translation);
		hit->normal = n;
		hit->fraction = f;
	}
	if (isfinite(hit->fraction))
		return true;
	hit->fraction = 1.0; // a miss: the whole translation is free
	return false;
}

bool fmWorld_CastRay(fmWorldId worldId, fmVec3 origin, fmVec3 translation, fmFilter filter,
                     fmRayHit* hit)
{
	fmWorld* w = fmGetWorld(worldId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	bool result = fmCastRayIn(worldId, origin, translation, filter, hit);
	fmFpEnv_Leave(&env);
	return result;
}

// ---- sphere overlaps ---------------------------------------------------------------------------

// Whether @p p is inside body @p b's closed surface: the crossings of a ray along +x (long
// enough to leave the body's box) are odd.
static bool fmInsideBody(const fmBody* b, fmVec3 p, fmVec3 hi)
{
	fmVec3 d = fmMakeVec3(hi.x - p.x + 1.0, 1e-7 * (hi.x - p.x + 1.0), 3e-7 * (hi.x - p.x + 1.0));
	int crossings = 0;
	for (int t = 0; t < b->mesh.triangleCount; ++t)
	{
		const int* tri = b->mesh.surface + 3 * t;
		crossings += fmSegmentTriangle(p, d, fmLoad(b->state.x, tri[0]), fmLoad(b->state.x, tri[1]),
		                               fmLoad(b->state.x, tri[2])) >= 0.0;
	}
	return crossings % 2 == 1;
}

// Body @p slot against the sphere: its nearest surface point and vertex, or false.
static bool fmOverlapBody(const fmWorld* w, int slot, fmVec3 center, double radius, fmOverlap* out)
{
	const fmBody* b = &w->bodies[slot];
	fmVec3 lo, hi;
	fmBodyBox(b, &lo, &hi);
	fmVec3 r = fmMakeVec3(radius, radius, radius);
	if (!fmSegmentHitsBox(center, fmMakeVec3(0.0, 0.0, 0.0), fmSub(lo, r), fmAdd(hi, r)))
		return false;
	double best = INFINITY;
	for (int t = 0; t < b->mesh.triangleCount; ++t)
	{
		const int* tri = b->mesh.surface + 3 * t;
		fmVec3 a = fmLoad(b->state.x, tri[0]), bb = fmLoad(b->state.x, tri[1]),
		       c = fmLoad(b->state.x, tri[2]);
		double wt[3];
		fmClosestOnTriangle(center, a, bb, c, wt);
		fmVec3 q = fmAdd(fmAdd(fmScale(wt[0], a), fmScale(wt[1], bb)), fmScale(wt[2], c));
		double d = fmLength(fmSub(center, q));
		if (!(d < best))
			continue;
		best = d;
		out->point = q;
		int k = wt[0] >= wt[1] && wt[0] >= wt[2] ? 0 : wt[1] >= wt[2] ? 1 : 2;
		out->vertex = b->userVertex[tri[k]];
	}
	bool inside = fmInsideBody(b, center, hi);
	if (!(best <= radius) && !inside)
		return false;
	out->body = fmWorldBodyId(w, slot);
	out->distance = inside ? 0.0 : best;
	return true;
}

static int fmOverlapIn(fmWorldId worldId, fmVec3 center, double radius, fmFilter filter,
                       fmOverlap* overlaps, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL);
	bool valid = fabs(center.x) + fabs(center.y) + fabs(center.z) < 3.0 * FM_MAX_COORDINATE &&
	             radius >= 0.0 && radius <= FM_MAX_COORDINATE;
	FM_ASSERT(valid);
	if (w == NULL || !valid)
		return 0;
	int count = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmOverlap o;
		memset(&o, 0, sizeof o);
		if (!fmBody_IsLive(&w->bodies[slot]) || !fmFiltersMeet(filter, w->bodies[slot].filter) ||
		    !fmOverlapBody(w, slot, center, radius, &o))
			continue;
		if (count < capacity && overlaps != NULL)
			overlaps[count] = o;
		count += 1;
	}
	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		int slot = fmQuerySlot(w, k);
		const fmCollider* c = fmWorldCollider(w, slot);
		fmVec3 n;
		double d = c->inUse && fmFiltersMeet(filter, c->def.filter)
		               ? fmCollider_Distance(c, center, &n)
		               : INFINITY;
		if (!(d <= radius))
			continue;
		if (count < capacity && overlaps != NULL)
		{
			fmOverlap* o = &overlaps[count];
			memset(o, 0, sizeof *o);
			o->collider = fmWorldColliderId(w, slot);
			o->vertex = -1;
			o->point = fmMulAdd(center, -d, n);
			o->distance = fmMax(d, 0.0);
		}
		count += 1;
	}
	return count;
}

int fmWorld_OverlapSphere(fmWorldId worldId, fmVec3 center, double radius, fmFilter filter,
                          fmOverlap* overlaps, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	int count = fmOverlapIn(worldId, center, radius, filter, overlaps, capacity);
	fmFpEnv_Leave(&env);
	return count;
}
