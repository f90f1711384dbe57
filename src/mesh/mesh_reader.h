// What the Gmsh, VTK and Medit readers share (docs/mesh-format.md) beside the scanner of
// scanner.h: binary loads in either byte order; a map from a file's node tags to femto's dense
// node numbers; and a growing list of tets that becomes an fmTetMesh with exactly sized arrays. Every count is checked against the limits
// of mesh.h and against the bytes left before anything of its size is allocated.
#pragma once

#include "mesh/scanner.h"

#include <femto/mesh.h>

#include <stddef.h>
#include <stdint.h>

// Binary loads of @p bytes; @p swap reverses the byte order.
uint32_t fmLoadU32(const unsigned char* bytes, bool swap);
uint64_t fmLoadU64(const unsigned char* bytes, bool swap);
double fmLoadF64(const unsigned char* bytes, bool swap);
float fmLoadF32(const unsigned char* bytes, bool swap);
// True when this machine stores integers little-endian.
bool fmHostIsLittleEndian(void);

// A file's node tags (any 64-bit values, in any order) mapped to dense indices 0..count-1.
typedef struct fmTagMap
{
	long long* tags; // sorted
	int* index;      // index[k] is the node of tags[k]
	int count;
	bool dense; // tags were first, first+1, ...: lookups are subtractions
	long long first;
} fmTagMap;

// Build the map of @p count tags (tags[i] is node i). fm_errIndex naming the repeated tag when a
// tag appears twice. @p tags is not kept.
fmResult fmTagMap_Build(fmTagMap* map, const long long* tags, int count, const char* name,
                        fmDiagnostic* diag);
// The node of @p tag, or -1.
int fmTagMap_Find(const fmTagMap* map, long long tag);
void fmTagMap_Free(fmTagMap* map);

// Elements of other kinds than tets, counted by name for one note.
#define FM_SKIP_KINDS 8
typedef struct fmSkipped
{
	const char* kind[FM_SKIP_KINDS];
	long long count[FM_SKIP_KINDS];
	long long other; // kinds beyond FM_SKIP_KINDS
	long long total;
} fmSkipped;

void fmSkipped_Add(fmSkipped* skipped, const char* kind, long long count);
// "12 triangles, 3 lines" into @p text.
void fmSkipped_Format(const fmSkipped* skipped, char* text, size_t size);

// Tets as they are read: node indices already checked against the node count.
typedef struct fmTetList
{
	int* tets;       // 4 per tet
	int* lines;      // line of each tet (0 in binary data), for duplicate reports
	double* regions; // region of each tet, or NULL while the format has none
	int count;
	int capacity;
	int limit; // most tets the file may declare (its element count, capped at FM_MAX_TETS)
	bool hasRegions;
	int reducedQuadratic; // 10-node tets read by their four corners
	fmSkipped skipped;
} fmTetList;

// Start a list for at most @p limit tets (checked by the caller against the bytes left).
void fmTetList_Init(fmTetList* list, long long limit, bool hasRegions);
// Add a tet (0-based nodes) read at @p line with @p region. fm_errOutOfMemory or fm_errLimit.
fmResult fmTetList_Add(fmTetList* list, const int nodes[4], int line, double region,
                       const fmScan* s);
void fmTetList_Free(fmTetList* list);

// Turn @p nodeCount nodes at @p positions (taken over: freed on failure) and the list (freed)
// into @p mesh: no tets is fm_errEmpty naming what was skipped; a tet on the same nodes as an
// earlier one is fm_errIndex; nodes only mid-edge nodes of quadratic tets used are dropped;
// the skipped kinds and unused nodes are warned about. @p firstIndex is kept for export.
fmResult fmTetList_Finish(fmTetList* list, double* positions, int nodeCount, int firstIndex,
                          const char* name, fmTetMesh* mesh, fmDiagnostic* diag);
