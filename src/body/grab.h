// A grab (grab.c): a point of a body held by a bounded, damped spring spread over the patch of
// vertices around it, moved by the caller every frame (fmBody_Grab, fmBody_MoveGrab,
// fmWorld_GrabRay). The grab owns the body's targets (targets.h) while it lasts: every substep
// places them where the target has got to within the frame.
#pragma once

#include "body/body.h"

typedef struct fmGrab
{
	int count;        // pulled vertices, the body's targets 0 .. count-1
	double* weight;   // count: each vertex's share of the pull (summing to 1)
	double* rest;     // 3 per vertex: where it was at the grab (m)
	fmVec3 anchor;    // the grabbed point at the grab
	fmVec3 from;      // where the target was at the frame's start
	fmVec3 goal;      // where the caller asked for it (reached at the frame's end)
	double stiffness; // N/m, the whole grab's
	double damping;   // N s/m, the whole grab's
	double maxForce;  // N, the whole grab's bound
	double proxy;     // the body's stiffening proxy (stability.h) at the grab
	double settled;   // J: the kinetic energy the body is settled below once let go
} fmGrab;

// Place the grabbed body's targets where the grab's target is at @p fraction of the frame (in
// [0, 1]: the substep's end).
void fmGrab_Advance(fmBody* body, double fraction);

// The frame is done: its goal is where the next one starts.
void fmGrab_EndFrame(fmBody* body);

// Drop the grab (its targets too); nothing when there is none.
void fmGrab_Free(fmBody* body);

// Whether an explicit world must take adaptive substeps for the body: it is grabbed, or was and
// is still stretched beyond 1.1 times its stiffening proxy at the grab (a stretched body let go
// snaps back, faster than the scene's fixed substep may follow), or still moves with more
// kinetic energy than twice its own at the grab plus that of a 1 cm fall (a body lifted or
// flung by a grab lands harder than the scene's fixed substep may hold). Forgets a let-go body
// that has relaxed and settled.
bool fmGrab_NeedsAdaptiveSteps(fmBody* body);
