// Static equilibrium: minimise Psi(x) - M g . x over the free vertices (docs/implicit.md).
// The same Newton minimiser as the implicit step without the inertia term; when Newton stalls
// (line search fails, or the iteration budget runs out) the load is ramped: gravity is applied
// in fractions that are halved until each one converges from the last equilibrium.
#include "body/anchors.h"
#include "body/loads.h"
#include "body/plasticity.h"
#include "body/targets.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"
#include "fem/forces.h"
#include "solver/newton.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// Fixed-point rounds of a follower load at full load (loads.h): the solve is repeated with the
// load re-frozen at its result until that result already balances it.
#define FM_MAX_FOLLOWER_ROUNDS 50

// Smallest load fraction increment before giving up.
#define FM_MIN_LOAD_STEP (1.0 / 256.0)

// |v| over every DOF.
static double fmStaticNorm(int n3, const double* v)
{
	double sum = 0.0;
	for (int k = 0; k < n3; ++k)
		sum += v[k] * v[k];
	return sqrt(sum);
}

// The size of the round-off in the elastic forces: a relative 1e-13 (as the energy's noise
// band, newton.c) of the force (mu + |lambda|) V / L that strains the body by one, V its
// volume and L its largest extent (the rest forces of an unstructured mesh measure 1e-16 of
// it). Forces below it strain the body by less than 1e-13: nothing pulls.
static double fmStaticForceRoundOff(const fmBody* b)
{
	double stiffness = 0.0, lo[3], hi[3];
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		const fmMaterial* m = fmTetUserMaterial(&b->mesh, t); // (its volume term wherever it is)
		stiffness += (m->mu + fabs(m->lambda)) * b->mesh.restVolume[t];
	}
	for (int e = 0; e < 3; ++e)
		lo[e] = hi[e] = b->state.x[e];
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
	{
		lo[k % 3] = fmMin(lo[k % 3], b->state.x[k]);
		hi[k % 3] = fmMax(hi[k % 3], b->state.x[k]);
	}
	double extent = fmMax(hi[0] - lo[0], fmMax(hi[1] - lo[1], hi[2] - lo[2]));
	return extent > 0.0 ? 1e-13 * stiffness / extent : 0.0;
}

// The force scale F of a static solve: its residual is |unbalanced force on the free DOFs| / F
// (docs/implicit.md, "Static equilibrium"). F adds up the sizes of the forces the problem puts
// on the body, measured at the start (b->x; the prescribed vertices not yet moved):
//  - the weight |M g| and the frozen loads, on the free DOFs;
//  - the elastic forces of the start shape, on every DOF: what is unbalanced on the free ones
//    (a body set in a deformed shape) and the supports' reaction on the held ones (a body
//    already deformed by its supports, solved again);
//  - the reaction the prescribed displacements cause: the change of the elastic forces, on
//    every DOF, when the held vertices are moved by their full displacement and the others
//    left where they are (K u_p for a linear material). Without it a solve driven by
//    prescribed displacements alone was measured against the rest shape's elastic forces:
//    zero on a generated box, round-off on an unstructured (TetGen) mesh, where the residual
//    was then divided by round-off and no state could be reported converged.
// @p scratch holds 3n doubles. Returns 0 when nothing pulls.
static double fmStaticForceScale(fmBody* b, fmImplicitCache* c, fmVec3 gravity, double* scratch)
{
	const int n3 = 3 * b->mesh.vertexCount;
	const double g[3] = {gravity.x, gravity.y, gravity.z};
	double weight = 0.0;
	for (int k = 0; k < n3; ++k)
		if (!fmIsDofPinned(&b->state, k))
			weight += b->mesh.mass[k / 3] * b->mesh.mass[k / 3] * g[k % 3] * g[k % 3];
	fmLoads_Freeze(b, b->state.x, 1.0);
	double loads = fmLoads_FrozenNorm(b);

	fmSolverCache_ForcesAtPositions(&b->mesh, c, b->state.x, NULL, NULL); // once a solve: serial
	double elastic = fmStaticNorm(n3, c->forces);
	double prescribed = 0.0;
	if (b->loads != NULL && b->loads->prescribedCount > 0)
	{
		// (The same force function as c->forces: a displacement of zero changes no bit.)
		fmLoads_PlaceStatic(b, 1.0);
		memset(scratch, 0, sizeof(double) * (size_t)n3);
		fmAddElasticForcesOn(&b->mesh, b->state.x, scratch, NULL, NULL);
		memcpy(b->state.x, c->xStart, sizeof(double) * (size_t)n3);
		for (int k = 0; k < n3; ++k)
			scratch[k] -= c->forces[k];
		prescribed = fmStaticNorm(n3, scratch);
	}
	double scale = sqrt(weight) + loads + elastic + prescribed;
	return scale > fmStaticForceRoundOff(b) ? scale : 0.0;
}

// Place the prescribed vertices and freeze the loads at fraction @p load, then solve.
static fmNewtonResult fmStaticSolveAt(fmBody* b, fmImplicitCache* c, fmNewtonProblem* pb,
                                      fmVec3 gravity, double load)
{
	pb->gravity = fmScale(load, gravity);
	fmLoads_PlaceStatic(b, load);
	fmLoads_Freeze(b, b->state.x, load);
	return fmNewton_Solve(&b->mesh, &b->state, c, pb);
}

// A follower load at full load: re-freeze at the result and solve again until the solve starts
// converged (Newton takes no step). Returns the last solve's result.
static fmNewtonResult fmStaticFollowerRounds(fmBody* b, fmImplicitCache* c, fmNewtonProblem* pb,
                                             fmVec3 gravity, fmNewtonResult r, int* iterations)
{
	if (b->loads == NULL || b->loads->followerCount == 0)
		return r;
	for (int round = 0; round < FM_MAX_FOLLOWER_ROUNDS && (r.converged || r.stagnated); ++round)
	{
		r = fmStaticSolveAt(b, c, pb, gravity, 1.0);
		*iterations += r.iterations;
		if (r.converged && r.iterations == 0)
			break;
	}
	return r;
}

// The arguments and the body a static solve needs: a live body, a tolerance and an iteration
// budget in range, and something that holds it where gravity or loads pull.
static fmResult fmStaticCheck(const fmBody* b, const fmWorld* world, double tolerance,
                              int maxIterations, fmDiagnostic* diag)
{
	FM_ASSERT(b != NULL && world != NULL); // a stale id is a programmer error, as everywhere
	if (b == NULL || world == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid or destroyed body id");
	if (!(tolerance >= FM_MIN_TOLERANCE && tolerance < 1.0) || maxIterations < 1 ||
	    maxIterations > FM_MAX_NEWTON_ITERATIONS)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "static solve needs a tolerance in [%g, 1) (e.g. 1e-8) and 1 to %d "
		                   "Newton iterations, got %g and %d",
		                   FM_MIN_TOLERANCE, FM_MAX_NEWTON_ITERATIONS, tolerance, maxIterations);
	int pins = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		pins += b->state.pinned[i] != 0; // rollers count: a well-posed set of them holds the body
	// Three springs to targets or attachments hold a body as well (no rigid motion is free).
	if (pins == 0 && fmTargets_Count(b) < 3 &&
	    (fmLength(world->def.gravity) > 0.0 || fmLoads_Active(b)))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "the body has no pinned vertex and fewer than three targets or "
		                   "attachments, so under gravity or loads it has no equilibrium (it would "
		                   "fall or drift forever): pin something (fmBody_PinBox, "
		                   "fmBody_PinBoxAxes) or attach it first");
	return fm_ok;
}

// The Newton problem of a static solve: no mass term, the exact Hessian (projected ones slow
// Newton to linear convergence without inertia; CG detects when it stops being positive
// definite), the best state kept, CG given room (the system is as ill-conditioned as the
// structure), the residual measured against fmStaticForceScale.
static fmNewtonProblem fmStaticProblem(fmBody* b, fmImplicitCache* c, fmWorld* world,
                                       double tolerance, int maxIterations, double* scratch,
                                       const fmTargetStep* targets)
{
	const int n3 = 3 * b->mesh.vertexCount;
	fmNewtonProblem pb;
	memset(&pb, 0, sizeof pb);
	pb.tolerance = tolerance;
	pb.scale = fmStaticForceScale(b, c, world->def.gravity, scratch);
	pb.maxNewton = maxIterations;
	pb.maxCg = world->def.cgIterations > n3 + 100 ? world->def.cgIterations : n3 + 100;
	pb.quadratic = fmElasticMesh_IsLinear(&b->mesh) && b->mesh.forceModel != fm_massSpring;
	pb.options = world->solverOptions;
	pb.tasks = &world->tasks;
	pb.arena = &world->arena;
	pb.exactHessian = true;
	pb.keepBest = true;
	pb.loads = fmLoads_Term(b);
	pb.targets = fmTargets_Term(targets);
	return pb;
}

// Load stepping: from the last converged fraction *@p done, try done + step; halve the step on
// failure, double it again after a success. A solve that stagnates close to the tolerance has
// met round-off, which a smaller load does not cure: its load level is kept (at its best state)
// and the result says how close it got. @p equilibrium holds the last equilibrium reached.
static fmNewtonResult fmStaticLoadSteps(fmBody* b, fmImplicitCache* c, fmNewtonProblem* pb,
                                        fmVec3 gravity, double* equilibrium, double* done,
                                        int* iterations)
{
	const size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
	double step = 1.0;
	fmNewtonResult r;
	memset(&r, 0, sizeof r);
	r.converged = true;
	r.finite = true;
	while (*done < 1.0)
	{
		double load = fmMin(1.0, *done + step);
		r = fmStaticSolveAt(b, c, pb, gravity, load);
		*iterations += r.iterations;
		if (r.projected)
		{
			// The true Hessian went indefinite (buckling-like states, compressed springs):
			// continue from here with per-element projected Hessians, always descent.
			pb->exactHessian = false;
			r = fmNewton_Solve(&b->mesh, &b->state, c, pb);
			*iterations += r.iterations;
		}
		// Stagnation means steps within the energy's round-off that no longer improve the
		// residual: a smaller load does not cure that. (A stalled line search may.)
		bool roundOff = r.finite && r.stagnated;
		if (r.converged || roundOff)
		{
			memcpy(equilibrium, b->state.x, bytes);
			*done = load;
			step = fmMin(1.0, 2.0 * step);
			continue;
		}
		// An attempt that ran out of iterations while still converging has moved towards the
		// equilibrium of every load near it: go on from there. One that went wrong (stalled,
		// stagnated far from the answer, non-finite) goes back to the last equilibrium.
		bool progressing = r.finite && !r.stalled && !r.stagnated;
		if (!progressing)
			memcpy(b->state.x, equilibrium, bytes);
		step *= 0.5;
		if (step < FM_MIN_LOAD_STEP || !r.finite)
			break;
	}
	return r;
}

// The result of a solve that reached load fraction @p done with the last attempt @p r.
static fmResult fmStaticReport(fmNewtonResult r, double done, double tolerance, int iterations,
                               fmDiagnostic* diag)
{
	if (done < 1.0)
		return fmDiagError(diag, fm_errNotConverged, "", 0, 0,
		                   "static solve did not converge: equilibrium reached up to %.3g of the "
		                   "load (the body is left there); the last attempt stopped at residual "
		                   "%.3g (tolerance %.3g) after %d Newton iterations in all. Try more "
		                   "iterations, a looser tolerance, more pins or a stiffer material",
		                   done, r.residual, tolerance, iterations);
	if (!r.converged)
		return fmDiagError(diag, fm_errNotConverged, "", 0, 0,
		                   "static solve stopped at residual %.3g, above the tolerance %.3g: the "
		                   "full load is applied, but after %d Newton iterations in all the "
		                   "residual stagnated (Newton steps that changed the energy by less than "
		                   "its round-off stopped improving it). The best state reached is kept; "
		                   "a tolerance above %.2g is within reach",
		                   r.residual, tolerance, iterations, r.residual);
	return fm_ok;
}

static fmResult fmBodySolveStaticIn(fmBodyId bodyId, double tolerance, int maxIterations,
                                    double* residual, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	fmBody* b = fmGetBody(bodyId);
	fmWorld* world = fmGetWorldOfBody(bodyId);
	fmResult checked = fmStaticCheck(b, world, tolerance, maxIterations, diag);
	if (checked != fm_ok)
		return checked;
	fmImplicitCache* c =
	    fmWorldReserveArena(world) ? fmSolverCache_Get(&b->solverCache, &b->mesh) : NULL;
	if (c == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the static solver");
	const int n3 = 3 * b->mesh.vertexCount;
	// The last equilibrium reached, to go back to when a load increment fails.
	double* equilibrium = FM_ALLOC_ARRAY(double, 2 * (size_t)n3);
	if (equilibrium == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the static solver");
	double* scratch = equilibrium + n3; // the force scale's
	memcpy(c->xStart, b->state.x, sizeof(double) * (size_t)n3);
	memcpy(equilibrium, b->state.x, sizeof(double) * (size_t)n3);
	fmLoads_BeginStatic(b);
	memcpy(c->xPred, b->state.x, sizeof(double) * (size_t)n3);
	fmAnchors_PlaceStatic(world, b);
	const fmTargetStep targets = {b, NULL, 0.0, 0.0}; // the springs alone
	fmNewtonProblem pb = fmStaticProblem(b, c, world, tolerance, maxIterations, scratch, &targets);
	fmVec3 gravity = world->def.gravity;
	double done = pb.scale <= 0.0 ? 1.0 : 0.0; // nothing pulls: already at equilibrium
	int iterations = 0;
	fmNewtonResult r = fmStaticLoadSteps(b, c, &pb, gravity, equilibrium, &done, &iterations);
	if (done >= 1.0)
		r = fmStaticFollowerRounds(b, c, &pb, gravity, r, &iterations);
	if (done < 1.0)
		memcpy(b->state.x, equilibrium, sizeof(double) * (size_t)n3);
	else
		fmLoads_FinishStatic(b);
	FM_FREE_ARRAY(equilibrium, double, 2 * (size_t)n3);
	if (residual)
		*residual = r.residual;
	memset(b->state.v, 0, sizeof(double) * (size_t)n3);
	return fmStaticReport(r, done, tolerance, iterations, diag);
}

// A plastic body's equilibrium: solved, its tets flowed where the equilibrium's strains put
// them (rate-independent), solved again, until no tet flows by more than
// FM_PLASTIC_STATIC_FLOW of its yield strain (the flow and the balance agree: the fixed point of
// the return map and the solve), at most FM_PLASTIC_STATIC_ROUNDS rounds.
#define FM_PLASTIC_STATIC_FLOW 1e-4
#define FM_PLASTIC_STATIC_ROUNDS 400

static fmResult fmBodySolvePlastic(fmBodyId bodyId, double tolerance, int maxIterations,
                                   double* residual, fmDiagnostic* diag)
{
	fmResult result = fmBodySolveStaticIn(bodyId, tolerance, maxIterations, residual, diag);
	fmBody* b = fmGetBody(bodyId);
	if (b == NULL || b->mesh.plasticStrain == NULL)
		return result;
	double flow = INFINITY;
	int round = 0;
	for (; result == fm_ok && round < FM_PLASTIC_STATIC_ROUNDS; ++round)
	{
		flow = fmPlasticity_Flow(b, 0.0);
		if (flow <= FM_PLASTIC_STATIC_FLOW)
			break;
		result = fmBodySolveStaticIn(bodyId, tolerance, maxIterations, residual, diag);
	}
	if (result == fm_ok && flow > FM_PLASTIC_STATIC_FLOW)
		return fmDiagError(diag, fm_errNotConverged, "", 0, 0,
		                   "static solve of a plastic body: after %d rounds of flow and balance "
		                   "the tets still flow by %.3g of their yield strain a round (the "
		                   "state is kept). Take the load in smaller increments (solve at a "
		                   "part of it first) or give the material some hardening",
		                   round, flow);
	return result;
}

fmResult fmBody_SolveStatic(fmBodyId bodyId, double tolerance, int maxIterations, double* residual,
                            fmDiagnostic* diag)
{
	// In femto's floating-point environment (fp_env.h), as every call that computes.
	fmWorld* world = fmGetWorldOfBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(world != NULL && world->def.crossPlatformDeterminism);
	fmResult result = fmBodySolvePlastic(bodyId, tolerance, maxIterations, residual, diag);
	fmBody* b = fmGetBody(bodyId);
	if (b != NULL)
		b->previousValid = false; // moved to its equilibrium: nothing to interpolate from
	if (world != NULL)
		fmWorld_MovedVertices(world);
	fmFpEnv_Leave(&env);
	return result;
}
