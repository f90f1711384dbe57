// Islands and sleeping (island.h): a union-find over the bodies touching in the last frame,
// rebuilt at the end of every frame (a world holds few bodies; the pairs are already sorted).
#include "world/island.h"
#include "core/det_math.h"

#include "body/anchors.h"
#include "body/body.h"
#include "contact/contact_events.h"
#include "core/core.h"

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

// Join bodies @p a and @p b (the lower slot is the root).
static void fmJoin(int* parent, int a, int b)
{
	int ra = fmFindRoot(parent, a), rb = fmFindRoot(parent, b);
	if (ra != rb)
		parent[ra < rb ? rb : ra] = ra < rb ? ra : rb;
}

// Join the bodies of every body-body pair of the last frame and of every weld; parent has
// bodyCapacity slots.
static void fmJoinPairs(const fmWorld* w, int* parent)
{
	for (int k = 0; k < w->bodyCapacity; ++k)
		parent[k] = k;
	for (int k = 0; w->anchorStages != NULL && k < w->bodyCapacity; ++k)
		for (int a = 0; fmBody_IsLive(&w->bodies[k]) && a < w->bodies[k].anchorCount; ++a)
		{
			int o = w->anchorStages->partner(w, &w->bodies[k], a);
			if (o >= 0)
				fmJoin(parent, k, o);
		}
	const uint64_t* pairs;
	int count = fmContactEvents_FramePairs(w, &pairs);
	for (int p = 0; p < count; ++p)
	{
		int a = (int)(pairs[p] >> 32), b = (int)(uint32_t)pairs[p];
		if (!(b & (int)0x80000000u)) // a collider is not part of an island
			fmJoin(parent, a, b);
	}
}

// Room for at least @p capacity sleep events (those stored kept). False when memory is short.
static bool fmReserveSleepEvents(fmWorld* w, int capacity)
{
	if (capacity <= w->sleepEventCapacity)
		return true;
	fmSleepEvent* fresh = FM_ALLOC_ARRAY(fmSleepEvent, capacity);
	if (fresh == NULL)
		return false;
	if (w->sleepEventCount > 0)
		memcpy(fresh, w->sleepEvents, sizeof(fmSleepEvent) * (size_t)w->sleepEventCount);
	FM_FREE_ARRAY(w->sleepEvents, fmSleepEvent, w->sleepEventCapacity);
	w->sleepEvents = fresh;
	w->sleepEventCapacity = capacity;
	return true;
}

static bool fmAddSleepEvent(fmWorld* w, int slot, bool asleep)
{
	if (w->sleepEventCount == w->sleepEventCapacity &&
	    !fmReserveSleepEvents(w, w->sleepEventCapacity ? 2 * w->sleepEventCapacity : 16))
		return false;
	fmSleepEvent* e = &w->sleepEvents[w->sleepEventCount++];
	e->body = fmWorldBodyId(w, slot);
	e->asleep = asleep;
	return true;
}

void fmIsland_Wake(fmWorld* w, int slot)
{
	fmBody* b = &w->bodies[slot];
	if (!fmBody_IsLive(b))
		return;
	b->sleepTimer = 0.0;
	b->wakeRequested = false;
	if (!b->asleep)
		return;
	int island = b->island;
	for (int k = 0; k < w->bodyCapacity; ++k)
	{
		fmBody* o = &w->bodies[k];
		if (!fmBody_IsLive(o) || !o->asleep || o->island != island)
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
		if (!fmBody_IsLive(b) || b->asleep || fmFindRoot((int*)parent, k) != root)
			continue;
		b->asleep = true;
		b->island = root;
		size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
		memset(b->state.v, 0, bytes);
		memcpy(b->vGood, b->state.v, bytes);
		fmAddSleepEvent(w, k, true);
	}
}

// The union-find's arrays for every body slot, kept by the world (no allocation per step once
// they exist). False when memory is short.
static bool fmIslandArrays(fmWorld* w)
{
	if (w->islandCapacity >= w->bodyCapacity)
		return true;
	FM_FREE_ARRAY(w->islandParent, int, w->islandCapacity);
	FM_FREE_ARRAY(w->islandLeast, double, w->islandCapacity);
	w->islandParent = FM_ALLOC_ARRAY(int, w->bodyCapacity);
	w->islandLeast = FM_ALLOC_ARRAY(double, w->bodyCapacity);
	w->islandCapacity = w->bodyCapacity;
	// Room for a sleep and a wake of every body in one step, so that events do not allocate.
	if (w->islandParent != NULL && w->islandLeast != NULL &&
	    fmReserveSleepEvents(w, 2 * w->bodyCapacity))
		return true;
	FM_FREE_ARRAY(w->islandParent, int, w->bodyCapacity);
	FM_FREE_ARRAY(w->islandLeast, double, w->bodyCapacity);
	w->islandCapacity = 0;
	return false;
}

void fmIsland_Sleep(fmWorld* w, int slot)
{
	if (!fmIslandArrays(w))
		return;
	fmJoinPairs(w, w->islandParent);
	fmSleepIsland(w, w->islandParent, fmFindRoot(w->islandParent, slot));
}

// The fastest vertex of a body (m/s).
static double fmFastest(const fmBody* b)
{
	double fastest = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		const double* v = b->state.v + 3 * i;
		fastest = fmMax(fastest, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	}
	return sqrt(fastest);
}

// Whether body @p slot touched a moving collider in the last frame (it keeps it awake).
static bool fmTouchesMovingCollider(fmWorld* w, int slot)
{
	const uint64_t* pairs;
	int count = fmContactEvents_FramePairs(w, &pairs);
	for (int p = 0; p < count; ++p)
	{
		int a = (int)(pairs[p] >> 32), b = (int)(uint32_t)pairs[p];
		if (a != slot || !(b & (int)0x80000000u))
			continue;
		if (fmCollider_IsMoving(fmWorldCollider(w, b & 0x7fffffff)))
			return true;
	}
	return false;
}

bool fmIsland_EndFrame(fmWorld* w, const fmStepContext* ctx)
{
	const double frameTime = ctx->frameTime;
	const fmContactDef* def = &w->def.contact;
	for (int k = 0; k < w->bodyCapacity; ++k)
		if (fmBody_IsLive(&w->bodies[k]) && w->bodies[k].wakeRequested)
			fmIsland_Wake(w, k);
	if (!def->enableSleep)
		return true;
	if (!fmIslandArrays(w))
		return false;
	int* parent = w->islandParent;
	double* least = w->islandLeast;
	fmJoinPairs(w, parent);
	for (int k = 0; k < w->bodyCapacity; ++k)
		least[k] = INFINITY;
	for (int k = 0; k < w->bodyCapacity; ++k)
	{
		fmBody* b = &w->bodies[k];
		if (!fmIsland_Stepping(b))
			continue;
		bool still = b->canSleep && b->targetCount == 0 && fmFastest(b) < def->sleepSpeed &&
		             !fmTouchesMovingCollider(w, k) &&
		             !(w->anchorStages != NULL && w->anchorStages->onMovingCollider(w, b));
		b->sleepTimer = still ? b->sleepTimer + frameTime : 0.0;
		int root = fmFindRoot(parent, k);
		least[root] = fmMin(least[root], b->sleepTimer);
	}
	for (int k = 0; k < w->bodyCapacity; ++k)
		if (fmFindRoot(parent, k) == k && least[k] >= def->sleepTime && isfinite(least[k]))
			fmSleepIsland(w, parent, k);
	return true;
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
