// Kinematic targets (targets.h) and fmBody_SetTargets.
#include "body/targets.h"
#include "core/det_math.h"

#include "body/grab.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// Target @p t's spring in the step: @p d = x - q (q where it pulls, the dashpot folded in) and
// its stiffness (returned).
static double fmTargetSpring(const fmTargetStep* s, int t, const double* x, double d[3])
{
	const fmTarget* target = fmTargets_At(s->body, t);
	const double* xi = x + 3 * target->vertex;
	double k = target->stiffness;
	if (s->xStart == NULL || target->damping <= 0.0)
	{
		for (int e = 0; e < 3; ++e)
			d[e] = xi[e] - target->position[e];
		return k;
	}
	double c = target->damping, blend = k + c * s->rate;
	const double* x0 = s->xStart + 3 * target->vertex;
	for (int e = 0; e < 3; ++e)
	{
		double q =
		    (k * target->position[e] + c * s->rate * x0[e] + c * target->motion[e] * s->frameRate) /
		    blend;
		d[e] = xi[e] - q;
	}
	return blend;
}

// The bounded spring's energy at stretch @p d of stiffness @p k and bound @p bound: 1/2 k r^2
// up to r = bound / k, linear beyond; the force's magnitude over r goes to @p slope.
static double fmHuber(const double d[3], double k, double bound, double* slope)
{
	double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
	if (k * k * r2 <= bound * bound)
	{
		*slope = k;
		return 0.5 * k * r2;
	}
	double r = sqrt(r2);
	*slope = bound / r;
	return bound * (r - 0.5 * bound / k);
}

void fmTargets_Force(const fmTargetStep* s, int t, const double* x, double force[3])
{
	double d[3], slope;
	double k = fmTargetSpring(s, t, x, d);
	fmHuber(d, k, fmTargets_At(s->body, t)->maxForce, &slope);
	for (int e = 0; e < 3; ++e)
		force[e] = -slope * d[e];
}

static double fmTargetsEnergy(const fmTargetStep* s, const double* x, double* gradient)
{
	double energy = 0.0;
	for (int t = 0; t < fmTargets_Count(s->body); ++t)
	{
		double d[3], slope;
		double k = fmTargetSpring(s, t, x, d);
		energy += fmHuber(d, k, fmTargets_At(s->body, t)->maxForce, &slope);
		int i = fmTargets_At(s->body, t)->vertex;
		for (int e = 0; gradient != NULL && e < 3; ++e)
			gradient[3 * i + e] += slope * d[e];
	}
	return energy;
}

// Target @p t's Hessian block at @p x: k I within the bound, (F / r)(I - n n^T) beyond it.
static void fmTargetBlock(const fmTargetStep* s, int t, const double* x, double block[9])
{
	double d[3], slope;
	double k = fmTargetSpring(s, t, x, d);
	fmHuber(d, k, fmTargets_At(s->body, t)->maxForce, &slope);
	bool bounded = slope < k;
	double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
	for (int a = 0; a < 3; ++a)
		for (int c = 0; c < 3; ++c)
			block[3 * a + c] = slope * ((a == c ? 1.0 : 0.0) - (bounded ? d[a] * d[c] / r2 : 0.0));
}

double fmTargets_ImplicitWork(const fmTargetStep* s, const double* x)
{
	double work = 0.0;
	for (int t = 0; t < fmTargets_Count(s->body); ++t)
	{
		fmTarget* target = fmTargets_At(s->body, t);
		fmTargets_Force(s, t, x, target->applied);
		for (int e = 0; e < 3; ++e)
			work += target->applied[e] *
			        (x[3 * target->vertex + e] - s->xStart[3 * target->vertex + e]);
	}
	return work;
}

void fmTargets_ExplicitForce(const fmTarget* target, const double* x, const double* v,
                             double stiffnessLimit, double dampingLimit, double frameRate,
                             double force[3])
{
	int i = target->vertex;
	double k = fmMin(target->stiffness, stiffnessLimit), c = fmMin(target->damping, dampingLimit);
	double f2 = 0.0;
	for (int e = 0; e < 3; ++e)
	{
		force[e] = k * (target->position[e] - x[3 * i + e]) +
		           c * (target->motion[e] * frameRate - v[3 * i + e]);
		f2 += force[e] * force[e];
	}
	if (f2 > target->maxForce * target->maxForce)
		for (int e = 0; e < 3; ++e)
			force[e] *= target->maxForce / sqrt(f2);
}

// The set is valid: every vertex in range, every position finite and within the coordinate
// limit, the stiffness finite and not negative. Says what is wrong in the world's last error.
static fmResult fmValidateTargets(const fmBody* b, fmWorld* w, const int* vertices,
                                  const fmVec3* positions, int count, double stiffness)
{
	const char* what = NULL;
	int at = -1;
	if (count < 0 || (count > 0 && (vertices == NULL || positions == NULL)))
		what = "count >= 0 and, when count > 0, non-NULL vertices and positions";
	else if (!(stiffness >= 0.0) || !isfinite(stiffness))
		what = "a finite stiffness >= 0 N/m";
	for (int t = 0; what == NULL && t < count; ++t)
	{
		fmVec3 p = positions[t];
		at = t;
		if (vertices[t] < 0 || vertices[t] >= b->mesh.vertexCount)
			what = "a vertex index in [0, vertexCount)";
		else if (!(fabs(p.x) <= FM_MAX_COORDINATE && fabs(p.y) <= FM_MAX_COORDINATE &&
		           fabs(p.z) <= FM_MAX_COORDINATE))
			what = "a finite position within FM_MAX_COORDINATE (1e9 m)";
	}
	if (what == NULL)
		return fm_ok;
	if (at >= 0)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "fmBody_SetTargets: target %d (vertex %d): expected %s", at,
		                   vertices[at], what);
	return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
	                   "fmBody_SetTargets: expected %s (count %d, stiffness %g)", what, count,
	                   stiffness);
}

bool fmTargets_Reserve(fmBody* b, int count)
{
	if (count <= b->targetCapacity)
		return true;
	fmTarget* targets = FM_ALLOC_ARRAY(fmTarget, count);
	if (targets == NULL)
		return false;
	fmTargets_Free(b);
	b->targets = targets;
	b->targetCapacity = count;
	return true;
}

void fmTargets_Free(fmBody* b)
{
	FM_FREE_ARRAY(b->targets, fmTarget, b->targetCapacity);
	b->targets = NULL;
	b->targetCapacity = 0;
	b->targetCount = 0;
}

static fmResult fmBodySetTargetsIn(fmBodyId bodyId, const int* vertices, const fmVec3* positions,
                                   int count, double stiffness)
{
	fmBody* b = fmGetBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	FM_ASSERT(b != NULL && w != NULL);
	if (b == NULL || w == NULL)
		return fm_errInvalidId;
	fmResult r = fmValidateTargets(b, w, vertices, positions, count, stiffness);
	if (r != fm_ok)
		return r;
	if (!fmTargets_Reserve(b, count))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmBody_SetTargets: no memory for %d targets", count);
	fmGrab_Free(b); // the set replaces a grab
	for (int t = 0; t < count; ++t)
		b->targets[t] = (fmTarget){.vertex = b->internalVertex[vertices[t]],
		                           .position = {positions[t].x, positions[t].y, positions[t].z},
		                           .stiffness = stiffness,
		                           .maxForce = INFINITY};
	b->targetCount = count;
	return fm_ok;
}

fmResult fmBody_SetTargets(fmBodyId bodyId, const int* vertices, const fmVec3* positions, int count,
                           double stiffness)
{
	if (count > 0)
		fmIsland_WakeBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	fmResult result = fmBodySetTargetsIn(bodyId, vertices, positions, count, stiffness);
	fmFpEnv_Leave(&env);
	return result;
}

int fmBody_GetTargetCount(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	return b ? b->targetCount : 0;
}

static double fmTargetsTermEnergy(const void* context, const double* x, const double* xStart,
                                  double* gradient)
{
	(void)xStart; // the step's own (fmTargetStep.xStart)
	return fmTargetsEnergy(context, x, gradient);
}

static void fmTargetsTermHessian(const void* context, const double* x, const fmBsrMatrix* pattern,
                                 double* values)
{
	const fmTargetStep* s = context;
	for (int t = 0; t < fmTargets_Count(s->body); ++t)
	{
		double block[9];
		fmTargetBlock(s, t, x, block);
		int i = fmTargets_At(s->body, t)->vertex;
		double* into =
		    values +
		    9 * (size_t)(pattern != NULL && pattern->diagonal != NULL ? pattern->diagonal[i] : i);
		for (int k = 0; k < 9; ++k)
			into[k] += block[k];
	}
}

static void fmTargetsTermProduct(const void* context, const double* x, const double* dx, double* y)
{
	const fmTargetStep* s = context;
	for (int t = 0; t < fmTargets_Count(s->body); ++t)
	{
		double block[9];
		fmTargetBlock(s, t, x, block);
		int i = fmTargets_At(s->body, t)->vertex;
		for (int a = 0; a < 3; ++a)
			for (int c = 0; c < 3; ++c)
				y[3 * i + a] += block[3 * a + c] * dx[3 * i + c];
	}
}

fmNewtonTerm fmTargets_Term(const fmTargetStep* step)
{
	return (fmNewtonTerm){step, fmTargetsTermEnergy, fmTargetsTermHessian, fmTargetsTermProduct,
	                      NULL};
}
