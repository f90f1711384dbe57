// The energy ledger of a body: the work done on it, against which a runaway is judged.
//
// A body's kinetic plus elastic energy can never exceed what it started with plus the work
// done on it since: by gravity, by contacts (depenetration) and by the caller (impulses, state
// set between frames, a material change). Every source of work feeds the ledger; a frame whose
// energy ends above E0 + W + 1% of (E0 + W_in) + a floor (docs/robustness.md) is a numerical
// failure, however slowly the energy crept up.
#pragma once

#include "core/arena.h"
#include "core/parallel.h"
#include "core/step_context.h"

#include <femto/types.h>

#include <stdbool.h>

struct fmBody;

// How the ledger's elastic pass runs: the forces of the shadow term in a buffer of @p arena (one
// vector of 3n doubles), on the workers of @p tasks (NULL: serially; the same bits on any
// number). An explicit body whose steps take their forces from the batched kernels (tet_blocks.h,
// at @p simd) is measured by them too, forces and energy in one pass at their speed (float per
// tet, summed in double: a relative error of about 1e-7 / strain, far inside the ledger's 1% and
// its floor); any other body by the double-precision reference.
typedef struct fmEnergyPass
{
	fmArena* arena;
	const fmTaskSystem* tasks;
	fmSimdLevel simd;
} fmEnergyPass;

typedef struct fmEnergyLedger
{
	bool started;            // the first frame has set initialEnergy
	double initialEnergy;    // J, kinetic + elastic energy at the first step (E0)
	double work;             // J, net work done on the body since (W)
	double workIn;           // J, the positive contributions to W (sets the tolerance)
	double floor;            // J, absolute tolerance for bodies that start at rest
	double gravityStart;     // J, sum of m g . x at the start of the frame
	double frameGravityWork; // J, gravity's work over the frame (set by fmLedger_Check)
	double measureStep;      // s, the shadow step energyGood was measured with
	double plainGood;        // J, plain kinetic + elastic energy of the good state
	double framePlain;       // J, the same at the end of the frame being checked
} fmEnergyLedger;

// Kinetic plus elastic energy of the body's current state (J), as the integrator conserves it.
// Symplectic Euler with step h does not conserve E = T + Psi - M g . x but, to O(h^2), the
// shadow energy E + (h/2) v . f(x) (f the conservative forces: elastic and gravity), whose
// difference from E swings by several percent at steps near the stability limit. Explicit
// frames measure with @p shadowStep = h, implicit ones (dissipative) with 0. The gravity part
// of the correction is included; the potential -M g . x itself is booked as gravity's work.
// @p plain (may be NULL) gets the plain kinetic + elastic energy. @p pass says how the elastic
// pass runs (below). A non-NULL @p inverted gets the body's inverted tets (fmBodyCountInverted)
// when the pass counted them on the way (the explicit kernels' blocks), else -1.
double fmBodyEnergy(struct fmBody* body, fmVec3 gravity, double shadowStep, double* plain,
                    int* inverted, const struct fmEnergyPass* pass);

// Start a frame measured with @p shadowStep (fmBodyEnergy): on the first frame record E0;
// otherwise book what the caller changed since the last good state (impulses, set positions or
// velocities, material) as work. Updates body->energyGood.
void fmLedger_BeginFrame(struct fmBody* body, fmVec3 gravity, double shadowStep,
                         const fmEnergyPass* pass);

// The verdict on a frame: ok, or which check failed with the energy it measured and the bound.
typedef struct fmLedgerVerdict
{
	bool ok;
	bool backstop;   // the per-frame backstop failed (else the ledger)
	double measured; // J, the energy that was compared
	double bound;    // J, what it was allowed
} fmLedgerVerdict;

// Check the end of a frame of @p frameTime seconds whose final energy is @p energy (J, as
// measured for the ledger) and @p plain (J, kinetic + elastic): within the ledger's bound, and
// the plain energy within the per-frame backstop (1000 times what the frame started with plus
// what gravity can add in it), which catches an unstable step whose shadow energy means
// nothing. Books nothing.
fmLedgerVerdict fmLedger_Check(struct fmBody* body, const fmFrameWork* work, fmVec3 gravity,
                               double energy, double plain, double frameTime);

// Within a frame the explicit step changed from @p fromStep to @p toStep: the shadow energy's
// measure changed with it. Book the difference at the current state in the frame's @p work
// (neutral: not in workIn; committed with the frame, dropped with a refused one), as BeginFrame
// does between frames. A stable step's shadow term is at most about the body's energy: the
// change is bounded by the energy the frame started with plus what gravity, contacts and loads
// can add in it, and a non-finite one books nothing (an exploding state's correction is as large
// as the explosion: booked, it would let the explosion pass the ledger).
void fmLedger_ChangeMeasure(struct fmBody* body, fmFrameWork* work, fmVec3 gravity,
                            double frameTime, double fromStep, double toStep,
                            const fmEnergyPass* pass);

// Book the frame's work (after every body of the world passed fmLedger_Check); the good state's
// energy was measured with @p shadowStep.
void fmLedger_Commit(struct fmBody* body, const fmFrameWork* work, double shadowStep);
