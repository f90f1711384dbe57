// Grabs (grab.h): fmBody_Grab, fmBody_MoveGrab, fmBody_ReleaseGrab, fmBody_GetGrab and
// fmWorld_GrabRay. Each pulled vertex gets the grab's stiffness, damping and bound in proportion
// to its share: mass times a smooth falloff (1 - (d / radius)^2)^2 with its distance d from the
// grabbed point. The shares sum to one, so the whole pull is bounded by maxForce and the patch,
// not one vertex, carries it: a point pulled alone tears its tets inside out.
#include "body/grab.h"
#include "core/det_math.h"

#include "body/targets.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "fem/stability.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// The defaults' scale of the body's weight (m/s^2): the world's gravity, or Earth's when it is
// weaker (a grab in zero gravity still needs a scale).
#define FM_GRAB_GRAVITY 9.81
// Default radius as a fraction of the body's size (its box's diagonal).
#define FM_GRAB_RADIUS 0.12
// Default stretch (m) at which the spring carries the body's weight: a slow pointer lifting the
// body leads the grabbed point by about this much.
#define FM_GRAB_SAG 0.002
// Default bound on the pull, in the body's weights: it lifts the body at 2 g.
#define FM_GRAB_FORCE 3.0

fmGrabDef fmDefaultGrabDef(void)
{
	fmGrabDef def;
	memset(&def, 0, sizeof def);
	def.dampingRatio = 1.0;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

void fmGrab_Free(fmBody* b)
{
	fmGrab* g = b->grab;
	if (g == NULL)
		return;
	b->grabRelaxProxy = g->proxy;
	b->grabRelaxKinetic = g->settled;
	FM_FREE_ARRAY(g->weight, double, g->count);
	FM_FREE_ARRAY(g->rest, double, 3 * (size_t)g->count);
	FM_FREE_ARRAY(g, fmGrab, 1);
	b->grab = NULL;
	b->targetCount = 0;
}

void fmGrab_Advance(fmBody* b, double fraction)
{
	const fmGrab* g = b->grab;
	if (g == NULL)
		return;
	fraction = fmMax(0.0, fmMin(1.0, fraction));
	fmVec3 motion = fmSub(g->goal, g->from);
	fmVec3 shift = fmSub(fmAdd(g->from, fmScale(fraction, motion)), g->anchor);
	for (int t = 0; t < g->count; ++t)
	{
		fmTarget* target = &b->targets[t];
		target->position[0] = g->rest[3 * t] + shift.x;
		target->position[1] = g->rest[3 * t + 1] + shift.y;
		target->position[2] = g->rest[3 * t + 2] + shift.z;
		target->motion[0] = motion.x;
		target->motion[1] = motion.y;
		target->motion[2] = motion.z;
	}
}

bool fmGrab_NeedsAdaptiveSteps(fmBody* b)
{
	if (b->grab != NULL)
		return true;
	if (b->grabRelaxProxy <= 0.0)
		return false;
	if (fmStiffeningProxy(&b->mesh, b->state.x) > 1.1 * b->grabRelaxProxy ||
	    !(fmBodyKineticEnergy(b) <= b->grabRelaxKinetic))
		return true;
	b->grabRelaxProxy = 0.0;
	return false;
}

void fmGrab_EndFrame(fmBody* b)
{
	if (b->grab != NULL)
		b->grab->from = b->grab->goal;
}

// The body's size: its box's diagonal (m), and its mass (kg).
static double fmBodySize(const fmBody* b, double* mass)
{
	fmVec3 lo = fmLoad(b->state.x, 0), hi = lo;
	*mass = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i);
		lo = fmMakeVec3(fmMin(lo.x, p.x), fmMin(lo.y, p.y), fmMin(lo.z, p.z));
		hi = fmMakeVec3(fmMax(hi.x, p.x), fmMax(hi.y, p.y), fmMax(hi.z, p.z));
		*mass += b->mesh.mass[i];
	}
	return fmLength(fmSub(hi, lo));
}

// The patch's radius: the asked one, but at least twice the distance to the nearest free vertex
// (with mass, not pinned on all three axes: so that some free vertex has a share); infinite when
// no vertex is free.
static double fmPatchRadius(const fmBody* b, fmVec3 point, double radius)
{
	double nearest = INFINITY;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (b->state.invMass[i] > 0.0)
			nearest = fmMin(nearest, fmLength(fmSub(fmLoad(b->state.x, i), point)));
	return fmMax(radius, 2.0 * nearest);
}

// The shares of the free vertices within @p radius of @p point into @p weight (one a vertex, zero
// outside and for pinned ones); returns how many have one.
static int fmPatchShares(const fmBody* b, fmVec3 point, double radius, double* weight)
{
	int count = 0;
	double total = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		double s = fmLength(fmSub(fmLoad(b->state.x, i), point)) / radius;
		weight[i] = s < 1.0 && b->state.invMass[i] > 0.0
		                ? b->mesh.mass[i] * (1.0 - s * s) * (1.0 - s * s)
		                : 0.0;
		count += weight[i] > 0.0;
		total += weight[i];
	}
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		weight[i] /= total;
	return count;
}

// What is wrong with @p def and @p point, or NULL.
static const char* fmGrabDefProblem(const fmGrabDef* def, fmVec3 point)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return "a grab def started from fmDefaultGrabDef()";
	if (!(fabs(point.x) <= FM_MAX_COORDINATE && fabs(point.y) <= FM_MAX_COORDINATE &&
	      fabs(point.z) <= FM_MAX_COORDINATE))
		return "a finite point within FM_MAX_COORDINATE (1e9 m)";
	double fields[4] = {def->radius, def->stiffness, def->dampingRatio, def->maxForce};
	for (int k = 0; k < 4; ++k)
		if (!(fields[k] >= 0.0) || !isfinite(fields[k]))
			return "a radius, stiffness, damping ratio and maximum force finite and >= 0";
	return NULL;
}

// The grab's whole stiffness, damping and bound from @p def and the body (its weight scales the
// defaults).
static void fmGrabStrength(fmGrab* g, const fmGrabDef* def, double mass, fmVec3 gravity)
{
	double weight = mass * fmMax(fmLength(gravity), FM_GRAB_GRAVITY);
	g->stiffness = def->stiffness > 0.0 ? def->stiffness : weight / FM_GRAB_SAG;
	g->damping = 2.0 * def->dampingRatio * sqrt(g->stiffness * mass);
	g->maxForce = def->maxForce > 0.0 ? def->maxForce : FM_GRAB_FORCE * weight;
}

// Fill a new grab of the vertices with a share in @p weight (one a vertex) and its targets.
static bool fmMakeGrab(fmBody* b, const double* weight, int count, fmGrab* g)
{
	g->count = count;
	g->weight = FM_ALLOC_ARRAY(double, count);
	g->rest = FM_ALLOC_ARRAY(double, 3 * (size_t)count);
	if (g->weight == NULL || g->rest == NULL || !fmTargets_Reserve(b, count))
		return false;
	int t = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		if (!(weight[i] > 0.0))
			continue;
		g->weight[t] = weight[i];
		memcpy(g->rest + 3 * t, b->state.x + 3 * i, 3 * sizeof(double));
		b->targets[t] = (fmTarget){.vertex = i,
		                           .stiffness = weight[i] * g->stiffness,
		                           .damping = weight[i] * g->damping,
		                           .maxForce = weight[i] * g->maxForce};
		t += 1;
	}
	b->targetCount = count;
	return true;
}

static fmResult fmBodyGrabIn(fmBody* b, fmWorld* w, fmVec3 point, const fmGrabDef* def)
{
	const char* problem = fmGrabDefProblem(def, point);
	if (problem != NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0, "fmBody_Grab: expected %s",
		                   problem);
	double mass, size = fmBodySize(b, &mass);
	double radius =
	    fmPatchRadius(b, point, def->radius > 0.0 ? def->radius : FM_GRAB_RADIUS * size);
	if (!isfinite(radius))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "fmBody_Grab: expected a body with a vertex free to move, but every "
		                   "vertex is pinned or massless");
	fmGrab_Free(b);
	b->targetCount = 0;
	double* weight = FM_ALLOC_ARRAY(double, b->mesh.vertexCount);
	fmGrab* g = FM_ALLOC_ZERO(fmGrab, 1);
	if (weight == NULL || g == NULL)
	{
		FM_FREE_ARRAY(weight, double, b->mesh.vertexCount);
		FM_FREE_ARRAY(g, fmGrab, 1);
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmBody_Grab: no memory for the grab");
	}
	b->grab = g;
	fmGrabStrength(g, def, mass, w->def.gravity);
	double proxy = fmStiffeningProxy(&b->mesh, b->state.x);
	g->proxy = b->grabRelaxProxy > 0.0 ? fmMin(b->grabRelaxProxy, proxy) : proxy;
	double settled = 2.0 * fmBodyKineticEnergy(b) + 0.01 * mass * fmLength(w->def.gravity);
	g->settled = b->grabRelaxProxy > 0.0 ? fmMin(b->grabRelaxKinetic, settled) : settled;
	g->anchor = g->from = g->goal = point;
	bool made = fmMakeGrab(b, weight, fmPatchShares(b, point, radius, weight), g);
	FM_FREE_ARRAY(weight, double, b->mesh.vertexCount);
	if (!made)
	{
		fmGrab_Free(b);
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmBody_Grab: no memory for the grab");
	}
	fmGrab_Advance(b, 1.0);
	return fm_ok;
}

fmResult fmBody_Grab(fmBodyId bodyId, fmVec3 point, const fmGrabDef* def)
{
	fmBody* b = fmGetBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	FM_ASSERT(b != NULL && w != NULL);
	if (b == NULL || w == NULL)
		return fm_errInvalidId;
	fmIsland_WakeBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	fmResult result = fmBodyGrabIn(b, w, point, def);
	fmFpEnv_Leave(&env);
	return result;
}

fmResult fmBody_MoveGrab(fmBodyId bodyId, fmVec3 target)
{
	fmBody* b = fmGetBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	FM_ASSERT(b != NULL && w != NULL);
	if (b == NULL || w == NULL)
		return fm_errInvalidId;
	if (b->grab == NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "fmBody_MoveGrab: the body is not grabbed (fmBody_Grab first)");
	if (!(fabs(target.x) <= FM_MAX_COORDINATE && fabs(target.y) <= FM_MAX_COORDINATE &&
	      fabs(target.z) <= FM_MAX_COORDINATE))
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "fmBody_MoveGrab: expected a finite target within FM_MAX_COORDINATE "
		                   "(1e9 m), got (%g, %g, %g)",
		                   target.x, target.y, target.z);
	b->grab->goal = target;
	fmIsland_WakeBody(bodyId);
	return fm_ok;
}

void fmBody_ReleaseGrab(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b != NULL)
		fmGrab_Free(b);
}

bool fmBody_GetGrab(fmBodyId bodyId, fmVec3* point, fmVec3* target)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL || b->grab == NULL)
		return false;
	const fmGrab* g = b->grab;
	fmVec3 now = g->anchor;
	for (int t = 0; t < g->count; ++t)
	{
		fmVec3 moved = fmSub(fmLoad(b->state.x, b->targets[t].vertex), fmLoad(g->rest, t));
		now = fmAdd(now, fmScale(g->weight[t], moved));
	}
	if (point != NULL)
		*point = now;
	if (target != NULL)
		*target = g->goal;
	return true;
}

bool fmWorld_GrabRay(fmWorldId worldId, fmVec3 origin, fmVec3 translation, fmFilter filter,
                     const fmGrabDef* def, fmRayHit* hit)
{
	fmRayHit local;
	fmRayHit* h = hit != NULL ? hit : &local;
	if (!fmWorld_CastRay(worldId, origin, translation, filter, h) || !fmBody_IsValid(h->body))
		return false;
	return fmBody_Grab(h->body, h->point, def) == fm_ok;
}
