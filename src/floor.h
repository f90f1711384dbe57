// The floor y = height (floor.c): the response of both integrators, depenetration limited by
// fmFloorDef.maxDepenetrationSpeed, and the work it does booked in the energy ledger.
#pragma once

#include "body.h"
#include "solver_cache.h"

// Explicit: positions lifted to the plane (at most at the floor's depenetration speed),
// velocities by the floor's friction mode; push-out work (against gravity, and the normal
// kinetic energy it adds) goes to the body's energy ledger. Returns the vertices in contact.
int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, double dt);

// Implicit: the lowest y of every vertex this step into cache->floorBound: the floor, except for
// a vertex deep below it, which may rise by at most the depenetration speed times h.
void fmFloor_SetBounds(const fmFloorDef* floor, const fmBody* body, fmImplicitCache* cache,
                       double h);

// Implicit: the work (J) the floor did lifting vertices out from below its plane in the step.
double fmFloor_ImplicitWork(const fmBody* body, const fmImplicitCache* cache, double floorHeight);

// Implicit, after the solve: restitution and friction on the velocities of the vertices on the
// floor (the normal impulse from the solve's push). Returns the vertices in contact.
int fmFloor_ImplicitVelocities(const fmFloorDef* floor, fmBody* body, const fmImplicitCache* cache,
                               double h);

// Whether vertex @p i is on or below the floor (within 1e-9 m).
bool fmFloor_Touches(const fmFloorDef* floor, const fmBody* body, int i);

// Vertices on or below the floor (within 1e-9 m), for the step statistics.
int fmFloor_CountContacts(const fmFloorDef* floor, const fmBody* body);
