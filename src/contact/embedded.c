// Vertices caught inside another body (embedded.h): the tets of the bodies near another in a
// spatial hash, and point-in-tet queries against it.
#include "contact/embedded.h"
#include "core/det_math.h"

#include "core/core.h"

#include <math.h>
#include <string.h>

void fmTetHash_Free(fmTetHash* th)
{
	fmSpatialHash_Free(&th->hash);
	FM_FREE_ARRAY(th->lower, fmVec3, th->capacity);
	FM_FREE_ARRAY(th->upper, fmVec3, th->capacity);
	FM_FREE_ARRAY(th->body, int, th->capacity);
	FM_FREE_ARRAY(th->tet, int, th->capacity);
	memset(th, 0, sizeof *th);
}

// Room for @p count tets. False when memory is short.
static bool fmTetHash_Reserve(fmTetHash* th, int count)
{
	if (count <= th->capacity)
		return true;
	fmSpatialHash hash = th->hash;
	th->hash = (fmSpatialHash){0};
	fmTetHash_Free(th);
	th->hash = hash;
	th->lower = FM_ALLOC_ARRAY(fmVec3, count);
	th->upper = FM_ALLOC_ARRAY(fmVec3, count);
	th->body = FM_ALLOC_ARRAY(int, count);
	th->tet = FM_ALLOC_ARRAY(int, count);
	th->capacity = count;
	if (th->lower && th->upper && th->body && th->tet)
		return true;
	fmTetHash_Free(th);
	return false;
}

// The box of tet @p t of body @p b; false when a corner is not finite (the frame's checks
// report it; the tet then stays out of the hash).
static bool fmTetBox(const fmBody* b, int t, fmVec3* lo, fmVec3* hi)
{
	const int* tet = b->mesh.tets + 4 * t;
	*lo = *hi = fmLoad(b->state.x, tet[0]);
	for (int c = 1; c < 4; ++c)
	{
		fmVec3 p = fmLoad(b->state.x, tet[c]);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
	return fabs(lo->x) + fabs(lo->y) + fabs(lo->z) + fabs(hi->x) + fabs(hi->y) + fabs(hi->z) < 1e30;
}

bool fmTetHash_Build(fmTetHash* th, const fmWorld* w, const bool* near)
{
	int total = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		total += fmBody_IsLive(&w->bodies[slot]) && near[slot] ? w->bodies[slot].mesh.tetCount : 0;
	th->count = 0;
	if (!fmTetHash_Reserve(th, total))
		return false;
	double extent = 0.0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		for (int t = 0; fmBody_IsLive(b) && near[slot] && t < b->mesh.tetCount; ++t)
		{
			fmVec3 lo, hi;
			if (!fmTetBox(b, t, &lo, &hi))
				continue;
			extent += fmMax(hi.x - lo.x, fmMax(hi.y - lo.y, hi.z - lo.z));
			th->lower[th->count] = lo;
			th->upper[th->count] = hi;
			th->body[th->count] = slot;
			th->tet[th->count] = t;
			th->count += 1;
		}
	}
	double cell = th->count > 0 ? extent / th->count : 0.0;
	return fmSpatialHash_Build(&th->hash, th->lower, th->upper, th->count, cell > 0.0 ? cell : 1.0);
}

// Whether @p p lies strictly inside tet @p t of body @p b (every barycentric coordinate
// positive, by the signed volumes of the four tets p makes with the faces).
static bool fmInsideTet(const fmBody* b, int t, fmVec3 p)
{
	const int* tet = b->mesh.tets + 4 * t;
	fmVec3 a = fmLoad(b->state.x, tet[0]), e1 = fmSub(fmLoad(b->state.x, tet[1]), a),
	       e2 = fmSub(fmLoad(b->state.x, tet[2]), a), e3 = fmSub(fmLoad(b->state.x, tet[3]), a);
	fmVec3 d = fmSub(p, a);
	double volume = fmDot(e1, fmCross(e2, e3));
	if (!(volume != 0.0))
		return false;
	double l1 = fmDot(d, fmCross(e2, e3)) / volume, l2 = fmDot(e1, fmCross(d, e3)) / volume,
	       l3 = fmDot(e1, fmCross(e2, d)) / volume;
	return l1 > 0.0 && l2 > 0.0 && l3 > 0.0 && l1 + l2 + l3 < 1.0;
}

int fmTetHash_Container(const fmTetHash* th, const fmWorld* w, fmHashQuery* query, int slot,
                        fmVec3 p, fmContainerTest* accepts)
{
	int count = fmSpatialHash_Query(&th->hash, query, p, p);
	if (count < 0)
		return -2;
	for (int c = 0; c < count; ++c)
	{
		int item = query->items[c], other = th->body[item];
		fmVec3 lo = th->lower[item], hi = th->upper[item];
		if (p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y || p.z < lo.z || p.z > hi.z)
			continue;
		if (accepts(w, slot, other) && fmInsideTet(&w->bodies[other], th->tet[item], p))
			return other;
	}
	return -1;
}
