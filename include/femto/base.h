/// @file base.h
/// femto base: version, export macro, replaceable hooks (allocator, assert, log).
/// The library never prints and never exits: everything it has to say goes through these hooks
/// or through result codes.
#pragma once

#include <stddef.h>
#include <stdint.h>

#define FM_VERSION_MAJOR 0
#define FM_VERSION_MINOR 1
#define FM_VERSION_PATCH 0

#if defined(_WIN32) && defined(FEMTO_SHARED) && defined(FEMTO_EXPORTS)
#define FM_API __declspec(dllexport)
#elif defined(_WIN32) && defined(FEMTO_SHARED)
#define FM_API __declspec(dllimport)
#elif defined(FEMTO_SHARED)
#define FM_API __attribute__((visibility("default")))
#else
#define FM_API
#endif

#ifdef __cplusplus
#define FM_C_BEGIN extern "C" {
#define FM_C_END }
#else
#define FM_C_BEGIN
#define FM_C_END
#endif

FM_C_BEGIN

/// Version of the library, as compiled.
typedef struct fmVersion
{
	int major; ///< incompatible API changes
	int minor; ///< features added compatibly
	int patch; ///< fixes
} fmVersion;

/// The version of the linked library.
FM_API fmVersion fmGetVersion(void);

/// Allocation hook. Must return memory aligned to @p alignment (a power of two, at most 64),
/// or NULL on failure; femto reports fm_errOutOfMemory and never dereferences NULL.
typedef void* fmAllocFcn(size_t size, size_t alignment);

/// Free hook; receives the size that was allocated.
typedef void fmFreeFcn(void* memory, size_t size);

/// Replace the allocator. Pass NULL for both to restore the default (aligned malloc).
/// Call before creating any world or loading any mesh. With fmWorldDef.workerCount above 1 a
/// step may call the hooks from several of the world's workers at once (bodies stepping side by
/// side grow their own buffers): they must be thread-safe, as malloc is.
FM_API void fmSetAllocator(fmAllocFcn* allocFcn, fmFreeFcn* freeFcn);

/// Bytes currently allocated through the femto allocator (leak checks, budgets).
FM_API size_t fmGetAllocatedBytes(void);

/// Assert hook for programmer errors (stale ids, NaN in a def). Return non-zero to break/abort.
typedef int fmAssertFcn(const char* condition, const char* fileName, int lineNumber);

/// Replace the assert hook. NULL restores the default, which aborts.
FM_API void fmSetAssertFcn(fmAssertFcn* assertFcn);

/// Severity of a log message.
typedef enum fmLogLevel
{
	fm_logInfo,	   ///< progress, statistics
	fm_logWarning, ///< input accepted with a doubt, simulation health
	fm_logError,   ///< something failed; the call also returns an error code
} fmLogLevel;

/// Log hook. @p context is the pointer given to fmSetLogFcn.
typedef void fmLogFcn(fmLogLevel level, const char* message, void* context);

/// Replace the log hook. NULL (the default) discards all messages: the library never prints.
FM_API void fmSetLogFcn(fmLogFcn* logFcn, void* context);

/// Internal: called by FM_ASSERT.
FM_API int fmInternalAssert(const char* condition, const char* fileName, int lineNumber);

#if !defined(NDEBUG) || defined(FEMTO_ENABLE_ASSERT)
/// Assert for programmer errors, routed through the assert hook.
#define FM_ASSERT(condition)                                                                       \
	do                                                                                             \
	{                                                                                              \
		if (!(condition))                                                                          \
			(void)fmInternalAssert(#condition, __FILE__, (int)__LINE__);                           \
	} while (0)
#else
#define FM_ASSERT(condition) ((void)0)
#endif

FM_C_END
