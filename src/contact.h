// The contact stage (contact.c): after every body has taken a substep, kinematic colliders
// move, and every body's surface vertices are kept out of the colliders and out of the other
// bodies' surfaces, by position projection with restitution and Coulomb friction on the
// velocities (docs/contact.md). The body-body detection and the body-collider queries run on
// the workers, the responses on one, in a fixed order: the same bits for any number of
// workers. The contact list, the pairs' begin and end events and the colliders' forces come
// out of it.
#pragma once

#include "world.h"

// Buffers of the contact stage of one world (contact.c), made on first use.
typedef struct fmContactState fmContactState;

// The thickness contact keeps (m): fmContactDef.thickness, or 1% of the smallest body's
// bounding-box diagonal.
double fmContact_Thickness(const fmWorld* world);

// Whether the world has anything for the contact stage to do (colliders, or body-body contact
// between two or more bodies).
bool fmContact_Active(const fmWorld* world);

// Start of a frame: collider impulses zeroed; the frame's first body-body detection will look
// for vertices embedded in another body (embedded.h), to be pushed out by at most the floor's
// depenetration speed in that substep and in the frame's later ones.
void fmContact_BeginFrame(fmWorld* world);

// The share of the thinner body's thickness two bodies may close in by in one implicit piece.
#define FM_PIECE_FRACTION 0.5

// Implicit steps no longer than this times a body's explicit stability limit keep bodies apart
// by the contact stage's projection alone, without frozen planes in the solve (contact.c).
#define FM_PLANE_STEP_FACTOR 2.0

// Implicit steps: how many equal pieces a step of @p h seconds is cut into (1 to @p most;
// @p most + 1 when it would take more) so
// that no two bodies that may meet close in on each other by more than FM_PIECE_FRACTION of the
// thinner one's rest thickness (2 V / S) in a piece, at their surfaces' fastest speeds: each
// body's solve sees the others frozen where they started, and the stage after it finds a
// vertex that crossed a surface only while it is still inside. -1 when memory is short.
int fmContact_Pieces(fmWorld* world, double h, int most);

// Start of a substep of @p h seconds: every body's positions kept as the start of its motion
// (for the swept tests); before an implicit step, the other bodies' surfaces near each surface
// vertex frozen as planes for the step's penalty (body->contactPlane). False when memory is
// short.
bool fmContact_BeginSubstep(fmWorld* world, double h);

// The contact stage of a substep of @p h seconds. False when memory is short.
bool fmContact_Substep(fmWorld* world, double h);

// After a substep's contact stage (@p listed: it ran and began the contact list; otherwise the
// list is emptied first): the floor's contacts of the stepping bodies (body->floorHits), in body
// order, appended to the contact list as the floor collider's, with their pairs and the floor's
// reaction; the bodies' hits are then cleared. False when memory is short.
bool fmContact_ReportFloor(fmWorld* world, bool listed);

// End of a frame of @p frameTime seconds: the colliders' forces, the frame's begin and end
// events. False when memory is short (the events are then lost).
bool fmContact_EndFrame(fmWorld* world, double frameTime);

// The pairs that touched during the last frame, sorted: (body slot << 32) | (other body's
// slot), or | 0x80000000 | collider slot for a collider (valid until the next step).
int fmContact_FramePairs(const fmWorld* world, const uint64_t** pairs);

// Replace the last frame's pairs with @p count sorted keys read from @p pairs (any alignment;
// a snapshot's, snapshot.c). False, and nothing changed, when memory is short.
bool fmContact_SetFramePairs(fmWorld* world, const void* pairs, int count);

// The last substep's contacts (valid until the next step); returns how many.
int fmContact_Points(const fmWorld* world, const fmContactPoint** points);

// Validate a contact def (part of fmWorldDef_Validate).
fmResult fmContactDef_Validate(const fmContactDef* def, fmDiagnostic* diag);

// Release a world's contact buffers; NULL is fine.
void fmContact_Free(fmContactState* state);
