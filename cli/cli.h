// Shared pieces of the femto tool: exit codes, messages, argument parsing, files, clocks.
#pragma once

#include <femto/femto.h>

#include <stdbool.h>
#include <stddef.h>

/// Exit codes of every command (docs/cli.md).
enum
{
	cli_exitOk = 0,    ///< success
	cli_exitInput = 1, ///< bad file or scene, I/O error, numerical failure
	cli_exitUsage = 2, ///< unknown command or option, bad option value
};

/// Longest path the tool handles.
#define CLI_MAX_PATH 1024

/// Most frames one run simulates (the scene's "frames", --frames, --seconds rounded up).
#define CLI_MAX_FRAMES 100000000

/// Scene and mesh files larger than this are refused before reading (64 MiB).
#define CLI_MAX_FILE_BYTES ((size_t)64 << 20)

/// Print "femto: <message>" to stderr.
void cliError(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// Print "femto: warning: <message>" to stderr.
void cliWarn(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// Print a usage error for @p command ("femto COMMAND --help" hint) and return cli_exitUsage.
int cliUsageError(const char* command, const char* format, ...)
    __attribute__((format(printf, 2, 3)));

/// Print a library diagnostic as "file:line:column: message" (with @p prefix if not NULL).
void cliPrintDiagnostic(const char* prefix, const fmDiagnostic* diag);

/// Parse a whole string as a finite double. False on trailing junk, overflow or empty text.
bool cliParseDouble(const char* text, double* value);

/// Parse a whole string as an int. False on junk or overflow.
bool cliParseInt(const char* text, int* value);

// Processors online, in [1, FM_MAX_WORKERS]: the default worker count.
int cliCoresAvailable(void);

/// Parse the value of integer option @p option of @p command, which must lie in [lo, hi].
/// On failure prints a usage error that says what was wrong ("--frames: 99999999999 is too
/// large (at most 100000000)"; "expected an integer" for junk) and returns false.
bool cliParseIntOption(const char* command, const char* option, const char* text, int lo, int hi,
                       int* value);

/// Fetch the value of option @p argv[*index] (e.g. "--frames 10"); advances *index.
/// Prints a usage error and returns NULL when the value is missing.
const char* cliOptionValue(const char* command, int argc, char** argv, int* index);

/// Read a whole file (at most CLI_MAX_FILE_BYTES) into a NUL-terminated buffer to free().
/// Prints "path: reason" and returns NULL on failure.
char* cliReadFile(const char* path, size_t* size);

/// Why the file @p path cannot be read (strerror's text, or "not a regular file: ..." for a
/// folder, a FIFO or a device, found without blocking on a FIFO); NULL when it is a regular file
/// that opens for reading.
const char* cliFileUnreadable(const char* path);

/// Create a directory and its parents (like mkdir -p). Prints "path: reason" on failure.
bool cliMakeDirectories(const char* path);

/// Join a directory and a file name into @p out. False (with a message) if too long.
bool cliJoinPath(char* out, size_t size, const char* directory, const char* name);

/// Monotonic wall clock in seconds.
double cliNow(void);

/// Whether stderr is a terminal (progress lines are only printed there).
bool cliStderrIsTty(void);

/// Route the library's warnings and errors to stderr (the first few; a runaway simulation would
/// repeat them every step).
void cliInstallLogHook(void);

/// Mute (true) or unmute library warnings, e.g. around loading the embedded mesh whose quirks
/// are known.
void cliMuteLibraryWarnings(bool mute);

/// Tell the log hook the tool already warned about the explicit step, so the library's own
/// warning about it is not repeated.
void cliNoteExplicitStepWarned(void);

/// A body's positions (or, with @p velocities, velocities) copied out of the library
/// (fmBody_CopyPositions): 3 doubles a vertex, to free(); NULL when memory is short.
double* cliCopyState(fmBodyId body, bool velocities);
