// The Newton minimiser shared by the implicit step and the static solver (newton.c):
// minimise E(x) = inertia/2 |x - xPred|_M^2 + massDamping/2 |x - xStart|_M^2
//               + 1/2 (x - xStart)^T D (x - xStart) + Psi(x) - M g . (x - xStart)
// over the free DOFs, optionally with lower bounds on y (the floor) as bound constraints.
#pragma once

#include "core/arena.h"
#include "fem/elastic_mesh.h"
#include "core/parallel.h"
#include "solver/pcg.h"
#include "solver/solver_cache.h"

// How Hessian-vector products are formed (measured in docs/implicit.md).
typedef enum fmProductMode
{
	fm_productAssembled, // block CSR matrix refilled each Newton iteration (default)
	fm_productMatrixFree // fmAddHessianProduct per CG iteration
} fmProductMode;

// Solver knobs for measurements (tests and benchmarks): a world's (fmWorld.solverOptions).
typedef struct fmSolverOptions
{
	fmProductMode product;
	fmPreconditioner preconditioner;
} fmSolverOptions;

// The measured defaults: an assembled matrix and symmetric Gauss-Seidel (docs/implicit.md).
fmSolverOptions fmDefaultSolverOptions(void);

// One minimisation problem.
// An energy term of the step's potential that the solver knows only through these functions:
// the body's loads and targets (body/), the contact penalty (contact/), made by the layers above
// and handed down in the problem. A term whose energy is NULL is absent.
typedef struct fmNewtonTerm
{
	const void* context;
	// The term's energy at @p x (J), its gradient added to @p gradient when not NULL; @p xStart
	// is the step's start.
	double (*energy)(const void* context, const double* x, const double* xStart, double* gradient);
	// Its Hessian at @p x added to @p values: to the blocks of @p pattern, or with @p pattern NULL
	// to 9 doubles a vertex, the diagonal blocks alone. NULL: no Hessian (a frozen force).
	void (*addHessian)(const void* context, const double* x, const fmBsrMatrix* pattern,
	                   double* values);
	// Its Hessian at @p x times @p dx, added to @p y. NULL: none.
	void (*addProduct)(const void* context, const double* x, const double* dx, double* y);
	// The largest t in [0, 1] such that the path x + s dx, s in [0, t], is admissible (a barrier's
	// collision-free steps); 1 or more: the whole step. NULL: no bound.
	double (*stepBound)(const void* context, const double* x, const double* dx);
} fmNewtonTerm;

typedef struct fmNewtonProblem
{
	double inertia;          // 1/h^2, 0 for statics
	double massDamping;      // alpha / h
	bool useDamping;         // the cache's damping matrix D (already divided by h) takes part
	fmVec3 gravity;          // m/s^2 (times the load factor in statics)
	const fmFloorDef* floor; // NULL: no floor; else cache->floorBound holds the bounds on y
	double tolerance;        // stop at |gradient over free DOFs| <= tolerance * scale
	double scale;            // force scale (N)
	int maxNewton;
	int maxCg;
	bool quadratic;    // Psi is quadratic (linear material): solve each Newton system tightly
	bool exactHessian; // unprojected element Hessians (statics); stop if CG finds them indefinite
	bool keepBest;     // end at the iterate of smallest residual, not the last (statics)
	bool inversionFree; // no iterate flattens or inverts a tet positive at the start (inversion.h)
	fmSolverOptions options;   // how products are formed and preconditioned
	const fmTaskSystem* tasks; // the world's workers for the matrix products (NULL: serial)
	fmArena* arena;            // the world's step arena (buffers of the parallel force passes)
	fmNewtonTerm loads;   // the frozen loads' potential -f . (x - xStart)
	fmNewtonTerm targets; // the kinematic targets' springs
	fmNewtonTerm contact; // the contact penalty and friction (colliders)
	fmNewtonTerm barrier; // the barrier contact between bodies and its friction; its step bound
	                      // limits every line-search step
} fmNewtonProblem;

typedef struct fmNewtonResult
{
	int iterations;
	int cgIterations;
	double residual; // |gradient over free DOFs| / scale at the end
	bool converged;
	bool finite;    // false: the energy or gradient went non-finite
	bool projected; // exactHessian was requested but the Hessian turned out indefinite
	bool stagnated; // stopped: FM_NEWTON_STAGNATION steps within the energy's round-off that
	                // did not improve the residual by 10%
	bool stalled;   // stopped: the line search found no step that lowers the energy
} fmNewtonResult;

// Newton steps within the energy's round-off and without a 10% better residual after which a
// solve has stagnated at round-off: it stops and says so instead of spinning.
#define FM_NEWTON_STAGNATION 8

// The relative residual the solve would see at @p x (its stopping rule: the gradient over the
// free DOFs and the floor's active set, divided by the problem's scale); NaN if not finite.
double fmNewton_Residual(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* cache, const fmNewtonProblem* problem,
                         const double* x);

// Whether a term of @p problem bounds the line search's steps (fmNewtonTerm.stepBound: the
// barrier between bodies, the colliders' barrier).
bool fmNewton_Bounded(const fmNewtonProblem* problem);

// The largest t in [0, 1] the terms' step bounds allow along x + t dx (1 with none).
double fmNewton_StepBound(const fmNewtonProblem* problem, const double* x, const double* dx);

// Minimise from body->x (overwritten with the result). xPred and xStart in the cache must be
// set by the caller; xStart is also where pinned vertices stay.
fmNewtonResult fmNewton_Solve(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* cache,
                              const fmNewtonProblem* problem);
