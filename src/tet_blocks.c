// The explicit FEM step's element layout and force pass (tet_blocks.h).
#include "tet_blocks.h"

#include "core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool fmTetBlocks_Applies(const fmBody* body, fmSimdLevel level)
{
	fmMaterialModel m = body->material.model;
	return level != fm_simdOff && body->forceModel == fm_fem &&
	       (m == fm_linear || m == fm_stvk || m == fm_neoHookean);
}

fmTetKernelFcn* fmTetBlocks_Kernel(fmSimdLevel level)
{
	switch (level)
	{
#if defined(__x86_64__) || defined(_M_X64)
	case fm_simdAvx512:
		return fmTetKernel_Forces_avx512;
	case fm_simdAvx2:
		return fmTetKernel_Forces_avx2;
#endif
	case fm_simdScalar:
		return fmTetKernel_Forces_scalar;
	default:
		return fmTetKernel_Forces_baseline;
	}
}

// ---- the layout ---------------------------------------------------------------------------------

// Spread the low 10 bits of @p v to every third bit.
static uint32_t fmSpreadBits(uint32_t v)
{
	v &= 0x3ffu;
	v = (v | (v << 16)) & 0x030000ffu;
	v = (v | (v << 8)) & 0x0300f00fu;
	v = (v | (v << 4)) & 0x030c30c3u;
	v = (v | (v << 2)) & 0x09249249u;
	return v;
}

static int fmCompareKeys(const void* a, const void* b)
{
	uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

// The tets in Morton order of their rest centroids (ties by index): neighbours in the order are
// neighbours in space, so a block's vertices stay in cache while its tets run.
static int* fmMortonOrder(const fmBody* b)
{
	uint64_t* keys = FM_ALLOC_ARRAY(uint64_t, b->tetCount);
	int* order = FM_ALLOC_ARRAY(int, b->tetCount);
	if (keys == NULL || order == NULL)
	{
		FM_FREE_ARRAY(keys, uint64_t, b->tetCount);
		FM_FREE_ARRAY(order, int, b->tetCount);
		return NULL;
	}
	fmVec3 lo = fmLoad(b->x0, 0), hi = lo;
	for (int i = 1; i < b->vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->x0, i);
		lo = fmMakeVec3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
		hi = fmMakeVec3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
	}
	double extent = fmax(fmax(hi.x - lo.x, hi.y - lo.y), fmax(hi.z - lo.z, 1e-300));
	for (int t = 0; t < b->tetCount; ++t)
	{
		const int* n = b->tets + 4 * t;
		fmVec3 c = fmScale(0.25, fmAdd(fmAdd(fmLoad(b->x0, n[0]), fmLoad(b->x0, n[1])),
		                               fmAdd(fmLoad(b->x0, n[2]), fmLoad(b->x0, n[3]))));
		uint32_t q[3];
		double p[3] = {c.x - lo.x, c.y - lo.y, c.z - lo.z};
		for (int k = 0; k < 3; ++k)
			q[k] = (uint32_t)fmin(1023.0, fmax(0.0, p[k] / extent * 1024.0));
		uint64_t code = fmSpreadBits(q[0]) | fmSpreadBits(q[1]) << 1 | fmSpreadBits(q[2]) << 2;
		keys[t] = code << 32 | (uint64_t)t;
	}
	qsort(keys, (size_t)b->tetCount, sizeof *keys, fmCompareKeys);
	for (int t = 0; t < b->tetCount; ++t)
		order[t] = (int)(keys[t] & 0xffffffffu);
	FM_FREE_ARRAY(keys, uint64_t, b->tetCount);
	return order;
}

// Greedy colours of the blocks (consecutive runs of FM_BLOCK_BATCHES * FM_LANES tets of
// @p order): the lowest colour no block sharing a vertex has. -1 when 64 are not enough.
static int fmColourBlocks(const fmBody* b, const int* order, int blockCount, int* colour)
{
	uint64_t* used = FM_ALLOC_ZERO(uint64_t, b->vertexCount); // colours around each vertex
	if (used == NULL)
		return -1;
	const int perBlock = FM_BLOCK_BATCHES * FM_LANES;
	int count = 0;
	for (int k = 0; k < blockCount; ++k)
	{
		int first = k * perBlock,
		    end = first + perBlock < b->tetCount ? first + perBlock : b->tetCount;
		uint64_t taken = 0;
		for (int t = first; t < end; ++t)
			for (int a = 0; a < 4; ++a)
				taken |= used[b->tets[4 * order[t] + a]];
		if (taken == UINT64_MAX)
		{
			count = -1;
			break;
		}
		int c = 0;
		while (taken >> c & 1u)
			++c;
		colour[k] = c;
		count = c + 1 > count ? c + 1 : count;
		for (int t = first; t < end; ++t)
			for (int a = 0; a < 4; ++a)
				used[b->tets[4 * order[t] + a]] |= (uint64_t)1 << c;
	}
	FM_FREE_ARRAY(used, uint64_t, b->vertexCount);
	return count;
}

// Pack tets order[first .. end) into one batch; unused lanes repeat the first tet, weightless.
static void fmPackBatch(const fmBody* b, const int* order, int first, int end, fmTetBatch* batch)
{
	for (int l = 0; l < FM_LANES; ++l)
	{
		int t = order[first + l < end ? first + l : first];
		for (int a = 0; a < 4; ++a)
			batch->nodes[a][l] = b->tets[4 * t + a];
		for (int k = 0; k < 9; ++k)
			batch->dmInv[k][l] = (float)b->DmInv[t].m[k];
		batch->volume[l] = first + l < end ? (float)b->restVolume[t] : 0.0f;
	}
}

uint64_t fmTetBlocks_Bytes(uint64_t tetCount)
{
	uint64_t batches = (tetCount + FM_LANES - 1) / FM_LANES;
	uint64_t blocks = (batches + FM_BLOCK_BATCHES - 1) / FM_BLOCK_BATCHES;
	return batches * (sizeof(fmTetBatch) + 1) + (blocks + 1) * sizeof(int) + 65 * sizeof(int) +
	       sizeof(fmTetBlocks);
}

void fmTetBlocks_Destroy(fmTetBlocks* tb)
{
	if (tb == NULL)
		return;
	FM_FREE_ARRAY(tb->batches, fmTetBatch, tb->batchCount);
	FM_FREE_ARRAY(tb->laneCount, uint8_t, tb->batchCount);
	FM_FREE_ARRAY(tb->blockStart, int, tb->blockCount + 1);
	FM_FREE_ARRAY(tb->colourStart, int, tb->colourCount + 1);
	FM_FREE_ARRAY(tb, fmTetBlocks, 1);
}

// Blocks in colour order (a counting sort, stable: within a colour, in Morton order); packs
// their batches.
static bool fmPackBlocks(fmTetBlocks* tb, const fmBody* b, const int* order, const int* colour)
{
	const int perBlock = FM_BLOCK_BATCHES * FM_LANES;
	for (int k = 0; k < tb->blockCount; ++k)
		tb->colourStart[colour[k] + 1] += 1;
	for (int c = 0; c < tb->colourCount; ++c)
		tb->colourStart[c + 1] += tb->colourStart[c];
	int batch = 0, slot = 0;
	for (int c = 0; c < tb->colourCount; ++c)
		for (int k = 0; k < tb->blockCount; ++k)
		{
			if (colour[k] != c)
				continue;
			tb->blockStart[slot++] = batch;
			int first = k * perBlock,
			    end = first + perBlock < tb->tetCount ? first + perBlock : tb->tetCount;
			for (int t = first; t < end; t += FM_LANES, ++batch)
			{
				int last = t + FM_LANES < end ? t + FM_LANES : end;
				fmPackBatch(b, order, t, last, &tb->batches[batch]);
				tb->laneCount[batch] = (uint8_t)(last - t);
			}
		}
	tb->blockStart[tb->blockCount] = batch;
	return batch == tb->batchCount;
}

fmTetBlocks* fmTetBlocks_Create(const fmBody* b)
{
	fmTetBlocks* tb = FM_ALLOC_ZERO(fmTetBlocks, 1);
	int* order = fmMortonOrder(b);
	const int perBlock = FM_BLOCK_BATCHES * FM_LANES;
	int blockCount = (b->tetCount + perBlock - 1) / perBlock;
	int* colour = FM_ALLOC_ZERO(int, blockCount);
	bool ok = tb != NULL && order != NULL && colour != NULL;
	if (ok)
	{
		tb->tetCount = b->tetCount;
		tb->blockCount = blockCount;
		tb->colourCount = fmColourBlocks(b, order, blockCount, colour);
		ok = tb->colourCount > 0;
	}
	if (ok)
	{
		// Blocks hold whole batches and every block but the last is full, so only the last
		// batch may be short.
		tb->batchCount = (b->tetCount + FM_LANES - 1) / FM_LANES;
		tb->batches = FM_ALLOC_ARRAY(fmTetBatch, tb->batchCount);
		tb->laneCount = FM_ALLOC_ARRAY(uint8_t, tb->batchCount);
		tb->blockStart = FM_ALLOC_ZERO(int, blockCount + 1);
		tb->colourStart = FM_ALLOC_ZERO(int, tb->colourCount + 1);
		ok = tb->batches && tb->laneCount && tb->blockStart && tb->colourStart;
	}
	if (ok)
		ok = fmPackBlocks(tb, b, order, colour);
	FM_FREE_ARRAY(order, int, b->tetCount);
	FM_FREE_ARRAY(colour, int, blockCount);
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
	const fmBody* body;
	const double* x;
	double* f;
	fmTetKernelFcn* kernel;
	fmKernelMaterial material;
	int firstBlock; // of the colour being run
} fmForcePass;

// Du of every lane, from displacements u = x - X taken in double.
static void fmGatherBatch(const fmForcePass* p, const fmTetBatch* batch, fmTetBatchWork* work)
{
	const double *x = p->x, *X = p->body->x0;
	for (int l = 0; l < FM_LANES; ++l)
	{
		int n0 = batch->nodes[0][l];
		for (int k = 0; k < 3; ++k)
		{
			int n = batch->nodes[k + 1][l];
			for (int i = 0; i < 3; ++i)
			{
				double du = (x[3 * n + i] - X[3 * n + i]) - (x[3 * n0 + i] - X[3 * n0 + i]);
				work->du[3 * i + k][l] = (float)du;
			}
		}
	}
}

// f += the batch's forces, lane by lane (the order every worker count shares).
static void fmScatterBatch(const fmForcePass* p, const fmTetBatch* batch, int lanes,
                           const fmTetBatchWork* work)
{
	double* f = p->f;
	for (int l = 0; l < lanes; ++l)
	{
		int n0 = batch->nodes[0][l];
		for (int i = 0; i < 3; ++i)
		{
			double sum = 0.0;
			for (int k = 0; k < 3; ++k)
			{
				double fk = (double)work->force[3 * k + i][l];
				f[3 * batch->nodes[k + 1][l] + i] += fk;
				sum += fk;
			}
			f[3 * n0 + i] -= sum;
		}
	}
}

static void fmForceBlocksTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmForcePass* p = context;
	const fmTetBlocks* tb = p->blocks;
	fmTetBatchWork work;
	for (int k = p->firstBlock + start; k < p->firstBlock + end; ++k)
		for (int j = tb->blockStart[k]; j < tb->blockStart[k + 1]; ++j)
		{
			fmGatherBatch(p, &tb->batches[j], &work);
			p->kernel(&tb->batches[j], &work, &p->material);
			fmScatterBatch(p, &tb->batches[j], tb->laneCount[j], &work);
		}
}

void fmTetBlocks_AddForces(const fmTetBlocks* tb, const fmBody* body, const double* x, double* f,
                           fmSimdLevel level, const fmTaskSystem* tasks)
{
	fmForcePass p = {tb,
	                 body,
	                 x,
	                 f,
	                 fmTetBlocks_Kernel(level),
	                 {body->material.model, (float)body->material.mu, (float)body->material.lambda},
	                 0};
	// Ranges of at least FM_PARALLEL_MIN_RANGE tets: smaller ones cost more to hand out.
	const int minBlocks =
	    (FM_PARALLEL_MIN_RANGE + FM_BLOCK_BATCHES * FM_LANES - 1) / (FM_BLOCK_BATCHES * FM_LANES);
	for (int c = 0; c < tb->colourCount; ++c)
	{
		p.firstBlock = tb->colourStart[c];
		fmParallelFor(tasks, tb->colourStart[c + 1] - p.firstBlock, minBlocks, fmForceBlocksTask,
		              &p);
	}
}
