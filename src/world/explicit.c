// Explicit integration, as the seeds: symplectic Euler with a velocity damping factor and
// Laplacian velocity smoothing (GAMES103 HW3 1.1 and 1.4), then the floor.
#include "world/explicit.h"

#include "body/loads.h"
#include "body/targets.h"
#include "contact/floor.h"
#include "core/det_math.h"
#include "core/timer.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/tet_blocks.h"
#include "fem/velocity_filter.h"

#include <string.h>

// Rayleigh damping force -(alpha M + beta K) v, with K the (unprojected) stiffness at x.
static void fmAddRayleighForces(fmBody* b, fmArena* arena)
{
	if (b->rayleighMass > 0.0)
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			b->state.f[k] -= b->rayleighMass * b->mesh.mass[k / 3] * b->state.v[k];
	if (b->rayleighStiffness > 0.0)
	{
		size_t mark = fmArena_Mark(arena);
		double* kv = fmArena_Doubles(arena, 3 * (size_t)b->mesh.vertexCount);
		if (kv == NULL)
			return;
		fmAddHessianProduct(&b->mesh, b->state.x, b->state.v, kv, 0);
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			b->state.f[k] -= b->rayleighStiffness * kv[k];
		fmArena_Release(arena, mark);
	}
}

// The kinematic targets' springs and dashpots in an explicit substep of @p dt in a frame of
// @p frameTime: f += their forces at the current positions and velocities, each spring's
// stiffness limited to mass / dt^2 and each dashpot to mass / (2 dt) (stable with the elastic
// forces for any target), each force kept for the target's work.
static void fmAddTargetForces(fmBody* b, double dt, double frameTime, double* f)
{
	for (int t = 0; t < fmTargets_Count(b); ++t)
	{
		fmTarget* target = fmTargets_At(b, t);
		double m = b->mesh.mass[target->vertex];
		fmTargets_ExplicitForce(target, b->state.x, b->state.v,
		                        (target->damping > 0.0 ? 0.25 : 1.0) * m / (dt * dt), 0.25 * m / dt,
		                        1.0 / frameTime, target->applied);
		for (int e = 0; e < 3; ++e)
			f[3 * target->vertex + e] += target->applied[e];
	}
}

// The work the targets' forces do over the coming position update x += dt v (J).
static double fmTargetWork(const fmBody* b, double dt)
{
	double work = 0.0;
	for (int t = 0; t < fmTargets_Count(b); ++t)
		for (int e = 0; e < 3; ++e)
			work += fmTargets_At(b, t)->applied[e] * dt *
			        b->state.v[3 * fmTargets_At(b, t)->vertex + e];
	return work;
}

// What the tasks of a parallel explicit step share (each writes only its own range).
typedef struct fmExplicitTask
{
	fmBody* body;
	double dt;
	fmVec3 gravity;
	// With a floor that holds the body: its responses to the vertices it takes, made after
	// their position update on each range.
	const fmFloorDef* floor;
	fmFloorTaken* floorTaken;
	fmVertexUpdate update;         // the body's arrays for the vertex kernels
	fmVertexKernelFcn* velocities; // of the world's instruction set
	fmVertexKernelFcn* positions;
} fmExplicitTask;

// Stage 1 for vertices [start, end): f = m g.
static void fmGravityTask(int start, int end, int worker, void* context)
{
	(void)worker;
	fmExplicitTask* c = context;
	fmBody* b = c->body;
	for (int i = start; i < end; ++i)
		fmStore(b->state.f, i, fmScale(b->mesh.mass[i], c->gravity));
}

// Stage 2 for vertices [start, end): v += dt f / m, then the seeds' damping factor (one pass:
// the same bits as the velocity filter's own; a factor of 1 leaves v as it is); pinned vertices
// stay at rest (fmVertexKernel_Velocities).
static void fmVelocitiesTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmExplicitTask* c = context;
	c->velocities(&c->update, start, end);
}

// Stage 4 for vertices [start, end): x += dt v, then the floor's response to each vertex it
// takes (collected in vertex order by fmFloor_ApplyExplicit).
static void fmPositionsTask(int start, int end, int worker, void* context)
{
	(void)worker;
	fmExplicitTask* c = context;
	c->positions(&c->update, start, end);
	if (c->floorTaken != NULL)
		fmFloor_RespondRange(c->floor, c->gravity, c->body, start, end, c->dt, c->floorTaken);
}

// f = m g + the elastic forces: the batched float kernels where they apply and are accurate
// (made on the body's first explicit step; gravity then comes with their last pass), else the
// double-precision reference kernel (also when memory is short). With the kernels, a non-NULL
// @p then runs on each vertex range right after its forces; returns whether it ran.
static bool fmGravityAndElasticForces(const fmWorld* world, const fmTaskSystem* tasks, fmBody* b,
                                      fmExplicitTask* context, fmArena* arena,
                                      const fmThenTask* then)
{
	if (b->mesh.tetBlocks == NULL && fmTetBlocks_Applies(&b->mesh, world->simd))
		b->mesh.tetBlocks = fmTetBlocks_Create(&b->mesh, world->tasks.workerCount);
	const fmTetBlocks* blocks = fmTetBlocks_Used(&b->mesh, world->simd);
	if (blocks != NULL)
	{
		fmTetBlocks_AddForces(blocks, &b->mesh, b->state.x, &context->gravity, b->state.f,
		                      world->simd, tasks, false, NULL, then);
		return then != NULL;
	}
	fmParallelFor(tasks, b->mesh.vertexCount, FM_PARALLEL_MIN_VERTICES, fmGravityTask, context);
	fmAddElasticForcesOn(&b->mesh, b->state.x, b->state.f, tasks, arena);
	return false;
}

// Whether nothing comes between the elastic forces and the velocity update, nor between the
// smoothing and the position update (no spring or Rayleigh damping, kinematic targets or loads):
// then each stage runs on a vertex range right after the one before (two passes fewer, the same
// operations in the same order).
static bool fmPlainStep(const fmBody* b)
{
	return b->mesh.forceModel != fm_massSpring && b->rayleighMass <= 0.0 &&
	       b->rayleighStiffness <= 0.0 && fmTargets_Count(b) == 0 && !fmLoads_Active(b);
}

fmResult fmExplicitStep(const fmWorld* world, const fmStepContext* ctx, fmBody* b)
{
	const double dt = ctx->substep;
	fmArena* arena = ctx->arena;
	const int n = b->mesh.vertexCount;
	const fmTaskSystem* tasks = ctx->tasks;
	const fmTetKernels kernels = fmTetBlocks_Kernels(world->simd);
	const double damping = fmVelocityFilter_DampingFactor(b->damping, dt / FM_SEED_STEP);
	fmExplicitTask context = {.body = b,
	                          .dt = dt,
	                          .gravity = world->def.gravity,
	                          .update = {.x = b->state.x,
	                                     .v = b->state.v,
	                                     .f = b->state.f,
	                                     .invMass = b->state.invMass,
	                                     .pinned = b->state.pinned,
	                                     .dt = dt,
	                                     .damping = damping},
	                          .velocities = kernels.velocities,
	                          .positions = kernels.positions};
	const size_t mark = fmArena_Mark(arena);
	fmFloorTaken floorTaken;
	if (fmFloor_Applies(&world->def.floor, b) && fmFloorTaken_Make(&floorTaken, arena, n))
	{
		// (Without the memory the floor responds serially, after the position update.)
		context.floor = &world->def.floor;
		context.floorTaken = &floorTaken;
	}

	// 0. Prescribed displacements move their vertices along their paths (loads.h).
	double start = fmSeconds();
	fmStepContext_AddLoadWork(ctx, b->slot, fmLoads_StepPrescribed(b, dt, dt));

	// 1. Gravity, elastic, damping, kinematic targets' forces and the loads.
	const bool plain = fmPlainStep(b);
	const fmThenTask velocities = {fmVelocitiesTask, &context},
	                 positions = {fmPositionsTask, &context};
	bool moved =
	    fmGravityAndElasticForces(world, tasks, b, &context, arena, plain ? &velocities : NULL);
	if (b->mesh.forceModel == fm_massSpring)
		fmAddSpringDamping(&b->mesh, b->state.invMass, b->state.x, b->state.v, b->state.f);
	fmAddRayleighForces(b, arena);
	fmAddTargetForces(b, dt, ctx->frameTime, b->state.f);
	const double* loads = fmLoads_Freeze(b, b->state.x, 1.0);
	for (int k = 0; loads != NULL && k < 3 * n; ++k)
		b->state.f[k] += loads[k];
	double forced = fmSeconds();

	// 2. Velocities: v += dt f / m, and the seeds' damping factor. Pinned vertices stay at rest.
	if (!moved)
		fmParallelFor(tasks, n, FM_PARALLEL_MIN_VERTICES, fmVelocitiesTask, &context);

	// 3. The seeds' Laplacian smoothing against high-frequency oscillation.
	bool placed = fmVelocityFilter_Smooth(&b->mesh, &b->state, b->smoothing, dt / FM_SEED_STEP,
	                                      arena, world->simd, tasks, plain ? &positions : NULL) &&
	              plain;
	fmStepContext_AddContactWork(ctx, b->slot, fmTargetWork(b, dt));
	// The loads' work over the coming position update x += dt v: exact for constant loads.
	fmStepContext_AddLoadWork(ctx, b->slot, fmLoads_Work(b, b->state.v, dt));

	// 4. Positions, then the floor.
	if (!placed)
		fmParallelFor(tasks, n, FM_PARALLEL_MIN_VERTICES, fmPositionsTask, &context);
	double floorWork;
	int floorContacts = fmFloor_ApplyExplicit(&world->def.floor, world->def.gravity, b, dt,
	                                          context.floorTaken, &floorWork);
	fmStepContext_AddContactWork(ctx, b->slot, floorWork);
	fmArena_Release(arena, mark);
	b->stepStage[0] = forced - start;
	b->stepStage[1] = fmSeconds() - forced;
	return floorContacts >= 0 ? fm_ok : fm_errOutOfMemory;
}
