// The implicit and static solvers' per-body cache: the block-sparse pattern of the Newton
// matrix with the slot of every element block, the vectors of a solve, and the assembly of
// element stiffness and spring damping into it (solver_cache.h).
#include "solver/solver_cache.h"

#include "core/core.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/nodal_pressure.h"

#include <math.h>

// Block rows a range of the parallel assembly takes at least: a tet's Hessian costs about a
// microsecond, so 1024 rows (some 6000 tets) are worth a worker's wake-up many times over.
#define FM_STIFFNESS_MIN_ROWS 1024
#include <string.h>

void fmSolverCache_Free(void* memory)
{
	fmImplicitCache* c = memory;
	if (c == NULL)
		return;
	size_t n3 = 3 * (size_t)c->vertexCount, blocks = (size_t)c->pattern.blocks;
	FM_FREE_ARRAY(c->tetSlot, int, 16 * (size_t)c->tetCount);
	FM_FREE_ARRAY(c->edgeSlot, int, 4 * (size_t)c->edgeCount);
	FM_FREE_ARRAY(c->hessian, double, 9 * blocks);
	FM_FREE_ARRAY(c->damping, double, 9 * blocks);
	FM_FREE_ARRAY(c->hessianBase, double, 9 * blocks);
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
	FM_FREE_ARRAY(c->forcesX, double, n3);
	FM_FREE_ARRAY(c->spare.forces, double, n3);
	FM_FREE_ARRAY(c->spare.x, double, n3);
	if (c->multigridBuilt)
		fmMultigrid_Free(&c->multigrid);
	fmBsr_Free(&c->pattern);
	FM_FREE_ARRAY(c, fmImplicitCache, 1);
}

// Slots of every node pair of every tet (and of every spring), so that refilling the matrix
// is a plain scatter in tet order (deterministic, no search).
static bool fmBuildSlots(const fmElasticMesh* mesh, fmImplicitCache* c)
{
	for (int t = 0; t < mesh->tetCount; ++t)
		for (int a = 0; a < 4; ++a)
			for (int d = 0; d < 4; ++d)
				c->tetSlot[16 * t + 4 * a + d] =
				    fmBsr_Find(&c->pattern, mesh->tets[4 * t + a], mesh->tets[4 * t + d]);
	for (int e = 0; e < c->edgeCount; ++e)
	{
		int p = mesh->edges[2 * e], q = mesh->edges[2 * e + 1];
		c->edgeSlot[4 * e + 0] = fmBsr_Find(&c->pattern, p, p);
		c->edgeSlot[4 * e + 1] = fmBsr_Find(&c->pattern, p, q);
		c->edgeSlot[4 * e + 2] = fmBsr_Find(&c->pattern, q, p);
		c->edgeSlot[4 * e + 3] = fmBsr_Find(&c->pattern, q, q);
		if (c->edgeSlot[4 * e + 1] < 0)
			return false; // springs are tet edges, so this cannot happen
	}
	return true;
}

fmImplicitCache* fmSolverCache_Get(fmImplicitCache** slot, const fmElasticMesh* mesh)
{
	if (*slot)
		return *slot;
	fmImplicitCache* c = FM_ALLOC_ZERO(fmImplicitCache, 1);
	if (c == NULL)
		return NULL;
	*slot = c;
	c->vertexCount = mesh->vertexCount;
	c->tetCount = mesh->tetCount;
	c->edgeCount = mesh->forceModel == fm_massSpring ? mesh->edgeCount : 0;
	for (int t = 0; t < mesh->tetCount; ++t)
		c->volume += mesh->restVolume[t];
	size_t n3 = 3 * (size_t)mesh->vertexCount;
	bool ok = fmBsr_Build(&c->pattern, mesh->vertexCount, mesh->tets, mesh->tetCount);
	if (ok && fmNodalPressure_On(mesh)) // a patch couples every pair of its vertices
		ok = fmBsr_Square(&c->pattern);
	if (!ok)
		c->pattern.blocks = 0;
	c->tetSlot = FM_ALLOC_ARRAY(int, 16 * (size_t)c->tetCount);
	c->edgeSlot = FM_ALLOC_ARRAY(int, 4 * (size_t)c->edgeCount);
	c->hessian = FM_ALLOC_ZERO(double, 9 * (size_t)c->pattern.blocks);
	c->blockInverse = FM_ALLOC_ZERO(double, 9 * (size_t)mesh->vertexCount);
	c->xPred = FM_ALLOC_ZERO(double, n3);
	c->xStart = FM_ALLOC_ZERO(double, n3);
	c->gradient = FM_ALLOC_ZERO(double, n3);
	c->direction = FM_ALLOC_ZERO(double, n3);
	c->trial = FM_ALLOC_ZERO(double, n3);
	c->forces = FM_ALLOC_ZERO(double, n3);
	c->temp = FM_ALLOC_ZERO(double, n3);
	c->work = FM_ALLOC_ZERO(double, 4 * n3);
	c->fixed = FM_ALLOC_ZERO(uint8_t, n3);
	c->floorBound = FM_ALLOC_ZERO(double, (size_t)mesh->vertexCount);
	c->best = FM_ALLOC_ZERO(double, n3);
	c->forcesX = FM_ALLOC_ZERO(double, n3);
	c->spare.forces = FM_ALLOC_ZERO(double, n3);
	c->spare.x = FM_ALLOC_ZERO(double, n3);
	ok = ok && c->tetSlot && (c->edgeSlot || c->edgeCount == 0) && c->hessian && c->blockInverse &&
	     c->xPred && c->xStart && c->gradient && c->direction && c->trial && c->forces && c->temp &&
	     c->work && c->fixed && c->floorBound && c->best && c->forcesX && c->spare.forces &&
	     c->spare.x;
	if (ok)
		ok = fmBuildSlots(mesh, c);
	if (!ok)
	{
		fmSolverCache_Free(c);
		*slot = NULL;
		return NULL;
	}
	return c;
}

fmMultigrid* fmSolverCache_Multigrid(fmImplicitCache* c)
{
	if (!c->multigridBuilt)
		c->multigridBuilt = c->pattern.rows > 0 && fmMultigrid_Build(&c->multigrid, &c->pattern);
	return c->multigridBuilt ? &c->multigrid : NULL;
}

double* fmSolverCache_Base(fmImplicitCache* c)
{
	if (c->hessianBase == NULL)
		c->hessianBase = FM_ALLOC_ARRAY(double, 9 * (size_t)c->pattern.blocks);
	return c->hessianBase;
}

// Only FEM bodies with a built-in model: their energy is summed the same way by every force
// pass (FVM forces come from another loop; a user energy's parameters may change unseen).
static bool fmForcesMemoizable(const fmElasticMesh* mesh)
{
	for (int k = 0; k < mesh->materialCount; ++k)
		if (mesh->materials[k].model == fm_stretchEnergy ||
		    mesh->materials[k].model == fm_invariantEnergy)
			return false;
	return mesh->forceModel == fm_fem && mesh->material.model != fm_stretchEnergy &&
	       mesh->material.model != fm_invariantEnergy;
}

static bool fmSameMaterial(const fmMaterial* a, const fmMaterial* b)
{
	return a->model == b->model && a->lambda == b->lambda && a->mu == b->mu && a->c01 == b->c01 &&
	       memcmp(&a->orthotropy, &b->orthotropy, sizeof a->orthotropy) == 0 &&
	       a->fibreStiffness == b->fibreStiffness &&
	       memcmp(&a->fibre, &b->fibre, sizeof a->fibre) == 0 &&
	       memcmp(&a->sheet, &b->sheet, sizeof a->sheet) == 0;
}

bool fmSolverCache_HasForcesAt(const fmElasticMesh* mesh, const fmImplicitCache* c, const double* x)
{
	return c->forcesValid && fmForcesMemoizable(mesh) &&
	       fmSameMaterial(&c->forcesMaterial, &mesh->material) &&
	       memcmp(c->forcesX, x, sizeof(double) * 3 * (size_t)mesh->vertexCount) == 0;
}

void fmSolverCache_NoteForces(const fmElasticMesh* mesh, fmImplicitCache* c, const double* x,
                              double psi)
{
	c->forcesValid = fmForcesMemoizable(mesh);
	if (!c->forcesValid)
		return;
	memcpy(c->forcesX, x, sizeof(double) * 3 * (size_t)mesh->vertexCount);
	c->forcesEnergy = psi;
	c->forcesMaterial = mesh->material;
}

void fmSolverCache_RestMoved(fmImplicitCache* c)
{
	c->forcesValid = false;
	c->spare.valid = false;
	c->hessianValid = false;
	c->hessianBaseValid = false;
}

void fmSolverCache_SwapForces(fmImplicitCache* c)
{
	fmForcesMemo last = {c->forces, c->forcesX, c->forcesEnergy, c->forcesMaterial, c->forcesValid};
	c->forces = c->spare.forces;
	c->forcesX = c->spare.x;
	c->forcesEnergy = c->spare.energy;
	c->forcesMaterial = c->spare.material;
	c->forcesValid = c->spare.valid;
	c->spare = last;
}

void fmSolverCache_ForcesAtPositions(const fmElasticMesh* mesh, fmImplicitCache* c, const double* x,
                                     const fmTaskSystem* tasks, fmArena* arena)
{
	if (fmSolverCache_HasForcesAt(mesh, c, x))
		return;
	memset(c->forces, 0, sizeof(double) * 3 * (size_t)mesh->vertexCount);
	fmSolverCache_NoteForces(mesh, c, x, fmAddElasticForcesOn(mesh, x, c->forces, tasks, arena));
}

// One tet's 16 blocks, times scale, into the rows [first, end) of the matrix.
static void fmScatterTet(const fmElasticMesh* mesh, const fmImplicitCache* c, int t,
                         const double* K, double scale, int first, int end, double* values)
{
	for (int p = 0; p < 4; ++p)
	{
		int row = mesh->tets[4 * t + p];
		if (row < first || row >= end)
			continue;
		for (int q = 0; q < 4; ++q)
		{
			double* block = values + 9 * (size_t)c->tetSlot[16 * t + 4 * p + q];
			for (int r = 0; r < 3; ++r)
				for (int s = 0; s < 3; ++s)
					block[3 * r + s] += scale * K[12 * (3 * p + r) + (3 * q + s)];
		}
	}
}

typedef struct fmStiffnessTask
{
	const fmElasticMesh* mesh;
	const fmImplicitCache* cache;
	const double* x;
	double scale;
	int project;
	double* values;
} fmStiffnessTask;

// The block rows [start, end): every tet with a node among them, in tet order, adds the blocks
// of those rows only. Each block gets its tets' terms in tet order, as in a serial loop, so any
// split into ranges gives the same bits (a tet across two ranges is evaluated by both).
static void fmStiffnessRowsTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmStiffnessTask* k = context;
	const fmElasticMesh* mesh = k->mesh;
	int first = mesh->tetCount, last = -1;
	for (int i = start; i < end; ++i)
		if (mesh->vertexTetStart[i + 1] > mesh->vertexTetStart[i])
		{
			int lo = mesh->vertexTets[mesh->vertexTetStart[i]] / 4;
			int hi = mesh->vertexTets[mesh->vertexTetStart[i + 1] - 1] / 4;
			first = lo < first ? lo : first;
			last = hi > last ? hi : last;
		}
	double K[144];
	for (int t = first; t <= last; ++t)
	{
		const int* n = mesh->tets + 4 * t;
		bool mine = false;
		for (int p = 0; p < 4; ++p)
			mine = mine || (n[p] >= start && n[p] < end);
		if (!mine)
			continue;
		fmTetHessian(mesh, k->x, t, K, k->project);
		fmScatterTet(mesh, k->cache, t, K, k->scale, start, end, k->values);
	}
}

static void fmAddSpringStiffness(const fmElasticMesh* mesh, const fmImplicitCache* c,
                                 const double* x, double scale, int project, double* values)
{
	double K[36];
	for (int e = 0; e < c->edgeCount; ++e)
	{
		fmSpringHessian(mesh, x, e, K, project);
		for (int p = 0; p < 2; ++p)
			for (int q = 0; q < 2; ++q)
			{
				double* block = values + 9 * (size_t)c->edgeSlot[4 * e + 2 * p + q];
				for (int r = 0; r < 3; ++r)
					for (int s = 0; s < 3; ++s)
						block[3 * r + s] += scale * K[6 * (3 * p + r) + (3 * q + s)];
			}
	}
}

typedef struct fmNodalAssembly
{
	const fmBsrMatrix* pattern;
	double scale;
	double* values;
} fmNodalAssembly;

// A block of the nodal pressure's Hessian into its slot of the square pattern.
static void fmAddNodalBlock(void* context, int row, int column, const double block[9])
{
	fmNodalAssembly* a = context;
	int slot = fmBsr_Find(a->pattern, row, column);
	FM_ASSERT(slot >= 0); // the pattern is the tet graph's square (fmSolverCache_Get)
	double* to = a->values + 9 * (size_t)slot;
	for (int r = 0; r < 9; ++r)
		to[r] += a->scale * block[r];
}

// values += scale * (PSD-projected) elastic Hessian at x, element by element in a fixed order:
// by block rows on the world's workers (the same bits for any number of them).
void fmSolverCache_AddStiffness(const fmElasticMesh* mesh, const fmImplicitCache* c,
                                const double* x, double scale, int project, double* values,
                                const fmTaskSystem* tasks)
{
	if (mesh->forceModel == fm_massSpring)
	{
		fmAddSpringStiffness(mesh, c, x, scale, project, values);
		return;
	}
	fmStiffnessTask task = {mesh, c, x, scale, project, values};
	fmParallelFor(tasks, mesh->vertexCount, FM_STIFFNESS_MIN_ROWS, fmStiffnessRowsTask, &task);
	if (fmNodalPressure_On(mesh)) // then the patches' terms, serially (the same bits)
	{
		fmNodalAssembly assembly = {&c->pattern, scale, values};
		fmNodalPressure_VisitHessian(mesh, x, project, fmAddNodalBlock, &assembly);
	}
}

// Spring damping as a matrix: each spring resists the rate of change of its length with
// c = 2 zeta sqrt(k / (1/ma + 1/mb)) (force_spring.c), i.e. the block c n n^T on [a, b].
void fmSolverCache_AddSpringDamping(const fmElasticMesh* mesh, const double* invMass,
                                    const fmImplicitCache* c, const double* x, double scale,
                                    double* values)
{
	for (int e = 0; e < c->edgeCount; ++e)
	{
		fmVec3 direction;
		double coefficient = fmSpringDashpot(mesh, invMass, x, e, &direction);
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

double fmSolverCache_Energy(const fmElasticMesh* mesh, const fmImplicitCache* cache,
                            const double* x, const fmTaskSystem* tasks, fmArena* arena)
{
	if (cache != NULL && fmSolverCache_HasForcesAt(mesh, cache, x))
		return cache->forcesEnergy;
	return fmElasticEnergyOn(mesh, x, tasks, arena);
}
