// A spatial hash over axis-aligned boxes (broad_phase.c): rebuilt every substep from the items'
// boxes, queried with a box; deterministic (items come out of a cell in insertion order) and
// without allocation once its arrays have grown to the scene.
#pragma once

#include <femto/femto.h>

#include <stdbool.h>

typedef struct fmSpatialHash
{
	double cell;       // m, the edge of a cell
	int tableSize;     // buckets, a power of two
	int tableCapacity; // allocated buckets + 1
	int* bucketStart;  // tableSize + 1: the entries of bucket k are [start[k], start[k + 1])
	int entryCount;
	int entryCapacity;
	int* entries;     // the item of each entry, grouped by bucket
	int* entryBucket; // scratch: the bucket of each entry before grouping
	int* itemRange;   // scratch: each item's cell range (lowest x, y, z, highest x, y, z)
	int rangeCapacity;
	int itemCount; // items in the last build
} fmSpatialHash;

// One querier's buffers: queries with distinct ones may run in parallel on the same hash (one
// per worker). Zeroed to start.
typedef struct fmHashQuery
{
	unsigned* stamp; // per item: the query that last returned it
	int stampCapacity;
	unsigned query; // the current query's stamp
	int* items;     // the last query's items
	int itemCapacity;
} fmHashQuery;

// Rebuild over @p count items, item k covering [lower[k], upper[k]], with cells of @p cell m.
// False when memory is short (the hash is then empty).
bool fmSpatialHash_Build(fmSpatialHash* hash, const fmVec3* lower, const fmVec3* upper, int count,
                         double cell);

// Room in @p query's stamps for every item of @p hash's last build; call it after the build,
// before the queries (it allocates). False when memory is short.
bool fmHashQuery_Reserve(fmHashQuery* query, const fmSpatialHash* hash);

// The items whose cells overlap [lower, upper], each once, into query->items (grown as
// needed); returns how many, or -1 when memory is short. Reads @p hash only. A box over more
// cells than the hash has entries returns every item (callers test the items' own boxes): the
// work of a query is bounded by the hash's size.
int fmSpatialHash_Query(const fmSpatialHash* hash, fmHashQuery* query, fmVec3 lower, fmVec3 upper);

// Release a querier's buffers; safe on a zeroed one.
void fmHashQuery_Free(fmHashQuery* query);

// Release the arrays; safe on a zeroed hash.
void fmSpatialHash_Free(fmSpatialHash* hash);
