// Plasticity in a body (docs/materials.md, "Plasticity"): multiplicative (F = Fe Fp), a tet's
// plastic part kept in its rest data: with Dm^-1 holding Dm^-1 Fp^-1, F = Ds Dm^-1 is the
// elastic part, so every force, Hessian and kernel sees Fe as it is; after each substep the
// return map (material/material_plastic.h) moves Dm^-1 where the flow puts it. The flow is
// isochoric (det Fp = 1): the rest volumes stay.
#pragma once

#include <stdbool.h>

struct fmBody;

// Give body @p b its per-tet plastic state (plastic strains, zero, and a copy of its rest data
// before any flow) when it has none; false when out of memory.
bool fmPlasticity_Allocate(struct fmBody* b);

// Free body @p b's plastic state (it has not flowed, or goes back to its rest shape).
void fmPlasticity_Free(struct fmBody* b);

// Keep body @p b's plastic state at the start of a frame it steps, to go back to
// (fmPlasticity_RestoreGood) when the frame is refused; nothing without plastic state.
void fmPlasticity_KeepGood(struct fmBody* b);

// A refused frame: body @p b's rest data, plastic strains and plastic work as they were kept at
// its start (nothing when none was kept this frame).
void fmPlasticity_RestoreGood(struct fmBody* b);

// Whether one of body @p b's materials flows.
bool fmPlasticity_AnyFlows(const struct fmBody* b);

// fmPlasticity_Allocate when one of body @p b's materials flows; false when out of memory.
bool fmPlasticity_Prepare(struct fmBody* b);

// Body @p b's rest data as before any flow, its plastic strains zero (a restored snapshot of a
// body that had not flowed).
void fmPlasticity_Unflowed(struct fmBody* b);

// After a substep of @p h: every plastic tet of body @p b flows (its Dm^-1 and plastic strain
// move; the implicit solve's kept evaluations follow); the
// plastic work of the flow (rest volume x the von Mises stress along the flow x the flow, the
// stress by the trapezoid from the yield surface the tet left to the returned state: exact for
// linear hardening) is added to the body's. Returns the largest flow of
// a tet this call, in units of its yield strain (sigma_y / 3 mu); 0 when nothing flowed.
double fmPlasticity_Flow(struct fmBody* b, double h);

// The largest equivalent plastic strain of body @p b's tets (0 without plastic state).
double fmPlasticity_LargestStrain(const struct fmBody* b);
