// The floor y = height (floor.c): the response of both integrators, depenetration limited by
// fmFloorDef.maxDepenetrationSpeed, and the work it does booked in the energy ledger.
#pragma once

#include "core/arena.h"
#include "body/body.h"
#include "solver/solver_cache.h"

// One vertex the floor held in a substep: what the contact list and the floor's reaction report.
typedef struct fmFloorHit
{
	int vertex;     // the body's index
	double depth;   // m below the floor when found (explicit), or still below it (implicit)
	fmVec3 impulse; // N s the floor gave the vertex (normal and friction)
} fmFloorHit;

// Whether the floor holds @p body: it is enabled and their filters meet.
bool fmFloor_Applies(const fmFloorDef* floor, const fmBody* body);

// Whether the floor at @p height takes vertex @p i of @p body: it is below the plane (or not a
// number) and free in y.
static inline bool fmFloor_Takes(const fmBody* body, int i, double height)
{
	return !(body->state.pinned[i] & FM_PIN_Y) && !(body->state.x[3 * i + 1] >= height);
}

// What the explicit floor did to one vertex it took.
typedef struct fmFloorResponse
{
	double depth;      // m below the floor when found
	fmVec3 impulse;    // N s
	double liftWork;   // J against gravity, lifting it
	double pushEnergy; // J of kinetic energy along y it added
} fmFloorResponse;

// The explicit floor's responses, made on vertex ranges in parallel (fmFloor_RespondRange) and
// collected in vertex order (fmFloor_ApplyExplicit). Each range lists what it took from its own
// first slot on, so that the collection visits the taken vertices only.
typedef struct fmFloorTaken
{
	int* vertex;                // a range's taken vertices, from the slot of its first vertex on
	fmFloorResponse* responses; // their responses, in the same slots
	int* count;                 // at a range's first vertex: how many it took
	int* rangeEnd;              // at a range's first vertex: the vertex after its last
} fmFloorTaken;

// A fmFloorTaken for @p vertexCount vertices from @p arena; false when short of memory.
bool fmFloorTaken_Make(fmFloorTaken* taken, fmArena* arena, int vertexCount);

// The arena bytes fmFloorTaken_Make takes for @p vertexCount vertices.
size_t fmFloorTaken_Bytes(size_t vertexCount);

// Explicit, on the vertices [start, end) of @p body after their position update: each that the
// floor takes (fmFloor_Takes) lifted to the plane (at most at the floor's depenetration speed),
// its velocity by the floor's friction mode, its response listed in @p taken. Touches those
// vertices and their slots only: vertex ranges respond in parallel.
void fmFloor_RespondRange(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, int start, int end,
                          double dt, fmFloorTaken* taken);

// Explicit: the floor's push-out work into @p work (J, for the ledger) and the vertices in contact
// to the body's floorHits, both in vertex order. With @p taken the ranges responded already (the
// position update does it on each vertex range, where the vertices are in cache) and they are
// only collected; without (NULL) every vertex is tested and responds here. Returns how many
// vertices, or -1 when the list could not grow.
int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, double dt,
                          const fmFloorTaken* taken, double* work);

// Implicit: the lowest y of every vertex this step into cache->floorBound: the floor, except for
// a vertex deep below it, which may rise by at most the depenetration speed times h.
void fmFloor_SetBounds(const fmFloorDef* floor, const fmBody* body, fmImplicitCache* cache,
                       double h);

// Implicit: the work (J) the floor did lifting vertices out from below its plane in the step.
double fmFloor_ImplicitWork(const fmBody* body, const fmImplicitCache* cache, double floorHeight);

// Implicit, after the solve: restitution and friction on the velocities of the vertices on the
// floor (the normal impulse from the solve's push, less what friction in the solve answered).
// With @p frictionInSolve (fmContact_FloorFriction: the Newton solves carry the Coulomb floor's
// friction) the floor's push is also the next solve's friction limit (penalty.h), and a vertex
// the floor's friction held in this solve gets no velocity friction for it. The vertices in
// contact go to body->floorHits. Returns how many, or -1 when that list could not grow.
int fmFloor_ImplicitVelocities(const fmFloorDef* floor, fmBody* body, const fmImplicitCache* cache,
                               double h, bool frictionInSolve);
