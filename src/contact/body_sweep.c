// Sweep and prune over body boxes (body_sweep.h).
#include "contact/body_sweep.h"

#include "core/core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool fmBodySweep_Sweepable(fmVec3 lower, fmVec3 upper)
{
	bool empty = lower.x == INFINITY && upper.x == -INFINITY;
	return empty || (isfinite(lower.x) && isfinite(lower.y) && isfinite(lower.z) &&
	                 isfinite(upper.x) && isfinite(upper.y) && isfinite(upper.z));
}

int fmSweepKey_Compare(const void* pa, const void* pb)
{
	const fmSweepKey* a = pa;
	const fmSweepKey* b = pb;
	if (a->x != b->x)
		return a->x < b->x ? -1 : 1;
	return (a->slot > b->slot) - (a->slot < b->slot);
}

static bool fmAddPair(fmBodySweep* s, int a, int b)
{
	if (2 * s->pairCount + 2 > s->pairCapacity &&
	    !fmGrowArray((void**)&s->pairs, &s->pairCapacity, 2 * s->pairCount, 2 * s->pairCount + 2,
	                 sizeof *s->pairs))
		return false;
	s->pairs[2 * s->pairCount] = a < b ? a : b;
	s->pairs[2 * s->pairCount + 1] = a < b ? b : a;
	s->pairCount += 1;
	return true;
}

static bool fmMeet(fmVec3 al, fmVec3 ah, fmVec3 bl, fmVec3 bh)
{
	return !(ah.x < bl.x || al.x > bh.x || ah.y < bl.y || al.y > bh.y || ah.z < bl.z ||
	         al.z > bh.z);
}

bool fmBodySweep_Pairs(fmBodySweep* s, const int* slots, int count, const fmVec3* lower,
                       const fmVec3* upper)
{
	s->pairCount = 0;
	if (!fmGrowArray((void**)&s->keys, &s->keyCapacity, 0, count > 0 ? count : 1, sizeof *s->keys))
		return false;
	int n = 0;
	for (int k = 0; k < count; ++k)
		if (lower[slots[k]].x <= upper[slots[k]].x) // (an empty box meets nothing)
			s->keys[n++] = (fmSweepKey){lower[slots[k]].x, slots[k]};
	qsort(s->keys, (size_t)n, sizeof *s->keys, fmSweepKey_Compare);
	for (int i = 0; i < n; ++i)
	{
		int a = s->keys[i].slot;
		for (int j = i + 1; j < n && s->keys[j].x <= upper[a].x; ++j)
		{
			int b = s->keys[j].slot;
			if (fmMeet(lower[a], upper[a], lower[b], upper[b]) && !fmAddPair(s, a, b))
				return false;
		}
	}
	return true;
}

static int fmCompareInts(const void* pa, const void* pb)
{
	int a = *(const int*)pa, b = *(const int*)pb;
	return (a > b) - (a < b);
}

bool fmBodySweep_Lists(fmBodySweep* s, int slots)
{
	if (!fmGrowArray((void**)&s->listStart, &s->listStartCapacity, 0, slots + 1,
	                 sizeof *s->listStart) ||
	    !fmGrowArray((void**)&s->list, &s->listCapacity, 0,
	                 2 * s->pairCount > 0 ? 2 * s->pairCount : 1, sizeof *s->list))
		return false;
	memset(s->listStart, 0, sizeof *s->listStart * ((size_t)slots + 1));
	for (int p = 0; p < 2 * s->pairCount; ++p)
		s->listStart[s->pairs[p] + 1] += 1;
	for (int k = 0; k < slots; ++k)
		s->listStart[k + 1] += s->listStart[k];
	// Fill from each list's end, then sort it.
	for (int p = 0; p < s->pairCount; ++p)
	{
		int a = s->pairs[2 * p], b = s->pairs[2 * p + 1];
		s->list[--s->listStart[a + 1]] = b;
		s->list[--s->listStart[b + 1]] = a;
	}
	// The starts went down by each list's length: list k now starts at listStart[k + 1].
	memmove(s->listStart, s->listStart + 1, sizeof *s->listStart * (size_t)slots);
	s->listStart[slots] = 2 * s->pairCount;
	for (int k = 0; k < slots; ++k)
		qsort(s->list + s->listStart[k], (size_t)(s->listStart[k + 1] - s->listStart[k]),
		      sizeof *s->list, fmCompareInts);
	return true;
}

void fmBodySweep_Free(fmBodySweep* s)
{
	FM_FREE_ARRAY(s->keys, fmSweepKey, s->keyCapacity);
	FM_FREE_ARRAY(s->pairs, int, s->pairCapacity);
	FM_FREE_ARRAY(s->listStart, int, s->listStartCapacity);
	FM_FREE_ARRAY(s->list, int, s->listCapacity);
	memset(s, 0, sizeof *s);
}
