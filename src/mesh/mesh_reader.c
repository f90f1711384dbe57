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

// ---- the scanner ------------------------------------------------------------------------------

void fmScan_Init(fmScan* s, const void* data, size_t size, const char* name, fmDiagnostic* diag)
{
	memset(s, 0, sizeof *s);
	s->data = data;
	s->size = data ? size : 0;
	s->name = name ? name : "";
	s->diag = diag;
	s->line = 1;
}

void fmScan_Advance(fmScan* s, size_t count)
{
	size_t end = count < s->size - s->pos ? s->pos + count : s->size;
	const unsigned char* p = s->data + s->pos;
	const unsigned char* stop = s->data + end;
	if (end - s->pos <= 16)
	{
		// Binary values (4 or 8 bytes) one at a time: a plain loop beats memchr's setup.
		for (; p < stop; ++p)
			if (*p == '\n')
			{
				s->line += s->line < INT_MAX;
				s->lineStart = (size_t)(p - s->data) + 1;
			}
		s->pos = end;
		return;
	}
	while (p < stop)
	{
		const unsigned char* nl = memchr(p, '\n', (size_t)(stop - p));
		if (nl == NULL)
			break;
		s->line += s->line < INT_MAX;
		s->lineStart = (size_t)(nl - s->data) + 1;
		p = nl + 1;
	}
	s->pos = end;
}

static bool fmScanIsSpace(unsigned char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

void fmScan_SkipLine(fmScan* s)
{
	const unsigned char* nl = memchr(s->data + s->pos, '\n', s->size - s->pos);
	fmScan_Advance(s, nl ? (size_t)(nl - (s->data + s->pos)) + 1 : s->size - s->pos);
}

void fmScan_SkipSpace(fmScan* s)
{
	while (s->pos < s->size)
	{
		unsigned char c = s->data[s->pos];
		if (c == '\n')
		{
			s->pos += 1;
			s->line += s->line < INT_MAX;
			s->lineStart = s->pos;
		}
		else if (fmScanIsSpace(c))
			s->pos += 1;
		else if (c == '#' && s->hashComments)
			fmScan_SkipLine(s);
		else
			return;
	}
}

bool fmScan_Next(fmScan* s)
{
	fmScan_SkipSpace(s);
	if (s->pos >= s->size)
	{
		s->token = s->data + s->size;
		s->tokenLength = 0;
		s->tokenLine = s->line;
		s->tokenColumn = (int)(s->pos - s->lineStart) + 1;
		return false;
	}
	size_t start = s->pos;
	while (s->pos < s->size && !fmScanIsSpace(s->data[s->pos]) &&
	       !(s->hashComments && s->data[s->pos] == '#'))
		s->pos += 1;
	s->token = s->data + start;
	s->tokenLength = s->pos - start;
	s->tokenLine = s->line;
	size_t column = start - s->lineStart + 1;
	s->tokenColumn = column < INT_MAX ? (int)column : INT_MAX;
	return true;
}

fmResult fmScan_Expect(fmScan* s, const char* what)
{
	if (fmScan_Next(s))
		return fm_ok;
	return fmScan_Error(s, fm_errSyntax, "the file ends: expected %s", what);
}

bool fmScan_Is(const fmScan* s, const char* word)
{
	size_t n = strlen(word);
	return s->tokenLength == n && memcmp(s->token, word, n) == 0;
}

static unsigned char fmLower(unsigned char c)
{
	return c >= 'A' && c <= 'Z' ? (unsigned char)(c - 'A' + 'a') : c;
}

bool fmScan_IsNoCase(const fmScan* s, const char* word)
{
	size_t n = strlen(word);
	if (s->tokenLength != n)
		return false;
	for (size_t k = 0; k < n; ++k)
		if (fmLower(s->token[k]) != fmLower((unsigned char)word[k]))
			return false;
	return true;
}

// The last token for a message: at most 40 bytes, non-printable bytes as '?'.
static void fmScanShown(const fmScan* s, char* text, size_t size)
{
	size_t n = s->tokenLength < 40 ? s->tokenLength : 40;
	if (n >= size)
		n = size - 1;
	for (size_t k = 0; k < n; ++k)
	{
		unsigned char c = s->token[k];
		text[k] = c >= 32 && c < 127 ? (char)c : '?';
	}
	text[n] = 0;
	if (s->tokenLength > n && size > n + 4)
		memcpy(text + n, "...", 4);
}

static fmResult fmScanVError(const fmScan* s, fmResult result, int line, int column,
                             const char* format, va_list args)
{
	char text[sizeof s->diag->message];
	vsnprintf(text, sizeof text, format, args);
	return fmDiagError(s->diag, result, s->name, line, column, "%s", text);
}

fmResult fmScan_Error(const fmScan* s, fmResult result, const char* format, ...)
{
	va_list args;
	va_start(args, format);
	fmResult r = fmScanVError(s, result, s->tokenLine ? s->tokenLine : s->line, s->tokenColumn,
	                          format, args);
	va_end(args);
	return r;
}

fmResult fmScan_ErrorHere(const fmScan* s, fmResult result, const char* format, ...)
{
	va_list args;
	va_start(args, format);
	size_t column = s->pos - s->lineStart + 1;
	fmResult r =
	    fmScanVError(s, result, s->line, column < INT_MAX ? (int)column : INT_MAX, format, args);
	va_end(args);
	return r;
}

fmResult fmScan_Word(fmScan* s, const char* word, bool ignoreCase)
{
	if (!fmScan_Next(s))
		return fmScan_Error(s, fm_errSyntax, "the file ends: expected \"%s\"", word);
	if (ignoreCase ? fmScan_IsNoCase(s, word) : fmScan_Is(s, word))
		return fm_ok;
	char shown[48];
	fmScanShown(s, shown, sizeof shown);
	return fmScan_Error(s, fm_errSyntax, "expected \"%s\", found \"%s\"", word, shown);
}

// Copy the last token into @p buffer as a C string, or fail when it is too long for a number.
static fmResult fmScanCopyNumber(const fmScan* s, const char* what, char* buffer)
{
	if (s->tokenLength > FM_SCAN_MAX_NUMBER)
		return fmScan_Error(s, fm_errSyntax,
		                    "%s is %zu characters long: expected a number of at most %d", what,
		                    s->tokenLength, FM_SCAN_MAX_NUMBER);
	memcpy(buffer, s->token, s->tokenLength);
	buffer[s->tokenLength] = 0;
	return fm_ok;
}

fmResult fmScan_Int64(fmScan* s, const char* what, long long lo, long long hi, long long* out)
{
	char what2[96];
	snprintf(what2, sizeof what2, "%s (an integer)", what);
	fmResult result = fmScan_Expect(s, what2);
	char buffer[FM_SCAN_MAX_NUMBER + 1];
	if (result == fm_ok)
		result = fmScanCopyNumber(s, what, buffer);
	if (result != fm_ok)
		return result;
	const char* p = buffer;
	bool negative = *p == '-';
	if (*p == '-' || *p == '+')
		++p;
	bool digits = *p != 0, overflow = false;
	unsigned long long v = 0;
	for (; *p && digits; ++p)
	{
		if (*p < '0' || *p > '9')
			digits = false;
		else if (v > (ULLONG_MAX - 9) / 10)
			overflow = true;
		else
			v = 10 * v + (unsigned long long)(*p - '0');
	}
	if (!digits)
		return fmScan_Error(s, fm_errSyntax, "expected %s (an integer), found \"%s\"", what,
		                    buffer);
	if (overflow || v > (unsigned long long)LLONG_MAX)
		return fmScan_Error(s, fm_errRange, "%s \"%s\" is too large: expected %lld to %lld", what,
		                    buffer, lo, hi);
	long long value = negative ? -(long long)v : (long long)v;
	if (value < lo || value > hi)
		return fmScan_Error(s, fm_errRange, "%s %lld is out of range: expected %lld to %lld", what,
		                    value, lo, hi);
	*out = value;
	return fm_ok;
}

fmResult fmScan_Int(fmScan* s, const char* what, int lo, int hi, int* out)
{
	long long value = 0;
	fmResult result = fmScan_Int64(s, what, lo, hi, &value);
	if (result == fm_ok)
		*out = (int)value;
	return result;
}

fmResult fmScan_Double(fmScan* s, const char* what, double* out)
{
	char what2[96];
	snprintf(what2, sizeof what2, "%s (a number)", what);
	fmResult result = fmScan_Expect(s, what2);
	char buffer[FM_SCAN_MAX_NUMBER + 1];
	if (result == fm_ok)
		result = fmScanCopyNumber(s, what, buffer);
	if (result != fm_ok)
		return result;
	char* end = NULL;
	errno = 0;
	double value = strtod(buffer, &end);
	if (end == buffer || *end != 0)
		return fmScan_Error(s, fm_errSyntax, "expected %s (a number), found \"%s\"", what, buffer);
	if (isnan(value) || (isinf(value) && errno != ERANGE))
		return fmScan_Error(s, fm_errRange, "%s is \"%s\": expected a finite number", what, buffer);
	if (errno == ERANGE && fabs(value) > DBL_MIN)
		return fmScan_Error(s, fm_errRange, "%s \"%s\" overflows a double", what, buffer);
	*out = value;
	return fm_ok;
}

fmResult fmScan_Bytes(fmScan* s, size_t count, const char* what, const unsigned char** bytes)
{
	if (count > s->size - s->pos)
		return fmScan_ErrorHere(s, fm_errCount,
		                        "the file ends at byte %zu, %zu bytes into %s: expected %zu bytes",
		                        s->size, s->size - s->pos, what, count);
	*bytes = s->data + s->pos;
	fmScan_Advance(s, count);
	return fm_ok;
}

size_t fmScan_Remaining(const fmScan* s)
{
	return s->size - s->pos;
}

fmResult fmScan_CheckCount(const fmScan* s, long long count, long long limit, size_t minBytes,
                           const char* what)
{
	if (count > limit)
		return fmScan_Error(s, fm_errLimit, "%lld %s exceed the limit of %lld", count, what, limit);
	unsigned long long need = (unsigned long long)count * (unsigned long long)minBytes;
	unsigned long long left = fmScan_Remaining(s);
	// In binary data (the scan has moved past the last text token) the count is located by its
	// position, not by a stale token.
	bool binary = s->token == NULL || s->data + s->pos != s->token + s->tokenLength;
	if (need > left && binary)
		return fmScan_ErrorHere(s, fm_errCount,
		                        "%lld %s declared before byte %zu but only %llu bytes follow: "
		                        "expected at least %llu bytes (%zu for each)",
		                        count, what, s->pos, left, need, minBytes);
	if (need > left)
		return fmScan_Error(s, fm_errCount,
		                    "%lld %s declared but only %llu bytes follow: expected at least %llu "
		                    "bytes (%zu for each)",
		                    count, what, left, need, minBytes);
	return fm_ok;
}

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
