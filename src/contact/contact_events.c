// The contact stage's results (contact_events.h).
#include "contact/contact_events.h"

#include "contact/contact_state.h"
#include "contact/floor.h"
#include "core/core.h"
#include "core/det_math.h"
#include "world/island.h"

#include <stdlib.h>
#include <string.h>

static int fmCompareKeys(const void* a, const void* b)
{
	uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

static bool fmAddEvent(fmWorld* w, fmContactState* s, uint64_t key, bool begin)
{
	if (!fmGrowArray((void**)&s->events, &s->eventCapacity, s->eventCount, s->eventCount + 1,
	                 sizeof(fmContactEvent)))
		return false;
	fmContactEvent* e = &s->events[s->eventCount++];
	memset(e, 0, sizeof *e);
	e->begin = begin;
	int a = (int)(key >> 32), b = (int)(uint32_t)key;
	e->body = fmWorldBodyId(w, a);
	if (b & (int)0x80000000u)
		e->collider = fmWorldColliderId(w, b & 0x7fffffff);
	else
		e->otherBody = fmWorldBodyId(w, b);
	return true;
}

bool fmContactEvents_ReportFloor(fmWorld* w, bool listed)
{
	fmContactState* s = w->contactState;
	if (s == NULL && !w->def.floor.enabled)
		return true;
	if (s == NULL && (s = fmContactState_Get(w)) == NULL)
		return false;
	if (!listed)
		s->pointCount = 0;
	fmCollider* floor = &w->floorCollider;
	const fmColliderId floorId = fmWorldColliderId(w, FM_FLOOR_SLOT);
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmBody* b = &w->bodies[slot];
		if (!fmIsland_Stepping(b) || b->contact.floorHitCount == 0)
			continue;
		// The body's points at once (a resting body has hundreds a substep, all serial here).
		if (!fmGrowArray((void**)&s->points, &s->pointCapacity, s->pointCount,
		                 s->pointCount + b->contact.floorHitCount, sizeof(fmContactPoint)))
			return false;
		memset(s->points + s->pointCount, 0,
		       (size_t)b->contact.floorHitCount * sizeof(fmContactPoint));
		const fmBodyId id = fmWorldBodyId(w, slot);
		for (int k = 0; k < b->contact.floorHitCount; ++k)
		{
			const fmFloorHit* hit = &b->contact.floorHits[k];
			fmContactPoint* p = &s->points[s->pointCount++];
			p->body = id;
			p->vertex = b->userVertex[hit->vertex];
			p->collider = floorId;
			p->point = fmLoad(b->state.x, hit->vertex);
			p->normal = floor->def.normal;
			p->depth = hit->depth;
			p->impulse = hit->impulse.y;
			floor->impulse = fmSub(floor->impulse, hit->impulse);
			floor->angularImpulse = fmSub(floor->angularImpulse,
			                              fmCross(fmSub(p->point, floor->position), hit->impulse));
		}
		b->contact.floorHitCount = 0;
		uint64_t key = ((uint64_t)(uint32_t)slot << 32) | (0x80000000u | (uint32_t)FM_FLOOR_SLOT);
		if (!fmContactState_RecordPair(s, key))
			return false;
	}
	return true;
}

bool fmContactEvents_EndFrame(fmWorld* w, double perSecond)
{
	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		fmCollider* c = fmWorldCollider(w, k < w->colliderCapacity ? k : FM_FLOOR_SLOT);
		c->force = fmScale(perSecond, c->impulse);
		c->torque = fmScale(perSecond, c->angularImpulse);
	}
	fmContactState* s = w->contactState;
	if (s == NULL)
		return true;
	// Sleeping bodies keep their pairs (no end events while an island sleeps).
	for (int k = 0; k < s->lastPairCount; ++k)
	{
		int a = (int)(s->lastPairs[k] >> 32), b = (int)(uint32_t)s->lastPairs[k];
		bool collider = (b & (int)0x80000000u) != 0;
		if ((w->bodies[a].asleep || (!collider && w->bodies[b].asleep)) &&
		    !fmContactState_RecordPair(s, s->lastPairs[k]))
			return false;
	}
	if (s->pairCount > 1)
		qsort(s->pairs, (size_t)s->pairCount, sizeof(uint64_t), fmCompareKeys);
	int unique = 0;
	for (int k = 0; k < s->pairCount; ++k)
		if (unique == 0 || s->pairs[unique - 1] != s->pairs[k])
			s->pairs[unique++] = s->pairs[k];
	s->pairCount = unique;
	s->eventCount = 0;
	bool ok = true;
	int a = 0, b = 0;
	while (ok && (a < s->pairCount || b < s->lastPairCount))
	{
		bool takeNew = b >= s->lastPairCount || (a < s->pairCount && s->pairs[a] < s->lastPairs[b]);
		bool same = a < s->pairCount && b < s->lastPairCount && s->pairs[a] == s->lastPairs[b];
		if (same)
			a += 1, b += 1;
		else if (takeNew)
			ok = fmAddEvent(w, s, s->pairs[a++], true);
		else
			ok = fmAddEvent(w, s, s->lastPairs[b++], false);
	}
	// This frame's pairs become the last frame's.
	uint64_t* pairs = s->lastPairs;
	int capacity = s->lastPairCapacity;
	s->lastPairs = s->pairs;
	s->lastPairCapacity = s->pairCapacity;
	s->lastPairCount = s->pairCount;
	s->pairs = pairs;
	s->pairCapacity = capacity;
	s->pairCount = 0;
	return ok;
}

int fmContactEvents_FramePairs(const fmWorld* w, const uint64_t** pairs)
{
	const fmContactState* s = w->contactState;
	*pairs = s ? s->lastPairs : NULL;
	return s ? s->lastPairCount : 0;
}

int fmContactEvents_Points(const fmWorld* w, const fmContactPoint** points)
{
	*points = w->contactState ? w->contactState->points : NULL;
	return w->contactState ? w->contactState->pointCount : 0;
}

bool fmContactEvents_SetFramePairs(fmWorld* w, const void* pairs, int count)
{
	if (count == 0 && w->contactState == NULL)
		return true;
	fmContactState* s = fmContactState_Get(w);
	if (s == NULL ||
	    !fmGrowArray((void**)&s->lastPairs, &s->lastPairCapacity, 0, count, sizeof(uint64_t)))
		return false;
	if (count > 0)
		memcpy(s->lastPairs, pairs, sizeof(uint64_t) * (size_t)count);
	s->lastPairCount = count;
	return true;
}

int fmWorld_GetContacts(fmWorldId worldId, fmContactPoint* contacts, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && (capacity == 0 || contacts != NULL));
	if (w == NULL || w->contactState == NULL)
		return 0;
	const fmContactState* s = w->contactState;
	int copy = capacity < s->pointCount ? capacity : s->pointCount;
	if (copy > 0 && contacts != NULL)
		memcpy(contacts, s->points, sizeof(fmContactPoint) * (size_t)copy);
	return s->pointCount;
}

int fmWorld_GetContactEvents(fmWorldId worldId, fmContactEvent* events, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && (capacity == 0 || events != NULL));
	if (w == NULL || w->contactState == NULL)
		return 0;
	const fmContactState* s = w->contactState;
	int copy = capacity < s->eventCount ? capacity : s->eventCount;
	if (copy > 0 && events != NULL)
		memcpy(events, s->events, sizeof(fmContactEvent) * (size_t)copy);
	return s->eventCount;
}
