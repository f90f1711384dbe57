// Backward Euler as optimisation (docs/implicit.md): x_{n+1} minimises the incremental potential
//   E(x) = 1/(2 h^2) |x - x_n - h v_n|_M^2 + Psi(x) - M g . x + Rayleigh damping terms
// subject to the pins and the floor y >= height. Newton's method with per-element PSD-projected
// Hessians (Teran et al. 2005), a preconditioned CG for each Newton system, and a backtracking
// (Armijo) line search on E along the floor-projected path (Bertsekas' projected Newton).
// v_{n+1} = (x_{n+1} - x_n) / h, then the body's damping factor, smoothing and floor friction.
#include "core.h"
#include "forces.h"
#include "integrator.h"
#include "newton.h"

#include <float.h>
#include <math.h>
#include <string.h>

static fmImplicitOptions s_options = {fm_productAssembled, fm_precondJacobi};

fmImplicitOptions fmImplicit_GetOptions(void)
{
	return s_options;
}

void fmImplicit_SetOptions(fmImplicitOptions options)
{
	s_options = options;
}

// ---- cache ---------------------------------------------------------------------------------

void fmImplicitCacheFree(void* memory)
{
	fmImplicitCache* c = memory;
	if (c == NULL)
		return;
	size_t n3 = 3 * (size_t)c->vertexCount, blocks = (size_t)c->pattern.blocks;
	FM_FREE_ARRAY(c->tetSlot, int, 16 * (size_t)c->tetCount);
	FM_FREE_ARRAY(c->edgeSlot, int, 4 * (size_t)c->edgeCount);
	FM_FREE_ARRAY(c->hessian, double, 9 * blocks);
	FM_FREE_ARRAY(c->damping, double, 9 * blocks);
	FM_FREE_ARRAY(c->blockInverse, double, 9 * (size_t)c->vertexCount);
	FM_FREE_ARRAY(c->xPred, double, n3);
	FM_FREE_ARRAY(c->xStart, double, n3);
	FM_FREE_ARRAY(c->gradient, double, n3);
	FM_FREE_ARRAY(c->direction, double, n3);
	FM_FREE_ARRAY(c->trial, double, n3);
	FM_FREE_ARRAY(c->forces, double, n3);
	FM_FREE_ARRAY(c->temp, double, n3);
	FM_FREE_ARRAY(c->work, double, 4 * n3);
	FM_FREE_ARRAY(c->fixed, uint8_t, n3);
	FM_FREE_ARRAY(c->floorBound, double, (size_t)c->vertexCount);
	FM_FREE_ARRAY(c->best, double, n3);
	fmBsr_Free(&c->pattern);
	FM_FREE_ARRAY(c, fmImplicitCache, 1);
}

// Slots of every node pair of every tet (and of every spring), so that refilling the matrix
// is a plain scatter in tet order (deterministic, no search).
static bool fmBuildSlots(const fmBody* b, fmImplicitCache* c)
{
	for (int t = 0; t < b->tetCount; ++t)
		for (int a = 0; a < 4; ++a)
			for (int d = 0; d < 4; ++d)
				c->tetSlot[16 * t + 4 * a + d] =
				    fmBsr_Find(&c->pattern, b->tets[4 * t + a], b->tets[4 * t + d]);
	for (int e = 0; e < c->edgeCount; ++e)
	{
		int p = b->edges[2 * e], q = b->edges[2 * e + 1];
		c->edgeSlot[4 * e + 0] = fmBsr_Find(&c->pattern, p, p);
		c->edgeSlot[4 * e + 1] = fmBsr_Find(&c->pattern, p, q);
		c->edgeSlot[4 * e + 2] = fmBsr_Find(&c->pattern, q, p);
		c->edgeSlot[4 * e + 3] = fmBsr_Find(&c->pattern, q, q);
		if (c->edgeSlot[4 * e + 1] < 0)
			return false; // springs are tet edges, so this cannot happen
	}
	return true;
}

fmImplicitCache* fmImplicit_GetCache(fmBody* b)
{
	if (b->implicitCache)
		return b->implicitCache;
	fmImplicitCache* c = FM_ALLOC_ZERO(fmImplicitCache, 1);
	if (c == NULL)
		return NULL;
	b->implicitCache = c;
	c->vertexCount = b->vertexCount;
	c->tetCount = b->tetCount;
	c->edgeCount = b->forceModel == fm_massSpring ? b->edgeCount : 0;
	for (int t = 0; t < b->tetCount; ++t)
		c->volume += b->restVolume[t];
	size_t n3 = 3 * (size_t)b->vertexCount;
	bool ok = fmBsr_Build(&c->pattern, b->vertexCount, b->tets, b->tetCount);
	if (!ok)
		c->pattern.blocks = 0;
	c->tetSlot = FM_ALLOC_ARRAY(int, 16 * (size_t)c->tetCount);
	c->edgeSlot = FM_ALLOC_ARRAY(int, 4 * (size_t)c->edgeCount);
	c->hessian = FM_ALLOC_ZERO(double, 9 * (size_t)c->pattern.blocks);
	c->blockInverse = FM_ALLOC_ZERO(double, 9 * (size_t)b->vertexCount);
	c->xPred = FM_ALLOC_ZERO(double, n3);
	c->xStart = FM_ALLOC_ZERO(double, n3);
	c->gradient = FM_ALLOC_ZERO(double, n3);
	c->direction = FM_ALLOC_ZERO(double, n3);
	c->trial = FM_ALLOC_ZERO(double, n3);
	c->forces = FM_ALLOC_ZERO(double, n3);
	c->temp = FM_ALLOC_ZERO(double, n3);
	c->work = FM_ALLOC_ZERO(double, 4 * n3);
	c->fixed = FM_ALLOC_ZERO(uint8_t, n3);
	c->floorBound = FM_ALLOC_ZERO(double, (size_t)b->vertexCount);
	c->best = FM_ALLOC_ZERO(double, n3);
	ok = ok && c->tetSlot && (c->edgeSlot || c->edgeCount == 0) && c->hessian && c->blockInverse &&
	     c->xPred && c->xStart && c->gradient && c->direction && c->trial && c->forces && c->temp &&
	     c->work && c->fixed && c->floorBound && c->best;
	if (ok)
		ok = fmBuildSlots(b, c);
	if (!ok)
	{
		fmImplicitCacheFree(c);
		b->implicitCache = NULL;
		return NULL;
	}
	return c;
}

// ---- assembly --------------------------------------------------------------------------------

// values += scale * (PSD-projected) elastic Hessian at x, element by element in a fixed order.
static void fmAddStiffness(const fmBody* b, const fmImplicitCache* c, const double* x, double scale,
                           int project, double* values)
{
	if (b->forceModel == fm_massSpring)
	{
		double K[36];
		for (int e = 0; e < c->edgeCount; ++e)
		{
			fmSpringHessian(b, x, e, K, project);
			for (int p = 0; p < 2; ++p)
				for (int q = 0; q < 2; ++q)
				{
					double* block = values + 9 * (size_t)c->edgeSlot[4 * e + 2 * p + q];
					for (int r = 0; r < 3; ++r)
						for (int s = 0; s < 3; ++s)
							block[3 * r + s] += scale * K[6 * (3 * p + r) + (3 * q + s)];
				}
		}
		return;
	}
	double K[144];
	for (int t = 0; t < b->tetCount; ++t)
	{
		fmTetHessian(b, x, t, K, project);
		for (int p = 0; p < 4; ++p)
			for (int q = 0; q < 4; ++q)
			{
				double* block = values + 9 * (size_t)c->tetSlot[16 * t + 4 * p + q];
				for (int r = 0; r < 3; ++r)
					for (int s = 0; s < 3; ++s)
						block[3 * r + s] += scale * K[12 * (3 * p + r) + (3 * q + s)];
			}
	}
}

// Spring damping as a matrix: each spring resists the rate of change of its length with
// c = 2 zeta sqrt(k / (1/ma + 1/mb)) (force_spring.c), i.e. the block c n n^T on [a, b].
static void fmAddSpringDampingMatrix(const fmBody* b, const fmImplicitCache* c, const double* x,
                                     double scale, double* values)
{
	for (int e = 0; e < c->edgeCount; ++e)
	{
		fmVec3 direction;
		double coefficient = fmSpringDashpot(b, x, e, &direction);
		if (coefficient <= 0.0)
			continue;
		const double n[3] = {direction.x, direction.y, direction.z};
		for (int k = 0; k < 4; ++k)
		{
			double sign = (k == 1 || k == 2) ? -1.0 : 1.0;
			double* block = values + 9 * (size_t)c->edgeSlot[4 * e + k];
			for (int r = 0; r < 3; ++r)
				for (int s = 0; s < 3; ++s)
					block[3 * r + s] += scale * sign * coefficient * n[r] * n[s];
		}
	}
}

// Residual reduction per Newton iteration below which a kept matrix is still good enough.
#define FM_REUSE_RATIO 0.25

// ---- the minimiser -------------------------------------------------------------------------

typedef struct fmNewtonContext
{
	fmBody* body;
	fmImplicitCache* cache;
	const fmNewtonProblem* problem;
} fmNewtonContext;

// Energy at x, and its gradient when @p gradient is not NULL. @p magnitude gets the sum of the
// absolute sizes of the terms (the scale of round-off in E).
static double fmNewtonEnergy(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                             const double* x, double* gradient, double* magnitude)
{
	const int n3 = 3 * b->vertexCount;
	double psi;
	if (gradient)
	{
		memset(c->forces, 0, sizeof(double) * (size_t)n3);
		psi = fmAddElasticForces(b, x, c->forces);
	}
	else
		psi = fmElasticEnergy(b, x);
	const double g[3] = {pb->gravity.x, pb->gravity.y, pb->gravity.z};
	double inertial = 0.0, external = 0.0, size = 0.0;
	for (int k = 0; k < n3; ++k)
	{
		double m = b->mass[k / 3];
		double toPred = x[k] - c->xPred[k], moved = x[k] - c->xStart[k];
		double term = 0.5 * m * (pb->inertia * toPred * toPred + pb->massDamping * moved * moved);
		inertial += term;
		external -= m * g[k % 3] * moved;
		size += fabs(m * g[k % 3] * moved);
		if (gradient)
			gradient[k] =
			    m * (pb->inertia * toPred + pb->massDamping * moved - g[k % 3]) - c->forces[k];
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
	if (magnitude)
		*magnitude = fabs(psi) + inertial + size + damping;
	return inertial + damping + psi + external;
}

// DOFs the step may not move: pins, and the floor where it pushes (active set: a vertex on the
// floor whose energy gradient points down is held; one the energy pulls up is released).
static void fmMarkFixed(const fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                        const double* x)
{
	for (int i = 0; i < b->vertexCount; ++i)
	{
		unsigned pin = b->pinned[i];
		bool onFloor = pb->floor && !(pin & FM_PIN_Y) && x[3 * i + 1] <= c->floorBound[i] &&
		               c->gradient[3 * i + 1] > 0.0;
		bool stick = onFloor && pb->floor->friction == fm_floorStick;
		c->fixed[3 * i] = (pin & 1u) || stick;
		c->fixed[3 * i + 1] = (pin & FM_PIN_Y) || onFloor;
		c->fixed[3 * i + 2] = (pin & 4u) || stick;
	}
}

static double fmFreeNorm(int n3, const double* v, const uint8_t* fixed)
{
	double s = 0.0;
	for (int k = 0; k < n3; ++k)
		if (!fixed[k])
			s += v[k] * v[k];
	return sqrt(s);
}

// The Newton matrix H = (inertia + massDamping) M + K(x) [+ D], assembled.
static void fmAssembleNewtonMatrix(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb)
{
	const size_t values = 9 * (size_t)c->pattern.blocks;
	if (pb->useDamping)
		memcpy(c->hessian, c->damping, sizeof(double) * values);
	else
		memset(c->hessian, 0, sizeof(double) * values);
	fmAddStiffness(b, c, b->x, 1.0, pb->exactHessian ? 0 : 1, c->hessian);
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double* block = c->hessian + 9 * (size_t)c->pattern.diagonal[i];
		double diagonal = (pb->inertia + pb->massDamping) * b->mass[i];
		block[0] += diagonal;
		block[4] += diagonal;
		block[8] += diagonal;
	}
}

// Diagonal blocks only, for the matrix-free path's preconditioner (into c->hessian's first
// 9 n entries, used as plain per-vertex storage).
static void fmDiagonalBlocksMatrixFree(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                                       double* blocks)
{
	memset(blocks, 0, sizeof(double) * 9 * (size_t)b->vertexCount);
	if (b->forceModel == fm_massSpring)
	{
		double K[36];
		for (int e = 0; e < c->edgeCount; ++e)
		{
			fmSpringHessian(b, b->x, e, K, pb->exactHessian ? 0 : 1);
			for (int p = 0; p < 2; ++p)
				for (int r = 0; r < 9; ++r)
					blocks[9 * (size_t)b->edges[2 * e + p] + r] +=
					    K[6 * (3 * p + r / 3) + (3 * p + r % 3)];
		}
	}
	else
	{
		double K[144];
		for (int t = 0; t < b->tetCount; ++t)
		{
			fmTetHessian(b, b->x, t, K, pb->exactHessian ? 0 : 1);
			for (int p = 0; p < 4; ++p)
				for (int r = 0; r < 9; ++r)
					blocks[9 * (size_t)b->tets[4 * t + p] + r] +=
					    K[12 * (3 * p + r / 3) + (3 * p + r % 3)];
		}
	}
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double diagonal = (pb->inertia + pb->massDamping) * b->mass[i];
		for (int r = 0; r < 3; ++r)
			blocks[9 * (size_t)i + 4 * r] += diagonal;
		if (pb->useDamping)
		{
			const double* d = c->damping + 9 * (size_t)c->pattern.diagonal[i];
			for (int r = 0; r < 9; ++r)
				blocks[9 * (size_t)i + r] += d[r];
		}
	}
}

static void fmAssembledProduct(void* context, const double* x, double* y)
{
	const fmNewtonContext* ctx = context;
	fmBsr_Multiply(&ctx->cache->pattern, ctx->cache->hessian, x, y);
}

static void fmMatrixFreeProduct(void* context, const double* x, double* y)
{
	const fmNewtonContext* ctx = context;
	fmBody* b = ctx->body;
	const fmNewtonProblem* pb = ctx->problem;
	if (pb->useDamping)
		fmBsr_Multiply(&ctx->cache->pattern, ctx->cache->damping, x, y);
	else
		memset(y, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	fmAddHessianProduct(b, b->x, x, y, pb->exactHessian ? 0 : 1);
	for (int k = 0; k < 3 * b->vertexCount; ++k)
		y[k] += (pb->inertia + pb->massDamping) * b->mass[k / 3] * x[k];
}

// Newton direction: solve H d = -gradient over the free DOFs.
static fmPcgResult fmNewtonDirection(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                                     double gradientNorm, double residual, bool refresh)
{
	const int n3 = 3 * b->vertexCount;
	fmNewtonContext ctx = {b, c, pb};
	fmLinearOperator* op = fmAssembledProduct;
	if (s_options.product == fm_productMatrixFree)
	{
		fmDiagonalBlocksMatrixFree(b, c, pb, c->work); // blocks in the CG's scratch, used below
		fmPcg_BuildPreconditioner(b->vertexCount, c->work, c->fixed, s_options.preconditioner,
		                          c->blockInverse);
		op = fmMatrixFreeProduct;
	}
	else
	{
		if (refresh)
			fmAssembleNewtonMatrix(b, c, pb);
		for (int i = 0; i < b->vertexCount; ++i)
			memcpy(c->work + 9 * (size_t)i, c->hessian + 9 * (size_t)c->pattern.diagonal[i],
			       9 * sizeof(double));
		fmPcg_BuildPreconditioner(b->vertexCount, c->work, c->fixed, s_options.preconditioner,
		                          c->blockInverse);
	}
	for (int k = 0; k < n3; ++k)
		c->temp[k] = -c->gradient[k];
	// Inexact Newton (Eisenstat-Walker flavour): a loose CG far from the solution, tighter
	// near it; a quadratic energy is solved tightly in one Newton step.
	double floorTolerance = 0.1 * pb->tolerance * pb->scale;
	double forcing = pb->quadratic ? 0.0 : fmin(0.1, residual);
	double tolerance = fmax(forcing * gradientNorm, floorTolerance);
	fmPcgWork work = {c->work, c->work + n3, c->work + 2 * n3, c->work + 3 * n3};
	return fmPcg_Solve(n3, op, &ctx, c->blockInverse, c->fixed, c->temp, c->direction, tolerance,
	                   pb->maxCg, &work);
}

// Positions after a step of length alpha along the direction, held above the floor.
static void fmTrialPoint(const fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb,
                         double alpha, double* out)
{
	for (int k = 0; k < 3 * b->vertexCount; ++k)
		out[k] = b->x[k] + alpha * c->direction[k];
	if (pb->floor == NULL)
		return;
	for (int i = 0; i < b->vertexCount; ++i)
		if (!(b->pinned[i] & FM_PIN_Y) && out[3 * i + 1] < c->floorBound[i])
			out[3 * i + 1] = c->floorBound[i];
}

// Backtracking line search (Armijo, c = 1e-4) on E along the projected path.
// Round-off: the elastic energy is a sum of per-tet densities of size (mu + lambda) times the
// volume that cancel to a small total, so E is only known to about 1e-13 of that; near the
// solution of a stiff body the decrease a Newton step makes is smaller than this noise. Within
// the noise a step is accepted when it lowers the gradient norm instead. Returns false if no
// step length is accepted.
static bool fmLineSearch(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb, double energy,
                         double magnitude, double gradientNorm, bool* inNoise)
{
	const int n3 = 3 * b->vertexCount;
	const double noise =
	    1e-13 * (magnitude + (b->material.mu + fabs(b->material.lambda)) * c->volume);
	double* trial = c->trial;
	double* trialGradient = c->work + 2 * n3;
	double alpha = 1.0;
	for (int attempt = 0; attempt < 40; ++attempt, alpha *= 0.5)
	{
		fmTrialPoint(b, c, pb, alpha, trial);
		double slope = 0.0;
		for (int k = 0; k < n3; ++k)
			slope += c->gradient[k] * (trial[k] - b->x[k]);
		double value = fmNewtonEnergy(b, c, pb, trial, NULL, NULL);
		bool accept = value <= energy + 1e-4 * slope;
		if (!accept && fabs(value - energy) <= noise)
		{
			fmNewtonEnergy(b, c, pb, trial, trialGradient, NULL);
			accept = fmFreeNorm(n3, trialGradient, c->fixed) < (1.0 - 1e-4 * alpha) * gradientNorm;
		}
		if (accept)
		{
			*inNoise = fabs(value - energy) <= noise;
			memcpy(b->x, trial, sizeof(double) * (size_t)n3);
			return true;
		}
	}
	return false;
}

// Make sure the direction goes downhill; otherwise use the preconditioned gradient.
static void fmEnsureDescent(fmBody* b, fmImplicitCache* c)
{
	const int n3 = 3 * b->vertexCount;
	double slope = 0.0;
	for (int k = 0; k < n3; ++k)
		slope += c->gradient[k] * c->direction[k];
	if (slope < 0.0)
		return;
	for (int i = 0; i < b->vertexCount; ++i)
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

fmNewtonResult fmNewton_Solve(fmBody* b, fmImplicitCache* c, const fmNewtonProblem* pb)
{
	fmNewtonResult result;
	memset(&result, 0, sizeof result);
	result.residual = INFINITY;
	result.finite = true;
	const int n3 = 3 * b->vertexCount;
	double bestResidual = INFINITY, keptResidual = INFINITY;
	int sinceBest = 0;
	bool inNoise = false; // the last step changed the energy by less than its round-off
	const double scale = pb->scale > 0.0 ? pb->scale : DBL_MIN;
	// Lazy Hessian: per-element projected Hessians dominate the cost of an iteration, so the
	// assembled matrix is reused (within a step and across steps: a body at rest hardly
	// changes it) as long as it still cuts the residual by FM_REUSE_RATIO per iteration; any
	// SPD matrix gives a descent direction, so a stale one only costs speed, never safety.
	// A quadratic energy has a constant Hessian. The matrix-free path has no matrix to keep.
	bool sameTerms = c->hessianValid && c->hessianInertia == pb->inertia &&
	                 c->hessianMassDamping == pb->massDamping &&
	                 c->hessianDamping == pb->useDamping && c->hessianExact == pb->exactHessian;
	bool stale = !sameTerms;
	double lastResidual = INFINITY;
	bool lastFresh = false;
	for (;;)
	{
		double magnitude;
		double energy = fmNewtonEnergy(b, c, pb, b->x, c->gradient, &magnitude);
		fmMarkFixed(b, c, pb, b->x);
		double gradientNorm = fmFreeNorm(n3, c->gradient, c->fixed);
		if (!isfinite(energy) || !isfinite(gradientNorm))
		{
			result.finite = false;
			break;
		}
		result.residual = gradientNorm / scale;
		if (pb->keepBest && result.residual < keptResidual)
		{
			keptResidual = result.residual;
			memcpy(c->best, b->x, sizeof(double) * (size_t)n3);
		}
		if (result.residual <= pb->tolerance)
		{
			result.converged = true;
			break;
		}
		if (result.iterations >= pb->maxNewton)
			break;
		// Stagnation: steps that change the energy by less than its round-off and no longer
		// improve the residual. (Far from the solution the residual may rise for many
		// iterations while the energy falls; that is progress.)
		bool improved = result.residual < 0.9 * bestResidual;
		bestResidual = improved ? result.residual : bestResidual;
		sinceBest = improved || !inNoise ? 0 : sinceBest + 1;
		if (sinceBest >= FM_NEWTON_STAGNATION)
		{
			result.stagnated = true;
			break;
		}
		bool slow = result.residual > FM_REUSE_RATIO * lastResidual;
		// (A fresh exact Hessian of a quadratic energy cannot do better; only the floor's active
		// set makes such a step slow.)
		bool refresh = stale || (slow && !(pb->quadratic && lastFresh)) ||
		               s_options.product == fm_productMatrixFree;
		if (refresh)
		{
			c->hessianValid = true;
			c->hessianInertia = pb->inertia;
			c->hessianMassDamping = pb->massDamping;
			c->hessianDamping = pb->useDamping;
			c->hessianExact = pb->exactHessian;
			stale = false;
		}
		lastResidual = result.residual;
		lastFresh = refresh;
		fmPcgResult cg = fmNewtonDirection(b, c, pb, gradientNorm, result.residual, refresh);
		result.cgIterations += cg.iterations;
		if (cg.indefinite && pb->exactHessian)
		{
			// The true Hessian is not positive definite here: project from now on.
			result.projected = true;
			break;
		}
		result.iterations += 1;
		fmEnsureDescent(b, c);
		if (!fmLineSearch(b, c, pb, energy, magnitude, gradientNorm, &inNoise))
		{
			result.stalled = true;
			break;
		}
	}
	if (pb->keepBest && result.finite && !result.converged && keptResidual < result.residual)
	{
		memcpy(b->x, c->best, sizeof(double) * (size_t)n3);
		result.residual = keptResidual;
	}
	return result;
}

// ---- the implicit step -----------------------------------------------------------------------

// Floor response on velocities after the solve, for vertices resting on the floor. The solve
// already stopped them at the floor (perfectly inelastic positions); here the approach velocity
// is removed (or reflected by the restitution), and friction acts on the tangential velocity:
// stick zeroes it (the seeds), Coulomb reduces it by at most mu * (normal impulse) / m, the
// normal impulse being the floor's force from the solve times h plus the removed approach.
static int fmFloorVelocities(const fmFloorDef* floor, fmBody* b, const fmImplicitCache* c, double h)
{
	int contacts = 0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double* v = b->v + 3 * i;
		if ((b->pinned[i] & FM_PIN_Y) || b->x[3 * i + 1] > c->floorBound[i])
			continue;
		++contacts;
		double impulse = fmax(0.0, c->gradient[3 * i + 1]) * h; // N s, the floor's push
		if (v[1] < 0.0)
		{
			double e = floor->friction == fm_floorCoulomb ? floor->restitution : 0.0;
			impulse += (1.0 + e) * b->mass[i] * -v[1];
			v[1] = -e * v[1];
		}
		if (floor->friction == fm_floorStick)
		{
			v[0] = 0.0;
			v[2] = 0.0;
			continue;
		}
		double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
		double keep =
		    vt > 0.0 ? fmax(0.0, 1.0 - floor->frictionCoefficient * impulse / (b->mass[i] * vt))
		             : 0.0;
		v[0] *= keep;
		v[2] *= keep;
	}
	return contacts;
}

// Force scale of a step: |M g| + |M v / h| + |elastic forces at the start|, over free vertices.
static double fmStepForceScale(fmBody* b, fmImplicitCache* c, fmVec3 gravity, double h)
{
	memset(c->forces, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	fmAddElasticForces(b, b->x, c->forces);
	const double g[3] = {gravity.x, gravity.y, gravity.z};
	double weight = 0.0, inertia = 0.0, elastic = 0.0;
	for (int k = 0; k < 3 * b->vertexCount; ++k)
	{
		if (fmIsDofPinned(b, k))
			continue;
		double m = b->mass[k / 3];
		weight += m * m * g[k % 3] * g[k % 3];
		inertia += m * m * b->v[k] * b->v[k] / (h * h);
		elastic += c->forces[k] * c->forces[k];
	}
	return sqrt(weight) + sqrt(inertia) + sqrt(elastic);
}

// Lagged damping matrix D / h at the start of the step: beta K(x_n) (Rayleigh stiffness part)
// plus the springs' dashpots. Returns false when there is none (or no memory for it).
static bool fmPrepareDamping(fmBody* b, fmImplicitCache* c, double h)
{
	bool springs = b->forceModel == fm_massSpring && b->springDamping > 0.0;
	if (b->rayleighStiffness <= 0.0 && !springs)
		return false;
	size_t values = 9 * (size_t)c->pattern.blocks;
	if (c->damping == NULL)
		c->damping = FM_ALLOC_ARRAY(double, values);
	if (c->damping == NULL)
		return false;
	memset(c->damping, 0, sizeof(double) * values);
	if (b->rayleighStiffness > 0.0)
		fmAddStiffness(b, c, c->xStart, b->rayleighStiffness / h, 1, c->damping);
	if (springs)
		fmAddSpringDampingMatrix(b, c, c->xStart, 1.0 / h, c->damping);
	return true;
}

// Lowest y of every vertex this step: the floor, except for a vertex deep below it, which may
// rise by at most the depenetration speed times h (a body that starts below the floor is lifted
// out, not catapulted; docs/robustness.md).
static void fmSetFloorBounds(const fmFloorDef* floor, const fmBody* b, fmImplicitCache* c, double h)
{
	for (int i = 0; i < b->vertexCount; ++i)
		c->floorBound[i] =
		    fmin(floor->height, c->xStart[3 * i + 1] + floor->maxDepenetrationSpeed * h);
}

// Work the floor did on the body in the step (J), for the energy ledger: its push (the energy
// gradient it holds back) times the lift, on the vertices it lifts out from below its plane (at
// most the depenetration speed times h each). Stopping a vertex that comes from above is an
// inelastic impact: no work is booked for it.
static double fmFloorWork(const fmBody* b, const fmImplicitCache* c, double floorHeight)
{
	double work = 0.0;
	for (int i = 0; i < b->vertexCount; ++i)
		if (!(b->pinned[i] & FM_PIN_Y) && c->floorBound[i] < floorHeight &&
		    b->x[3 * i + 1] <= c->floorBound[i])
			work += fmax(0.0, c->gradient[3 * i + 1]) *
			        fmax(0.0, b->x[3 * i + 1] - c->xStart[3 * i + 1]);
	return work;
}

fmResult fmImplicitStep(const fmWorld* world, fmBody* b, double h, fmNewtonResult* solve)
{
	memset(solve, 0, sizeof *solve);
	fmImplicitCache* c = fmImplicit_GetCache(b);
	if (c == NULL)
		return fm_errOutOfMemory;
	const int n3 = 3 * b->vertexCount;
	const fmFloorDef* floor = world->def.floor.enabled ? &world->def.floor : NULL;
	const double g[3] = {world->def.gravity.x, world->def.gravity.y, world->def.gravity.z};

	// 1. Start state and inertial prediction (pinned axes stay put). The first guess is the
	//    free flight x + h v + h^2 g held above the floor: a body in free fall is then solved
	//    before the first iteration, however stiff or light it is (E / density of 1e17 and
	//    more leaves the rigid motion to round-off in the elastic forces otherwise).
	memcpy(c->xStart, b->x, sizeof(double) * (size_t)n3);
	for (int k = 0; k < n3; ++k)
		c->xPred[k] = fmIsDofPinned(b, k) ? b->x[k] : b->x[k] + h * b->v[k];
	fmNewtonProblem pb;
	memset(&pb, 0, sizeof pb);
	pb.inertia = 1.0 / (h * h);
	pb.massDamping = b->rayleighMass / h;
	pb.useDamping = fmPrepareDamping(b, c, h);
	pb.gravity = world->def.gravity;
	pb.floor = floor;
	pb.tolerance = world->def.tolerance;
	pb.scale = fmStepForceScale(b, c, pb.gravity, h);
	pb.maxNewton = world->def.newtonIterations;
	pb.maxCg = world->def.cgIterations;
	pb.quadratic = b->material.model == fm_linear && b->forceModel != fm_massSpring;
	for (int k = 0; k < n3; ++k)
		b->x[k] = fmIsDofPinned(b, k) ? c->xPred[k] : c->xPred[k] + h * h * g[k % 3];
	if (floor)
	{
		fmSetFloorBounds(floor, b, c, h);
		for (int i = 0; i < b->vertexCount; ++i)
			if (!(b->pinned[i] & FM_PIN_Y) && b->x[3 * i + 1] < c->floorBound[i])
				b->x[3 * i + 1] = c->floorBound[i];
	}

	// 2. Newton on the incremental potential.
	*solve = fmNewton_Solve(b, c, &pb);
	if (!solve->finite)
		return fm_errNumerical;

	// 3. Velocities from the positions, then the body's damping factor and smoothing (as in
	//    explicit mode, so that a scene behaves alike under both integrators).
	for (int k = 0; k < n3; ++k)
		b->v[k] = fmIsDofPinned(b, k) ? 0.0 : (b->x[k] - c->xStart[k]) / h;
	fmFilterVelocities(b, h);

	// 4. Floor: its work to the ledger, then restitution and friction on the velocities of the
	//    vertices on it.
	if (floor)
	{
		fmLedger_AddContactWork(b, fmFloorWork(b, c, floor->height));
		fmFloorVelocities(floor, b, c, h);
	}
	return fm_ok;
}
