// Pairs of bodies whose boxes overlap, by sweep and prune along x (body_sweep.c): what the
// contact stage's mid phase and the barrier's gather ask of every body, found for all of them at
// once in O(n log n + pairs) instead of O(n^2) box tests (a thousand props on a floor spent a
// quarter of their frame on those).
#pragma once

#include <femto/femto.h>

#include <stdbool.h>

// A body's place in the sweep: its box's low x, then its slot (a total order).
typedef struct fmSweepKey
{
	double x;
	int slot;
} fmSweepKey;

// Orders sweep keys by x, then slot (qsort's comparison).
int fmSweepKey_Compare(const void* a, const void* b);

// The sweep's buffers, zeroed to start; grown to the scene, then reused.
typedef struct fmBodySweep
{
	fmSweepKey* keys;
	int keyCapacity;
	int* pairs; // pairCount pairs: the lower slot, then the higher
	int pairCount;
	int pairCapacity;
	// Per slot (slots + 1 entries), what fmBodySweep_Lists makes: the slots paired with slot s
	// are list[listStart[s] .. listStart[s + 1]), ascending.
	int* listStart;
	int listStartCapacity;
	int* list;
	int listCapacity;
} fmBodySweep;

// Whether a box can take part in a sweep: finite, or empty (its low corner +inf, its high -inf:
// a body without a surface, which meets nothing). A caller with any other box (a body gone
// non-finite) tests every pair instead.
bool fmBodySweep_Sweepable(fmVec3 lower, fmVec3 upper);

// The pairs of the @p count slots @p slots (ascending, each sweepable) whose boxes [lower[s],
// upper[s]] overlap, closed on every axis (touching boxes meet, as fmBoxesMeet), each once.
// False when memory is short.
bool fmBodySweep_Pairs(fmBodySweep* sweep, const int* slots, int count, const fmVec3* lower,
                       const fmVec3* upper);

// For each of @p slots slots, the slots it is paired with, ascending, from the pairs found.
// False when memory is short.
bool fmBodySweep_Lists(fmBodySweep* sweep, int slots);

// Release the buffers; safe on a zeroed sweep.
void fmBodySweep_Free(fmBodySweep* sweep);
