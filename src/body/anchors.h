// Attachments (anchors.c): a body's vertices glued to a collider (a game's rigid body on the
// other side) or welded to another body's vertices, and fmBody_AttachToCollider, fmBody_Weld.
// Each anchor is a bounded spring and dashpot (a target, targets.h) that every substep places
// before the bodies step:
// - glued to a collider: at the point of the collider's frame where the vertex was when glued,
//   where the collider's motion leaves it at the step's end (implicit) or where it is at the
//   start (explicit: its forces act there); the spring's force, reversed, goes into the
//   collider's impulse (fmCollider_GetContactForce), so a rigid engine feels the body it carries;
// - welded: both ends at one point, the two vertices' midpoint, moving at their mean velocity:
//   implicit, the midpoint of their predicted ends x + h v + h^2 a, a the pair's acceleration
//   over the last substep from everything but welds (measured from the two bodies' momenta, so
//   the prediction never feeds back through the weld's stiffness), so each body's solve pulls
//   its vertex there and the pair meets however stiff the weld; explicit, their midpoint now.
//   The two ends' forces, k (midpoint - x), are equal and opposite throughout an explicit step
//   and, implicit, whenever the prediction holds (at rest, in free fall, pushed or carried as
//   one), so the pair carries its weight and keeps its momentum (docs/contact.md,
//   "Attachments").
// Anchors whose collider or partner body is gone are dropped at the next substep.
#pragma once

#include "body/body.h"

#include <stdint.h>

struct fmWorld;

typedef struct fmAnchor
{
	int collider;        // glued: the collider's slot; welded: -1
	int body;            // welded: the partner's slot
	uint32_t generation; // of the collider or the partner in its slot
	int otherVertex;     // welded: the partner's vertex (its own numbering)
	fmVec3 local;        // glued: the point in the collider's frame (m)
	fmVec3 lever;        // glued: the point minus the collider's centre at the substep's end
	// Welded, implicit: the pair's acceleration over the last substep from everything but welds
	// (the two bodies' external forces over their masses), which the next predicted ends take.
	fmVec3 acceleration;
} fmAnchor;

// Whether body @p b is welded to body @p o (another body): welded bodies do not collide with
// each other, as a game engine's jointed bodies (docs/contact.md, "Attachments").
bool fmAnchors_WeldedTo(const fmBody* b, const fmBody* o);
static inline bool fmAnchors_Welded(const fmBody* b, const fmBody* o)
{
	return b->anchorCount > 0 && fmAnchors_WeldedTo(b, o);
}

// The attachments' stages the world's frame calls, through fmWorld.anchorStages (set by
// fmAnchors_Enable): a program that never attaches links none of them (the page's .wasm).
typedef struct fmAnchorStages
{
	// Place every live body's anchors for a substep of h in a frame of frameTime (before any
	// body steps: welds read their partners' start), dropping those whose source is gone.
	void (*place)(struct fmWorld* world, double h, double frameTime);
	// After every body stepped a substep of h: the glued anchors' forces, reversed, go into
	// their colliders' impulses, in body order; the welded ones note their pair's acceleration.
	void (*afterSubstep)(struct fmWorld* world, double h);
	// Wake the sleeping bodies that hang on a moving collider or are welded to an awake body.
	void (*wake)(struct fmWorld* world);
	// Whether the body hangs on a collider that moves (it cannot sleep).
	bool (*onMovingCollider)(const struct fmWorld* world, const fmBody* body);
	// The slot of anchor a's live weld partner, or -1 (glued, or the partner gone).
	int (*partner)(const struct fmWorld* world, const fmBody* body, int a);
} fmAnchorStages;

// Set the world's attachment stages (the first attachment, or a snapshot that holds some).
void fmAnchors_Enable(struct fmWorld* world);

// Place one body's anchors for a static solve: glued ones where their colliders are, welded ones
// at the midpoint of the two vertices now.
void fmAnchors_PlaceStatic(struct fmWorld* world, fmBody* body);

// An anchor as a snapshot keeps it (plain values, no padding): the placement a substep makes is
// rebuilt from it.
typedef struct fmAnchorRecord
{
	int32_t vertex, collider, body, otherVertex; // the body's vertex; as fmAnchor's
	uint32_t generation;
	int32_t zero; // 0
	double local[3];
	double stiffness, damping, maxForce; // N/m, N s/m, N (INFINITY: none)
	double acceleration[3];              // m/s^2, as fmAnchor's
} fmAnchorRecord;

// Anchor @p a of @p body as a record.
fmAnchorRecord fmAnchors_Record(const fmBody* body, int a);

// What is wrong with @p record as an anchor of @p body in @p world, or NULL: a vertex, collider
// slot, partner slot or partner vertex out of range, a point or spring not finite.
const char* fmAnchors_RecordProblem(const struct fmWorld* world, const fmBody* body,
                                    const fmAnchorRecord* record);

// Room for @p count anchors, those held kept; false without memory.
bool fmAnchors_Reserve(fmBody* body, int count);

// Set @p body's anchor @p a from a checked record (room reserved; the caller sets the count).
void fmAnchors_Restore(fmBody* body, int a, const fmAnchorRecord* record);

// Release the anchors' memory.
void fmAnchors_Free(fmBody* body);
