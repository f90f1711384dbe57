// The step arena (arena.h).
#include "core/arena.h"

#include "core/core.h"

#include <string.h>

#define FM_ARENA_ALIGN 64

static size_t fmArenaRound(size_t bytes)
{
	return (bytes + FM_ARENA_ALIGN - 1) & ~(size_t)(FM_ARENA_ALIGN - 1);
}

size_t fmArena_Bytes(size_t vectors, size_t count)
{
	return fmMulSize(vectors, fmArenaRound(fmMulSize(count, sizeof(double))));
}

bool fmArena_Reserve(fmArena* arena, size_t bytes)
{
	FM_ASSERT(arena->used == 0); // reserved between steps, never with buffers out
	if (bytes <= arena->capacity)
		return true;
	unsigned char* block = fmAlloc(bytes);
	if (block == NULL)
		return false;
	fmDealloc(arena->base, arena->capacity);
	arena->base = block;
	arena->capacity = bytes;
	return true;
}

double* fmArena_DoublesUninit(fmArena* arena, size_t count)
{
	size_t bytes = fmArenaRound(fmMulSize(count, sizeof(double)));
	bool fits = bytes <= arena->capacity - arena->used;
	FM_ASSERT(fits);
	if (!fits)
		return NULL;
	double* out = (double*)(void*)(arena->base + arena->used);
	arena->used += bytes;
	return out;
}

double* fmArena_Doubles(fmArena* arena, size_t count)
{
	double* out = fmArena_DoublesUninit(arena, count);
	if (out != NULL)
		memset(out, 0, sizeof(double) * count);
	return out;
}

size_t fmArena_Mark(const fmArena* arena)
{
	return arena->used;
}

void fmArena_Release(fmArena* arena, size_t mark)
{
	FM_ASSERT(mark <= arena->used);
	arena->used = mark;
}

void fmArena_Free(fmArena* arena)
{
	fmDealloc(arena->base, arena->capacity);
	memset(arena, 0, sizeof *arena);
}
