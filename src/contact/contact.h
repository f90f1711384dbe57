// The contact stage (contact.c): after every body has taken a substep, kinematic colliders
// move (before it, under the colliders' barrier), and every body's surface vertices are kept out of
// the colliders and out of the other bodies' surfaces, by position projection with restitution and
// Coulomb friction on the velocities (docs/contact.md). This module is the stage's order and its
// settings; the work is in its modules: contact_collider.h (vertices against colliders),
// contact_detect.h (the body-body broad phase and parallel detection), contact_pair.h (vertex
// against triangle, embedded vertices, self-collision), contact_edge.h (edge against edge),
// barrier_contact.h (bodies inside the implicit solve), contact_ledger.h (the energy ledger),
// contact_events.h (the contact list, events, colliders' forces, snapshots), on the buffers of
// contact_state.h. Rules: the body-body detection and the body-collider queries run on the workers,
// each writing only its own items; the responses run on one thread, in a fixed order (bodies,
// vertices, colliders, triangles ascending): the same bits for any number of workers.
#pragma once

#include "world/world.h"

// The thickness contact keeps (m): fmContactDef.thickness, or 1% of the smallest body's
// bounding-box diagonal. Within a step, the value its start found (world.h: stepKnown).
double fmContact_Thickness(const fmWorld* world);

// Whether the world has a collider in use.
bool fmContact_HasColliders(const fmWorld* world);

// Whether surfaces of bodies can meet: two or more bodies with contact between bodies on, or
// one that collides with itself. Within a step, what its start found.
bool fmContact_BodiesMeet(const fmWorld* world);

// Whether the world has anything for the contact stage to do (colliders, or body-body contact
// between two or more bodies).
bool fmContact_Active(const fmWorld* world);

// Whether the implicit solves carry the Coulomb floor's friction, lagged one step (penalty.h):
// an implicit world of the Newton solver whose enabled floor has Coulomb friction with mu > 0
// (vertex block descent keeps its own floor friction, vbd.c). Its friction records live in the
// bodies' contact arrays, which fmContact_BeginSubstep then keeps without colliders.
bool fmContact_FloorFriction(const fmWorld* world);

// Start of a frame: collider impulses zeroed; the frame's first body-body detection will look
// for vertices embedded in another body (embedded.h), to be pushed out by at most the floor's
// depenetration speed in that substep and in the frame's later ones. In a barrier world, whose
// solves never put a vertex inside another body, only when something else can have: a new world
// or integrator, positions moved since the last frame's end (set, restored, solved statically,
// written through a pointer, torn), an overlap found in the last frame, moving prescribed
// displacements (and, in the substep, a collider's push: fmContact_Substep).
void fmContact_BeginFrame(fmWorld* world);

// End of a frame that passed its checks: the positions' fingerprint the next frame's start
// compares (a barrier world looks for embedded vertices only after something moved them outside
// the solves). Returns the last substep's contacts.
int fmContact_EndFrame(fmWorld* world);

// Whether the implicit solves hold bodies off the colliders with a barrier and bound their
// steps (penalty.h): an implicit world of the Newton solver. Its kinematic colliders move at
// the substep's start (fmContact_BeginSubstep), and the contact stage does not move a vertex
// the solve left outside them.
bool fmContact_ColliderBarrier(const fmWorld* world);

// Start of a substep of @p h seconds: every body's positions kept as the start of its motion
// (for the swept tests), the lagged friction found after the last step handed to this one;
// before an implicit step, every body's surface edges made for the barrier and, under the
// colliders' barrier, the kinematic colliders moved to where the substep leaves them. False
// when memory is short.
bool fmContact_BeginSubstep(fmWorld* world, double h);

// The contact stage of the context's substep. False when memory is short.
bool fmContact_Substep(fmWorld* world, const fmStepContext* context);

// Validate a contact def (part of fmWorldDef_Validate).
fmResult fmContactDef_Validate(const fmContactDef* def, fmDiagnostic* diag);
