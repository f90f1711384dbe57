// The order a substep steps its bodies in (schedule.h).
#include "world/schedule.h"

#include "contact/barrier_contact.h"
#include "contact/contact.h"
#include "core/det_math.h"
#include "math/geometry.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void fmSchedule_Free(fmSchedule* s)
{
	size_t n = (size_t)s->capacity;
	FM_FREE_ARRAY(s->order, int, n);
	FM_FREE_ARRAY(s->groupStart, int, n + 1);
	FM_FREE_ARRAY(s->colour, int, n);
	FM_FREE_ARRAY(s->stepLo, fmVec3, n);
	FM_FREE_ARRAY(s->stepHi, fmVec3, n);
	FM_FREE_ARRAY(s->nearLo, fmVec3, n);
	FM_FREE_ARRAY(s->nearHi, fmVec3, n);
	FM_FREE_ARRAY(s->sorted, fmSweepKey, n);
	FM_FREE_ARRAY(s->stamp, int, n);
	FM_FREE_ARRAY(s->pairs, int, s->pairCapacity);
	FM_FREE_ARRAY(s->gatherLo, fmVec3, n);
	FM_FREE_ARRAY(s->gatherHi, fmVec3, n);
	FM_FREE_ARRAY(s->live, int, n);
	fmBodySweep_Free(&s->gather);
	memset(s, 0, sizeof *s);
}

// Room for @p slots body slots; false (and nothing held) when memory is short.
static bool fmScheduleReserve(fmSchedule* s, int slots)
{
	if (slots <= s->capacity)
		return true;
	fmSchedule_Free(s);
	size_t n = (size_t)slots;
	s->order = FM_ALLOC_ARRAY(int, n);
	s->groupStart = FM_ALLOC_ARRAY(int, n + 1);
	s->colour = FM_ALLOC_ARRAY(int, n);
	s->stepLo = FM_ALLOC_ARRAY(fmVec3, n);
	s->stepHi = FM_ALLOC_ARRAY(fmVec3, n);
	s->nearLo = FM_ALLOC_ARRAY(fmVec3, n);
	s->nearHi = FM_ALLOC_ARRAY(fmVec3, n);
	s->sorted = FM_ALLOC_ARRAY(fmSweepKey, n);
	s->stamp = FM_ALLOC_ARRAY(int, n);
	s->gatherLo = FM_ALLOC_ARRAY(fmVec3, n);
	s->gatherHi = FM_ALLOC_ARRAY(fmVec3, n);
	s->live = FM_ALLOC_ARRAY(int, n);
	s->capacity = slots;
	if (s->order && s->groupStart && s->colour && s->stepLo && s->stepHi && s->nearLo &&
	    s->nearHi && s->sorted && s->stamp && s->gatherLo && s->gatherHi && s->live)
		return true;
	fmSchedule_Free(s);
	return false;
}

// The stepping bodies' slots into s->sorted (slot order); returns how many.
static int fmSteppingSlots(fmSchedule* s, const fmWorld* w)
{
	int count = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		s->colour[i] = -1;
		if (fmIsland_Stepping(&w->bodies[i]))
			s->sorted[count++].slot = i;
	}
	return count;
}

static bool fmFiniteBox(fmVec3 lo, fmVec3 hi)
{
	return isfinite(lo.x) && isfinite(lo.y) && isfinite(lo.z) && isfinite(hi.x) && isfinite(hi.y) &&
	       isfinite(hi.z);
}

// Each stepping body's step box, and its near box: the step box with its surface's box (as the
// other bodies' solves see it) grown by the gap.
static void fmNearBoxes(fmSchedule* s, const fmWorld* w, double inertia, int count)
{
	double gap = fmContact_Thickness(w);
	fmVec3 g = fmMakeVec3(gap, gap, gap);
	for (int k = 0; k < count; ++k)
	{
		int i = s->sorted[k].slot;
		const fmBody* b = &w->bodies[i];
		fmBarrierContact_StepBox(w, b, inertia, &s->stepLo[i], &s->stepHi[i]);
		if (!fmFiniteBox(s->stepLo[i], s->stepHi[i]) ||
		    !fmFiniteBox(b->contact.surfaceLower, b->contact.surfaceUpper))
		{
			// Anything meets a body that went non-finite (the checks will refuse the frame).
			s->stepLo[i] = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
			s->stepHi[i] = fmMakeVec3(INFINITY, INFINITY, INFINITY);
		}
		s->nearLo[i] = fmMinVec(s->stepLo[i], fmSub(b->contact.surfaceLower, g));
		s->nearHi[i] = fmMaxVec(s->stepHi[i], fmAdd(b->contact.surfaceUpper, g));
		s->sorted[k].x = s->nearLo[i].x;
	}
}

// Whether body @p a's step can reach body @p b's surface within the gap, or the other way
// round: then one reads the other's positions in its solve (fmBarrierContact_Begin's test).
static bool fmStepsMeet(const fmSchedule* s, const fmWorld* w, int a, int b)
{
	double gap = fmContact_Thickness(w);
	fmVec3 g = fmMakeVec3(gap, gap, gap);
	const fmBody* A = &w->bodies[a];
	const fmBody* B = &w->bodies[b];
	return fmBoxesMeet(s->stepLo[a], s->stepHi[a], fmSub(B->contact.surfaceLower, g),
	                   fmAdd(B->contact.surfaceUpper, g)) ||
	       fmBoxesMeet(s->stepLo[b], s->stepHi[b], fmSub(A->contact.surfaceLower, g),
	                   fmAdd(A->contact.surfaceUpper, g));
}

static bool fmAddPair(fmSchedule* s, int a, int b)
{
	if (s->pairCount + 2 > s->pairCapacity &&
	    !fmGrowArray((void**)&s->pairs, &s->pairCapacity, s->pairCount, s->pairCount + 2,
	                 sizeof *s->pairs))
		return false;
	s->pairs[s->pairCount++] = a < b ? a : b;
	s->pairs[s->pairCount++] = a < b ? b : a;
	return true;
}

// The pairs of stepping bodies that may meet: sweep and prune along x over the near boxes.
static bool fmFindPairs(fmSchedule* s, const fmWorld* w, int count)
{
	qsort(s->sorted, (size_t)count, sizeof *s->sorted, fmSweepKey_Compare);
	s->pairCount = 0;
	for (int k = 0; k < count; ++k)
	{
		int a = s->sorted[k].slot;
		for (int m = k + 1; m < count && s->sorted[m].x <= s->nearHi[a].x; ++m)
		{
			int b = s->sorted[m].slot;
			if (fmBoxesMeet(s->nearLo[a], s->nearHi[a], s->nearLo[b], s->nearHi[b]) &&
			    fmStepsMeet(s, w, a, b) && !fmAddPair(s, a, b))
				return false;
		}
	}
	return true;
}

static int fmComparePairs(const void* pa, const void* pb)
{
	const int* a = pa;
	const int* b = pb;
	if (a[1] != b[1])
		return (a[1] > b[1]) - (a[1] < b[1]);
	return (a[0] > b[0]) - (a[0] < b[0]);
}

// Greedy colours in slot order: each body takes the smallest colour none of its neighbours of
// lower slots took. Pairs sorted by their higher slot list each body's lower neighbours.
static int fmColour(fmSchedule* s, const fmWorld* w)
{
	int pairs = s->pairCount / 2;
	if (pairs > 1)
		qsort(s->pairs, (size_t)pairs, 2 * sizeof *s->pairs, fmComparePairs);
	for (int c = 0; c < w->bodyCapacity; ++c)
		s->stamp[c] = -1;
	int colours = 0, p = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		if (!fmIsland_Stepping(&w->bodies[i]))
			continue;
		for (; p < pairs && s->pairs[2 * p + 1] == i; ++p)
			s->stamp[s->colour[s->pairs[2 * p]]] = i;
		int c = 0;
		while (s->stamp[c] == i)
			c += 1;
		s->colour[i] = c;
		colours = c + 1 > colours ? c + 1 : colours;
	}
	return colours;
}

// The groups: the slots by colour, each colour in slot order (a counting sort).
static void fmGroups(fmSchedule* s, const fmWorld* w, int colours)
{
	for (int c = 0; c <= colours; ++c)
		s->groupStart[c] = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (s->colour[i] >= 0)
			s->groupStart[s->colour[i] + 1] += 1;
	for (int c = 0; c < colours; ++c)
		s->groupStart[c + 1] += s->groupStart[c];
	for (int c = 0; c < colours; ++c)
		s->stamp[c] = s->groupStart[c];
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (s->colour[i] >= 0)
			s->order[s->stamp[s->colour[i]]++] = i;
	s->groupCount = colours;
}

// The gather lists (schedule.h): each live body's box of the substep, a stepping one's near box
// (its step box and its surface's box: every surface box it notes in the substep lies in it),
// any other's surface box, grown by the gap as the gather grows the surfaces it tests; the pairs
// that meet by a sweep. A body whose box a sweep cannot order (non-finite, or a step box without
// bounds: moving loads) leaves the gathers to test every body.
static bool fmGatherLists(fmSchedule* s, const fmWorld* w)
{
	double gap = fmContact_Thickness(w);
	fmVec3 g = fmMakeVec3(gap, gap, gap);
	int live = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		const fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		fmVec3 lo = s->colour[i] >= 0 ? s->nearLo[i] : b->contact.surfaceLower;
		fmVec3 hi = s->colour[i] >= 0 ? s->nearHi[i] : b->contact.surfaceUpper;
		s->gatherLo[i] = fmSub(lo, g);
		s->gatherHi[i] = fmAdd(hi, g);
		if (!fmBodySweep_Sweepable(s->gatherLo[i], s->gatherHi[i]))
			return true;
		s->live[live++] = i;
	}
	if (!fmBodySweep_Pairs(&s->gather, s->live, live, s->gatherLo, s->gatherHi) ||
	    !fmBodySweep_Lists(&s->gather, w->bodyCapacity))
		return false;
	s->gatherKnown = true;
	return true;
}

bool fmSchedule_Build(fmSchedule* s, const fmWorld* w, double inertia, bool barrier)
{
	if (!fmScheduleReserve(s, w->bodyCapacity > 0 ? w->bodyCapacity : 1))
		return false;
	s->gatherKnown = false;
	int count = fmSteppingSlots(s, w);
	if (!barrier || count < 2)
	{
		for (int k = 0; k < count; ++k)
			s->order[k] = s->sorted[k].slot;
		s->groupStart[0] = 0;
		s->groupStart[1] = count;
		s->groupCount = count > 0 ? 1 : 0;
		return true;
	}
	fmNearBoxes(s, w, inertia, count);
	if (!fmFindPairs(s, w, count))
		return false;
	fmGroups(s, w, fmColour(s, w));
	return fmGatherLists(s, w);
}
