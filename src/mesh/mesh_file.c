// Mesh files on disk (mesh_file.h): whole files read into memory for the readers, and the
// writers' opening, finishing and checking of what they write.
// POSIX for open, fstat and read: the file is checked through its descriptor before reading.
#define _POSIX_C_SOURCE 200809L

#include "mesh/mesh_file.h"

#include "core/core.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void fmFileText_Free(fmFileText* t)
{
	fmDealloc(t->data, t->capacity);
	memset(t, 0, sizeof *t);
}

// What a non-regular file is, for the message that refuses it.
static const char* fmFileKind(mode_t mode)
{
	if (S_ISDIR(mode))
		return "a directory";
	if (S_ISFIFO(mode))
		return "a FIFO (named pipe)";
	if (S_ISCHR(mode))
		return "a character device";
	if (S_ISBLK(mode))
		return "a block device";
	if (S_ISSOCK(mode))
		return "a socket";
	return "not a regular file";
}

// Only regular files, of at most @p limit bytes: a device such as /dev/zero never ends and a
// FIFO may never deliver; their size is unknown, so neither can be checked before reading.
static fmResult fmCheckFile(int fd, const char* path, size_t limit, size_t* size,
                            fmDiagnostic* diag)
{
	struct stat info;
	if (fstat(fd, &info) != 0)
		return fmDiagError(diag, fm_errIo, path, 0, 0, "cannot read: %s", strerror(errno));
	if (!S_ISREG(info.st_mode))
		return fmDiagError(diag, fm_errIo, path, 0, 0,
		                   "is %s, not a regular file: expected a mesh file on disk",
		                   fmFileKind(info.st_mode));
	unsigned long long bytes = info.st_size > 0 ? (unsigned long long)info.st_size : 0u;
	if (bytes > (unsigned long long)limit)
		return fmDiagError(diag, fm_errLimit, path, 0, 0,
		                   "file is %llu bytes, more than the limit of %zu bytes "
		                   "(fmMeshLoadDef.maxFileBytes)",
		                   bytes, limit);
	*size = (size_t)bytes;
	return fm_ok;
}

// Read the @p t->capacity bytes the file had when it was checked. A file that shrank meanwhile is
// read as far as it goes; one that grew is refused (its size would escape the limit).
static fmResult fmReadAll(int fd, const char* path, fmFileText* t, fmDiagnostic* diag)
{
	while (t->size < t->capacity)
	{
		size_t chunk = t->capacity - t->size < (1u << 30) ? t->capacity - t->size : (1u << 30);
		ssize_t got = read(fd, t->data + t->size, chunk);
		if (got < 0 && errno == EINTR)
			continue;
		if (got < 0)
			return fmDiagError(diag, fm_errIo, path, 0, 0, "cannot read: %s", strerror(errno));
		if (got == 0)
			return fm_ok;
		t->size += (size_t)got;
	}
	char probe;
	ssize_t more;
	do
		more = read(fd, &probe, 1);
	while (more < 0 && errno == EINTR);
	if (more > 0)
		return fmDiagError(diag, fm_errIo, path, 0, 0,
		                   "the file grew while it was read (it was %zu bytes): expected a file "
		                   "that is not being written",
		                   t->capacity);
	return fm_ok;
}

// The size is checked before anything is allocated, and a large file is never held twice (no
// growing buffer). O_NONBLOCK: opening a FIFO without a writer would otherwise block forever before the check.
fmResult fmReadWholeFile(const char* path, size_t limit, fmFileText* t, fmDiagnostic* diag)
{
	memset(t, 0, sizeof *t);
	int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0)
		return fmDiagError(diag, fm_errIo, path, 0, 0, "cannot open: %s", strerror(errno));
	fmResult result = fmCheckFile(fd, path, limit, &t->capacity, diag);
	if (result == fm_ok && t->capacity > 0)
	{
		t->data = fmAlloc(t->capacity);
		if (t->data == NULL)
			result = fmDiagError(diag, fm_errOutOfMemory, path, 0, 0,
			                     "out of memory reading %zu bytes", t->capacity);
	}
	if (result == fm_ok)
		result = fmReadAll(fd, path, t, diag);
	close(fd);
	if (result != fm_ok)
		fmFileText_Free(t);
	return result;
}

// ---- writing ----------------------------------------------------------------------------------

// Where a file is written before it is renamed over @p path: "dir/.name.femto-PID.tmp", hidden,
// in the same folder (a rename within one file system replaces the file at once), one per
// process. False when the name does not fit.
static bool fmTempPath(const char* path, char* temp, size_t size)
{
	const char* slash = strrchr(path, '/');
	size_t folder = slash != NULL ? (size_t)(slash - path) + 1 : 0;
	int written = snprintf(temp, size, "%.*s.%s.femto-%ld.tmp", (int)folder, path, path + folder,
	                       (long)getpid());
	return written > 0 && (size_t)written < size;
}

// Whether @p path is written in place: it exists and is not a regular file (a FIFO, /dev/null),
// which a rename would replace.
static bool fmWrittenInPlace(const char* path)
{
	struct stat info;
	return stat(path, &info) == 0 && !S_ISREG(info.st_mode) && !S_ISDIR(info.st_mode);
}

FILE* fmOpenForWriting(const char* path, fmDiagnostic* diag, fmResult* result)
{
	struct stat info;
	char temp[FM_TEMP_PATH];
	*result = fm_ok;
	if (stat(path, &info) == 0 && S_ISDIR(info.st_mode))
	{
		*result = fmDiagError(diag, fm_errIo, path, 0, 0,
		                      "cannot write: it is a directory (expected a file name)");
		return NULL;
	}
	if (!fmWrittenInPlace(path) && !fmTempPath(path, temp, sizeof temp))
	{
		*result = fmDiagError(diag, fm_errIo, path, 0, 0, "cannot write: the path is too long");
		return NULL;
	}
	const char* target = fmWrittenInPlace(path) ? path : temp;
	FILE* f = fopen(target, "w");
	if (f == NULL && target == path)
		*result =
		    fmDiagError(diag, fm_errIo, path, 0, 0, "cannot open for writing: %s", strerror(errno));
	else if (f == NULL)
		*result = fmDiagError(diag, fm_errIo, path, 0, 0,
		                      "cannot open for writing: %s (writing its temporary %s)",
		                      strerror(errno), target);
	return f;
}

fmResult fmFinishFileStaged(FILE* f, bool ok, const char* path, fmDiagnostic* diag)
{
	int savedErrno = errno;
	if (fclose(f) != 0 && ok)
	{
		ok = false;
		savedErrno = errno;
	}
	if (ok)
		return fm_ok;
	fmDiscardFile(path);
	return fmDiagError(diag, fm_errIo, path, 0, 0, "cannot write: %s%s", strerror(savedErrno),
	                   fmWrittenInPlace(path) ? "" : " (the file is unchanged)");
}

fmResult fmCommitFile(const char* path, fmDiagnostic* diag)
{
	char temp[FM_TEMP_PATH];
	if (fmWrittenInPlace(path) || !fmTempPath(path, temp, sizeof temp))
		return fm_ok;
	if (rename(temp, path) == 0)
		return fm_ok;
	int savedErrno = errno;
	remove(temp);
	return fmDiagError(diag, fm_errIo, path, 0, 0,
	                   "cannot put the written file in place: %s (the file is unchanged)",
	                   strerror(savedErrno));
}

void fmDiscardFile(const char* path)
{
	char temp[FM_TEMP_PATH];
	if (!fmWrittenInPlace(path) && fmTempPath(path, temp, sizeof temp))
		remove(temp);
}

fmResult fmFinishFile(FILE* f, bool ok, const char* path, fmDiagnostic* diag)
{
	fmResult result = fmFinishFileStaged(f, ok, path, diag);
	return result == fm_ok ? fmCommitFile(path, diag) : result;
}

fmResult fmCheckFinitePoints(const char* path, const fmTetMesh* m, const double* x,
                             fmDiagnostic* diag)
{
	for (size_t k = 0; k < 3 * (size_t)m->nodeCount; ++k)
		if (!isfinite(x[k]))
			return fmDiagError(diag, fm_errRange, path, 0, 0,
			                   "point %d has a non-finite coordinate: expected finite positions",
			                   (int)(k / 3) + m->firstIndex);
	return fm_ok;
}
