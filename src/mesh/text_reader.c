// Line tokenizer for the TetGen readers. Numbers are parsed from a bounded copy of the field
// because the text is not NUL-terminated; integers are parsed by hand to catch overflow.
#include "mesh/text_reader.h"

#include "core/core.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Line and column of byte @p offset (1-based), for the NUL byte report.
static void fmReaderLocate(const char* text, size_t offset, int* line, int* column)
{
	int l = 1;
	size_t lineStart = 0;
	for (size_t i = 0; i < offset; ++i)
	{
		if (text[i] == '\n')
		{
			++l;
			lineStart = i + 1;
		}
	}
	*line = l;
	*column = (int)(offset - lineStart + 1);
}

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
	r->text = text;
	r->size = text ? size : 0;
	r->name = name ? name : "";
	r->diag = diag;
	r->nextLine = 1;
	const char* nul = r->size ? memchr(text, 0, r->size) : NULL;
	if (nul == NULL)
		return fm_ok;
	int line, column;
	fmReaderLocate(text, (size_t)(nul - text), &line, &column);
	return fmDiagError(diag, fm_errSyntax, r->name, line, column,
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
	while (r->pos < r->size)
	{
		const char* start = r->text + r->pos;
		size_t left = r->size - r->pos;
		const char* end = memchr(start, '\n', left);
		size_t length = end ? (size_t)(end - start) : left;
		r->pos += end ? length + 1 : length;
		r->line = r->nextLine++;
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
	r->line = r->nextLine;
	r->lineStart = NULL;
	r->lineLength = 0;
	r->fieldCount = 0;
	return fm_readEnd;
}

size_t fmReader_Remaining(const fmTextReader* r)
{
	return r->size - r->pos;
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

// Copy field @p field into @p buffer as a C string; fails if it is too long to be a number.
static fmResult fmReaderCopy(const fmTextReader* r, int field, const char* what, char* buffer)
{
	int length = r->fieldLength[field];
	if (length > FM_READER_MAX_NUMBER)
		return fmReader_Error(r, fm_errSyntax, field,
		                      "%s is %d characters long: expected a number of at most %d", what,
		                      length, FM_READER_MAX_NUMBER);
	memcpy(buffer, r->field[field], (size_t)length);
	buffer[length] = 0;
	return fm_ok;
}

// Decimal integer with optional sign; *overflow when |value| exceeds INT_MAX + 1.
static bool fmParseInt(const char* s, long long* value, bool* overflow)
{
	bool negative = *s == '-';
	if (*s == '-' || *s == '+')
		++s;
	if (*s == 0)
		return false;
	long long v = 0;
	*overflow = false;
	for (; *s; ++s)
	{
		if (*s < '0' || *s > '9')
			return false;
		if (v <= (long long)INT_MAX + 1)
			v = 10 * v + (*s - '0');
		else
			*overflow = true;
	}
	*overflow = *overflow || v > (long long)INT_MAX + 1;
	*value = negative ? -v : v;
	return true;
}

fmResult fmReader_Int(const fmTextReader* r, int field, int lo, int hi, const char* what, int* out)
{
	char buffer[FM_READER_MAX_NUMBER + 1];
	fmResult copied = fmReaderCopy(r, field, what, buffer);
	if (copied != fm_ok)
		return copied;
	long long value = 0;
	bool overflow = false;
	if (!fmParseInt(buffer, &value, &overflow))
		return fmReader_Error(r, fm_errSyntax, field, "expected %s (an integer), found \"%s\"",
		                      what, buffer);
	if (overflow || value < INT_MIN || value > INT_MAX)
		return fmReader_Error(r, fm_errRange, field,
		                      "%s \"%s\" overflows an int: expected %d to %d", what, buffer, lo,
		                      hi);
	if (value < lo || value > hi)
		return fmReader_Error(r, fm_errRange, field, "%s %lld is out of range: expected %d to %d",
		                      what, value, lo, hi);
	*out = (int)value;
	return fm_ok;
}

fmResult fmReader_Double(const fmTextReader* r, int field, const char* what, double* out)
{
	char buffer[FM_READER_MAX_NUMBER + 1];
	fmResult copied = fmReaderCopy(r, field, what, buffer);
	if (copied != fm_ok)
		return copied;
	char* end = NULL;
	errno = 0;
	double value = strtod(buffer, &end);
	if (end == buffer || *end != 0)
		return fmReader_Error(r, fm_errSyntax, field, "expected %s (a number), found \"%s\"", what,
		                      buffer);
	if (isnan(value) || (isinf(value) && errno != ERANGE))
		return fmReader_Error(r, fm_errRange, field, "%s is \"%s\": expected a finite number", what,
		                      buffer);
	// ERANGE also flags underflow; a value that rounds to (sub)normal or zero is kept.
	if (errno == ERANGE && fabs(value) > DBL_MIN)
		return fmReader_Error(r, fm_errRange, field, "%s \"%s\" overflows a double", what, buffer);
	*out = value;
	return fm_ok;
}
