// Worlds: creation, the frame step (substeps over bodies), health checks and state restore.
#include "world/world.h"
#include "core/det_math.h"

#include "contact/collider.h"
#include "contact/contact.h"
#include "contact/contact_events.h"
#include "contact/contact_state.h"
#include "core/core.h"
#include "draw/draw_shapes.h"
#include "world/explicit.h"
#include "contact/floor.h"
#include "fem/forces.h"
#include "core/fp_env.h"
#include "world/implicit.h"
#include "world/island.h"
#include "core/simd.h"
#include "core/timer.h"

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

static fmWorld* fmWorldOrAssert(fmWorldId id)
{
	fmWorld* w = fmGetWorld(id);
	FM_ASSERT(w != NULL);
	return w;
}

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
	FM_FREE_ARRAY(w->drawPoints, float, 3 * (size_t)w->drawPointCapacity);
	if (w->drawShape != NULL)
		fmShapeBuffer_Free(w->drawShape);
	FM_FREE_ARRAY(w->drawShape, fmShapeBuffer, 1);
	FM_FREE_ARRAY(w->sleepEvents, fmSleepEvent, w->sleepEventCapacity);
	FM_FREE_ARRAY(w->islandParent, int, w->islandCapacity);
	FM_FREE_ARRAY(w->islandLeast, double, w->islandCapacity);
	fmArena_Free(&w->arena);
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

bool fmWorldReserveArena(fmWorld* w)
{
	size_t vertices = 0, tets = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
		{
			vertices = fmMaxSize(vertices, (size_t)w->bodies[i].mesh.vertexCount);
			tets = fmMaxSize(tets, (size_t)w->bodies[i].mesh.tetCount);
		}
	// Two vectors of 3n doubles: the most any stage holds at once; a parallel explicit step
	// also keeps every tet's forces and energy (13 doubles a tet) for its gather.
	size_t bytes = fmArena_Bytes(2, 3 * vertices);
	if (w->tasks.workerCount > 1 || w->tasks.enqueueTask != NULL)
		bytes += fmArena_Bytes(1, 12 * tets) + fmArena_Bytes(1, tets);
	// The explicit floor's responses and lists (fmFloorTaken), under the smoothing's sums.
	if (w->def.integrator != fm_implicit && w->def.floor.enabled)
		bytes += fmFloorTaken_Bytes(vertices);
	return fmArena_Reserve(&w->arena, bytes);
}

double fmWorldBodyStepLimit(fmWorld* w, const fmBody* b)
{
	return w != NULL && fmWorldReserveArena(w) ? fmExplicitStepLimit(&b->mesh, &b->state, &w->arena) : 0.0;
}

// The explicit stability limit of the world at the bodies' current deformation (s); 0 for an
// empty world. Refreshes each body's cached limit.
static double fmCurrentExplicitLimit(fmWorld* w)
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
	double limit = fmCurrentExplicitLimit(w);
	fmFpEnv_Leave(&env);
	return isfinite(limit) ? limit : 0.0;
}

// Up to eight tets of a body that went bad (non-finite or inverted), in the mesh's numbering,
// into @p list; returns how many there are in all.
static int fmListBadTets(const fmBody* b, char* list, size_t size)
{
	int count = 0;
	size_t length = 0;
	list[0] = '\0';
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		double J = fmDet(&F);
		if (isfinite(J) && J > 0.0)
			continue;
		if (count < 8 && length + 16 < size)
			length += (size_t)snprintf(list + length, size - length, "%s%d", count ? ", " : "",
			                           b->userTet[t] + b->firstIndex);
		++count;
	}
	if (count > 8 && length + 6 < size)
		snprintf(list + length, size - length, ", ...");
	return count;
}

// What to try after a failure, by integrator.
static const char* fmFailureAdvice(const fmWorld* w)
{
	return w->def.integrator == fm_implicit
	           ? "try more substeps (a smaller dt), a tighter tolerance or more Newton iterations"
	           : "try a smaller dt (more substeps) or the implicit integrator";
}

// The first vertex with a non-finite position or velocity, or -1.
static int fmFirstNonFiniteVertex(const fmBody* b)
{
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		if (!isfinite(b->state.x[k]) || !isfinite(b->state.v[k]))
			return k / 3;
	return -1;
}

// What went wrong with a body after (or during) a frame.
typedef enum fmBadBody
{
	fm_badState,    // non-finite positions or velocities, or an energy that overflowed
	fm_badLedger,   // energy beyond E0 + W + tolerance
	fm_badBackstop, // energy beyond the per-frame backstop (an unstable step)
	fm_badSolve,    // the implicit solve's energy or gradient went non-finite
} fmBadBody;

// Say why body @p index went bad in the world's last error, naming the vertex and tets:
// @p energy is the measured energy and @p bound what was allowed (ledger and backstop), @p
// residual the implicit solve's last one (fm_badSolve).
static fmResult fmReportBadBody(fmWorld* w, int index, fmBadBody kind, double energy, double bound,
                                double residual)
{
	const fmBody* b = &w->bodies[index];
	char list[160], what[384];
	int bad = fmListBadTets(b, list, sizeof list);
	int vertex = fmFirstNonFiniteVertex(b);
	if (vertex >= 0)
		snprintf(what, sizeof what, "non-finite position or velocity at vertex %d",
		         b->userVertex[vertex] + b->firstIndex);
	else if (kind == fm_badSolve)
		snprintf(what, sizeof what,
		         "the implicit solve's energy or gradient went non-finite (last relative "
		         "residual %.3g)",
		         residual);
	else if (kind == fm_badState || !isfinite(energy))
		snprintf(what, sizeof what,
		         "its energy overflowed (positions and velocities beyond what a double holds "
		         "squared)");
	else if (kind == fm_badBackstop)
		snprintf(what, sizeof what,
		         "energy ran away within the frame: %.3g J (kinetic + elastic) is more than "
		         "%.3g J, 1000 times what the frame started with plus what gravity can add",
		         energy, bound);
	else
		snprintf(what, sizeof what,
		         "energy ran away: %.3g J (kinetic + elastic%s) is more than the %.3g J its "
		         "ledger allows (%.3g J at the start plus %.3g J of work done on it, "
		         "docs/robustness.md)",
		         energy,
		         w->def.integrator == fm_explicit ? ", as symplectic Euler conserves it" : "",
		         bound, b->ledger.initialEnergy,
		         b->ledger.work + b->ledger.frameGravityWork + w->frameWork[index].contact);
	fmDiagError(&w->lastError, fm_errNumerical, "", 0, 0,
	            "body %d: %s; %d inverted or non-finite tets (%s); state restored to the last "
	            "good frame; %s",
	            index, what, bad, list, fmFailureAdvice(w));
	fmLog(fm_logError, "%s", w->lastError.message);
	return fm_errNumerical;
}

// How the energy ledger measures the world's bodies (energy_ledger.h).
static fmEnergyPass fmWorldEnergyPass(fmWorld* w)
{
	fmEnergyPass pass = {&w->arena, &w->tasks, w->simd};
	return pass;
}

// Health of a body after a frame: finite state, and energy within the ledger's bound.
static fmResult fmCheckBody(fmWorld* w, int index, const fmStepContext* ctx)
{
	fmBody* b = &w->bodies[index];
	double plain = NAN;
	fmEnergyPass pass = fmWorldEnergyPass(w);
	b->invertedAfter = -1;
	double energy = fmFirstNonFiniteVertex(b) < 0 ? fmBodyEnergy(b, w->def.gravity, ctx->shadowStep,
	                                                             &plain, &b->invertedAfter, &pass)
	                                              : NAN;
	b->energyAfter = energy;
	if (!isfinite(energy) || !isfinite(plain))
		return fmReportBadBody(w, index, fm_badState, energy, NAN, NAN);
	fmLedgerVerdict verdict =
	    fmLedger_Check(b, &ctx->work[index], w->def.gravity, energy, plain, ctx->frameTime);
	if (verdict.ok)
		return fm_ok;
	return fmReportBadBody(w, index, verdict.backstop ? fm_badBackstop : fm_badLedger,
	                       verdict.measured, verdict.bound, NAN);
}

static void fmRestoreAll(fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
		memcpy(b->state.x, b->xGood, bytes);
		memcpy(b->state.v, b->vGood, bytes);
		b->energyStale = true; // energyGood may belong to a state the caller had set
	}
}

// Explicit steps beyond twice the estimated limit explode (the seeds' house at dt = 0.003 runs
// at 1.6 times the conservative estimate thanks to its damping and smoothing, and explodes at
// 1.25 times its own step): say so once per world, with what would work.
static void fmWarnExplicitStep(fmWorld* w, const fmStepContext* ctx)
{
	double dt = ctx->frameTime / ctx->substepCount, frameTime = ctx->frameTime;
	if (w->def.integrator != fm_explicit || w->warnedStep || w->def.autoSubstep)
		return;
	double limit = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			limit = fmMin(limit, w->bodies[i].explicitLimit);
	if (!(limit > 0.0) || !(dt > 2.0 * limit)) // a collapsed body fails the step itself
		return;
	w->warnedStep = true;
	fmDiagWarn(&w->lastError, "", 0,
	           "explicit step %.3g s is more than twice the estimated stability limit %.3g s: "
	           "expect an explosion; use at least %.0f substeps per frame of %.3g s, or the "
	           "implicit integrator",
	           dt, limit, ceil(frameTime / limit), frameTime);
}

// A frame the integrators can take: 1 to FM_MAX_SUBSTEPS substeps of FM_MIN_SUBSTEP to
// FM_MAX_SUBSTEP seconds. (A step of 1e300 s makes the inertia term 1/h^2 vanish: the implicit
// solve would be a static one without pins and nothing would move.)
static fmResult fmCheckFrame(fmWorld* w, double timeStep, int subStepCount)
{
	if (!(timeStep > 0.0 && isfinite(timeStep)) || subStepCount < 1 ||
	    subStepCount > FM_MAX_SUBSTEPS)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "time step must be finite and > 0 and substeps in [1, %d], got %g and "
		                   "%d",
		                   FM_MAX_SUBSTEPS, timeStep, subStepCount);
	double h = timeStep / subStepCount;
	if (!(h >= FM_MIN_SUBSTEP && h <= FM_MAX_SUBSTEP))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "a substep of %g s is outside what the integrators can take (%g to %g "
		                   "s); for an equilibrium use fmBody_SolveStatic",
		                   h, FM_MIN_SUBSTEP, FM_MAX_SUBSTEP);
	return fm_ok;
}

// With autoSubstep, explicit substeps are at most FM_AUTO_STEP_FRACTION of the stability limit
// at the bodies' current deformation (stability.h), and at least subStepCount to a frame. The
// limit is linear stability; contacts and large compressions within a step need more room:
// measured on the audit's Neo-Hookean house drop (tests/test_health.c), 0.5 of the limit blew up
// at 2.4 s, 0.35 and less ran the whole drop. Deformation changes
// within a frame (an impact compresses a body in a few substeps), so a cheap stiffening proxy is
// watched after every substep and the limit re-evaluated when it moves by 10%.
#define FM_AUTO_STEP_FRACTION 0.3

typedef struct fmAutoStep
{
	double limit; // s, stability limit at the last evaluation
	double proxy; // stiffening proxy at the last evaluation
} fmAutoStep;

static double fmWorldStiffeningProxy(const fmWorld* w)
{
	double proxy = 1.0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			proxy = fmMax(proxy, fmStiffeningProxy(&w->bodies[i].mesh, w->bodies[i].state.x));
	return proxy;
}

static void fmAutoStep_Evaluate(fmWorld* w, fmAutoStep* a)
{
	a->limit = fmCurrentExplicitLimit(w);
	a->proxy = fmWorldStiffeningProxy(w);
}

// The next substep: no longer than the nominal one or FM_AUTO_STEP_FRACTION of the limit, and
// never leaving a sliver at the end of the frame; 0 when a body has collapsed (its limit is 0).
static double fmAutoStep_Next(fmWorld* w, fmAutoStep* a, double nominal, double remaining,
                              bool watch)
{
	if (watch)
	{
		double proxy = fmWorldStiffeningProxy(w);
		if (!(proxy <= 1.1 * a->proxy && proxy >= a->proxy / 1.1))
			fmAutoStep_Evaluate(w, a);
	}
	if (!(a->limit > 0.0))
		return 0.0; // a body has collapsed: no step is stable
	double h = fmMin(nominal, FM_AUTO_STEP_FRACTION * a->limit);
	double count = ceil(remaining / h * (1.0 - 1e-12));
	return remaining / fmMax(count, 1.0);
}

// Step body @p index by @p h with the world's integrator, keeping what it produced in the body
// (stepResult and the solve's counters). Writes nothing the other bodies' steps touch.
static void fmStepBody(fmWorld* w, int index, const fmStepContext* ctx)
{
	fmBody* b = &w->bodies[index];
	if (w->def.integrator != fm_implicit)
	{
		b->stepResult = fmExplicitStep(w, ctx, b);
		return;
	}
	fmNewtonResult solve;
	b->stepResult = fmImplicitStep(w, ctx, b, &solve);
	b->stepResidual = solve.residual;
	b->stepNewton = solve.iterations;
	b->stepCg = solve.cgIterations;
	b->stepConverged = solve.converged;
	b->stepStopped = solve.stagnated ? "it stagnated at round-off"
	                 : solve.stalled ? "the line search found no decrease"
	                                 : "it hit the Newton iteration limit";
}

// Merge body @p index's step into the world: solver counters into the statistics, a step above
// the tolerance into a warning (once a frame) or, with notConvergedIsError, an error, and a
// failure into the last error.
static fmResult fmMergeBodyStep(fmWorld* w, int index)
{
	const fmBody* b = &w->bodies[index];
	if (b->stepResult == fm_errNumerical)
		return fmReportBadBody(w, index,
		                       w->def.integrator == fm_implicit ? fm_badSolve : fm_badState, NAN,
		                       NAN, b->stepResidual);
	if (b->stepResult != fm_ok)
		return fmDiagError(&w->lastError, b->stepResult, "", 0, 0,
		                   "body %d: the %s step failed (%s)", index,
		                   w->def.integrator == fm_implicit ? "implicit" : "explicit",
		                   fmResultMessage(b->stepResult));
	bool implicit = w->def.integrator == fm_implicit;
	*(implicit ? &w->profile.solve : &w->profile.forces) += 1e3 * b->stepStage[0];
	*(implicit ? &w->profile.finish : &w->profile.integrate) += 1e3 * b->stepStage[1];
	if (!implicit)
		return fm_ok;
	w->stats.newtonIterations += b->stepNewton;
	w->stats.cgIterations += b->stepCg;
	w->stats.residual = b->stepResidual;
	w->stats.maxResidual = fmMax(w->stats.maxResidual, b->stepResidual);
	if (b->stepConverged)
		return fm_ok;
	w->stats.unconvergedSteps += 1;
	const char* format = "body %d: the implicit step ended at relative residual %.3g, above the "
	                     "tolerance %.3g, after %d Newton and %d CG iterations (%s)";
	if (w->def.notConvergedIsError)
		return fmDiagError(&w->lastError, fm_errNotConverged, "", 0, 0, format, index,
		                   b->stepResidual, w->def.tolerance, b->stepNewton, b->stepCg,
		                   b->stepStopped);
	if (w->stats.unconvergedSteps == 1)
		fmDiagWarn(&w->lastError, "", 0, format, index, b->stepResidual, w->def.tolerance,
		           b->stepNewton, b->stepCg, b->stepStopped);
	return fm_ok;
}

// Advance every body by one substep of @p h.
// The frame budget is spent: say so once a frame.
static void fmBudgetHit(fmWorld* w, const char* what)
{
	if (w->stats.budgetHit)
		return;
	w->stats.budgetHit = true;
	fmDiagWarn(&w->lastError, "", 0, "the frame budget is spent: %s", what);
}

static fmResult fmSubstep(fmWorld* w, fmStepContext* ctx, double h)
{
	ctx->substep = h;
	// The frame budget: what is left of maxNewtonPerFrame bounds every step of this substep.
	int left = w->def.maxNewtonPerFrame - w->stats.newtonIterations;
	ctx->newtonLimit = w->def.newtonIterations;
	if (w->def.integrator == fm_implicit && left < ctx->newtonLimit)
	{
		ctx->newtonLimit = left > 1 ? left : 1;
		fmBudgetHit(w, "the implicit steps' Newton iterations were cut to what maxNewtonPerFrame "
		               "leaves (at least one a step); their residuals are reported");
	}
	// Stage a: every body steps on its own (the stage threads will share).
	bool contact = fmContact_Active(w);
	if (contact && !fmContact_BeginSubstep(w, ctx))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the contact buffers");
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]))
			fmStepBody(w, i, ctx);
	// Stage b: contact between the bodies and with the colliders (contact.c), in a fixed order.
	double contactStart = fmSeconds();
	bool contactOk =
	    (!contact || fmContact_Substep(w, ctx)) && fmContactEvents_ReportFloor(w, contact);
	w->profile.contact += 1e3 * (fmSeconds() - contactStart);
	if (!contactOk)
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the contact buffers");
	// Stage c: the results merge in body order, the same for any schedule of stage a.
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		if (!fmIsland_Stepping(&w->bodies[i]))
			continue;
		fmResult r = fmMergeBodyStep(w, i);
		if (r != fm_ok)
			return r;
	}
	w->stats.steps += 1;
	return fm_ok;
}

// An implicit substep of @p h, cut into the pieces fmContact_Pieces asks for where bodies close
// in fast (within what is left of maxSubstepsPerFrame and FM_MIN_SUBSTEP).
static fmResult fmImplicitPieces(fmWorld* w, fmStepContext* ctx, double h, int substepsLeft)
{
	int most = w->def.maxSubstepsPerFrame - w->stats.steps - (substepsLeft - 1);
	most = (int)fmMin(most, floor(h / FM_MIN_SUBSTEP));
	ctx->substep = h;
	int pieces = most > 1 && fmContact_Active(w) ? fmContact_Pieces(w, ctx, most) : 1;
	if (pieces < 0)
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the contact buffers");
	if (pieces > most)
	{
		pieces = most;
		fmBudgetHit(w, "an implicit step was cut into fewer pieces than fast bodies closing in "
		               "need (maxSubstepsPerFrame): they may pass through each other");
	}
	fmResult r = fm_ok;
	ctx->pieces = pieces;
	for (int k = 0; k < pieces && r == fm_ok; ++k)
		r = fmSubstep(w, ctx, h / pieces);
	ctx->pieces = 1;
	return r;
}

static fmResult fmFixedSubsteps(fmWorld* w, fmStepContext* ctx, double h, int count)
{
	fmResult r = fm_ok;
	for (int s = 0; s < count && r == fm_ok; ++s)
		r = w->def.integrator == fm_implicit ? fmImplicitPieces(w, ctx, h, count - s)
		                                     : fmSubstep(w, ctx, h);
	return r;
}

// Substeps between autoSubstep's checks for non-finite state within a frame.
#define FM_FINITE_CHECK_SUBSTEPS 256

// autoSubstep: substeps planned by fmAutoStep_Next until the frame is done. @p lastStep gets the
// length of the last one (the ledger measures the shadow energy with it).
static fmResult fmAdaptiveSubsteps(fmWorld* w, fmStepContext* ctx, fmAutoStep* plan)
{
	const double timeStep = ctx->frameTime, nominal = timeStep / ctx->substepCount;
	double remaining = timeStep, h = ctx->shadowStep;
	while (remaining > 1e-12 * timeStep)
	{
		if (w->stats.steps >= FM_MAX_SUBSTEPS || !(h > 0.0))
			return fmDiagError(&w->lastError, fm_errNumerical, "", 0, 0,
			                   "the stability limit asks for more than %d substeps in a frame of "
			                   "%.3g s (the next would be %.3g s): a body is collapsing; state "
			                   "restored to the last good frame; try the implicit integrator",
			                   FM_MAX_SUBSTEPS, timeStep, h);
		fmResult r = fmSubstep(w, ctx, h);
		if (r != fm_ok)
			return r;
		// A body gone non-finite (collapsed, or blown up by substeps the budget made longer than
		// stable) is refused now, not after the rest of the frame's substeps.
		for (int i = 0; w->stats.steps % FM_FINITE_CHECK_SUBSTEPS == 0 && i < w->bodyCapacity; ++i)
			if (fmIsland_Stepping(&w->bodies[i]) && fmFirstNonFiniteVertex(&w->bodies[i]) >= 0)
				return fmReportBadBody(w, i, fm_badState, NAN, 0.0, 0.0);
		remaining -= h;
		if (!(remaining > 1e-12 * timeStep))
			break;
		h = fmAutoStep_Next(w, plan, nominal, remaining, true);
		int left = w->def.maxSubstepsPerFrame - w->stats.steps;
		if (h > 0.0 && remaining / h > left + 1e-9)
		{
			h = remaining / (left > 1 ? left : 1);
			fmBudgetHit(w, "autoSubstep took longer substeps than the stability limit to end the "
			               "frame within maxSubstepsPerFrame");
		}
		// The ledger measures the shadow energy with the step: a new step changes the measure,
		// which is neither work nor a runaway.
		fmEnergyPass pass = fmWorldEnergyPass(w);
		for (int i = 0; i < w->bodyCapacity && h != ctx->shadowStep && h > 0.0; ++i)
			if (fmBody_IsLive(&w->bodies[i]))
				fmLedger_ChangeMeasure(&w->bodies[i], w->def.gravity, ctx->shadowStep, h, &pass);
		ctx->shadowStep = h;
	}
	return fm_ok;
}

// The frame's step context: its times, the world's workers and arena, the bookings zeroed.
static fmStepContext fmWorldStepContext(fmWorld* w, double timeStep, int subStepCount)
{
	memset(w->frameWork, 0, sizeof(fmFrameWork) * (size_t)w->bodyCapacity);
	fmStepContext ctx = {.frameTime = timeStep,
	                     .substep = timeStep / subStepCount,
	                     .substepCount = subStepCount,
	                     .pieces = 1,
	                     .newtonLimit = w->def.newtonIterations,
	                     .integrator = w->def.integrator,
	                     .gravity = w->def.gravity,
	                     .tasks = &w->tasks,
	                     .arena = &w->arena,
	                     .simd = w->simd,
	                     .work = w->frameWork,
	                     .bodyCapacity = w->bodyCapacity};
	return ctx;
}

// Open every stepping body's energy ledger. The state to fall back on (xGood, vGood) is the
// last one that passed the checks, kept from the previous frame: a state the user set to NaN or
// Inf between steps is not "good". What the caller changed since is booked as work.
static void fmOpenLedgers(fmWorld* w, const fmStepContext* ctx)
{
	fmEnergyPass pass = fmWorldEnergyPass(w);
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]))
			fmLedger_BeginFrame(&w->bodies[i], w->def.gravity, ctx->shadowStep, &pass);
}

// Health checks against the ledgers: a failure restores every body. Only when every body passed
// are the frame's work booked (the ledgers closed) and the good states moved forward.
static fmResult fmCloseLedgers(fmWorld* w, const fmStepContext* ctx)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]) && fmCheckBody(w, i, ctx) != fm_ok)
		{
			fmRestoreAll(w);
			return fm_errNumerical;
		}
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmIsland_Stepping(b))
			continue;
		fmLedger_Commit(b, &ctx->work[i], ctx->shadowStep);
		size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
		memcpy(b->xGood, b->state.x, bytes);
		memcpy(b->vGood, b->state.v, bytes);
		b->energyGood = b->energyAfter;
		b->energyStale = false;
		w->stats.invertedTets += b->invertedAfter >= 0
		                             ? b->invertedAfter
		                             : fmBodyCountInvertedOn(b, &w->tasks, &w->arena);
	}
	return fm_ok;
}

// The frame step of fmWorld_Step, in femto's floating-point environment.
static fmResult fmWorldStep(fmWorld* w, double timeStep, int subStepCount)
{
	memset(&w->stats, 0, sizeof w->stats);
	fmDiagClear(&w->lastError);
	fmResult r = fmCheckFrame(w, timeStep, subStepCount);
	if (r != fm_ok)
		return r;
	if (!fmWorldReserveArena(w))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the step buffers");
	fmStepContext ctx = fmWorldStepContext(w, timeStep, subStepCount);

	// Stage 1: the substep length (autoSubstep: from the stability limit at the current
	// deformation).
	const bool autoStep = w->def.integrator == fm_explicit && w->def.autoSubstep;
	fmAutoStep plan = {0.0, 1.0};
	if (autoStep)
	{
		fmAutoStep_Evaluate(w, &plan);
		ctx.substep = fmAutoStep_Next(w, &plan, ctx.substep, timeStep, false);
	}

	// Stage 2: open the ledgers.
	fmContact_BeginFrame(w);
	ctx.shadowStep = w->def.integrator == fm_explicit ? ctx.substep : 0.0;
	w->sleepEventCount = 0;
	fmOpenLedgers(w, &ctx);
	fmWarnExplicitStep(w, &ctx);

	// Stage 3: substeps, every body advanced by the chosen integrator.
	r = autoStep ? fmAdaptiveSubsteps(w, &ctx, &plan) : fmFixedSubsteps(w, &ctx, ctx.substep, subStepCount);
	if (r != fm_ok)
	{
		fmRestoreAll(w);
		return r;
	}

	// Stage 4: check and close the ledgers, then the frame's contact events and islands.
	double checking = fmSeconds();
	if (fmCloseLedgers(w, &ctx) != fm_ok)
		return fm_errNumerical;
	const fmContactPoint* points;
	w->stats.contacts = fmContactEvents_Points(w, &points);
	if (!fmContactEvents_EndFrame(w, 1.0 / ctx.frameTime) || !fmIsland_EndFrame(w, &ctx))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the contact or sleep events");
	w->profile.check = 1e3 * (fmSeconds() - checking);
	return fm_ok;
}

fmResult fmWorld_Step(fmWorldId worldId, double timeStep, int subStepCount)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return fm_errInvalidId;
	// The host's floating-point state is saved, femto's set (round to nearest, no FTZ or DAZ),
	// and the host's restored after the step, on every path (fp_env.h).
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	double start = fmSeconds();
	memset(&w->profile, 0, sizeof w->profile);
	fmResult r = fmWorldStep(w, timeStep, subStepCount);
	w->profile.step = 1e3 * (fmSeconds() - start);
	w->profile.narrowPhase = fmMax(0.0, w->profile.contact - w->profile.broadPhase);
	fmFpEnv_Leave(&env);
	return r;
}
