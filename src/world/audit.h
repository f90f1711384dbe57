// The contact audit (audit.c): fmWorld_AuditContact, and the same tests for one body against the
// others, which body creation uses to refuse a body that would start inside another.
#pragma once

#include "world/world.h"

// How the body in @p slot overlaps the other live bodies whose filters and boxes meet its own
// (the audit's tests both ways, no inverted tets, no self-contact, and tets of either body of a
// pair whose centre lies inside the other: bodies lying on each other's surfaces).
typedef struct fmAuditOverlap
{
	int crossings;      // surface edges crossing surface triangles
	int verticesInside; // surface vertices inside the other body
	int tetsInside;     // tet centres inside the other body
	int other;          // the slot of the first body overlapped, -1 for none
	double deepest;     // m
	// the body's surface edges crossing its own triangles (a body that meets itself:
	// self-collision or torn pieces), and the first of them
	int selfCrossings;
	fmAuditFinding firstSelfCrossing;
} fmAuditOverlap;

// The overlap of the body in @p slot with the others (other -1 and the counts 0 for none), and
// of its surface with itself when it meets itself. fm_errOutOfMemory,
// fm_errNumerical for non-finite positions.
fmResult fmAudit_Overlap(fmWorld* world, int slot, fmAuditOverlap* overlap);
