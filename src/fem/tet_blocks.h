// The explicit FEM step's element layout and force pass (tet_blocks.c): a body's tets (in the
// body's Morton order, reorder.h) packed FM_LANES to a batch in float for the batched kernels of
// tet_kernel.c, grouped in blocks. The force pass runs the blocks on the workers, each block
// summing its tets' forces on each of its vertices into a sum of its own; then each vertex adds
// its blocks' sums in block order. Every vertex receives its tets' forces in the same order for
// any number of workers: the same bits on 1 or N workers, with no atomics and no colouring
// (docs/decisions.md, "Blocks, not colours").
#pragma once

#include "core/parallel.h"
#include "fem/elastic_mesh.h"
#include "fem/kernels/tet_kernel.h"
#include "fem/kernels/vertex_kernel.h"

// Tets of a block: 32 batches (about 150 vertices, a few KiB of positions and forces in cache).
#define FM_BLOCK_BATCHES 32

typedef struct fmTetBlocks
{
	int tetCount;
	double restVolume; // of the body (m^3)
	int batchCount;
	fmTetBatch* batches; // in block order
	uint8_t* laneCount;  // tets in each batch (FM_LANES but in a block's last batch)
	int blockCount;
	int* blockStart;     // blockCount + 1 batch offsets
	double* blockEnergy; // blockCount: each block's energy in the last pass that asked for it
	int* blockInverted;  // blockCount: its inverted tets in that pass
	// The vertices of block k are blockVertices[blockVertexStart[k] .. blockVertexStart[k + 1]),
	// in the order its tets first use them; its batches number them from 0. A block gathers
	// their displacements once, runs its batches into a buffer of fmTetBatchForces, and then
	// each vertex sums its entries there (no read-modify-write chains through memory) into
	// blockSums: entry j of the block's vertex list has the buffer offsets (floats, where an
	// (x, y, z, 0) entry starts) incidences[incidenceStart[j] .. incidenceStart[j + 1]).
	int* blockVertexStart; // blockCount + 1
	int* blockVertices;    // 4 per tet at most
	int entryCount;        // entries of blockVertices used
	int* incidenceStart;   // one per entry of blockVertices, and one more
	uint16_t* incidences;  // 4 per tet
	double* blockSums;     // 3 per entry (and one more): the entry's block's force on its vertex
	// Vertex i's entries of blockVertices, in block order: vertexEntries[vertexEntryStart[i] ..
	// vertexEntryStart[i + 1]).
	int* vertexEntryStart; // vertexCount + 1
	int* vertexEntries;    // entryCount
	int maxBlockVertices;
	// The seeds' smoothing sums as a weighted vertex graph: sum_i = sum over the tets around i
	// of their 4 velocities = sum_j w_ij v_j, w_ij the tets holding both i and j (w_ii: the tets
	// around i). Vertex i's terms are neighbourOffset / neighbourWeight[neighbourStart[i] ..
	// neighbourStart[i + 1]), in the order its tets first name them: 3 j (where v_j starts in
	// the velocity array) and w_ij.
	int* neighbourStart; // vertexCount + 1
	int neighbourCount;  // neighbourStart[vertexCount]
	int* neighbourOffset;
	double* neighbourWeight;
	int vertexCount;
	int workerCount;
	size_t scratchBytes; // per worker: the block's displacements and its batches' forces
	unsigned char* scratch;
} fmTetBlocks;

// Whether the batched kernels can take the elastic forces of @p body (FEM force model; linear,
// StVK, Neo-Hookean or corotated) at the resolved instruction set @p level (not fm_simdOff).
bool fmTetBlocks_Applies(const fmElasticMesh* mesh, fmSimdLevel level);

// Float carries the entries of F = R (I + strain) to about 1e-7 whatever the strain, so under a
// rotation the batched kernels' stress is off by about 1e-7 (lambda + 2 mu): a relative force
// error of about 1e-7 / strain. Bodies whose typical strain, density * 10 m/s^2 * size /
// (lambda + 2 mu), is below this (very stiff ones) take the double-precision kernel instead.
#define FM_FLOAT_KERNEL_MIN_STRAIN 1e-5

// Whether the typical strain of @p body is large enough for the float kernels (above).
bool fmTetBlocks_Accurate(const fmTetBlocks* blocks, const fmElasticMesh* mesh);

// The body's layout when its explicit steps take their forces from it at @p level (made, the
// kernels apply and are accurate for it), else NULL.
const fmTetBlocks* fmTetBlocks_Used(const fmElasticMesh* mesh, fmSimdLevel level);

// Build the layout of a body (from its rest shape) for force passes on up to @p workerCount
// workers; NULL when memory is short.
fmTetBlocks* fmTetBlocks_Create(const fmElasticMesh* mesh, int workerCount);

void fmTetBlocks_Destroy(fmTetBlocks* blocks);

// Bytes fmTetBlocks_Create takes at most for a mesh of these counts on one worker (the body's
// memory estimate).
uint64_t fmTetBlocks_Bytes(uint64_t tetCount, uint64_t vertexCount);

// The kernels of one instruction set: a batch's forces, and a block's vertices' sums of them.
typedef struct fmTetKernels
{
	fmTetKernelFcn* forces;
	fmTetSumFcn* sums;
	fmTetWeightedSumFcn* weightedSums;   // the smoothing's
	fmTetGatherFcn* gatherSums;          // each vertex's blocks' sums, with m g
	fmTetDisplacementFcn* displacements; // a block's rows of x - X
	fmVertexKernelFcn* velocities;       // the explicit step's vertex updates
	fmVertexKernelFcn* blend;
	fmVertexKernelFcn* positions;
} fmTetKernels;

// The kernel variants of an instruction set fmSimd_Resolve returned (not fm_simdOff).
fmTetKernels fmTetBlocks_Kernels(fmSimdLevel level);

// sums[i] = the sum over the tets around vertex i of their 4 velocities (the seeds' Laplacian
// smoothing, velocity_filter.c), vertex by vertex on the workers, with the kernel of @p level
// (the same bits on every level).
void fmTetBlocks_SmoothingSums(const fmTetBlocks* blocks, const double* v, double* sums,
                               fmSimdLevel level, const fmTaskSystem* tasks);

// f += the elastic forces at positions @p x, with the kernel of @p level, on the workers (at most
// the count the layout was made for); with @p gravity, f = m g + the elastic forces instead (the
// explicit step's gravity, the same bits as setting it first). With @p energy, returns the
// elastic energy (J): each tet's from the kernel (float), summed in double block by block, then
// over the blocks in order (the same bits on any number of workers); else 0. With @p energy, a
// non-NULL @p inverted gets the count of tets with !(det F > 0) at @p x, exactly
// fmInvertedTets's: the kernels' float det F proves most tets upright, and the others are
// rechecked in double. A non-NULL @p then runs on each range of vertices right after their forces
// are complete.
double fmTetBlocks_AddForces(const fmTetBlocks* blocks, const fmElasticMesh* mesh, const double* x,
                             const fmVec3* gravity, double* f, fmSimdLevel level,
                             const fmTaskSystem* tasks, bool energy, int* inverted,
                             const fmThenTask* then);
