// The row kernels of the block sparse matrices of bsr.h: the product and the Gauss-Seidel sweeps,
// which the implicit and static solvers' conjugate gradient spends most of its time in.
// bsr_kernel.c is compiled once per instruction set, as tet_kernel.c is (CMakeLists.txt); bsr.c
// calls the variant the CPU runs. A row's sum keeps one running sum per block entry (simd.h,
// fmBlockSums), so every variant gives the same bits.
#pragma once

#include "solver/bsr.h"

// y = A x on the block rows [first, end) (fmBsr_MultiplyRows).
typedef void fmBsrMultiplyFcn(const fmBsrMatrix* matrix, const double* values, const double* x,
                              double* y, int first, int end);
// The forward sweep of fmBsr_ForwardSweep.
typedef void fmBsrForwardFcn(const fmBsrMatrix* matrix, const double* values,
                             const double* blockInverse, const uint8_t* fixed, const double* r,
                             double* z, int first, int end);
// The backward sweep of fmBsr_BackwardSweep.
typedef void fmBsrBackwardFcn(const fmBsrMatrix* matrix, const double* values,
                              const double* blockInverse, const uint8_t* fixed, double* z,
                              int first, int end);

// One variant's kernels.
typedef struct fmBsrKernels
{
	fmBsrMultiplyFcn* multiplyRows;
	fmBsrForwardFcn* forwardSweep;
	fmBsrBackwardFcn* backwardSweep;
} fmBsrKernels;

fmBsrMultiplyFcn fmBsrKernel_MultiplyRows_scalar;
fmBsrMultiplyFcn fmBsrKernel_MultiplyRows_baseline;
fmBsrForwardFcn fmBsrKernel_ForwardSweep_scalar;
fmBsrForwardFcn fmBsrKernel_ForwardSweep_baseline;
fmBsrBackwardFcn fmBsrKernel_BackwardSweep_scalar;
fmBsrBackwardFcn fmBsrKernel_BackwardSweep_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmBsrMultiplyFcn fmBsrKernel_MultiplyRows_avx2;
fmBsrMultiplyFcn fmBsrKernel_MultiplyRows_avx512;
fmBsrForwardFcn fmBsrKernel_ForwardSweep_avx2;
fmBsrForwardFcn fmBsrKernel_ForwardSweep_avx512;
fmBsrBackwardFcn fmBsrKernel_BackwardSweep_avx2;
fmBsrBackwardFcn fmBsrKernel_BackwardSweep_avx512;
#endif
