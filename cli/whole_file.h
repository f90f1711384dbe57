// Whole files or none: a file the tools write goes to a hidden temporary name in its folder
// ("dir/.name.PID.tmp") and is renamed over its name only when everything reached the disk, so a
// file that exists is whole, and a failure leaves the old one as it was (whole_file.c).
#pragma once

#include "cli.h"

#include <stdbool.h>
#include <stdio.h>

// A file being written: the stream goes to @p temp, renamed to @p path by cliOutput_Commit.
typedef struct cliOutput
{
	FILE* file;
	const char* path;
	char temp[CLI_MAX_PATH];
} cliOutput;

// Open @p path's temporary file for writing (a path that exists and is not a regular file, a
// FIFO or /dev/stdout, is written in place). False, with the reason on stderr, on failure.
bool cliOutput_Open(cliOutput* out, const char* path);

// Close the file and rename it over its path; false (the temporary removed, the path untouched)
// when a write failed.
bool cliOutput_Commit(cliOutput* out);

// Drop a file being written (a failure half-way): nothing replaces its path.
bool cliOutput_Abort(cliOutput* out);

// "dir/name" -> "dir/.name.PID.tmp" into @p temp; false when it does not fit.
bool cliTempPath(const char* path, char* temp, size_t size);

// Put the finished temporary file in place, or remove it when @p ok is false.
bool cliReplace(const char* temp, const char* path, bool ok);
