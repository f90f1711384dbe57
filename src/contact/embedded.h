// Vertices caught inside another body (embedded.c): a spatial hash over the tets of the bodies
// near another, rebuilt every contact stage, and the point-in-tet query that says which body's
// tets hold a point. The contact stage uses it for a surface vertex that went deeper into
// another body than the thickness and the substep's motion reach: no triangle is then near
// enough to find it, but a tet still holds it, and it is pushed out toward that body's nearest
// surface (docs/contact.md).
#pragma once

#include "contact/broad_phase.h"
#include "world/world.h"

typedef struct fmTetHash
{
	fmSpatialHash hash;
	fmVec3* lower; // per hashed tet: its box
	fmVec3* upper;
	int* body; // per hashed tet: its body slot
	int* tet;  // per hashed tet: its index in the body
	int capacity;
	int count;
} fmTetHash;

// Whether a vertex of body slot @p slot may be held by body slot @p other (the caller's
// filtering rules: other bodies only, filters that meet, not both asleep).
typedef bool fmContainerTest(const fmWorld* world, int slot, int other);

// Rebuild @p th over the tets of every live body slot k with near[k]. False when memory is
// short (the hash is then empty).
bool fmTetHash_Build(fmTetHash* th, const fmWorld* world, const bool* near);

// The body slot whose tet holds point @p p (strictly inside, by barycentric coordinates), the
// first in hash order that @p accepts for a vertex of @p slot; -1 when none does, -2 when
// @p query could not grow. Reads @p th only: queries with distinct @p query buffers may run in
// parallel.
int fmTetHash_Container(const fmTetHash* th, const fmWorld* world, fmHashQuery* query, int slot,
                     fmVec3 p, fmContainerTest* accepts);

// Release the arrays; safe on a zeroed hash.
void fmTetHash_Free(fmTetHash* th);
