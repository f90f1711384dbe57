// Kinematic targets (targets.h) and fmBody_SetTargets.
#include "body/targets.h"
#include "core/det_math.h"

#include "core/core.h"
#include "core/fp_env.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

double fmTargets_Energy(const fmBody* b, const double* x, double* gradient)
{
	double energy = 0.0;
	for (int t = 0; t < b->targetCount; ++t)
	{
		int i = b->targetVertex[t];
		for (int e = 0; e < 3; ++e)
		{
			double d = x[3 * i + e] - b->targetPosition[3 * t + e];
			energy += 0.5 * b->targetStiffness * d * d;
			if (gradient)
				gradient[3 * i + e] += b->targetStiffness * d;
		}
	}
	return energy;
}

void fmTargets_AddProduct(const fmBody* b, const double* x, double* y)
{
	for (int t = 0; t < b->targetCount; ++t)
	{
		int i = b->targetVertex[t];
		for (int e = 0; e < 3; ++e)
			y[3 * i + e] += b->targetStiffness * x[3 * i + e];
	}
}

void fmTargets_AddDiagonal(const fmBody* b, const int* diagonal, double* values)
{
	for (int t = 0; t < b->targetCount; ++t)
	{
		int i = b->targetVertex[t];
		double* block = values + 9 * (size_t)(diagonal ? diagonal[i] : i);
		for (int e = 0; e < 3; ++e)
			block[4 * e] += b->targetStiffness;
	}
}

double fmTargets_ImplicitWork(const fmBody* b, const double* xStart)
{
	double work = 0.0;
	for (int t = 0; t < b->targetCount; ++t)
	{
		int i = b->targetVertex[t];
		for (int e = 0; e < 3; ++e)
			work += b->targetStiffness * (b->targetPosition[3 * t + e] - b->state.x[3 * i + e]) *
			        (b->state.x[3 * i + e] - xStart[3 * i + e]);
	}
	return work;
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

// Room for @p count targets (grows, never shrinks: dragging calls this every frame).
static bool fmReserveTargets(fmBody* b, int count)
{
	if (count <= b->targetCapacity)
		return true;
	int* vertex = FM_ALLOC_ARRAY(int, count);
	double* position = FM_ALLOC_ARRAY(double, 3 * (size_t)count);
	if (vertex == NULL || position == NULL)
	{
		FM_FREE_ARRAY(vertex, int, count);
		FM_FREE_ARRAY(position, double, 3 * (size_t)count);
		return false;
	}
	FM_FREE_ARRAY(b->targetVertex, int, b->targetCapacity);
	FM_FREE_ARRAY(b->targetPosition, double, 3 * (size_t)b->targetCapacity);
	b->targetVertex = vertex;
	b->targetPosition = position;
	b->targetCapacity = count;
	return true;
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
	if (!fmReserveTargets(b, count))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmBody_SetTargets: no memory for %d targets", count);
	for (int t = 0; t < count; ++t)
	{
		b->targetVertex[t] = b->internalVertex[vertices[t]];
		b->targetPosition[3 * t] = positions[t].x;
		b->targetPosition[3 * t + 1] = positions[t].y;
		b->targetPosition[3 * t + 2] = positions[t].z;
	}
	b->targetCount = count;
	b->targetStiffness = stiffness;
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
	(void)xStart;
	return fmTargets_Energy(context, x, gradient);
}

static void fmTargetsTermHessian(const void* context, const double* x, const fmBsrMatrix* pattern,
                                 double* values)
{
	(void)x;
	fmTargets_AddDiagonal(context, pattern != NULL ? pattern->diagonal : NULL, values);
}

static void fmTargetsTermProduct(const void* context, const double* x, const double* dx, double* y)
{
	(void)x;
	fmTargets_AddProduct(context, dx, y);
}

fmNewtonTerm fmTargets_Term(const fmBody* body)
{
	return (fmNewtonTerm){body, fmTargetsTermEnergy, fmTargetsTermHessian, fmTargetsTermProduct,
	                      NULL};
}
