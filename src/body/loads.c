// Loads and prescribed displacements (loads.h): fmBody_AddNodalForce, fmBody_AddPressure,
// fmBody_ClearLoads, fmBody_PinBoxAxes, fmBody_PrescribeDisplacement, and what the integrators
// and the static solver call.
#include "body/loads.h"
#include "core/det_math.h"
#include "solver/solver_cache.h"

#include "core/core.h"
#include "core/fp_env.h"
#include "fem/forces.h"
#include "world/energy_ledger.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// ---- the load set ------------------------------------------------------------------------------

void fmLoads_Free(fmLoadSet* s)
{
	if (s == NULL)
		return;
	size_t n3 = 3 * (size_t)s->vertexCount;
	FM_FREE_ARRAY(s->fixed, double, n3);
	FM_FREE_ARRAY(s->frozen, double, n3);
	FM_FREE_ARRAY(s->followerTriangle, int, 3 * (size_t)s->followerCapacity);
	FM_FREE_ARRAY(s->followerPressure, double, s->followerCapacity);
	FM_FREE_ARRAY(s->prescribed, fmPrescribed, s->prescribedCapacity);
	FM_FREE_ARRAY(s->shadowForces, double, 2 * n3);
	FM_FREE_ARRAY(s, fmLoadSet, 1);
}

// A per-vertex array of @p stride doubles (each stride's thirds a 3n block) for @p count
// vertices: a vertex whose source is itself keeps its values, a copy gets none.
static double* fmRenumbered(const double* old, int oldCount, int count, const int* from, int blocks)
{
	double* out = FM_ALLOC_ZERO(double, 3 * (size_t)blocks * (size_t)count);
	for (int k = 0; out != NULL && old != NULL && k < blocks; ++k)
		for (int i = 0; i < count; ++i)
			if (from[i] == i && i < oldCount)
				memcpy(out + 3 * ((size_t)k * count + i), old + 3 * ((size_t)k * oldCount + i),
				       3 * sizeof(double));
	return out;
}

bool fmLoads_Renumber(fmBody* b, int count, const int* from)
{
	fmLoadSet* s = b->loads;
	if (s == NULL)
		return true;
	int n = s->vertexCount;
	double* fixed = s->fixed != NULL ? fmRenumbered(s->fixed, n, count, from, 1) : NULL;
	double* frozen = fmRenumbered(s->frozen, n, count, from, 1);
	double* shadow =
	    s->shadowForces != NULL ? fmRenumbered(s->shadowForces, n, count, from, 2) : NULL;
	if ((s->fixed != NULL && fixed == NULL) || frozen == NULL ||
	    (s->shadowForces != NULL && shadow == NULL))
	{
		FM_FREE_ARRAY(fixed, double, 3 * (size_t)count);
		FM_FREE_ARRAY(frozen, double, 3 * (size_t)count);
		FM_FREE_ARRAY(shadow, double, 6 * (size_t)count);
		return false;
	}
	FM_FREE_ARRAY(s->fixed, double, 3 * (size_t)n);
	FM_FREE_ARRAY(s->frozen, double, 3 * (size_t)n);
	FM_FREE_ARRAY(s->shadowForces, double, 6 * (size_t)n);
	s->fixed = fixed;
	s->frozen = frozen;
	s->shadowForces = shadow;
	s->vertexCount = count;
	return true;
}

// The body's load set with its frozen vector, made on first use; NULL when memory is short.
static fmLoadSet* fmLoadsGet(fmBody* b)
{
	if (b->loads == NULL)
	{
		fmLoadSet* s = FM_ALLOC_ZERO(fmLoadSet, 1);
		double* frozen = FM_ALLOC_ZERO(double, 3 * (size_t)b->mesh.vertexCount);
		if (s == NULL || frozen == NULL)
		{
			FM_FREE_ARRAY(s, fmLoadSet, 1);
			FM_FREE_ARRAY(frozen, double, 3 * (size_t)b->mesh.vertexCount);
			return NULL;
		}
		s->vertexCount = b->mesh.vertexCount;
		s->frozen = frozen;
		b->loads = s;
	}
	return b->loads;
}

bool fmLoads_Active(const fmBody* b)
{
	return b->loads != NULL && (b->loads->fixed != NULL || b->loads->followerCount > 0);
}

bool fmLoads_Moving(const fmBody* b)
{
	const fmLoadSet* s = b->loads;
	for (int p = 0; s != NULL && p < s->prescribedCount; ++p)
		if (!s->prescribed[p].reached)
			return true;
	return false;
}

// f += the follower pressure at x: on each triangle (a, b, c), counter-clockwise seen from
// outside, the area vector N = (b - a) x (c - a) / 2 points outward; a pressure p pushes against
// it with -p N, a third on each vertex (the consistent load of a linear triangle).
static void fmAddFollower(const fmLoadSet* s, const double* x, double scale, double* f)
{
	for (int t = 0; t < s->followerCount; ++t)
	{
		const int* tri = s->followerTriangle + 3 * t;
		fmVec3 a = fmLoad(x, tri[0]), e1 = fmSub(fmLoad(x, tri[1]), a);
		fmVec3 e2 = fmSub(fmLoad(x, tri[2]), a);
		fmVec3 share = fmScale(-scale * s->followerPressure[t] / 6.0, fmCross(e1, e2));
		for (int k = 0; k < 3; ++k)
			fmStore(f, tri[k], fmAdd(fmLoad(f, tri[k]), share));
	}
}

const double* fmLoads_Freeze(fmBody* b, const double* x, double scale)
{
	if (!fmLoads_Active(b))
		return NULL;
	fmLoadSet* s = b->loads;
	size_t n3 = 3 * (size_t)b->mesh.vertexCount;
	if (s->fixed != NULL)
		for (size_t k = 0; k < n3; ++k)
			s->frozen[k] = scale * s->fixed[k];
	else
		memset(s->frozen, 0, sizeof(double) * n3);
	fmAddFollower(s, x, scale, s->frozen);
	return s->frozen;
}

void fmLoads_AddForces(const fmBody* b, const double* x, double* f)
{
	if (!fmLoads_Active(b))
		return;
	if (b->loads->fixed != NULL)
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			f[k] += b->loads->fixed[k];
	fmAddFollower(b->loads, x, 1.0, f);
}

double fmLoads_Energy(const fmBody* b, const double* x, const double* xStart, double* gradient)
{
	if (!fmLoads_Active(b))
		return 0.0;
	const double* f = b->loads->frozen;
	double energy = 0.0;
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
	{
		energy -= f[k] * (x[k] - xStart[k]);
		if (gradient)
			gradient[k] -= f[k];
	}
	return energy;
}

double fmLoads_Work(const fmBody* b, const double* d, double scale)
{
	if (!fmLoads_Active(b))
		return 0.0;
	const double* f = b->loads->frozen;
	double work = 0.0;
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		work += fmIsDofPinned(&b->state, k) ? 0.0 : f[k] * d[k];
	return scale * work;
}

double fmLoads_FrozenNorm(const fmBody* b)
{
	if (!fmLoads_Active(b))
		return 0.0;
	double sum = 0.0;
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		sum += fmIsDofPinned(&b->state, k) ? 0.0 : b->loads->frozen[k] * b->loads->frozen[k];
	return sqrt(sum);
}

double fmLoads_Size(const fmBody* b)
{
	const fmLoadSet* s = b->loads;
	if (s == NULL)
		return 0.0;
	double size = 0.0;
	for (int k = 0; s->fixed != NULL && k < 3 * b->mesh.vertexCount; ++k)
		size += fabs(s->fixed[k]); // (the 1-norm: no square to overflow)
	for (int t = 0; t < s->followerCount; ++t)
	{
		const int* tri = s->followerTriangle + 3 * t;
		fmVec3 a = fmLoad(b->mesh.x0, tri[0]);
		fmVec3 n =
		    fmCross(fmSub(fmLoad(b->mesh.x0, tri[1]), a), fmSub(fmLoad(b->mesh.x0, tri[2]), a));
		size += fabs(s->followerPressure[t]) * 0.5 * fmLength(n);
	}
	return size;
}

double fmLoads_LongestDisplacement(const fmBody* b)
{
	const fmLoadSet* s = b->loads;
	double longest = 0.0;
	for (int k = 0; s != NULL && k < s->prescribedCount; ++k)
	{
		const double* d = s->prescribed[k].displacement;
		longest = fmMax(longest, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
	}
	return longest;
}

// ---- prescribed displacements ------------------------------------------------------------------

// Place prescribed vertex @p p at fraction @p s of the way from @p origin to start + displacement.
static void fmPlace(fmBody* b, const fmPrescribed* p, const double* origin, double s)
{
	for (int e = 0; e < 3; ++e)
		if (p->axes & (1u << e))
		{
			double goal = p->start[e] + p->displacement[e];
			b->state.x[3 * p->vertex + e] = origin[e] + s * (goal - origin[e]);
		}
}

// A moving support must not stall: the body may not fall asleep (island.c) while prescribed
// vertices are on their way.
static void fmLoadsKeepAwake(fmBody* b, fmLoadSet* s)
{
	if (s->keptAwake)
		return;
	s->keptAwake = true;
	s->canSleep = b->canSleep;
	b->canSleep = false;
}

static void fmLoadsLetSleep(fmBody* b)
{
	if (b->loads == NULL || !b->loads->keptAwake)
		return;
	b->loads->keptAwake = false;
	b->canSleep = b->loads->canSleep;
}

// Elastic energy at the body's positions, and the forces into @p f when it is not NULL.
static double fmElasticWithForces(fmBody* b, double* f)
{
	if (f == NULL)
		return fmSolverCache_Energy(&b->mesh, b->solverCache, b->state.x, NULL, NULL);
	memset(f, 0, sizeof(double) * 3 * (size_t)b->mesh.vertexCount);
	return fmAddElasticForces(&b->mesh, b->state.x, f);
}

double fmLoads_StepPrescribed(fmBody* b, double dt, double shadowStep)
{
	if (!fmLoads_Moving(b))
		return 0.0;
	// The motion changes the elastic energy by what the supports do on the body: booked as
	// work, exactly (two force passes while a prescribed motion runs). The explicit step's
	// ledger measures the shadow energy T + Psi + h/2 v . f (energy_ledger.h), whose force term
	// the motion changes too: booked with it.
	fmLoadSet* s = b->loads;
	size_t n3 = 3 * (size_t)b->mesh.vertexCount;
	if (shadowStep > 0.0 && s->shadowForces == NULL)
		s->shadowForces = FM_ALLOC_ARRAY(double, 2 * n3);
	double* before = shadowStep > 0.0 ? s->shadowForces : NULL;
	double* after = before != NULL ? before + n3 : NULL;
	double energy = fmElasticWithForces(b, before);
	for (int i = 0; i < s->prescribedCount; ++i)
	{
		fmPrescribed* p = &s->prescribed[i];
		if (p->reached)
			continue;
		p->elapsed += dt;
		double fraction = p->time > 0.0 ? fmMin(p->elapsed / p->time, 1.0) : 1.0;
		p->reached = fraction >= 1.0;
		fmPlace(b, p, p->start, fraction);
	}
	double work = fmElasticWithForces(b, after) - energy;
	for (size_t k = 0; after != NULL && k < n3; ++k)
		work += 0.5 * shadowStep * b->state.v[k] * (after[k] - before[k]);
	if (!fmLoads_Moving(b))
		fmLoadsLetSleep(b);
	return work;
}

void fmLoads_BeginStatic(fmBody* b)
{
	for (int i = 0; b->loads != NULL && i < b->loads->prescribedCount; ++i)
	{
		fmPrescribed* p = &b->loads->prescribed[i];
		memcpy(p->from, b->state.x + 3 * p->vertex, sizeof p->from);
	}
}

void fmLoads_PlaceStatic(fmBody* b, double load)
{
	for (int i = 0; b->loads != NULL && i < b->loads->prescribedCount; ++i)
		fmPlace(b, &b->loads->prescribed[i], b->loads->prescribed[i].from, load);
}

void fmLoads_FinishStatic(fmBody* b)
{
	for (int i = 0; b->loads != NULL && i < b->loads->prescribedCount; ++i)
	{
		b->loads->prescribed[i].reached = true;
		b->loads->prescribed[i].elapsed = b->loads->prescribed[i].time;
	}
	fmLoadsLetSleep(b);
}

// ---- the public calls --------------------------------------------------------------------------

static bool fmFiniteVec(fmVec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// A box of ordered, non-NaN bounds (infinite bounds make half-spaces).
static bool fmGoodBox(fmVec3 min, fmVec3 max)
{
	return min.x <= max.x && min.y <= max.y && min.z <= max.z;
}

static bool fmInBox(const fmBody* b, int i, fmVec3 min, fmVec3 max)
{
	fmVec3 p = fmLoad(b->state.x, i);
	return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
	       p.z <= max.z;
}

// The body of a call that changes loads, woken; NULL (asserted) for a stale id or bad box.
static fmBody* fmLoadBody(fmBodyId bodyId, fmVec3 min, fmVec3 max, bool good)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	FM_ASSERT(good && fmGoodBox(min, max));
	if (b == NULL || !good || !fmGoodBox(min, max))
		return NULL;
	fmIsland_WakeBody(bodyId);
	return b;
}

static int fmOutOfMemory(fmBodyId bodyId, const char* call)
{
	fmWorld* w = fmGetWorldOfBody(bodyId);
	if (w != NULL)
		fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0, "%s: out of memory", call);
	return -1;
}

int fmBody_AddNodalForce(fmBodyId bodyId, fmVec3 min, fmVec3 max, fmVec3 force)
{
	fmBody* b = fmLoadBody(bodyId, min, max, fmFiniteVec(force));
	if (b == NULL)
		return -1;
	fmLoadSet* s = fmLoadsGet(b);
	if (s != NULL && s->fixed == NULL)
		s->fixed = FM_ALLOC_ZERO(double, 3 * (size_t)b->mesh.vertexCount);
	if (s == NULL || s->fixed == NULL)
		return fmOutOfMemory(bodyId, "fmBody_AddNodalForce");
	int count = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (fmInBox(b, i, min, max))
		{
			fmStore(s->fixed, i, fmAdd(fmLoad(s->fixed, i), force));
			++count;
		}
	return count;
}

static bool fmReserveFollowers(fmLoadSet* s, int count)
{
	if (count <= s->followerCapacity)
		return true;
	int capacity = count > 2 * s->followerCapacity ? count : 2 * s->followerCapacity;
	int* tri = FM_ALLOC_ARRAY(int, 3 * (size_t)capacity);
	double* pressure = FM_ALLOC_ARRAY(double, capacity);
	if (tri == NULL || pressure == NULL)
	{
		FM_FREE_ARRAY(tri, int, 3 * (size_t)capacity);
		FM_FREE_ARRAY(pressure, double, capacity);
		return false;
	}
	if (s->followerCount > 0)
	{
		memcpy(tri, s->followerTriangle, sizeof(int) * 3 * (size_t)s->followerCount);
		memcpy(pressure, s->followerPressure, sizeof(double) * (size_t)s->followerCount);
	}
	FM_FREE_ARRAY(s->followerTriangle, int, 3 * (size_t)s->followerCapacity);
	FM_FREE_ARRAY(s->followerPressure, double, s->followerCapacity);
	s->followerTriangle = tri;
	s->followerPressure = pressure;
	s->followerCapacity = capacity;
	return true;
}

int fmBody_AddPressure(fmBodyId bodyId, fmVec3 min, fmVec3 max, double pressure, bool follower)
{
	fmBody* b = fmLoadBody(bodyId, min, max, isfinite(pressure));
	if (b == NULL)
		return -1;
	fmLoadSet* s = fmLoadsGet(b);
	if (s != NULL && !follower && s->fixed == NULL)
		s->fixed = FM_ALLOC_ZERO(double, 3 * (size_t)b->mesh.vertexCount);
	if (s == NULL || (!follower && s->fixed == NULL))
		return fmOutOfMemory(bodyId, "fmBody_AddPressure");
	int count = 0;
	for (int t = 0; t < b->mesh.triangleCount; ++t)
	{
		const int* tri = b->mesh.surface + 3 * t;
		if (!fmInBox(b, tri[0], min, max) || !fmInBox(b, tri[1], min, max) ||
		    !fmInBox(b, tri[2], min, max))
			continue;
		++count;
		if (!follower)
		{
			// Fixed direction: the rest shape's area vector, once (fmAddFollower's formula).
			fmLoadSet one = {0};
			one.followerCount = 1;
			one.followerTriangle = (int*)tri;
			one.followerPressure = &pressure;
			fmAddFollower(&one, b->mesh.x0, 1.0, s->fixed);
			continue;
		}
		if (!fmReserveFollowers(s, s->followerCount + 1))
			return fmOutOfMemory(bodyId, "fmBody_AddPressure");
		memcpy(s->followerTriangle + 3 * s->followerCount, tri, 3 * sizeof(int));
		s->followerPressure[s->followerCount++] = pressure;
	}
	return count;
}

void fmBody_ClearLoads(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL || b->loads == NULL)
		return;
	fmIsland_WakeBody(bodyId);
	fmLoadSet* s = b->loads;
	FM_FREE_ARRAY(s->fixed, double, 3 * (size_t)s->vertexCount);
	s->fixed = NULL;
	s->followerCount = 0;
}

int fmBody_PinBoxAxes(fmBodyId bodyId, fmVec3 min, fmVec3 max, unsigned axes)
{
	fmBody* b = fmLoadBody(bodyId, min, max, axes <= 7u);
	if (b == NULL)
		return -1;
	int count = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (fmInBox(b, i, min, max))
		{
			fmBody_SetPinnedAxes(bodyId, b->userVertex[i], b->state.pinned[i] | axes);
			++count;
		}
	return count;
}

static bool fmReservePrescribed(fmLoadSet* s, int count)
{
	if (count <= s->prescribedCapacity)
		return true;
	int capacity = count > 2 * s->prescribedCapacity ? count : 2 * s->prescribedCapacity;
	fmPrescribed* p = FM_ALLOC_ARRAY(fmPrescribed, capacity);
	if (p == NULL)
		return false;
	if (s->prescribedCount > 0)
		memcpy(p, s->prescribed, sizeof(fmPrescribed) * (size_t)s->prescribedCount);
	FM_FREE_ARRAY(s->prescribed, fmPrescribed, s->prescribedCapacity);
	s->prescribed = p;
	s->prescribedCapacity = capacity;
	return true;
}

int fmBody_PrescribeDisplacement(fmBodyId bodyId, fmVec3 min, fmVec3 max, unsigned axes,
                                 fmVec3 displacement, double time)
{
	bool good =
	    axes >= 1u && axes <= 7u && fmFiniteVec(displacement) && time >= 0.0 && isfinite(time);
	fmBody* b = fmLoadBody(bodyId, min, max, good);
	if (b == NULL)
		return -1;
	fmLoadSet* s = fmLoadsGet(b);
	if (s == NULL)
		return fmOutOfMemory(bodyId, "fmBody_PrescribeDisplacement");
	int count = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		if (!fmInBox(b, i, min, max))
			continue;
		if (!fmReservePrescribed(s, s->prescribedCount + 1))
			return fmOutOfMemory(bodyId, "fmBody_PrescribeDisplacement");
		fmPrescribed* p = &s->prescribed[s->prescribedCount++];
		memset(p, 0, sizeof *p);
		p->vertex = i;
		p->axes = axes;
		memcpy(p->start, b->state.x + 3 * i, sizeof p->start);
		memcpy(p->from, p->start, sizeof p->from);
		p->displacement[0] = displacement.x;
		p->displacement[1] = displacement.y;
		p->displacement[2] = displacement.z;
		p->time = time;
		fmBody_SetPinnedAxes(bodyId, b->userVertex[i], b->state.pinned[i] | axes);
		++count;
	}
	if (count > 0)
		fmLoadsKeepAwake(b, s);
	return count;
}

void fmBody_ComputeLoadForces(fmBodyId bodyId, double* forces)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL && forces != NULL);
	if (b == NULL || forces == NULL)
		return;
	fmWorld* w = fmGetWorldOfBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	memset(forces, 0, sizeof(double) * 3 * (size_t)b->mesh.vertexCount);
	double* f = FM_ALLOC_ZERO(double, 3 * (size_t)b->mesh.vertexCount);
	if (f != NULL)
	{
		fmLoads_AddForces(b, b->state.x, f);
		for (int i = 0; i < b->mesh.vertexCount; ++i)
			memcpy(forces + 3 * (size_t)b->userVertex[i], f + 3 * i, 3 * sizeof(double));
	}
	FM_FREE_ARRAY(f, double, 3 * (size_t)b->mesh.vertexCount);
	fmFpEnv_Leave(&env);
}

static double fmLoadsTermEnergy(const void* context, const double* x, const double* xStart,
                                double* gradient)
{
	return fmLoads_Energy(context, x, xStart, gradient);
}

fmNewtonTerm fmLoads_Term(const fmBody* body)
{
	return (fmNewtonTerm){body, fmLoadsTermEnergy, NULL, NULL, NULL};
}
