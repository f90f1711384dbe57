// The preconditioned conjugate gradient for the implicit and static solvers (docs/implicit.md)
// over the block sparse matrices of bsr.h, and its preconditioners.
#pragma once

#include "solver/bsr.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

// Preconditioner choice for fmPcg_Solve.
typedef enum fmPreconditioner
{
	fm_precondJacobi,               // inverse of the diagonal entries
	fm_precondBlockJacobi,          // inverse of the 3x3 diagonal blocks
	fm_precondSymmetricGaussSeidel, // one forward and one backward block Gauss-Seidel sweep
	fm_precondMultigrid,            // an aggregation multigrid V-cycle (multigrid.h)
	fm_precondAuto, // symmetric Gauss-Seidel below FM_MG_MIN_ROWS vertices, multigrid from there
} fmPreconditioner;

// The preconditioner of a CG solve: blockInverse (9 doubles per vertex, already inverted and
// restricted to the free DOFs); for symmetric Gauss-Seidel and multigrid also the matrix.
typedef struct fmPcgPreconditioner
{
	fmPreconditioner kind;
	const double* blockInverse;
	const fmBsrMatrix* matrix;           // fm_precondSymmetricGaussSeidel only
	const double* values;                // its values (9 per block)
	const struct fmTaskSystem* tasks;    // workers for its parts (NULL: serial)
	const struct fmMultigrid* multigrid; // fm_precondMultigrid only: set up for this matrix
} fmPcgPreconditioner;

// y = A x for the CG (the operator must be symmetric positive semi-definite on the free DOFs).
typedef void fmLinearOperator(void* context, const double* x, double* y);

// Scratch for the CG: four vectors of n doubles, given by the caller (no allocation).
typedef struct fmPcgWork
{
	double* r;
	double* z;
	double* p;
	double* q;
} fmPcgWork;

// Result of a CG solve.
typedef struct fmPcgResult
{
	int iterations;
	double residual; // |b - A x| reached (2-norm over free DOFs)
	bool converged;  // residual <= the requested tolerance
	bool indefinite; // stopped at a direction of non-positive curvature
} fmPcgResult;

// Solve A x = b over the DOFs with fixed[k] == 0 (x and every vector stay 0 on fixed DOFs),
// starting from x = 0, until |b - A x| <= tolerance or maxIterations.
// Stops early at a direction of non-positive curvature (returns what it has). Deterministic:
// every reduction is summed in index order.
fmPcgResult fmPcg_Solve(int n, fmLinearOperator* op, void* context,
                        const fmPcgPreconditioner* preconditioner, const uint8_t* fixed,
                        const double* b, double* x, double tolerance, int maxIterations,
                        const fmPcgWork* work);

// Invert the 3x3 diagonal blocks @p diagBlocks (9 per vertex) into @p blockInverse for the
// preconditioner @p kind (fmBsr_InvertDiagonalBlocks; fm_precondJacobi keeps the diagonal
// entries only).
void fmPcg_BuildPreconditioner(int vertexCount, const double* diagBlocks, const uint8_t* fixed,
                               fmPreconditioner kind, double* blockInverse);
