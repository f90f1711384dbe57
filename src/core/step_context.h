// The step context: what one frame of fmWorld_Step hands down its stages, built once a frame by
// world.c (after Box2D's b2StepContext). The frame's times live here and nowhere else: a stage
// reads them from the context, never from a parameter of its own, and the files that read them
// are listed in docs/architecture.md (scripts/check-structure.sh keeps the list true).
//
// The stages also book into it the work they do on each body (contacts, targets, loads); the
// world alone opens and closes the bodies' energy ledgers with it (energy_ledger.h).
#pragma once

#include "core/arena.h"
#include "core/parallel.h"

#include <femto/femto.h>

// The work done on one body in the frame being stepped (J).
typedef struct fmFrameWork
{
	double contact; // the positive work of contacts and kinematic targets
	double load;    // the net work of loads and prescribed displacements (either sign)
	double loadIn;  // its positive substep contributions
	double measure; // the shadow energy's change of measure as the explicit step changed within
	                // the frame (either sign; neither work done nor a runaway)
} fmFrameWork;

typedef struct fmStepContext
{
	double frameTime;  // s, the frame (fmWorld_Step's timeStep)
	double substep;    // s, the substep being taken
	double shadowStep; // s, the step the ledger measures the shadow energy with (explicit: the
	                   // substep; implicit: 0)
	double elapsed;    // s, the frame's time the substeps taken so far have covered
	int substepCount;  // the caller's substeps a frame
	int newtonLimit;   // Newton iterations an implicit step may take now (the frame budget)
	fmIntegrator integrator;
	fmVec3 gravity;            // m/s^2
	const fmTaskSystem* tasks; // the world's workers (NULL: serial, in a body stepped on one)
	fmArena* arena; // the step's temporaries (the worker's own while bodies step at once)
	int worker;     // the worker stepping a body: whose arena and barrier scratch it uses
	fmSimdLevel simd;          // the element kernels' instruction set
	fmFrameWork* work;         // per body slot: what the stages booked this frame
	int bodyCapacity;          // slots in work
} fmStepContext;

// Book @p work (J) a contact or a kinematic target did on the body in slot @p slot during a
// substep: its positive part.
void fmStepContext_AddContactWork(const fmStepContext* context, int slot, double work);

// Book @p work (J, either sign) loads or prescribed displacements did on the body in slot @p slot
// during a substep.
void fmStepContext_AddLoadWork(const fmStepContext* context, int slot, double work);
