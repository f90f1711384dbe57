// The preconditioned conjugate gradient (Hestenes-Stiefel, with the preconditioner applied as
// z = B r; Shewchuk, "An Introduction to the Conjugate Gradient Method Without the Agonizing
// Pain", 1994, algorithm B3) and its preconditioners.
#include "solver/pcg.h"

#include "core/parallel.h"
#include "solver/multigrid.h"

#include <math.h>
#include <string.h>

// Fixed-order dot product over all entries (fixed DOFs hold zeros): four running sums, of the
// entries k = 0, 1, 2, 3 mod 4, added as (s0 + s1) + (s2 + s3) at the end. Four chains instead of
// one (a CG iteration takes three of these); the same order on every target and worker count.
static double fmDotN(int n, const double* a, const double* b)
{
	double s[4] = {0.0, 0.0, 0.0, 0.0};
	int k = 0;
	for (; k + 3 < n; k += 4)
		for (int j = 0; j < 4; ++j)
			s[j] += a[k + j] * b[k + j];
	for (int j = 0; k < n; ++k, ++j)
		s[j] += a[k] * b[k];
	return (s[0] + s[1]) + (s[2] + s[3]);
}

static void fmApplyBlocks(int n, const double* blockInverse, const double* r, double* z)
{
	for (int i = 0; i < n / 3; ++i)
	{
		const double* B = blockInverse + 9 * (size_t)i;
		const double* u = r + 3 * (size_t)i;
		z[3 * i] = B[0] * u[0] + B[1] * u[1] + B[2] * u[2];
		z[3 * i + 1] = B[3] * u[0] + B[4] * u[1] + B[5] * u[2];
		z[3 * i + 2] = B[6] * u[0] + B[7] * u[1] + B[8] * u[2];
	}
}

// Symmetric block Gauss-Seidel on the rows [first, end), coupled to no other row: a forward
// sweep, then a backward one (pcg.h).
static void fmSgsRows(const fmPcgPreconditioner* pre, const uint8_t* fixed, const double* r,
                      double* z, int first, int end)
{
	fmBsr_ForwardSweep(pre->matrix, pre->values, pre->blockInverse, fixed, r, z, first, end);
	fmBsr_BackwardSweep(pre->matrix, pre->values, pre->blockInverse, fixed, z, first, end);
}

typedef struct fmSgsTask
{
	const fmPcgPreconditioner* pre;
	const uint8_t* fixed;
	const double* r;
	double* z;
	int rows;
	int parts;
} fmSgsTask;

static void fmSgsPartsTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmSgsTask* t = context;
	for (int part = start; part < end; ++part)
		fmSgsRows(t->pre, t->fixed, t->r, t->z, (int)((long long)t->rows * part / t->parts),
		          (int)((long long)t->rows * (part + 1) / t->parts));
}

// Symmetric block Gauss-Seidel in parts of about FM_SGS_PART_ROWS rows, each part on its own
// (block Jacobi between the parts): SPD for an SPD matrix. The parts depend on the matrix size
// only, so any number of workers gives the same bits.
static void fmApplySgs(int n, const fmPcgPreconditioner* pre, const uint8_t* fixed, const double* r,
                       double* z)
{
	int rows = n / 3;
	fmSgsTask task = {pre, fixed, r, z, rows, (rows + FM_SGS_PART_ROWS - 1) / FM_SGS_PART_ROWS};
	fmParallelFor(pre->tasks, task.parts, 1, fmSgsPartsTask, &task);
}

// z = B r, and r . z. A multigrid cycle whose r . z is not positive (its smoother diverged on
// a matrix far from diagonally dominant) is replaced by symmetric Gauss-Seidel, always SPD.
static double fmPrecondition(int n, const fmPcgPreconditioner* pre, const uint8_t* fixed,
                             const double* r, double* z)
{
	if (pre->kind == fm_precondMultigrid)
	{
		fmMultigrid_Apply(pre->multigrid, r, z);
		double rz = fmDotN(n, r, z);
		if (rz > 0.0 && isfinite(rz))
			return rz;
	}
	if (pre->kind != fm_precondJacobi && pre->kind != fm_precondBlockJacobi)
		fmApplySgs(n, pre, fixed, r, z);
	else
		fmApplyBlocks(n, pre->blockInverse, r, z);
	return fmDotN(n, r, z);
}

fmPcgResult fmPcg_Solve(int n, fmLinearOperator* op, void* context, const fmPcgPreconditioner* pre,
                        const uint8_t* fixed, const double* b, double* x, double tolerance,
                        int maxIterations, const fmPcgWork* w)
{
	fmPcgResult result = {0, 0.0, false, false};
	for (int k = 0; k < n; ++k)
	{
		x[k] = 0.0;
		w->r[k] = fixed[k] ? 0.0 : b[k];
	}
	double rr = fmDotN(n, w->r, w->r);
	result.residual = sqrt(rr);
	if (result.residual <= tolerance)
	{
		result.converged = true;
		return result;
	}
	double rz = fmPrecondition(n, pre, fixed, w->r, w->z);
	memcpy(w->p, w->z, sizeof(double) * (size_t)n);
	while (result.iterations < maxIterations)
	{
		op(context, w->p, w->q);
		for (int k = 0; k < n; ++k)
			w->q[k] = fixed[k] ? 0.0 : w->q[k];
		double pq = fmDotN(n, w->p, w->q);
		// A (projected) PSD operator can still be singular: no curvature means no information.
		if (!(pq > 0.0))
		{
			result.indefinite = true;
			break;
		}
		double alpha = rz / pq;
		for (int k = 0; k < n; ++k)
		{
			x[k] += alpha * w->p[k];
			w->r[k] -= alpha * w->q[k];
		}
		result.iterations += 1;
		rr = fmDotN(n, w->r, w->r);
		result.residual = sqrt(rr);
		if (result.residual <= tolerance)
		{
			result.converged = true;
			break;
		}
		double rzNew = fmPrecondition(n, pre, fixed, w->r, w->z);
		double beta = rzNew / rz;
		rz = rzNew;
		for (int k = 0; k < n; ++k)
			w->p[k] = w->z[k] + beta * w->p[k];
	}
	return result;
}

void fmPcg_BuildPreconditioner(int vertexCount, const double* diagBlocks, const uint8_t* fixed,
                               fmPreconditioner kind, double* blockInverse)
{
	fmBsr_InvertDiagonalBlocks(vertexCount, diagBlocks, fixed, kind == fm_precondJacobi,
	                           blockInverse);
}
