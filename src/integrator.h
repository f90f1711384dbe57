// Time integrators. Each advances one body by one step of length dt; the world calls them in
// order for every substep. Both return fm_ok or fm_errNumerical (the world restores the state).
#pragma once

#include "newton.h"
#include "world.h"

// Symplectic Euler with the seeds' damping factor and Laplacian velocity smoothing, then the
// floor (explicit.c).
fmResult fmExplicitStep(const fmWorld* world, fmBody* body, double dt);

// Backward Euler: Newton on the incremental potential with projected Hessians, PCG and a
// backtracking line search; pins exact, floor as constraints (implicit.c). @p solve gets the
// Newton solve's counters and whether it converged. fm_errNumerical: the solve went
// non-finite (the world restores the state).
fmResult fmImplicitStep(const fmWorld* world, fmBody* body, double dt, fmNewtonResult* solve);

// The seeds' velocity damping factor and Laplacian smoothing, scaled from their 3 ms step to dt
// so that damping per second does not depend on the step (velocity_filter.c).
void fmFilterVelocities(fmBody* body, double dt);

// Floor response for explicit integration: positions lifted to the plane (at most at the
// floor's depenetration speed), velocities by the floor's friction mode; push-out work (against
// gravity, and the normal kinetic energy it adds) goes to the body's energy ledger (contact.c).
// Returns the number of vertices in contact.
int fmApplyFloor(const fmFloorDef* floor, fmVec3 gravity, fmBody* body, double dt);

// Release the implicit solver's per-body buffers (body->implicitCache). NULL is fine.
void fmImplicitCacheFree(void* cache);
