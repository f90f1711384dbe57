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

// Explicit: positions lifted to the plane (at most at the floor's depenetration speed),
// velocities by the floor's friction mode; push-out work (against gravity, and the normal
// kinetic energy it adds) goes to the body's energy ledger. The vertices in contact go to
// body->floorHits. Returns how many, or -1 when that list could not grow.
int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, double dt);

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
