// What `femto bench` needs to use the optional programs it finds at run time (tetgen, gnuplot,
// the Bullet peer): a PATH look-up, shell quoting, a private temporary folder and temporary
// names for files written whole (tools.c).
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// Look @p name up in the folders of PATH: true, with its path in @p out, when one of them holds
/// an executable regular file of that name. False (silently) when none does or PATH is unset.
bool cliBenchFindProgram(const char* name, char* out, size_t size);

/// Append @p text to the NUL-terminated @p command, single-quoted for sh (a quote inside is
/// written '\''), preceded by a space. False, with @p command unchanged, when it does not fit.
bool cliBenchAppendQuoted(char* command, size_t size, const char* text);

/// Append @p text to the NUL-terminated @p command as it is. False, with @p command unchanged,
/// when it does not fit.
bool cliBenchAppendText(char* command, size_t size, const char* text);

/// Run @p command with sh; its exit status, or -1 when it could not run or ended on a signal.
int cliBenchRunCommand(const char* command);

/// Make a private folder "femto-bench.XXXXXX" under $TMPDIR (or /tmp), mode 0700, its path in
/// @p out. Prints the reason and returns false on failure.
bool cliBenchTempDir_Make(char* out, size_t size);

/// Remove a folder made by cliBenchTempDir_Make() with every file in it (it has no folders).
/// Safe on an empty path.
void cliBenchTempDir_Remove(const char* path);

/// "dir/name" -> "dir/.name.PID.tmp": the temporary name a file is written under before it is
/// renamed over @p path (same folder, so the rename is atomic). False when it does not fit.
bool cliBenchTempName(const char* path, char* out, size_t size);
