// Vertex block descent (vbd.h).
#include "solver/vbd.h"

#include "core/core.h"
#include "fem/forces.h"
#include "material/material.h"

#include <float.h>
#include <math.h>
#include <string.h>

// Sweeps a step may take at most, over its Newton iteration limit (one sweep moves every vertex
// once: far less than a Newton iteration does).
#define FM_VBD_SWEEPS_PER_NEWTON 20

// Greedy vertex colours (no two vertices of a tet share one), the vertices sorted by colour:
// order[start[c] .. start[c + 1]) has colour c. Returns the colour count, 0 when short of memory
// or when 64 colours are not enough.
static int fmVbdColour(const fmElasticMesh* mesh, int* order, int* start, int capacity)
{
	int* colour = FM_ALLOC_ARRAY(int, mesh->vertexCount);
	if (colour == NULL)
		return 0;
	int count = 0;
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		uint64_t taken = 0;
		for (int k = mesh->vertexTetStart[i]; k < mesh->vertexTetStart[i + 1]; ++k)
		{
			const int* n = mesh->tets + 4 * (mesh->vertexTets[k] / 4);
			for (int a = 0; a < 4; ++a)
				if (n[a] < i)
					taken |= (uint64_t)1 << (colour[n[a]] & 63);
		}
		int c = 0;
		while (c < 64 && (taken >> c & 1u))
			++c;
		if (c == 64) // more than 64 colours: the caller sweeps serially
		{
			FM_FREE_ARRAY(colour, int, mesh->vertexCount);
			return 0;
		}
		colour[i] = c;
		count = c + 1 > count ? c + 1 : count;
	}
	count = count < capacity ? count : capacity;
	memset(start, 0, sizeof(int) * (size_t)(count + 1));
	for (int i = 0; i < mesh->vertexCount; ++i)
		start[colour[i] + 1] += 1;
	for (int c = 0; c < count; ++c)
		start[c + 1] += start[c];
	int* next = FM_ALLOC_ARRAY(int, count);
	if (next != NULL)
	{
		memcpy(next, start, sizeof(int) * (size_t)count);
		for (int i = 0; i < mesh->vertexCount; ++i)
			order[next[colour[i]]++] = i;
	}
	FM_FREE_ARRAY(next, int, count);
	FM_FREE_ARRAY(colour, int, mesh->vertexCount);
	return next != NULL ? count : 0;
}

// The gradient g (3) and projected Hessian H (9) of the potential in vertex i's position.
static void fmVbdVertexSystem(const fmElasticMesh* mesh, fmBodyState* state,
                              const fmImplicitCache* c, const fmNewtonProblem* pb, int i,
                              double g[3], double H[9])
{
	const double m = mesh->mass[i], w = pb->inertia + pb->massDamping;
	const double grav[3] = {pb->gravity.x, pb->gravity.y, pb->gravity.z};
	memset(H, 0, 9 * sizeof(double));
	for (int k = 0; k < 3; ++k)
	{
		double x = state->x[3 * i + k];
		g[k] = m * (pb->inertia * (x - c->xPred[3 * i + k]) +
		            pb->massDamping * (x - c->xStart[3 * i + k]) - grav[k]);
		H[4 * k] = m * w;
	}
	for (int e = mesh->vertexTetStart[i]; e < mesh->vertexTetStart[i + 1]; ++e)
	{
		int t = mesh->vertexTets[e] / 4, a = mesh->vertexTets[e] % 4;
		fmMat3 F = fmTetDeformation(mesh, state->x, t), P;
		double dPdF[81];
		fmTetEvaluate(mesh, t, &F, &P, dPdF, true);
		const fmMat3* D = &mesh->DmInv[t];
		double ga[3];
		for (int j = 0; j < 3; ++j) // g_a: row a - 1 of Dm^-1, g_0 = minus their sum
			ga[j] = a > 0 ? D->m[3 * (a - 1) + j] : -(D->m[j] + D->m[3 + j] + D->m[6 + j]);
		const double V0 = mesh->restVolume[t];
		for (int r = 0; r < 3; ++r)
		{
			g[r] += V0 * (P.m[3 * r] * ga[0] + P.m[3 * r + 1] * ga[1] + P.m[3 * r + 2] * ga[2]);
			for (int s = 0; s < 3; ++s)
			{
				double sum = 0.0;
				for (int j = 0; j < 3; ++j)
					for (int l = 0; l < 3; ++l)
						sum += dPdF[9 * (3 * r + j) + (3 * s + l)] * ga[j] * ga[l];
				H[3 * r + s] += V0 * sum;
			}
		}
	}
}

// Vertex i's step when the floor stops it: y at the bound, and with Coulomb friction x and z
// minimising the vertex's quadratic model with y held there (the 2x2 system of its x, z rows);
// with stick friction x and z stay.
static fmVec3 fmVbdOnFloor(const fmBodyState* state, const fmNewtonProblem* pb, int i,
                           const double g[3], const double H[9], double bound)
{
	fmVec3 x = fmLoad(state->x, i);
	double dy = bound - x.y;
	x.y = bound;
	if (pb->floor->friction == fm_floorStick)
		return x;
	// [Hxx Hxz; Hzx Hzz] d = -(g_xz + H_xz,y dy), pinned axes already decoupled (identity rows).
	double rx = -(g[0] + H[1] * dy), rz = -(g[2] + H[7] * dy);
	double det = H[0] * H[8] - H[2] * H[6];
	if (!(fabs(det) > 0.0))
		return x;
	x.x += (H[8] * rx - H[2] * rz) / det;
	x.z += (H[0] * rz - H[6] * rx) / det;
	return x;
}

// Move vertex i by its 3x3 Newton step, its pinned axes held, the floor as a bound on y (a
// vertex the floor stops keeps its tangential place with stick friction).
static void fmVbdMoveVertex(const fmElasticMesh* mesh, fmBodyState* state, const fmImplicitCache* c,
                            const fmNewtonProblem* pb, int i)
{
	double g[3], H[9];
	fmVbdVertexSystem(mesh, state, c, pb, i, g, H);
	for (int k = 0; k < 3; ++k)
		if (fmIsDofPinned(state, 3 * i + k))
		{
			g[k] = 0.0;
			for (int j = 0; j < 3; ++j)
				H[3 * k + j] = H[3 * j + k] = (j == k) ? 1.0 : 0.0;
		}
	fmMat3 A, Ainv;
	memcpy(A.m, H, sizeof A.m);
	if (!fmInverse(&A, &Ainv))
		return;
	fmVec3 step = fmScale(-1.0, fmMatVec(&Ainv, fmMakeVec3(g[0], g[1], g[2])));
	fmVec3 x = fmAdd(fmLoad(state->x, i), step);
	if (pb->floor && !(state->pinned[i] & FM_PIN_Y) && x.y < c->floorBound[i])
		x = fmVbdOnFloor(state, pb, i, g, H, c->floorBound[i]);
	fmStore(state->x, i, x);
}

typedef struct fmVbdColourTask
{
	const fmElasticMesh* mesh;
	fmBodyState* state;
	const fmImplicitCache* cache;
	const fmNewtonProblem* problem;
	const int* vertices;
} fmVbdColourTask;

static void fmVbdColourRange(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmVbdColourTask* t = context;
	for (int k = start; k < end; ++k)
		if (t->state->pinned[t->vertices[k]] != FM_PIN_ALL)
			fmVbdMoveVertex(t->mesh, t->state, t->cache, t->problem, t->vertices[k]);
}

fmNewtonResult fmVbd_Solve(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* c,
                           const fmNewtonProblem* pb)
{
	fmNewtonResult result;
	memset(&result, 0, sizeof result);
	result.finite = true;
	int* order = FM_ALLOC_ARRAY(int, mesh->vertexCount);
	int start[65];
	int colours = order ? fmVbdColour(mesh, order, start, 64) : 0;
	const fmTaskSystem* tasks = pb->tasks;
	if (order != NULL && colours == 0) // one colour in vertex order, on one worker
	{
		for (int i = 0; i < mesh->vertexCount; ++i)
			order[i] = i;
		start[0] = 0, start[1] = mesh->vertexCount, colours = 1, tasks = NULL;
	}
	const int maxSweeps = pb->maxNewton * FM_VBD_SWEEPS_PER_NEWTON;
	for (;;)
	{
		result.residual = fmNewton_Residual(mesh, state, c, pb, state->x);
		if (!isfinite(result.residual))
		{
			result.finite = false;
			break;
		}
		if (result.residual <= pb->tolerance)
		{
			result.converged = true;
			break;
		}
		if (colours == 0 || result.iterations >= maxSweeps)
			break;
		// One sweep: the colours in turn; a colour's vertices share no tet, so they move
		// independently (on the workers; the same bits for any count).
		for (int k = 0; k < colours; ++k)
		{
			fmVbdColourTask task = {mesh, state, c, pb, order + start[k]};
			fmParallelFor(tasks, start[k + 1] - start[k], FM_PARALLEL_MIN_RANGE / 16,
			              fmVbdColourRange, &task);
		}
		result.iterations += 1;
	}
	FM_FREE_ARRAY(order, int, mesh->vertexCount);
	return result;
}
