// Edge against edge between bodies (contact_edge.c): two surface edges of different bodies whose
// closest points lie inside both edges, within the thickness or crossed during the substep, are
// pushed apart along the direction between those points, shared by inverse masses; then
// restitution and friction act on their relative velocity (explicit
// substeps; implicit steps hold edges apart with the barrier, barrier_contact.h). Rules: finding
// reads only (on the workers, into the worker's own list, each body pair once: the other body of a
// higher slot); projecting and responding run on one thread in item order.
#pragma once

#include "contact/contact_state.h"

// The point at parameter @p s along edge @p e (vertices into @p x: positions, 3 a vertex).
fmVec3 fmContactEdge_Point(const double* x, const int e[2], double s);

// Surface edge @p edge (triangle edge / 3, edge % 3) of body @p slot against the surface edges
// of the bodies of higher slots near it (so each pair of bodies once), into @p wf's list.
void fmContactEdge_Find(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                        int edge, double thickness, int item);

// One projection of an edge contact: the edges apart along the normal to the thickness, shared
// by inverse masses (momentum kept).
bool fmContactEdge_Project(fmWorld* w, fmContactState* s, fmEdgeContact* c, double thickness);

// Restitution and friction on the edges' relative velocity at the closest points.
bool fmContactEdge_Respond(fmWorld* w, fmContactState* s, fmEdgeContact* c);

// An edge contact into the contact list (at the nearer end of the first body's edge) and the
// frame's pairs.
bool fmContactEdge_Record(fmWorld* w, fmContactState* s, const fmEdgeContact* c);
