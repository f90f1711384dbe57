// The contact stage's buffers (contact_state.c): one per world, made on first use and kept
// between steps, so that a step allocates only where a buffer must grow. They hold what the
// stage's modules (contact*.c) pass to each other: the body-body broad phase, the contacts
// detected, the contact list, the frame's pairs and events, and the vertices the substep
// changed (for the energy ledger). Rules: the stage writes them on one thread, except during a
// parallel detection, where worker k writes only workers[k] and the items of its own ranges
// (contact_detect.h, contact_collider.h); everything is read back in item order, whatever the
// number of workers.
#pragma once

#include "contact/barrier_contact.h"
#include "contact/body_sweep.h"
#include "contact/broad_phase.h"
#include "contact/embedded.h"
#include "world/world.h"

// Detection items a task range takes at least (each is a box test, or a hash query and its
// narrow tests).
#define FM_CONTACT_MIN_RANGE 64

// Where a vertex goes back to against a collider (fmFindVertexVsCollider).
typedef struct fmColliderFind
{
	fmVec3 x;      // its position on the collider's surface
	fmVec3 normal; // the surface's outward normal there
	double depth;  // m, how far in it was
	bool hit;      // false: outside, and it did not cross the surface
} fmColliderFind;

// A vertex the contact stage changed, with its state before (the ledger's bookkeeping).
typedef struct fmLoggedVertex
{
	int body;
	int vertex;
	fmVec3 x;
	fmVec3 v;
} fmLoggedVertex;

// A vertex against a triangle of another body.
typedef struct fmPairContact
{
	int body;     // the vertex's body slot
	int vertex;   // its index in the body
	int other;    // the triangle's body slot
	int triangle; // its index in the other body's surface
	double w[3];  // barycentric weights of the triangle's point nearest the vertex
	fmVec3 normal;
	double depth;
	double impulse;
	double reach;  // m, the most the projections may still separate the pair in this substep
	bool embedded; // the vertex was inside the other body, beyond any triangle's reach
} fmPairContact;

// What one worker of the parallel detection found (fmDetect): its queries' buffers, the edge
// contacts it found in item order, its broad-phase time and whether memory ran short. Each on
// cache lines of its own: the workers write theirs at every query.
typedef struct fmWorkerFinds
{
	_Alignas(64) fmHashQuery query;
	fmHashQuery tetQuery; // for the tet hash (embedded.h)
	struct fmEdgeContact* edges;
	int edgeCount;
	int edgeCapacity;
	double broadPhase; // s
	bool failed;
} fmWorkerFinds;

// An edge of one body's surface within the thickness of an edge of another's (both ways
// between the bodies' surfaces, the endpoints excluded: those are vertex-triangle contacts).
typedef struct fmEdgeContact
{
	int body, other; // body slots, body < other
	int a[2], b[2];  // the edges' vertices
	double s, t;     // the closest points' parameters along a and b
	fmVec3 normal;   // unit, from b's edge toward a's
	double reach;    // m, the most the projections may still separate them in this substep
	double impulse;  // N s
	int item;        // the detection item (surface edge) that found it, for a fixed order
	int sequence;    // its place among that item's contacts
} fmEdgeContact;

// The contact stage's buffers of one world, made on first use (fmContactState_Get).
typedef struct fmContactState
{
	fmSpatialHash hash;
	fmTetHash tetHash;  // the near bodies' tets: vertices embedded deeper than the reach
	bool tetHashReady;  // built for this detection (the frame's first)
	bool colliderMoved; // the substep's collider stage moved a vertex (contact_collider.c)
	int triangleCapacity;
	fmVec3* lower; // per global triangle: its box
	fmVec3* upper;
	int* triangleBody;                     // per global triangle: its body slot
	int* triangleIndex;                    // per global triangle: its index in that body's surface
	fmWorkerFinds workers[FM_MAX_WORKERS]; // the parallel detection's per-worker buffers
	fmColliderFind* colliderFinds;         // per surface vertex of the body against a collider
	int colliderFindCapacity;
	int* items; // the detection's items: (body slot, vertex or surface edge) pairs
	int itemCapacity;
	fmPairContact* found; // per vertex item: its contact, where hit[k]
	uint8_t* hit;
	int foundCapacity;
	fmVec3* bodyLower; // per body slot: its surface's box, grown (the mid phase)
	fmVec3* bodyUpper;
	bool* bodyNear;    // per body slot: another body's box (or its own, self-colliding) overlaps
	double* bodySpeed; // per body slot: its surface vertices' fastest speed
	int bodyBoxCapacity;
	// Per body slot: the bodies whose boxes meet its box and that it can touch (itself when it
	// collides with itself), neighbour[neighbourStart[slot] ... neighbourStart[slot + 1]),
	// ascending; the boxes of its vertices and edges lie in its box, so no other body meets them
	int* neighbourStart; // bodyBoxCapacity + 1
	int* neighbour;
	int neighbourCapacity;
	fmBodySweep sweep; // the pairs of body boxes that overlap (body_sweep.h)
	int* live;         // bodyBoxCapacity: the live slots, ascending (the sweep's input)
	int triangleCount; // the triangles in the hash (those of bodies near another)
	fmPairContact* pairContacts;
	int pairContactCount;
	int pairContactCapacity;
	fmEdgeContact* edgeContacts;
	int edgeContactCount;
	int edgeContactCapacity;
	fmContactPoint* points; // the last substep's contacts
	int pointCount;
	int pointCapacity;
	uint64_t* pairs; // pairs that touched during the frame (sorted and made unique at its end)
	int pairCount;
	int pairCapacity;
	uint64_t* lastPairs; // the previous frame's
	int lastPairCount;
	int lastPairCapacity;
	fmContactEvent* events;
	int eventCount;
	int eventCapacity;
	fmLoggedVertex* logged; // the vertices the substep's contacts changed, with their old state
	int loggedCount;
	int loggedCapacity;
	int* tets; // scratch: the tets around a body's logged vertices
	int tetCapacity;
	double* forces; // scratch: a spring body's forces
	int forceCapacity;
	double predict;  // s: motion bounds add |v| predict (the implicit step's planes, made before
	                 // the step), 0 after it
	bool predicting; // predict > 0: the frozen planes are being made
	// The implicit solves' barrier terms (barrier_contact.h), one a worker: the bodies of a
	// schedule's group solve at once (world/schedule.h).
	fmBarrierScratch barrier[FM_MAX_WORKERS];
} fmContactState;

// The world's contact buffers, made (zeroed) on first use; NULL when memory is short.
fmContactState* fmContactState_Get(fmWorld* world);

// Release a world's contact buffers; NULL is fine.
void fmContactState_Free(fmContactState* s);

// Room for a box, a flag and a speed per body slot (bodyLower, bodyUpper, bodyNear, bodySpeed).
// False, with none, when memory is short.
bool fmContactState_ReserveBodyBoxes(const fmWorld* world, fmContactState* s);

// Add @p key ((body slot << 32) | other body's slot, or | 0x80000000 | collider slot) to the
// frame's pairs, unless it is the last one added. False when memory is short.
bool fmContactState_RecordPair(fmContactState* s, uint64_t key);

// A new, zeroed point at the end of the contact list; NULL when memory is short.
fmContactPoint* fmContactState_NewPoint(fmContactState* s);

// Note vertex i of body @p slot's state before the stage first changes it (logged, for the
// energy ledger; b->contactMark). False when memory is short.
bool fmContactState_LogVertex(fmContactState* s, fmBody* b, int slot, int i);
