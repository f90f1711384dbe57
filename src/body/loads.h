// Loads and prescribed displacements of a body (loads.c, docs/loads.md): nodal forces, surface
// pressure (fixed direction or follower) and pinned vertices moved along a prescribed path, in
// the explicit step, the implicit step and the static solver, their work booked in the body's
// energy ledger.
//
// Every integrator sees the loads through one vector, the "frozen" load: the total load force
// at a configuration, times a scale (the static solver's load fraction). Nodal forces and
// fixed-direction pressure (computed once on the rest shape) are constant; follower pressure is
// evaluated at the configuration the load is frozen at: every explicit substep, the start of
// every implicit step, and every Newton solve of the static solver, which then repeats the
// solve with the load re-frozen at its result until the result no longer moves (a lagged,
// fixed-point treatment: each Newton solve minimises a true potential -f . x with a symmetric
// Hessian, and the follower load's non-symmetric stiffness never enters a matrix).
#pragma once

#include "body/body.h"
#include "solver/newton.h"

// One vertex moved by a prescribed displacement (fmBody_PrescribeDisplacement).
typedef struct fmPrescribed
{
	int vertex;             // the body's index
	unsigned axes;          // pinned axes it moves along (bit 0 x, 1 y, 2 z)
	double start[3];        // m, where it was when the displacement was prescribed
	double displacement[3]; // m, reached after `time`
	double time;            // s of simulated time to reach it (dynamics); 0: at once
	double elapsed;         // s of it simulated so far
	bool reached;           // the full displacement is in place
	double from[3];         // m, where the static solver's ramp starts
} fmPrescribed;

typedef struct fmLoadSet
{
	int vertexCount;
	double* fixed; // 3n (N): nodal forces plus fixed-direction pressure, or NULL
	int followerCount;
	int followerCapacity;
	int* followerTriangle;    // 3 per follower triangle (the body's vertices, outward)
	double* followerPressure; // Pa per follower triangle
	double* frozen;           // 3n (N): the total load frozen by fmLoads_Freeze
	int prescribedCount;
	int prescribedCapacity;
	fmPrescribed* prescribed;
	double* shadowForces; // 6n: elastic forces before and after a prescribed move (explicit)
	bool keptAwake;       // a prescribed motion holds the body awake (body->canSleep false)
	bool canSleep;        // body->canSleep to give back when the motion ends
} fmLoadSet;

// Free a body's load set (NULL is fine).
void fmLoads_Free(fmLoadSet* loads);

// The load arrays for @p count vertices after a tear (fracture.h): a vertex whose source
// @p from[i] is itself keeps its loads, a copy starts with none; false when out of memory
// (unchanged).
bool fmLoads_Renumber(fmBody* body, int count, const int* from);

// Whether the body carries a force load (nodal or pressure).
bool fmLoads_Active(const fmBody* body);

// Whether a prescribed displacement is still on its way (dynamics).
bool fmLoads_Moving(const fmBody* body);

// Freeze the load at positions @p x times @p scale into body->loads->frozen; returns it, or NULL
// when the body has no force load.
const double* fmLoads_Freeze(fmBody* body, const double* x, double scale);

// f += the load at positions @p x (unscaled, follower pressure evaluated at x).
void fmLoads_AddForces(const fmBody* body, const double* x, double* f);

// The frozen load's potential -f . (x - xStart) at @p x, with -f added to @p gradient when it
// is not NULL (0 without loads).
double fmLoads_Energy(const fmBody* body, const double* x, const double* xStart, double* gradient);

// The frozen loads as a term of an implicit or static solve's potential (fmLoads_Energy; no
// Hessian), for fmNewtonProblem.loads; @p body must outlive the solve.
fmNewtonTerm fmLoads_Term(const fmBody* body);

// The frozen load's work f . d over the free axes, @p d a displacement times @p scale.
double fmLoads_Work(const fmBody* body, const double* d, double scale);

// |frozen load| over the free axes (N), for the solvers' force scales.
double fmLoads_FrozenNorm(const fmBody* body);

// An upper bound of the body's total load (N): its nodal forces' and fixed pressure's sizes
// summed, and each follower triangle's |p| times its rest area (it may stretch: a bound for the
// scene's sanity check, not a measure).
double fmLoads_Size(const fmBody* body);

// The longest prescribed displacement of the body (m), 0 with none.
double fmLoads_LongestDisplacement(const fmBody* body);

// Dynamics: move the prescribed vertices along their paths by @p dt seconds (before a step).
// Returns the work their motion did (J, for the ledger): the elastic energy it added, and the
// change of the shadow energy's force term measured with @p shadowStep (the explicit substep;
// 0 implicit).
double fmLoads_StepPrescribed(fmBody* body, double dt, double shadowStep);

// Statics: record where each prescribed vertex starts its ramp.
void fmLoads_BeginStatic(fmBody* body);

// Statics: place the prescribed vertices at fraction @p load of their ramp.
void fmLoads_PlaceStatic(fmBody* body, double load);

// Statics: the full displacement was reached; a later dynamic run keeps it.
void fmLoads_FinishStatic(fmBody* body);
