// Sparse symmetric block matrices (3x3 blocks, one block row per vertex): the pattern built from
// a tet mesh, the product, the block Gauss-Seidel sweeps and the inverted diagonal blocks that the
// conjugate gradient (pcg.h) and the multigrid hierarchy (multigrid.h) are made of.
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

// Insertion sort of a short list (a row's columns) with duplicates removed; returns the new
// length.
int fmSortUnique(int* list, int count);

// Build the pattern of every vertex pair that shares a tet (4 ints per tet). Returns false when
// memory is short (the matrix is left freed).
bool fmBsr_Build(fmBsrMatrix* matrix, int vertexCount, const int* tets, int tetCount);

// Replace the pattern by its square's: vertex pairs within two tets of each other (a vertex
// patch's pairs, the nodal pressure's, fem/nodal_pressure.h). False without memory (the pattern
// unchanged).
bool fmBsr_Square(fmBsrMatrix* matrix);

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

// Invert the 3x3 diagonal blocks @p diagBlocks (9 per row) into @p blockInverse, with fixed DOFs
// (3 per row) replaced by identity rows and columns; with @p diagonalOnly the off-diagonal
// entries are dropped first (the inverse of the diagonal entries). A block that is not positive
// definite falls back to its (positive part of the) diagonal.
void fmBsr_InvertDiagonalBlocks(int rows, const double* diagBlocks, const uint8_t* fixed,
                                bool diagonalOnly, double* blockInverse);
