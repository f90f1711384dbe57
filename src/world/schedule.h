// The order a substep steps its bodies in (schedule.c): groups of bodies that cannot touch each
// other during the substep, stepped one group after another. The bodies of a group run on the
// world's workers at once; each group sees the groups before it where their steps ended and the
// ones after it where they start. Implicit steps with barrier contact between bodies group them
// by a greedy colouring of the bodies whose reach in the step meets another's surface (in slot
// order, so the groups and the results depend on the scene, never on the number of workers);
// every other substep has one group of all its bodies, which never read each other's state.
#pragma once

#include "contact/body_sweep.h"

#include <femto/fm_math.h>

#include <stdbool.h>

struct fmWorld;

// What a substep's schedule holds: the stepping bodies' slots, group after group (each group in
// slot order), group g being order[groupStart[g], groupStart[g + 1]).
typedef struct fmSchedule
{
	int* order;      // the slots of the bodies stepped, by group
	int* groupStart; // groupCount + 1 entries
	int groupCount;
	int* colour;    // per body slot: its group (-1: not stepped)
	fmVec3* stepLo; // per body slot: the box its step can reach (fmBarrierContact_StepBox)
	fmVec3* stepHi;
	fmVec3* nearLo; // per body slot: that box and its surface's grown by the gap
	fmVec3* nearHi;
	fmSweepKey* sorted; // the stepping slots (by the low x of their near boxes for the sweep)
	int* pairs;         // the pairs of slots that may meet, two entries each
	int pairCount, pairCapacity;
	int* stamp; // per group: the last slot a neighbour of which took it
	// With the barrier (gatherKnown): per stepping slot, the live bodies whose surfaces its
	// barrier's gather (fmBarrierPairs_GatherOthers) can meet in the substep, a superset found by
	// a sweep over each live body's box of the substep (gatherLo, gatherHi: a stepping body's
	// near box, any other's surface box, grown by the gap), in gather.list.
	bool gatherKnown;
	fmBodySweep gather;
	fmVec3* gatherLo;
	fmVec3* gatherHi;
	int* live;    // the live slots, ascending
	int capacity; // slots the per-slot arrays hold
} fmSchedule;

// Group the bodies of @p world that step in the substep, whose implicit steps have the inertia
// term @p inertia (1 / h^2); @p barrier: they hold bodies apart with the barrier (each reads the
// others near it). False when memory is short.
bool fmSchedule_Build(fmSchedule* schedule, const struct fmWorld* world, double inertia,
                      bool barrier);

// Release the schedule's arrays.
void fmSchedule_Free(fmSchedule* schedule);
