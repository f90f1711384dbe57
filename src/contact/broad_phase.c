// The contact stage's broad phase (broad_phase.h): a uniform grid hashed into buckets, filled
// by a counting sort so that a bucket lists its items in the order they were given.
#include "contact/broad_phase.h"

#include "core/core.h"

#include <math.h>
#include <string.h>

// Cells an item may cover along one axis (a guard: callers choose the cell from the items'
// sizes); a larger item is cut to that many cells from its lower corner.
#define FM_HASH_MAX_SPAN 1024

// Cells an item covers on average at most (the grid coarsens beyond it).
#define FM_HASH_MAX_CELLS 64

void fmSpatialHash_Free(fmSpatialHash* h)
{
	FM_FREE_ARRAY(h->bucketStart, int, h->tableCapacity);
	FM_FREE_ARRAY(h->entries, int, h->entryCapacity);
	FM_FREE_ARRAY(h->entryBucket, int, h->entryCapacity);
	FM_FREE_ARRAY(h->itemRange, int, h->rangeCapacity);
	memset(h, 0, sizeof *h);
}

void fmHashQuery_Free(fmHashQuery* q)
{
	FM_FREE_ARRAY(q->stamp, unsigned, q->stampCapacity);
	FM_FREE_ARRAY(q->items, int, q->itemCapacity);
	memset(q, 0, sizeof *q);
}

bool fmHashQuery_Reserve(fmHashQuery* q, const fmSpatialHash* h)
{
	if (h->itemCount <= q->stampCapacity)
		return true;
	unsigned* stamp = FM_ALLOC_ZERO(unsigned, h->itemCount);
	if (stamp == NULL)
		return false;
	FM_FREE_ARRAY(q->stamp, unsigned, q->stampCapacity);
	q->stamp = stamp;
	q->stampCapacity = h->itemCount;
	q->query = 0;
	return true;
}

static int fmCellOf(double x, double cell)
{
	double c = floor(x / cell);
	return c < -1e9 ? -1000000000 : c > 1e9 ? 1000000000 : (int)c;
}

static int fmBucketOf(const fmSpatialHash* h, int x, int y, int z)
{
	unsigned k = (unsigned)x * 73856093u ^ (unsigned)y * 19349663u ^ (unsigned)z * 83492791u;
	return (int)(k & (unsigned)(h->tableSize - 1));
}

// The cell range of a box along the three axes, each clamped to FM_HASH_MAX_SPAN cells.
static void fmCellRange(double cell, fmVec3 lower, fmVec3 upper, int lo[3], int hi[3])
{
	const double a[3] = {lower.x, lower.y, lower.z}, b[3] = {upper.x, upper.y, upper.z};
	for (int e = 0; e < 3; ++e)
	{
		lo[e] = fmCellOf(a[e], cell);
		hi[e] = fmCellOf(b[e], cell);
		if (hi[e] - lo[e] >= FM_HASH_MAX_SPAN)
			hi[e] = lo[e] + FM_HASH_MAX_SPAN - 1;
	}
}

static bool fmReserve(fmSpatialHash* h, int entries)
{
	int table = 1;
	while (table < 2 * entries && table < (1 << 26))
		table <<= 1;
	if (entries > h->entryCapacity)
	{
		int grown = entries + entries / 2;
		int* fresh = FM_ALLOC_ARRAY(int, grown);
		int* bucket = FM_ALLOC_ARRAY(int, grown);
		if (fresh == NULL || bucket == NULL)
		{
			FM_FREE_ARRAY(fresh, int, grown);
			FM_FREE_ARRAY(bucket, int, grown);
			return false;
		}
		FM_FREE_ARRAY(h->entries, int, h->entryCapacity);
		FM_FREE_ARRAY(h->entryBucket, int, h->entryCapacity);
		h->entries = fresh;
		h->entryBucket = bucket;
		h->entryCapacity = grown;
	}
	if (table + 1 > h->tableCapacity)
	{
		int* fresh = FM_ALLOC_ARRAY(int, table + 1);
		if (fresh == NULL)
			return false;
		FM_FREE_ARRAY(h->bucketStart, int, h->tableCapacity);
		h->bucketStart = fresh;
		h->tableCapacity = table + 1;
	}
	h->tableSize = table;
	return true;
}

// Double a querier's list of items, keeping the @p found first ones.
static bool fmGrowItems(fmHashQuery* q, int found)
{
	int grown = 2 * found + 16;
	int* fresh = FM_ALLOC_ARRAY(int, grown);
	if (fresh == NULL)
		return false;
	if (found > 0)
		memcpy(fresh, q->items, sizeof(int) * (size_t)found);
	FM_FREE_ARRAY(q->items, int, q->itemCapacity);
	q->items = fresh;
	q->itemCapacity = grown;
	return true;
}

bool fmSpatialHash_Build(fmSpatialHash* h, const fmVec3* lower, const fmVec3* upper, int count,
                         double cell)
{
	h->entryCount = 0;
	long long entries = 0;
	if (!fmGrowArray((void**)&h->itemRange, &h->rangeCapacity, 0, 6 * (count > 0 ? count : 1),
	                 sizeof(int)))
	{
		h->tableSize = 0;
		return false;
	}
	// Cells grow until the items cover at most FM_HASH_MAX_CELLS cells each on average: a few
	// huge items (a body blowing up before the step's checks catch it) cost a coarser grid,
	// not a table of billions of entries. Each item's cell range is kept for the passes below.
	for (int attempt = 0; attempt < 64; ++attempt, cell *= 2.0)
	{
		entries = 0;
		for (int k = 0; k < count; ++k)
		{
			int *lo = h->itemRange + 6 * k, *hi = lo + 3;
			fmCellRange(cell, lower[k], upper[k], lo, hi);
			entries += (long long)(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
		}
		if (entries <= (long long)FM_HASH_MAX_CELLS * (count > 0 ? count : 1))
			break;
	}
	h->cell = cell;
	h->itemCount = 0;
	if (entries > (1 << 28) || !fmReserve(h, (int)entries))
	{
		h->tableSize = 0;
		return false;
	}
	h->itemCount = count;
	memset(h->bucketStart, 0, sizeof(int) * ((size_t)h->tableSize + 1));
	int n = 0;
	for (int k = 0; k < count; ++k)
	{
		const int *lo = h->itemRange + 6 * k, *hi = lo + 3;
		for (int x = lo[0]; x <= hi[0]; ++x)
			for (int y = lo[1]; y <= hi[1]; ++y)
				for (int z = lo[2]; z <= hi[2]; ++z)
				{
					int bucket = fmBucketOf(h, x, y, z);
					h->entryBucket[n++] = bucket;
					h->bucketStart[bucket + 1] += 1;
				}
	}
	for (int b = 0; b < h->tableSize; ++b)
		h->bucketStart[b + 1] += h->bucketStart[b];
	// Fill in item order: each bucket's entries stay in the order the items were given. The
	// starts are advanced while filling and shifted back after.
	n = 0;
	for (int k = 0; k < count; ++k)
	{
		const int *lo = h->itemRange + 6 * k, *hi = lo + 3;
		int cells = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
		for (int c = 0; c < cells; ++c)
			h->entries[h->bucketStart[h->entryBucket[n++]]++] = k;
	}
	for (int b = h->tableSize; b > 0; --b)
		h->bucketStart[b] = h->bucketStart[b - 1];
	h->bucketStart[0] = 0;
	h->entryCount = n;
	return true;
}

// Add @p item to the query's items unless this query returned it already. False when memory is
// short.
static bool fmTakeItem(fmHashQuery* q, int item, int* found)
{
	if (q->stamp[item] == q->query)
		return true;
	q->stamp[item] = q->query;
	if (*found == q->itemCapacity && !fmGrowItems(q, *found))
		return false;
	q->items[(*found)++] = item;
	return true;
}

int fmSpatialHash_Query(const fmSpatialHash* h, fmHashQuery* q, fmVec3 lower, fmVec3 upper)
{
	if (h->tableSize == 0)
		return 0;
	if (q->stampCapacity < h->itemCount)
		return -1;       // (fmHashQuery_Reserve was not called after the build)
	if (++q->query == 0) // the stamps wrapped: start them again
	{
		memset(q->stamp, 0, sizeof(unsigned) * (size_t)q->stampCapacity);
		q->query = 1;
	}
	int lo[3], hi[3], found = 0;
	fmCellRange(h->cell, lower, upper, lo, hi);
	// A box over more cells than the hash has entries (a body flung kilometres in a substep): its
	// cells would cost more than every entry, so every item is returned, each once.
	double cells = (double)(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
	if (cells > h->entryCount)
	{
		for (int e = 0; e < h->entryCount; ++e)
			if (!fmTakeItem(q, h->entries[e], &found))
				return -1;
		return found;
	}
	for (int x = lo[0]; x <= hi[0]; ++x)
		for (int y = lo[1]; y <= hi[1]; ++y)
			for (int z = lo[2]; z <= hi[2]; ++z)
			{
				int bucket = fmBucketOf(h, x, y, z);
				for (int e = h->bucketStart[bucket]; e < h->bucketStart[bucket + 1]; ++e)
					if (!fmTakeItem(q, h->entries[e], &found))
						return -1;
			}
	return found;
}
