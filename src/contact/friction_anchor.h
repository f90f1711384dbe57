// Anchored friction between bodies (friction_anchor.c): the record each body keeps of its barrier
// friction pairs from one implicit step to the next, so that a pair's spring of static friction
// starts each step from the stretch the last one ended with (barrier_contact.h, penalty.h: the
// same rule against colliders and the floor, per vertex). Rules: a body's records are written
// once its solve is done and read by its next solve; a record's stretch moves by its pair's
// whole relative motion between the two step starts (every body's), so both bodies of a pair
// carry the same stretch.
#pragma once

#include "contact/barrier_contact.h"

// A pair's friction spring as a body's last step began it (body->contact.stretch, sorted by
// stencil, fmBarrierStencil_Compare): the closest points' weights, their relative position
// sum_j w[j] x[j] at that step's start, and the stretch it started from. The next step's stretch
// is this one plus the pair's relative motion since, every body's whole motion counted (both
// bodies of a pair then carry the same stretch: equal and opposite forces).
typedef struct fmBarrierStretch
{
	fmBarrierStencil stencil;
	double w[4];
	fmVec3 relative;
	fmVec3 stretch;
} fmBarrierStretch;

// The order of stencils (body slots, then vertices, then the kind): <0, 0 or >0.
int fmBarrierStencil_Compare(const fmBarrierStencil* a, const fmBarrierStencil* b);

// The stretch pair @p f's spring starts this step from: the one the solved body's last step
// started it from plus the pair's relative motion since, along the surface now, at most the
// slip width (zero for a new pair).
fmVec3 fmFrictionAnchor_Carried(const fmBarrierContact* bc, const fmBarrierFriction* f);

// Keep in @p body each friction pair of the step (fmBarrierStretch), for the body's next step.
// False when memory is short.
bool fmFrictionAnchor_Keep(const fmBarrierContact* bc, fmBody* body);
