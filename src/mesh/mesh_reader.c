// What the Gmsh, VTK and Medit readers share: the scanner, binary loads, the node tag map and the
// tet list (mesh_reader.h).
#include "mesh/mesh_reader.h"

#include "core/core.h"
#include "mesh/mesh_internal.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- binary loads -----------------------------------------------------------------------------

bool fmHostIsLittleEndian(void)
{
	const uint16_t one = 1;
	unsigned char first;
	memcpy(&first, &one, 1);
	return first == 1;
}

static void fmLoadBytes(void* out, const unsigned char* bytes, size_t n, bool swap)
{
	unsigned char b[8];
	for (size_t k = 0; k < n; ++k)
		b[k] = swap ? bytes[n - 1 - k] : bytes[k];
	memcpy(out, b, n);
}

uint32_t fmLoadU32(const unsigned char* bytes, bool swap)
{
	uint32_t v;
	fmLoadBytes(&v, bytes, 4, swap);
	return v;
}

uint64_t fmLoadU64(const unsigned char* bytes, bool swap)
{
	uint64_t v;
	fmLoadBytes(&v, bytes, 8, swap);
	return v;
}

double fmLoadF64(const unsigned char* bytes, bool swap)
{
	double v;
	fmLoadBytes(&v, bytes, 8, swap);
	return v;
}

float fmLoadF32(const unsigned char* bytes, bool swap)
{
	float v;
	fmLoadBytes(&v, bytes, 4, swap);
	return v;
}

// ---- node tags --------------------------------------------------------------------------------

typedef struct fmTagPair
{
	long long tag;
	int index;
} fmTagPair;

static int fmCompareTagPairs(const void* a, const void* b)
{
	const fmTagPair* p = a;
	const fmTagPair* q = b;
	return p->tag < q->tag ? -1 : (p->tag > q->tag);
}

fmResult fmTagMap_Build(fmTagMap* map, const long long* tags, int count, const char* name,
                        fmDiagnostic* diag)
{
	memset(map, 0, sizeof *map);
	map->count = count;
	map->dense = true;
	map->first = count > 0 ? tags[0] : 0;
	for (int i = 1; i < count && map->dense; ++i)
		map->dense = (unsigned long long)tags[i] == (unsigned long long)tags[i - 1] + 1u;
	if (map->dense)
		return fm_ok;
	fmTagPair* pairs = FM_ALLOC_ARRAY(fmTagPair, count);
	map->tags = FM_ALLOC_ARRAY(long long, count);
	map->index = FM_ALLOC_ARRAY(int, count);
	fmResult result = fm_ok;
	if (pairs == NULL || map->tags == NULL || map->index == NULL)
		result = fmDiagError(diag, fm_errOutOfMemory, name, 0, 0,
		                     "out of memory for the tags of %d nodes", count);
	for (int i = 0; i < count && result == fm_ok; ++i)
	{
		pairs[i].tag = tags[i];
		pairs[i].index = i;
	}
	if (result == fm_ok)
		qsort(pairs, (size_t)count, sizeof *pairs, fmCompareTagPairs);
	for (int k = 0; k < count && result == fm_ok; ++k)
	{
		if (k > 0 && pairs[k].tag == pairs[k - 1].tag)
			result =
			    fmDiagError(diag, fm_errIndex, name, 0, 0,
			                "node tag %lld is given twice: expected each node once", pairs[k].tag);
		map->tags[k] = pairs[k].tag;
		map->index[k] = pairs[k].index;
	}
	FM_FREE_ARRAY(pairs, fmTagPair, count);
	if (result != fm_ok)
		fmTagMap_Free(map);
	return result;
}

int fmTagMap_Find(const fmTagMap* map, long long tag)
{
	if (map->dense)
	{
		// Subtract in unsigned arithmetic: any two tags are allowed, no overflow.
		unsigned long long k = (unsigned long long)tag - (unsigned long long)map->first;
		return k < (unsigned long long)map->count ? (int)k : -1;
	}
	int lo = 0, hi = map->count - 1;
	while (lo <= hi)
	{
		int mid = lo + (hi - lo) / 2;
		if (map->tags[mid] == tag)
			return map->index[mid];
		if (map->tags[mid] < tag)
			lo = mid + 1;
		else
			hi = mid - 1;
	}
	return -1;
}

void fmTagMap_Free(fmTagMap* map)
{
	if (!map->dense)
	{
		FM_FREE_ARRAY(map->tags, long long, map->count);
		FM_FREE_ARRAY(map->index, int, map->count);
	}
	memset(map, 0, sizeof *map);
}

// ---- skipped elements -------------------------------------------------------------------------

void fmSkipped_Add(fmSkipped* skipped, const char* kind, long long count)
{
	skipped->total += count;
	for (int k = 0; k < FM_SKIP_KINDS; ++k)
	{
		if (skipped->kind[k] == NULL)
			skipped->kind[k] = kind;
		if (strcmp(skipped->kind[k], kind) == 0)
		{
			skipped->count[k] += count;
			return;
		}
	}
	skipped->other += count;
}

void fmSkipped_Format(const fmSkipped* skipped, char* text, size_t size)
{
	size_t n = 0;
	text[0] = 0;
	for (int k = 0; k < FM_SKIP_KINDS && skipped->kind[k] && n < size; ++k)
		n += (size_t)snprintf(text + n, size - n, "%s%lld %s", n ? ", " : "", skipped->count[k],
		                      skipped->kind[k]);
	if (skipped->other > 0 && n < size)
		snprintf(text + n, size - n, "%s%lld of other kinds", n ? ", " : "", skipped->other);
}

// ---- tets -------------------------------------------------------------------------------------

void fmTetList_Init(fmTetList* list, long long limit, bool hasRegions)
{
	memset(list, 0, sizeof *list);
	list->limit = limit < FM_MAX_TETS ? (int)(limit > 0 ? limit : 0) : FM_MAX_TETS;
	list->hasRegions = hasRegions;
}

void fmTetList_Free(fmTetList* list)
{
	FM_FREE_ARRAY(list->tets, int, 4 * (size_t)list->capacity);
	FM_FREE_ARRAY(list->lines, int, list->capacity);
	if (list->regions)
		FM_FREE_ARRAY(list->regions, double, list->capacity);
	list->tets = NULL;
	list->lines = NULL;
	list->regions = NULL;
	list->count = list->capacity = 0;
}

// Double the capacity (at least 1024, at most the limit): memory follows the tets actually read.
static fmResult fmTetListGrow(fmTetList* list, const fmScan* s)
{
	if (list->count >= list->limit)
		return fmScan_Error(s, fm_errLimit,
		                    "more than %d tets: the file's element count or the limit of "
		                    "FM_MAX_TETS is exceeded",
		                    list->limit);
	long long wanted = list->capacity < 512 ? 1024 : 2LL * list->capacity;
	int capacity = wanted < list->limit ? (int)wanted : list->limit;
	int* tets = FM_ALLOC_ARRAY(int, 4 * (size_t)capacity);
	int* lines = FM_ALLOC_ARRAY(int, capacity);
	double* regions = list->hasRegions ? FM_ALLOC_ARRAY(double, capacity) : NULL;
	if (tets == NULL || lines == NULL || (list->hasRegions && regions == NULL))
	{
		FM_FREE_ARRAY(tets, int, 4 * (size_t)capacity);
		FM_FREE_ARRAY(lines, int, capacity);
		FM_FREE_ARRAY(regions, double, capacity);
		return fmScan_Error(s, fm_errOutOfMemory, "out of memory for %d tets", capacity);
	}
	int n = list->count;
	if (n > 0)
	{
		memcpy(tets, list->tets, 4 * sizeof(int) * (size_t)n);
		memcpy(lines, list->lines, sizeof(int) * (size_t)n);
		if (regions)
			memcpy(regions, list->regions, sizeof(double) * (size_t)n);
	}
	int count = list->count;
	fmTetList_Free(list);
	list->tets = tets;
	list->lines = lines;
	list->regions = regions;
	list->count = count;
	list->capacity = capacity;
	return fm_ok;
}

fmResult fmTetList_Add(fmTetList* list, const int nodes[4], int line, double region,
                       const fmScan* s)
{
	for (int a = 0; a < 4; ++a)
		for (int b = a + 1; b < 4; ++b)
			if (nodes[a] == nodes[b])
			{
				// In binary data the last text token is far behind: locate by position.
				bool binary = s->token == NULL || s->data + s->pos != s->token + s->tokenLength;
				if (binary)
					return fmScan_ErrorHere(s, fm_errIndex,
					                        "a tet before byte %zu uses one node twice (its "
					                        "corners %d and %d): expected 4 different nodes",
					                        s->pos, a + 1, b + 1);
				return fmScan_Error(s, fm_errIndex,
				                    "a tet uses one node twice (its corners %d and %d): expected "
				                    "4 different nodes",
				                    a + 1, b + 1);
			}
	if (list->count == list->capacity)
	{
		fmResult result = fmTetListGrow(list, s);
		if (result != fm_ok)
			return result;
	}
	memcpy(list->tets + 4 * (size_t)list->count, nodes, 4 * sizeof(int));
	list->lines[list->count] = line;
	if (list->hasRegions)
		list->regions[list->count] = region;
	list->count += 1;
	return fm_ok;
}

// Drop the nodes no tet uses when quadratic tets were read by their corners (their mid-edge nodes
// would otherwise stay in the body as fixed points). Renumbers the tets.
static fmResult fmDropMidNodes(fmTetMesh* m, const char* name, fmDiagnostic* diag)
{
	int* newIndex = FM_ALLOC_ARRAY(int, m->nodeCount);
	if (newIndex == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, name, 0, 0, "out of memory for %d nodes",
		                   m->nodeCount);
	for (int i = 0; i < m->nodeCount; ++i)
		newIndex[i] = -1;
	for (size_t k = 0; k < 4 * (size_t)m->tetCount; ++k)
		newIndex[m->tets[k]] = 0;
	int kept = 0;
	for (int i = 0; i < m->nodeCount; ++i)
		if (newIndex[i] == 0)
		{
			newIndex[i] = kept;
			memmove(m->positions + 3 * (size_t)kept, m->positions + 3 * (size_t)i,
			        3 * sizeof(double));
			++kept;
		}
	for (size_t k = 0; k < 4 * (size_t)m->tetCount; ++k)
		m->tets[k] = newIndex[m->tets[k]];
	double* positions = FM_ALLOC_ARRAY(double, 3 * (size_t)kept);
	if (positions == NULL)
	{
		FM_FREE_ARRAY(newIndex, int, m->nodeCount);
		return fmDiagError(diag, fm_errOutOfMemory, name, 0, 0, "out of memory for %d nodes", kept);
	}
	memcpy(positions, m->positions, 3 * sizeof(double) * (size_t)kept);
	FM_FREE_ARRAY(m->positions, double, 3 * (size_t)m->nodeCount);
	FM_FREE_ARRAY(newIndex, int, m->nodeCount);
	m->positions = positions;
	m->nodeCount = kept;
	return fm_ok;
}

// The tets and regions in arrays of exactly their size (fmFreeTetMesh frees by the counts).
static fmResult fmTetListTake(fmTetList* list, fmTetMesh* m, const char* name, fmDiagnostic* diag)
{
	bool anyRegion = false;
	for (int t = 0; t < list->count && list->hasRegions && !anyRegion; ++t)
		anyRegion = list->regions[t] != 0.0;
	m->tetCount = list->count;
	m->tets = FM_ALLOC_ARRAY(int, 4 * (size_t)list->count);
	if (anyRegion)
	{
		m->tetAttributeCount = 1;
		m->tetAttributes = FM_ALLOC_ARRAY(double, list->count);
	}
	if (m->tets == NULL || (anyRegion && m->tetAttributes == NULL))
		return fmDiagError(diag, fm_errOutOfMemory, name, 0, 0, "out of memory for %d tets",
		                   list->count);
	memcpy(m->tets, list->tets, 4 * sizeof(int) * (size_t)list->count);
	if (anyRegion)
		memcpy(m->tetAttributes, list->regions, sizeof(double) * (size_t)list->count);
	return fm_ok;
}

fmResult fmTetList_Finish(fmTetList* list, double* positions, int nodeCount, int firstIndex,
                          const char* name, fmTetMesh* mesh, fmDiagnostic* diag)
{
	fmTetMesh m;
	memset(&m, 0, sizeof m);
	m.nodeCount = nodeCount;
	m.positions = positions;
	m.firstIndex = firstIndex;
	char skipped[256];
	fmSkipped_Format(&list->skipped, skipped, sizeof skipped);
	fmResult result = fm_ok;
	if (list->count == 0)
		result = fmDiagError(diag, fm_errEmpty, name, 0, 0,
		                     "no tetrahedra in the file%s%s%s: expected a volume mesh of tets",
		                     skipped[0] ? " (it has " : "", skipped, skipped[0] ? ")" : "");
	if (result == fm_ok)
		result = fmTetListTake(list, &m, name, diag);
	if (result == fm_ok)
		result = fmCheckDuplicateTets(&m, list->lines, name, diag);
	if (result == fm_ok && list->reducedQuadratic > 0)
		result = fmDropMidNodes(&m, name, diag);
	fmTetList_Free(list);
	if (result != fm_ok)
	{
		fmFreeTetMesh(&m);
		return result;
	}
	if (list->skipped.total > 0)
		fmDiagWarn(diag, name, 0, "only tetrahedra are read: skipped %s", skipped);
	if (list->reducedQuadratic > 0)
		fmDiagWarn(diag, name, 0,
		           "%d quadratic (10-node) tets read by their 4 corners; their mid-edge nodes are "
		           "dropped",
		           list->reducedQuadratic);
	fmWarnUnreferenced(&m, name, diag);
	*mesh = m;
	return fm_ok;
}
