// Kinematic targets (targets.c): springs from chosen vertices to positions the caller moves
// every frame (fmBody_SetTargets) or a grab moves (grab.h), in both integrators, with their work
// booked in the body's energy ledger. A target may carry a dashpot against its vertex's velocity
// relative to the target's, and a bound on its force: beyond the stretch maxForce / stiffness
// its energy grows linearly (a Huber spring), so its pull never exceeds maxForce.
#pragma once

#include "body/body.h"
#include "solver/newton.h"

// One pulled vertex.
typedef struct fmTarget
{
	int vertex;         // the body's index of the pulled vertex
	double position[3]; // m, where it is pulled now
	double motion[3];   // m, the position's motion over the frame (its velocity x frame time)
	double stiffness;   // N/m
	double damping;     // N s/m, against the vertex's velocity relative to the position's
	double maxForce;    // N, the bound on the target's force (INFINITY: none)
	double applied[3];  // N, the force of the last substep (its work, an attachment's reaction)
} fmTarget;

// The body's springs: its targets, then its attachments' (anchors.h), as every sum takes them.
static inline int fmTargets_Count(const fmBody* body)
{
	return body->targetCount + body->anchorCount;
}

// Spring @p t of fmTargets_Count.
static inline fmTarget* fmTargets_At(const fmBody* body, int t)
{
	return t < body->targetCount ? &body->targets[t] : &body->anchorTargets[t - body->targetCount];
}

// Room for @p count targets on the body (grows, never shrinks); false without memory.
bool fmTargets_Reserve(fmBody* body, int count);

// The targets as an implicit step sees them: the dashpot over a step of 1 / @p rate is a spring
// toward where the vertex would be at the target's velocity, so each target is one bounded
// spring of stiffness k + c rate toward the blend of the two. @p xStart NULL and @p rate 0 for a
// static solve (the springs alone).
typedef struct fmTargetStep
{
	const fmBody* body;
	const double* xStart; // the step's start positions, or NULL
	double rate;          // 1/s, one over the step
	double frameRate;     // 1/s, one over the frame: a target's velocity is motion x frameRate
} fmTargetStep;

// Implicit: the force (N, minus the gradient of its energy) of target @p t at positions @p x.
void fmTargets_Force(const fmTargetStep* step, int t, const double* x, double force[3]);

// The springs as a term of an implicit step's potential (energy, Hessian, products), for
// fmNewtonProblem.targets; @p step and its body must outlive the solve.
fmNewtonTerm fmTargets_Term(const fmTargetStep* step);

// Implicit: the springs' work over a step from the step's start to @p x, with the forces at the
// end (backward Euler's), each spring's force kept in its `applied` (the attachments' reactions).
double fmTargets_ImplicitWork(const fmTargetStep* step, const double* x);

// Explicit: the force of target @p t on its vertex at @p x, @p v (the body's arrays) with its
// stiffness limited to @p stiffnessLimit and its damping to @p dampingLimit (N/m and N s/m: the
// substep's stability), the target moving at motion x @p frameRate, bounded by maxForce.
void fmTargets_ExplicitForce(const fmTarget* target, const double* x, const double* v,
                             double stiffnessLimit, double dampingLimit, double frameRate,
                             double force[3]);

// Release the targets' memory.
void fmTargets_Free(fmBody* body);
