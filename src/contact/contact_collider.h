// Surface vertices against colliders (contact_collider.c), the stage's second step: each vertex
// inside a collider, or whose motion in the substep crossed it (a swept test), goes back onto
// its surface; its velocity relative to the collider gets restitution and Coulomb friction (or
// a stick collider's), the collider the reaction, the contact list the point. Rules: colliders
// are exact shapes, kept with no gap; the queries of a body against a collider run on the
// workers, each vertex reading only its own state, and the responses on one thread in a fixed
// order (bodies, colliders, surface vertices ascending): the same bits for any number of
// workers. A sleeping body is not moved; a kinematic collider moving into it wakes it.
#pragma once

#include "contact/contact_state.h"

// Every awake body's surface vertices against the colliders its swept box may touch and whose
// filter meets its own, in body, collider and vertex order; @p thickness (the one between
// bodies) only bounds what an implicit creep takes back. False when memory is short.
bool fmContactCollider_Collide(fmWorld* w, fmContactState* s, double thickness);

// The friction the implicit solve gave each vertex with a friction record (lagged from the last
// step: penalty.h), in the substep of @p h seconds, as an impulse on the collider or the floor
// that wrote the record, whether or not the vertex still touches it: the solve's friction is
// part of the vertex's momentum change, so the reaction fmCollider_GetContactForce reports must
// hold all of it (Newton's third law, which a rigid-body engine coupled through it relies on).
// In body and vertex order, on one thread; after the solve, before the contact stage moves
// anything.
void fmContactCollider_BookSolveFriction(fmWorld* w, double h);

// Drop the friction records collider @p slot wrote (FM_FLOOR_SLOT: the floor's): it is gone,
// and a collider made later in its slot must neither feel nor give that friction.
void fmContactCollider_ForgetFriction(fmWorld* w, int slot);
