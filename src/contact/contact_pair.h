// Vertex against triangle between bodies (contact_pair.c), and self-collision: a surface vertex
// within the thickness of another body's surface triangle (or its own, self-colliding), or that
// crossed it in the substep, is pushed out along the triangle's normal and the triangle the
// other way, shared by inverse masses (momentum kept); then the same restitution and friction as
// against colliders act on their relative velocity. A vertex deeper than any triangle's reach
// that another body's tet holds (embedded.h) is pushed toward that body's nearest surface
// triangle at most at the floor's depenetration speed. Rules: finding reads only (it runs on
// the workers, with the worker's own query buffers); projecting and responding run on one
// thread in the stage's fixed order; a projection never moves a vertex below the floor, and
// nothing moves a pinned axis.
#pragma once

#include "contact/contact_state.h"

// The contact of surface vertex i of body @p slot: the nearest triangle of another body (or
// its own, self-colliding) it touches or crossed in the substep, queried with @p wf's buffers
// (safe in parallel with other workers'). False when none, or when memory ran short
// (wf->failed).
bool fmContactPair_Find(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                        int i, double thickness, fmPairContact* found);

// One projection of a vertex-triangle contact: the gap along the normal back to the thickness,
// shared by inverse masses. False when memory is short.
bool fmContactPair_Project(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness);

// The velocity response of a vertex-triangle contact: the relative velocity of the vertex and
// the triangle's point loses its approach (restitution) and some slip (friction), the impulse
// shared by inverse masses. False when memory is short.
bool fmContactPair_Respond(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness);

// An awake body touches a sleeping one: the sleeper stays still (no inverse mass) and wakes,
// with its island, at the end of the frame (island.h).
void fmContactPair_WakeSleeper(fmWorld* w, const fmPairContact* found);
