// Snapshots: a world's complete simulation state in a caller's buffer, restored so that the
// world continues bit-identically (lockstep networking, replays, rollback).
//
// What a step depends on is saved: every body's positions, velocities, last good state, pins
// (inverse masses follow from them), material and spring stiffness, energy ledger, the cached
// stability limit, and the implicit solver's kept Newton matrix with what it was built with (the
// lazy Hessian reuses it across steps, so a restored world without it would take other Newton
// steps). The world's settings that setters change are saved too. Per-step temporaries (the
// solver's vectors, the damping matrix, the arena) are rebuilt by every step and are not. Bodies
// are matched by slot, generation and counts: a snapshot restores into the world it was taken from,
// with the same bodies (created or destroyed bodies make it refuse, untouched).
#include "snapshot.h"

#include "core.h"
#include "world.h"

#include <string.h>

#define FM_SNAPSHOT_MAGIC 0x4E53464Du // "FMSN"
#define FM_SNAPSHOT_VERSION 2u

// A cursor over the buffer: writing with data == NULL only counts.
typedef struct fmStream
{
	unsigned char* out;      // writing; NULL to count
	const unsigned char* in; // reading
	size_t size;
	size_t used;
	bool overflow;
} fmStream;

static void fmPut(fmStream* s, const void* data, size_t bytes)
{
	if (bytes == 0) // an empty array may be a NULL pointer
		return;
	if (s->out != NULL && !s->overflow && bytes <= s->size - s->used)
		memcpy(s->out + s->used, data, bytes);
	else if (s->out != NULL)
		s->overflow = true;
	s->used += bytes;
}

static void fmGet(fmStream* s, void* data, size_t bytes)
{
	if (bytes == 0)
		return;
	if (s->overflow || bytes > s->size - s->used)
	{
		s->overflow = true;
		memset(data, 0, bytes);
		return;
	}
	memcpy(data, s->in + s->used, bytes);
	s->used += bytes;
}

// One value or array through the stream in either direction.
static void fmMove(fmStream* s, bool save, void* data, size_t bytes)
{
	if (save)
		fmPut(s, data, bytes);
	else
		fmGet(s, data, bytes);
}

static void fmMoveBool(fmStream* s, bool save, bool* value)
{
	uint8_t byte = *value ? 1 : 0;
	fmMove(s, save, &byte, 1);
	*value = byte != 0;
}

static void fmMoveDouble(fmStream* s, bool save, double* value)
{
	fmMove(s, save, value, sizeof *value);
}

static void fmMoveLedger(fmStream* s, bool save, fmEnergyLedger* l)
{
	fmMoveBool(s, save, &l->started);
	double* fields[] = {&l->initialEnergy,    &l->work,
	                    &l->workIn,           &l->floor,
	                    &l->gravityStart,     &l->frameContactWork,
	                    &l->frameGravityWork, &l->measureStep,
	                    &l->plainGood,        &l->framePlain};
	for (size_t k = 0; k < sizeof fields / sizeof fields[0]; ++k)
		fmMoveDouble(s, save, fields[k]);
}

static void fmMoveMaterial(fmStream* s, bool save, fmMaterial* m)
{
	int32_t model = (int32_t)m->model;
	fmMove(s, save, &model, sizeof model);
	m->model = (fmMaterialModel)model;
	fmMoveDouble(s, save, &m->lambda);
	fmMoveDouble(s, save, &m->mu);
	fmMoveDouble(s, save, &m->c01);
	// User energies: function and parameter pointers, valid within the process that saved them.
	fmMove(s, save, &m->stretchEnergy, sizeof m->stretchEnergy);
	fmMove(s, save, &m->invariantEnergy, sizeof m->invariantEnergy);
	fmMove(s, save, &m->userParams, sizeof m->userParams);
}

// The implicit solver's state carried from step to step: a flags byte (bit 0: a kept matrix
// follows, bit 1: the last step started from x + h v, the guess the next one tries first), the
// steps before the other guess is tried again (a byte), then the kept matrix's terms and
// values. A cache that does not exist (no implicit step yet) is saved as none of these;
// restoring "no matrix" into a body that has one marks it stale, which is what the saved body
// would have done.
static bool fmMoveSolverMatrix(fmStream* s, bool save, fmBody* b)
{
	fmImplicitCache* c = b->implicitCache;
	uint8_t flags =
	    (uint8_t)((c != NULL && c->hessianValid ? 1u : 0u) | (c != NULL && c->coasted ? 2u : 0u));
	uint8_t recheck = (uint8_t)(c != NULL ? c->guessRecheck : 0);
	fmMove(s, save, &flags, 1);
	fmMove(s, save, &recheck, 1);
	bool warm = (flags & 2u) || recheck > 0;
	if (!save && warm && (c = fmSolverCache_Get(b)) == NULL)
		return false;
	if (!save && c != NULL)
	{
		c->coasted = (flags & 2u) != 0;
		c->guessRecheck = recheck;
	}
	if (!(flags & 1u))
	{
		if (!save && c != NULL)
			c->hessianValid = false;
		return true;
	}
	if (!save && (c = fmSolverCache_Get(b)) == NULL)
		return false;
	int64_t blocks = c->pattern.blocks;
	fmMove(s, save, &blocks, sizeof blocks);
	if (blocks != c->pattern.blocks)
		return false;
	c->hessianValid = true;
	fmMoveDouble(s, save, &c->hessianInertia);
	fmMoveDouble(s, save, &c->hessianMassDamping);
	fmMoveBool(s, save, &c->hessianDamping);
	fmMoveBool(s, save, &c->hessianExact);
	fmMove(s, save, c->hessian, sizeof(double) * 9 * (size_t)blocks);
	return true;
}

// A body's identity in the snapshot: slot, generation and sizes.
typedef struct fmBodyKey
{
	int32_t slot;
	uint32_t generation;
	int32_t vertexCount;
	int32_t tetCount;
	int32_t edgeCount;
	int32_t forceModel;
} fmBodyKey;

static fmBodyKey fmKeyOf(const fmBody* b, int slot)
{
	fmBodyKey key = {slot,        b->generation, b->vertexCount,
	                 b->tetCount, b->edgeCount,  (int32_t)b->forceModel};
	return key;
}

static void fmMoveBodyState(fmStream* s, bool save, fmBody* b)
{
	size_t n3 = 3 * (size_t)b->vertexCount, n = (size_t)b->vertexCount;
	fmMove(s, save, b->x, sizeof(double) * n3);
	fmMove(s, save, b->v, sizeof(double) * n3);
	fmMove(s, save, b->xGood, sizeof(double) * n3);
	fmMove(s, save, b->vGood, sizeof(double) * n3);
	fmMove(s, save, b->pinned, n);
	fmMove(s, save, b->springK, sizeof(double) * (size_t)b->edgeCount);
	fmMoveMaterial(s, save, &b->material);
	fmMoveDouble(s, save, &b->energyGood);
	fmMoveBool(s, save, &b->energyStale);
	fmMoveDouble(s, save, &b->explicitLimit);
	fmMoveLedger(s, save, &b->ledger);
}

static bool fmMoveBody(fmStream* s, bool save, fmBody* b)
{
	fmMoveBodyState(s, save, b);
	return fmMoveSolverMatrix(s, save, b);
}

// The material saved in body @p b's record at @p offset is one fmMaterial_Validate accepts (a
// corrupted model number would index past the model table).
static bool fmRecordMaterialValid(const fmBody* b, const void* buffer, size_t size, size_t offset)
{
	size_t n = (size_t)b->vertexCount;
	size_t at = offset + sizeof(double) * (12 * n + (size_t)b->edgeCount) + n;
	fmStream s = {NULL, buffer, size, at, false};
	fmMaterial material = b->material;
	fmMoveMaterial(&s, false, &material);
	return !s.overflow && fmMaterial_Validate(&material, NULL) == fm_ok;
}

// Bytes of body @p b's record at @p offset of the buffer (after its key), or SIZE_MAX when the
// record does not fit @p b (another matrix size), the buffer, or holds an invalid material.
static size_t fmBodyRecordBytes(fmBody* b, const void* buffer, size_t size, size_t offset)
{
	if (!fmRecordMaterialValid(b, buffer, size, offset))
		return SIZE_MAX;
	fmStream count = {NULL, NULL, 0, 0, false};
	fmMoveBodyState(&count, true, b);
	fmStream s = {NULL, buffer, size, offset + count.used, false};
	uint8_t present = 0;
	fmGet(&s, &present, 1);
	s.used += 1; // the first guess's recheck countdown
	if (present & 1u)
	{
		int64_t blocks = 0;
		fmGet(&s, &blocks, sizeof blocks);
		fmImplicitCache* c = fmSolverCache_Get(b); // the same mesh gives the same pattern
		if (c == NULL || blocks != c->pattern.blocks)
			return SIZE_MAX;
		s.used += 2 * sizeof(double) + 2 + sizeof(double) * 9 * (size_t)blocks;
	}
	return s.overflow || s.used > size ? SIZE_MAX : s.used - offset;
}

static void fmMoveWorldSettings(fmStream* s, bool save, fmWorld* w)
{
	fmWorldDef* d = &w->def;
	fmMove(s, save, &d->gravity, sizeof d->gravity);
	fmMoveBool(s, save, &d->floor.enabled);
	fmMoveDouble(s, save, &d->floor.height);
	int32_t ints[6] = {(int32_t)d->floor.friction,
	                   (int32_t)d->integrator,
	                   d->newtonIterations,
	                   d->cgIterations,
	                   (int32_t)w->solverOptions.product,
	                   (int32_t)w->solverOptions.preconditioner};
	fmMove(s, save, ints, sizeof ints);
	d->floor.friction = (fmFloorFriction)ints[0];
	d->integrator = (fmIntegrator)ints[1];
	d->newtonIterations = ints[2];
	d->cgIterations = ints[3];
	w->solverOptions.product = (fmProductMode)ints[4];
	w->solverOptions.preconditioner = (fmPreconditioner)ints[5];
	fmMoveDouble(s, save, &d->floor.frictionCoefficient);
	fmMoveDouble(s, save, &d->floor.restitution);
	fmMoveDouble(s, save, &d->floor.maxDepenetrationSpeed);
	fmMoveDouble(s, save, &d->tolerance);
	fmMoveBool(s, save, &d->notConvergedIsError);
	fmMoveBool(s, save, &d->autoSubstep);
	fmMoveBool(s, save, &w->warnedStep);
}

// Write the snapshot (or count it, when @p s->out is NULL).
static void fmWriteSnapshot(fmStream* s, fmWorld* w)
{
	uint32_t header[3] = {FM_SNAPSHOT_MAGIC, FM_SNAPSHOT_VERSION, 0};
	for (int i = 0; i < w->bodyCapacity; ++i)
		header[2] += w->bodies[i].x != NULL;
	fmPut(s, header, sizeof header);
	fmMoveWorldSettings(s, true, w);
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (b->x == NULL)
			continue;
		fmBodyKey key = fmKeyOf(b, i);
		fmPut(s, &key, sizeof key);
		fmMoveBody(s, true, b);
	}
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

// Check that every body record matches a live body of the world, without changing anything.
static fmResult fmCheckSnapshot(fmWorld* w, const void* buffer, size_t size)
{
	fmStream s = {NULL, buffer, size, 0, false};
	uint32_t header[3];
	fmGet(&s, header, sizeof header);
	if (s.overflow || header[0] != FM_SNAPSHOT_MAGIC || header[1] != FM_SNAPSHOT_VERSION)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "not a femto snapshot of version %u", FM_SNAPSHOT_VERSION);
	uint32_t live = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		live += w->bodies[i].x != NULL;
	if (header[2] != live)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot holds %u bodies, the world %u: bodies were created or "
		                   "destroyed since it was taken",
		                   header[2], live);
	return fm_ok;
}

fmResult fmWorld_RestoreSnapshot(fmWorldId worldId, const void* buffer, size_t size)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && buffer != NULL);
	if (w == NULL)
		return fm_errInvalidId;
	if (buffer == NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0, "snapshot buffer is NULL");
	fmResult r = fmCheckSnapshot(w, buffer, size);
	if (r != fm_ok)
		return r;
	// Every body's key is checked before anything is written: a mismatch leaves the world as
	// it was.
	fmStream s = {NULL, buffer, size, 3 * sizeof(uint32_t), false};
	fmWorld settings = *w;
	fmMoveWorldSettings(&s, false, &settings); // to find the bodies; applied last
	size_t bodiesAt = s.used;
	if (s.overflow || fmWorldDef_Validate(&settings.def, NULL) != fm_ok ||
	    (unsigned)settings.solverOptions.product > (unsigned)fm_productMatrixFree ||
	    (unsigned)settings.solverOptions.preconditioner > (unsigned)fm_precondAuto)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the snapshot's world settings are invalid: not restored");
	for (int pass = 0; pass < 2; ++pass)
	{
		s.used = bodiesAt;
		for (int i = 0; i < w->bodyCapacity; ++i)
		{
			fmBody* b = &w->bodies[i];
			if (b->x == NULL)
				continue;
			fmBodyKey key, expected = fmKeyOf(b, i);
			fmGet(&s, &key, sizeof key);
			if (s.overflow || memcmp(&key, &expected, sizeof key) != 0)
				return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
				                   "the snapshot's body in slot %d does not match the world's "
				                   "(another body, or other sizes): not restored",
				                   i);
			if (pass == 0)
			{
				size_t bytes = fmBodyRecordBytes(b, buffer, size, s.used);
				if (bytes == SIZE_MAX)
					return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
					                   "the snapshot's body in slot %d is truncated or has "
					                   "another solver matrix: not restored",
					                   i);
				s.used += bytes;
				continue;
			}
			if (!fmMoveBody(&s, false, b))
				return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
				                   "out of memory restoring body %d's solver matrix", i);
			for (int k = 0; k < b->vertexCount; ++k) // pins are axis masks; inverse masses follow
			{
				b->pinned[k] &= FM_PIN_ALL;
				b->invMass[k] = b->pinned[k] == FM_PIN_ALL ? 0.0 : 1.0 / b->mass[k];
			}
		}
		if (s.overflow)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "the snapshot is truncated (%zu bytes)", size);
	}
	fmMoveWorldSettings(&(fmStream){NULL, buffer, size, 3 * sizeof(uint32_t), false}, false, w);
	return fm_ok;
}
