// Explicit integration (explicit.c): symplectic Euler with the seeds' damping factor and
// Laplacian velocity smoothing, then the floor.
#pragma once

#include "world/world.h"

// Advance @p body by the context's substep, temporaries from its arena. Returns fm_ok (the world
// checks the result's health).
fmResult fmExplicitStep(const fmWorld* world, const fmStepContext* context, fmBody* body);
