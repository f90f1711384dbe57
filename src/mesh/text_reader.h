// Line tokenizer of the TetGen readers (.node, .ele, .face) and the OBJ reader, on the scanner of
// scanner.h (its cursor, line counting, number parsing and messages): a record is a line of
// whitespace-separated fields; '#' starts a comment (whole line or trailing); blank lines are
// skipped; LF and CRLF line ends are accepted, a carriage return anywhere else in a line (a file
// with CR-only line ends) is an error; a UTF-8 byte-order mark at the start is skipped. Every
// error names the file, line and column.
#pragma once

#include "mesh/scanner.h"

#include <femto/mesh.h>

#include <stddef.h>

// More fields than any TetGen record can have (index + 10 nodes + FM_MAX_ATTRIBUTES + marker).
#define FM_READER_MAX_FIELDS 80

typedef struct fmTextReader
{
	fmScan cursor;      // at the start of the next unread line
	const char* name;   // file name for diagnostics
	fmDiagnostic* diag; // may be NULL
	int line;           // 1-based line of the current record
	const char* lineStart;
	int lineLength; // bytes of the current line without its line end
	fmResult error; // why fmReader_Next returned fm_readError (also in diag when there is one)
	int fieldCount; // fields on the current record (may exceed FM_READER_MAX_FIELDS)
	const char* field[FM_READER_MAX_FIELDS];
	int fieldLength[FM_READER_MAX_FIELDS];
} fmTextReader;

// What fmReader_Next found.
typedef enum fmReadStatus
{
	fm_readRecord, // a record with at least one field
	fm_readEnd,    // end of text (only blank and comment lines were left)
	fm_readError,  // a line over FM_MAX_LINE bytes or a bare CR: r->error and the diagnostic say
} fmReadStatus;

// Start reading @p text (after a UTF-8 byte-order mark, if any); fails with fm_errSyntax naming
// the line and column of a NUL byte.
fmResult fmReader_Init(fmTextReader* r, const char* text, size_t size, const char* name,
                       fmDiagnostic* diag);

// Advance to the next record (skipping blank and comment lines) and split it into fields.
fmReadStatus fmReader_Next(fmTextReader* r);

// Bytes not yet read (used to bound header counts before allocating).
size_t fmReader_Remaining(const fmTextReader* r);

// 1-based column of field @p field; one past the line end for a missing field.
int fmReader_Column(const fmTextReader* r, int field);

// Fail unless the record has between @p minCount and @p maxCount fields; @p layout names them,
// e.g. "<point #> <x> <y> <z>".
fmResult fmReader_ExpectFields(const fmTextReader* r, int minCount, int maxCount,
                               const char* layout);

// Parse field @p field as an integer in [lo, hi]; @p what names it in messages.
fmResult fmReader_Int(const fmTextReader* r, int field, int lo, int hi, const char* what, int* out);

// Parse field @p field as a finite double (overflow, NaN and Inf are errors).
fmResult fmReader_Double(const fmTextReader* r, int field, const char* what, double* out);

// An error at field @p field of the current record (field < 0: no column).
fmResult fmReader_Error(const fmTextReader* r, fmResult result, int field, const char* format, ...)
    __attribute__((format(printf, 4, 5)));
