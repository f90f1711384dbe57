// Mesh files on disk, shared by the readers and writers of every format: a whole regular file
// read into one buffer of its size, and the writers' open, finish (any write failure becomes
// fm_errIo) and the check that refuses non-finite positions before anything is written.
#pragma once

#include <femto/mesh.h>

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

// A whole file in one allocation of exactly its size.
typedef struct fmFileText
{
	char* data;
	size_t size;     // bytes read
	size_t capacity; // bytes allocated (the size the file had when it was opened)
} fmFileText;

// Read a whole regular file of at most @p limit bytes into one buffer of its size (a FIFO, device
// or directory is refused without waiting on it; the size is checked before allocating).
fmResult fmReadWholeFile(const char* path, size_t limit, fmFileText* t, fmDiagnostic* diag);
void fmFileText_Free(fmFileText* t);

// Writing is whole files or none: a writer opens @p path with fmOpenForWriting, which opens a
// temporary file beside it (a FIFO or device is written in place), and fmFinishFile renames
// the temporary over @p path only when everything was written; on any failure the temporary is
// removed and @p path is as it was. Writers of two files (TetGen's .node and .ele) finish both
// with fmFinishFileStaged, then fmCommitFile each, or fmDiscardFile both.
#define FM_TEMP_PATH 4096

// Open @p path for writing (its temporary); NULL with fm_errIo in @p result (and the diagnostic)
// on failure, a directory at @p path included.
FILE* fmOpenForWriting(const char* path, fmDiagnostic* diag, fmResult* result);

// Close @p f and turn any write failure (@p ok false, or fclose failing) into fm_errIo; on
// success put the file in place (fmCommitFile).
fmResult fmFinishFile(FILE* f, bool ok, const char* path, fmDiagnostic* diag);

// fmFinishFile without putting the file in place: the temporary stays for fmCommitFile (or is
// removed on failure).
fmResult fmFinishFileStaged(FILE* f, bool ok, const char* path, fmDiagnostic* diag);

// Rename @p path's finished temporary over it; fm_errIo (and the temporary removed) on failure.
fmResult fmCommitFile(const char* path, fmDiagnostic* diag);

// Remove @p path's temporary, if any.
void fmDiscardFile(const char* path);

// fm_errRange naming the first point of @p m whose position in @p x (3 per node) is not finite.
fmResult fmCheckFinitePoints(const char* path, const fmTetMesh* m, const double* x,
                             fmDiagnostic* diag);
