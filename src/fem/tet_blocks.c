// The explicit FEM step's element layout and force pass (tet_blocks.h).
#include "fem/tet_blocks.h"

#include "core/core.h"
#include "fem/forces.h"
#include "material/material.h"

#include <string.h>

// Floats of one batch's output in a block's buffer (a multiple of FM_LANES).
#define FM_BATCH_FLOATS ((int)(sizeof(fmTetBatchForces) / sizeof(float)))

bool fmTetBlocks_Applies(const fmElasticMesh* mesh, fmSimdLevel level)
{
	fmMaterialModel m = mesh->material.model;
	// (A plastic body's Dm^-1 is not its rest positions' inverse: the kernels' F = I + Du Dm^-1,
	// exact at small strain, needs it to be.)
	return level != fm_simdOff && mesh->forceModel == fm_fem && mesh->tetMaterial == NULL &&
	       mesh->plasticStrain == NULL && mesh->tetParts == NULL &&
	       (m == fm_linear || m == fm_stvk || m == fm_neoHookean || m == fm_mooneyRivlin ||
	        m == fm_neoHookeanIsochoric || m == fm_corotated);
}

bool fmTetBlocks_Accurate(const fmTetBlocks* tb, const fmElasticMesh* mesh)
{
	double density = mesh->totalMass / tb->restVolume;
	double modulus = mesh->material.lambda + 2.0 * mesh->material.mu;
	return density * 10.0 * mesh->restSize >= FM_FLOAT_KERNEL_MIN_STRAIN * modulus;
}

const fmTetBlocks* fmTetBlocks_Used(const fmElasticMesh* mesh, fmSimdLevel level)
{
	const fmTetBlocks* tb = mesh->tetBlocks;
	return tb != NULL && fmTetBlocks_Applies(mesh, level) && fmTetBlocks_Accurate(tb, mesh) ? tb
	                                                                                        : NULL;
}

fmTetKernels fmTetBlocks_Kernels(fmSimdLevel level)
{
	switch (level)
	{
#if defined(__x86_64__) || defined(_M_X64)
	case fm_simdAvx512:
		return (fmTetKernels){fmTetKernel_Forces_avx512,           fmTetKernel_SumForces_avx512,
		                      fmTetKernel_WeightedSums_avx512,     fmVertexKernel_GatherSums_avx512,
		                      fmVertexKernel_Displacements_avx512, fmVertexKernel_Velocities_avx512,
		                      fmVertexKernel_Blend_avx512,         fmVertexKernel_Positions_avx512};
	case fm_simdAvx2:
		return (fmTetKernels){fmTetKernel_Forces_avx2,           fmTetKernel_SumForces_avx2,
		                      fmTetKernel_WeightedSums_avx2,     fmVertexKernel_GatherSums_avx2,
		                      fmVertexKernel_Displacements_avx2, fmVertexKernel_Velocities_avx2,
		                      fmVertexKernel_Blend_avx2,         fmVertexKernel_Positions_avx2};
#endif
	case fm_simdScalar:
		return (fmTetKernels){fmTetKernel_Forces_scalar,           fmTetKernel_SumForces_scalar,
		                      fmTetKernel_WeightedSums_scalar,     fmVertexKernel_GatherSums_scalar,
		                      fmVertexKernel_Displacements_scalar, fmVertexKernel_Velocities_scalar,
		                      fmVertexKernel_Blend_scalar,         fmVertexKernel_Positions_scalar};
	default:
		return (fmTetKernels){
		    fmTetKernel_Forces_baseline,           fmTetKernel_SumForces_baseline,
		    fmTetKernel_WeightedSums_baseline,     fmVertexKernel_GatherSums_baseline,
		    fmVertexKernel_Displacements_baseline, fmVertexKernel_Velocities_baseline,
		    fmVertexKernel_Blend_baseline,         fmVertexKernel_Positions_baseline};
	}
}

// ---- the layout ---------------------------------------------------------------------------------

// A block's own numbering of the vertices: local[v] is vertex v's number in the block being
// packed, or -1; verts lists them in the order of first use.
typedef struct fmBlockVertices
{
	int* local; // vertexCount, -1 outside the block being packed
	int* verts; // the block's vertices (at most 4 FM_BLOCK_BATCHES FM_LANES)
	int count;
	int* cursor; // 4 FM_BLOCK_BATCHES FM_LANES: counts, then fill positions of incidences
} fmBlockVertices;

// A block has at most 4 vertices a tet: their rows (4 doubles each) fit fmTetBatch.row.
_Static_assert(4 * 4 * FM_BLOCK_BATCHES * FM_LANES <= 65536, "a block's rows must fit uint16_t");

// Where vertex @p v's row starts in the block being packed (4 times its number there).
static uint16_t fmLocalRow(fmBlockVertices* bv, int v)
{
	if (bv->local[v] < 0)
	{
		bv->local[v] = bv->count;
		bv->verts[bv->count++] = v;
	}
	return (uint16_t)(4 * bv->local[v]);
}

// Pack tets [first, end) into one batch; unused lanes repeat the first tet, weightless.
static void fmPackBatch(const fmElasticMesh* mesh, int first, int end, fmBlockVertices* bv,
                        fmTetBatch* batch)
{
	for (int l = 0; l < FM_LANES; ++l)
	{
		int t = first + l < end ? first + l : first;
		for (int a = 0; a < 4; ++a)
			batch->row[a][l] = fmLocalRow(bv, mesh->tets[4 * t + a]);
		for (int k = 0; k < 9; ++k)
			batch->dmInv[k][l] = (float)mesh->DmInv[t].m[k];
		batch->volume[l] = first + l < end ? (float)mesh->restVolume[t] : 0.0f;
	}
}

// A worker's scratch for blocks of up to @p vertices vertices: their displacements, 4 doubles
// each (the kernel loads a vertex's as one vector), then the forces of a block's batches (64-byte
// aligned).
static size_t fmScratchBytes(int vertices)
{
	size_t u = (4 * (size_t)vertices * sizeof(double) + 63) / 64 * 64;
	return u + FM_BLOCK_BATCHES * sizeof(fmTetBatchForces);
}

uint64_t fmTetBlocks_Bytes(uint64_t tetCount, uint64_t vertexCount)
{
	const uint64_t blockVertices = 4 * FM_BLOCK_BATCHES * FM_LANES;
	uint64_t batches = (tetCount + FM_LANES - 1) / FM_LANES;
	uint64_t blocks = (batches + FM_BLOCK_BATCHES - 1) / FM_BLOCK_BATCHES;
	// Batches, their lane counts, block offsets (two arrays), the blocks' vertex lists (about a
	// third of 4 per tet on a tet mesh; 4 per tet is the most) with their sums (3 doubles each)
	// and each vertex's entries in them (a start per vertex), one worker's scratch, one energy
	// per block. Incidences: 4 per tet, with a start per vertex list entry; the smoothing's
	// vertex graph: at most 16 entries per tet (about 3 on a tet mesh), an int and a double
	// each, and a start per vertex.
	return batches * (sizeof(fmTetBatch) + 1) + 2 * (blocks + 1) * sizeof(int) +
	       (blocks + 1) * sizeof(double) + 12 * tetCount * (sizeof(int) + sizeof(double)) +
	       4 * tetCount * sizeof(uint16_t) + 16 * tetCount * (sizeof(int) + sizeof(double)) +
	       2 * (vertexCount + 1) * sizeof(int) +
	       fmScratchBytes((int)(vertexCount < blockVertices ? vertexCount : blockVertices)) +
	       sizeof(fmTetBlocks);
}

void fmTetBlocks_Destroy(fmTetBlocks* tb)
{
	if (tb == NULL)
		return;
	FM_FREE_ARRAY(tb->batches, fmTetBatch, tb->batchCount);
	FM_FREE_ARRAY(tb->laneCount, uint8_t, tb->batchCount);
	FM_FREE_ARRAY(tb->blockStart, int, tb->blockCount + 1);
	FM_FREE_ARRAY(tb->blockEnergy, double, tb->blockCount);
	FM_FREE_ARRAY(tb->blockInverted, int, tb->blockCount);
	FM_FREE_ARRAY(tb->blockVertexStart, int, tb->blockCount + 1);
	FM_FREE_ARRAY(tb->blockVertices, int, 4 * (size_t)tb->tetCount);
	FM_FREE_ARRAY(tb->blockSums, double, 3 * (size_t)tb->entryCount + 1);
	FM_FREE_ARRAY(tb->vertexEntryStart, int, (size_t)tb->vertexCount + 1);
	FM_FREE_ARRAY(tb->vertexEntries, int, (size_t)tb->entryCount);
	FM_FREE_ARRAY(tb->incidenceStart, int, 4 * (size_t)tb->tetCount + 1);
	FM_FREE_ARRAY(tb->incidences, uint16_t, 4 * (size_t)tb->tetCount);
	FM_FREE_ARRAY(tb->neighbourStart, int, (size_t)tb->vertexCount + 1);
	FM_FREE_ARRAY(tb->neighbourOffset, int, tb->neighbourCount);
	FM_FREE_ARRAY(tb->neighbourWeight, double, tb->neighbourCount);
	FM_FREE_ARRAY(tb->scratch, unsigned char, tb->scratchBytes*(size_t)tb->workerCount);
	FM_FREE_ARRAY(tb, fmTetBlocks, 1);
}

// Pack block @p k (tets k * perBlock ...) at batch @p batch; returns the next batch.
static int fmPackBlock(fmTetBlocks* tb, const fmElasticMesh* mesh, int k, int batch,
                       fmBlockVertices* bv)
{
	const int perBlock = FM_BLOCK_BATCHES * FM_LANES;
	int first = k * perBlock,
	    end = first + perBlock < tb->tetCount ? first + perBlock : tb->tetCount;
	for (int t = first; t < end; t += FM_LANES, ++batch)
	{
		int last = t + FM_LANES < end ? t + FM_LANES : end;
		fmPackBatch(mesh, t, last, bv, &tb->batches[batch]);
		tb->laneCount[batch] = (uint8_t)(last - t);
	}
	return batch;
}

// The incidences of the block whose vertex list starts at entry @p base (@p count vertices) and
// whose batches are [first, end): for each vertex, the buffer offsets (floats) of its force
// entries in batch, lane, node order. @p cursor has room for @p count ints.
static void fmBuildIncidences(fmTetBlocks* tb, int first, int end, int base, int count, int* cursor)
{
	memset(cursor, 0, sizeof(int) * (size_t)count);
	for (int j = first; j < end; ++j)
		for (int l = 0; l < tb->laneCount[j]; ++l)
			for (int a = 0; a < 4; ++a)
				cursor[tb->batches[j].row[a][l] / 4] += 1;
	int at = tb->incidenceStart[base];
	for (int i = 0; i < count; ++i)
	{
		tb->incidenceStart[base + i] = at;
		at += cursor[i];
		cursor[i] = tb->incidenceStart[base + i];
	}
	tb->incidenceStart[base + count] = at;
	for (int j = first; j < end; ++j)
		for (int l = 0; l < tb->laneCount[j]; ++l)
			for (int a = 0; a < 4; ++a)
				tb->incidences[cursor[tb->batches[j].row[a][l] / 4]++] =
				    (uint16_t)((j - first) * FM_BATCH_FLOATS + 4 * (FM_LANES * a + l));
}

// Packs the blocks' batches and vertex lists, in the body's (Morton) order.
static bool fmPackBlocks(fmTetBlocks* tb, const fmElasticMesh* mesh, fmBlockVertices* bv)
{
	int batch = 0, vertexCount = 0;
	for (int k = 0; k < tb->blockCount; ++k)
	{
		tb->blockStart[k] = batch;
		tb->blockVertexStart[k] = vertexCount;
		bv->verts = tb->blockVertices + vertexCount;
		bv->count = 0;
		int first = batch;
		batch = fmPackBlock(tb, mesh, k, batch, bv);
		fmBuildIncidences(tb, first, batch, vertexCount, bv->count, bv->cursor);
		for (int i = 0; i < bv->count; ++i)
			bv->local[bv->verts[i]] = -1;
		vertexCount += bv->count;
		tb->maxBlockVertices = bv->count > tb->maxBlockVertices ? bv->count : tb->maxBlockVertices;
	}
	tb->blockStart[tb->blockCount] = batch;
	tb->blockVertexStart[tb->blockCount] = vertexCount;
	tb->entryCount = vertexCount;
	return batch == tb->batchCount;
}

// Each vertex's entries of the blocks' vertex lists, in block order (a stable counting sort),
// and room for the blocks' sums.
static bool fmBuildVertexEntries(fmTetBlocks* tb, int vertexCount)
{
	tb->vertexCount = vertexCount;
	tb->vertexEntryStart = FM_ALLOC_ZERO(int, (size_t)vertexCount + 1);
	tb->vertexEntries = FM_ALLOC_ARRAY(int, (size_t)tb->entryCount);
	tb->blockSums = FM_ALLOC_ZERO(double, 3 * (size_t)tb->entryCount + 1);
	if (tb->vertexEntryStart == NULL || tb->vertexEntries == NULL || tb->blockSums == NULL)
		return false;
	for (int e = 0; e < tb->entryCount; ++e)
		tb->vertexEntryStart[tb->blockVertices[e] + 1] += 1;
	for (int i = 0; i < vertexCount; ++i)
		tb->vertexEntryStart[i + 1] += tb->vertexEntryStart[i];
	// Placing moves each vertex's start to its end (the next one's start); then shift back.
	for (int e = 0; e < tb->entryCount; ++e)
		tb->vertexEntries[tb->vertexEntryStart[tb->blockVertices[e]]++] = e;
	for (int i = vertexCount; i > 0; --i)
		tb->vertexEntryStart[i] = tb->vertexEntryStart[i - 1];
	tb->vertexEntryStart[0] = 0;
	return true;
}

// The arrays of a layout of @p blockCount blocks; false when short.
static bool fmAllocateBlocks(fmTetBlocks* tb, const fmElasticMesh* mesh, int blockCount)
{
	tb->tetCount = mesh->tetCount;
	tb->blockCount = blockCount;
	for (int t = 0; t < mesh->tetCount; ++t)
		tb->restVolume += mesh->restVolume[t];
	// Blocks hold whole batches and every block but the last is full, so only the last batch
	// may be short.
	tb->batchCount = (mesh->tetCount + FM_LANES - 1) / FM_LANES;
	tb->batches = FM_ALLOC_ARRAY(fmTetBatch, tb->batchCount);
	tb->laneCount = FM_ALLOC_ARRAY(uint8_t, tb->batchCount);
	tb->blockStart = FM_ALLOC_ZERO(int, blockCount + 1);
	tb->blockVertexStart = FM_ALLOC_ZERO(int, blockCount + 1);
	tb->blockVertices = FM_ALLOC_ARRAY(int, 4 * (size_t)mesh->tetCount);
	tb->incidenceStart = FM_ALLOC_ZERO(int, 4 * (size_t)mesh->tetCount + 1);
	tb->incidences = FM_ALLOC_ARRAY(uint16_t, 4 * (size_t)mesh->tetCount);
	return tb->batches && tb->laneCount && tb->blockStart && tb->blockVertexStart &&
	       tb->blockVertices && tb->incidenceStart && tb->incidences;
}

// One pass over the vertex graph of the smoothing sums (fmTetBlocks.neighbourOffset): for each
// vertex, the vertices of its tets with how many of its tets hold each, in first-named order.
// With @p offsets NULL it only counts the entries; else it fills offsets and weights. @p slot
// (the place of vertex j in the current list) is -1 for every vertex, and again on return.
static int fmNeighbourPass(fmTetBlocks* tb, const fmElasticMesh* mesh, int* slot, int* offsets,
                           double* weights)
{
	int count = 0;
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		tb->neighbourStart[i] = count;
		for (int e = mesh->vertexTetStart[i]; e < mesh->vertexTetStart[i + 1]; ++e)
			for (int a = 0; a < 4; ++a)
			{
				int j = mesh->tets[4 * (mesh->vertexTets[e] / 4) + a];
				if (slot[j] < 0)
				{
					slot[j] = count++;
					if (offsets != NULL)
						offsets[slot[j]] = 3 * j, weights[slot[j]] = 0.0;
				}
				if (offsets != NULL)
					weights[slot[j]] += 1.0;
			}
		for (int e = mesh->vertexTetStart[i]; e < mesh->vertexTetStart[i + 1]; ++e)
			for (int a = 0; a < 4; ++a)
				slot[mesh->tets[4 * (mesh->vertexTets[e] / 4) + a]] = -1;
	}
	tb->neighbourStart[mesh->vertexCount] = count;
	return count;
}

// The smoothing's vertex graph: counted, then filled into arrays of its size.
static bool fmBuildNeighbours(fmTetBlocks* tb, const fmElasticMesh* mesh)
{
	const int n = mesh->vertexCount;
	tb->neighbourStart = FM_ALLOC_ZERO(int, (size_t)n + 1);
	int* slot = FM_ALLOC_ARRAY(int, n);
	bool ok = tb->neighbourStart != NULL && slot != NULL;
	for (int j = 0; ok && j < n; ++j)
		slot[j] = -1;
	if (ok)
	{
		tb->neighbourCount = fmNeighbourPass(tb, mesh, slot, NULL, NULL);
		tb->neighbourOffset = FM_ALLOC_ARRAY(int, tb->neighbourCount);
		tb->neighbourWeight = FM_ALLOC_ARRAY(double, tb->neighbourCount);
		ok = tb->neighbourOffset != NULL && tb->neighbourWeight != NULL;
	}
	if (ok)
		fmNeighbourPass(tb, mesh, slot, tb->neighbourOffset, tb->neighbourWeight);
	FM_FREE_ARRAY(slot, int, n);
	return ok;
}

fmTetBlocks* fmTetBlocks_Create(const fmElasticMesh* mesh, int workerCount)
{
	fmTetBlocks* tb = FM_ALLOC_ZERO(fmTetBlocks, 1);
	// The body keeps its tets in Morton order already (reorder.h): blocks are runs of it.
	const int perBlock = FM_BLOCK_BATCHES * FM_LANES;
	int blockCount = (mesh->tetCount + perBlock - 1) / perBlock;
	fmBlockVertices bv = {FM_ALLOC_ARRAY(int, mesh->vertexCount), NULL, 0,
	                      FM_ALLOC_ARRAY(int, 4 * perBlock)};
	bool ok = tb != NULL && bv.local != NULL && bv.cursor != NULL;
	if (ok)
	{
		for (int i = 0; i < mesh->vertexCount; ++i)
			bv.local[i] = -1;
		ok = fmAllocateBlocks(tb, mesh, blockCount) && fmPackBlocks(tb, mesh, &bv) &&
		     fmBuildVertexEntries(tb, mesh->vertexCount) && fmBuildNeighbours(tb, mesh);
	}
	if (ok)
	{
		tb->workerCount = workerCount > 0 ? workerCount : 1;
		tb->scratchBytes = fmScratchBytes(tb->maxBlockVertices);
		tb->scratch = FM_ALLOC_ARRAY(unsigned char, tb->scratchBytes*(size_t)tb->workerCount);
		tb->blockEnergy = FM_ALLOC_ZERO(double, tb->blockCount);
		tb->blockInverted = FM_ALLOC_ZERO(int, tb->blockCount);
		ok = tb->scratch != NULL && tb->blockEnergy != NULL && tb->blockInverted != NULL;
	}
	FM_FREE_ARRAY(bv.local, int, mesh->vertexCount);
	FM_FREE_ARRAY(bv.cursor, int, 4 * perBlock);
	if (!ok)
	{
		fmTetBlocks_Destroy(tb);
		return NULL;
	}
	return tb;
}

// ---- the force pass -----------------------------------------------------------------------------

typedef struct fmForcePass
{
	const fmTetBlocks* blocks;
	const fmElasticMesh* mesh;
	const double* x;
	const fmVec3* gravity; // f = m g + the forces, or NULL: f += the forces
	double* f;
	fmTetKernels kernels;
	fmKernelMaterial material;
	bool energy;            // the blocks' energies wanted
	const fmThenTask* then; // on each vertex range after its sums, or NULL
} fmForcePass;

// A worker's scratch: 4 doubles per block vertex, then the block's batch forces.
static double* fmScratch(const fmTetBlocks* tb, int worker, fmTetBatchForces** forces)
{
	unsigned char* base = tb->scratch + tb->scratchBytes * (size_t)worker;
	*forces =
	    (fmTetBatchForces*)(base + tb->scratchBytes - FM_BLOCK_BATCHES * sizeof(fmTetBatchForces));
	return (double*)base;
}

// Lane @p l of a batch by the double-precision reference: F = I + Du Dm^-1 from the block's
// displacements @p u, the material's P, and the forces -V0 P Dm^-T into the batch's output.
static void fmReferenceLane(const fmForcePass* p, const fmTetBatch* batch, int l, const double* u,
                            fmTetBatchForces* out, float* energy)
{
	fmMat3 Du, DmInv;
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
		{
			Du.m[3 * i + k] = u[batch->row[k + 1][l] + i] - u[batch->row[0][l] + i];
			DmInv.m[3 * i + k] = (double)batch->dmInv[3 * i + k][l];
		}
	fmMat3 F = fmMatMul(&Du, &DmInv), P;
	for (int i = 0; i < 3; ++i)
		F.m[4 * i] += 1.0;
	double psi = fmMaterial_Evaluate(&p->mesh->material, &F, &P, NULL);
	fmMat3 M = fmMatMulT(&P, &DmInv);
	double V0 = (double)batch->volume[l];
	if (energy)
		energy[l] = (float)(V0 * psi);
	for (int i = 0; i < 3; ++i)
	{
		double sum = 0.0;
		for (int k = 0; k < 3; ++k)
		{
			double fk = -V0 * M.m[3 * i + k];
			out->force[k + 1][l][i] = (float)fk;
			sum += fk;
		}
		out->force[0][l][i] = (float)-sum;
	}
}

// One block: gather its vertices' displacements, run its batches, then every vertex sums its
// entries of the block's forces in a fixed order into the block's sums; the block's energy is
// its tets' in order.
static void fmForceBlock(const fmForcePass* p, int k, int worker)
{
	const fmTetBlocks* tb = p->blocks;
	const int base = tb->blockVertexStart[k], count = tb->blockVertexStart[k + 1] - base;
	const int* verts = tb->blockVertices + base;
	fmTetBatchForces* out;
	double* u = fmScratch(tb, worker, &out);
	p->kernels.displacements(verts, count, p->x, p->mesh->x0, u);
	double energy = 0.0;
	int inverted = 0;
	float laneEnergy[FM_LANES];
	float* lanes = p->energy ? laneEnergy : NULL;
	for (int j = tb->blockStart[k]; j < tb->blockStart[k + 1]; ++j)
	{
		fmTetBatchForces* o = &out[j - tb->blockStart[k]];
		bool fallback = p->kernels.forces(&tb->batches[j], u, &p->material, o, lanes);
		for (int l = 0; fallback && l < tb->laneCount[j]; ++l)
			if (o->fallback[l])
				fmReferenceLane(p, &tb->batches[j], l, u, o, lanes);
		for (int l = 0; lanes && l < tb->laneCount[j]; ++l)
		{
			energy += (double)lanes[l];
			// Batch j holds the body's tets FM_LANES j ... (blocks are runs of its order).
			unsigned char flat = 0;
			if (!o->upright[l])
				fmInvertedTets(p->mesh, p->x, FM_LANES * j + l, FM_LANES * j + l + 1, &flat);
			inverted += flat;
		}
	}
	if (p->energy)
	{
		tb->blockEnergy[k] = energy;
		tb->blockInverted[k] = inverted;
	}
	p->kernels.sums(&out[0].force[0][0][0], tb->incidences, tb->incidenceStart + base, count,
	                tb->blockSums + 3 * (size_t)base);
}

static void fmForceBlocksTask(int start, int end, int worker, void* context)
{
	const fmForcePass* p = context;
	for (int k = start; k < end; ++k)
		fmForceBlock(p, k, worker);
}

// f (or m g) += the blocks' sums for vertices [start, end), each vertex's in block order (summed
// in registers, then stored: the same additions in the same order).
static void fmAddBlockSumsTask(int start, int end, int worker, void* context)
{
	const fmForcePass* p = context;
	const fmTetBlocks* tb = p->blocks;
	if (p->gravity != NULL)
	{
		const fmBlockGather gather = {tb->blockSums,
		                              tb->vertexEntries,
		                              tb->vertexEntryStart,
		                              p->mesh->mass,
		                              {p->gravity->x, p->gravity->y, p->gravity->z},
		                              p->f};
		p->kernels.gatherSums(&gather, start, end);
	}
	else
		for (int i = start; i < end; ++i)
		{
			double* fi = p->f + 3 * i;
			for (int e = tb->vertexEntryStart[i]; e < tb->vertexEntryStart[i + 1]; ++e)
			{
				const double* sum = tb->blockSums + 3 * (size_t)tb->vertexEntries[e];
				fi[0] += sum[0], fi[1] += sum[1], fi[2] += sum[2];
			}
		}
	if (p->then != NULL)
		p->then->task(start, end, worker, p->then->context);
}

double fmTetBlocks_AddForces(const fmTetBlocks* tb, const fmElasticMesh* mesh, const double* x,
                             const fmVec3* gravity, double* f, fmSimdLevel level,
                             const fmTaskSystem* tasks, bool energy, int* inverted,
                             const fmThenTask* then)
{
	fmForcePass p = {tb,
	                 mesh,
	                 x,
	                 gravity,
	                 f,
	                 fmTetBlocks_Kernels(level),
	                 {mesh->material.model, (float)mesh->material.mu, (float)mesh->material.lambda,
	                  (float)mesh->material.c01},
	                 energy,
	                 then};
	// The blocks, in ranges as small as one block: a block (512 tets, 5-10 us) is worth ten
	// times what handing out a range costs a polling pool (about 0.5 us). Workers beyond the
	// layout's scratch run serially (the same bits). Then the vertices gather their blocks'
	// sums.
	const fmTaskSystem* run = tasks != NULL && tasks->workerCount <= tb->workerCount ? tasks : NULL;
	fmParallelForBalanced(run, tb->blockCount, 1, fmForceBlocksTask, &p);
	fmParallelFor(tasks, tb->vertexCount, FM_PARALLEL_MIN_VERTICES, fmAddBlockSumsTask, &p);
	double sum = 0.0; // in block order: the same bits on any number of workers
	int flat = 0;
	for (int k = 0; energy && k < tb->blockCount; ++k)
	{
		sum += tb->blockEnergy[k];
		flat += tb->blockInverted[k];
	}
	if (energy && inverted != NULL)
		*inverted = flat;
	return energy ? sum : 0.0;
}

// ---- the smoothing sums -------------------------------------------------------------------------

typedef struct fmSmoothPass
{
	const fmTetBlocks* blocks;
	const double* v;
	double* sums;
	fmTetWeightedSumFcn* kernel;
} fmSmoothPass;

static void fmSmoothVerticesTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmSmoothPass* p = context;
	const fmTetBlocks* tb = p->blocks;
	p->kernel(p->v, tb->neighbourOffset, tb->neighbourWeight, tb->neighbourStart, start, end,
	          p->sums);
}

void fmTetBlocks_SmoothingSums(const fmTetBlocks* tb, const double* v, double* sums,
                               fmSimdLevel level, const fmTaskSystem* tasks)
{
	fmSmoothPass p = {tb, v, sums, fmTetBlocks_Kernels(level).weightedSums};
	fmParallelFor(tasks, tb->vertexCount, FM_PARALLEL_MIN_VERTICES, fmSmoothVerticesTask, &p);
}
