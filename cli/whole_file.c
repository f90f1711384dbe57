// Whole files or none (whole_file.h): every file the tools write goes to a temporary name in
// its folder and is renamed over its name when complete.
#include "whole_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

// Close @p file and report a write error by path. Returns true if everything reached the disk.
static bool cliFinishFile(FILE* file, const char* path)
{
	bool failed = ferror(file) != 0;
	int savedErrno = errno;
	if (fclose(file) != 0)
	{
		failed = true;
		savedErrno = errno;
	}
	if (failed)
		fprintf(stderr, "%s: write error: %s\n", path, strerror(savedErrno));
	return !failed;
}

// "dir/name" -> "dir/.name.PID.tmp": hidden, in the same folder (rename within one file system
// is atomic), unique per process. A path that exists and is not a regular file (a FIFO,
// /dev/stdout) is written in place: renaming over it would replace it.
bool cliTempPath(const char* path, char* temp, size_t size)
{
	struct stat info;
	if (stat(path, &info) == 0 && !S_ISREG(info.st_mode))
		return snprintf(temp, size, "%s", path) < (int)size;
	const char* slash = strrchr(path, '/');
	size_t folder = slash != NULL ? (size_t)(slash - path) + 1 : 0;
	int written =
	    snprintf(temp, size, "%.*s.%s.%ld.tmp", (int)folder, path, path + folder, (long)getpid());
	if (written < 0 || (size_t)written >= size)
	{
		fprintf(stderr, "%s: path too long\n", path);
		return false;
	}
	return true;
}

// Put the finished temporary file in place (or remove it when @p ok is false).
bool cliReplace(const char* temp, const char* path, bool ok)
{
	if (strcmp(temp, path) == 0)
		return ok;
	if (ok && rename(temp, path) != 0)
	{
		fprintf(stderr, "%s: cannot rename %s over it: %s\n", path, temp, strerror(errno));
		ok = false;
	}
	if (!ok)
		remove(temp);
	return ok;
}

bool cliOutput_Open(cliOutput* out, const char* path)
{
	out->path = path;
	out->file = NULL;
	if (!cliTempPath(path, out->temp, sizeof out->temp))
		return false;
	out->file = fopen(out->temp, "w");
	if (out->file == NULL)
		fprintf(stderr, "%s: cannot open for writing: %s\n", out->temp, strerror(errno));
	return out->file != NULL;
}

bool cliOutput_Commit(cliOutput* out)
{
	bool ok = cliFinishFile(out->file, out->temp);
	out->file = NULL;
	return cliReplace(out->temp, out->path, ok);
}

// Drop a file being written (a failure half-way): nothing replaces @p out->path.
bool cliOutput_Abort(cliOutput* out)
{
	fclose(out->file);
	out->file = NULL;
	return cliReplace(out->temp, out->path, false);
}
