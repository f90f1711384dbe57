// Batched element kernels: the explicit FEM step's forces, FM_LANES tets at once in float on the
// lane wrapper of simd.h, with its blocks' per-vertex force sums and smoothing sums; and the
// implicit passes' polar rotations of corotated tets, Neo-Hookean and corotated forces and the
// inverted-tet flags, FM_POLAR_LANES at once in double. tet_kernel.c is compiled once per
// instruction set (CMakeLists.txt); each compilation defines the functions with its own suffix,
// and tet_blocks.c and forces.c call the ones simd.c's level chose. Formulas:
// docs/performance.md ("The explicit kernel") and docs/implicit.md ("Material kernels").
#pragma once

#include <femto/fm_math.h>
#include <femto/types.h>

#include "core/simd.h"

// One batch of FM_LANES tets, structure of arrays, as the kernel streams it (768 bytes).
typedef struct fmTetBatch
{
	// Node a of lane l: 4 n, n its vertex's number in the block (where the vertex's 4 doubles
	// start in the block's rows); unused lanes repeat lane 0's.
	uint16_t row[4][FM_LANES];
	float dmInv[9][FM_LANES]; // Dm^-1, row-major
	float volume[FM_LANES];   // V0 (m^3); 0 in unused lanes, which then give zero forces
} fmTetBatch;

// A batch's output: the elastic force on node a (0..3) of lane l at force[a][l] as (x, y, z, 0)
// (node 0 gets minus the sum of the others): a vertex's sum loads each of its entries as one
// vector.
typedef struct fmTetBatchForces
{
	float force[4][FM_LANES][4];
	// Non-zero in lanes the kernel leaves to the double-precision reference (corotated: tets
	// near flat or inverted, where its polar iteration does not apply; tet_blocks.c redoes
	// them). Set on every variant alike, so the choice does not depend on the instruction set.
	int32_t fallback[FM_LANES];
	// Energy passes only (a non-NULL energy): non-zero in lanes whose float det F proves the
	// double-precision det F > 0 (fmTetKernel_Forces); tet_blocks.c rechecks the others in double
	// for the frame's inverted-tet count.
	int32_t upright[FM_LANES];
} fmTetBatchForces;

// The material as the kernels take it.
typedef struct fmKernelMaterial
{
	fmMaterialModel model; // linear, StVK, (isochoric) Neo-Hookean, Mooney-Rivlin or corotated
	float mu;
	float lambda;
	float c01; // Mooney-Rivlin's second constant (unused by the other models)
} fmKernelMaterial;

// fmTetKernel_Forces_<variant>: the forces of one batch, from the displacements u = x - X of
// its block's vertices (4 doubles each, the fourth unused, in the block's numbering). The kernel
// forms Du = [u1 - u0, u2 - u0, u3 - u0] in double, rounds it once to float, and works from H = F -
// I = Du Dm^-1, so a small strain keeps its relative accuracy in float. With a non-NULL
// @p energy, each lane's elastic energy V0 psi (J; 0 in unused lanes) goes to energy[lane]
// (Neo-Hookean's from Green's strain, free of first-order cancellation), and out->upright says
// which lanes' det F is surely positive. Returns whether any lane was left to the reference
// (out->fallback).
typedef bool fmTetKernelFcn(const fmTetBatch* batch, const double* u,
                            const fmKernelMaterial* material, fmTetBatchForces* out, float* energy);

fmTetKernelFcn fmTetKernel_Forces_scalar;
fmTetKernelFcn fmTetKernel_Forces_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmTetKernelFcn fmTetKernel_Forces_avx2;
fmTetKernelFcn fmTetKernel_Forces_avx512;
#endif

// fmTetKernel_SumForces_<variant>: the sums of @p count vertices' entries in a block's batch
// outputs @p forces (floats from the first batch's force[0][0]): vertex i's entries start at the
// float offsets offsets[start[i] .. start[i + 1]), and sums[3 i + c] is the sum of their
// component c in double, in that order (the same bits on every variant).
typedef void fmTetSumFcn(const float* forces, const uint16_t* offsets, const int* start, int count,
                         double* sums);

fmTetSumFcn fmTetKernel_SumForces_scalar;
fmTetSumFcn fmTetKernel_SumForces_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmTetSumFcn fmTetKernel_SumForces_avx2;
fmTetSumFcn fmTetKernel_SumForces_avx512;
#endif

// fmTetKernel_WeightedSums_<variant>: for vertices i in [first, end), sums[3 i + c] = the sum
// over e in [start[i], start[i + 1]) of weights[e] * v[offsets[e] + c], in double, in that
// order (the same bits on every variant); v holds 3 doubles a vertex.
typedef void fmTetWeightedSumFcn(const double* v, const int* offsets, const double* weights,
                                 const int* start, int first, int end, double* sums);

fmTetWeightedSumFcn fmTetKernel_WeightedSums_scalar;
fmTetWeightedSumFcn fmTetKernel_WeightedSums_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmTetWeightedSumFcn fmTetKernel_WeightedSums_avx2;
fmTetWeightedSumFcn fmTetKernel_WeightedSums_avx512;
#endif

// ---- batched polar rotations (the implicit solver's corotated tets) ----------------------------

// Matrices the polar kernel takes at once.
#define FM_POLAR_LANES 8

// The deformation gradients of up to FM_POLAR_LANES tets (row-major, entry k of lane l at
// F[k][l]; unused lanes hold the identity) and their rotations.
typedef struct fmPolarBatch
{
	double F[9][FM_POLAR_LANES];
	double R[9][FM_POLAR_LANES]; // where ok (elsewhere unspecified)
	bool ok[FM_POLAR_LANES];     // false where fmPolarRotationFast refuses F
} fmPolarBatch;

// fmTetKernel_Polar_<variant>: fmPolarRotationFast (svd3.h) of every lane, in double, with the
// same operations in the same order lane by lane (each lane stops at its own convergence), so the
// same bits as one matrix at a time on every variant.
typedef void fmPolarKernelFcn(fmPolarBatch* batch);

fmPolarKernelFcn fmTetKernel_Polar_scalar;
fmPolarKernelFcn fmTetKernel_Polar_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmPolarKernelFcn fmTetKernel_Polar_avx2;
fmPolarKernelFcn fmTetKernel_Polar_avx512;
#endif

// ---- batched forces of one material (the implicit solver's force passes) -----------------------

// Tets the force batch takes at once.
#define FM_FORCE_LANES FM_POLAR_LANES

// Up to FM_FORCE_LANES tets of a body of one StVK, Neo-Hookean or corotated material (entry k of
// lane l at [k][l]; unused lanes: zero Ds, zero volume) and their forces and energy densities.
typedef struct fmForceBatch
{
	double Ds[9][FM_FORCE_LANES];    // in: [x1 - x0, x2 - x0, x3 - x0] (columns), row-major
	double dmInv[9][FM_FORCE_LANES]; // in: Dm^-1
	double volume[FM_FORCE_LANES];   // in: V0 (m^3)
	double mu, lambda;               // in: the material's Lame constants (Pa)
	// out: force[a][i] the force on node a = 1..3, component i; force[0][i] their sum, in node
	// order (node 0 takes minus it)
	double force[4][3][FM_FORCE_LANES];
	double psi[FM_FORCE_LANES]; // out: energy density (J/m^3)
	// out: false in lanes the kernel leaves to the scalar path (corotated: where the polar
	// iteration declines F), whose forces and psi are then meaningless
	bool ok[FM_FORCE_LANES];
} fmForceBatch;

// A force kernel: P, psi and the nodal forces -V0 P Dm^-T of every lane from F = Ds Dm^-1, with
// the operations of the scalar path in their order (fmTetDeformation, the material, and
// fmAddTetForces in forces.c): the same bits as one tet at a time, on every variant.
// fmTetKernel_NeoHookean_<variant>: fmNeoHookean_Evaluate (ln J by fmClampedLogJ, lane by lane);
// every lane ok. fmTetKernel_Corotated_<variant>: R by fmTetKernel_Polar's iteration, then
// fmCorotated_Stress; lanes the iteration declines are not ok.
typedef void fmForceBatchKernelFcn(fmForceBatch* batch);

// fmTetKernel_FillForceBatch_<variant>: the full batch of tets [first, first + FM_FORCE_LANES) of
// a body (tets: 4 vertex numbers each; dmInv, volume: its rest data) at positions x:
// Ds[3 i + k][l] = x[3 n_{k+1} + i] - x[3 n_0 + i], Dm^-1 and V0 of each lane, the entries
// forces.c's one-lane fill writes (the same bits). Leaves mu and lambda alone.
typedef void fmForceBatchFillFcn(const double* x, const int* tets, const fmMat3* dmInv,
                                 const double* volume, int first, fmForceBatch* batch);

fmForceBatchFillFcn fmTetKernel_FillForceBatch_scalar;
fmForceBatchFillFcn fmTetKernel_FillForceBatch_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmForceBatchFillFcn fmTetKernel_FillForceBatch_avx2;
fmForceBatchFillFcn fmTetKernel_FillForceBatch_avx512;
#endif

// fmTetKernel_Inverted_<variant>: inverted[l] = !(det F > 0) for lanes l < count, F = Ds Dm^-1
// (fmTetDeformation's products, det by the first row of cof F: fmDet's bits).
typedef void fmInvertedKernelFcn(const fmForceBatch* batch, int count, unsigned char* inverted);

fmInvertedKernelFcn fmTetKernel_Inverted_scalar;
fmInvertedKernelFcn fmTetKernel_Inverted_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmInvertedKernelFcn fmTetKernel_Inverted_avx2;
fmInvertedKernelFcn fmTetKernel_Inverted_avx512;
#endif

// fmTetKernel_Proxy_<variant>: *largest = the largest of itself and, over lanes l < count,
// max(|F|^2, |F|^4 / (4 J^2)) (INFINITY where !(J > 0)), F = Ds Dm^-1 and J as
// fmTetKernel_Inverted's: fmStiffeningProxy's values, bit for bit.
typedef void fmProxyKernelFcn(const fmForceBatch* batch, int count, double* largest);

fmProxyKernelFcn fmTetKernel_Proxy_scalar;
fmProxyKernelFcn fmTetKernel_Proxy_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmProxyKernelFcn fmTetKernel_Proxy_avx2;
fmProxyKernelFcn fmTetKernel_Proxy_avx512;
#endif

fmForceBatchKernelFcn fmTetKernel_Corotated_scalar;
fmForceBatchKernelFcn fmTetKernel_Corotated_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmForceBatchKernelFcn fmTetKernel_Corotated_avx2;
fmForceBatchKernelFcn fmTetKernel_Corotated_avx512;
#endif
// fmTetKernel_Stvk_<variant>: fmStvk_Evaluate's P and psi without the volume floor; lanes below
// the floor's J (FM_STVK_FLOOR_J) are not ok (none in the browser's build: the .wasm line).
fmForceBatchKernelFcn fmTetKernel_Stvk_scalar;
fmForceBatchKernelFcn fmTetKernel_Stvk_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmForceBatchKernelFcn fmTetKernel_Stvk_avx2;
fmForceBatchKernelFcn fmTetKernel_Stvk_avx512;
#endif
fmForceBatchKernelFcn fmTetKernel_NeoHookean_scalar;
fmForceBatchKernelFcn fmTetKernel_NeoHookean_baseline;
#if defined(__x86_64__) || defined(_M_X64)
fmForceBatchKernelFcn fmTetKernel_NeoHookean_avx2;
fmForceBatchKernelFcn fmTetKernel_NeoHookean_avx512;
#endif
