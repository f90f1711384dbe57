// Body-body detection (contact_detect.c): the bodies' boxes and the spatial hash of their
// surface triangles (the broad phase), then the parallel detection tasks: every surface vertex
// against the triangles near it (contact_pair.h), every surface edge against the edges near it
// (contact_edge.h). Rules: the detection reads the bodies and writes only each worker's buffers
// (s->workers[k]) and each item's own slot (s->found[k], s->hit[k]); the results are read back
// in item order (edge contacts sorted by item and sequence), so they are the same bits for any
// number of workers. With s->predict > 0 (before an implicit step) the reaches add the motion
// the velocities will carry over the step.
#pragma once

#include "contact/contact_state.h"

// The three vertices of surface triangle @p t of body @p b.
const int* fmContactDetect_Triangle(const fmBody* b, int t);

// How far vertex i may have moved in the substep: since its start, and before an implicit
// step what its velocity will carry it (both bounds of the broad phase's boxes and reaches).
double fmContactDetect_Motion(const fmContactState* s, const fmBody* b, int i);

// Whether the box [lo, hi] of something of body @p slot overlaps the box of a body it may touch
// (another one whose filter meets its own, or itself when it collides with itself; with
// @p higher, only the bodies of higher slots and itself, which the edges test against): most
// vertices of a pile of bodies apart from each other skip the spatial hash entirely.
bool fmContactDetect_NearOtherBody(const fmWorld* w, const fmContactState* s, int slot, fmVec3 lo,
                                   fmVec3 hi, bool higher);

// Every body's surface triangles with their boxes (grown by the thickness and by how far their
// vertices moved in the substep) into the broad phase.
bool fmContactDetect_BuildTriangles(fmWorld* w, fmContactState* s, double thickness);

// Every surface vertex of the bodies near another, in parallel: its contact into s->found[k]
// where s->hit[k], in a fixed order whatever the workers. Returns how many items, or -1 when
// memory is short.
int fmContactDetect_Vertices(fmWorld* w, fmContactState* s, double thickness);

// Every surface edge of the bodies near another against the other bodies' edges, in parallel:
// the contacts into s->edgeContacts in item order whatever the workers. False when memory is
// short.
bool fmContactDetect_Edges(fmWorld* w, fmContactState* s, double thickness);
