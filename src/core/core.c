// Hooks (allocator, assert, log), result strings and diagnostics.
#include "core/core.h"

#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static fmAllocFcn* s_allocFcn;
static fmFreeFcn* s_freeFcn;
static fmAssertFcn* s_assertFcn;
static fmLogFcn* s_logFcn;
static void* s_logContext;
// Atomic: worker threads may allocate (never in a step, but a pool starts its threads).
static _Atomic size_t s_allocatedBytes;

fmVersion fmGetVersion(void)
{
	fmVersion v = {FM_VERSION_MAJOR, FM_VERSION_MINOR, FM_VERSION_PATCH};
	return v;
}

void fmSetAllocator(fmAllocFcn* allocFcn, fmFreeFcn* freeFcn)
{
	s_allocFcn = allocFcn;
	s_freeFcn = freeFcn;
}

size_t fmGetAllocatedBytes(void)
{
	return atomic_load(&s_allocatedBytes);
}

void fmSetAssertFcn(fmAssertFcn* assertFcn)
{
	s_assertFcn = assertFcn;
}

fmAssertFcn* fmGetAssertFcn(void)
{
	return s_assertFcn;
}

void fmSetLogFcn(fmLogFcn* logFcn, void* context)
{
	s_logFcn = logFcn;
	s_logContext = context;
}

int fmInternalAssert(const char* condition, const char* fileName, int lineNumber)
{
	if (s_assertFcn)
		return s_assertFcn(condition, fileName, lineNumber);
	fprintf(stderr, "femto: assertion failed: %s at %s:%d\n", condition, fileName, lineNumber);
	abort();
}

size_t fmMulSize(size_t a, size_t b)
{
	if (a != 0 && b > SIZE_MAX / a)
		return SIZE_MAX;
	return a * b;
}

bool fmGrowArray(void** array, int* capacity, int count, int needed, size_t size)
{
	if (needed <= *capacity)
		return true;
	int grown = needed + needed / 2 + 16;
	void* fresh = fmAlloc(fmMulSize((size_t)grown, size));
	if (fresh == NULL)
		return false;
	if (count > 0)
		memcpy(fresh, *array, (size_t)count * size);
	fmDealloc(*array, fmMulSize((size_t)*capacity, size));
	*array = fresh;
	*capacity = grown;
	return true;
}

enum
{
	fm_alignment = 64
};

void* fmAlloc(size_t size)
{
	if (size == 0 || size > SIZE_MAX / 2)
		return NULL;
	size_t rounded = (size + fm_alignment - 1) & ~(size_t)(fm_alignment - 1);
	void* p = s_allocFcn ? s_allocFcn(rounded, fm_alignment) : aligned_alloc(fm_alignment, rounded);
	if (p)
		atomic_fetch_add(&s_allocatedBytes, rounded);
	return p;
}

void* fmAllocZero(size_t size)
{
	void* p = fmAlloc(size);
	if (p)
		memset(p, 0, size);
	return p;
}

void fmDealloc(void* memory, size_t size)
{
	if (memory == NULL)
		return;
	size_t rounded = (size + fm_alignment - 1) & ~(size_t)(fm_alignment - 1);
	atomic_fetch_sub(&s_allocatedBytes, rounded);
	if (s_freeFcn)
		s_freeFcn(memory, rounded);
	else
		free(memory);
}

void fmLog(fmLogLevel level, const char* format, ...)
{
	if (s_logFcn == NULL)
		return;
	char buffer[1024];
	va_list args;
	va_start(args, format);
	vsnprintf(buffer, sizeof buffer, format, args);
	va_end(args);
	s_logFcn(level, buffer, s_logContext);
}

#define FM_RESULT_NAME(name, message) #name,
#define FM_RESULT_MESSAGE(name, message) message,
static const char* s_resultNames[] = {FM_RESULT_LIST(FM_RESULT_NAME)};
static const char* s_resultMessages[] = {FM_RESULT_LIST(FM_RESULT_MESSAGE)};

const char* fmResultName(fmResult result)
{
	if ((unsigned)result >= (unsigned)fm_resultCount)
		return "fm_unknownResult";
	return s_resultNames[result];
}

const char* fmResultMessage(fmResult result)
{
	if ((unsigned)result >= (unsigned)fm_resultCount)
		return "unknown result";
	return s_resultMessages[result];
}

void fmDiagClear(fmDiagnostic* diag)
{
	if (diag)
		memset(diag, 0, sizeof *diag);
}

fmResult fmDiagError(fmDiagnostic* diag, fmResult result, const char* file, int line, int column,
                     const char* format, ...)
{
	if (diag == NULL)
		return result;
	diag->result = result;
	snprintf(diag->file, sizeof diag->file, "%s", file ? file : "");
	diag->line = line;
	diag->column = column;
	va_list args;
	va_start(args, format);
	vsnprintf(diag->message, sizeof diag->message, format, args);
	va_end(args);
	return result;
}

void fmDiagWarn(fmDiagnostic* diag, const char* file, int line, const char* format, ...)
{
	char text[400];
	va_list args;
	va_start(args, format);
	vsnprintf(text, sizeof text, format, args);
	va_end(args);
	char located[512];
	if (file && file[0] && line > 0)
		snprintf(located, sizeof located, "%s:%d: warning: %s", file, line, text);
	else if (file && file[0])
		snprintf(located, sizeof located, "%s: warning: %s", file, text);
	else
		snprintf(located, sizeof located, "warning: %s", text);
	fmLog(fm_logWarning, "%s", located);
	if (diag == NULL)
		return;
	if (diag->warningCount == 0)
		snprintf(diag->warning, sizeof diag->warning, "%s", located);
	diag->warningCount += 1;
}

const char* fmDiagnostic_Format(const fmDiagnostic* diag, char* buffer, size_t size)
{
	if (buffer == NULL || size == 0)
		return buffer;
	if (diag == NULL)
	{
		buffer[0] = 0;
		return buffer;
	}
	const char* msg = diag->message[0] ? diag->message : fmResultMessage(diag->result);
	if (diag->file[0] && diag->line > 0 && diag->column > 0)
		snprintf(buffer, size, "%s:%d:%d: %s", diag->file, diag->line, diag->column, msg);
	else if (diag->file[0] && diag->line > 0)
		snprintf(buffer, size, "%s:%d: %s", diag->file, diag->line, msg);
	else if (diag->file[0])
		snprintf(buffer, size, "%s: %s", diag->file, msg);
	else
		snprintf(buffer, size, "%s", msg);
	return buffer;
}
