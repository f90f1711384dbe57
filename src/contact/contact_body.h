// What the contact stage keeps about one body between its calls: the body's surface vertices,
// the swept tests' start positions, the implicit step's frozen planes and lagged friction, the
// floor's hits. Typed, made and freed by the contact stage; the body only carries it
// (fmBody.contact), and the implicit solve reads it through fmContactPenalty.
#pragma once

#include <femto/types.h>

#include <stdint.h>

struct fmBarrierStretch;
struct fmEdgePlane;
struct fmFloorHit;

// A vertex's friction record for the next implicit step (body->contact.friction, this many
// doubles): the contact normal (0-2), the Coulomb limit mu lambda (3; N, 0: none), the surface's
// velocity (4-6), 1 for a stick contact (7), the stretch of the static friction's spring at the
// end of the step that found it (8-10, m, at most the slip width): the next step's slip starts
// from it, so a contact that holds is anchored where it first held and does not creep; the
// stiffest the spring may be over the inertia term m / h^2 (11); and the slot of the collider
// that found it plus one (12; FM_FLOOR_SLOT + 1 for the floor): the solve's friction impulse goes
// to that collider's reaction (contact_collider.h).
#define FM_FRICTION_STRIDE 13

// Bodies a body can be known to overlap at once (barrier_contact.h).
#define FM_OVERLAP_SLOTS 4

typedef struct fmBodyContact
{
	int surfaceVertexCount;
	int* surfaceVertex;  // the vertices on the surface, ascending
	double* start;       // 3n: positions at the start of the substep (the swept tests)
	int* mark;           // n: 1 + the contact log entry of a vertex the stage changed, or 0
	double* plane;       // 4n: an implicit step's frozen plane of another body near each
	                     // surface vertex (n, n . q), NaN where none (penalty.h)
	uint8_t* tetMark;    // tetCount: scratch marks of the ledger's energy change
	double* colliderGap; // 2n: each surface vertex's distance to the nearest collider it meets at
	                     // the implicit step's start (m; INFINITY: none), which the solve's
	                     // collider queries skip a vertex by while its motion is shorter; then
	                     // how deep inside the colliders' barrier lets it stay in the step (m,
	                     // <= 0; penalty.h, fmContactPenalty_Prepare)
	int* embeddedHolder; // n: 1 + the slot of the body whose tet held the vertex this frame
	                     // (its later substeps push it on), or 0
	// An implicit step's frozen planes of other bodies' surface edges near this body's surface
	// edges (penalty.h), made before the step like `plane`
	struct fmEdgePlane* edgePlanes;
	int edgePlaneCount;
	int edgePlaneCapacity;
	// FM_FRICTION_STRIDE n: implicit friction against colliders and the Coulomb floor, lagged one
	// step (penalty.h)
	double* friction;
	double* frictionNext; // FM_FRICTION_STRIDE n: what this step found, for the next one
	// The stretch of each barrier pair's friction spring at the end of the body's last implicit
	// step, sorted by stencil (barrier_contact.h)
	struct fmBarrierStretch* stretch;
	int stretchCount, stretchCapacity;
	// 1 + the slots of bodies a vertex of this one was found inside in the last frame (0: none):
	// the pair meets through the contact stage's projection, not the barrier, until apart
	int overlapWith[FM_OVERLAP_SLOTS];
	int surfaceEdgeCount;
	int* surfaceEdge; // 2 per surface edge, low vertex first (barrier_contact.h)
	// The surface's box where the body stands in an implicit substep's solves: taken when the
	// substep begins and again when the body's own solve ends (barrier_contact.h)
	fmVec3 surfaceLower, surfaceUpper;
	double thinness; // 2 V / S at rest (m): how thick the body is (contact.c)
	// The floor's contacts of the last substep (floor.h), for the contact list and the floor's
	// reaction
	struct fmFloorHit* floorHits;
	int floorHitCount;
	int floorHitCapacity;
} fmBodyContact;

// Free a body's contact arrays (@p vertexCount vertices, @p tetCount tets) and zero them.
void fmBodyContact_Free(fmBodyContact* contact, int vertexCount, int tetCount);
