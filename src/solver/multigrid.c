// Aggregation multigrid for the Newton systems (multigrid.h). Plain (unsmoothed) aggregation
// on the vertex graph: each aggregate is a vertex and its free neighbours (Vanek, Mandel and
// Brezina's first pass), stragglers join a neighbouring aggregate; the prolongation copies an
// aggregate's 3 DOFs to each of its vertices, so the Galerkin matrix P^T A P is a sum of
// blocks. The V-cycle smooths with the same partwise block Gauss-Seidel as the one-level
// preconditioner (pcg.c): forward on the way down, backward on the way up, so the cycle is a
// symmetric operator that CG can use.
#include "solver/multigrid.h"

#include "core/core.h"

#include <math.h>
#include <string.h>

// The coarse correction is scaled by this factor (over-correction: piecewise-constant
// prolongation underestimates the energy of the smooth errors it corrects; Blaheta 1986).
// The factor is chosen by measurement (docs/implicit.md, multigrid).
#define FM_MG_OVERCORRECTION 1.5

// A coarse level must have at most this fraction of the rows above it, or coarsening stops.
#define FM_MG_MIN_REDUCTION 0.75

// Rows a range of the parallel residual takes at least.
#define FM_MG_MIN_RANGE 1024

static void fmMgFreeLevel(fmMgLevel* L, bool coarse)
{
	size_t rows = (size_t)L->pattern.rows, blocks = (size_t)L->pattern.blocks;
	FM_FREE_ARRAY(L->coarseValues, double, 9 * blocks);
	FM_FREE_ARRAY(L->blockInverse, double, 9 * rows);
	FM_FREE_ARRAY(L->ownFixed, uint8_t, 3 * rows);
	FM_FREE_ARRAY(L->aggregate, int, rows);
	FM_FREE_ARRAY(L->coarseSlot, int, blocks);
	FM_FREE_ARRAY(L->r, double, 3 * rows);
	FM_FREE_ARRAY(L->z, double, 3 * rows);
	FM_FREE_ARRAY(L->t, double, 3 * rows);
	FM_FREE_ARRAY(L->q, double, 3 * rows);
	FM_FREE_ARRAY(L->w, double, 3 * rows);
	if (coarse)
		fmBsr_Free(&L->pattern);
	memset(L, 0, sizeof *L);
}

void fmMultigrid_Free(fmMultigrid* mg)
{
	size_t dense = 3 * (size_t)mg->denseRows;
	FM_FREE_ARRAY(mg->dense, double, dense* dense);
	FM_FREE_ARRAY(mg->setupFixed, uint8_t, 3 * (size_t)mg->level[0].pattern.rows);
	for (int l = 0; l < mg->levelCount; ++l)
		fmMgFreeLevel(&mg->level[l], l > 0);
	memset(mg, 0, sizeof *mg);
}

// Aggregates of a graph (the pattern's rows and columns), deterministic in row order. Returns
// the number of aggregates.
static int fmMgAggregate(const fmBsrMatrix* m, int* aggregate, int* firstPass)
{
	int count = 0;
	for (int i = 0; i < m->rows; ++i)
		aggregate[i] = -1;
	// 1. A vertex none of whose neighbours is taken starts an aggregate of itself and them.
	for (int i = 0; i < m->rows; ++i)
	{
		bool free = aggregate[i] < 0;
		for (int k = m->rowStart[i]; free && k < m->rowStart[i + 1]; ++k)
			free = aggregate[m->columns[k]] < 0;
		if (!free)
			continue;
		for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
			aggregate[m->columns[k]] = count;
		count += 1;
	}
	// 2. A vertex left over joins the first aggregate of pass 1 among its neighbours.
	memcpy(firstPass, aggregate, sizeof(int) * (size_t)m->rows);
	for (int i = 0; i < m->rows; ++i)
		for (int k = m->rowStart[i]; aggregate[i] < 0 && k < m->rowStart[i + 1]; ++k)
			aggregate[i] = firstPass[m->columns[k]];
	// 3. (Only a vertex whose neighbours were all left over: a lone one.) Its own aggregate.
	for (int i = 0; i < m->rows; ++i)
		if (aggregate[i] < 0)
			aggregate[i] = count++;
	return count;
}

// The pattern of P^T A P: aggregates I and J are coupled when a row of I has a column in J.
// @p members lists the rows of each aggregate (CSR in memberStart); @p scratch holds at least
// the largest sum of row lengths over an aggregate's members.
static int fmMgCoarseRows(const fmBsrMatrix* m, const int* aggregate, int coarse,
                          const int* memberStart, const int* members, int* scratch, int* rowStart,
                          int* columns)
{
	int total = 0;
	for (int I = 0; I < coarse; ++I)
	{
		int count = 0;
		for (int p = memberStart[I]; p < memberStart[I + 1]; ++p)
			for (int k = m->rowStart[members[p]]; k < m->rowStart[members[p] + 1]; ++k)
				scratch[count++] = aggregate[m->columns[k]];
		int unique = fmSortUnique(scratch, count);
		if (columns)
			memcpy(columns + total, scratch, sizeof(int) * (size_t)unique);
		if (rowStart)
			rowStart[I + 1] = total + unique;
		total += unique;
	}
	return total;
}

// The next level's pattern and the fine blocks' slots in it.
static bool fmMgCoarsen(const fmMgLevel* fine, int coarse, fmMgLevel* next)
{
	const fmBsrMatrix* m = &fine->pattern;
	int* memberStart = FM_ALLOC_ZERO(int, (size_t)coarse + 1);
	int* members = FM_ALLOC_ARRAY(int, m->rows);
	int* fill = FM_ALLOC_ARRAY(int, coarse);
	bool ok = memberStart && members && fill;
	int longest = 0;
	if (ok)
	{
		for (int i = 0; i < m->rows; ++i)
			memberStart[fine->aggregate[i] + 1] += 1;
		for (int I = 0; I < coarse; ++I)
			memberStart[I + 1] += memberStart[I];
		memcpy(fill, memberStart, sizeof(int) * (size_t)coarse);
		for (int i = 0; i < m->rows; ++i)
			members[fill[fine->aggregate[i]]++] = i;
		for (int I = 0; I < coarse; ++I)
		{
			int length = 0;
			for (int p = memberStart[I]; p < memberStart[I + 1]; ++p)
				length += m->rowStart[members[p] + 1] - m->rowStart[members[p]];
			longest = length > longest ? length : longest;
		}
	}
	int* scratch = ok ? FM_ALLOC_ARRAY(int, (size_t)longest + 1) : NULL;
	fmBsrMatrix* c = &next->pattern;
	ok = ok && scratch;
	if (ok)
	{
		c->rows = coarse;
		c->blocks =
		    fmMgCoarseRows(m, fine->aggregate, coarse, memberStart, members, scratch, NULL, NULL);
		c->rowStart = FM_ALLOC_ZERO(int, (size_t)coarse + 1);
		c->columns = FM_ALLOC_ARRAY(int, c->blocks);
		c->diagonal = FM_ALLOC_ARRAY(int, coarse);
		ok = c->rowStart && c->columns && c->diagonal;
	}
	if (ok)
	{
		fmMgCoarseRows(m, fine->aggregate, coarse, memberStart, members, scratch, c->rowStart,
		               c->columns);
		for (int I = 0; I < coarse; ++I)
			c->diagonal[I] = fmBsr_Find(c, I, I);
		for (int i = 0; i < m->rows; ++i)
			for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
				fine->coarseSlot[k] =
				    fmBsr_Find(c, fine->aggregate[i], fine->aggregate[m->columns[k]]);
	}
	FM_FREE_ARRAY(scratch, int, (size_t)longest + 1);
	FM_FREE_ARRAY(memberStart, int, (size_t)coarse + 1);
	FM_FREE_ARRAY(members, int, m->rows);
	FM_FREE_ARRAY(fill, int, coarse);
	return ok;
}

// A level's own arrays: block inverses and residual scratch for all; aggregates and slots for
// those with a level below; matrix values, fixed flags and vectors for the coarse ones.
static bool fmMgAllocLevel(fmMgLevel* L, bool coarse, bool hasNext)
{
	size_t rows = (size_t)L->pattern.rows, blocks = (size_t)L->pattern.blocks;
	L->blockInverse = FM_ALLOC_ZERO(double, 9 * rows);
	L->t = FM_ALLOC_ZERO(double, 3 * rows);
	bool ok = L->blockInverse && L->t;
	if (hasNext)
	{
		L->aggregate = FM_ALLOC_ARRAY(int, rows);
		L->coarseSlot = FM_ALLOC_ARRAY(int, blocks);
		ok = ok && L->aggregate && L->coarseSlot;
	}
	if (coarse)
	{
		L->coarseValues = FM_ALLOC_ZERO(double, 9 * blocks);
		L->ownFixed = FM_ALLOC_ZERO(uint8_t, 3 * rows);
		L->r = FM_ALLOC_ZERO(double, 3 * rows);
		L->z = FM_ALLOC_ZERO(double, 3 * rows);
		L->q = FM_ALLOC_ZERO(double, 3 * rows);
		L->w = FM_ALLOC_ZERO(double, 3 * rows);
		L->values = L->coarseValues;
		L->fixed = L->ownFixed;
		ok = ok && L->coarseValues && L->ownFixed && L->r && L->z && L->q && L->w;
	}
	return ok;
}

// Aggregate level l into level l + 1 if that pays; false when memory is short.
static bool fmMgAddLevel(fmMultigrid* mg, bool* added)
{
	*added = false;
	fmMgLevel* L = &mg->level[mg->levelCount - 1];
	int rows = L->pattern.rows;
	if (rows <= FM_MG_COARSE_ROWS || mg->levelCount == FM_MG_MAX_LEVELS)
		return true;
	int* aggregate = FM_ALLOC_ARRAY(int, rows);
	int* firstPass = FM_ALLOC_ARRAY(int, rows);
	if (aggregate == NULL || firstPass == NULL)
	{
		FM_FREE_ARRAY(aggregate, int, rows);
		FM_FREE_ARRAY(firstPass, int, rows);
		return false;
	}
	int coarse = fmMgAggregate(&L->pattern, aggregate, firstPass);
	FM_FREE_ARRAY(firstPass, int, rows);
	bool ok = true;
	if (coarse <= FM_MG_MIN_REDUCTION * rows)
	{
		L->aggregate = aggregate;
		L->coarseSlot = FM_ALLOC_ARRAY(int, L->pattern.blocks);
		aggregate = NULL;
		fmMgLevel* next = &mg->level[mg->levelCount];
		ok = L->coarseSlot && fmMgCoarsen(L, coarse, next);
		mg->levelCount += 1; // (so that Free releases whatever next holds)
		ok = ok && fmMgAllocLevel(next, true, false);
		*added = ok;
	}
	FM_FREE_ARRAY(aggregate, int, rows);
	return ok;
}

bool fmMultigrid_Build(fmMultigrid* mg, const fmBsrMatrix* fine)
{
	memset(mg, 0, sizeof *mg);
	mg->level[0].pattern = *fine;
	mg->levelCount = 1;
	bool ok = fmMgAllocLevel(&mg->level[0], false, false);
	mg->setupFixed = FM_ALLOC_ARRAY(uint8_t, 3 * (size_t)fine->rows);
	ok = ok && mg->setupFixed != NULL;
	for (bool added = true; ok && added;)
		ok = fmMgAddLevel(mg, &added);
	mg->denseRows = mg->level[mg->levelCount - 1].pattern.rows;
	if (mg->denseRows > 2 * FM_MG_COARSE_ROWS)
		mg->denseRows = 0; // coarsening stalled: the bottom gets Gauss-Seidel instead
	size_t dense = 3 * (size_t)mg->denseRows;
	if (ok && dense > 0)
	{
		mg->dense = FM_ALLOC_ZERO(double, dense* dense);
		ok = mg->dense != NULL;
	}
	if (!ok)
	{
		mg->level[0].pattern = (fmBsrMatrix){0}; // not ours to free
		fmMultigrid_Free(mg);
	}
	return ok;
}

size_t fmMultigrid_EstimateBytes(size_t rows, size_t blocks)
{
	// Level 0: block inverses, a vector, aggregates and slots. Coarser levels together hold
	// fewer rows and blocks than level 0 (each aggregate holds a vertex and its neighbours),
	// each with values, a pattern, block inverses, flags and three vectors.
	size_t fine =
	    rows * (9 * sizeof(double) + 3 * sizeof(double) + sizeof(int) + 3) + blocks * sizeof(int);
	size_t coarse = blocks * (9 * sizeof(double) + sizeof(int)) +
	                rows * (15 * sizeof(double) + 3 + 3 * sizeof(int) + 9 * sizeof(double));
	size_t dense = 3 * 2 * (size_t)FM_MG_COARSE_ROWS;
	return fine + coarse + dense * dense * sizeof(double) + sizeof(fmMultigrid);
}

// Level l + 1 = P^T A_l P over the free DOFs: fine block (i, j) adds its free entries into
// block (I, J) in the fine blocks' order (deterministic); a coarse DOF none of whose fine DOFs
// is free is fixed.
static void fmMgGalerkin(const fmMgLevel* L, fmMgLevel* next)
{
	const fmBsrMatrix* m = &L->pattern;
	memset(next->coarseValues, 0, sizeof(double) * 9 * (size_t)next->pattern.blocks);
	memset(next->ownFixed, 1, 3 * (size_t)next->pattern.rows);
	for (int i = 0; i < m->rows; ++i)
	{
		const uint8_t* fi = L->fixed + 3 * i;
		for (int e = 0; e < 3; ++e)
			if (!fi[e])
				next->ownFixed[3 * L->aggregate[i] + e] = 0;
		for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
		{
			const uint8_t* fj = L->fixed + 3 * m->columns[k];
			const double* a = L->values + 9 * (size_t)k;
			double* c = next->coarseValues + 9 * (size_t)L->coarseSlot[k];
			for (int e = 0; e < 3; ++e)
				for (int f = 0; f < 3; ++f)
					if (!fi[e] && !fj[f])
						c[3 * e + f] += a[3 * e + f];
		}
	}
}

static void fmMgInvertDiagonal(fmMgLevel* L)
{
	const fmBsrMatrix* m = &L->pattern;
	for (int i = 0; i < m->rows; ++i)
		fmBsr_InvertDiagonalBlocks(1, L->values + 9 * (size_t)m->diagonal[i], L->fixed + 3 * i,
		                           false, L->blockInverse + 9 * (size_t)i);
}

// Cholesky factor (lower triangle, in place) of the bottom level as a dense matrix, fixed DOFs
// as identity rows. False if it is not numerically positive definite.
static bool fmMgFactorBottom(fmMultigrid* mg)
{
	const fmMgLevel* L = &mg->level[mg->levelCount - 1];
	const fmBsrMatrix* m = &L->pattern;
	const int n = 3 * mg->denseRows;
	double* A = mg->dense;
	memset(A, 0, sizeof(double) * (size_t)n * (size_t)n);
	for (int i = 0; i < m->rows; ++i)
		for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
			for (int e = 0; e < 3; ++e)
				for (int f = 0; f < 3; ++f)
					A[(size_t)(3 * i + e) * n + 3 * m->columns[k] + f] =
					    L->values[9 * (size_t)k + 3 * e + f];
	for (int d = 0; d < n; ++d)
		if (L->fixed[d])
			A[(size_t)d * n + d] = 1.0;
	for (int j = 0; j < n; ++j)
	{
		double* row = A + (size_t)j * n;
		double s = row[j];
		for (int k = 0; k < j; ++k)
			s -= row[k] * row[k];
		if (!(s > 0.0) || !isfinite(s))
			return false;
		row[j] = sqrt(s);
		for (int i = j + 1; i < n; ++i)
		{
			double* other = A + (size_t)i * n;
			double t = other[j];
			for (int k = 0; k < j; ++k)
				t -= other[k] * row[k];
			other[j] = t / row[j];
		}
	}
	return true;
}

void fmMultigrid_Setup(fmMultigrid* mg, const double* values, const double* blockInverse,
                       const uint8_t* fixed, unsigned valuesVersion,
                       const struct fmTaskSystem* tasks)
{
	mg->tasks = tasks;
	fmMgLevel* top = &mg->level[0];
	const size_t n3 = 3 * (size_t)top->pattern.rows;
	if (mg->ready && top->values == values && mg->setupVersion == valuesVersion &&
	    memcmp(mg->setupFixed, fixed, n3) == 0)
		return;
	mg->setupVersion = valuesVersion;
	memcpy(mg->setupFixed, fixed, n3);
	top->values = values;
	top->fixed = (uint8_t*)fixed; // never written at level 0
	memcpy(top->blockInverse, blockInverse, sizeof(double) * 9 * (size_t)top->pattern.rows);
	for (int l = 0; l + 1 < mg->levelCount; ++l)
	{
		fmMgGalerkin(&mg->level[l], &mg->level[l + 1]);
		fmMgInvertDiagonal(&mg->level[l + 1]);
	}
	mg->denseOk = mg->denseRows > 0 && fmMgFactorBottom(mg);
	mg->ready = true;
}

typedef struct fmMgTask
{
	const fmMgLevel* level;
	const double* r;
	double* z;
	int parts;
} fmMgTask;

static void fmMgForwardTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmMgTask* t = context;
	const fmMgLevel* L = t->level;
	int rows = L->pattern.rows;
	for (int part = start; part < end; ++part)
		fmBsr_ForwardSweep(&L->pattern, L->values, L->blockInverse, L->fixed, t->r, t->z,
		                   (int)((long long)rows * part / t->parts),
		                   (int)((long long)rows * (part + 1) / t->parts));
}

static void fmMgBackwardTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmMgTask* t = context;
	const fmMgLevel* L = t->level;
	int rows = L->pattern.rows;
	for (int part = start; part < end; ++part)
		fmBsr_BackwardSweep(&L->pattern, L->values, L->blockInverse, L->fixed, t->z,
		                    (int)((long long)rows * part / t->parts),
		                    (int)((long long)rows * (part + 1) / t->parts));
}

// t = r - A z over the rows [start, end), 0 on fixed DOFs.
static void fmMgResidualTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmMgTask* t = context;
	const fmMgLevel* L = t->level;
	fmBsr_MultiplyRows(&L->pattern, L->values, t->z, L->t, start, end);
	for (int k = 3 * start; k < 3 * end; ++k)
		L->t[k] = L->fixed[k] ? 0.0 : t->r[k] - L->t[k];
}

// Solve with the bottom level's Cholesky factor (z = L^-T L^-1 r; fixed DOFs stay 0).
static void fmMgSolveBottom(const fmMultigrid* mg, const fmMgLevel* L, const double* r, double* z)
{
	const int n = 3 * mg->denseRows;
	const double* A = mg->dense;
	for (int i = 0; i < n; ++i)
	{
		double s = L->fixed[i] ? 0.0 : r[i];
		for (int k = 0; k < i; ++k)
			s -= A[(size_t)i * n + k] * z[k];
		z[i] = s / A[(size_t)i * n + i];
	}
	for (int i = n - 1; i >= 0; --i)
	{
		double s = z[i];
		for (int k = i + 1; k < n; ++k)
			s -= A[(size_t)k * n + i] * z[k];
		z[i] = s / A[(size_t)i * n + i];
	}
	for (int i = 0; i < n; ++i)
		z[i] = L->fixed[i] ? 0.0 : z[i];
}

static void fmMgCycle(const fmMultigrid* mg, int l, const double* r, double* z);

// The W-cycle's second visit of level l (not the bottom): z += B_l (r - A_l z), with B_l a
// cycle of its own, so that level l is solved by two iterations (z = (2 B - B A B) r:
// symmetric).
static void fmMgSecondCycle(const fmMultigrid* mg, int l)
{
	const fmMgLevel* L = &mg->level[l];
	if (l == mg->levelCount - 1 && mg->denseOk)
		return; // solved exactly already
	fmMgTask task = {L, L->r, L->z, 1};
	fmMgResidualTask(0, L->pattern.rows, 0, &task);
	memcpy(L->q, L->t, sizeof(double) * 3 * (size_t)L->pattern.rows);
	fmMgCycle(mg, l, L->q, L->w);
	for (int k = 0; k < 3 * L->pattern.rows; ++k)
		L->z[k] += L->w[k];
}

static void fmMgCycle(const fmMultigrid* mg, int l, const double* r, double* z)
{
	const fmMgLevel* L = &mg->level[l];
	const int rows = L->pattern.rows;
	fmMgTask task = {L, r, z, (rows + FM_SGS_PART_ROWS - 1) / FM_SGS_PART_ROWS};
	if (l == mg->levelCount - 1 && mg->denseOk)
	{
		fmMgSolveBottom(mg, L, r, z);
		return;
	}
	// Pre-smoothing: z = (D + L)^-1 r, part by part.
	fmParallelFor(mg->tasks, task.parts, 1, fmMgForwardTask, &task);
	if (l < mg->levelCount - 1)
	{
		// Coarse correction: z += P A_c^-1 P^T (r - A z), A_c^-1 by the next cycle.
		fmParallelFor(mg->tasks, rows, FM_MG_MIN_RANGE, fmMgResidualTask, &task);
		fmMgLevel* next = (fmMgLevel*)&mg->level[l + 1];
		memset(next->r, 0, sizeof(double) * 3 * (size_t)next->pattern.rows);
		for (int i = 0; i < rows; ++i)
			for (int e = 0; e < 3; ++e)
				next->r[3 * L->aggregate[i] + e] += L->t[3 * i + e];
		fmMgCycle(mg, l + 1, next->r, next->z);
		fmMgSecondCycle(mg, l + 1);
		for (int i = 0; i < rows; ++i)
			for (int e = 0; e < 3; ++e)
				z[3 * i + e] += L->fixed[3 * i + e]
				                    ? 0.0
				                    : FM_MG_OVERCORRECTION * next->z[3 * L->aggregate[i] + e];
	}
	// Post-smoothing: z += (D + U)^-1 (r - A z), the backward sweep started from D^-1 t.
	fmParallelFor(mg->tasks, rows, FM_MG_MIN_RANGE, fmMgResidualTask, &task);
	double* d = L->t;
	for (int i = 0; i < rows; ++i)
	{
		const double* B = L->blockInverse + 9 * (size_t)i;
		double u[3] = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
		for (int e = 0; e < 3; ++e)
			d[3 * i + e] = L->fixed[3 * i + e]
			                   ? 0.0
			                   : B[3 * e] * u[0] + B[3 * e + 1] * u[1] + B[3 * e + 2] * u[2];
	}
	fmMgTask post = {L, r, d, task.parts};
	fmParallelFor(mg->tasks, task.parts, 1, fmMgBackwardTask, &post);
	for (int k = 0; k < 3 * rows; ++k)
		z[k] += d[k];
}

void fmMultigrid_Apply(const fmMultigrid* mg, const double* r, double* z)
{
	fmMgCycle(mg, 0, r, z);
}
