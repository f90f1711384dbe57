// The scanner of the mesh text readers (scanner.h). Numbers are parsed from a bounded copy of the
// token because the data is not NUL-terminated; integers are parsed by hand to catch overflow.
#include "mesh/scanner.h"

#include "core/core.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
	const unsigned char* start;
	size_t length;
	fmScan_NextLine(s, &start, &length);
}

bool fmScan_NextLine(fmScan* s, const unsigned char** start, size_t* length)
{
	if (s->pos >= s->size)
		return false;
	*start = s->data + s->pos;
	const unsigned char* nl = memchr(*start, '\n', s->size - s->pos);
	*length = nl ? (size_t)(nl - *start) : s->size - s->pos;
	s->pos += *length;
	if (nl)
	{
		s->pos += 1;
		s->line += s->line < INT_MAX;
		s->lineStart = s->pos;
	}
	return true;
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

fmResult fmScan_ParseInteger(const fmScan* s, const char* what, char* buffer, long long* value,
                             bool* overflow)
{
	fmResult result = fmScanCopyNumber(s, what, buffer);
	if (result != fm_ok)
		return result;
	const char* p = buffer;
	bool negative = *p == '-';
	if (*p == '-' || *p == '+')
		++p;
	bool digits = *p != 0;
	unsigned long long v = 0;
	*overflow = false;
	for (; *p && digits; ++p)
	{
		if (*p < '0' || *p > '9')
			digits = false;
		else if (v > (ULLONG_MAX - 9) / 10)
			*overflow = true;
		else
			v = 10 * v + (unsigned long long)(*p - '0');
	}
	if (!digits)
		return fmScan_Error(s, fm_errSyntax, "expected %s (an integer), found \"%s\"", what,
		                    buffer);
	*overflow = *overflow || v > (unsigned long long)LLONG_MAX;
	*value = *overflow ? 0 : negative ? -(long long)v : (long long)v;
	return fm_ok;
}

fmResult fmScan_Int64(fmScan* s, const char* what, long long lo, long long hi, long long* out)
{
	char what2[96];
	snprintf(what2, sizeof what2, "%s (an integer)", what);
	fmResult result = fmScan_Expect(s, what2);
	char buffer[FM_SCAN_MAX_NUMBER + 1];
	long long value = 0;
	bool overflow = false;
	if (result == fm_ok)
		result = fmScan_ParseInteger(s, what, buffer, &value, &overflow);
	if (result != fm_ok)
		return result;
	if (overflow)
		return fmScan_Error(s, fm_errRange, "%s \"%s\" is too large: expected %lld to %lld", what,
		                    buffer, lo, hi);
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
	return result == fm_ok ? fmScan_ParseDouble(s, what, out) : result;
}

fmResult fmScan_ParseDouble(const fmScan* s, const char* what, double* out)
{
	char buffer[FM_SCAN_MAX_NUMBER + 1];
	fmResult result = fmScanCopyNumber(s, what, buffer);
	if (result != fm_ok)
		return result;
	char* end = NULL;
	errno = 0;
	double value = strtod(buffer, &end);
	if (end == buffer || *end != 0)
		return fmScan_Error(s, fm_errSyntax, "expected %s (a number), found \"%s\"", what, buffer);
	if (isnan(value) || (isinf(value) && errno != ERANGE))
		return fmScan_Error(s, fm_errRange, "%s is \"%s\": expected a finite number", what, buffer);
	// ERANGE also flags underflow; a value that rounds to (sub)normal or zero is kept.
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
