// Elastic forces by the finite element method (the seeds' derivation) and their derivatives.
//
// Per tet: F = Ds Dm^-1 with Ds = [x1-x0, x2-x0, x3-x0]; energy V0 psi(F); the force on node a
// is -V0 P(F) g_a, where g_a (a = 1..3) are the rows of Dm^-1 and g_0 = -(g_1 + g_2 + g_3), i.e.
// the columns of -V0 P Dm^-T, and node 0 gets minus the sum (the seeds' formula).
#include "fem/forces.h"

#include "fem/force_fvm.h"
#include "fem/force_spring.h"
#include "fem/nodal_pressure.h"

#include "fem/kernels/tet_kernel.h"
#include "material/material.h"
#include "material/material_stretch.h"

#include <string.h>

void fmShapeGradients(const fmMat3* DmInv, fmVec3 g[4])
{
	for (int a = 1; a < 4; ++a)
		g[a] =
		    fmMakeVec3(DmInv->m[3 * (a - 1)], DmInv->m[3 * (a - 1) + 1], DmInv->m[3 * (a - 1) + 2]);
	g[0] = fmScale(-1.0, fmAdd(fmAdd(g[1], g[2]), g[3]));
}

// The batched stiffening proxy and StVK forces; none in the browser (the .wasm line: there
// stability.c takes the proxy and the force passes StVK one tet at a time).
#if defined(__EMSCRIPTEN__)
#define FM_NATIVE_KERNEL(kernel) NULL
#else
#define FM_NATIVE_KERNEL(kernel) kernel
#endif

// The batched double-precision kernels of the force passes, of the CPU's instruction set (every
// variant gives the same bits).
typedef struct fmPassKernels
{
	fmPolarKernelFcn* polar;
	fmForceBatchKernelFcn* neoHookean;
	fmForceBatchKernelFcn* corotated;
	fmForceBatchFillFcn* fill;
	fmInvertedKernelFcn* inverted;
	fmProxyKernelFcn* proxy;
	fmForceBatchKernelFcn* stvk;
} fmPassKernels;

static fmPassKernels fmPassKernelsOfCpu(void)
{
	switch (fmSimd_Detect())
	{
#if defined(__x86_64__) || defined(_M_X64)
	case fm_simdAvx512:
		return (fmPassKernels){fmTetKernel_Polar_avx512,
		                       fmTetKernel_NeoHookean_avx512,
		                       fmTetKernel_Corotated_avx512,
		                       fmTetKernel_FillForceBatch_avx512,
		                       fmTetKernel_Inverted_avx512,
		                       FM_NATIVE_KERNEL(fmTetKernel_Proxy_avx512),
		                       FM_NATIVE_KERNEL(fmTetKernel_Stvk_avx512)};
	case fm_simdAvx2:
		return (fmPassKernels){fmTetKernel_Polar_avx2,
		                       fmTetKernel_NeoHookean_avx2,
		                       fmTetKernel_Corotated_avx2,
		                       fmTetKernel_FillForceBatch_avx2,
		                       fmTetKernel_Inverted_avx2,
		                       FM_NATIVE_KERNEL(fmTetKernel_Proxy_avx2),
		                       FM_NATIVE_KERNEL(fmTetKernel_Stvk_avx2)};
#endif
	case fm_simdScalar:
		return (fmPassKernels){fmTetKernel_Polar_scalar,
		                       fmTetKernel_NeoHookean_scalar,
		                       fmTetKernel_Corotated_scalar,
		                       fmTetKernel_FillForceBatch_scalar,
		                       fmTetKernel_Inverted_scalar,
		                       FM_NATIVE_KERNEL(fmTetKernel_Proxy_scalar),
		                       FM_NATIVE_KERNEL(fmTetKernel_Stvk_scalar)};
	default:
		return (fmPassKernels){fmTetKernel_Polar_baseline,
		                       fmTetKernel_NeoHookean_baseline,
		                       fmTetKernel_Corotated_baseline,
		                       fmTetKernel_FillForceBatch_baseline,
		                       fmTetKernel_Inverted_baseline,
		                       FM_NATIVE_KERNEL(fmTetKernel_Proxy_baseline),
		                       FM_NATIVE_KERNEL(fmTetKernel_Stvk_baseline)};
	}
}

// The batched polar kernel when some tet of @p body is corotated; NULL otherwise.
static fmPolarKernelFcn* fmPolarKernel(const fmElasticMesh* mesh)
{
	bool corotated = mesh->material.model == fm_corotated;
	for (int k = 0; k < mesh->materialCount; ++k)
		corotated = corotated || mesh->materials[k].model == fm_corotated;
	return corotated ? fmPassKernelsOfCpu().polar : NULL;
}

// The batched force kernel of a body of one material (no per-tet materials) when its model has
// one (StVK, Neo-Hookean, corotated); NULL otherwise. @p kernels gets the CPU's kernels.
static fmForceBatchKernelFcn* fmForceBatchKernel(const fmElasticMesh* mesh, fmPassKernels* kernels)
{
	*kernels = fmPassKernelsOfCpu();
	if (mesh->tetMaterial != NULL || fmNodalPressure_On(mesh))
		return NULL;
	if (mesh->material.model == fm_neoHookean)
		return kernels->neoHookean;
	if (mesh->material.model == fm_stvk)
		return kernels->stvk;
	return mesh->material.model == fm_corotated ? kernels->corotated : NULL;
}

// Tets [first, first + count), count <= FM_FORCE_LANES, into a force batch at x (the edge
// matrices of fmTetDeformation; unused lanes zero): a full batch by the kernels' fill.
static void fmFillForceBatch(const fmElasticMesh* mesh, const double* x, int first, int count,
                             const fmPassKernels* kernels, fmForceBatch* batch)
{
	batch->mu = mesh->material.mu;
	batch->lambda = mesh->material.lambda;
	if (count == FM_FORCE_LANES)
	{
		kernels->fill(x, mesh->tets, mesh->DmInv, mesh->restVolume, first, batch);
		return;
	}
	for (int l = 0; l < FM_FORCE_LANES; ++l)
	{
		int t = first + (l < count ? l : 0);
		const int* n = mesh->tets + 4 * t;
		for (int i = 0; i < 3; ++i)
			for (int k = 0; k < 3; ++k)
				batch->Ds[3 * i + k][l] = l < count ? x[3 * n[k + 1] + i] - x[3 * n[0] + i] : 0.0;
		for (int e = 0; e < 9; ++e)
			batch->dmInv[e][l] = mesh->DmInv[t].m[e];
		batch->volume[l] = l < count ? mesh->restVolume[t] : 0.0;
	}
}

// P and psi of tets [first, first + count), count <= FM_POLAR_LANES, at x: the corotated tets
// take their rotations from the batched polar kernel (about a third of a corotated implicit
// frame one tet at a time), the same bits as fmMaterial_Evaluate's.
static void fmTetStresses(const fmElasticMesh* mesh, const double* x, int first, int count,
                          fmPolarKernelFcn* polar, fmMat3* P, double* psi)
{
	fmPolarBatch batch;
	fmMat3 F[FM_POLAR_LANES];
	int lane[FM_POLAR_LANES], lanes = 0;
	for (int j = 0; j < count; ++j)
	{
		F[j] = fmTetDeformation(mesh, x, first + j);
		lane[j] = fmTetMaterial(mesh, first + j)->model == fm_corotated ? lanes++ : -1;
		for (int k = 0; lane[j] >= 0 && k < 9; ++k)
			batch.F[k][lane[j]] = F[j].m[k];
	}
	if (lanes > 0)
	{
		for (int k = 0; k < 9; ++k)
			for (int l = lanes; l < FM_POLAR_LANES; ++l)
				batch.F[k][l] = k % 4 == 0 ? 1.0 : 0.0;
		polar(&batch);
	}
	for (int j = 0; j < count; ++j)
	{
		const fmMaterial* m = fmTetMaterial(mesh, first + j);
		if (lane[j] >= 0 && batch.ok[lane[j]])
		{
			fmMat3 R;
			for (int k = 0; k < 9; ++k)
				R.m[k] = batch.R[k][lane[j]];
			psi[j] = fmCorotated_Stress(m, &F[j], &R, &P[j]);
		}
		else
			psi[j] = fmTetEvaluate(mesh, first + j, &F[j], &P[j], NULL, false);
	}
}

// Inlined into both loops of a pass (GCC left a call: 6% more instructions in a Neo-Hookean
// force pass).
#if defined(__GNUC__) || defined(__clang__)
#define FM_FORCES_INLINE static inline __attribute__((always_inline))
#else
#define FM_FORCES_INLINE static inline
#endif

// f += tet @p t's forces from its stress P: the columns of -V0 P Dm^-T on nodes 1..3, minus their
// sum on node 0 (the seeds' formula).
FM_FORCES_INLINE void fmAddTetForces(const fmElasticMesh* mesh, int t, const fmMat3* P, double* f)
{
	double V0 = mesh->restVolume[t];
	fmMat3 H = fmMatMulT(P, &mesh->DmInv[t]);
	const int* n = mesh->tets + 4 * t;
	fmVec3 sum = {0, 0, 0};
	for (int a = 1; a < 4; ++a)
	{
		fmVec3 fa = fmScale(-V0, fmColumn(&H, a - 1));
		sum = fmAdd(sum, fa);
		fmStore(f, n[a], fmAdd(fmLoad(f, n[a]), fa));
	}
	fmStore(f, n[0], fmSub(fmLoad(f, n[0]), sum));
}

// The same forces into tet @p t's 12 entries of @p forces; node 0 keeps minus the sum
// (a - b == a + -b: the same bits once gathered).
FM_FORCES_INLINE void fmStoreTetForces(const fmElasticMesh* mesh, int t, const fmMat3* P,
                                       double* forces)
{
	double V0 = mesh->restVolume[t];
	fmMat3 H = fmMatMulT(P, &mesh->DmInv[t]);
	fmVec3 sum = {0, 0, 0};
	double* out = forces + 12 * (size_t)t;
	for (int a = 1; a < 4; ++a)
	{
		fmVec3 fa = fmScale(-V0, fmColumn(&H, a - 1));
		sum = fmAdd(sum, fa);
		fmStore(out, a, fa);
	}
	fmStore(out, 0, fmScale(-1.0, sum));
}

void fmInvertedTets(const fmElasticMesh* mesh, const double* x, int first, int end,
                    unsigned char* inverted)
{
	fmPassKernels kernels = fmPassKernelsOfCpu();
	fmForceBatch batch;
	for (int start = first; start < end; start += FM_FORCE_LANES)
	{
		int count = end - start < FM_FORCE_LANES ? end - start : FM_FORCE_LANES;
		fmFillForceBatch(mesh, x, start, count, &kernels, &batch);
		kernels.inverted(&batch, count, inverted + (start - first));
	}
}

double fmStiffeningProxyTets(const fmElasticMesh* mesh, const double* x, int first, int end)
{
	fmPassKernels kernels = fmPassKernelsOfCpu();
	fmForceBatch batch;
	double largest = 1.0;
	for (int start = first; start < end; start += FM_FORCE_LANES)
	{
		int count = end - start < FM_FORCE_LANES ? end - start : FM_FORCE_LANES;
		fmFillForceBatch(mesh, x, start, count, &kernels, &batch);
		kernels.proxy(&batch, count, &largest);
	}
	return largest;
}

// P and psi of tet @p t at x one tet at a time (a lane a batched kernel left to the scalar path).
static double fmScalarStress(const fmElasticMesh* mesh, const double* x, int t, fmMat3* P)
{
	fmMat3 F = fmTetDeformation(mesh, x, t);
	return fmTetEvaluate(mesh, t, &F, P, NULL, false);
}

// f += the forces of a body of one material, a batch at a time through @p kernel; returns the
// elastic energy (J), in tet order.
static double fmAddBatchedForces(const fmElasticMesh* mesh, const double* x, double* f,
                                 const fmPassKernels* kernels, fmForceBatchKernelFcn* kernel)
{
	double energy = 0.0;
	fmForceBatch batch;
	for (int first = 0; first < mesh->tetCount; first += FM_FORCE_LANES)
	{
		int count =
		    mesh->tetCount - first < FM_FORCE_LANES ? mesh->tetCount - first : FM_FORCE_LANES;
		fmFillForceBatch(mesh, x, first, count, kernels, &batch);
		kernel(&batch);
		for (int l = 0; l < count; ++l)
		{
			if (!batch.ok[l])
			{
				fmMat3 P;
				energy += mesh->restVolume[first + l] * fmScalarStress(mesh, x, first + l, &P);
				fmAddTetForces(mesh, first + l, &P, f);
				continue;
			}
			const int* n = mesh->tets + 4 * (first + l);
			energy += mesh->restVolume[first + l] * batch.psi[l];
			for (int a = 1; a < 4; ++a)
				for (int i = 0; i < 3; ++i)
					f[3 * n[a] + i] = f[3 * n[a] + i] + batch.force[a][i][l];
			for (int i = 0; i < 3; ++i)
				f[3 * n[0] + i] = f[3 * n[0] + i] - batch.force[0][i][l];
		}
	}
	return energy;
}

static double fmAddFemForces(const fmElasticMesh* mesh, const double* x, double* f)
{
	fmPassKernels kernels;
	fmForceBatchKernelFcn* batched = fmForceBatchKernel(mesh, &kernels);
	if (batched != NULL)
		return fmAddBatchedForces(mesh, x, f, &kernels, batched);
	fmPolarKernelFcn* polar = fmPolarKernel(mesh);
	double energy = 0.0;
	if (polar == NULL) // one tet at a time: no batch to fill
	{
		for (int t = 0; t < mesh->tetCount; ++t)
		{
			fmMat3 F = fmTetDeformation(mesh, x, t), P;
			energy += mesh->restVolume[t] * fmTetEvaluate(mesh, t, &F, &P, NULL, false);
			fmAddTetForces(mesh, t, &P, f);
		}
		return energy;
	}
	for (int first = 0; first < mesh->tetCount; first += FM_POLAR_LANES)
	{
		int count =
		    mesh->tetCount - first < FM_POLAR_LANES ? mesh->tetCount - first : FM_POLAR_LANES;
		fmMat3 P[FM_POLAR_LANES];
		double psi[FM_POLAR_LANES];
		fmTetStresses(mesh, x, first, count, polar, P, psi);
		for (int j = 0; j < count; ++j)
		{
			energy += mesh->restVolume[first + j] * psi[j];
			fmAddTetForces(mesh, first + j, &P[j], f);
		}
	}
	return energy;
}

// Tets [first, end) of a body of one material into their 12 entries of @p forces and their
// energies, a batch at a time through @p kernel.
static void fmStoreBatchedForces(const fmElasticMesh* mesh, const double* x, int first, int end,
                                 double* forces, double* energies, const fmPassKernels* kernels,
                                 fmForceBatchKernelFcn* kernel)
{
	fmForceBatch batch;
	for (int start = first; start < end; start += FM_FORCE_LANES)
	{
		int count = end - start < FM_FORCE_LANES ? end - start : FM_FORCE_LANES;
		fmFillForceBatch(mesh, x, start, count, kernels, &batch);
		kernel(&batch);
		for (int l = 0; l < count; ++l)
		{
			if (!batch.ok[l])
			{
				fmMat3 P;
				energies[start + l] =
				    mesh->restVolume[start + l] * fmScalarStress(mesh, x, start + l, &P);
				fmStoreTetForces(mesh, start + l, &P, forces);
				continue;
			}
			double* out = forces + 12 * (size_t)(start + l);
			energies[start + l] = mesh->restVolume[start + l] * batch.psi[l];
			for (int i = 0; i < 3; ++i)
			{
				out[i] = -1.0 * batch.force[0][i][l];
				for (int a = 1; a < 4; ++a)
					out[3 * a + i] = batch.force[a][i][l];
			}
		}
	}
}

void fmTetForces(const fmElasticMesh* mesh, const double* x, int first, int end, double* forces,
                 double* energies)
{
	fmPassKernels kernels;
	fmForceBatchKernelFcn* batched = fmForceBatchKernel(mesh, &kernels);
	if (batched != NULL)
	{
		fmStoreBatchedForces(mesh, x, first, end, forces, energies, &kernels, batched);
		return;
	}
	fmPolarKernelFcn* polar = fmPolarKernel(mesh);
	if (polar == NULL)
	{
		for (int t = first; t < end; ++t)
		{
			fmMat3 F = fmTetDeformation(mesh, x, t), P;
			energies[t] = mesh->restVolume[t] * fmTetEvaluate(mesh, t, &F, &P, NULL, false);
			fmStoreTetForces(mesh, t, &P, forces);
		}
		return;
	}
	for (int start = first; start < end; start += FM_POLAR_LANES)
	{
		int count = end - start < FM_POLAR_LANES ? end - start : FM_POLAR_LANES;
		fmMat3 P[FM_POLAR_LANES];
		double psi[FM_POLAR_LANES];
		fmTetStresses(mesh, x, start, count, polar, P, psi);
		for (int j = 0; j < count; ++j)
		{
			energies[start + j] = mesh->restVolume[start + j] * psi[j];
			fmStoreTetForces(mesh, start + j, &P[j], forces);
		}
	}
}

void fmGatherTetForces(const fmElasticMesh* mesh, const double* forces, int first, int end,
                       double* f)
{
	for (int i = first; i < end; ++i)
	{
		fmVec3 sum = fmLoad(f, i);
		for (int k = mesh->vertexTetStart[i]; k < mesh->vertexTetStart[i + 1]; ++k)
			sum = fmAdd(sum, fmLoad(forces, mesh->vertexTets[k])); // 3 doubles at 3 (4 t + a)
		fmStore(f, i, sum);
	}
}

double fmAddElasticForces(const fmElasticMesh* mesh, const double* x, double* f)
{
	switch (mesh->forceModel)
	{
	case fm_fvm:
		return fmAddFvmForces(mesh, x, f);
	case fm_massSpring:
		return fmAddSpringForces(mesh, x, f);
	default:
	{
		double energy = fmAddFemForces(mesh, x, f); // then the patches' (in this order)
		return fmNodalPressure_On(mesh) ? energy + fmNodalPressure_AddForces(mesh, x, f) : energy;
	}
	}
}

double fmElasticEnergy(const fmElasticMesh* mesh, const double* x)
{
	double energy = 0.0;
	if (mesh->forceModel == fm_massSpring)
	{
		return fmSpringEnergy(mesh, x);
	}
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(mesh, x, t);
		energy += mesh->restVolume[t] * fmTetEvaluate(mesh, t, &F, NULL, NULL, false);
	}
	return energy + (fmNodalPressure_On(mesh) ? fmNodalPressure_AddForces(mesh, x, NULL) : 0.0);
}

// dP/dF of the body's material at F, projected to PSD when asked (in the SVD frame where the
// material allows: ~7x cheaper than the 9x9 eigen-solver).
static void fmTetStressDerivative(const fmElasticMesh* mesh, int t, const fmMat3* F, double* dPdF,
                                  int project)
{
	if (project && (fmMaterial_StvkClampedHessian(fmTetMaterial(mesh, t), F, dPdF) ||
	                fmMaterial_NeoHookeanClampedHessian(fmTetMaterial(mesh, t), F, dPdF)))
		return;
	if (project)
		fmTetEvaluate(mesh, t, F, NULL, dPdF, true);
	else
		fmTetEvaluate(mesh, t, F, NULL, dPdF, false);
}

// K = V0 B^T (dP/dF) B with B the map from node displacements to dF (dF_ij = sum_a u_ai g_a[j]),
// contracted in two passes: T_a = (dP/dF) g_a over the second index of the stress (3 nodes),
// then K_ab = T_a^T g_b for the upper blocks a <= b (mirrored), node 0 by the balance
// g_0 = -(g_1 + g_2 + g_3): about 5x fewer operations than the direct quadruple sum.
void fmContractTetHessian(const double* dPdF, const fmMat3* DmInv, double V0, double* K)
{
	// T[a][c][d][l] = sum_j dP_cj/dF_dl g_a[j], a = 1..3, g_a = row a - 1 of Dm^-1.
	double T[4][27];
	for (int a = 1; a < 4; ++a)
	{
		const double* g = DmInv->m + 3 * (a - 1);
		for (int c = 0; c < 3; ++c)
			for (int dl = 0; dl < 9; ++dl)
				T[a][9 * c + dl] = dPdF[9 * (3 * c) + dl] * g[0] +
				                   dPdF[9 * (3 * c + 1) + dl] * g[1] +
				                   dPdF[9 * (3 * c + 2) + dl] * g[2];
	}
	for (int e = 0; e < 27; ++e)
		T[0][e] = -(T[1][e] + T[2][e] + T[3][e]);
	fmVec3 g[4];
	fmShapeGradients(DmInv, g);
	for (int a = 0; a < 4; ++a)
		for (int b = a; b < 4; ++b)
		{
			const double gb[3] = {g[b].x, g[b].y, g[b].z};
			for (int c = 0; c < 3; ++c)
				for (int d = 0; d < 3; ++d)
				{
					const double* t = T[a] + 9 * c + 3 * d;
					double v = V0 * (t[0] * gb[0] + t[1] * gb[1] + t[2] * gb[2]);
					K[12 * (3 * a + c) + (3 * b + d)] = v;
					K[12 * (3 * b + d) + (3 * a + c)] = v;
				}
		}
}

// Stores the 3x3 block (a, b) of a tet's stiffness and its mirror (b, a).
static void fmStoreTetBlock(double* K, int a, int b, const double block[9])
{
	for (int i = 0; i < 3; ++i)
		for (int k = 0; k < 3; ++k)
		{
			K[12 * (3 * a + i) + (3 * b + k)] = block[3 * i + k];
			K[12 * (3 * b + k) + (3 * a + i)] = block[3 * i + k];
		}
}

// A tet's projected stiffness straight from the clamped tangents' terms (material.h), block by
// block from the shape gradients g_a, without the 9x9 dP/dF: StVK, with f_a = F g_a,
// K_ab = V0 ((g_a . S+ g_b) I + mu (g_a . g_b) F F^T + mu f_b f_a^T + lambda f_a f_b^T);
// Neo-Hookean, with h_a = G g_a, K_ab = V0 (mu (g_a . g_b) I + k (g_a . g_b) G G^T +
// t h_b h_a^T + lambda h_a h_b^T). False where the tangents decline.
static bool fmTetBlocksClamped(const fmElasticMesh* mesh, int t, const fmMat3* F, double* K)
{
	const fmMaterial* m = fmTetMaterial(mesh, t);
	fmMat3 Sp, W;
	fmNeoHookeanTerms nh;
	const bool stvk = fmMaterial_StvkClampedTerms(m, F, &Sp);
	if (!stvk && !fmMaterial_NeoHookeanClampedTerms(m, F, &nh))
		return false;
	// StVK: M = F (the f_a), W = F F^T, the identity's weight g_a . S+ g_b; Neo-Hookean: M = G,
	// W = G G^T (weight k), the identity's weight mu (g_a . g_b).
	const fmMat3* M = stvk ? F : &nh.G;
	W = fmMatMulT(M, M);
	const double V0 = mesh->restVolume[t];
	const double wW = stvk ? m->mu : nh.k, wSwap = stvk ? m->mu : nh.t;
	fmVec3 g[4], f[4];
	fmShapeGradients(&mesh->DmInv[t], g);
	for (int a = 0; a < 4; ++a)
		f[a] = fmMatVec(M, g[a]);
	for (int a = 0; a < 4; ++a)
		for (int b = a; b < 4; ++b)
		{
			double gg = fmDot(g[a], g[b]);
			double eye = stvk ? fmDot(g[a], fmMatVec(&Sp, g[b])) : m->mu * gg;
			const double fa[3] = {f[a].x, f[a].y, f[a].z}, fb[3] = {f[b].x, f[b].y, f[b].z};
			double block[9];
			for (int i = 0; i < 3; ++i)
				for (int k = 0; k < 3; ++k)
					block[3 * i + k] = V0 * ((i == k ? eye : 0.0) + wW * gg * W.m[3 * i + k] +
					                         wSwap * fb[i] * fa[k] + m->lambda * fa[i] * fb[k]);
			fmStoreTetBlock(K, a, b, block);
		}
	return true;
}

void fmTetHessian(const fmElasticMesh* mesh, const double* x, int t, double* K, int project)
{
	fmMat3 F = fmTetDeformation(mesh, x, t);
	if (project && fmTetBlocksClamped(mesh, t, &F, K))
		return;
	double dPdF[81];
	fmTetStressDerivative(mesh, t, &F, dPdF, project);
	// K_(a c),(b d) = V0 sum_jl dP_cj/dF_dl g_a[j] g_b[l]; the projected dP/dF gives a PSD K
	// because K = V0 B^T (dP/dF) B.
	fmContractTetHessian(dPdF, &mesh->DmInv[t], mesh->restVolume[t], K);
}

void fmAddHessianProduct(const fmElasticMesh* mesh, const double* x, const double* dx, double* out,
                         int project)
{
	if (mesh->forceModel == fm_massSpring)
	{
		double K[36];
		for (int e = 0; e < mesh->edgeCount; ++e)
		{
			const int* n = mesh->edges + 2 * e;
			fmSpringHessian(mesh, x, e, K, project);
			double u[6], y[6] = {0};
			for (int k = 0; k < 3; ++k)
			{
				u[k] = dx[3 * n[0] + k];
				u[3 + k] = dx[3 * n[1] + k];
			}
			for (int r = 0; r < 6; ++r)
				for (int c = 0; c < 6; ++c)
					y[r] += K[6 * r + c] * u[c];
			for (int k = 0; k < 3; ++k)
			{
				out[3 * n[0] + k] += y[k];
				out[3 * n[1] + k] += y[3 + k];
			}
		}
		return;
	}
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(mesh, x, t);
		double dPdF[81];
		fmTetStressDerivative(mesh, t, &F, dPdF, project);
		fmVec3 g[4];
		fmShapeGradients(&mesh->DmInv[t], g);
		const int* n = mesh->tets + 4 * t;
		// dF = sum_a dx_a g_a^T; dP = dPdF : dF; out_a += V0 dP g_a.
		fmMat3 dF = fmZero3();
		for (int a = 0; a < 4; ++a)
		{
			fmVec3 u = fmLoad(dx, n[a]);
			const double ga[3] = {g[a].x, g[a].y, g[a].z};
			const double ua[3] = {u.x, u.y, u.z};
			for (int i = 0; i < 3; ++i)
				for (int j = 0; j < 3; ++j)
					dF.m[3 * i + j] += ua[i] * ga[j];
		}
		fmMat3 dP;
		for (int r = 0; r < 9; ++r)
		{
			double s = 0.0;
			for (int c = 0; c < 9; ++c)
				s += dPdF[9 * r + c] * dF.m[c];
			dP.m[r] = s;
		}
		const double V0 = mesh->restVolume[t];
		for (int a = 0; a < 4; ++a)
		{
			fmVec3 y = fmScale(V0, fmMatVec(&dP, g[a]));
			fmStore(out, n[a], fmAdd(fmLoad(out, n[a]), y));
		}
	}
	if (fmNodalPressure_On(mesh))
		fmNodalPressure_AddProduct(mesh, x, dx, out, project);
}

// ---- on the world's workers --------------------------------------------------------------------

typedef struct fmForcesTask
{
	const fmElasticMesh* mesh;
	const double* x;
	double* f;
	double* tetForces;   // 12 per tet, or NULL for energies only
	double* tetEnergies; // 1 per tet
} fmForcesTask;

static void fmTetForcesTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmForcesTask* c = context;
	fmTetForces(c->mesh, c->x, start, end, c->tetForces, c->tetEnergies);
}

static void fmTetEnergiesTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmForcesTask* c = context;
	for (int t = start; t < end; ++t)
	{
		fmMat3 F = fmTetDeformation(c->mesh, c->x, t);
		c->tetEnergies[t] =
		    c->mesh->restVolume[t] * fmTetEvaluate(c->mesh, t, &F, NULL, NULL, false);
	}
}

static void fmGatherTask(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmForcesTask* c = context;
	fmGatherTetForces(c->mesh, c->tetForces, start, end, c->f);
}

// The tets' energies summed in tet order: the serial loop's sum.
static double fmSumInOrder(const double* values, int count)
{
	double sum = 0.0;
	for (int t = 0; t < count; ++t)
		sum += values[t];
	return sum;
}

static bool fmRunsInParallel(const fmElasticMesh* mesh, const fmTaskSystem* tasks)
{
	// A body of fewer than two ranges of tets stays on the serial scatter (the same bits).
	return tasks != NULL && (tasks->workerCount > 1 || tasks->enqueueTask != NULL) &&
	       mesh->forceModel == fm_fem && mesh->tetCount >= 2 * FM_PARALLEL_MIN_RANGE;
}

double fmAddElasticForcesOn(const fmElasticMesh* mesh, const double* x, double* f,
                            const fmTaskSystem* tasks, fmArena* arena)
{
	if (!fmRunsInParallel(mesh, tasks))
		return fmAddElasticForces(mesh, x, f);
	size_t mark = fmArena_Mark(arena);
	fmForcesTask c = {mesh, x, f, fmArena_DoublesUninit(arena, 12 * (size_t)mesh->tetCount),
	                  fmArena_DoublesUninit(arena, (size_t)mesh->tetCount)};
	double energy;
	if (c.tetForces == NULL || c.tetEnergies == NULL)
		energy = fmAddElasticForces(mesh, x, f);
	else
	{
		fmParallelFor(tasks, mesh->tetCount, FM_PARALLEL_MIN_RANGE, fmTetForcesTask, &c);
		// The gather is split as the tets were (vertex ranges of as many tets' corners), so
		// each worker mostly reads the forces it wrote (docs/decisions.md, "Parallel gathers").
		int vertexRange =
		    (int)((int64_t)FM_PARALLEL_MIN_RANGE * mesh->vertexCount / mesh->tetCount);
		fmParallelFor(tasks, mesh->vertexCount, vertexRange > 1 ? vertexRange : 1, fmGatherTask,
		              &c);
		energy = fmSumInOrder(c.tetEnergies, mesh->tetCount);
		if (fmNodalPressure_On(mesh)) // (serial: the same bits as fmAddElasticForces)
			energy += fmNodalPressure_AddForces(mesh, x, f);
	}
	fmArena_Release(arena, mark);
	return energy;
}

double fmElasticEnergyOn(const fmElasticMesh* mesh, const double* x, const fmTaskSystem* tasks,
                         fmArena* arena)
{
	if (!fmRunsInParallel(mesh, tasks))
		return fmElasticEnergy(mesh, x);
	size_t mark = fmArena_Mark(arena);
	fmForcesTask c = {mesh, x, NULL, NULL, fmArena_DoublesUninit(arena, (size_t)mesh->tetCount)};
	double energy;
	if (c.tetEnergies == NULL)
		energy = fmElasticEnergy(mesh, x);
	else
	{
		fmParallelFor(tasks, mesh->tetCount, FM_PARALLEL_MIN_RANGE, fmTetEnergiesTask, &c);
		energy = fmSumInOrder(c.tetEnergies, mesh->tetCount);
		if (fmNodalPressure_On(mesh))
			energy += fmNodalPressure_AddForces(mesh, x, NULL);
	}
	fmArena_Release(arena, mark);
	return energy;
}
