// Snapshots: a world's complete simulation state in a caller's buffer, restored so that the
// world continues bit-identically (lockstep networking, replays, rollback).
//
// What a step depends on is saved: every body's positions, velocities, last good state, pins
// (inverse masses follow from them), material and spring stiffness, energy ledger, the cached
// stability limit, and the implicit solver's kept Newton matrix with what it was built with and,
// for a body in contact, its base without the contact terms (since version 8) (the lazy Hessian
// reuses both across steps, so a restored world without them would take other Newton steps). The
// world's settings that setters change are saved too (the floor with its filter and the force it
// reported), and the contact state a step reads from the one before (format version 3, the floor's
// filter and force since 4): every collider's pose (kinematic ones move), velocity and angular
// velocity (fmCollider_SetVelocity) and last force and torque; every body's sleep state (asleep, a
// wake asked for, its sleep timer and island) and the implicit collider friction found in the last
// step, which the next step's solve uses (body->contact.frictionNext, saved for the vertices that
// have some, with the static spring's stretch since version 6), and its attachments (glue and
// weld ends, since version 10); and the pairs that touched in the last frame (the next frame's
// begin and end events and islands come from them). Per-step temporaries (the solver's vectors,
// the damping matrix, the arena, the contact stage's buffers, its contact list and events) are
// rebuilt by every step and are not. Bodies are matched by slot, generation and counts, colliders
// by slot, generation, shape and (meshes) vertex and triangle counts: a snapshot restores into
// the world it was taken from, with the same bodies and colliders (created or destroyed ones make
// it refuse, untouched). A mesh collider's triangles are not saved; its vertices moved by
// fmCollider_SetMeshVertices are (version 10: those it has now and a target the next frame moves
// it to, fmGetMeshMotion).
#include "world/snapshot.h"
#include "world/snapshot_body.h"
#include "world/snapshot_stream.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "body/tear_topology.h"
#include "contact/collider.h"
#include "contact/contact_events.h"
#include "contact/friction_anchor.h"
#include "contact/mesh_motion.h"
#include "core/checksum.h"
#include "core/core.h"
#include "world/world.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define FM_SNAPSHOT_MAGIC 0x4E53464Du // "FMSN"
#define FM_SNAPSHOT_VERSION 13u

// The header: magic, version, live bodies, live colliders, the snapshot's length in bytes (two
// words, low first) and its checksum (two words: fmChecksum64 of the whole snapshot with these
// two words zero; since version 7).
#define FM_SNAPSHOT_HEADER_WORDS 8
#define FM_SNAPSHOT_HEADER_BYTES (FM_SNAPSHOT_HEADER_WORDS * sizeof(uint32_t))
#define FM_SNAPSHOT_LENGTH_AT (4 * sizeof(uint32_t))
#define FM_SNAPSHOT_SUM_AT (6 * sizeof(uint32_t))

static void fmMoveWorldSettings(fmStream* s, bool save, fmWorld* w)
{
	fmWorldDef* d = &w->def;
	fmStream_Move(s, save, &d->gravity, sizeof d->gravity);
	fmStream_MoveBool(s, save, &d->floor.enabled);
	fmStream_MoveDouble(s, save, &d->floor.height);
	int32_t ints[6] = {(int32_t)d->floor.friction,
	                   (int32_t)d->integrator,
	                   d->newtonIterations,
	                   d->cgIterations,
	                   (int32_t)w->solverOptions.product,
	                   (int32_t)w->solverOptions.preconditioner};
	fmStream_Move(s, save, ints, sizeof ints);
	d->floor.friction = (fmFloorFriction)ints[0];
	d->integrator = (fmIntegrator)ints[1];
	d->newtonIterations = ints[2];
	d->cgIterations = ints[3];
	w->solverOptions.product = (fmProductMode)ints[4];
	w->solverOptions.preconditioner = (fmPreconditioner)ints[5];
	fmStream_MoveDouble(s, save, &d->floor.frictionCoefficient);
	fmStream_MoveDouble(s, save, &d->floor.restitution);
	fmStream_MoveDouble(s, save, &d->floor.maxDepenetrationSpeed);
	fmStream_Move(s, save, &d->floor.filter, sizeof d->floor.filter);
	fmStream_Move(s, save, &w->floorCollider.force, sizeof w->floorCollider.force);
	fmStream_Move(s, save, &w->floorCollider.torque, sizeof w->floorCollider.torque);
	fmStream_MoveDouble(s, save, &d->tolerance);
	fmStream_MoveBool(s, save, &d->notConvergedIsError);
	fmStream_MoveBool(s, save, &d->autoSubstep);
	fmStream_MoveBool(s, save, &w->warnedStep);
}

// ---- contact state (format version 3) ----------------------------------------------------------

// A collider's identity in the snapshot: slot, generation, shape and a mesh's counts.
typedef struct fmColliderKey
{
	int32_t slot;
	uint32_t generation;
	int32_t shape;
	int32_t vertexCount;
	int32_t triangleCount;
} fmColliderKey;

static fmColliderKey fmColliderKeyOf(const fmCollider* c, int slot)
{
	fmColliderKey key = {slot, c->generation, (int32_t)c->def.shape,
	                     c->mesh != NULL ? c->mesh->vertexCount : 0,
	                     c->mesh != NULL ? c->mesh->triangleCount : 0};
	return key;
}

static int fmLiveColliders(const fmWorld* w)
{
	int live = 0;
	for (int k = 0; k < w->colliderCapacity; ++k)
		live += w->colliders[k].inUse;
	return live;
}

// A collider's state: its pose (a kinematic one moves), its velocities (fmCollider_SetVelocity)
// and the force and torque of the last step (fmCollider_GetContactForce).
static void fmMoveColliderState(fmStream* s, bool save, fmCollider* c)
{
	fmStream_Move(s, save, &c->position, sizeof c->position);
	fmStream_Move(s, save, &c->rotation, sizeof c->rotation);
	fmStream_Move(s, save, &c->def.velocity, sizeof c->def.velocity);
	fmStream_Move(s, save, &c->def.angularVelocity, sizeof c->def.angularVelocity);
	fmStream_Move(s, save, &c->force, sizeof c->force);
	fmStream_Move(s, save, &c->torque, sizeof c->torque);
}

#define FM_COLLIDER_RECORD_BYTES (sizeof(fmColliderKey) + 5 * sizeof(fmVec3) + sizeof(fmMat3))

static bool fmVecWithin(fmVec3 v, double limit)
{
	return fabs(v.x) <= limit && fabs(v.y) <= limit && fabs(v.z) <= limit;
}

// A pose and velocities the contact stage can work with: finite, a rotation's entries within
// [-2, 2] (a rotation drifts by round-off only), velocities within fmCollider_SetVelocity's 1e6.
static bool fmColliderStateValid(const fmCollider* c)
{
	bool rotation = true;
	for (int k = 0; k < 9; ++k)
		rotation = rotation && fabs(c->rotation.m[k]) <= 2.0;
	return rotation && fmVecWithin(c->position, DBL_MAX) && fmVecWithin(c->def.velocity, 1e6) &&
	       fmVecWithin(c->def.angularVelocity, 1e6);
}

// The implicit collider friction the last step found for vertex i (penalty.h), or NULL: its
// limit mu lambda is > 0 exactly where the contact stage wrote it (the rest is zero).
static const double* fmFrictionFound(const fmBody* b, int i)
{
	const double* f =
	    b->contact.frictionNext ? b->contact.frictionNext + (size_t)FM_FRICTION_STRIDE * i : NULL;
	return f != NULL && f[3] > 0.0 ? f : NULL;
}

#define FM_FRICTION_RECORD_BYTES (sizeof(int32_t) + FM_FRICTION_STRIDE * sizeof(double))

// A barrier pair's friction spring (fmBarrierStretch): its stencil's four body slots and four
// vertices, the kind byte, the weights, the relative position and the stretch.
#define FM_STRETCH_RECORD_BYTES (8 * sizeof(int32_t) + 1 + 10 * sizeof(double))

static void fmPutStretch(fmStream* s, const fmBarrierStretch* r)
{
	for (int k = 0; k < 4; ++k)
	{
		int32_t body = r->stencil.body[k], vertex = r->stencil.vertex[k];
		fmStream_Put(s, &body, sizeof body);
		fmStream_Put(s, &vertex, sizeof vertex);
	}
	uint8_t edgeEdge = r->stencil.edgeEdge ? 1u : 0u;
	fmStream_Put(s, &edgeEdge, 1);
	fmStream_Put(s, r->w, 4 * sizeof(double));
	fmStream_Put(s, &r->relative, 3 * sizeof(double));
	fmStream_Put(s, &r->stretch, 3 * sizeof(double));
}

// Read a stretch record into @p r; returns its kind byte (0 or 1 when valid).
static uint8_t fmGetStretch(fmStream* s, fmBarrierStretch* r)
{
	for (int k = 0; k < 4; ++k)
	{
		int32_t body = -1, vertex = -1;
		fmStream_Get(s, &body, sizeof body);
		fmStream_Get(s, &vertex, sizeof vertex);
		r->stencil.body[k] = body;
		r->stencil.vertex[k] = vertex;
	}
	uint8_t edgeEdge = 0;
	fmStream_Get(s, &edgeEdge, 1);
	r->stencil.edgeEdge = edgeEdge != 0;
	fmStream_Get(s, r->w, 4 * sizeof(double));
	fmStream_Get(s, &r->relative, 3 * sizeof(double));
	fmStream_Get(s, &r->stretch, 3 * sizeof(double));
	return edgeEdge;
}

// Whether all @p count doubles at @p v are finite.
static bool fmAllFinite(const double* v, int count)
{
	for (int k = 0; k < count; ++k)
		if (!isfinite(v[k]))
			return false;
	return true;
}

// Whether stretch record @p r names live bodies' vertices with finite numbers. (A body's records
// may name a body destroyed since its last step: those are not saved, and never matched.)
static bool fmStretchNamesLive(const fmWorld* w, const fmBarrierStretch* r)
{
	for (int k = 0; k < 4; ++k)
	{
		int body = r->stencil.body[k];
		if (body < 0 || body >= w->bodyCapacity || !fmBody_IsLive(&w->bodies[body]) ||
		    r->stencil.vertex[k] < 0 || r->stencil.vertex[k] >= w->bodies[body].mesh.vertexCount)
			return false;
	}
	const double numbers[10] = {r->w[0],       r->w[1],       r->w[2],       r->w[3],
	                            r->relative.x, r->relative.y, r->relative.z, r->stretch.x,
	                            r->stretch.y,  r->stretch.z};
	return fmAllFinite(numbers, 10);
}

// Whether stretch record @p r is one a snapshot holds: live names, finite numbers, a kind byte
// of 0 or 1, after @p last (NULL: first).
static bool fmStretchValid(const fmWorld* w, const fmBarrierStretch* r,
                           const fmBarrierStretch* last, uint8_t kind)
{
	return kind <= 1u && fmStretchNamesLive(w, r) &&
	       (last == NULL || fmBarrierStencil_Compare(&last->stencil, &r->stencil) < 0);
}

// A body's contact state: a flags byte (bit 0 asleep, bit 1 a wake asked for), its sleep timer
// and island, then the count of vertices with friction for the next step, each as its index and
// its FM_FRICTION_STRIDE doubles, then the count of its barrier pairs' stretches and each.
static void fmPutBodyContact(fmStream* s, const fmWorld* w, const fmBody* b)
{
	uint8_t flags = (uint8_t)((b->asleep ? 1u : 0u) | (b->wakeRequested ? 2u : 0u));
	int32_t island = b->island, count = 0;
	fmStream_Put(s, &flags, 1);
	fmStream_Put(s, &b->sleepTimer, sizeof b->sleepTimer);
	fmStream_Put(s, &island, sizeof island);
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		count += fmFrictionFound(b, i) != NULL;
	fmStream_Put(s, &count, sizeof count);
	for (int32_t i = 0; i < b->mesh.vertexCount; ++i)
	{
		const double* f = fmFrictionFound(b, i);
		if (f == NULL)
			continue;
		fmStream_Put(s, &i, sizeof i);
		fmStream_Put(s, f, FM_FRICTION_STRIDE * sizeof(double));
	}
	int32_t stretches = 0;
	for (int k = 0; k < b->contact.stretchCount; ++k)
		stretches += fmStretchNamesLive(w, &b->contact.stretch[k]);
	fmStream_Put(s, &stretches, sizeof stretches);
	for (int k = 0; k < b->contact.stretchCount; ++k)
		if (fmStretchNamesLive(w, &b->contact.stretch[k]))
			fmPutStretch(s, &b->contact.stretch[k]);
	int32_t anchors = b->anchorCount;
	fmStream_Put(s, &anchors, sizeof anchors);
	for (int a = 0; a < anchors; ++a)
	{
		fmAnchorRecord record = fmAnchors_Record(b, a);
		fmStream_Put(s, &record, sizeof record);
	}
}

// The contact section: the substep the contact stage last worked on, every live collider (key
// and state), every live body's contact state, the last frame's pairs (a count and the sorted
// keys of fmContactEvents_FramePairs).
static void fmPutContact(fmStream* s, fmWorld* w)
{
	fmStream_Put(s, &w->contactStep, sizeof w->contactStep);
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		if (!w->colliders[k].inUse)
			continue;
		fmColliderKey key = fmColliderKeyOf(&w->colliders[k], k);
		fmStream_Put(s, &key, sizeof key);
		fmMoveColliderState(s, true, &w->colliders[k]);
		const fmMeshShape* m = w->colliders[k].mesh;
		uint8_t flags = m != NULL ? (uint8_t)fmMeshMotion_Flags(m) : 0;
		if (m != NULL) // its moved vertices (version 10): fmGetMeshMotion
			fmStream_Put(s, &flags, 1);
		for (int a = 0; a < 2 && (flags >> a & 1); ++a)
			fmStream_Put(s, a == 0 ? m->vertices : m->motion->to,
			             sizeof(fmVec3) * (size_t)m->vertexCount);
	}
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			fmPutBodyContact(s, w, &w->bodies[i]);
	const uint64_t* pairs;
	int32_t count = fmContactEvents_FramePairs(w, &pairs);
	fmStream_Put(s, &count, sizeof count);
	fmStream_Put(s, pairs, sizeof(uint64_t) * (size_t)count);
}

// Write the snapshot (or count it, when @p s->out is NULL).
static void fmWriteSnapshot(fmStream* s, fmWorld* w)
{
	uint32_t header[FM_SNAPSHOT_HEADER_WORDS] = {
	    FM_SNAPSHOT_MAGIC, FM_SNAPSHOT_VERSION, 0, (uint32_t)fmLiveColliders(w), 0, 0, 0, 0};
	for (int i = 0; i < w->bodyCapacity; ++i)
		header[2] += fmBody_IsLive(&w->bodies[i]);
	fmStream_Put(s, header, sizeof header);
	fmMoveWorldSettings(s, true, w);
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			fmSnapshotBody_PutTopology(s, &w->bodies[i]);
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		fmBodyKey key = fmSnapshotBody_Key(b, i);
		fmStream_Put(s, &key, sizeof key);
		fmSnapshotBody_Move(s, true, b);
	}
	fmPutContact(s, w);
	if (s->out != NULL && !s->overflow)
		fmSnapshot_Seal(s->out, s->used);
}

// A 64-bit value into the header at byte @p at, as two 32-bit words, low first.
static void fmPutWide(unsigned char* buffer, size_t at, uint64_t value)
{
	uint32_t words[2] = {(uint32_t)value, (uint32_t)(value >> 32)};
	memcpy(buffer + at, words, sizeof words);
}

static uint64_t fmGetWide(const unsigned char* buffer, size_t at)
{
	uint32_t words[2];
	memcpy(words, buffer + at, sizeof words);
	return (uint64_t)words[1] << 32 | words[0];
}

// The checksum of the snapshot's @p length bytes with its checksum words read as zero.
static uint64_t fmSnapshotSum(const unsigned char* buffer, size_t length)
{
	const unsigned char zero[8] = {0};
	uint64_t h = fmChecksum64(buffer, FM_SNAPSHOT_SUM_AT, 0);
	h = fmChecksum64(zero, sizeof zero, h);
	return fmChecksum64(buffer + FM_SNAPSHOT_HEADER_BYTES, length - FM_SNAPSHOT_HEADER_BYTES, h);
}

void fmSnapshot_Seal(void* buffer, size_t length)
{
	if (length < FM_SNAPSHOT_HEADER_BYTES)
		return;
	fmPutWide(buffer, FM_SNAPSHOT_LENGTH_AT, (uint64_t)length);
	fmPutWide(buffer, FM_SNAPSHOT_SUM_AT, fmSnapshotSum(buffer, length));
}

size_t fmWorld_GetSnapshotSize(fmWorldId worldId)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL);
	if (w == NULL)
		return 0;
	fmStream s = {NULL, NULL, 0, 0, false};
	fmWriteSnapshot(&s, w);
	return s.used;
}

fmResult fmWorld_SaveSnapshot(fmWorldId worldId, void* buffer, size_t size, size_t* written)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && buffer != NULL);
	if (written)
		*written = 0;
	if (w == NULL)
		return fm_errInvalidId;
	if (buffer == NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0, "snapshot buffer is NULL");
	size_t needed = fmWorld_GetSnapshotSize(worldId);
	if (size < needed)
		return fmDiagError(&w->lastError, fm_errLimit, "", 0, 0,
		                   "the snapshot needs %zu bytes, the buffer has %zu "
		                   "(fmWorld_GetSnapshotSize)",
		                   needed, size);
	fmStream s = {buffer, NULL, size, 0, false};
	fmWriteSnapshot(&s, w);
	if (written)
		*written = s.used;
	return fm_ok;
}

// ---- restoring: everything checked first, then applied ----------------------------------------

// Check the header: a snapshot of this version, of as many bodies and colliders as the world has.
static fmResult fmCheckSnapshot(fmWorld* w, const void* buffer, size_t size)
{
	fmStream s = {NULL, buffer, size, 0, false};
	uint32_t header[FM_SNAPSHOT_HEADER_WORDS];
	fmStream_Get(&s, header, sizeof header);
	if (s.overflow || header[0] != FM_SNAPSHOT_MAGIC || header[1] != FM_SNAPSHOT_VERSION)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "not a femto snapshot of version %u", FM_SNAPSHOT_VERSION);
	uint64_t length = fmGetWide(buffer, FM_SNAPSHOT_LENGTH_AT);
	if (length < FM_SNAPSHOT_HEADER_BYTES || length > size)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot is truncated or corrupt: it says it is %llu bytes long, "
		                   "the buffer given has %zu",
		                   (unsigned long long)length, size);
	if (fmSnapshotSum(buffer, (size_t)length) != fmGetWide(buffer, FM_SNAPSHOT_SUM_AT))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot is corrupt: its checksum does not match its %llu bytes "
		                   "(changed since it was saved)",
		                   (unsigned long long)length);
	uint32_t live = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		live += fmBody_IsLive(&w->bodies[i]);
	if (header[2] != live)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot holds %u bodies, the world %u: bodies were created or "
		                   "destroyed since it was taken",
		                   header[2], live);
	if (header[3] != (uint32_t)fmLiveColliders(w))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot holds %u colliders, the world %d: colliders were created "
		                   "or destroyed since it was taken",
		                   header[3], fmLiveColliders(w));
	return fm_ok;
}

// The world settings at the stream's position into @p settings (a copy of the world), checked.
static fmResult fmCheckSettings(fmWorld* w, fmStream* s, fmWorld* settings)
{
	*settings = *w;
	fmMoveWorldSettings(s, false, settings);
	if (s->overflow || fmWorldDef_Validate(&settings->def, NULL) != fm_ok ||
	    !fmVecWithin(settings->floorCollider.force, DBL_MAX) ||
	    !fmVecWithin(settings->floorCollider.torque, DBL_MAX) ||
	    (unsigned)settings->solverOptions.product > (unsigned)fm_productMatrixFree ||
	    (unsigned)settings->solverOptions.preconditioner > (unsigned)fm_precondAuto)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot's world settings are invalid: not restored");
	return fm_ok;
}

// One pass over the body records at the stream's position: pass 0 checks every key and record
// (changing nothing), pass 1 restores them.
static fmResult fmBodiesPass(fmWorld* w, fmStream* s, int pass)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		fmBodyKey key, expected = fmSnapshotBody_Key(b, i);
		fmStream_Get(s, &key, sizeof key);
		if (s->overflow || memcmp(&key, &expected, sizeof key) != 0)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "the snapshot's body in slot %d does not match the world's "
			                   "(another body, or other sizes): not restored",
			                   i);
		if (pass == 0)
		{
			size_t bytes = fmSnapshotBody_RecordBytes(b, s->in, s->size, s->used);
			if (bytes == SIZE_MAX)
				return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
				                   "the snapshot's body in slot %d is truncated or has "
				                   "another solver matrix: not restored",
				                   i);
			s->used += bytes;
			continue;
		}
		if (!fmSnapshotBody_Move(s, false, b))
			return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                   "out of memory restoring body %d's solver matrix", i);
		for (int k = 0; k < b->mesh.vertexCount; ++k) // pins are axis masks; inverse masses follow
		{
			b->state.pinned[k] &= FM_PIN_ALL;
			b->state.invMass[k] = b->state.pinned[k] == FM_PIN_ALL ? 0.0 : 1.0 / b->mesh.mass[k];
		}
	}
	if (s->overflow)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot is truncated (%zu bytes)", s->size);
	return fm_ok;
}

// A mesh collider's record after its state: a flags byte (fmMeshMotion_Flags), its vertices now
// when moved, its target when pending. Steps over it, pointing @p at to the two arrays (NULL when
// absent); returns the flags, or -1 when truncated or invalid.
static int fmGetMeshMotion(fmStream* s, const fmMeshShape* m, const void* at[2])
{
	uint8_t flags = 0;
	fmStream_Get(s, &flags, 1);
	for (int a = 0; a < 2; ++a)
	{
		at[a] = (flags >> a & 1) && !s->overflow ? s->in + s->used : NULL;
		if (at[a] != NULL)
			fmStream_Skip(s, sizeof(fmVec3) * (size_t)m->vertexCount);
		if (at[a] != NULL && !s->overflow && fmMeshMotion_Problem(m, at[a], m->vertexCount))
			return -1;
	}
	return s->overflow || flags == 2 || flags > 3 ? -1 : flags;
}

static const char* fmShapeName(int32_t shape)
{
	static const char* const names[] = {"plane", "sphere", "box", "capsule", "mesh"};
	return shape >= 0 && shape < (int32_t)fm_shapeTypeCount ? names[shape] : "unknown shape";
}

// The error for a collider record whose key is not the world's collider in that slot.
static fmResult fmColliderMismatch(fmWorld* w, const fmColliderKey* saved,
                                   const fmColliderKey* live)
{
	int slot = live->slot;
	if (saved->slot != live->slot || saved->generation != live->generation ||
	    saved->shape != live->shape)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot's collider in slot %d (a %s, generation %u) is not the "
		                   "world's (a %s in slot %d, generation %u): colliders were destroyed "
		                   "and created since it was taken: not restored",
		                   saved->slot, fmShapeName(saved->shape), saved->generation,
		                   fmShapeName(live->shape), slot, live->generation);
	return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
	                   "the snapshot's mesh collider in slot %d has %d triangles and %d vertices, "
	                   "the world's %d and %d: not restored",
	                   slot, saved->triangleCount, saved->vertexCount, live->triangleCount,
	                   live->vertexCount);
}

// Check every collider record (key and state) at the stream's position, changing nothing.
static fmResult fmCheckColliders(fmWorld* w, fmStream* s)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmCollider copy = w->colliders[k];
		if (!copy.inUse)
			continue;
		fmColliderKey key, expected = fmColliderKeyOf(&copy, k);
		fmStream_Get(s, &key, sizeof key);
		if (!s->overflow && memcmp(&key, &expected, sizeof key) != 0)
			return fmColliderMismatch(w, &key, &expected);
		fmMoveColliderState(s, false, &copy);
		const void* at[2];
		int flags = copy.mesh != NULL ? fmGetMeshMotion(s, copy.mesh, at) : 0;
		if (s->overflow || !fmColliderStateValid(&copy) || flags < 0)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "the snapshot's collider in slot %d is truncated or has a "
			                   "non-finite pose, velocity or mesh vertex: not restored",
			                   k);
		if ((flags & 1) && !fmMeshMotion_Reserve(w, copy.mesh)) // (changes no step)
			return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                   "out of memory restoring the moving mesh collider in slot %d", k);
	}
	return fm_ok;
}

// Check body @p b's attachments at the stream's position (a count, then each record) and step
// over them, reserving room for them (keeping what the body holds).
static fmResult fmCheckAnchors(const fmWorld* w, fmStream* s, fmBody* b)
{
	int32_t count = -1;
	fmStream_Get(s, &count, sizeof count);
	if (s->overflow || count < 0 || count > FM_MAX_ANCHORS_PER_VERTEX * b->mesh.vertexCount ||
	    (size_t)count > (s->size - s->used) / sizeof(fmAnchorRecord))
		return fm_errParameter;
	for (int32_t a = 0; a < count; ++a)
	{
		fmAnchorRecord record;
		fmStream_Get(s, &record, sizeof record);
		if (s->overflow || fmAnchors_RecordProblem(w, b, &record) != NULL)
			return fm_errParameter;
	}
	return fmAnchors_Reserve(b, count) ? fm_ok : fm_errOutOfMemory;
}

// Check body @p b's contact record at the stream's position and step over it: flags, an island
// that is a body slot, friction vertices ascending within the body. A body that gets friction
// and has no array for it yet gets a zeroed one (what a missing array means to the step).
static fmResult fmCheckBodyContact(const fmWorld* w, fmStream* s, fmBody* b)
{
	uint8_t flags = 0;
	int32_t island = 0, count = 0, last = -1;
	fmStream_Get(s, &flags, 1);
	fmStream_Skip(s, sizeof(double)); // the sleep timer
	fmStream_Get(s, &island, sizeof island);
	fmStream_Get(s, &count, sizeof count);
	if (s->overflow || flags > 3u || island < 0 || island >= w->bodyCapacity || count < 0 ||
	    count > b->mesh.vertexCount || (size_t)count * FM_FRICTION_RECORD_BYTES > s->size - s->used)
		return fm_errParameter;
	for (int32_t k = 0; k < count; ++k)
	{
		int32_t vertex = -1;
		double f[FM_FRICTION_STRIDE];
		fmStream_Get(s, &vertex, sizeof vertex);
		fmStream_Get(s, f, sizeof f);
		// Finite, a limit (saved where > 0), a stiffness cap > 0 (fmSlipWidth divides by it) and
		// a collider slot + 1 that is a whole number in range (the booking skips a slot not in
		// use).
		if (s->overflow || vertex <= last || vertex >= b->mesh.vertexCount ||
		    !fmAllFinite(f, FM_FRICTION_STRIDE) || !(f[3] > 0.0) || !(f[11] > 0.0) ||
		    !(f[12] >= 0.0 && f[12] <= FM_FLOOR_SLOT + 1 && (double)(int)f[12] == f[12]))
			return fm_errParameter;
		last = vertex;
	}
	int32_t stretches = -1;
	fmStream_Get(s, &stretches, sizeof stretches);
	if (s->overflow || stretches < 0 ||
	    (size_t)stretches > (s->size - s->used) / FM_STRETCH_RECORD_BYTES)
		return fm_errParameter;
	fmBarrierStretch record, previous;
	for (int32_t k = 0; k < stretches; ++k)
	{
		uint8_t kind = fmGetStretch(s, &record);
		if (s->overflow || !fmStretchValid(w, &record, k > 0 ? &previous : NULL, kind))
			return fm_errParameter;
		previous = record;
	}
	fmResult anchors = fmCheckAnchors(w, s, b);
	if (anchors != fm_ok)
		return anchors;
	if (count > 0 && b->contact.frictionNext == NULL)
		b->contact.frictionNext =
		    FM_ALLOC_ZERO(double, (size_t)FM_FRICTION_STRIDE * b->mesh.vertexCount);
	if (count > 0 && b->contact.frictionNext == NULL)
		return fm_errOutOfMemory;
	// Grown keeping what is there: a later refusal leaves the body as it was.
	return fmGrowArray((void**)&b->contact.stretch, &b->contact.stretchCapacity,
	                   b->contact.stretchCount, stretches, sizeof *b->contact.stretch)
	           ? fm_ok
	           : fm_errOutOfMemory;
}

// Step over a body's contact record (checked).
static void fmSkipBodyContact(fmStream* s)
{
	int32_t count = 0;
	fmStream_Skip(s, 1 + sizeof(double) + sizeof(int32_t));
	fmStream_Get(s, &count, sizeof count);
	fmStream_Skip(s, (size_t)count * FM_FRICTION_RECORD_BYTES);
	fmStream_Get(s, &count, sizeof count);
	fmStream_Skip(s, (size_t)count * FM_STRETCH_RECORD_BYTES);
	fmStream_Get(s, &count, sizeof count);
	fmStream_Skip(s, (size_t)count * sizeof(fmAnchorRecord));
}

// Restore body @p b's contact record (checked) from the stream's position.
static void fmApplyBodyContact(fmStream* s, fmBody* b)
{
	uint8_t flags = 0;
	int32_t island = 0, count = 0;
	fmStream_Get(s, &flags, 1);
	fmStream_Get(s, &b->sleepTimer, sizeof b->sleepTimer);
	fmStream_Get(s, &island, sizeof island);
	fmStream_Get(s, &count, sizeof count);
	b->asleep = (flags & 1u) != 0;
	b->wakeRequested = (flags & 2u) != 0;
	b->island = island;
	if (b->contact.frictionNext != NULL)
		memset(b->contact.frictionNext, 0,
		       sizeof(double) * (size_t)FM_FRICTION_STRIDE * b->mesh.vertexCount);
	for (int32_t k = 0; k < count; ++k)
	{
		int32_t vertex = 0;
		fmStream_Get(s, &vertex, sizeof vertex);
		fmStream_Get(s, b->contact.frictionNext + (size_t)FM_FRICTION_STRIDE * vertex,
		             FM_FRICTION_STRIDE * sizeof(double));
	}
	int32_t stretches = 0;
	fmStream_Get(s, &stretches, sizeof stretches);
	for (int32_t k = 0; k < stretches; ++k)
		(void)fmGetStretch(s, &b->contact.stretch[k]);
	b->contact.stretchCount = stretches;
	int32_t anchors = 0;
	fmStream_Get(s, &anchors, sizeof anchors);
	for (int32_t a = 0; a < anchors; ++a)
	{
		fmAnchorRecord record;
		fmStream_Get(s, &record, sizeof record);
		fmAnchors_Restore(b, a, &record);
	}
	b->anchorCount = anchors;
}

// Check the last frame's pairs at the stream's position: a count that fits, keys ascending, each
// of a body slot and another body's slot or a collider's (0x80000000 | slot) within the world's
// tables (or the floor's, FM_FLOOR_SLOT). Returns the count, or -1.
static int32_t fmCheckPairs(const fmWorld* w, fmStream* s)
{
	int32_t count = -1;
	fmStream_Get(s, &count, sizeof count);
	if (s->overflow || count < 0 || (size_t)count > (s->size - s->used) / sizeof(uint64_t))
		return -1;
	uint64_t last = 0;
	for (int32_t k = 0; k < count; ++k)
	{
		uint64_t key = 0;
		fmStream_Get(s, &key, sizeof key);
		uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
		uint32_t collider = b & 0x7fffffffu;
		bool other = (b & 0x80000000u) ? collider < (uint32_t)w->colliderCapacity ||
		                                     collider == (uint32_t)FM_FLOOR_SLOT
		                               : b < (uint32_t)w->bodyCapacity;
		if ((k > 0 && key <= last) || a >= (uint32_t)w->bodyCapacity || !other)
			return -1;
		last = key;
	}
	return count;
}

// Check the contact section at the stream's position (changing nothing the step sees).
static fmResult fmCheckContact(fmWorld* w, fmStream* s)
{
	double step = 0.0;
	fmStream_Get(s, &step, sizeof step);
	if (s->overflow || !(step >= 0.0 && step <= FM_MAX_SUBSTEP))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot's contact section is truncated or invalid: not restored");
	fmResult r = fmCheckColliders(w, s);
	for (int i = 0; r == fm_ok && i < w->bodyCapacity; ++i)
	{
		fmResult body =
		    fmBody_IsLive(&w->bodies[i]) ? fmCheckBodyContact(w, s, &w->bodies[i]) : fm_ok;
		if (body == fm_errOutOfMemory)
			r = fmDiagError(&w->lastError, body, "", 0, 0,
			                "out of memory restoring body %d's collider friction or attachments",
			                i);
		else if (body != fm_ok)
			r = fmDiagError(&w->lastError, body, "", 0, 0,
			                "the snapshot's contact state of the body in slot %d (sleep, island, "
			                "collider friction, attachments) is truncated or invalid: not restored",
			                i);
	}
	if (r == fm_ok && fmCheckPairs(w, s) < 0)
		r = fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                "the snapshot's contact pairs of the last frame are truncated or "
		                "invalid: not restored");
	return r;
}

// Step over the (checked) collider records, restoring them when @p apply.
static void fmColliderRecords(fmStream* s, fmWorld* w, bool apply)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmCollider* c = &w->colliders[k];
		if (!c->inUse)
			continue;
		fmStream_Skip(s, sizeof(fmColliderKey));
		if (apply)
			fmMoveColliderState(s, false, c);
		else
			fmStream_Skip(s, FM_COLLIDER_RECORD_BYTES - sizeof(fmColliderKey));
		const void* at[2];
		int flags = c->mesh != NULL ? fmGetMeshMotion(s, c->mesh, at) : 0;
		if (apply && c->mesh != NULL)
			fmMeshMotion_Restore(c->mesh, flags, at[0], at[1]);
	}
}

// Restore the contact section (checked) at @p at: the pairs first (the only part that may need
// memory: out of memory leaves the world as it was), then the colliders and the bodies.
static fmResult fmApplyContact(fmWorld* w, const void* buffer, size_t size, size_t at)
{
	fmStream s = {NULL, buffer, size, at + sizeof w->contactStep, false};
	fmColliderRecords(&s, w, false);
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			fmSkipBodyContact(&s);
	int32_t count = 0;
	fmStream_Get(&s, &count, sizeof count);
	if (!fmContactEvents_SetFramePairs(w, (const unsigned char*)buffer + s.used, count))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory restoring the contact pairs");
	s.used = at;
	fmStream_Get(&s, &w->contactStep, sizeof w->contactStep);
	fmColliderRecords(&s, w, true);
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
		{
			fmApplyBodyContact(&s, &w->bodies[i]);
			if (w->bodies[i].anchorCount > 0)
				fmAnchors_Enable(w);
		}
	return fm_ok;
}

// Check every body's topology record (version 13) at the stream's position; @p differs: some
// body must change its topology to take the snapshot.
static fmResult fmCheckTopologies(fmWorld* w, fmStream* s, bool* differs)
{
	*differs = false;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		if (!fmBody_IsLive(&w->bodies[i]))
			continue;
		int count = 0, check = fmSnapshotBody_CheckTopology(s, &w->bodies[i], &count);
		if (check == -2)
			return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                   "out of memory checking the torn topology of body %d", i);
		if (check < 0)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "the snapshot's torn topology of the body in slot %d is not one "
			                   "it can take (another mesh, or corrupted): not restored",
			                   i);
		int held = fmTearTopology_HighestHeld(w, &w->bodies[i]);
		if (check == 1 && held >= count)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "the snapshot's body in slot %d has %d vertices (less torn than "
			                   "now), but its vertex %d is held by a target, an attachment, a "
			                   "prescribed displacement or a pressure: release them first; not "
			                   "restored",
			                   i, count, held);
		*differs = *differs || check == 1;
	}
	return fm_ok;
}

// Give the bodies the snapshot's topologies (checked), a copy of the world kept in @p backup
// first (the rest of the restore may still refuse the snapshot: then the copy goes back).
static fmResult fmApplyTopologies(fmWorld* w, fmWorldId worldId, fmStream* s, void** backup,
                                  size_t* backupSize)
{
	*backupSize = fmWorld_GetSnapshotSize(worldId);
	*backup = fmAlloc(*backupSize);
	if (*backup == NULL || fmWorld_SaveSnapshot(worldId, *backup, *backupSize, NULL) != fm_ok)
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory keeping the world while its torn bodies change");
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]) && !fmSnapshotBody_ApplyTopology(s, w, &w->bodies[i]))
			return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                   "out of memory giving body %d its torn topology", i);
	return fm_ok;
}

static fmResult fmRestoreIn(fmWorldId worldId, fmWorld* w, const void* buffer, size_t size);
static fmResult fmRestoreBodies(fmWorld* w, fmStream* s, const void* buffer, size_t size);

fmResult fmWorld_RestoreSnapshot(fmWorldId worldId, const void* buffer, size_t size)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && buffer != NULL);
	if (w == NULL)
		return fm_errInvalidId;
	if (buffer == NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0, "snapshot buffer is NULL");
	return fmRestoreIn(worldId, w, buffer, size);
}

static fmResult fmRestoreIn(fmWorldId worldId, fmWorld* w, const void* buffer, size_t size)
{
	// Everything is checked before anything is written: a mismatch leaves the world as it was.
	// (Torn bodies change their topology first, the world kept to go back to.)
	fmResult r = fmCheckSnapshot(w, buffer, size);
	if (r == fm_ok)
		size = (size_t)fmGetWide(buffer, FM_SNAPSHOT_LENGTH_AT); // checked: within the buffer
	fmStream s = {NULL, buffer, size, FM_SNAPSHOT_HEADER_BYTES, false};
	fmWorld settings;
	if (r == fm_ok)
		r = fmCheckSettings(w, &s, &settings); // applied last
	size_t topologyAt = s.used;
	bool differs = false;
	if (r == fm_ok)
		r = fmCheckTopologies(w, &s, &differs);
	void* backup = NULL;
	size_t backupSize = 0;
	if (r == fm_ok && differs)
	{
		fmStream t = {NULL, buffer, size, topologyAt, false};
		r = fmApplyTopologies(w, worldId, &t, &backup, &backupSize);
	}
	if (r == fm_ok)
		r = fmRestoreBodies(w, &s, buffer, size);
	if (r != fm_ok && backup != NULL)
	{
		fmDiagnostic error = w->lastError;
		fmRestoreIn(worldId, w, backup, backupSize); // (the world's own: it takes it)
		w->lastError = error;
	}
	if (backup != NULL)
		fmDealloc(backup, backupSize);
	return r;
}

// The rest of a restore after the topologies: the bodies, the contact state, the settings.
static fmResult fmRestoreBodies(fmWorld* w, fmStream* sp, const void* buffer, size_t size)
{
	fmStream s = *sp;
	size_t bodiesAt = s.used;
	fmResult r = fmBodiesPass(w, &s, 0);
	size_t contactAt = s.used;
	if (r == fm_ok)
		r = fmCheckContact(w, &s);
	if (r == fm_ok)
		r = fmApplyContact(w, buffer, size, contactAt);
	s.used = bodiesAt;
	if (r == fm_ok)
		r = fmBodiesPass(w, &s, 1);
	fmWorld_MovedVertices(w);
	for (int i = 0; r == fm_ok && i < w->bodyCapacity; ++i)
		w->bodies[i].previousValid = false; // restored: nothing to interpolate from
	if (r != fm_ok)
		return r;
	fmMoveWorldSettings(&(fmStream){NULL, buffer, size, FM_SNAPSHOT_HEADER_BYTES, false}, false, w);
	fmWorldSyncFloor(w);
	return fm_ok;
}
