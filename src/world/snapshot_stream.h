// The snapshot's byte stream (snapshot_stream.c): a cursor over the caller's buffer that writes,
// counts (no buffer) or reads values in the machine's layout, and remembers running past the end
// instead of touching memory beyond it.
#pragma once

#include <stdbool.h>
#include <stddef.h>

// A cursor over the buffer: writing with out == NULL only counts.
typedef struct fmStream
{
	unsigned char* out;      // writing; NULL to count
	const unsigned char* in; // reading
	size_t size;
	size_t used;
	bool overflow;
} fmStream;

// Write (or count) @p bytes of @p data; overflow when they do not fit.
void fmStream_Put(fmStream* stream, const void* data, size_t bytes);

// Read @p bytes into @p data; zeros and overflow when they are not there.
void fmStream_Get(fmStream* stream, void* data, size_t bytes);

// One value or array through the stream in either direction (@p save: put, else get).
void fmStream_Move(fmStream* stream, bool save, void* data, size_t bytes);
void fmStream_MoveBool(fmStream* stream, bool save, bool* value);
void fmStream_MoveDouble(fmStream* stream, bool save, double* value);

// Step over @p bytes, or mark the stream overflowed when they are not there.
void fmStream_Skip(fmStream* stream, size_t bytes);
