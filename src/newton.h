// The Newton minimiser shared by the implicit step and the static solver (implicit.c):
// minimise E(x) = inertia/2 |x - xPred|_M^2 + massDamping/2 |x - xStart|_M^2
//               + 1/2 (x - xStart)^T D (x - xStart) + Psi(x) - M g . (x - xStart)
// over the free DOFs, optionally with the floor y >= height as bound constraints.
#pragma once

#include "body.h"
#include "pcg.h"

// Solver buffers of one body (body->implicitCache), allocated on first use.
typedef struct fmImplicitCache
{
	int vertexCount;
	int tetCount;
	int edgeCount;
	double volume;        // rest volume of the body (m^3)
	fmBsrMatrix pattern;  // vertex pairs sharing a tet
	int* tetSlot;         // 16 per tet: slot of block (a, b) of its nodes
	int* edgeSlot;        // 4 per edge (mass-spring): slots (a,a), (a,b), (b,a), (b,b)
	double* hessian;      // 9 per block: the Newton matrix
	double* damping;      // 9 per block: lagged damping matrix D (allocated when needed)
	double* blockInverse; // 9 per vertex: preconditioner
	double* xPred;        // 3n: inertial target
	double* xStart;       // 3n: positions at the start of the step
	double* gradient;     // 3n
	double* direction;    // 3n
	double* trial;        // 3n
	double* forces;       // 3n
	double* temp;         // 3n
	double* work;         // 4 * 3n: CG vectors
	uint8_t* fixed;       // 3n: DOF held by a pin or the floor
	double* floorBound;   // n: lowest y each vertex may take this step (the floor, or less
	                      // while a deep vertex is lifted at the depenetration speed)
	double* best;         // 3n: the state of smallest residual (fmNewtonProblem.keepBest)
	// The Newton matrix is kept between iterations and steps and refreshed when it stops
	// paying (see fmNewton_Solve); these say what it was built with.
	bool hessianValid;
	double hessianInertia;
	double hessianMassDamping;
	bool hessianDamping;
	bool hessianExact;
} fmImplicitCache;

// How Hessian-vector products are formed (measured in docs/implicit.md).
typedef enum fmProductMode
{
	fm_productAssembled, // block CSR matrix refilled each Newton iteration (default)
	fm_productMatrixFree // fmAddHessianProduct per CG iteration
} fmProductMode;

// Solver knobs for measurements (tests and benchmarks); process-wide, not thread-safe.
typedef struct fmImplicitOptions
{
	fmProductMode product;
	fmPreconditioner preconditioner;
} fmImplicitOptions;

fmImplicitOptions fmImplicit_GetOptions(void);
void fmImplicit_SetOptions(fmImplicitOptions options);

// One minimisation problem.
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

// The cache of @p body, allocated if needed; NULL when memory is short.
fmImplicitCache* fmImplicit_GetCache(fmBody* body);

// Minimise from body->x (overwritten with the result). xPred and xStart in the cache must be
// set by the caller; xStart is also where pinned vertices stay.
fmNewtonResult fmNewton_Solve(fmBody* body, fmImplicitCache* cache, const fmNewtonProblem* problem);
