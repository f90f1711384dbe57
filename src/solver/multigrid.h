// An aggregation multigrid preconditioner for the Newton systems (multigrid.c): a hierarchy of
// ever coarser block matrices, built once from the vertex graph of a body's Newton matrix, and
// a symmetric W-cycle (block Gauss-Seidel smoothing, a dense Cholesky solve at the bottom)
// whose cost per CG iteration stays a few matrix products while the iterations it needs stay
// about constant under mesh refinement, where a one-level preconditioner's grow with the
// mesh's diameter (docs/implicit.md measures both).
#pragma once

#include "core/parallel.h"
#include "solver/bsr.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

// Most levels of a hierarchy (each about 15 times smaller than the one above it).
#define FM_MG_MAX_LEVELS 12

// Coarsening stops at this many block rows; the bottom level is solved exactly.
#define FM_MG_COARSE_ROWS 64

// Vertices from which the multigrid cycle pays for its cost (about twice a symmetric
// Gauss-Seidel sweep's) in the CG iterations it saves (the crossover measured in
// docs/implicit.md).
#define FM_MG_MIN_ROWS 4096

// One level: its matrix A_l, and the aggregates that map it to the next level.
typedef struct fmMgLevel
{
	fmBsrMatrix pattern;  // level 0: a shallow copy of the fine pattern (not owned)
	const double* values; // 9 per block (level 0: the caller's matrix, set by Setup)
	double* coarseValues; // levels > 0: the storage of values
	double* blockInverse; // 9 per row: inverted diagonal blocks, fixed DOFs cut out
	uint8_t* fixed;       // 3 per row: DOFs held (level 0: the caller's, set by Setup)
	uint8_t* ownFixed;    // levels > 0: the storage of fixed
	int* aggregate;       // rows: the row of the next level this row belongs to
	int* coarseSlot;      // blocks: the block of the next level this block adds into
	double* r;            // 3 per row: right-hand side (levels > 0)
	double* z;            // 3 per row: solution (levels > 0)
	double* t;            // 3 per row: residual scratch
	double* q;            // 3 per row: the second visit's residual (levels > 0)
	double* w;            // 3 per row: the second visit's correction (levels > 0)
} fmMgLevel;

// A multigrid hierarchy (one per body's implicit cache).
typedef struct fmMultigrid
{
	int levelCount;
	fmMgLevel level[FM_MG_MAX_LEVELS];
	int denseRows; // block rows of the bottom level (dense when <= 2 FM_MG_COARSE_ROWS)
	double* dense; // (3 denseRows)^2: the bottom matrix's Cholesky factor
	bool denseOk;  // the factor exists (else the bottom level gets a Gauss-Seidel sweep)
	bool ready;    // Setup has run since the last Build
	// What the levels were set up from: the caller's version of the fine values and a copy of
	// the fine fixed flags (3 per row), so that a Setup with both unchanged costs nothing.
	unsigned setupVersion;
	uint8_t* setupFixed;
	const struct fmTaskSystem* tasks; // the workers of the sweeps and products (NULL: serial)
} fmMultigrid;

// Build the levels' aggregates and patterns from the fine pattern (kept by reference: it must
// outlive the hierarchy). Returns false when memory is short (the hierarchy is left freed).
bool fmMultigrid_Build(fmMultigrid* mg, const fmBsrMatrix* fine);

// Release a hierarchy. Safe on a zeroed one.
void fmMultigrid_Free(fmMultigrid* mg);

// Bytes a hierarchy over @p rows block rows and @p blocks blocks takes at most (the memory
// budget's estimate).
size_t fmMultigrid_EstimateBytes(size_t rows, size_t blocks);

// Fill the coarse matrices from the fine one (values: 9 per block, blockInverse: its inverted
// diagonal blocks as fmBsr_InvertDiagonalBlocks makes them, fixed: 3 per row) by Galerkin
// projection over the free DOFs, invert their diagonal blocks and factor the bottom one. The
// fine arrays are kept by reference until the next Setup. @p valuesVersion is the caller's
// count of changes to @p values: a Setup with the same array, version and fixed flags as the
// last one keeps the levels as they are (a Newton iteration that reuses its matrix with the same
// active set; the levels are a pure function of those, so the bits are the same).
void fmMultigrid_Setup(fmMultigrid* mg, const double* values, const double* blockInverse,
                       const uint8_t* fixed, unsigned valuesVersion,
                       const struct fmTaskSystem* tasks);

// z = B r, one symmetric W-cycle (forward sweeps down, backward sweeps up, each coarse level
// visited twice, the coarse corrections over-corrected by 1.5): B is symmetric,
// and positive definite for a positive definite matrix. Fixed DOFs of z are 0. The same bits
// for any number of workers.
void fmMultigrid_Apply(const fmMultigrid* mg, const double* r, double* z);
