// The seeds' velocity damping factor and Laplacian velocity smoothing (GAMES103 HW3 1.1, 1.4),
// shared by both integrators.
//
// The seeds give both per step of 3 ms. Applied per step as they are, a 1/60 s implicit step
// would damp 5.6 times less per second than the explicit 3 ms steps of the same scene, and a
// scene would change character with its time step. So both are rates: the factor d and the
// blend s are what one 3 ms step does, and a step of n such steps (seedSteps = dt / FM_SEED_STEP,
// the integrator's to give) applies d^n and 1 - (1 - s)^n. At the seeds' step this is exactly the
// seeds' filter.
#include "fem/velocity_filter.h"

#include "core/det_math.h"
#include "fem/tet_blocks.h"

#include <math.h>
#include <string.h>

// v <- (1 - s) v + s * (average velocity of the tets around each vertex), the GAMES103 Smooth_V:
// every tet adds the sum of its 4 velocities to each of its vertices, divided by 4 * tets around.
// On several workers each vertex gathers the sums of its tets in tet order instead: the same
// additions in the same order as the scatter, so the same bits.
typedef struct fmSmoothTask
{
	const fmElasticMesh* mesh;
	fmBodyState* state;
	double blend;
	double* sum;            // 3 per vertex
	const fmThenTask* then; // after the blend of each range, or NULL
	fmVertexUpdate update;  // the blend's arrays and weights (fmVertexKernel_Blend)
	fmVertexKernelFcn* blendKernel;
} fmSmoothTask;

static fmVec3 fmTetVelocitySum(const fmElasticMesh* mesh, const double* v, int t)
{
	const int* n = mesh->tets + 4 * t;
	return fmAdd(fmAdd(fmLoad(v, n[0]), fmLoad(v, n[1])), fmAdd(fmLoad(v, n[2]), fmLoad(v, n[3])));
}

static void fmGatherSumsTask(int start, int end, int worker, void* context)
{
	(void)worker;
	fmSmoothTask* c = context;
	const fmElasticMesh* mesh = c->mesh;
	for (int i = start; i < end; ++i)
	{
		fmVec3 sum = {0, 0, 0};
		for (int k = mesh->vertexTetStart[i]; k < mesh->vertexTetStart[i + 1]; ++k)
			sum = fmAdd(sum, fmTetVelocitySum(mesh, c->state->v, mesh->vertexTets[k] / 4));
		fmStore(c->sum, i, sum);
	}
}

static void fmBlendTask(int start, int end, int worker, void* context)
{
	const fmSmoothTask* c = context;
	c->blendKernel(&c->update, start, end);
	if (c->then != NULL)
		c->then->task(start, end, worker, c->then->context);
}

static bool fmSmoothVelocities(const fmElasticMesh* mesh, fmBodyState* state, double blend,
                               fmArena* arena, fmSimdLevel level, const fmTaskSystem* tasks,
                               const fmThenTask* then)
{
	size_t mark = fmArena_Mark(arena);
	// The blocks' sums and the gather write every vertex's sum; the scatter adds to zeros.
	bool gather = mesh->tetBlocks != NULL ||
	              (tasks != NULL && (tasks->workerCount > 1 || tasks->enqueueTask != NULL) &&
	               mesh->vertexCount >= 2 * FM_PARALLEL_MIN_VERTICES);
	size_t count = 3 * (size_t)mesh->vertexCount;
	fmSmoothTask context = {.mesh = mesh,
	                        .state = state,
	                        .blend = blend,
	                        .sum = gather ? fmArena_DoublesUninit(arena, count)
	                                      : fmArena_Doubles(arena, count),
	                        .then = then};
	if (context.sum == NULL)
		return false;
	context.update = (fmVertexUpdate){.v = state->v,
	                                  .weight = mesh->smoothWeight,
	                                  .sum = context.sum,
	                                  .pinned = state->pinned,
	                                  .keep = 1.0 - blend,
	                                  .blend = blend};
	context.blendKernel = fmTetBlocks_Kernels(level).blend;
	if (mesh->tetBlocks != NULL) // the explicit kernels' blocks, where the body has them
		fmTetBlocks_SmoothingSums(mesh->tetBlocks, state->v, context.sum, level, tasks);
	else if (gather)
		fmParallelFor(tasks, mesh->vertexCount, FM_PARALLEL_MIN_VERTICES, fmGatherSumsTask,
		              &context);
	else
		for (int t = 0; t < mesh->tetCount; ++t)
		{
			fmVec3 s = fmTetVelocitySum(mesh, state->v, t);
			const int* n = mesh->tets + 4 * t;
			for (int a = 0; a < 4; ++a)
				fmStore(context.sum, n[a], fmAdd(fmLoad(context.sum, n[a]), s));
		}
	fmParallelFor(tasks, mesh->vertexCount, FM_PARALLEL_MIN_VERTICES, fmBlendTask, &context);
	fmArena_Release(arena, mark);
	return true;
}

typedef struct fmDampTask
{
	double* v;
	double factor;
} fmDampTask;

// v *= factor for vertices [start, end).
static void fmDampTaskRun(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmDampTask* c = context;
	for (int k = 3 * start; k < 3 * end; ++k)
		c->v[k] *= c->factor;
}

double fmVelocityFilter_DampingFactor(double damping, double seedSteps)
{
	return damping < 1.0 ? fmMathPow(damping, seedSteps) : 1.0;
}

bool fmVelocityFilter_Smooth(const fmElasticMesh* mesh, fmBodyState* state, double smoothing,
                             double seedSteps, fmArena* arena, fmSimdLevel level,
                             const fmTaskSystem* tasks, const fmThenTask* then)
{
	return smoothing > 0.0 &&
	       fmSmoothVelocities(mesh, state, 1.0 - fmMathPow(1.0 - smoothing, seedSteps), arena,
	                          level, tasks, then);
}

void fmFilterVelocities(const fmElasticMesh* mesh, fmBodyState* state, double damping,
                        double smoothing, double seedSteps, fmArena* arena, fmSimdLevel level,
                        const fmTaskSystem* tasks)
{
	if (damping < 1.0)
	{
		fmDampTask damp = {state->v, fmVelocityFilter_DampingFactor(damping, seedSteps)};
		fmParallelFor(tasks, mesh->vertexCount, FM_PARALLEL_MIN_VERTICES, fmDampTaskRun, &damp);
	}
	fmVelocityFilter_Smooth(mesh, state, smoothing, seedSteps, arena, level, tasks, NULL);
}
