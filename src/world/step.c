// The frame step (fmWorld_Step): the step context, the substeps over the bodies (fixed or
// adaptive), the stages in a fixed order, the ledgers opened and closed, the health checks
// and the restore of the last good state (docs/architecture.md, "A frame").
#include "world/world.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "body/grab.h"
#include "body/loads.h"
#include "body/plasticity.h"
#include "contact/barrier_contact.h"
#include "contact/contact.h"
#include "contact/contact_collider.h"
#include "contact/contact_events.h"
#include "contact/mesh_motion.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"
#include "core/timer.h"
#include "fem/forces.h"
#include "world/audit.h"
#include "world/energy_ledger.h"
#include "world/explicit.h"
#include "world/implicit.h"
#include "world/island.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

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
		         b->ledger.work + b->ledger.frameGravityWork + w->frameWork[index].contact +
		             w->frameWork[index].measure);
	char advice[400];
	if (w->budgetNeed > 0.0 && w->def.integrator == fm_explicit)
		snprintf(advice, sizeof advice,
		         "the stability limit asks for %.3g substeps a frame, more than "
		         "maxSubstepsPerFrame (%d) allows, so autoSubstep took longer ones: the body is "
		         "too stiff for its mass to step explicitly; use the implicit integrator",
		         w->budgetNeed, w->def.maxSubstepsPerFrame);
	else if (w->fastCollider >= 0)
		snprintf(advice, sizeof advice,
		         "%s (the likely cause: the collider in slot %d moves %.3g m in a substep, more "
		         "than its %.3g m thickness; slow it, or take %d substeps a frame)",
		         fmFailureAdvice(w), w->fastCollider, w->fastSweep, w->fastThickness,
		         w->fastSubsteps);
	else
		snprintf(advice, sizeof advice, "%s", fmFailureAdvice(w));
	fmDiagError(&w->lastError, fm_errNumerical, "", 0, 0,
	            "body %d: %s; %d inverted or non-finite tets (%s); state restored to the last "
	            "good frame; %s",
	            index, what, bad, list, advice);
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
		fmPlasticity_RestoreGood(b); // the frame's plastic flow undone
		b->energyStale = true;       // energyGood may belong to a state the caller had set
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
// What no step can follow, refused before it is stepped and named by its key (the advice would
// otherwise blame the time step): a contact thickness larger than the largest body (contact
// across whole bodies), loads that accelerate a body faster than FM_MAX_LOAD_ACCELERATION, a
// prescribed displacement FM_MAX_DISPLACEMENT_SIZES times the body's size.
#define FM_MAX_LOAD_ACCELERATION 1e9
#define FM_MAX_DISPLACEMENT_SIZES 1e3

static fmResult fmCheckScale(fmWorld* w)
{
	double largest = 0.0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		const fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		largest = fmMax(largest, b->mesh.restSize);
		double load = fmLoads_Size(b), reach = fmLoads_LongestDisplacement(b);
		if (load > FM_MAX_LOAD_ACCELERATION * b->mesh.totalMass)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "body %d: its loads (fmBody_AddNodalForce, fmBody_AddPressure; "
			                   "scene: loads, pressure) add up to %.3g N on %.3g kg, more than "
			                   "%.0e m/s^2: no step can follow that; check their units",
			                   i, load, b->mesh.totalMass, FM_MAX_LOAD_ACCELERATION);
		if (reach > FM_MAX_DISPLACEMENT_SIZES * b->mesh.restSize)
			return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                   "body %d: a prescribed displacement (fmBody_PrescribeDisplacement; "
			                   "scene: displacement) of %.3g m is more than %.0f times the body's "
			                   "%.3g m size; check its units",
			                   i, reach, FM_MAX_DISPLACEMENT_SIZES, b->mesh.restSize);
	}
	double thickness = w->def.contact.thickness;
	if (largest > 0.0 && thickness > largest)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "the contact thickness (fmContactDef.thickness; scene: "
		                   "contact.thickness) is %.3g m, more than the largest body's %.3g m "
		                   "size: contact would act across whole bodies; give a thickness well "
		                   "below the bodies' size (0: automatic, 1%% of the smallest)",
		                   thickness, largest);
	return fm_ok;
}

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
	return fmCheckScale(w);
}

// With autoSubstep, explicit substeps are at most FM_AUTO_STEP_FRACTION of the stability limit
// at the bodies' current deformation (stability.h), and at least subStepCount to a frame. The
// limit is linear stability; contacts and large compressions within a step need more room
// (docs/decisions.md, "autoSubstep's fraction"). Deformation changes within a frame (an impact
// compresses a body in a few substeps), so a cheap stiffening proxy is watched after every
// substep and the limit re-evaluated when it moves by 10%.
#define FM_AUTO_STEP_FRACTION 0.3

typedef struct fmAutoStep
{
	double limit; // s, stability limit at the last evaluation
	double proxy; // stiffening proxy at the last evaluation
} fmAutoStep;

// The proxy of one body, its tets in ranges on the workers: each worker keeps the largest of its
// ranges (a maximum: the same for any ranges, workers and order).
typedef struct fmProxyTask
{
	const fmBody* body;
	double largest[FM_MAX_WORKERS];
} fmProxyTask;

static void fmProxyRange(int start, int end, int worker, void* context)
{
	fmProxyTask* task = context;
	const fmBody* b = task->body;
	task->largest[worker] =
	    fmMax(task->largest[worker], fmStiffeningProxyRange(&b->mesh, b->state.x, start, end));
}

static double fmWorldStiffeningProxy(const fmWorld* w)
{
	double proxy = 1.0;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		if (!fmBody_IsLive(&w->bodies[i]))
			continue;
		fmProxyTask task = {.body = &w->bodies[i]};
		for (int k = 0; k < w->tasks.workerCount; ++k)
			task.largest[k] = 1.0;
		fmParallelFor(&w->tasks, w->bodies[i].mesh.tetCount, FM_PARALLEL_MIN_RANGE, fmProxyRange,
		              &task);
		for (int k = 0; k < w->tasks.workerCount; ++k)
			proxy = fmMax(proxy, task.largest[k]);
	}
	return proxy;
}

static void fmAutoStep_Evaluate(fmWorld* w, fmAutoStep* a)
{
	a->limit = fmWorldExplicitLimit(w);
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

// What the bodies of a schedule group stepping at once share.
typedef struct fmGroupTask
{
	fmWorld* world;
	const fmStepContext* context;
	const int* slots;
} fmGroupTask;

// Bodies [start, end) of a group, each on worker @p worker alone: its loops serial, its
// temporaries in the worker's arena and barrier scratch.
static void fmStepBodiesTask(int start, int end, int worker, void* context)
{
	const fmGroupTask* task = context;
	fmStepContext own = *task->context;
	own.tasks = NULL;
	own.worker = worker;
	own.arena = worker == 0 ? &task->world->arena : &task->world->workerArenas[worker - 1];
	for (int k = start; k < end; ++k)
		fmStepBody(task->world, task->slots[k], &own);
}

// Step schedule group @p g: its large bodies one after another (each on all the workers), then
// the others at once (one a worker); then note their surfaces for the groups after it
// (schedule.h: no body of a group reads another's state, so any order gives the same bits).
static void fmStepGroup(fmWorld* w, const fmStepContext* ctx, int g, bool barrier)
{
	int* slots = w->schedule.order + w->schedule.groupStart[g];
	const int count = w->schedule.groupStart[g + 1] - w->schedule.groupStart[g];
	int small = 0; // the small bodies to the front, the large ones stepped
	for (int k = 0; k < count; ++k)
	{
		int slot = slots[k];
		if (w->bodies[slot].mesh.vertexCount >= FM_BODY_PARALLEL_MAX_VERTICES)
			fmStepBody(w, slot, ctx);
		else
			slots[k] = slots[small], slots[small++] = slot;
	}
	bool workers = w->tasks.workerCount > 1 || w->tasks.enqueueTask != NULL;
	fmGroupTask task = {w, ctx, slots};
	if (small > 1 && workers)
		fmParallelForBalanced(&w->tasks, small, 1, fmStepBodiesTask, &task);
	else
		for (int k = 0; k < small; ++k)
			fmStepBody(w, slots[k], ctx);
	for (int k = 0; barrier && k < count; ++k)
		fmBarrierContact_NoteSurface(&w->bodies[slots[k]]);
}

// A relative residual above this after a step of a nearly incompressible body: its solve
// ended further from balance than the step's whole force scale (it diverged: the locking tets'
// Newton systems are too ill-conditioned to solve), which no frame may keep, however
// notConvergedIsError is set. (Other bodies meet residuals of 1 to 10 in legitimate hard
// steps: a Newton budget of one, a body coming out of a collider, far-off targets, inertia
// below the round-off of the elastic forces; they stay warnings.)
#define FM_RESIDUAL_DIVERGED 1.0

// The largest lambda / mu of the body's materials (a near-incompressible one is the likely cause
// of a diverged solve: linear tets lock, the Newton systems turn ill-conditioned).
static double fmStiffestVolume(const fmBody* b)
{
	double ratio = b->mesh.material.lambda / b->mesh.material.mu;
	for (int k = 1; k < b->mesh.materialCount; ++k)
		ratio = fmMax(ratio, b->mesh.materials[k].lambda / b->mesh.materials[k].mu);
	return ratio;
}

static fmResult fmReportDiverged(fmWorld* w, int index)
{
	const fmBody* b = &w->bodies[index];
	double ratio = fmStiffestVolume(b);
	return fmDiagError(&w->lastError, fm_errNotConverged, "", 0, 0,
	                   "body %d: the implicit solve diverged: relative residual %.3g after %d "
	                   "Newton and %d CG iterations (%s), further from balance than the step's "
	                   "whole force scale; state restored to the last good frame; the cause: a "
	                   "nearly incompressible material (lambda / mu = %.3g, a Poisson ratio of "
	                   "%.7g): linear tets lock under it; use a Poisson ratio of 0.49 or less",
	                   index, b->stepResidual, b->stepNewton, b->stepCg, b->stepStopped, ratio,
	                   ratio / (2.0 * (ratio + 1.0)));
}

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
	if (b->stepResidual > FM_RESIDUAL_DIVERGED && fmStiffestVolume(b) > FM_NEARLY_INCOMPRESSIBLE)
		return fmReportDiverged(w, index);
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
	// Stage a: every body steps on its own (the stage threads will share). First the grabs'
	// targets, the moving meshes and the attachments go where the substep's end puts them.
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]))
			fmGrab_Advance(&w->bodies[i], (ctx->elapsed + h) / ctx->frameTime);
	if (w->meshMotion != NULL)
		w->meshMotion->substep(w, (ctx->elapsed + h) / ctx->frameTime);
	if (w->anchorStages != NULL)
		w->anchorStages->place(w, h, ctx->frameTime);
	bool contact = fmContact_Active(w);
	if ((contact || fmContact_FloorFriction(w)) && !fmContact_BeginSubstep(w, h))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the contact buffers");
	const bool barrier = fmBarrierContact_Active(w);
	if (!fmSchedule_Build(&w->schedule, w, 1.0 / (h * h), barrier))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the bodies' schedule");
	for (int g = 0; g < w->schedule.groupCount; ++g)
		fmStepGroup(w, ctx, g, barrier);
	// Stage b: contact between the bodies and with the colliders (contact.c), in a fixed order;
	// first the colliders' and the floor's reaction to the solve's friction.
	double contactStart = fmSeconds();
	if (w->anchorStages != NULL)
		w->anchorStages->afterSubstep(w, h);
	if (w->def.integrator == fm_implicit && (contact || fmContact_FloorFriction(w)))
		fmContactCollider_BookSolveFriction(w, h);
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
	// Stage d: plastic flow, each plastic body's tets in order (body/plasticity.h).
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]) && w->bodies[i].mesh.plasticStrain != NULL)
			fmPlasticity_Flow(&w->bodies[i], h);
	w->stats.steps += 1;
	ctx->elapsed += h;
	if (w->def.substepCallback != NULL)
		w->def.substepCallback(w->stats.steps - 1, ctx->elapsed, w->def.substepContext);
	return fm_ok;
}

static fmResult fmFixedSubsteps(fmWorld* w, fmStepContext* ctx, double h, int count)
{
	fmResult r = fm_ok;
	for (int s = 0; s < count && r == fm_ok; ++s)
		r = fmSubstep(w, ctx, h);
	return r;
}

// Substeps between autoSubstep's checks for non-finite state within a frame.
#define FM_FINITE_CHECK_SUBSTEPS 256

// The relative change of the substep below which the energy ledger keeps measuring the shadow
// energy with the step it had: dividing the frame's remainder again rounds the same substep
// differently in its last bits, and each new measure costs two energy passes over the bodies
// (a third of a 10k body's explicit frame). The measure's error is at most this fraction of the
// shadow term h/2 v.f, never accumulated (the kept step is the reference).
#define FM_MEASURE_STEP_RESOLUTION 1e-6

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
			if (w->budgetNeed == 0.0) // the first cut's: later ones may see the body collapsing
				w->budgetNeed = w->stats.steps + remaining / h;
			h = remaining / (left > 1 ? left : 1);
			fmBudgetHit(w, "autoSubstep took longer substeps than the stability limit to end the "
			               "frame within maxSubstepsPerFrame");
		}
		// The ledger measures the shadow energy with the step: a new step changes the measure,
		// which is neither work nor a runaway. A step within FM_MEASURE_STEP_RESOLUTION of the
		// measure's (the frame's remainder divided again, rounded) keeps the measure.
		if (!(h > 0.0) || fabs(h - ctx->shadowStep) <= FM_MEASURE_STEP_RESOLUTION * ctx->shadowStep)
			continue;
		fmEnergyPass pass = fmWorldEnergyPass(w);
		for (int i = 0; i < w->bodyCapacity; ++i)
			if (fmBody_IsLive(&w->bodies[i]))
				fmLedger_ChangeMeasure(&w->bodies[i], &ctx->work[i], w->def.gravity, timeStep,
				                       ctx->shadowStep, h, &pass);
		ctx->shadowStep = h;
	}
	return fm_ok;
}

// Whether a stepping body is grabbed, or was and is still stretched (grab.h).
static bool fmWorldGrabbed(fmWorld* w)
{
	bool any = false;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]))
			any = fmGrab_NeedsAdaptiveSteps(&w->bodies[i]) || any;
	return any;
}

// The frame's step context: its times, the world's workers and arena, the bookings zeroed.
static fmStepContext fmWorldStepContext(fmWorld* w, double timeStep, int subStepCount)
{
	memset(w->frameWork, 0, sizeof(fmFrameWork) * (size_t)w->bodyCapacity);
	fmStepContext ctx = {.frameTime = timeStep,
	                     .substep = timeStep / subStepCount,
	                     .substepCount = subStepCount,
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
		{
			fmLedger_BeginFrame(&w->bodies[i], w->def.gravity, ctx->shadowStep, &pass);
			fmPlasticity_KeepGood(&w->bodies[i]);
		}
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
		b->plasticKept = false;
		size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
		memcpy(b->xGood, b->state.x, bytes);
		memcpy(b->vGood, b->state.v, bytes);
		b->energyGood = b->energyAfter;
		b->energyStale = false;
		fmGrab_EndFrame(b);
		w->stats.invertedTets += b->invertedAfter >= 0
		                             ? b->invertedAfter
		                             : fmBodyCountInvertedOn(b, &w->tasks, &w->arena);
	}
	return fm_ok;
}

// Whether a live body's box, grown by @p margin, meets [lo, hi].
static bool fmBodyNear(const fmBody* b, fmVec3 lo, fmVec3 hi, double margin)
{
	fmVec3 blo = fmMakeVec3(INFINITY, INFINITY, INFINITY), bhi = fmScale(-1.0, blo);
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i);
		blo = fmMakeVec3(fmMin(blo.x, p.x), fmMin(blo.y, p.y), fmMin(blo.z, p.z));
		bhi = fmMakeVec3(fmMax(bhi.x, p.x), fmMax(bhi.y, p.y), fmMax(bhi.z, p.z));
	}
	return blo.x - margin <= hi.x && lo.x <= bhi.x + margin && blo.y - margin <= hi.y &&
	       lo.y <= bhi.y + margin && blo.z - margin <= hi.z && lo.z <= bhi.z + margin;
}

// A kinematic collider that moves more than its thickness in a substep can pass over a body's
// vertices between two substeps, which then never meet it: say so (once a frame, for the worst
// one whose path in the frame passes a body), with the substeps that would do, and keep it for
// the advice of a failure in the frame.
static void fmWarnFastColliders(fmWorld* w, const fmStepContext* ctx)
{
	w->fastCollider = -1;
	double worst = 1.0;
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		const fmCollider* c = &w->colliders[k];
		fmVec3 lo, hi;
		if (!c->inUse || !fmCollider_Bounds(c, &lo, &hi))
			continue;
		double speed = fmCollider_SweepSpeed(c);
		double thickness = fmCollider_Thickness(c), sweep = speed * ctx->substep;
		if (!(sweep > worst * thickness))
			continue;
		double reach = speed * ctx->frameTime;
		bool near = false;
		for (int i = 0; i < w->bodyCapacity && !near; ++i)
			near = fmBody_IsLive(&w->bodies[i]) && fmBodyNear(&w->bodies[i], lo, hi, reach);
		if (!near)
			continue;
		worst = sweep / thickness;
		w->fastCollider = k;
		w->fastSweep = sweep;
		w->fastThickness = thickness;
		double substeps = ceil(reach / thickness);
		w->fastSubsteps = substeps < INT_MAX ? (int)substeps : INT_MAX;
	}
	if (w->fastCollider >= 0)
		fmDiagWarn(
		    &w->lastError, "", 0,
		    "the collider in slot %d moves %.3g m in a substep of %.3g s, more than its %.3g m "
		    "thickness: bodies in its way can pass through it unhit; slow it, or take %d "
		    "substeps a frame",
		    w->fastCollider, w->fastSweep, ctx->substep, w->fastThickness, w->fastSubsteps);
}

// What is wrong with the positions the caller set on body @p i since the last frame (written
// into @p why), or false when nothing: tets turned inside out that were not at the last good
// state (a mirrored body), or the body put across or inside another it collides with.
static bool fmSetPositionsWrong(fmWorld* w, int i, char* why, size_t size)
{
	const fmBody* b = &w->bodies[i];
	if (fmFirstNonFiniteVertex(b) >= 0)
		return false; // the step reports it
	// Inside out: most of its tets inverted, more than at the last good state. A crushed tet or
	// a few may be set (invertible elasticity pushes them back out, as it does a one-tet body's
	// apex pushed through its face); a mirrored body cannot come back: every tet would have to
	// pass through itself at once.
	int inverted = fmBodyCountInverted(b);
	if (b->mesh.tetCount > 1 && 2 * inverted > b->mesh.tetCount &&
	    inverted > fmBodyCountInvertedAt(b, b->xGood))
	{
		snprintf(why, size,
		         "turn the body inside out (%d of its %d tets inverted): a mirrored body cannot "
		         "come back, its volume energy would be released as an explosion",
		         inverted, b->mesh.tetCount);
		return true;
	}
	fmAuditOverlap o;
	if (!fmContact_BodiesMeet(w) || fmAudit_Overlap(w, i, &o) != fm_ok || o.other < 0)
		return false; // (non-finite positions: the step reports them)
	snprintf(why, size,
	         "put it across or inside body %d (%d surface edges crossing, %d surface vertices and "
	         "%d tet centres inside): bodies that collide must stay apart (or give the two "
	         "bodies filters that do not meet)",
	         o.other, o.crossings, o.verticesInside, o.tetsInside);
	return true;
}

// Positions set by the caller (fmBody_SetPositions) since the last frame that turned tets inside
// out or put a body inside or across another it collides with are refused as at creation
// (contact holds bodies apart and cannot separate surfaces that already cross; left to try, it
// ground on without end; an inside-out body explodes): the frame is not stepped, every body goes
// back to its last good state (the sets dropped), and the error says which body and why.
static fmResult fmRefuseBadSets(fmWorld* w)
{
	fmResult r = fm_ok;
	char why[320];
	for (int i = 0; i < w->bodyCapacity && r == fm_ok; ++i)
		if (fmBody_IsLive(&w->bodies[i]) && w->bodies[i].positionsSet &&
		    fmSetPositionsWrong(w, i, why, sizeof why))
			r = fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
			                "body %d: the positions set since the last frame "
			                "(fmBody_SetPositions) %s; state restored to the last good frame "
			                "(what was set since is dropped)",
			                i, why);
	for (int i = 0; i < w->bodyCapacity; ++i)
		w->bodies[i].positionsSet = false;
	if (r != fm_ok)
		fmRestoreAll(w);
	return r;
}

// The frame step of fmWorld_Step, in femto's floating-point environment.
static fmResult fmWorldStep(fmWorld* w, double timeStep, int subStepCount)
{
	memset(&w->stats, 0, sizeof w->stats);
	w->budgetNeed = 0.0;
	fmDiagClear(&w->lastError);
	fmResult r = fmCheckFrame(w, timeStep, subStepCount);
	if (r == fm_ok)
		r = fmRefuseBadSets(w);
	if (r != fm_ok)
		return r;
	if (!fmWorldReserveArena(w))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the step buffers");
	fmStepContext ctx = fmWorldStepContext(w, timeStep, subStepCount);

	// Stage 1: the substep length (autoSubstep, or a grab in an explicit world: from the
	// stability limit at the current deformation, which a grab can stretch far).
	const bool autoStep =
	    w->def.integrator == fm_explicit && (w->def.autoSubstep || fmWorldGrabbed(w));
	fmAutoStep plan = {0.0, 1.0};
	if (autoStep)
	{
		fmAutoStep_Evaluate(w, &plan);
		ctx.substep = fmAutoStep_Next(w, &plan, ctx.substep, timeStep, false);
	}

	// Stage 2: open the ledgers.
	fmContact_BeginFrame(w);
	if (w->anchorStages != NULL)
		w->anchorStages->wake(w);
	ctx.shadowStep = w->def.integrator == fm_explicit ? ctx.substep : 0.0;
	w->sleepEventCount = 0;
	fmOpenLedgers(w, &ctx);
	fmWarnExplicitStep(w, &ctx);
	if (w->meshMotion != NULL)
		w->meshMotion->beginFrame(w, 1.0 / timeStep);
	fmWarnFastColliders(w, &ctx);

	// Stage 3: substeps, every body advanced by the chosen integrator.
	r = autoStep ? fmAdaptiveSubsteps(w, &ctx, &plan)
	             : fmFixedSubsteps(w, &ctx, ctx.substep, subStepCount);
	if (r != fm_ok)
	{
		if (w->meshMotion != NULL)
			w->meshMotion->endFrame(w, false);
		fmRestoreAll(w);
		return r;
	}

	// Stage 4: check and close the ledgers (moving meshes back with the bodies when that
	// fails), then the frame's contact events and islands.
	double checking = fmSeconds();
	bool closed = fmCloseLedgers(w, &ctx) == fm_ok;
	if (w->meshMotion != NULL)
		w->meshMotion->endFrame(w, closed);
	if (!closed)
		return fm_errNumerical;
	fmFracture_EndFrame(w); // the tears, from the checked state
	w->stats.contacts = fmContact_EndFrame(w);
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
	// A world steps on one thread at a time (docs/embedding.md, "Threading"). The refusal writes
	// nothing: the world, its last error included, belongs to the step in progress.
	if (atomic_exchange(&w->stepping, 1) != 0)
		return fm_errBusy;
	// The host's floating-point state is saved, femto's set (round to nearest, no FTZ or DAZ),
	// and the host's restored after the step, on every path (fp_env.h).
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	double start = fmSeconds();
	memset(&w->profile, 0, sizeof w->profile);
	w->stepKnown = false;
	w->stepThickness = fmContact_Thickness(w);
	w->stepBodiesMeet = fmContact_BodiesMeet(w);
	w->stepKnown = true;
	fmWorld_MovedVertices(w); // (the user may have moved vertices through the step's pointers)
	for (int i = 0; !w->advancing && i < w->bodyCapacity; ++i)
		w->bodies[i].previousValid = false; // a frame not from fmWorld_Advance: no last two
	fmResult r = fmWorldStep(w, timeStep, subStepCount);
	fmWorld_MovedVertices(w);
	w->stepKnown = false;
	w->profile.step = 1e3 * (fmSeconds() - start);
	w->profile.narrowPhase = fmMax(0.0, w->profile.contact - w->profile.broadPhase);
	fmFpEnv_Leave(&env);
	atomic_store(&w->stepping, 0);
	return r;
}

// ---- the game loop's fixed step ----------------------------------------------------------------
// fmWorld_Advance: real time accumulated, whole frames stepped, the rest the render's
// interpolation factor; each body's positions kept before each frame for the interpolated
// copies (body.c, draw/render_mesh.c). As Box2D's samples and Glenn Fiedler's "Fix Your
// Timestep!" write it around a world; here once, with the spiral of death bounded.

#define FM_MAX_ADVANCE_FRAMES 1000
#define FM_MAX_ADVANCE_SECONDS 1e6

fmFixedStep fmDefaultFixedStep(void)
{
	fmFixedStep clock;
	memset(&clock, 0, sizeof clock);
	clock.frameTime = 1.0 / 60.0;
	clock.substeps = 1;
	clock.maxFrames = 4;
	clock.internalValue = FM_DEF_MAGIC;
	return clock;
}

// What is wrong with @p clock or @p elapsed, or NULL.
static const char* fmClockProblem(const fmFixedStep* clock, double elapsed)
{
	if (clock == NULL || clock->internalValue != FM_DEF_MAGIC)
		return "the clock was not made by fmDefaultFixedStep()";
	if (!(clock->frameTime >= FM_MIN_SUBSTEP && clock->frameTime <= FM_MAX_SUBSTEP))
		return "frameTime is outside [FM_MIN_SUBSTEP, FM_MAX_SUBSTEP] s";
	if (clock->substeps < 1 || clock->substeps > FM_MAX_SUBSTEPS)
		return "substeps is outside [1, FM_MAX_SUBSTEPS]";
	if (!(clock->frameTime / clock->substeps >= FM_MIN_SUBSTEP))
		return "frameTime / substeps is below FM_MIN_SUBSTEP s";
	if (clock->maxFrames < 1 || clock->maxFrames > FM_MAX_ADVANCE_FRAMES)
		return "maxFrames is outside [1, 1000]";
	if (!(clock->accumulator >= 0.0 && clock->accumulator < clock->frameTime))
		return "accumulator is outside [0, frameTime)";
	if (!(elapsed >= 0.0 && elapsed <= FM_MAX_ADVANCE_SECONDS))
		return "elapsed is negative, not finite or above 1e6 s";
	return NULL;
}

// Every live body's positions now, for the interpolated copies. False when memory is short.
static bool fmKeepPrevious(fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		size_t values = 3 * (size_t)b->mesh.vertexCount;
		if (b->previousX == NULL && (b->previousX = FM_ALLOC_ARRAY(double, values)) == NULL)
			return false;
		memcpy(b->previousX, b->state.x, sizeof(double) * values);
		b->previousValid = true;
	}
	return true;
}

fmResult fmWorld_Advance(fmWorldId worldId, fmFixedStep* clock, double elapsed, int* framesStepped)
{
	if (framesStepped != NULL)
		*framesStepped = 0;
	fmWorld* w = fmGetWorld(worldId);
	if (w == NULL)
		return fm_errInvalidId;
	if (atomic_load(&w->stepping) != 0) // in a step: its positions are not to be read
		return fm_errBusy;
	const char* problem = fmClockProblem(clock, elapsed);
	if (problem != NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0, "fmWorld_Advance: %s",
		                   problem);
	clock->accumulator += elapsed;
	int frames = 0;
	fmResult result = fm_ok;
	while (clock->accumulator >= clock->frameTime && frames < clock->maxFrames)
	{
		if (!fmKeepPrevious(w))
		{
			result = fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                     "fmWorld_Advance: out of memory for the bodies' positions");
			break;
		}
		clock->accumulator -= clock->frameTime; // spent even when the step fails: not retried
		w->advancing = true;
		result = fmWorld_Step(worldId, clock->frameTime, clock->substeps);
		w->advancing = false;
		if (result != fm_ok)
			break;
		++frames;
	}
	// Beyond maxFrames the time is dropped: what is left is less than a frame.
	if (clock->accumulator >= clock->frameTime)
		clock->accumulator -= clock->frameTime * floor(clock->accumulator / clock->frameTime);
	if (!(clock->accumulator < clock->frameTime)) // round-off at the edge
		clock->accumulator = 0.0;
	clock->alpha = clock->accumulator / clock->frameTime;
	if (framesStepped != NULL)
		*framesStepped = frames;
	return result;
}
