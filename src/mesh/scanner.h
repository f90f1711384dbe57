// The scanner of every mesh text reader (TetGen and OBJ through text_reader.h; Gmsh, VTK and
// Medit through mesh_reader.h): a cursor over a file held in memory (not NUL-terminated, may mix
// text and binary blocks) that tracks line and column, whitespace-separated tokens, numbers
// parsed with overflow checks, and errors located at a token or the cursor.
#pragma once

#include <femto/mesh.h>

#include <stdbool.h>
#include <stddef.h>

// Longest number token accepted (digits of a double written with %.17g need 24).
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

// The line at the current position: its first byte and its length without the LF that ends it
// (a CR before the LF is kept); moves past it. False at the end of the data.
bool fmScan_NextLine(fmScan* s, const unsigned char** start, size_t* length);

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

// The last token as a decimal integer with an optional sign, copied into @p buffer (at least
// FM_SCAN_MAX_NUMBER + 1 bytes, for messages): fm_errSyntax when it is too long or not an
// integer; *overflow when its magnitude exceeds LLONG_MAX (*value is then not meaningful).
fmResult fmScan_ParseInteger(const fmScan* s, const char* what, char* buffer, long long* value,
                             bool* overflow);

// The last token as a finite double: fm_errSyntax when it is not a number, fm_errRange for NaN,
// infinity or overflow (an underflow to a subnormal or zero is kept).
fmResult fmScan_ParseDouble(const fmScan* s, const char* what, double* out);

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
