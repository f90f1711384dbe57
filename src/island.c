// Islands and sleeping (island.h): a union-find over the bodies touching in the last frame,
// rebuilt at the end of every frame (a world holds few bodies; the pairs are already sorted).
#include "island.h"

#include "body.h"
#include "contact.h"
#include "core.h"

#include <math.h>
#include <string.h>

static int fmFindRoot(int* parent, int k)
{
	while (parent[k] != k)
	{
		parent[k] = parent[parent[k]];
		k = parent[k];
	}
	return k;
}

// Join the bodies of every body-body pair of the last frame; parent has bodyCapacity slots.
static void fmJoinPairs(const fmWorld* w, int* parent)
{
	for (int k = 0; k < w->bodyCapacity; ++k)
		parent[k] = k;
	const uint64_t* pairs;
	int count = fmContact_FramePairs(w, &pairs);
	for (int p = 0; p < count; ++p)
	{
		int a = (int)(pairs[p] >> 32), b = (int)(uint32_t)pairs[p];
		if (b & (int)0x80000000u)
			continue; // a collider: not part of an island
		int ra = fmFindRoot(parent, a), rb = fmFindRoot(parent, b);
		if (ra != rb)
			parent[ra < rb ? rb : ra] = ra < rb ? ra : rb; // the lower slot is the root
	}
}

static bool fmAddSleepEvent(fmWorld* w, int slot, bool asleep)
{
	if (w->sleepEventCount == w->sleepEventCapacity)
	{
		int grown = w->sleepEventCapacity ? 2 * w->sleepEventCapacity : 16;
		fmSleepEvent* fresh = FM_ALLOC_ARRAY(fmSleepEvent, grown);
		if (fresh == NULL)
			return false;
		if (w->sleepEventCount > 0)
			memcpy(fresh, w->sleepEvents, sizeof(fmSleepEvent) * (size_t)w->sleepEventCount);
		FM_FREE_ARRAY(w->sleepEvents, fmSleepEvent, w->sleepEventCapacity);
		w->sleepEvents = fresh;
		w->sleepEventCapacity = grown;
	}
	fmSleepEvent* e = &w->sleepEvents[w->sleepEventCount++];
	e->body = fmWorldBodyId(w, slot);
	e->asleep = asleep;
	return true;
}

void fmIsland_Wake(fmWorld* w, int slot)
{
	fmBody* b = &w->bodies[slot];
	if (b->x == NULL)
		return;
	b->sleepTimer = 0.0;
	b->wakeRequested = false;
	if (!b->asleep)
		return;
	int island = b->island;
	for (int k = 0; k < w->bodyCapacity; ++k)
	{
		fmBody* o = &w->bodies[k];
		if (o->x == NULL || !o->asleep || o->island != island)
			continue;
		o->asleep = false;
		o->sleepTimer = 0.0;
		o->wakeRequested = false;
		fmAddSleepEvent(w, k, false); // an event lost to memory is only an event
	}
}

// Put every live body whose root is @p root to sleep: still, and marked with the island.
static void fmSleepIsland(fmWorld* w, const int* parent, int root)
{
	for (int k = 0; k < w->bodyCapacity; ++k)
	{
		fmBody* b = &w->bodies[k];
		if (b->x == NULL || b->asleep || fmFindRoot((int*)parent, k) != root)
			continue;
		b->asleep = true;
		b->island = root;
		size_t bytes = sizeof(double) * 3 * (size_t)b->vertexCount;
		memset(b->v, 0, bytes);
		memcpy(b->vGood, b->v, bytes);
		fmAddSleepEvent(w, k, true);
	}
}

void fmIsland_Sleep(fmWorld* w, int slot)
{
	int* parent = FM_ALLOC_ARRAY(int, w->bodyCapacity);
	if (parent == NULL)
		return;
	fmJoinPairs(w, parent);
	fmSleepIsland(w, parent, fmFindRoot(parent, slot));
	FM_FREE_ARRAY(parent, int, w->bodyCapacity);
}

// The fastest vertex of a body (m/s).
static double fmFastest(const fmBody* b)
{
	double fastest = 0.0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		const double* v = b->v + 3 * i;
		fastest = fmax(fastest, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	}
	return sqrt(fastest);
}

// Whether body @p slot touched a moving collider in the last frame (it keeps it awake).
static bool fmTouchesMovingCollider(const fmWorld* w, int slot)
{
	const uint64_t* pairs;
	int count = fmContact_FramePairs(w, &pairs);
	for (int p = 0; p < count; ++p)
	{
		int a = (int)(pairs[p] >> 32), b = (int)(uint32_t)pairs[p];
		if (a != slot || !(b & (int)0x80000000u))
			continue;
		const fmColliderDef* d = &w->colliders[b & 0x7fffffff].def;
		if (fmDot(d->velocity, d->velocity) > 0.0 ||
		    fmDot(d->angularVelocity, d->angularVelocity) > 0.0)
			return true;
	}
	return false;
}

bool fmIsland_EndFrame(fmWorld* w, double frameTime)
{
	const fmContactDef* def = &w->def.contact;
	for (int k = 0; k < w->bodyCapacity; ++k)
		if (w->bodies[k].x != NULL && w->bodies[k].wakeRequested)
			fmIsland_Wake(w, k);
	if (!def->enableSleep)
		return true;
	int* parent = FM_ALLOC_ARRAY(int, w->bodyCapacity);
	double* least = FM_ALLOC_ARRAY(double, w->bodyCapacity);
	bool ok = parent != NULL && least != NULL;
	if (ok)
	{
		fmJoinPairs(w, parent);
		for (int k = 0; k < w->bodyCapacity; ++k)
			least[k] = INFINITY;
		for (int k = 0; k < w->bodyCapacity; ++k)
		{
			fmBody* b = &w->bodies[k];
			if (!fmIsland_Stepping(b))
				continue;
			bool still = b->canSleep && b->targetCount == 0 && fmFastest(b) < def->sleepSpeed &&
			             !fmTouchesMovingCollider(w, k);
			b->sleepTimer = still ? b->sleepTimer + frameTime : 0.0;
			int root = fmFindRoot(parent, k);
			least[root] = fmin(least[root], b->sleepTimer);
		}
		for (int k = 0; k < w->bodyCapacity; ++k)
			if (fmFindRoot(parent, k) == k && least[k] >= def->sleepTime && isfinite(least[k]))
				fmSleepIsland(w, parent, k);
	}
	FM_FREE_ARRAY(parent, int, w->bodyCapacity);
	FM_FREE_ARRAY(least, double, w->bodyCapacity);
	return ok;
}

void fmIsland_WakeBody(fmBodyId bodyId)
{
	fmWorld* w = fmGetWorldOfBody(bodyId);
	if (w != NULL && fmGetBody(bodyId) != NULL)
		fmIsland_Wake(w, bodyId.index1 - 1);
}

int fmWorld_GetSleepEvents(fmWorldId worldId, fmSleepEvent* events, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL);
	if (w == NULL)
		return 0;
	int n = w->sleepEventCount < capacity ? w->sleepEventCount : capacity;
	if (events != NULL && n > 0)
		memcpy(events, w->sleepEvents, sizeof(fmSleepEvent) * (size_t)n);
	return w->sleepEventCount;
}

bool fmBody_IsAwake(fmBodyId bodyId)
{
	const fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	return b != NULL && !b->asleep;
}

void fmBody_SetAwake(fmBodyId bodyId, bool awake)
{
	fmWorld* w = fmGetWorldOfBody(bodyId);
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL && w != NULL);
	if (b == NULL || w == NULL)
		return;
	if (awake)
		fmIsland_Wake(w, bodyId.index1 - 1);
	else
		fmIsland_Sleep(w, bodyId.index1 - 1);
}
