// The aggregation multigrid preconditioner (src/solver/multigrid.c): a symmetric positive definite
// operator that respects fixed DOFs, and CG iterations that stay about constant under mesh
// refinement where the one-level symmetric Gauss-Seidel's grow with the mesh's diameter.
#include "support.h"
#include "test.h"

#include "body/body.h"
#include "solver/multigrid.h"
#include "solver/solver_cache.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The Newton matrix of an implicit step at rest, K + M / h^2 (h = 1/60 s), of a 1 m steel-soft
// box (E = 1 MPa, nu = 0.3, 1000 kg/m^3) in cells^3 cubes, with the bottom layer's DOFs fixed;
// its block inverses for the preconditioners.
typedef struct fmTestSystem
{
	fmWorldId world;
	fmBody* body;
	fmImplicitCache* cache;
	int n3;
} fmTestSystem;

static bool makeSystem(fmTestSystem* s, int cells)
{
	memset(s, 0, sizeof *s);
	fmBodyId id = fmTestMakeBox(&s->world, cells, cells, cells, fmMakeVec3(1.0, 1.0, 1.0),
	                            fmMakeMaterial(fm_neoHookean, 1e6, 0.3), fm_fem);
	if (!fmBody_IsValid(id))
		return false;
	s->body = fmGetBody(id);
	s->cache = fmSolverCache_Get(&s->body->solverCache, &s->body->mesh);
	if (s->cache == NULL)
		return false;
	fmImplicitCache* c = s->cache;
	s->n3 = 3 * s->body->mesh.vertexCount;
	memset(c->hessian, 0, sizeof(double) * 9 * (size_t)c->pattern.blocks);
	fmSolverCache_AddStiffness(&s->body->mesh, c, s->body->state.x, 1.0, 1, c->hessian, NULL);
	for (int i = 0; i < s->body->mesh.vertexCount; ++i)
	{
		double* block = c->hessian + 9 * (size_t)c->pattern.diagonal[i];
		for (int e = 0; e < 3; ++e)
			block[4 * e] += 3600.0 * s->body->mesh.mass[i];
		bool bottom = s->body->state.x[3 * i + 1] < 1e-9;
		for (int e = 0; e < 3; ++e)
			c->fixed[3 * i + e] = bottom;
	}
	for (int i = 0; i < s->body->mesh.vertexCount; ++i)
		memcpy(c->work + 9 * (size_t)i, c->hessian + 9 * (size_t)c->pattern.diagonal[i],
		       9 * sizeof(double));
	fmPcg_BuildPreconditioner(s->body->mesh.vertexCount, c->work, c->fixed, fm_precondBlockJacobi,
	                          c->blockInverse);
	return true;
}

static double dot(int n, const double* a, const double* b)
{
	double s = 0.0;
	for (int k = 0; k < n; ++k)
		s += a[k] * b[k];
	return s;
}

static void randomFree(int n, const uint8_t* fixed, double* v)
{
	for (int k = 0; k < n; ++k)
		v[k] = fixed[k] ? 0.0 : 2.0 * rand() / (double)RAND_MAX - 1.0;
}

// u . B v = v . B u, u . B u > 0, B u = 0 on fixed DOFs, for random u, v (B: one V-cycle).
TEST(cycle_is_symmetric_positive_definite)
{
	fmTestSystem s;
	CHECK(makeSystem(&s, 16));
	if (s.cache == NULL)
		return;
	fmMultigrid* mg = fmSolverCache_Multigrid(s.cache);
	CHECK(mg != NULL);
	if (mg == NULL)
		return;
	printf("  %d levels: %d", mg->levelCount, mg->level[0].pattern.rows);
	for (int l = 1; l < mg->levelCount; ++l)
		printf(" -> %d", mg->level[l].pattern.rows);
	printf(" block rows, bottom %s\n", mg->denseRows > 0 ? "dense" : "smoothed");
	CHECK(mg->levelCount >= 3);
	fmMultigrid_Setup(mg, s.cache->hessian, s.cache->blockInverse, s.cache->fixed,
	                  ++s.cache->hessianVersion, NULL);
	CHECK(mg->denseOk);
	const int n = s.n3;
	double* u = malloc(sizeof(double) * 4 * (size_t)n);
	double *v = u + n, *Bu = u + 2 * n, *Bv = u + 3 * n;
	srand(7);
	for (int trial = 0; trial < 5; ++trial)
	{
		randomFree(n, s.cache->fixed, u);
		randomFree(n, s.cache->fixed, v);
		fmMultigrid_Apply(mg, u, Bu);
		fmMultigrid_Apply(mg, v, Bv);
		double uBv = dot(n, u, Bv), vBu = dot(n, v, Bu);
		double size = sqrt(dot(n, u, u) * dot(n, Bv, Bv));
		CHECK(fabs(uBv - vBu) <= 1e-12 * size);
		CHECK(dot(n, u, Bu) > 0.0);
		bool fixedZero = true;
		for (int k = 0; k < n; ++k)
			fixedZero = fixedZero && (!s.cache->fixed[k] || Bu[k] == 0.0);
		CHECK(fixedZero);
	}
	free(u);
	fmDestroyWorld(s.world);
}

typedef struct fmTestOperator
{
	const fmImplicitCache* cache;
} fmTestOperator;

static void multiply(void* context, const double* x, double* y)
{
	const fmTestOperator* op = context;
	fmBsr_Multiply(&op->cache->pattern, op->cache->hessian, x, y);
}

// CG iterations to solve the system to 1e-8 of the right-hand side (a uniform load).
static int iterations(fmTestSystem* s, fmPreconditioner kind)
{
	fmImplicitCache* c = s->cache;
	const int n = s->n3;
	for (int k = 0; k < n; ++k)
		c->temp[k] = k % 3 == 1 ? -s->body->mesh.mass[k / 3] * 9.8 : 0.0;
	fmPcgPreconditioner pre = {kind, c->blockInverse, &c->pattern, c->hessian, NULL, NULL};
	if (kind == fm_precondMultigrid)
	{
		pre.multigrid = fmSolverCache_Multigrid(c);
		fmMultigrid_Setup(&c->multigrid, c->hessian, c->blockInverse, c->fixed, ++c->hessianVersion,
		                  NULL);
	}
	fmPcgWork work = {c->work, c->work + n, c->work + 2 * n, c->work + 3 * n};
	fmTestOperator op = {c};
	double tolerance = 1e-8 * sqrt(dot(n, c->temp, c->temp));
	fmPcgResult result = fmPcg_Solve(n, multiply, &op, &pre, c->fixed, c->temp, c->direction,
	                                 tolerance, 5000, &work);
	return result.converged ? result.iterations : -1;
}

// Refining the box 64 times in tets (2x in each direction, twice) multiplies the one-level
// preconditioner's iterations by about 5 (more than the diameter's 4: its parts are coupled
// by nothing) and the multigrid's by about 2 (plain aggregation is not fully independent of the
// mesh size, smoothed aggregation would be); the solutions agree.
TEST(iterations_grow_far_slower_with_resolution)
{
	const int cells[3] = {6, 12, 24};
	int sgs[3], mg[3];
	for (int k = 0; k < 3; ++k)
	{
		fmTestSystem s;
		sgs[k] = mg[k] = -1;
		CHECK(makeSystem(&s, cells[k]));
		if (s.cache == NULL)
			continue;
		sgs[k] = iterations(&s, fm_precondSymmetricGaussSeidel);
		double* one = malloc(sizeof(double) * (size_t)s.n3);
		memcpy(one, s.cache->direction, sizeof(double) * (size_t)s.n3);
		mg[k] = iterations(&s, fm_precondMultigrid);
		double difference = 0.0, size = 0.0;
		for (int i = 0; i < s.n3; ++i)
		{
			difference = fmax(difference, fabs(one[i] - s.cache->direction[i]));
			size = fmax(size, fabs(one[i]));
		}
		CHECK(difference <= 1e-6 * size);
		free(one);
		printf("  %2d^3 cells (%5d vertices): CG iterations, symmetric Gauss-Seidel %3d, "
		       "multigrid %3d\n",
		       cells[k], s.body->mesh.vertexCount, sgs[k], mg[k]);
		fmDestroyWorld(s.world);
	}
	CHECK(sgs[0] > 0 && mg[0] > 0 && sgs[2] > 0 && mg[2] > 0);
	CHECK(sgs[2] >= 4 * sgs[0]); // the one-level method degrades (the test can tell)
	// The multigrid's growth is at most half the one-level method's, and it needs at most a
	// third of the iterations at the finest mesh.
	CHECK(2 * mg[2] * sgs[0] <= sgs[2] * mg[0]);
	CHECK(3 * mg[2] <= sgs[2]);
}
