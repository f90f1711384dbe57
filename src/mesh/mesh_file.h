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

// Open @p path for writing; NULL with fm_errIo in @p result (and the diagnostic) on failure.
FILE* fmOpenForWriting(const char* path, fmDiagnostic* diag, fmResult* result);

// Close @p f and turn any write failure (@p ok false, or fclose failing) into fm_errIo.
fmResult fmFinishFile(FILE* f, bool ok, const char* path, fmDiagnostic* diag);

// fm_errRange naming the first point of @p m whose position in @p x (3 per node) is not finite.
fmResult fmCheckFinitePoints(const char* path, const fmTetMesh* m, const double* x,
                             fmDiagnostic* diag);
