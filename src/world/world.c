// Worlds: definitions and their checks, creation and destruction, ids, settings, the explicit
// stability estimate; the frame step is step.c's.
#include "world/world.h"
#include "core/det_math.h"

#include "contact/collider.h"
#include "contact/contact.h"
#include "contact/contact_events.h"
#include "contact/contact_state.h"
#include "contact/floor.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "core/simd.h"
#include "core/timer.h"
#include "fem/forces.h"
#include "world/explicit.h"
#include "world/implicit.h"
#include "world/island.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define FM_MAX_WORLDS 128

static fmWorld s_worlds[FM_MAX_WORLDS];

fmFloorDef fmDefaultFloorDef(void)
{
	fmFloorDef floor;
	memset(&floor, 0, sizeof floor);
	floor.enabled = true;
	floor.height = 0.0;
	floor.friction = fm_floorStick;
	floor.frictionCoefficient = 0.5;
	floor.restitution = 0.0;
	floor.maxDepenetrationSpeed = 1.0;
	floor.filter = fmDefaultFilter();
	return floor;
}

fmWorldDef fmDefaultWorldDef(void)
{
	fmWorldDef def;
	memset(&def, 0, sizeof def);
	def.gravity = fmMakeVec3(0.0, -9.8, 0.0);
	def.floor = fmDefaultFloorDef();
	def.floor.height = -3.0;
	def.integrator = fm_explicit;
	def.newtonIterations = 20;
	def.tolerance = FM_TOLERANCE_ACCURATE;
	def.cgIterations = 500;
	def.maxBodies = 64;
	def.workerCount = 1;
	def.maxNewtonPerFrame = 1000000;
	def.maxSubstepsPerFrame = FM_MAX_SUBSTEPS;
	def.memoryBudget = FM_DEFAULT_MEMORY_BUDGET;
	def.contact.bodies = true;
	def.contact.friction = 0.5;
	def.contact.iterations = 4;
	def.contact.sleepSpeed = 0.05;
	def.contact.sleepTime = 0.5;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

static bool fmIsFiniteVec(fmVec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// Gravity beyond about 1000 g is no game's and no lab's; it only drives bodies through
// everything (1e30 m/s^2 inverts every tet in one step).
#define FM_MAX_GRAVITY 1e4

static fmResult fmValidateGravity(fmVec3 gravity, fmDiagnostic* diag)
{
	if (!fmIsFiniteVec(gravity) || !(fmLength(gravity) <= FM_MAX_GRAVITY))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "gravity must be finite with |g| <= %g m/s^2 (Earth: 9.8), got "
		                   "(%g, %g, %g)",
		                   FM_MAX_GRAVITY, gravity.x, gravity.y, gravity.z);
	return fm_ok;
}

fmResult fmFloorDef_Validate(const fmFloorDef* floor, fmDiagnostic* diag)
{
	if (floor == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "floor def is NULL");
	if (!floor->enabled)
		return fm_ok;
	if (!isfinite(floor->height))
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "floor height must be finite");
	if (floor->friction != fm_floorStick && floor->friction != fm_floorCoulomb)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown floor friction mode %d",
		                   (int)floor->friction);
	if (!(floor->frictionCoefficient >= 0.0 && isfinite(floor->frictionCoefficient)))
		return fmDiagError(
		    diag, fm_errParameter, "", 0, 0,
		    "floor friction coefficient must be >= 0 (0.5 is rubber on wood), got %g",
		    floor->frictionCoefficient);
	if (!(floor->restitution >= 0.0 && floor->restitution <= 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "floor restitution must be in [0, 1], got %g", floor->restitution);
	if (!(floor->maxDepenetrationSpeed > 0.0 && isfinite(floor->maxDepenetrationSpeed)))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "floor maxDepenetrationSpeed must be finite and > 0 m/s (default 1; "
		                   "start from fmDefaultFloorDef()), got %g",
		                   floor->maxDepenetrationSpeed);
	return fm_ok;
}

size_t fmWorldTableBytes(int maxBodies)
{
	return fmMulSize((size_t)(maxBodies > 0 ? maxBodies : 0), sizeof(fmBody) + sizeof(fmFrameWork));
}

// a + b, or SIZE_MAX where it would overflow.
static size_t fmAddBytes(size_t a, size_t b)
{
	return a > SIZE_MAX - b ? SIZE_MAX : a + b;
}

size_t fmWorldMemoryInUse(const fmWorld* world)
{
	size_t used = fmAddBytes(fmWorldTableBytes(world->bodyCapacity), world->bodyMemory);
	used = fmAddBytes(used, sizeof(fmCollider) * (size_t)world->colliderCapacity);
	for (int k = 0; k < world->colliderCapacity; ++k)
		if (world->colliders[k].inUse && world->colliders[k].mesh != NULL)
			used = fmAddBytes(used, world->colliders[k].mesh->bytes);
	return used;
}

fmResult fmWorldDef_Validate(const fmWorldDef* def, fmDiagnostic* diag)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "world def not initialised: start from fmDefaultWorldDef()");
	fmResult r = fmValidateGravity(def->gravity, diag);
	if (r == fm_ok)
		r = fmFloorDef_Validate(&def->floor, diag);
	if (r != fm_ok)
		return r;
	if (def->integrator != fm_explicit && def->integrator != fm_implicit)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown integrator %d",
		                   (int)def->integrator);
	if (def->newtonIterations < 1 || def->newtonIterations > FM_MAX_NEWTON_ITERATIONS)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "newtonIterations must be in [1, %d] (default 20), got %d",
		                   FM_MAX_NEWTON_ITERATIONS, def->newtonIterations);
	if (def->cgIterations < 1 || def->cgIterations > FM_MAX_CG_ITERATIONS)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "cgIterations must be in [1, %d] (default 500), got %d",
		                   FM_MAX_CG_ITERATIONS, def->cgIterations);
	if (!(def->tolerance >= FM_MIN_TOLERANCE && def->tolerance < 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "tolerance must be in [%g, 1) (a relative residual, default 1e-6; "
		                   "double precision cannot reach below %g), got %g",
		                   FM_MIN_TOLERANCE, FM_MIN_TOLERANCE, def->tolerance);
	if (def->maxBodies < 1 || def->maxBodies > (1 << 20))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "maxBodies must be in [1, 2^20], got %d", def->maxBodies);
	if (def->maxNewtonPerFrame < 1 || def->maxSubstepsPerFrame < 1 ||
	    def->maxSubstepsPerFrame > FM_MAX_SUBSTEPS)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "the frame budget needs maxNewtonPerFrame >= 1 and maxSubstepsPerFrame "
		                   "in [1, %d], got %d and %d",
		                   FM_MAX_SUBSTEPS, def->maxNewtonPerFrame, def->maxSubstepsPerFrame);
	if (def->workerCount < 1 || def->workerCount > FM_MAX_WORKERS)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "workerCount must be in [1, %d] (default 1), got %d", FM_MAX_WORKERS,
		                   def->workerCount);
	if ((int)def->implicitSolver < 0 || def->implicitSolver >= fm_implicitSolverCount)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "implicitSolver must be fm_solverNewton or fm_solverVbd, got %d",
		                   (int)def->implicitSolver);
	if ((int)def->simd < 0 || def->simd >= fm_simdLevelCount)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "simd must be one of fm_simdAuto .. fm_simdAvx512 (\"auto\", \"off\", "
		                   "\"scalar\", \"sse2\", \"avx2\", \"avx512\"), got %d",
		                   (int)def->simd);
	r = fmContactDef_Validate(&def->contact, diag);
	if (r != fm_ok)
		return r;
	if ((def->enqueueTask == NULL) != (def->finishTask == NULL))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "give both task callbacks (enqueueTask and finishTask) or neither");
	if (def->memoryBudget == 0)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "memoryBudget must be > 0 bytes (default %zu = 4 GiB; SIZE_MAX for no "
		                   "limit)",
		                   (size_t)FM_DEFAULT_MEMORY_BUDGET);
	size_t table = fmWorldTableBytes(def->maxBodies);
	if (table > def->memoryBudget)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "the table of maxBodies = %d bodies takes %zu bytes, more than the "
		                   "memoryBudget of %zu bytes: raise the budget or lower maxBodies",
		                   def->maxBodies, table, def->memoryBudget);
	return fm_ok;
}

fmWorldId fmCreateWorld(const fmWorldDef* def)
{
	fmWorldId id = {0, 0};
	FM_ASSERT(def != NULL);
	if (fmWorldDef_Validate(def, NULL) != fm_ok)
		return id;
	for (int i = 0; i < FM_MAX_WORLDS; ++i)
	{
		fmWorld* w = &s_worlds[i];
		// A slot whose generation would wrap is retired: its old ids must never come back.
		if (w->inUse || w->generation == UINT32_MAX)
			continue;
		uint32_t generation = w->generation + 1;
		fmBody* bodies = FM_ALLOC_ZERO(fmBody, def->maxBodies);
		fmFrameWork* frameWork = FM_ALLOC_ZERO(fmFrameWork, def->maxBodies);
		if (bodies == NULL || frameWork == NULL)
		{
			FM_FREE_ARRAY(bodies, fmBody, def->maxBodies);
			FM_FREE_ARRAY(frameWork, fmFrameWork, def->maxBodies);
			return id;
		}
		memset(w, 0, sizeof *w);
		w->bodies = bodies;
		w->frameWork = frameWork;
		w->generation = generation;
		w->inUse = true;
		w->fastCollider = -1;
		w->verticesEpoch = 1;
		w->embeddedDue = true;
		w->def = *def;
		w->bodyCapacity = def->maxBodies;
		w->solverOptions = fmDefaultSolverOptions();
		w->simd = fmSimd_Resolve(def->simd);
		fmTaskSystem_Init(&w->tasks, def); // without threads it runs serially
		fmWorldSyncFloor(w);
		id.index1 = i + 1;
		id.generation = generation;
		return id;
	}
	return id;
}

fmWorld* fmGetWorld(fmWorldId id)
{
	if (id.index1 < 1 || id.index1 > FM_MAX_WORLDS)
		return NULL;
	fmWorld* w = &s_worlds[id.index1 - 1];
	return (w->inUse && w->generation == id.generation) ? w : NULL;
}

fmWorldId fmWorldIdOf(const fmWorld* w)
{
	fmWorldId id = {(int32_t)(w - s_worlds) + 1, w->generation};
	return id;
}

fmBodyId fmWorldBodyId(const fmWorld* w, int slot)
{
	fmWorldId world = fmWorldIdOf(w);
	fmBodyId id = {slot + 1, w->bodies[slot].generation, world.index1 - 1, world.generation};
	return id;
}

fmColliderId fmWorldColliderId(const fmWorld* w, int slot)
{
	fmWorldId world = fmWorldIdOf(w);
	uint32_t generation =
	    slot == FM_FLOOR_SLOT ? w->floorCollider.generation : w->colliders[slot].generation;
	fmColliderId id = {slot + 1, generation, world.index1 - 1, world.generation};
	return id;
}

fmCollider* fmWorldCollider(fmWorld* w, int slot)
{
	return slot == FM_FLOOR_SLOT ? &w->floorCollider : &w->colliders[slot];
}

void fmWorldSyncFloor(fmWorld* w)
{
	const fmFloorDef* floor = &w->def.floor;
	fmColliderDef def = fmDefaultColliderDef();
	def.offset = floor->height;
	def.stick = floor->friction == fm_floorStick;
	def.friction = floor->frictionCoefficient;
	def.restitution = floor->restitution;
	def.filter = floor->filter;
	fmCollider* c = &w->floorCollider;
	fmCollider kept = *c;
	fmCollider_Init(c, &def); // a plane: nothing to allocate
	// A floor put back (after fmDestroyCollider or a disabled floor) gets a new id.
	c->generation = kept.generation + (!kept.inUse && floor->enabled ? 1u : 0u);
	c->inUse = floor->enabled;
	c->impulse = kept.impulse;
	c->angularImpulse = kept.angularImpulse;
	c->force = kept.force;
	c->torque = kept.torque;
}

fmWorld* fmGetWorldOfBody(fmBodyId id)
{
	if (id.index1 == 0 || id.world0 < 0 || id.world0 >= FM_MAX_WORLDS)
		return NULL;
	fmWorld* w = &s_worlds[id.world0];
	return (w->inUse && w->generation == id.worldGeneration) ? w : NULL;
}

fmWorld* fmWorldOrAssert(fmWorldId id)
{
	fmWorld* w = fmGetWorld(id);
	FM_ASSERT(w != NULL);
	return w;
}

static void fmWorldFreeWorkerArenas(fmWorld* w);

void fmDestroyWorld(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			fmBodyRelease(&w->bodies[i]);
	FM_FREE_ARRAY(w->bodies, fmBody, w->bodyCapacity);
	FM_FREE_ARRAY(w->frameWork, fmFrameWork, w->bodyCapacity);
	for (int k = 0; k < w->colliderCapacity; ++k)
		fmCollider_Release(&w->colliders[k]);
	FM_FREE_ARRAY(w->colliders, fmCollider, w->colliderCapacity);
	fmContactState_Free(w->contactState);
	FM_FREE_ARRAY(w->drawPoints, float, FM_DRAW_CONTACT_FLOATS*(size_t)w->drawPointCapacity);
	fmAttachment_Release(&w->drawShape);
	FM_FREE_ARRAY(w->sleepEvents, fmSleepEvent, w->sleepEventCapacity);
	FM_FREE_ARRAY(w->islandParent, int, w->islandCapacity);
	FM_FREE_ARRAY(w->islandLeast, double, w->islandCapacity);
	fmArena_Free(&w->arena);
	fmWorldFreeWorkerArenas(w);
	fmSchedule_Free(&w->schedule);
	fmTaskSystem_Shutdown(&w->tasks);
	uint32_t generation = w->generation;
	memset(w, 0, sizeof *w);
	w->generation = generation;
}

bool fmWorld_IsValid(fmWorldId worldId)
{
	return fmGetWorld(worldId) != NULL;
}

const fmDiagnostic* fmWorld_GetLastError(fmWorldId worldId)
{
	// A stale id gets a diagnostic that says so, never NULL (callers print it unchecked).
	static const fmDiagnostic s_invalidId = {.result = fm_errInvalidId,
	                                         .message = "invalid or destroyed world id"};
	fmWorld* w = fmWorldOrAssert(worldId);
	return w ? &w->lastError : &s_invalidId;
}

fmStepStats fmWorld_GetStepStats(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	fmStepStats none;
	memset(&none, 0, sizeof none);
	return w ? w->stats : none;
}

fmProfile fmWorld_GetProfile(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	fmProfile none;
	memset(&none, 0, sizeof none);
	return w ? w->profile : none;
}

fmResult fmWorld_SetGravity(fmWorldId worldId, fmVec3 gravity)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return fm_errInvalidId;
	fmResult r = fmValidateGravity(gravity, &w->lastError);
	if (r == fm_ok)
		w->def.gravity = gravity;
	return r;
}

void fmWorld_SetIntegrator(fmWorldId worldId, fmIntegrator integrator)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	FM_ASSERT(integrator == fm_explicit || integrator == fm_implicit);
	if (w && (integrator == fm_explicit || integrator == fm_implicit))
	{
		w->def.integrator = integrator;
		w->warnedStep = false;
		w->embeddedDue = true; // (an explicit state may hold vertices inside other bodies)
	}
}

fmResult fmWorld_SetFloor(fmWorldId worldId, const fmFloorDef* floor)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	FM_ASSERT(floor != NULL);
	if (w == NULL)
		return fm_errInvalidId;
	fmResult r = fmFloorDef_Validate(floor, &w->lastError);
	if (r == fm_ok)
	{
		w->def.floor = *floor;
		fmWorldSyncFloor(w);
	}
	return r;
}

fmColliderId fmWorld_GetFloorCollider(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	fmColliderId none = {0, 0, 0, 0};
	return w != NULL && w->def.floor.enabled ? fmWorldColliderId(w, FM_FLOOR_SLOT) : none;
}

static size_t fmMaxSize(size_t a, size_t b)
{
	return a > b ? a : b;
}

// Bytes a step of a body of @p vertices vertices and @p tets tets takes from its arena at once:
// two vectors of 3n doubles; a parallel explicit step (@p parallel) also keeps every tet's
// forces and energy (13 doubles a tet) for its gather; the explicit floor's responses and lists
// (fmFloorTaken), under the smoothing's sums.
static size_t fmStepBytes(const fmWorld* w, size_t vertices, size_t tets, bool parallel)
{
	size_t bytes = fmArena_Bytes(2, 3 * vertices);
	if (parallel)
		bytes += fmArena_Bytes(1, 12 * tets) + fmArena_Bytes(1, tets);
	if (w->def.integrator != fm_implicit && w->def.floor.enabled)
		bytes += fmFloorTaken_Bytes(vertices);
	return bytes;
}

static void fmWorldFreeWorkerArenas(fmWorld* w)
{
	if (w->workerArenas == NULL)
		return;
	for (int k = 0; k < w->tasks.workerCount - 1; ++k)
		fmArena_Free(&w->workerArenas[k]);
	FM_FREE_ARRAY(w->workerArenas, fmArena, (size_t)(w->tasks.workerCount - 1));
}

// The workers' arenas (workers 1 and up) for bodies of up to @p vertices vertices that step on
// one worker each (serially inside).
static bool fmWorldReserveWorkerArenas(fmWorld* w, size_t vertices)
{
	const int extra = w->tasks.workerCount - 1;
	if (extra <= 0 || vertices == 0)
		return true;
	if (w->workerArenas == NULL)
		w->workerArenas = FM_ALLOC_ZERO(fmArena, (size_t)extra);
	if (w->workerArenas == NULL)
		return false;
	size_t bytes = fmStepBytes(w, vertices, 0, false);
	for (int k = 0; k < extra; ++k)
		if (!fmArena_Reserve(&w->workerArenas[k], bytes))
			return false;
	return true;
}

// w->reserved grown to cover body @p b.
static void fmWorldCover(fmWorld* w, const fmBody* b)
{
	fmArenaSizes* r = &w->reserved;
	size_t n = (size_t)b->mesh.vertexCount;
	r->vertices = fmMaxSize(r->vertices, n);
	r->tets = fmMaxSize(r->tets, (size_t)b->mesh.tetCount);
	if (n < FM_BODY_PARALLEL_MAX_VERTICES)
		r->small = fmMaxSize(r->small, n);
}

// The arenas reserved for the bodies w->reserved covers.
static bool fmWorldReserveCovered(fmWorld* w)
{
	const fmArenaSizes* r = &w->reserved;
	bool parallel = w->tasks.workerCount > 1 || w->tasks.enqueueTask != NULL;
	return fmArena_Reserve(&w->arena, fmStepBytes(w, r->vertices, r->tets, parallel)) &&
	       fmWorldReserveWorkerArenas(w, r->small);
}

bool fmWorldReserveArena(fmWorld* w)
{
	memset(&w->reserved, 0, sizeof w->reserved);
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			fmWorldCover(w, &w->bodies[i]);
	return fmWorldReserveCovered(w);
}

bool fmWorldReserveArenaFor(fmWorld* w, const fmBody* b)
{
	fmWorldCover(w, b);
	return fmWorldReserveCovered(w);
}

double fmWorldBodyStepLimit(fmWorld* w, const fmBody* b)
{
	return w != NULL && fmWorldReserveArenaFor(w, b)
	           ? fmExplicitStepLimit(&b->mesh, &b->state, &w->arena)
	           : 0.0;
}

// The explicit stability limit of the world at the bodies' current deformation (s); 0 for an
// empty world. Refreshes each body's cached limit.
double fmWorldExplicitLimit(fmWorld* w)
{
	double dt = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		b->explicitLimit = fmExplicitStepLimit(&b->mesh, &b->state, &w->arena);
		dt = fmMin(dt, b->explicitLimit);
	}
	return dt; // INFINITY: nothing constrains the step; 0: a body has collapsed
}

double fmWorld_EstimateExplicitStep(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return 0.0;
	if (!fmWorldReserveArena(w))
		return 0.0;
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	double limit = fmWorldExplicitLimit(w);
	fmFpEnv_Leave(&env);
	return isfinite(limit) ? limit : 0.0;
}
