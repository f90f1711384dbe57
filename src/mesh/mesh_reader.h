// What the Gmsh, VTK and Medit readers share (docs/mesh-format.md): a scanner over a file held in
// memory that mixes text and binary blocks, with located errors; binary loads in either byte
// order; a map from a file's node tags to femto's dense node numbers; and a growing list of tets
// that becomes an fmTetMesh with exactly sized arrays. Every count is checked against the limits
// of mesh.h and against the bytes left before anything of its size is allocated.
#pragma once

#include <femto/mesh.h>

#include <stddef.h>
#include <stdint.h>

// Longest number token accepted (as the TetGen reader).
#define FM_SCAN_MAX_NUMBER 127

typedef struct fmScan
{
	const unsigned char* data; // not NUL-terminated; may hold binary blocks
	size_t size;
	size_t pos;         // next unread byte
	const char* name;   // file name for diagnostics
	fmDiagnostic* diag; // may be NULL
	int line;           // 1-based line of pos (binary bytes count their line ends too)
	size_t lineStart;   // offset of the start of that line
	bool hashComments;  // '#' starts a comment that runs to the end of the line (Medit)
	// The last token read, where messages point.
	const unsigned char* token;
	size_t tokenLength;
	int tokenLine;
	int tokenColumn;
} fmScan;

void fmScan_Init(fmScan* s, const void* data, size_t size, const char* name, fmDiagnostic* diag);

// Move over @p count bytes (at most those left), counting line ends.
void fmScan_Advance(fmScan* s, size_t count);

// Skip spaces, tabs, line ends (and comments when hashComments is set).
void fmScan_SkipSpace(fmScan* s);

// Move to the start of the next line (or the end).
void fmScan_SkipLine(fmScan* s);

// The next whitespace-separated token into s->token; false at the end of the data.
bool fmScan_Next(fmScan* s);

// fmScan_Next, or an fm_errSyntax "the file ends: expected @p what" when nothing is left.
fmResult fmScan_Expect(fmScan* s, const char* what);

// The last token equals @p word (exactly, or ignoring ASCII case).
bool fmScan_Is(const fmScan* s, const char* word);
bool fmScan_IsNoCase(const fmScan* s, const char* word);

// Read the next token as an integer in [lo, hi]; @p what names it in messages.
fmResult fmScan_Int64(fmScan* s, const char* what, long long lo, long long hi, long long* out);
fmResult fmScan_Int(fmScan* s, const char* what, int lo, int hi, int* out);

// Read the next token as a finite double.
fmResult fmScan_Double(fmScan* s, const char* what, double* out);

// Read an expected word (e.g. "$EndNodes"); the message names it and what was found.
fmResult fmScan_Word(fmScan* s, const char* word, bool ignoreCase);

// An error at the last token (line and column).
fmResult fmScan_Error(const fmScan* s, fmResult result, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

// An error at the current position (line and column of s->pos).
fmResult fmScan_ErrorHere(const fmScan* s, fmResult result, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

// Take @p count raw bytes at the current position; an error naming the byte offset and @p what
// when fewer are left.
fmResult fmScan_Bytes(fmScan* s, size_t count, const char* what, const unsigned char** bytes);

// Bytes not yet read.
size_t fmScan_Remaining(const fmScan* s);

// Refuse a declared @p count of @p what above @p limit, or one that the @p minBytes bytes each
// that every item needs cannot fit in the rest of the data (so a 100-byte file cannot ask for
// gigabytes). The error points at the last token (the count).
fmResult fmScan_CheckCount(const fmScan* s, long long count, long long limit, size_t minBytes,
                           const char* what);

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
