// The contact stage's results (contact_events.c): the contact list, the floor's contacts reported
// as its collider's, the frame's touching pairs and their begin and end events, the colliders'
// forces, the pairs a snapshot saves and restores, and the public fmWorld_GetContacts and
// fmWorld_GetContactEvents. Rules: one thread, after the stage; pairs are keys
// (body slot << 32) | other body's slot, or | 0x80000000 | collider slot, sorted and unique at
// the end of a frame, so the events come in key order; a sleeping body keeps its pairs (no end
// events while an island sleeps).
#pragma once

#include "world/world.h"

// After a substep's contact stage (@p listed: it ran and began the contact list; otherwise the
// list is emptied first): the floor's contacts of the stepping bodies (body->floorHits), in body
// order, appended to the contact list as the floor collider's, with their pairs and the floor's
// reaction; the bodies' hits are then cleared. False when memory is short.
bool fmContactEvents_ReportFloor(fmWorld* w, bool listed);

// End of a frame: the colliders' forces (their impulses times @p perSecond, 1 / the frame's time),
// the frame's begin and end
// events. False when memory is short (the events are then lost).
bool fmContactEvents_EndFrame(fmWorld* w, double perSecond);

// The pairs that touched during the last frame, sorted: (body slot << 32) | (other body's
// slot), or | 0x80000000 | collider slot for a collider (valid until the next step).
int fmContactEvents_FramePairs(const fmWorld* w, const uint64_t** pairs);

// The last substep's contacts (valid until the next step); returns how many.
int fmContactEvents_Points(const fmWorld* w, const fmContactPoint** points);

// Replace the last frame's pairs with @p count sorted keys read from @p pairs (any alignment;
// a snapshot's, snapshot.c). False, and nothing changed, when memory is short.
bool fmContactEvents_SetFramePairs(fmWorld* w, const void* pairs, int count);
