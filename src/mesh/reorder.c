// The order a body keeps its vertices and tets in (reorder.h).
#include "mesh/reorder.h"
#include "core/det_math.h"

#include "core/core.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

// Spread the low 10 bits of @p v to every third bit.
static uint64_t fmSpreadBits(uint32_t v)
{
	uint64_t x = v & 0x3ffu;
	x = (x | (x << 16)) & 0x030000ffu;
	x = (x | (x << 8)) & 0x0300f00fu;
	x = (x | (x << 4)) & 0x030c30c3u;
	x = (x | (x << 2)) & 0x09249249u;
	return x;
}

static int fmCompareKeys(const void* a, const void* b)
{
	uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

// Morton code (30 bits) of @p p in the box [lo, lo + extent]^3.
static uint64_t fmMortonCode(const double p[3], const double lo[3], double extent)
{
	uint64_t code = 0;
	for (int k = 0; k < 3; ++k)
	{
		double q = fmMin(1023.0, fmMax(0.0, (p[k] - lo[k]) / extent * 1024.0));
		code |= fmSpreadBits((uint32_t)q) << k;
	}
	return code;
}

// Tets sorted by the Morton code of their centroids (the user's index breaks ties).
static bool fmMortonTets(const double* x, int n, const int* tets, int m, int* tetOrder)
{
	uint64_t* keys = FM_ALLOC_ARRAY(uint64_t, m);
	if (keys == NULL)
		return false;
	double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]};
	for (int i = 1; i < n; ++i)
		for (int k = 0; k < 3; ++k)
			lo[k] = fmMin(lo[k], x[3 * i + k]), hi[k] = fmMax(hi[k], x[3 * i + k]);
	double extent = fmMax(fmMax(hi[0] - lo[0], hi[1] - lo[1]), fmMax(hi[2] - lo[2], 1e-300));
	for (int t = 0; t < m; ++t)
	{
		double c[3] = {0.0, 0.0, 0.0};
		for (int a = 0; a < 4; ++a)
			for (int k = 0; k < 3; ++k)
				c[k] += 0.25 * x[3 * tets[4 * t + a] + k];
		keys[t] = fmMortonCode(c, lo, extent) << 32 | (uint64_t)t;
	}
	qsort(keys, (size_t)m, sizeof *keys, fmCompareKeys);
	for (int t = 0; t < m; ++t)
		tetOrder[t] = (int)(keys[t] & 0xffffffffu);
	FM_FREE_ARRAY(keys, uint64_t, m);
	return true;
}

bool fmReorder_Compute(const double* positions, int vertexCount, const int* tets, int tetCount,
                       int* tetOrder, int* vertexOrder)
{
	bool* placed = FM_ALLOC_ZERO(bool, vertexCount);
	if (placed == NULL || !fmMortonTets(positions, vertexCount, tets, tetCount, tetOrder))
	{
		FM_FREE_ARRAY(placed, bool, vertexCount);
		return false;
	}
	int next = 0;
	for (int k = 0; k < tetCount; ++k)
		for (int a = 0; a < 4; ++a)
		{
			int v = tets[4 * tetOrder[k] + a];
			if (!placed[v])
				placed[v] = true, vertexOrder[next++] = v;
		}
	for (int v = 0; v < vertexCount; ++v)
		if (!placed[v])
			vertexOrder[next++] = v;
	FM_FREE_ARRAY(placed, bool, vertexCount);
	return true;
}
