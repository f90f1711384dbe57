// Implicit integration (implicit.c): backward Euler as the minimisation of the incremental
// potential by the Newton solver (newton.h), pins exact, the floor as bounds (floor.h).
#pragma once

#include "solver/newton.h"
#include "world/world.h"

// Advance @p body by the context's substep (temporaries from its arena). @p solve gets the
// Newton solve's counters and whether it converged. fm_errNumerical: the solve went non-finite (the
// world restores the state); fm_errOutOfMemory: no memory for the solver's cache.
fmResult fmImplicitStep(const fmWorld* world, const fmStepContext* context, fmBody* body,
                        fmNewtonResult* solve);
