// The floor y = height (floor.c): the response of both integrators, depenetration limited by
// fmFloorDef.maxDepenetrationSpeed, and the work it does booked in the energy ledger.
#pragma once

#include "body.h"
#include "solver_cache.h"

// One vertex the floor held in a substep: what the contact list and the floor's reaction report.
typedef struct fmFloorHit
{
	int vertex;     // the body's index
	double depth;   // m below the floor when found (explicit), or still below it (implicit)
	fmVec3 impulse; // N s the floor gave the vertex (normal and friction)
} fmFloorHit;

// Whether the floor holds @p body: it is enabled and their filters meet.
bool fmFloor_Holds(const fmFloorDef* floor, const fmBody* body);

// Whether the floor at @p height takes vertex @p i of @p body: it is below the plane (or not a
// number) and free in y.
static inline bool fmFloor_Takes(const fmBody* body, int i, double height)
{
	return !(body->pinned[i] & FM_PIN_Y) && !(body->x[3 * i + 1] >= height);
}

// What the explicit floor did to one vertex it took.
typedef struct fmFloorResponse
{
	double depth;      // m below the floor when found
	fmVec3 impulse;    // N s
	double liftWork;   // J against gravity, lifting it
	double pushEnergy; // J of kinetic energy along y it added
} fmFloorResponse;

// Explicit, one vertex the floor takes (fmFloor_Takes): its position lifted to the plane (at
// most at the floor's depenetration speed), its velocity by the floor's friction mode. Touches
// that vertex only: vertex ranges respond in parallel.
void fmFloor_RespondExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, int vertex,
                             double dt, fmFloorResponse* response);

// Explicit: fmFloor_RespondExplicit on every vertex the floor takes; the push-out work goes to
// the body's energy ledger and the vertices in contact to body->floorHits, both in vertex order.
// With @p taken and @p responses (one a vertex) the responses were made already (the position
// update does them on each vertex range, where the vertices are in cache): they are only
// collected. Returns how many vertices, or -1 when the list could not grow.
int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, double dt,
                          const uint8_t* taken, const fmFloorResponse* responses);

// Implicit: the lowest y of every vertex this step into cache->floorBound: the floor, except for
// a vertex deep below it, which may rise by at most the depenetration speed times h.
void fmFloor_SetBounds(const fmFloorDef* floor, const fmBody* body, fmImplicitCache* cache,
                       double h);

// Implicit: the work (J) the floor did lifting vertices out from below its plane in the step.
double fmFloor_ImplicitWork(const fmBody* body, const fmImplicitCache* cache, double floorHeight);

// Implicit, after the solve: restitution and friction on the velocities of the vertices on the
// floor (the normal impulse from the solve's push). The vertices in contact go to
// body->floorHits. Returns how many, or -1 when that list could not grow.
int fmFloor_ImplicitVelocities(const fmFloorDef* floor, fmBody* body, const fmImplicitCache* cache,
                               double h);
