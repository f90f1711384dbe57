// The Newton minimiser shared by the implicit step and the static solver (newton.h): projected
// Newton (Bertsekas) with per-element PSD-projected or exact Hessians (Teran et al. 2005), a
// preconditioned CG for each Newton system, a lazily refreshed assembled matrix, and a
// backtracking (Armijo) line search on E along the path projected onto the bounds.
#include "solver/newton.h"
#include "core/det_math.h"

#include "core/core.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/inversion.h"
#include "fem/nodal_pressure.h"

#include <float.h>
#include <math.h>
#include <string.h>

fmSolverOptions fmDefaultSolverOptions(void)
{
	fmSolverOptions options = {fm_productAssembled, fm_precondAuto};
	return options;
}

// Relative residual, in tolerances, below which a Newton system is solved to finish the solve.
#define FM_NEWTON_FINISH 30.0

// Residual reduction per Newton iteration below which a kept matrix is still good enough.
#define FM_REUSE_RATIO 0.25

typedef struct fmNewtonContext
{
	const fmElasticMesh* mesh;
	fmBodyState* state;
	fmImplicitCache* cache;
	const fmNewtonProblem* problem;
} fmNewtonContext;

static double fmTermEnergy(const fmNewtonTerm* term, const double* x, const double* xStart,
                           double* gradient)
{
	return term->energy != NULL ? term->energy(term->context, x, xStart, gradient) : 0.0;
}

static void fmTermHessian(const fmNewtonTerm* term, const double* x, const fmBsrMatrix* pattern,
                          double* values)
{
	if (term->addHessian != NULL)
		term->addHessian(term->context, x, pattern, values);
}

static void fmTermProduct(const fmNewtonTerm* term, const double* x, const double* dx, double* y)
{
	if (term->addProduct != NULL)
		term->addProduct(term->context, x, dx, y);
}

// Elastic energy at x, with the forces into c->forces when asked; an evaluation at the x of the
// cache's last forces (the line search's accepted point, the chosen first guess) is reused.
static double fmElasticAt(const fmElasticMesh* mesh, fmImplicitCache* c, const fmNewtonProblem* pb,
                          const double* x, bool forces)
{
	if (fmSolverCache_HasForcesAt(mesh, c, x))
		return c->forcesEnergy;
	if (!forces)
		return fmElasticEnergyOn(mesh, x, pb->tasks, pb->arena);
	memset(c->forces, 0, sizeof(double) * 3 * (size_t)mesh->vertexCount);
	double psi = fmAddElasticForcesOn(mesh, x, c->forces, pb->tasks, pb->arena);
	fmSolverCache_NoteForces(mesh, c, x, psi);
	return psi;
}

// Energy at x, and its gradient when @p gradient is not NULL. @p magnitude gets the sum of the
// absolute sizes of the terms (the scale of round-off in E).
static double fmNewtonEnergy(const fmElasticMesh* mesh, fmImplicitCache* c,
                             const fmNewtonProblem* pb, const double* x, double* gradient,
                             double* magnitude)
{
	const int n3 = 3 * mesh->vertexCount;
	double psi = fmElasticAt(mesh, c, pb, x, gradient != NULL);
	const double g[3] = {pb->gravity.x, pb->gravity.y, pb->gravity.z};
	double inertial = 0.0, external = 0.0, size = 0.0;
	// DOF k = 3 i + e, in k order (a vertex, then its axes: no division per DOF).
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		double m = mesh->mass[i];
		for (int e = 0; e < 3; ++e)
		{
			int k = 3 * i + e;
			double toPred = x[k] - c->xPred[k], moved = x[k] - c->xStart[k];
			double term =
			    0.5 * m * (pb->inertia * toPred * toPred + pb->massDamping * moved * moved);
			inertial += term;
			external -= m * g[e] * moved;
			size += fabs(m * g[e] * moved);
			if (gradient)
				gradient[k] =
				    m * (pb->inertia * toPred + pb->massDamping * moved - g[e]) - c->forces[k];
		}
	}
	double damping = 0.0;
	if (pb->useDamping)
	{
		double* moved = c->work; // the CG's vectors are free outside the CG
		double* pushed = c->work + n3;
		for (int k = 0; k < n3; ++k)
			moved[k] = x[k] - c->xStart[k];
		fmBsr_Multiply(&c->pattern, c->damping, moved, pushed);
		for (int k = 0; k < n3; ++k)
		{
			damping += 0.5 * moved[k] * pushed[k];
			if (gradient)
				gradient[k] += pushed[k];
		}
	}
	double loaded = fmTermEnergy(&pb->loads, x, c->xStart, gradient); // -f . (x - xStart)
	double pulled = fmTermEnergy(&pb->targets, x, c->xStart, gradient) +
	                fmTermEnergy(&pb->contact, x, c->xStart, gradient) +
	                fmTermEnergy(&pb->barrier, x, c->xStart, gradient) + loaded;
	if (magnitude)
		*magnitude = fabs(psi) + inertial + size + damping + pulled + 2.0 * fabs(loaded);
	return inertial + damping + psi + external + pulled;
}

// Round-off band of E (see fmLineSearch): differences below it are noise.
static double fmEnergyNoise(const fmElasticMesh* mesh, const fmImplicitCache* c, double magnitude)
{
	return 1e-13 * (magnitude + (mesh->material.mu + fabs(mesh->material.lambda)) * c->volume);
}

// Stiffness of vertex i's y DOF in the Newton matrix this direction uses (assembled just before
// when it is refreshed), or without one (matrix-free) the inertia alone, which makes the
// estimate of a step's reach an upper bound.
static double fmVerticalStiffness(const fmElasticMesh* mesh, const fmImplicitCache* c,
                                  const fmNewtonProblem* pb, int i)
{
	if (c->hessianValid && pb->options.product == fm_productAssembled)
		return c->hessian[9 * (size_t)c->pattern.diagonal[i] + 4];
	return (pb->inertia + pb->massDamping) * mesh->mass[i];
}

// DOFs the step may not move: pins, and the floor where it pushes (active set: a vertex on the
// floor whose energy gradient points down is held; one the energy pulls up is released).
// With @p reach, a vertex that is pushed down and above the floor by less than its Newton step
// would move it (push over stiffness) counts as on it too: Bertsekas' epsilon-active set. The
// step then puts it on the floor (fmReachFloor). Left free, the CG aims it through the floor,
// the clamp of the trial point bends the path, and the line search halves the step until it
// is the size of the gap (a resting box's vertices 4e-8 m up cost nine energy passes a frame).
static void fmMarkFixed(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                        const fmNewtonProblem* pb, const double* x, bool reach)
{
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		unsigned pin = state->pinned[i];
		double push = c->gradient[3 * i + 1];
		double gap = pb->floor ? x[3 * i + 1] - c->floorBound[i] : INFINITY;
		// (The inertia alone bounds the stiffness from below: most vertices are out of reach
		// by it, without a look into the matrix.)
		double inertia = (pb->inertia + pb->massDamping) * mesh->mass[i];
		bool onFloor = !(pin & FM_PIN_Y) && push > 0.0 &&
		               (gap <= 0.0 || (reach && gap * inertia <= push &&
		                               gap * fmVerticalStiffness(mesh, c, pb, i) <= push));
		bool stick = onFloor && pb->floor->friction == fm_floorStick;
		c->fixed[3 * i] = (pin & 1u) || stick;
		c->fixed[3 * i + 1] = (pin & FM_PIN_Y) || onFloor;
		c->fixed[3 * i + 2] = (pin & 4u) || stick;
	}
}

// The direction of the vertices held within reach of the floor: onto it.
static void fmReachFloor(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                         const fmNewtonProblem* pb)
{
	if (pb->floor == NULL)
		return;
	for (int i = 0; i < mesh->vertexCount; ++i)
		if (c->fixed[3 * i + 1] && !(state->pinned[i] & FM_PIN_Y) &&
		    state->x[3 * i + 1] > c->floorBound[i])
			c->direction[3 * i + 1] = c->floorBound[i] - state->x[3 * i + 1];
}

static double fmFreeNorm(int n3, const double* v, const uint8_t* fixed)
{
	double s = 0.0;
	for (int k = 0; k < n3; ++k)
		if (!fixed[k])
			s += v[k] * v[k];
	return sqrt(s);
}

double fmNewton_Residual(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                         const fmNewtonProblem* pb, const double* x)
{
	fmNewtonEnergy(mesh, c, pb, x, c->gradient, NULL);
	fmMarkFixed(mesh, state, c, pb, x, false);
	double scale = pb->scale > 0.0 ? pb->scale : DBL_MIN;
	return fmFreeNorm(3 * mesh->vertexCount, c->gradient, c->fixed) / scale;
}

// Whether the problem has contact terms with a Hessian (the part a contact refresh renews).
static bool fmHasContactHessian(const fmNewtonProblem* pb)
{
	return pb->contact.addHessian != NULL || pb->barrier.addHessian != NULL;
}

// The contact terms' Hessians added to the matrix (the last terms of the sum: a contact refresh
// at the base's positions gives the bits of a full assembly).
static void fmAddContactHessians(fmBodyState* state, fmImplicitCache* c, const fmNewtonProblem* pb)
{
	fmTermHessian(&pb->contact, state->x, &c->pattern, c->hessian);
	fmTermHessian(&pb->barrier, state->x, &c->pattern, c->hessian);
}

// The Newton matrix H = (inertia + massDamping) M + K(x) [+ D] + targets + contact, assembled;
// the part before the contact terms is kept as the base when the problem has them (and memory
// allows). True when the base now holds it.
static bool fmAssembleNewtonMatrix(const fmElasticMesh* mesh, fmBodyState* state,
                                   fmImplicitCache* c, const fmNewtonProblem* pb)
{
	const size_t values = 9 * (size_t)c->pattern.blocks;
	c->hessianVersion += 1;
	if (pb->useDamping)
		memcpy(c->hessian, c->damping, sizeof(double) * values);
	else
		memset(c->hessian, 0, sizeof(double) * values);
	fmSolverCache_AddStiffness(mesh, c, state->x, 1.0, pb->exactHessian ? 0 : 1, c->hessian,
	                           pb->tasks);
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		double* block = c->hessian + 9 * (size_t)c->pattern.diagonal[i];
		double diagonal = (pb->inertia + pb->massDamping) * mesh->mass[i];
		block[0] += diagonal;
		block[4] += diagonal;
		block[8] += diagonal;
	}
	fmTermHessian(&pb->targets, state->x, &c->pattern, c->hessian);
	bool base = fmHasContactHessian(pb) && fmSolverCache_Base(c) != NULL;
	if (base)
		memcpy(c->hessianBase, c->hessian, sizeof(double) * values);
	fmAddContactHessians(state, c, pb);
	return base;
}

// The kept base with the contact terms at x: contacts change from one iteration to the next far
// more than the elastic matrix does.
static void fmRefreshContactHessian(fmBodyState* state, fmImplicitCache* c,
                                    const fmNewtonProblem* pb)
{
	c->hessianVersion += 1;
	memcpy(c->hessian, c->hessianBase, sizeof(double) * 9 * (size_t)c->pattern.blocks);
	fmAddContactHessians(state, c, pb);
}

// Diagonal blocks only, for the matrix-free path's preconditioner (into c->hessian's first
// 9 n entries, used as plain per-vertex storage).
static void fmDiagonalBlocksMatrixFree(const fmElasticMesh* mesh, fmBodyState* state,
                                       fmImplicitCache* c, const fmNewtonProblem* pb,
                                       double* blocks)
{
	memset(blocks, 0, sizeof(double) * 9 * (size_t)mesh->vertexCount);
	if (mesh->forceModel == fm_massSpring)
	{
		double K[36];
		for (int e = 0; e < c->edgeCount; ++e)
		{
			fmSpringHessian(mesh, state->x, e, K, pb->exactHessian ? 0 : 1);
			for (int p = 0; p < 2; ++p)
				for (int r = 0; r < 9; ++r)
					blocks[9 * (size_t)mesh->edges[2 * e + p] + r] +=
					    K[6 * (3 * p + r / 3) + (3 * p + r % 3)];
		}
	}
	else
	{
		double K[144];
		for (int t = 0; t < mesh->tetCount; ++t)
		{
			fmTetHessian(mesh, state->x, t, K, pb->exactHessian ? 0 : 1);
			for (int p = 0; p < 4; ++p)
				for (int r = 0; r < 9; ++r)
					blocks[9 * (size_t)mesh->tets[4 * t + p] + r] +=
					    K[12 * (3 * p + r / 3) + (3 * p + r % 3)];
		}
		if (fmNodalPressure_On(mesh))
			fmNodalPressure_AddDiagonal(mesh, state->x, blocks, pb->exactHessian ? 0 : 1);
	}
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		double diagonal = (pb->inertia + pb->massDamping) * mesh->mass[i];
		for (int r = 0; r < 3; ++r)
			blocks[9 * (size_t)i + 4 * r] += diagonal;
		if (pb->useDamping)
		{
			const double* d = c->damping + 9 * (size_t)c->pattern.diagonal[i];
			for (int r = 0; r < 9; ++r)
				blocks[9 * (size_t)i + r] += d[r];
		}
	}
	fmTermHessian(&pb->targets, state->x, NULL, blocks);
	fmTermHessian(&pb->contact, state->x, NULL, blocks);
	fmTermHessian(&pb->barrier, state->x, NULL, blocks);
}

// One range of block rows of the assembled product y = H x.
typedef struct fmProductTask
{
	const fmImplicitCache* cache;
	const double* x;
	double* y;
} fmProductTask;

static void fmProductRowsTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmProductTask* t = context;
	fmBsr_MultiplyRows(&t->cache->pattern, t->cache->hessian, t->x, t->y, start, end);
}

// y = H x on the world's workers: every block row is computed alone, the same bits for any
// split.
static void fmAssembledProduct(void* context, const double* x, double* y)
{
	const fmNewtonContext* ctx = context;
	fmProductTask task = {ctx->cache, x, y};
	fmParallelFor(ctx->problem->tasks, ctx->cache->pattern.rows, FM_PARALLEL_MIN_RANGE,
	              fmProductRowsTask, &task);
}

static void fmMatrixFreeProduct(void* context, const double* x, double* y)
{
	const fmNewtonContext* ctx = context;
	const fmElasticMesh* mesh = ctx->mesh;
	const fmBodyState* state = ctx->state;
	const fmNewtonProblem* pb = ctx->problem;
	if (pb->useDamping)
		fmBsr_Multiply(&ctx->cache->pattern, ctx->cache->damping, x, y);
	else
		memset(y, 0, sizeof(double) * 3 * (size_t)mesh->vertexCount);
	fmAddHessianProduct(mesh, state->x, x, y, pb->exactHessian ? 0 : 1);
	for (int k = 0; k < 3 * mesh->vertexCount; ++k)
		y[k] += (pb->inertia + pb->massDamping) * mesh->mass[k / 3] * x[k];
	fmTermProduct(&pb->targets, state->x, x, y);
	fmTermProduct(&pb->contact, state->x, x, y);
	fmTermProduct(&pb->barrier, state->x, x, y);
}

// Newton direction: solve H d = -gradient over the free DOFs.
static fmPcgResult fmNewtonDirection(const fmElasticMesh* mesh, fmBodyState* state,
                                     fmImplicitCache* c, const fmNewtonProblem* pb,
                                     double gradientNorm, double residual)
{
	const int n3 = 3 * mesh->vertexCount;
	fmNewtonContext ctx = {mesh, state, c, pb};
	fmLinearOperator* op = fmAssembledProduct;
	if (pb->options.product == fm_productMatrixFree)
	{
		fmMarkFixed(mesh, state, c, pb, state->x,
		            true); // (the reach from the inertia alone: no matrix)
		fmDiagonalBlocksMatrixFree(mesh, state, c, pb,
		                           c->work); // blocks in the CG's scratch, used below
		fmPcg_BuildPreconditioner(mesh->vertexCount, c->work, c->fixed, pb->options.preconditioner,
		                          c->blockInverse);
		op = fmMatrixFreeProduct;
	}
	else
	{
		// The epsilon-active set, from the matrix this direction uses.
		fmMarkFixed(mesh, state, c, pb, state->x, true);
		for (int i = 0; i < mesh->vertexCount; ++i)
			memcpy(c->work + 9 * (size_t)i, c->hessian + 9 * (size_t)c->pattern.diagonal[i],
			       9 * sizeof(double));
		fmPcg_BuildPreconditioner(mesh->vertexCount, c->work, c->fixed, pb->options.preconditioner,
		                          c->blockInverse);
	}
	for (int k = 0; k < n3; ++k)
		c->temp[k] = -c->gradient[k];
	// Inexact Newton (Eisenstat-Walker flavour): a loose CG far from the solution, tighter
	// near it; a quadratic energy is solved tightly in one Newton step.
	// Within FM_NEWTON_FINISH times the tolerance, the system is solved to half the tolerance
	// instead: the step then usually ends the solve, and the CG iterations this adds cost less
	// than the Newton iteration it saves (docs/decisions.md, "Finishing Newton").
	double floorTolerance = 0.1 * pb->tolerance * pb->scale;
	double forcing = pb->quadratic ? 0.0 : fmMin(0.1, residual);
	double tolerance = fmMax(forcing * gradientNorm, floorTolerance);
	if (residual < FM_NEWTON_FINISH * pb->tolerance)
		tolerance = fmMin(tolerance, fmMax(0.5 * pb->tolerance * pb->scale, floorTolerance));
	fmPcgWork work = {c->work, c->work + n3, c->work + 2 * n3, c->work + 3 * n3};
	fmPcgPreconditioner pre = {
	    pb->options.preconditioner, c->blockInverse, &c->pattern, c->hessian, pb->tasks, NULL};
	if (pb->options.product == fm_productMatrixFree)
		pre.kind = pre.kind == fm_precondJacobi ? fm_precondJacobi : fm_precondBlockJacobi;
	if (pre.kind == fm_precondAuto)
		pre.kind = mesh->vertexCount >= FM_MG_MIN_ROWS ? fm_precondMultigrid
		                                               : fm_precondSymmetricGaussSeidel;
	if (pre.kind == fm_precondMultigrid)
	{
		// Without memory for its levels, the one-level preconditioner.
		fmMultigrid* mg = fmSolverCache_Multigrid(c);
		pre.kind = mg ? fm_precondMultigrid : fm_precondSymmetricGaussSeidel;
		if (mg)
			fmMultigrid_Setup(mg, c->hessian, c->blockInverse, c->fixed, c->hessianVersion,
			                  pb->tasks);
		pre.multigrid = mg;
	}
	return fmPcg_Solve(n3, op, &ctx, &pre, c->fixed, c->temp, c->direction, tolerance, pb->maxCg,
	                   &work);
}

// Positions after a step of length alpha along the direction, held above the floor; true when
// the floor bent the path (a coordinate was lifted to it).
static bool fmTrialPoint(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                         const fmNewtonProblem* pb, double alpha, double* out)
{
	for (int k = 0; k < 3 * mesh->vertexCount; ++k)
		out[k] = state->x[k] + alpha * c->direction[k];
	bool bent = false;
	for (int i = 0; pb->floor != NULL && i < mesh->vertexCount; ++i)
		if (!(state->pinned[i] & FM_PIN_Y) && out[3 * i + 1] < c->floorBound[i])
		{
			out[3 * i + 1] = c->floorBound[i];
			bent = true;
		}
	return bent;
}

bool fmNewton_Bounded(const fmNewtonProblem* pb)
{
	return pb->barrier.stepBound != NULL || pb->contact.stepBound != NULL;
}

double fmNewton_StepBound(const fmNewtonProblem* pb, const double* x, const double* dx)
{
	double t = 1.0;
	if (pb->barrier.stepBound != NULL)
		t = fmMin(t, pb->barrier.stepBound(pb->barrier.context, x, dx));
	if (pb->contact.stepBound != NULL && t > 0.0)
		t = fmMin(t, pb->contact.stepBound(pb->contact.context, x, dx));
	return t;
}

// Whether the straight path from x to @p trial is admissible for the barrier (a path the floor
// bent is checked again as it is); @p scratch gets the motion.
static bool fmPathAdmissible(const fmElasticMesh* mesh, const fmBodyState* state,
                             const fmNewtonProblem* pb, const double* trial, double* scratch)
{
	for (int k = 0; k < 3 * mesh->vertexCount; ++k)
		scratch[k] = trial[k] - state->x[k];
	return fmNewton_StepBound(pb, state->x, scratch) >= 1.0;
}

// The longest step along the direction that the inversion filter and the barrier's collision
// detection allow (1 at most).
static double fmStepLimit(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                          const fmNewtonProblem* pb)
{
	double alpha = pb->inversionFree
	                   ? fmInversion_StepLimit(mesh, state->x, c->direction, FM_INVERSION_KEEP)
	                   : 1.0;
	if (fmNewton_Bounded(pb) && alpha > 0.0)
	{
		const int n3 = 3 * mesh->vertexCount;
		for (int k = 0; k < n3; ++k)
			c->trial[k] = alpha * c->direction[k];
		alpha *= fmMin(1.0, fmNewton_StepBound(pb, state->x, c->trial));
	}
	return alpha;
}

// Backtracking line search (Armijo, c = 1e-4) on E along the projected path.
// Round-off: the elastic energy is a sum of per-tet densities of size (mu + lambda) times the
// volume that cancel to a small total, so E is only known to about 1e-13 of that; near the
// solution of a stiff body the decrease a Newton step makes is smaller than this noise. Within
// the noise a step is accepted when it lowers the gradient norm instead. Returns false if no
// step length is accepted.
static bool fmLineSearch(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                         const fmNewtonProblem* pb, double energy, double magnitude,
                         double gradientNorm, bool* inNoise)
{
	const int n3 = 3 * mesh->vertexCount;
	const double noise = fmEnergyNoise(mesh, c, magnitude);
	double* trial = c->trial;
	double* trialGradient = c->work + 2 * n3;
	double alpha = fmStepLimit(mesh, state, c, pb);
	if (!(alpha > 0.0))
		return false; // a tet at the edge of the filter already, or a pair touching: stalled
	for (int attempt = 0; attempt < 40; ++attempt, alpha *= 0.5)
	{
		bool bent = fmTrialPoint(mesh, state, c, pb, alpha, trial);
		if (pb->inversionFree && fmInversion_Any(mesh, state->x, trial))
			continue; // the floor's projection bent the path into a flat tet: shorter
		if (bent && fmNewton_Bounded(pb) &&
		    !fmPathAdmissible(mesh, state, pb, trial, trialGradient))
			continue; // the floor bent the path into another surface: shorter
		double slope = 0.0;
		for (int k = 0; k < n3; ++k)
			slope += c->gradient[k] * (trial[k] - state->x[k]);
		// The full step is usually taken: its forces then serve the next iteration's gradient.
		double value =
		    fmNewtonEnergy(mesh, c, pb, trial, attempt == 0 ? trialGradient : NULL, NULL);
		bool accept = value <= energy + 1e-4 * slope;
		if (!accept && fabs(value - energy) <= noise)
		{
			fmNewtonEnergy(mesh, c, pb, trial, trialGradient, NULL);
			accept = fmFreeNorm(n3, trialGradient, c->fixed) < (1.0 - 1e-4 * alpha) * gradientNorm;
		}
		if (accept)
		{
			*inNoise = fabs(value - energy) <= noise;
			memcpy(state->x, trial, sizeof(double) * (size_t)n3);
			return true;
		}
	}
	return false;
}

// Make sure the direction goes downhill; otherwise use the preconditioned gradient.
static void fmEnsureDescent(const fmElasticMesh* mesh, fmImplicitCache* c)
{
	const int n3 = 3 * mesh->vertexCount;
	double slope = 0.0;
	for (int k = 0; k < n3; ++k)
		slope += c->gradient[k] * c->direction[k];
	if (slope < 0.0)
		return;
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		const double* B = c->blockInverse + 9 * (size_t)i;
		const double* g = c->gradient + 3 * (size_t)i;
		for (int r = 0; r < 3; ++r)
			c->direction[3 * i + r] =
			    c->fixed[3 * i + r]
			        ? 0.0
			        : -(B[3 * r] * g[0] + B[3 * r + 1] * g[1] + B[3 * r + 2] * g[2]);
	}
}

// What the Newton loop remembers between iterations.
typedef struct fmNewtonTrack
{
	double bestResidual; // the best residual by a margin (stagnation)
	double keptResidual; // the best state's (pb->keepBest)
	int sinceBest;       // iterations in the energy's noise without improving on bestResidual
	bool inNoise;        // the last step changed the energy by less than its round-off
	bool stale;          // the kept Hessian was assembled for other terms
	double lastResidual;
	bool lastFresh;       // the last direction came from a freshly assembled Hessian
	bool lastContactOnly; // ... from a kept base with fresh contact terms
} fmNewtonTrack;

// After the residual of an iteration is known: keep the best state, and whether to stop
// (converged, out of iterations, stagnated: steps that change the energy by less than its
// round-off and no longer improve the residual; far from the solution the residual may rise
// for many iterations while the energy falls, which is progress).
static bool fmNewtonStops(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                          const fmNewtonProblem* pb, fmNewtonTrack* t, fmNewtonResult* result)
{
	if (pb->keepBest && result->residual < t->keptResidual)
	{
		t->keptResidual = result->residual;
		memcpy(c->best, state->x, sizeof(double) * 3 * (size_t)mesh->vertexCount);
	}
	if (result->residual <= pb->tolerance)
	{
		result->converged = true;
		return true;
	}
	if (result->iterations >= pb->maxNewton)
		return true;
	bool improved = result->residual < 0.9 * t->bestResidual;
	t->bestResidual = improved ? result->residual : t->bestResidual;
	t->sinceBest = improved || !t->inNoise ? 0 : t->sinceBest + 1;
	result->stagnated = t->sinceBest >= FM_NEWTON_STAGNATION;
	return result->stagnated;
}

// Lazy Hessian: per-element projected Hessians dominate the cost of an iteration, so the
// assembled matrix is reused (within a step and across steps: a body at rest hardly changes it)
// as long as it still cuts the residual by FM_REUSE_RATIO per iteration; any SPD matrix gives a
// descent direction, so a stale one only costs speed, never safety. A quadratic energy has a
// constant Hessian (a fresh exact one cannot do better; only the floor's active set makes such
// a step slow). The matrix-free path has no matrix to keep.
// With contact terms, a slow matrix is first renewed in its contact part only, on the kept base
// (the matrix without them, from the last full assembly, in this step or an earlier one): a
// landing's contacts change from one iteration to the next far more than the body's stiffness
// does. If that direction is slow too, the matrix is assembled in full.
static void fmNewtonMatrix(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                           const fmNewtonProblem* pb, fmNewtonTrack* t, double residual)
{
	bool slow = residual > FM_REUSE_RATIO * t->lastResidual;
	bool matrixFree = pb->options.product == fm_productMatrixFree;
	bool refresh = t->stale || (slow && !(pb->quadratic && t->lastFresh)) || matrixFree;
	bool contactOnly = refresh && !matrixFree && !t->stale && c->hessianBaseValid &&
	                   !t->lastContactOnly && fmHasContactHessian(pb);
	if (contactOnly)
		fmRefreshContactHessian(state, c, pb);
	else if (refresh && !matrixFree)
		c->hessianBaseValid = fmAssembleNewtonMatrix(mesh, state, c, pb);
	if (refresh)
	{
		c->hessianValid = true;
		c->hessianInertia = pb->inertia;
		c->hessianMassDamping = pb->massDamping;
		c->hessianDamping = pb->useDamping;
		c->hessianExact = pb->exactHessian;
		t->stale = false;
	}
	t->lastResidual = residual;
	t->lastFresh = refresh && !contactOnly;
	t->lastContactOnly = contactOnly;
}

fmNewtonResult fmNewton_Solve(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                              const fmNewtonProblem* pb)
{
	fmNewtonResult result;
	memset(&result, 0, sizeof result);
	result.residual = INFINITY;
	result.finite = true;
	const int n3 = 3 * mesh->vertexCount;
	const double scale = pb->scale > 0.0 ? pb->scale : DBL_MIN;
	bool sameTerms = c->hessianValid && c->hessianInertia == pb->inertia &&
	                 c->hessianMassDamping == pb->massDamping &&
	                 c->hessianDamping == pb->useDamping && c->hessianExact == pb->exactHessian;
	fmNewtonTrack t = {.bestResidual = INFINITY,
	                   .keptResidual = INFINITY,
	                   .stale = !sameTerms,
	                   .lastResidual = INFINITY};
	for (;;)
	{
		double magnitude;
		double energy = fmNewtonEnergy(mesh, c, pb, state->x, c->gradient, &magnitude);
		fmMarkFixed(mesh, state, c, pb, state->x, false);
		double gradientNorm = fmFreeNorm(n3, c->gradient, c->fixed);
		if (!isfinite(energy) || !isfinite(gradientNorm))
		{
			result.finite = false;
			break;
		}
		result.residual = gradientNorm / scale;
		if (fmNewtonStops(mesh, state, c, pb, &t, &result))
			break;
		fmNewtonMatrix(mesh, state, c, pb, &t, result.residual);
		fmPcgResult cg = fmNewtonDirection(mesh, state, c, pb, gradientNorm, result.residual);
		result.cgIterations += cg.iterations;
		if (cg.indefinite && pb->exactHessian)
		{
			// The true Hessian is not positive definite here: project from now on.
			result.projected = true;
			break;
		}
		result.iterations += 1;
		fmEnsureDescent(mesh, c);
		fmReachFloor(mesh, state, c, pb);
		if (!fmLineSearch(mesh, state, c, pb, energy, magnitude, gradientNorm, &t.inNoise))
		{
			result.stalled = true;
			break;
		}
	}
	if (pb->keepBest && result.finite && !result.converged && t.keptResidual < result.residual)
	{
		memcpy(state->x, c->best, sizeof(double) * (size_t)n3);
		result.residual = t.keptResidual;
	}
	return result;
}
