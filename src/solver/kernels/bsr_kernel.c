// The block sparse rows' kernels (bsr_kernel.h), compiled once per instruction set:
// FM_KERNEL_VARIANT names the variant and the build adds its -m flags (as for tet_kernel.c).
#ifndef FM_KERNEL_VARIANT
#define FM_KERNEL_VARIANT baseline
#endif
#include "solver/kernels/bsr_kernel.h"

#include "core/simd.h"

// t = the sum of A_ik u_k over the blocks [first, end) of a row: even and odd blocks in two sets
// of running sums, half the dependency chain of one (the sweeps' row-after-row order exposes it).
static inline void fmRowSum(const int* columns, const double* values, const double* u, int first,
                            int end, double t[3])
{
	fmBlockSums even = fmV_BlockZero(), odd = fmV_BlockZero();
	int k = first;
	for (; k + 1 < end; k += 2)
	{
		fmV_BlockAdd(&even, values + 9 * (size_t)k, u + 3 * (size_t)columns[k]);
		fmV_BlockAdd(&odd, values + 9 * (size_t)k + 9, u + 3 * (size_t)columns[k + 1]);
	}
	if (k < end)
		fmV_BlockAdd(&even, values + 9 * (size_t)k, u + 3 * (size_t)columns[k]);
	fmV_BlockMerge(&even, &odd);
	fmV_BlockResult(&even, t);
}

// z = B_i t for one vertex, with the fixed DOFs of the result zeroed.
static inline void fmSolveBlock(const double* B, const double* t, const uint8_t* fixed, double* z)
{
	for (int r = 0; r < 3; ++r)
		z[r] = fixed[r] ? 0.0 : B[3 * r] * t[0] + B[3 * r + 1] * t[1] + B[3 * r + 2] * t[2];
}

void FM_KERNEL_NAME(fmBsrKernel_MultiplyRows)(const fmBsrMatrix* m, const double* values,
                                              const double* x, double* y, int first, int end)
{
	for (int i = first; i < end; ++i)
		fmRowSum(m->columns, values, x, m->rowStart[i], m->rowStart[i + 1], y + 3 * (size_t)i);
}

void FM_KERNEL_NAME(fmBsrKernel_ForwardSweep)(const fmBsrMatrix* m, const double* values,
                                              const double* blockInverse, const uint8_t* fixed,
                                              const double* r, double* z, int first, int end)
{
	for (int i = first; i < end; ++i)
	{
		int k = m->rowStart[i];
		while (m->columns[k] < first)
			++k;
		double t[3];
		fmRowSum(m->columns, values, z, k, m->diagonal[i], t);
		for (int e = 0; e < 3; ++e)
			t[e] = r[3 * (size_t)i + e] - t[e];
		fmSolveBlock(blockInverse + 9 * (size_t)i, t, fixed + 3 * (size_t)i, z + 3 * (size_t)i);
	}
}

void FM_KERNEL_NAME(fmBsrKernel_BackwardSweep)(const fmBsrMatrix* m, const double* values,
                                               const double* blockInverse, const uint8_t* fixed,
                                               double* z, int first, int end)
{
	for (int i = end - 1; i >= first; --i)
	{
		int k = m->rowStart[i + 1];
		while (m->columns[k - 1] >= end)
			--k;
		double t[3], d[3];
		fmRowSum(m->columns, values, z, m->diagonal[i] + 1, k, t);
		fmSolveBlock(blockInverse + 9 * (size_t)i, t, fixed + 3 * (size_t)i, d);
		for (int e = 0; e < 3; ++e)
			z[3 * (size_t)i + e] -= d[e];
	}
}
