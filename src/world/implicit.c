// Backward Euler as optimisation (docs/implicit.md): x_{n+1} minimises the incremental potential
//   E(x) = 1/(2 h^2) |x - x_n - h v_n|_M^2 + Psi(x) - M g . x + Rayleigh damping terms
// subject to the pins and the floor y >= height. Newton's method with per-element PSD-projected
// Hessians (Teran et al. 2005), a preconditioned CG for each Newton system, and a backtracking
// (Armijo) line search on E along the floor-projected path (Bertsekas' projected Newton).
// v_{n+1} = (x_{n+1} - x_n) / h, then the body's damping factor, smoothing and floor friction.
#include "world/implicit.h"

#include "body/loads.h"
#include "body/targets.h"
#include "contact/barrier_contact.h"
#include "contact/contact.h"
#include "contact/floor.h"
#include "contact/friction_anchor.h"
#include "contact/penalty.h"
#include "core/core.h"
#include "core/timer.h"
#include "fem/forces.h"
#include "fem/inversion.h"
#include "fem/nodal_pressure.h"
#include "fem/velocity_filter.h"
#include "solver/newton.h"
#include "solver/vbd.h"

#include <math.h>
#include <string.h>

// A first guess replaces the one the last step took when its residual is below this fraction of
// the other's.
#define FM_GUESS_SWITCH 0.5

// Steps before a guess that lost by more than 1 / FM_GUESS_SWITCH is tried again.
#define FM_GUESS_RECHECK 8

// Force scale of a step: |M g| + |M v / h| + |elastic forces at the start|, over free vertices.
// The forces at the start are usually those of the last step's final iterate, still cached.
static double fmStepForceScale(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb, double h)
{
	fmSolverCache_ForcesAtPositions(&b->mesh, c, b->state.x, pb->tasks, pb->arena);
	const fmVec3 gravity = pb->gravity;
	const double g[3] = {gravity.x, gravity.y, gravity.z};
	double weight = 0.0, inertia = 0.0, elastic = 0.0;
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
	{
		if (fmIsDofPinned(&b->state, k))
			continue;
		double m = b->mesh.mass[k / 3];
		weight += m * m * g[k % 3] * g[k % 3];
		inertia += m * m * b->state.v[k] * b->state.v[k] / (h * h);
		elastic += c->forces[k] * c->forces[k];
	}
	// The kinematic targets' pull is an external force too.
	double pull = 0.0;
	const fmTargetStep* targets = pb->targets.context;
	for (int t = 0; t < fmTargets_Count(b); ++t)
	{
		double f[3];
		fmTargets_Force(targets, t, b->state.x, f);
		for (int e = 0; e < 3; ++e)
			pull +=
			    fmIsDofPinned(&b->state, 3 * fmTargets_At(b, t)->vertex + e) ? 0.0 : f[e] * f[e];
	}
	return sqrt(weight) + sqrt(inertia) + sqrt(elastic) + sqrt(pull) + fmLoads_FrozenNorm(b);
}

// Lagged damping matrix D / h at the start of the step: beta K(x_n) (Rayleigh stiffness part)
// plus the springs' dashpots. Returns false when there is none (or no memory for it).
static bool fmPrepareDamping(fmBody* b, fmImplicitCache* c, double h, const fmTaskSystem* tasks)
{
	bool springs = b->mesh.forceModel == fm_massSpring && b->mesh.springDamping > 0.0;
	if (b->rayleighStiffness <= 0.0 && !springs)
		return false;
	size_t values = 9 * (size_t)c->pattern.blocks;
	if (c->damping == NULL)
		c->damping = FM_ALLOC_ARRAY(double, values);
	if (c->damping == NULL)
		return false;
	memset(c->damping, 0, sizeof(double) * values);
	if (b->rayleighStiffness > 0.0)
		fmSolverCache_AddStiffness(&b->mesh, c, c->xStart, b->rayleighStiffness / h, 1, c->damping,
		                           tasks);
	if (springs)
		fmSolverCache_AddSpringDamping(&b->mesh, b->state.invMass, c, c->xStart, 1.0 / h,
		                               c->damping);
	return true;
}

// Whether a vertex of @p x (free to move in y) is on the floor.
static bool fmTouchesFloor(const fmBody* b, const fmImplicitCache* c, const fmFloorDef* floor,
                           const double* x)
{
	for (int i = 0; floor != NULL && i < b->mesh.vertexCount; ++i)
		if (!(b->state.pinned[i] & FM_PIN_Y) && x[3 * i + 1] <= c->floorBound[i])
			return true;
	return false;
}

// The first guess: the free flight already in b->x, or the inertial guess x + h v held above
// the floor. A body resting on the floor or moving steadily starts far closer to the solution
// from x + h v (the free flight sags every vertex by h^2 g against the elastic forces). The
// guess the last step took is tried first and kept if the solve would stop there at once (a
// body at rest: one force pass a frame); otherwise the other replaces it if its relative
// residual is less than half (both are admissible starts; the residual, not the potential,
// decides: docs/decisions.md, "The first guess").
// x + h v is only considered for a body on the floor, a collider or another body (@p touching):
// in the air the free flight is right, and
// for a body whose inertia is below the round-off of its elastic forces (density 1e-20,
// E = 1e20) both residuals are noise, so a comparison could drop the free flight by chance.
static void fmChooseFirstGuess(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                               bool touching)
{
	const int n3 = 3 * b->mesh.vertexCount;
	double* inertial = c->trial;
	memcpy(inertial, c->xPred, sizeof(double) * (size_t)n3);
	if (pb->floor)
		for (int i = 0; i < b->mesh.vertexCount; ++i)
			if (!(b->state.pinned[i] & FM_PIN_Y) && inertial[3 * i + 1] < c->floorBound[i])
				inertial[3 * i + 1] = c->floorBound[i];
	double* favoured = c->coasted ? inertial : b->state.x;
	double* other = c->coasted ? b->state.x : inertial;
	double kept = fmNewton_Residual(&b->mesh, &b->state, c, pb, favoured);
	// A guess that lost clearly is not tried again for a few steps (a wobbling body would
	// otherwise pay a second force pass every step to find that the other guess is worse).
	if (kept > pb->tolerance && c->guessRecheck > 0)
		c->guessRecheck -= 1;
	else if (kept > pb->tolerance &&
	         (c->coasted || touching || fmTouchesFloor(b, c, pb->floor, b->state.x)))
	{
		fmSolverCache_SwapForces(c); // the favoured guess's forces stay at hand
		double challenger = fmNewton_Residual(&b->mesh, &b->state, c, pb, other);
		bool switched = challenger < FM_GUESS_SWITCH * kept;
		c->guessRecheck = challenger > kept / FM_GUESS_SWITCH ? FM_GUESS_RECHECK : 0;
		if (!switched)
			fmSolverCache_SwapForces(c);
		c->coasted = c->coasted != switched;
	}
	if (c->coasted)
		memcpy(b->state.x, inertial, sizeof(double) * (size_t)n3);
}

// The Newton problem of the context's substep h: inertia 1 / h^2, Rayleigh damping, gravity,
// the floor (NULL when it does not hold the body), the loads, targets and contact penalty
// (@p penalty, filled here; absent from the problem without contact), the residual's scale and
// the world's solver settings.
static fmNewtonProblem fmImplicitProblem(const fmWorld* world, const fmStepContext* ctx, fmBody* b,
                                         fmImplicitCache* c, const fmFloorDef* floor,
                                         fmContactPenalty* penalty, const fmBarrierContact* barrier,
                                         fmTargetStep* targets)
{
	const double h = ctx->substep;
	fmArena* arena = ctx->arena;
	fmNewtonProblem pb;
	memset(&pb, 0, sizeof pb);
	pb.inertia = 1.0 / (h * h);
	pb.massDamping = b->rayleighMass / h;
	pb.useDamping = fmPrepareDamping(b, c, h, ctx->tasks);
	pb.gravity = world->def.gravity;
	pb.floor = floor;
	pb.tolerance = world->def.tolerance;
	pb.tasks = ctx->tasks;
	pb.arena = arena;
	*targets = (fmTargetStep){b, c->xStart, 1.0 / h, 1.0 / ctx->frameTime};
	pb.targets = fmTargets_Term(targets);
	pb.scale = fmStepForceScale(b, c, &pb, h);
	pb.maxNewton = ctx->newtonLimit;
	pb.maxCg = world->def.cgIterations;
	pb.quadratic = fmElasticMesh_IsLinear(&b->mesh) && b->mesh.forceModel != fm_massSpring;
	pb.options = world->solverOptions;
	*penalty = (fmContactPenalty){world->colliders,
	                              world->colliderCapacity,
	                              FM_PENALTY_KAPPA / (h * h),
	                              fmContact_Thickness(world),
	                              c->xStart,
	                              h,
	                              b,
	                              fmContact_ColliderBarrier(world),
	                              NULL,
	                              NULL};
	pb.loads = fmLoads_Term(b);
	// Bodies meet through the barrier (barrier_contact.h); the colliders' barrier (or, under
	// vertex block descent's settings, their penalty) holds them off the colliders; its friction
	// term carries the colliders' and the Coulomb floor's friction.
	bool colliders = fmContact_HasColliders(world);
	bool pushes = (colliders && !penalty->barrier) ||
	              (fmContact_BodiesMeet(world) && !fmBarrierContact_Active(world));
	if (colliders || pushes || fmContact_FloorFriction(world))
		pb.contact = fmContactPenalty_Term(penalty);
	pb.barrier = fmBarrierContact_Term(barrier);
	// Neo-Hookean-class bodies keep every tet's orientation through the solve (inversion.h),
	// except with a penalty in the solve: its push needs the collapse the filter forbids (a
	// 10 m/s body against a thin wall tunnels through it within the filter). The barriers'
	// steps are bounded instead: no vertex crosses, so none needs a tet to collapse.
	pb.inversionFree = fmInversion_Needed(&b->mesh) && b->mesh.forceModel == fm_fem && !pushes;
	return pb;
}

// The free flight x + h v + h^2 g held above the floor, as the solve's start: a body in free
// fall is then solved before the first iteration, however stiff or light it is (E / density of
// 1e17 and more leaves the rigid motion to round-off in the elastic forces otherwise).
static void fmImplicitFreeFlight(fmBody* b, fmImplicitCache* c, double h, fmVec3 gravity,
                                 const fmFloorDef* floor)
{
	const double g[3] = {gravity.x, gravity.y, gravity.z};
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		b->state.x[k] = fmIsDofPinned(&b->state, k) ? c->xPred[k] : c->xPred[k] + h * h * g[k % 3];
	if (floor)
	{
		fmFloor_SetBounds(floor, b, c, h);
		for (int i = 0; i < b->mesh.vertexCount; ++i)
			if (!(b->state.pinned[i] & FM_PIN_Y) && b->state.x[3 * i + 1] < c->floorBound[i])
				b->state.x[3 * i + 1] = c->floorBound[i];
	}
}

// An inversion-free solve starts where no tet is flat or inverted: the guesses may squash tets
// against the floor (their vertices lifted to it), the step's start cannot. Where even the start
// lifted to the floor's bounds flattens a tet (a body pushed below the floor further than the
// floor lifts in a step), no path keeps every tet: this step goes without the filter.
static void fmInversionFreeStart(fmBody* b, fmImplicitCache* c, fmNewtonProblem* pb,
                                 const fmFloorDef* floor)
{
	const size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
	if (!pb->inversionFree || !fmInversion_Any(&b->mesh, c->xStart, b->state.x))
		return;
	memcpy(b->state.x, c->xStart, bytes);
	if (floor == NULL)
		return;
	memcpy(c->trial, c->xStart, bytes); // free until the line search
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (!(b->state.pinned[i] & FM_PIN_Y) && c->trial[3 * i + 1] < c->floorBound[i])
			c->trial[3 * i + 1] = c->floorBound[i];
	pb->inversionFree = !fmInversion_Any(&b->mesh, c->xStart, c->trial);
}

// A barrier's solve starts where no surfaces cross and no vertex is in a collider: the first
// guess is taken only as far along the straight path from the step's start as no pair (and no
// vertex and collider) closes to a tenth of its gap.
static void fmBarrierFreeStart(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb)
{
	if (!fmNewton_Bounded(pb))
		return;
	const int n3 = 3 * b->mesh.vertexCount;
	for (int k = 0; k < n3; ++k)
		c->trial[k] = b->state.x[k] - c->xStart[k];
	double t = fmNewton_StepBound(pb, c->xStart, c->trial);
	if (t >= 1.0)
		return;
	for (int k = 0; k < n3; ++k)
		b->state.x[k] = c->xStart[k] + t * c->trial[k];
}

// The work the step's targets, loads and contact penalty did, booked with the ledger.
static void fmImplicitAddWork(const fmStepContext* ctx, fmBody* b, fmImplicitCache* c,
                              const fmNewtonProblem* pb)
{
	fmStepContext_AddContactWork(ctx, b->slot,
	                             fmTargets_ImplicitWork(pb->targets.context, b->state.x));
	if (fmLoads_Active(b))
	{
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			c->trial[k] = b->state.x[k] - c->xStart[k]; // free after the solve
		fmStepContext_AddLoadWork(ctx, b->slot, fmLoads_Work(b, c->trial, 1.0));
	}
	fmStepContext_AddContactWork(ctx, b->slot,
	                             fmContactPenalty_Work(pb->contact.context, b, c->xStart));
	if (pb->barrier.context != NULL)
		fmStepContext_AddContactWork(ctx, b->slot,
		                             fmBarrierContact_Work(pb->barrier.context, b->state.x));
}

fmResult fmImplicitStep(const fmWorld* world, const fmStepContext* ctx, fmBody* b,
                        fmNewtonResult* solve)
{
	const double h = ctx->substep;
	fmArena* arena = ctx->arena;
	memset(solve, 0, sizeof *solve);
	fmImplicitCache* c = fmSolverCache_Get(&b->solverCache, &b->mesh);
	if (c == NULL)
		return fm_errOutOfMemory;
	const int n3 = 3 * b->mesh.vertexCount;
	const fmFloorDef* floor = fmFloor_Applies(&world->def.floor, b) ? &world->def.floor : NULL;
	b->contact.floorHitCount = 0;

	// 1. Start state and inertial prediction (pinned axes stay put), the free flight as the first
	//    guess. Prescribed displacements move their vertices first; the loads are frozen at the
	//    start (follower pressure lagged by one step, loads.h).
	double start = fmSeconds();
	fmStepContext_AddLoadWork(ctx, b->slot, fmLoads_StepPrescribed(b, h, 0.0));
	fmLoads_Freeze(b, b->state.x, 1.0);
	memcpy(c->xStart, b->state.x, sizeof(double) * (size_t)n3);
	for (int k = 0; k < n3; ++k)
		c->xPred[k] =
		    fmIsDofPinned(&b->state, k) ? b->state.x[k] : b->state.x[k] + h * b->state.v[k];
	fmContactPenalty penalty;
	fmBarrierContact barrier;
	fmTargetStep targets;
	memset(&barrier, 0, sizeof barrier);
	if (fmBarrierContact_Active(world) &&
	    !fmBarrierContact_Begin(&barrier, world, b->slot, c->xStart, c->xPred, 1.0 / (h * h),
	                            ctx->worker))
		return fm_errOutOfMemory;
	fmNewtonProblem pb = fmImplicitProblem(world, ctx, b, c, floor, &penalty, &barrier, &targets);
	if (pb.contact.energy != NULL && fmContact_HasColliders(world))
		fmContactPenalty_Prepare(&penalty, b, world->def.floor.maxDepenetrationSpeed);
	fmImplicitFreeFlight(b, c, h, world->def.gravity, floor);
	fmChooseFirstGuess(b, c, &pb,
	                   (pb.barrier.energy != NULL && barrier.touching) ||
	                       fmContactPenalty_Touches(&penalty, b));
	fmInversionFreeStart(b, c, &pb, floor);
	fmBarrierFreeStart(b, c, &pb);

	// 2. Newton on the incremental potential.
	*solve = world->def.implicitSolver == fm_solverVbd && !pb.useDamping &&
	                 fmTargets_Count(b) == 0 && !fmLoads_Active(b) && pb.barrier.energy == NULL &&
	                 !fmNodalPressure_On(&b->mesh) // (a patch couples more than a vertex's tets)
	             ? fmVbd_Solve(&b->mesh, &b->state, c, &pb)
	             : fmNewton_Solve(&b->mesh, &b->state, c, &pb);
	double solved = fmSeconds();
	b->stepStage[0] = solved - start;
	if (!solve->finite)
		return fm_errNumerical;

	// 3. Velocities from the positions, then the body's damping factor and smoothing (as in
	//    explicit mode, so that a scene behaves alike under both integrators).
	fmImplicitAddWork(ctx, b, c, &pb);
	if (!fmFrictionAnchor_Keep(&barrier, b))
		return fm_errOutOfMemory;
	for (int k = 0; k < n3; ++k)
		b->state.v[k] = fmIsDofPinned(&b->state, k) ? 0.0 : (b->state.x[k] - c->xStart[k]) / h;
	fmFilterVelocities(&b->mesh, &b->state, b->damping, b->smoothing, h / FM_SEED_STEP, arena,
	                   world->simd, ctx->tasks);

	// 4. Floor: its work to the ledger, then restitution and friction on the velocities of the
	//    vertices on it.
	if (floor)
	{
		fmStepContext_AddContactWork(ctx, b->slot, fmFloor_ImplicitWork(b, c, floor->height));
		if (fmFloor_ImplicitVelocities(floor, b, c, h, fmContact_FloorFriction(world)) < 0)
			return fm_errOutOfMemory;
	}
	b->stepStage[1] = fmSeconds() - solved;
	return fm_ok;
}
