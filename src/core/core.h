// Internal services: allocation through the user's hooks, logging, diagnostics.
#pragma once

#include <femto/types.h>

#include <stdarg.h>

// Allocate @p size bytes (64-byte aligned) through the allocator hook. NULL on failure or
// size 0. Sizes must be computed with fmMulSize() when they come from input.
void* fmAlloc(size_t size);
// Zeroed allocation.
void* fmAllocZero(size_t size);
// Free memory from fmAlloc; @p size must be the size that was allocated.
void fmDealloc(void* memory, size_t size);

// a * b, or SIZE_MAX if it overflows (fmAlloc then fails cleanly).
size_t fmMulSize(size_t a, size_t b);

// Room for @p needed elements of @p size bytes in *@p array (its first @p count kept), grown by
// half again when short. False, and nothing changed, when memory is short.
bool fmGrowArray(void** array, int* capacity, int count, int needed, size_t size);

// Typed helpers: count elements of type T.
#define FM_ALLOC_ARRAY(T, count) ((T*)fmAlloc(fmMulSize((size_t)(count), sizeof(T))))
#define FM_ALLOC_ZERO(T, count) ((T*)fmAllocZero(fmMulSize((size_t)(count), sizeof(T))))
#define FM_FREE_ARRAY(p, T, count) fmDealloc((p), fmMulSize((size_t)(count), sizeof(T)))

// printf-style message to the log hook.
void fmLog(fmLogLevel level, const char* format, ...) __attribute__((format(printf, 2, 3)));

// Fill @p diag (may be NULL) with an error and return @p result.
fmResult fmDiagError(fmDiagnostic* diag, fmResult result, const char* file, int line, int column,
                     const char* format, ...) __attribute__((format(printf, 6, 7)));

// Record a warning in @p diag (may be NULL) and send it to the log hook.
void fmDiagWarn(fmDiagnostic* diag, const char* file, int line, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

// Reset a diagnostic to "ok, no warnings".
void fmDiagClear(fmDiagnostic* diag);

// The assert hook in use (NULL: the default, which aborts); tests save and restore it.
fmAssertFcn* fmGetAssertFcn(void);

// Magic for def structs made by fmDefault*Def().
#define FM_DEF_MAGIC 0x46454D54
