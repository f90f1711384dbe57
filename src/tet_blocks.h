// The explicit FEM step's element layout and force pass (tet_blocks.c): a body's tets sorted
// along a space-filling curve, packed FM_LANES to a batch in float for the batched kernels of
// tet_kernel.c, grouped in blocks, and the blocks coloured so that blocks of one colour share no
// vertex. The force pass runs colour by colour; within a colour the workers take blocks, and
// every vertex receives its tets' forces in the same order for any number of workers: the same
// bits on 1 or N workers, with no per-tet force buffer and no atomics.
#pragma once

#include "body.h"
#include "parallel.h"
#include "tet_kernel.h"

// Tets of a block: 32 batches (about 150 vertices, a few KiB of positions and forces in cache).
#define FM_BLOCK_BATCHES 32

typedef struct fmTetBlocks
{
	int tetCount;
	int batchCount;
	fmTetBatch* batches; // in colour order, then block order
	uint8_t* laneCount;  // tets in each batch (FM_LANES but in a block's last batch)
	int blockCount;
	int* blockStart; // blockCount + 1 batch offsets
	int colourCount;
	int* colourStart; // colourCount + 1 block offsets
} fmTetBlocks;

// Whether the batched kernels can take the elastic forces of @p body (FEM force model, a
// material with a kernel) at the resolved instruction set @p level (not fm_simdOff).
bool fmTetBlocks_Applies(const fmBody* body, fmSimdLevel level);

// Build the layout of a body (from its rest shape); NULL when memory is short.
fmTetBlocks* fmTetBlocks_Create(const fmBody* body);

void fmTetBlocks_Destroy(fmTetBlocks* blocks);

// Bytes fmTetBlocks_Create takes for @p tetCount tets (the body's memory estimate).
uint64_t fmTetBlocks_Bytes(uint64_t tetCount);

// The kernel variant of an instruction set fmSimd_Resolve returned (not fm_simdOff).
fmTetKernelFcn* fmTetBlocks_Kernel(fmSimdLevel level);

// f += the elastic forces at positions @p x, with the kernel of @p level, on the workers.
void fmTetBlocks_AddForces(const fmTetBlocks* blocks, const fmBody* body, const double* x,
                           double* f, fmSimdLevel level, const fmTaskSystem* tasks);
