// The implicit and static solvers' buffers of one body (solver_cache.c): the block-sparse
// Newton matrix with the slot of every element block, and the vectors of a solve.
#pragma once

#include "core/arena.h"
#include "core/parallel.h"
#include "fem/elastic_mesh.h"
#include "solver/multigrid.h"
#include "solver/pcg.h"

// An evaluation of the elastic forces kept aside: the forces, where, their energy, with what.
typedef struct fmForcesMemo
{
	double* forces; // 3n
	double* x;      // 3n
	double energy;
	fmMaterial material;
	bool valid;
} fmForcesMemo;

// Solver buffers of one body (body->implicitCache), allocated on first use.
typedef struct fmImplicitCache
{
	int vertexCount;
	int tetCount;
	int edgeCount;
	double volume;         // rest volume of the body (m^3)
	fmBsrMatrix pattern;   // vertex pairs sharing a tet
	int* tetSlot;          // 16 per tet: slot of block (a, b) of its nodes
	int* edgeSlot;         // 4 per edge (mass-spring): slots (a,a), (a,b), (b,a), (b,b)
	double* hessian;       // 9 per block: the Newton matrix
	double* damping;       // 9 per block: lagged damping matrix D (allocated when needed)
	double* hessianBase;   // 9 per block: the Newton matrix without its contact terms, as last
	                       // assembled in full (allocated when a solve has them)
	double* blockInverse;  // 9 per vertex: preconditioner
	fmMultigrid multigrid; // the multigrid preconditioner's levels, built on first use
	bool multigridBuilt;   // multigrid holds the levels of pattern
	double* xPred;         // 3n: inertial target
	double* xStart;        // 3n: positions at the start of the step
	double* gradient;      // 3n
	double* direction;     // 3n
	double* trial;         // 3n
	double* forces;        // 3n
	double* temp;          // 3n
	double* work;          // 4 * 3n: CG vectors
	uint8_t* fixed;        // 3n: DOF held by a pin or the floor
	double* floorBound;    // n: lowest y each vertex may take this step (the floor, or less
	                       // while a deep vertex is lifted at the depenetration speed)
	double* best;          // 3n: the state of smallest residual (fmNewtonProblem.keepBest)
	// The elastic forces in `forces` and their energy are those at forcesX, with forcesMaterial
	// (a FEM body with a built-in model): the step's force scale and the world's energy check
	// at the end of a step reuse the solver's last evaluation instead of repeating it (the
	// same bits: a pure function of x). Never saved: it is recomputed when it does not match.
	double* forcesX;     // 3n
	double forcesEnergy; // J
	fmMaterial forcesMaterial;
	bool forcesValid;
	fmForcesMemo spare; // a second evaluation kept aside (fmSolverCache_SwapForces)
	bool coasted; // the last implicit step started from x + h v: the guess tried first (saved in
	              // snapshots: the next step's result depends on it)
	int guessRecheck; // steps before the other first guess is tried again (saved too)
	// The Newton matrix is kept between iterations and steps and refreshed when it stops
	// paying (see fmNewton_Solve); these say what it was built with.
	bool hessianValid;
	unsigned hessianVersion; // counts the changes of `hessian` (the multigrid's setup follows)
	double hessianInertia;
	double hessianMassDamping;
	bool hessianDamping;
	bool hessianExact;
	bool hessianBaseValid; // hessianBase is the base of the kept matrix (saved in snapshots)
} fmImplicitCache;

// The cache in @p slot (a body's fmBody.solverCache) for @p mesh, allocated on first use; NULL
// when memory is short.
fmImplicitCache* fmSolverCache_Get(fmImplicitCache** slot, const fmElasticMesh* mesh);

// The multigrid levels over the cache's pattern, built on first use; NULL when memory is short.
fmMultigrid* fmSolverCache_Multigrid(fmImplicitCache* cache);

// The cache's hessianBase, allocated on first use; NULL when memory is short.
double* fmSolverCache_Base(fmImplicitCache* cache);

// Release a cache (body->implicitCache); NULL is fine.
void fmSolverCache_Free(void* cache);

// The cache's forces and energy are the elastic ones of @p body at @p x (see forcesX).
bool fmSolverCache_HasForcesAt(const fmElasticMesh* mesh, const fmImplicitCache* cache,
                               const double* x);

// Note that cache->forces now holds the elastic forces at @p x, with energy @p psi.
void fmSolverCache_NoteForces(const fmElasticMesh* mesh, fmImplicitCache* cache, const double* x,
                              double psi);

// Exchange the cache's last forces evaluation with the spare one (to try another point and come
// back without evaluating again).
void fmSolverCache_SwapForces(fmImplicitCache* cache);

// The body's rest data moved (plastic flow): its kept forces and Newton matrix are stale.
void fmSolverCache_RestMoved(fmImplicitCache* cache);

// Make cache->forces the elastic forces at @p x (computed unless they are already), on the
// workers of @p tasks (NULL: serially) with temporaries from @p arena.
void fmSolverCache_ForcesAtPositions(const fmElasticMesh* mesh, fmImplicitCache* cache,
                                     const double* x, const fmTaskSystem* tasks, fmArena* arena);

// values += scale * (PSD-projected if @p project) elastic Hessian at x, element by element in a
// fixed order, into the cache's block pattern; on the workers of @p tasks (NULL: serial), the
// same bits for any number of them.
void fmSolverCache_AddStiffness(const fmElasticMesh* mesh, const fmImplicitCache* cache,
                                const double* x, double scale, int project, double* values,
                                const fmTaskSystem* tasks);

// values += scale * the springs' dashpot matrices at x (mass-spring bodies).
void fmSolverCache_AddSpringDamping(const fmElasticMesh* mesh, const double* invMass,
                                    const fmImplicitCache* cache, const double* x, double scale,
                                    double* values);

// The elastic energy at @p x: the cache's last evaluation when it was at @p x (the world's energy
// check after an implicit step; the same bits), else fmElasticEnergyOn. @p cache may be NULL.
double fmSolverCache_Energy(const fmElasticMesh* mesh, const fmImplicitCache* cache,
                            const double* x, const fmTaskSystem* tasks, fmArena* arena);
