// The explicit step's per-vertex stages, compiled once per instruction set like the element
// kernels (tet_kernel.h; CMakeLists.txt): a block's displacement rows, each vertex's blocks' force
// sums with gravity, the velocity update, the seeds' smoothing blend and the position update.
// Each does the same operations in the same order on every variant (the same bits); with AVX2
// four vertices' 12 doubles are three vectors. tet_blocks.c picks the variant with the element
// kernels (fmTetBlocks_Kernels); explicit.c and velocity_filter.c call them. docs/performance.md,
// "The explicit step's instructions".
#pragma once

#include <stddef.h>
#include <stdint.h>

// fmVertexKernel_Displacements_<variant>: u[4 i + c] = x[3 v + c] - X[3 v + c] for the @p count
// vertices v = verts[i] of a block, c = 0, 1, 2, and u[4 i + 3] = 0 (the rows the force kernel
// loads), in double on every variant.
typedef void fmTetDisplacementFcn(const int* verts, int count, const double* x, const double* X,
                                  double* u);
fmTetDisplacementFcn fmVertexKernel_Displacements_scalar;
fmTetDisplacementFcn fmVertexKernel_Displacements_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmTetDisplacementFcn fmVertexKernel_Displacements_avx2;
fmTetDisplacementFcn fmVertexKernel_Displacements_avx512;
#endif

// fmVertexKernel_GatherSums_<variant>: for vertices i in [start, end), f[3 i + c] = mass[i] g[c]
// plus the block sums sums[3 e + c] of its entries e = entries[entryStart[i] ..
// entryStart[i + 1]), in that order (the same bits on every variant). @p sums holds one double
// beyond its last entry (a vector's fourth lane reads it and drops it).
typedef struct fmBlockGather
{
	const double* sums;
	const int* entries;
	const int* entryStart;
	const double* mass;
	double g[3];
	double* f;
} fmBlockGather;
typedef void fmTetGatherFcn(const fmBlockGather* gather, int start, int end);
fmTetGatherFcn fmVertexKernel_GatherSums_scalar;
fmTetGatherFcn fmVertexKernel_GatherSums_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmTetGatherFcn fmVertexKernel_GatherSums_avx2;
fmTetGatherFcn fmVertexKernel_GatherSums_avx512;
#endif

// ---- the explicit step's vertex updates --------------------------------------------------------
// One substep's per-vertex stages on vertices [start, end) (3 doubles a vertex), each with the
// same operations in the same order on every variant: the same bits (four vertices at a time
// where the vector unit allows; a vertex with pins takes the general path).
typedef struct fmVertexUpdate
{
	double* x;             // positions (m)
	double* v;             // velocities (m/s)
	const double* f;       // forces (N)
	const double* invMass; // 1/kg
	const double* weight;  // the smoothing's weight of each vertex's sum
	const double* sum;     // the smoothing's sums (3 a vertex)
	const uint8_t* pinned; // fmBodyState.pinned
	double dt;             // s
	double damping;        // the step's damping factor (1: none)
	double keep, blend;    // the smoothing: v = keep v + blend weight sum
} fmVertexUpdate;

// fmVertexKernel_Velocities_<variant>: v = (v + (dt invMass) f) damping; a pinned vertex keeps its
// velocity (times the factor), a roller's pinned axes go to zero before the factor.
// fmVertexKernel_Blend_<variant>: v = keep v + blend (weight sum) but for pinned vertices; a
// roller's pinned axes to zero. fmVertexKernel_Positions_<variant>: x += dt v but for pinned
// vertices.
typedef void fmVertexKernelFcn(const fmVertexUpdate* update, int start, int end);
fmVertexKernelFcn fmVertexKernel_Velocities_scalar, fmVertexKernel_Blend_scalar,
    fmVertexKernel_Positions_scalar;
fmVertexKernelFcn fmVertexKernel_Velocities_baseline, fmVertexKernel_Blend_baseline,
    fmVertexKernel_Positions_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmVertexKernelFcn fmVertexKernel_Velocities_avx2, fmVertexKernel_Blend_avx2,
    fmVertexKernel_Positions_avx2;
fmVertexKernelFcn fmVertexKernel_Velocities_avx512, fmVertexKernel_Blend_avx512,
    fmVertexKernel_Positions_avx512;
#endif
