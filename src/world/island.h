// Islands and sleeping (island.c), as in Box2D: bodies that touched each other during a frame
// form an island; an island whose bodies all stayed slower than fmContactDef.sleepSpeed for
// sleepTime falls asleep. A sleeping body is not stepped, checked or moved by contact (it is an
// immovable obstacle); it wakes, with its island, at the end of a frame in which an awake body
// or a moving collider touched it, or when the API changes it.
#pragma once

#include "world/world.h"

// After a frame that passed its checks: wake what was touched, advance the timers, put islands
// at rest to sleep. False when memory for the events is short.
bool fmIsland_EndFrame(fmWorld* world, const fmStepContext* context);

// Wake body slot @p slot and every body of its island (an event for each that slept).
void fmIsland_Wake(fmWorld* world, int slot);

// Put body slot @p slot and every body touching it (transitively, in the last frame) to sleep.
void fmIsland_Sleep(fmWorld* world, int slot);

// Wake the body behind a public id (the API calls that change a body).
void fmIsland_WakeBody(fmBodyId bodyId);

// Whether a body is stepped (live and awake).
static inline bool fmIsland_Stepping(const fmBody* b)
{
	return fmBody_IsLive(b) && !b->asleep;
}
