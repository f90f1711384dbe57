// Sparse symmetric block matrices (3x3 blocks, one block row per vertex) and a preconditioned
// conjugate gradient for the implicit and static solvers (docs/implicit.md).
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

// Block compressed sparse rows: the sparsity pattern of a tet mesh's stiffness matrix, built
// once from the connectivity; the values are refilled every Newton iteration.
typedef struct fmBsrMatrix
{
	int rows;      // block rows = vertices
	int blocks;    // stored 3x3 blocks
	int* rowStart; // rows + 1: blocks of row i are rowStart[i] .. rowStart[i + 1] - 1
	int* columns;  // blocks: block column, sorted ascending within a row
	int* diagonal; // rows: the slot of block (i, i)
} fmBsrMatrix;

// Build the pattern of every vertex pair that shares a tet (4 ints per tet). Returns false when
// memory is short (the matrix is left freed).
bool fmBsr_Build(fmBsrMatrix* matrix, int vertexCount, const int* tets, int tetCount);

// Release the pattern. Safe on a zeroed matrix.
void fmBsr_Free(fmBsrMatrix* matrix);

// Slot of block (row, column), or -1 if the pattern does not hold it.
int fmBsr_Find(const fmBsrMatrix* matrix, int row, int column);

// y = A x with A's values (9 per block, row-major); rows summed in a fixed order.
void fmBsr_Multiply(const fmBsrMatrix* matrix, const double* values, const double* x, double* y);

// The same for block rows [first, end) only (rows are independent: a parallel product).
void fmBsr_MultiplyRows(const fmBsrMatrix* matrix, const double* values, const double* x, double* y,
                        int first, int end);

// Rows of a part of the Gauss-Seidel sweeps: parts run on separate workers and ignore each
// other (fewer parts: a stronger preconditioner; more: more parallel). The parts depend on the
// matrix size only, so any number of workers gives the same bits.
#define FM_SGS_PART_ROWS 4096

// Block Gauss-Seidel on the rows [first, end) of A (values, blockInverse: the inverted diagonal
// blocks, fixed DOFs cut out), coupled to no other row. The forward sweep solves the lower
// triangle from z = 0: z_i = D_i^-1 (r_i - sum_{first<=j<i} A_ij z_j); the backward sweep
// updates z by the upper triangle: z_i -= D_i^-1 sum_{i<j<end} A_ij z_j. Together: one
// symmetric Gauss-Seidel application z = (D + U)^-1 D (D + L)^-1 r. Fixed DOFs of z stay 0.
void fmBsr_ForwardSweep(const fmBsrMatrix* matrix, const double* values, const double* blockInverse,
                        const uint8_t* fixed, const double* r, double* z, int first, int end);
void fmBsr_BackwardSweep(const fmBsrMatrix* matrix, const double* values,
                         const double* blockInverse, const uint8_t* fixed, double* z, int first,
                         int end);

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
// preconditioner @p kind, with fixed DOFs replaced by identity rows and columns. A block that
// is not positive definite falls back to its (positive part of the) diagonal.
void fmPcg_BuildPreconditioner(int vertexCount, const double* diagBlocks, const uint8_t* fixed,
                               fmPreconditioner kind, double* blockInverse);
