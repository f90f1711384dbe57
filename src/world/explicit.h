// Explicit integration (explicit.c): symplectic Euler with the seeds' damping factor and
// Laplacian velocity smoothing, then the floor.
#pragma once

#include "world/world.h"

// Advance @p body by one step of @p dt, temporaries from @p arena. Returns fm_ok (the world
// checks the result's health).
fmResult fmExplicitStep(const fmWorld* world, fmBody* body, double dt, fmArena* arena);
