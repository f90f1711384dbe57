// A bump allocator for step temporaries (arena.c), as Box2D's stack allocator: the world
// reserves it for its largest body at the start of a frame (the only time it may allocate, and
// only when a larger body arrived), the stages take named buffers from it and give them back in
// reverse order. No allocation per step after the first.
#pragma once

#include <stdbool.h>
#include <stddef.h>

typedef struct fmArena
{
	unsigned char* base;
	size_t capacity; // bytes
	size_t used;     // bytes handed out
} fmArena;

// Make sure @p bytes fit (growing the block when the arena is empty and too small). False when
// memory is short; the arena is then unchanged.
bool fmArena_Reserve(fmArena* arena, size_t bytes);

// @p count doubles, 64-byte aligned, zeroed; NULL (and an assert) when they do not fit the
// reservation, a programming error.
double* fmArena_Doubles(fmArena* arena, size_t count);

// The same without zeroing, for a buffer the caller overwrites whole (no wasted bandwidth).
double* fmArena_DoublesUninit(fmArena* arena, size_t count);

// The current top, to give everything above it back with fmArena_Release().
size_t fmArena_Mark(const fmArena* arena);
void fmArena_Release(fmArena* arena, size_t mark);

// Free the block.
void fmArena_Free(fmArena* arena);

// Bytes an arena needs to hand out @p vectors buffers of @p count doubles.
size_t fmArena_Bytes(size_t vectors, size_t count);
