// Line tokenizer for the TetGen and OBJ readers (text_reader.h): lines from the scanner's cursor,
// fields parsed by the scanner's number parsers.
#include "mesh/text_reader.h"

#include "core/core.h"

#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

fmResult fmReader_Init(fmTextReader* r, const char* text, size_t size, const char* name,
                       fmDiagnostic* diag)
{
	memset(r, 0, sizeof *r);
	// Editors on Windows may start a UTF-8 file with the byte-order mark EF BB BF; it is not data.
	if (text != NULL && size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0)
	{
		text += 3;
		size -= 3;
	}
	r->name = name ? name : "";
	r->diag = diag;
	fmScan_Init(&r->cursor, text, size, r->name, diag);
	const char* nul = r->cursor.size ? memchr(text, 0, r->cursor.size) : NULL;
	if (nul == NULL)
		return fm_ok;
	fmScan at = r->cursor;
	fmScan_Advance(&at, (size_t)(nul - text));
	return fmScan_ErrorHere(&at, fm_errSyntax,
	                        "NUL byte in the text: expected a TetGen text file, not binary data");
}

static bool fmIsSpace(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Split the current line into fields, stopping at a '#' comment.
static void fmReaderSplit(fmTextReader* r)
{
	const char* s = r->lineStart;
	int n = r->lineLength;
	r->fieldCount = 0;
	int i = 0;
	while (i < n && s[i] != '#')
	{
		if (fmIsSpace(s[i]))
		{
			++i;
			continue;
		}
		int start = i;
		while (i < n && !fmIsSpace(s[i]) && s[i] != '#')
			++i;
		if (r->fieldCount < FM_READER_MAX_FIELDS)
		{
			r->field[r->fieldCount] = s + start;
			r->fieldLength[r->fieldCount] = i - start;
		}
		r->fieldCount += 1;
	}
}

fmReadStatus fmReader_Next(fmTextReader* r)
{
	const unsigned char* line;
	size_t length;
	for (r->line = r->cursor.line; fmScan_NextLine(&r->cursor, &line, &length);
	     r->line = r->cursor.line)
	{
		const char* start = (const char*)line;
		if (length > 0 && start[length - 1] == '\r')
			--length;
		// A CR that does not end the line: CR-only line ends (classic Mac OS) would otherwise read
		// as one long line of spaces and fail as "extra field" or "line too long".
		const char* cr = memchr(start, '\r', length < FM_MAX_LINE + 1 ? length : FM_MAX_LINE + 1);
		if (cr != NULL)
		{
			r->error = fmDiagError(r->diag, fm_errSyntax, r->name, r->line, (int)(cr - start) + 1,
			                       "carriage return inside a line: the file has CR-only (old Mac) "
			                       "line ends; expected LF or CRLF line ends");
			return fm_readError;
		}
		if (length > FM_MAX_LINE)
		{
			r->error = fmDiagError(r->diag, fm_errLimit, r->name, r->line, FM_MAX_LINE + 1,
			                       "line is %zu bytes long: expected at most %d bytes per line",
			                       length, FM_MAX_LINE);
			return fm_readError;
		}
		r->lineStart = start;
		r->lineLength = (int)length;
		fmReaderSplit(r);
		if (r->fieldCount > 0)
			return fm_readRecord;
	}
	// The end is on the line after the last one, whether or not that ends with a LF.
	r->line = r->cursor.line + (r->cursor.lineStart < r->cursor.size);
	r->lineStart = NULL;
	r->lineLength = 0;
	r->fieldCount = 0;
	return fm_readEnd;
}

size_t fmReader_Remaining(const fmTextReader* r)
{
	return fmScan_Remaining(&r->cursor);
}

int fmReader_Column(const fmTextReader* r, int field)
{
	if (field < 0)
		return 0;
	if (field < r->fieldCount && field < FM_READER_MAX_FIELDS)
		return (int)(r->field[field] - r->lineStart) + 1;
	// A missing field: just after the last one (before any trailing comment).
	int last = r->fieldCount < FM_READER_MAX_FIELDS ? r->fieldCount - 1 : FM_READER_MAX_FIELDS - 1;
	if (last < 0)
		return 1;
	return (int)(r->field[last] + r->fieldLength[last] - r->lineStart) + 1;
}

fmResult fmReader_Error(const fmTextReader* r, fmResult result, int field, const char* format, ...)
{
	char text[sizeof r->diag->message];
	va_list args;
	va_start(args, format);
	vsnprintf(text, sizeof text, format, args);
	va_end(args);
	return fmDiagError(r->diag, result, r->name, r->line, fmReader_Column(r, field), "%s", text);
}

fmResult fmReader_ExpectFields(const fmTextReader* r, int minCount, int maxCount,
                               const char* layout)
{
	int n = r->fieldCount;
	if (n >= minCount && n <= maxCount)
		return fm_ok;
	char count[32];
	if (minCount == maxCount)
		snprintf(count, sizeof count, "%d", minCount);
	else
		snprintf(count, sizeof count, "%d to %d", minCount, maxCount);
	if (n < minCount)
		return fmReader_Error(r, fm_errSyntax, n,
		                      "missing field: expected %s fields (%s), found %d", count, layout, n);
	int extra = maxCount < FM_READER_MAX_FIELDS ? maxCount : FM_READER_MAX_FIELDS - 1;
	int shown = r->fieldLength[extra] < 40 ? r->fieldLength[extra] : 40;
	return fmReader_Error(r, fm_errSyntax, extra,
	                      "extra field \"%.*s\": expected %s fields (%s), found %d", shown,
	                      r->field[extra], count, layout, n);
}

// Field @p field as the scanner's last token, for its number parsers and messages.
static fmScan fmReaderField(const fmTextReader* r, int field)
{
	fmScan s = r->cursor;
	s.token = (const unsigned char*)r->field[field];
	s.tokenLength = (size_t)r->fieldLength[field];
	s.tokenLine = r->line;
	s.tokenColumn = fmReader_Column(r, field);
	return s;
}

fmResult fmReader_Int(const fmTextReader* r, int field, int lo, int hi, const char* what, int* out)
{
	fmScan s = fmReaderField(r, field);
	char buffer[FM_SCAN_MAX_NUMBER + 1];
	long long value = 0;
	bool overflow = false;
	fmResult result = fmScan_ParseInteger(&s, what, buffer, &value, &overflow);
	if (result != fm_ok)
		return result;
	if (overflow || value < INT_MIN || value > INT_MAX)
		return fmScan_Error(&s, fm_errRange, "%s \"%s\" overflows an int: expected %d to %d", what,
		                    buffer, lo, hi);
	if (value < lo || value > hi)
		return fmScan_Error(&s, fm_errRange, "%s %lld is out of range: expected %d to %d", what,
		                    value, lo, hi);
	*out = (int)value;
	return fm_ok;
}

fmResult fmReader_Double(const fmTextReader* r, int field, const char* what, double* out)
{
	fmScan s = fmReaderField(r, field);
	return fmScan_ParseDouble(&s, what, out);
}
