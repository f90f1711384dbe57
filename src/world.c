// Worlds: creation, the frame step (substeps over bodies), health checks and state restore.
#include "world.h"

#include "core.h"
#include "forces.h"
#include "integrator.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define FM_MAX_WORLDS 128

static fmWorld s_worlds[FM_MAX_WORLDS];

fmWorldDef fmDefaultWorldDef(void)
{
	fmWorldDef def;
	memset(&def, 0, sizeof def);
	def.gravity = fmMakeVec3(0.0, -9.8, 0.0);
	def.floor.enabled = true;
	def.floor.height = -3.0;
	def.floor.friction = fm_floorStick;
	def.floor.frictionCoefficient = 0.5;
	def.floor.restitution = 0.0;
	def.integrator = fm_explicit;
	def.newtonIterations = 20;
	def.tolerance = 1e-6;
	def.cgIterations = 500;
	def.maxBodies = 64;
	def.memoryBudget = FM_DEFAULT_MEMORY_BUDGET;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

static bool fmIsFiniteVec(fmVec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// A floor def, shared by the world def and fmWorld_SetFloor().
static fmResult fmFloorDef_Validate(const fmFloorDef* floor, fmDiagnostic* diag)
{
	if (floor == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "floor def is NULL");
	if (floor->enabled && !isfinite(floor->height))
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "floor height must be finite");
	if (floor->enabled && floor->friction != fm_floorStick && floor->friction != fm_floorCoulomb)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown floor friction mode");
	if (floor->enabled &&
	    !(floor->frictionCoefficient >= 0.0 && isfinite(floor->frictionCoefficient)))
		return fmDiagError(
		    diag, fm_errParameter, "", 0, 0,
		    "floor friction coefficient must be >= 0 (0.5 is rubber on wood), got %g",
		    floor->frictionCoefficient);
	if (floor->enabled && !(floor->restitution >= 0.0 && floor->restitution <= 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "floor restitution must be in [0, 1], got %g", floor->restitution);
	return fm_ok;
}

size_t fmWorldTableBytes(int maxBodies)
{
	return fmMulSize((size_t)(maxBodies > 0 ? maxBodies : 0), sizeof(fmBody));
}

fmResult fmWorldDef_Validate(const fmWorldDef* def, fmDiagnostic* diag)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "world def not initialised: start from fmDefaultWorldDef()");
	if (!fmIsFiniteVec(def->gravity))
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "gravity must be finite");
	fmResult r = fmFloorDef_Validate(&def->floor, diag);
	if (r != fm_ok)
		return r;
	if (def->integrator != fm_explicit && def->integrator != fm_implicit)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown integrator %d",
		                   (int)def->integrator);
	if (def->newtonIterations < 1 || def->cgIterations < 1)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "newton and CG iteration limits must be >= 1 (defaults 20 and 500)");
	if (!(def->tolerance > 0.0 && def->tolerance < 1.0))
		return fmDiagError(
		    diag, fm_errParameter, "", 0, 0,
		    "tolerance must be in (0, 1) (a relative residual; default 1e-6), got %g",
		    def->tolerance);
	if (def->maxBodies < 1 || def->maxBodies > (1 << 20))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "maxBodies must be in [1, 2^20], got %d", def->maxBodies);
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
		if (bodies == NULL)
			return id;
		memset(w, 0, sizeof *w);
		w->bodies = bodies;
		w->generation = generation;
		w->inUse = true;
		w->def = *def;
		w->bodyCapacity = def->maxBodies;
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
		if (w->bodies[i].x)
			fmBodyRelease(&w->bodies[i]);
	FM_FREE_ARRAY(w->bodies, fmBody, w->bodyCapacity);
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

void fmWorld_SetGravity(fmWorldId worldId, fmVec3 gravity)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	FM_ASSERT(fmIsFiniteVec(gravity));
	if (w && fmIsFiniteVec(gravity))
		w->def.gravity = gravity;
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

void fmWorld_SetFloor(fmWorldId worldId, const fmFloorDef* floor)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	bool valid = fmFloorDef_Validate(floor, NULL) == fm_ok;
	FM_ASSERT(valid);
	if (w && valid)
		w->def.floor = *floor;
}

// Largest stable symplectic Euler step: 2 / omega_max, with omega_max^2 bounded by
// Gershgorin's theorem on M^-1 K: the largest absolute row sum of the rest stiffness matrix
// (the linear-elastic one, assembled per tet; springs use k_e) divided by the vertex mass.
// A true upper bound at rest; large strains stiffen StVK, hence the 0.9 safety factor.
static void fmAddTetRowSums(const fmBody* b, int t, double* rowSum)
{
	const fmMat3* D = &b->DmInv[t];
	fmVec3 g[4];
	for (int a = 1; a < 4; ++a)
		g[a] = fmMakeVec3(D->m[3 * (a - 1)], D->m[3 * (a - 1) + 1], D->m[3 * (a - 1) + 2]);
	g[0] = fmScale(-1.0, fmAdd(fmAdd(g[1], g[2]), g[3]));
	const double lambda = fmax(b->material.lambda, 0.0), mu = b->material.mu;
	// K_ab = V0 (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I) for linear elasticity.
	for (int a = 0; a < 4; ++a)
	{
		const double ga[3] = {g[a].x, g[a].y, g[a].z};
		double sums[3] = {0, 0, 0};
		for (int c = 0; c < 4; ++c)
		{
			const double gb[3] = {g[c].x, g[c].y, g[c].z};
			double dot = fmDot(g[a], g[c]);
			for (int i = 0; i < 3; ++i)
				for (int j = 0; j < 3; ++j)
					sums[i] += fabs(lambda * ga[i] * gb[j] + mu * gb[i] * ga[j] +
					                (i == j ? mu * dot : 0.0));
		}
		int node = b->tets[4 * t + a];
		for (int i = 0; i < 3; ++i)
			rowSum[3 * node + i] += b->restVolume[t] * sums[i];
	}
}

double fmBodyExplicitStepLimit(const fmBody* b)
{
	double* rowSum = b->scratch;
	memset(rowSum, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	if (b->forceModel == fm_massSpring)
	{
		// An edge block [H -H; -H H] at rest has row sums of 2 k |n_i| (|n_x| + |n_y| + |n_z|).
		for (int e = 0; e < b->edgeCount; ++e)
			for (int k = 0; k < 2; ++k)
				for (int i = 0; i < 3; ++i)
					rowSum[3 * b->edges[2 * e + k] + i] += 2.0 * sqrt(3.0) * b->springK[e];
	}
	else
	{
		for (int t = 0; t < b->tetCount; ++t)
			fmAddTetRowSums(b, t, rowSum);
	}
	double omega2 = 0.0;
	for (int k = 0; k < 3 * b->vertexCount; ++k)
		omega2 = fmax(omega2, rowSum[k] * b->invMass[k / 3]);
	memset(rowSum, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	return omega2 > 0.0 ? 0.9 * 2.0 / sqrt(omega2) : INFINITY;
}

double fmWorld_EstimateExplicitStep(fmWorldId worldId)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return 0.0;
	double dt = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].x)
			dt = fmin(dt, w->bodies[i].explicitLimit);
	return isfinite(dt) ? dt : 0.0;
}

// Kinetic plus elastic energy, the measure of a runaway.
static double fmBodyEnergy(const fmBody* b)
{
	double kinetic = 0.0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmVec3 v = fmLoad(b->v, i);
		kinetic += 0.5 * b->mass[i] * fmDot(v, v);
	}
	return kinetic + fmElasticEnergy(b, b->x);
}

// Why a body went bad: non-finite state, or energy far beyond what the frame could add.
static fmResult fmCheckBody(fmWorld* w, int index, double energyBefore, double frameTime,
                            double* energyAfter)
{
	const fmBody* b = &w->bodies[index];
	int badVertex = -1;
	for (int k = 0; k < 3 * b->vertexCount && badVertex < 0; ++k)
		if (!isfinite(b->x[k]) || !isfinite(b->v[k]))
			badVertex = k / 3;
	double energy = badVertex < 0 ? fmBodyEnergy(b) : NAN;
	*energyAfter = energy;
	// Gravity can add at most M |g| (fall height) + M |g|^2 T^2 in a frame; a stable elastic
	// body does not multiply its energy by 1000 on top of that.
	double g = fmLength(w->def.gravity);
	double size = b->restSize;
	double bound = 1000.0 * (energyBefore + b->totalMass * g * (size + g * frameTime * frameTime)) +
	               1e-6 * b->totalMass * size * size;
	if (badVertex < 0 && energy <= bound)
		return fm_ok;

	// Name the tets that went bad: non-finite or inverted deformation.
	char list[160] = "";
	int count = 0, length = 0;
	for (int t = 0; t < b->tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(b, b->x, t);
		double J = fmDet(&F);
		if (isfinite(J) && J > 0.0)
			continue;
		if (count < 8 && length < (int)sizeof list - 16)
			length += snprintf(list + length, sizeof list - (size_t)length, "%s%d",
			                   count ? ", " : "", t + b->firstIndex);
		++count;
	}
	if (badVertex >= 0)
		fmDiagError(&w->lastError, fm_errNumerical, "", 0, 0,
		            "body %d: non-finite position or velocity at vertex %d; %d bad tets (%s%s); "
		            "state restored to the start of the frame; try a smaller dt or the implicit "
		            "integrator",
		            index, badVertex + b->firstIndex, count, list, count > 8 ? ", ..." : "");
	else
		fmDiagError(
		    &w->lastError, fm_errNumerical, "", 0, 0,
		    "body %d: energy ran away (%.3g J after %.3g J); %d inverted tets (%s%s); state "
		    "restored to the start of the frame; try a smaller dt or the implicit integrator",
		    index, energy, energyBefore, count, list, count > 8 ? ", ..." : "");
	fmLog(fm_logError, "%s", w->lastError.message);
	return fm_errNumerical;
}

static void fmRestoreAll(fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (b->x == NULL)
			continue;
		size_t bytes = sizeof(double) * 3 * (size_t)b->vertexCount;
		memcpy(b->x, b->xGood, bytes);
		memcpy(b->v, b->vGood, bytes);
		b->energyStale = true; // energyGood may belong to a state the caller had set
	}
}

// Explicit steps beyond twice the estimated limit explode (the seeds' house at dt = 0.003 runs
// at 1.6 times the conservative estimate thanks to its damping and smoothing, and explodes at
// 1.25 times its own step): say so once per world, with what would work.
static void fmWarnExplicitStep(fmWorld* w, double frameTime, int subStepCount)
{
	double dt = frameTime / subStepCount;
	if (w->def.integrator != fm_explicit || w->warnedStep)
		return;
	double limit = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].x)
			limit = fmin(limit, w->bodies[i].explicitLimit);
	if (!(dt > 2.0 * limit))
		return;
	w->warnedStep = true;
	fmDiagWarn(&w->lastError, "", 0,
	           "explicit step %.3g s is more than twice the estimated stability limit %.3g s: "
	           "expect an explosion; use at least %d substeps per frame of %.3g s, or the implicit "
	           "integrator",
	           dt, limit, (int)ceil(frameTime / limit), frameTime);
}

fmResult fmWorld_Step(fmWorldId worldId, double timeStep, int subStepCount)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	if (w == NULL)
		return fm_errInvalidId;
	memset(&w->stats, 0, sizeof w->stats);
	fmDiagClear(&w->lastError);
	if (!(timeStep > 0.0 && isfinite(timeStep)) || subStepCount < 1)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "time step must be > 0 and substeps >= 1, got %g and %d", timeStep,
		                   subStepCount);

	// Stage 1: the energy before the frame bounds what the frame may produce. The state to fall
	// back on (xGood, vGood) is the last one that passed the checks, kept from the previous
	// frame: a state the user set to NaN or Inf between steps is not "good".
	// The energy of the good state is kept from the last check: recompute it only when the
	// caller changed the state or the material since (an elastic energy pass saved per frame).
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		size_t bytes = sizeof(double) * 3 * (size_t)b->vertexCount;
		if (b->x && (b->energyStale || memcmp(b->x, b->xGood, bytes) != 0 ||
		             memcmp(b->v, b->vGood, bytes) != 0))
			b->energyGood = fmBodyEnergy(b);
	}
	const double dt = timeStep / subStepCount;
	fmWarnExplicitStep(w, timeStep, subStepCount);

	// Stage 2: substeps, every body advanced by the chosen integrator.
	for (int s = 0; s < subStepCount; ++s)
	{
		for (int i = 0; i < w->bodyCapacity; ++i)
		{
			fmBody* b = &w->bodies[i];
			if (b->x == NULL)
				continue;
			fmResult r = w->def.integrator == fm_implicit ? fmImplicitStep(w, b, dt, &w->stats)
			                                              : fmExplicitStep(w, b, dt);
			if (r != fm_ok)
			{
				if (w->lastError.result == fm_ok)
					fmDiagError(&w->lastError, r, "", 0, 0,
					            "body %d: the %s step failed (%s); state restored to the start of "
					            "the frame",
					            i, w->def.integrator == fm_implicit ? "implicit" : "explicit",
					            fmResultMessage(r));
				fmRestoreAll(w);
				return r;
			}
		}
		w->stats.steps += 1;
	}

	// Stage 3: health checks; a failure restores every body.
	w->stats.contacts = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (b->x == NULL)
			continue;
		double energy;
		if (fmCheckBody(w, i, b->energyGood, timeStep, &energy) != fm_ok)
		{
			fmRestoreAll(w);
			return fm_errNumerical;
		}
		size_t bytes = sizeof(double) * 3 * (size_t)b->vertexCount;
		memcpy(b->xGood, b->x, bytes);
		memcpy(b->vGood, b->v, bytes);
		b->energyGood = energy;
		b->energyStale = false;
		w->stats.invertedTets += fmBodyCountInverted(b);
		if (w->def.floor.enabled)
			for (int k = 0; k < b->vertexCount; ++k)
				w->stats.contacts += b->x[3 * k + 1] <= w->def.floor.height + 1e-9;
	}
	return fm_ok;
}
