// Isotropic energies written in the signed principal stretches s = (s0, s1, s2) of F = U diag(s)
// V^T (fmSvd3; s2 < 0 for an inverted tet): fixed corotated and the user's stretch energy, and
// Neo-Hookean / Mooney-Rivlin / StVK when a projected tangent is wanted (their eigen-structure is
// explicit here). One assembly turns psi(s), its gradient and Hessian into P and dP/dF
// (Irving, Teran, Fedkiw 2004; Teran, Sifakis, Irving, Fedkiw 2005):
//   P = U diag(dpsi) V^T,
//   dP/dF = sum_ab d2psi_ab (u_a v_a^T)(u_b v_b^T)^T                      (stretch block)
//         + sum_{i<j} q_ij f_ij f_ij^T + r_ij t_ij t_ij^T                   (flip and twist)
// with f_ij, t_ij = (u_i v_j^T +- u_j v_i^T) / sqrt 2, q_ij = (dpsi_i - dpsi_j) / (s_i - s_j) and
// r_ij = (dpsi_i + dpsi_j) / (s_i + s_j).
#include "material/material_stretch.h"
#include "core/det_math.h"
#include "material/material.h"
#include "material/material_invariant.h"
#include "math/svd3.h"

#include <string.h>

// What a stretch energy gives the assembly: psi, gradient g, Hessian H and, when hasModes, the
// flip and twist eigenvalues q_ij = (g_i - g_j)/(s_i - s_j), r_ij = (g_i + g_j)/(s_i + s_j) in
// closed form (pairs 01, 02, 12), free of cancellation and of the guards needed otherwise.
typedef struct fmStretchDerivs
{
	double psi, g[3], H[9], q[3], r[3];
	bool hasModes;
} fmStretchDerivs;

static const int s_pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

// Fixed corotated (Stomakhin et al. 2012): psi = mu sum (s_i - 1)^2 + lambda/2 (J - 1)^2, i.e.
// mu |F - R|^2 + lambda/2 (det F - 1)^2.
static void fmCorotatedStretch(const fmMaterial* m, const double s[3], bool hessian,
                               fmStretchDerivs* d)
{
	double J = s[0] * s[1] * s[2];
	double dJ[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
	d->psi = 0.5 * m->lambda * (J - 1.0) * (J - 1.0);
	for (int i = 0; i < 3; ++i)
	{
		d->psi += m->mu * (s[i] - 1.0) * (s[i] - 1.0);
		d->g[i] = 2.0 * m->mu * (s[i] - 1.0) + m->lambda * (J - 1.0) * dJ[i];
	}
	if (!hessian)
		return;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			double v = m->lambda * dJ[i] * dJ[j];
			if (i == j)
				v += 2.0 * m->mu;
			else
				v += m->lambda * (J - 1.0) * s[3 - i - j]; // d2J/ds_i ds_j = the third stretch
			d->H[3 * i + j] = v;
		}
	for (int k = 0; k < 3; ++k)
	{
		int i = s_pairs[k][0], j = s_pairs[k][1];
		double sk = s[3 - i - j];
		d->q[k] = 2.0 * m->mu - m->lambda * (J - 1.0) * sk;
		// -4 mu / (s_i + s_j) is the rotation's own singularity (s_i = -s_j); bounded there.
		d->r[k] = 2.0 * m->mu + m->lambda * (J - 1.0) * sk -
		          4.0 * m->mu / fmMax(s[i] + s[j], FM_STRETCH_GAP * fmMax(fabs(s[0]), 1e-150));
	}
	d->hasModes = true;
}

// The Neo-Hookean / Mooney-Rivlin energy of material_invariant.c written in the stretches
// (I1 = sum s^2, I2 = sum_{i<j} s_i^2 s_j^2, J = s0 s1 s2), for the analytic PSD projection:
// psi = C10 (I1 - 3) + C01 (I2 - 3) - a l(J) + b/2 l(J)^2.
static void fmMooneyRivlinStretch(const fmMaterial* m, const double s[3], bool hessian,
                                  fmStretchDerivs* d)
{
	double c01 = m->model == fm_mooneyRivlin ? m->c01 : 0.0;
	double c10 = 0.5 * m->mu - c01, a = m->mu + 2.0 * c01, b = m->lambda - 4.0 * c01;
	double J = s[0] * s[1] * s[2];
	double dJ[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
	double l[3], sq[3] = {s[0] * s[0], s[1] * s[1], s[2] * s[2]};
	fmClampedLogJ(J, l);
	double I1 = sq[0] + sq[1] + sq[2];
	double I2 = sq[0] * sq[1] + sq[0] * sq[2] + sq[1] * sq[2];
	double kappa = (b * l[0] - a) * l[1];                    // d psi / dJ
	double kappa2 = b * l[1] * l[1] + (b * l[0] - a) * l[2]; // d2 psi / dJ2
	d->psi = c10 * (I1 - 3.0) + c01 * (I2 - 3.0) - a * l[0] + 0.5 * b * l[0] * l[0];
	for (int i = 0; i < 3; ++i)
		d->g[i] = 2.0 * c10 * s[i] + 2.0 * c01 * s[i] * (I1 - sq[i]) + kappa * dJ[i];
	if (!hessian)
		return;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			double v = kappa2 * dJ[i] * dJ[j];
			if (i == j)
				v += 2.0 * c10 + 2.0 * c01 * (I1 - sq[i]);
			else
				v += 4.0 * c01 * s[i] * s[j] + kappa * s[3 - i - j];
			d->H[3 * i + j] = v;
		}
	for (int k = 0; k < 3; ++k)
	{
		int i = s_pairs[k][0], j = s_pairs[k][1];
		double sk = s[3 - i - j];
		d->q[k] = 2.0 * c10 + 2.0 * c01 * (sk * sk - s[i] * s[j]) - kappa * sk;
		d->r[k] = 2.0 * c10 + 2.0 * c01 * (sk * sk + s[i] * s[j]) + kappa * sk;
	}
	d->hasModes = true;
}

// St. Venant-Kirchhoff in the stretches (G = diag(s_i^2 - 1)/2), for the analytic projection:
// psi = mu/4 sum (s_i^2 - 1)^2 + lambda/8 (I1 - 3)^2.
static void fmStvkStretch(const fmMaterial* m, const double s[3], bool hessian, fmStretchDerivs* d)
{
	double sq[3] = {s[0] * s[0], s[1] * s[1], s[2] * s[2]};
	double trG2 = sq[0] + sq[1] + sq[2] - 3.0; // 2 tr G
	d->psi = 0.125 * m->lambda * trG2 * trG2;
	for (int i = 0; i < 3; ++i)
	{
		d->psi += 0.25 * m->mu * (sq[i] - 1.0) * (sq[i] - 1.0);
		d->g[i] = m->mu * s[i] * (sq[i] - 1.0) + 0.5 * m->lambda * trG2 * s[i];
	}
	if (!hessian)
		return;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			d->H[3 * i + j] = m->lambda * s[i] * s[j] +
			                  (i == j ? m->mu * (3.0 * sq[i] - 1.0) + 0.5 * m->lambda * trG2 : 0.0);
	for (int k = 0; k < 3; ++k)
	{
		int i = s_pairs[k][0], j = s_pairs[k][1];
		double common = m->mu * (sq[i] + sq[j] - 1.0) + 0.5 * m->lambda * trG2;
		d->q[k] = common + m->mu * s[i] * s[j];
		d->r[k] = common - m->mu * s[i] * s[j];
	}
	d->hasModes = true;
}

// StVK's volume floor (material.h) in principal stretches: psi(J), J = s0 s1 s2, adds
// psi' J / s_i to g_i, psi'' (J/s_i)(J/s_j) + psi' s_k (i != j, k the third) to H_ij, and to the
// pair (i, j)'s flip -psi' s_k and twist psi' s_k ((g_i -/+ g_j) / (s_i -/+ s_j) of psi(J)).
static void fmStvkFloorStretch(const fmMaterial* m, const double s[3], bool hessian,
                               fmStretchDerivs* d)
{
	double f[3];
	if (!fmMaterial_StvkFloor(m, s[0] * s[1] * s[2], f))
		return;
	const double others[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]}; // J / s_i
	d->psi += f[0];
	for (int i = 0; i < 3; ++i)
		d->g[i] += f[1] * others[i];
	if (!hessian)
		return;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			d->H[3 * i + j] += f[2] * others[i] * others[j] + (i == j ? 0.0 : f[1] * s[3 - i - j]);
	for (int k = 0; k < 3; ++k)
	{
		int third = 3 - s_pairs[k][0] - s_pairs[k][1];
		d->q[k] -= f[1] * s[third];
		d->r[k] += f[1] * s[third];
	}
}

static void fmStretchEnergy(const fmMaterial* m, const double s[3], bool hessian,
                            fmStretchDerivs* d)
{
	memset(d, 0, sizeof *d);
	switch (m->model)
	{
	case fm_corotated:
		fmCorotatedStretch(m, s, hessian, d);
		break;
	case fm_neoHookean:
	case fm_mooneyRivlin:
		fmMooneyRivlinStretch(m, s, hessian, d);
		break;
	case fm_stvk:
		fmStvkStretch(m, s, hessian, d);
		fmStvkFloorStretch(m, s, hessian, d);
		break;
	default:
		m->stretchEnergy(s, m->userParams, &d->psi, d->g, hessian ? d->H : NULL);
		break;
	}
}

// Flip and twist eigenvalues from the gradient where the energy has no closed form for them.
static void fmGuardedModes(const double s[3], fmStretchDerivs* d)
{
	double gap = FM_STRETCH_GAP * fmMax(fabs(s[0]), 1e-150); // s[0] has the largest magnitude
	const double* g = d->g;
	const double* H = d->H;
	for (int k = 0; k < 3; ++k)
	{
		int i = s_pairs[k][0], j = s_pairs[k][1];
		// Flip: q -> d2psi_ii - d2psi_ij as s_i -> s_j (psi is symmetric).
		d->q[k] = s[i] - s[j] > gap ? (g[i] - g[j]) / (s[i] - s[j])
		                            : 0.5 * (H[3 * i + i] + H[3 * j + j]) - H[3 * i + j];
		// Twist: s_i + s_j >= 0 by the ordering; it vanishes only where the rotation of F is
		// undefined (s_i = -s_j), where the bounded denominator keeps dP/dF finite.
		d->r[k] = (g[i] + g[j]) / fmMax(s[i] + s[j], gap);
	}
}

// Adds w * a b^T to the upper triangle (c >= r) of the 9x9 matrix A (a, b as vec of 3x3
// row-major matrices). The assembled dP/dF is symmetric, so the lower half is mirrored at the end.
static void fmAddOuter9Upper(double* A, double w, const double* a, const double* b)
{
	if (w == 0.0)
		return;
	for (int r = 0; r < 9; ++r)
	{
		double wa = w * a[r];
		for (int c = r; c < 9; ++c)
			A[9 * r + c] += wa * b[c];
	}
}

// q[ij] = (u_a v_b^T)_ij = U_ia V_jb.
static void fmDyad(const fmMat3* U, const fmMat3* V, int a, int b, double* q)
{
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			q[3 * i + j] = U->m[3 * i + a] * V->m[3 * j + b];
}

// dP/dF from its eigen-structure; with project, every mode's eigenvalue is clamped at zero,
// which is exactly the nearest PSD matrix because the modes are orthonormal.
static void fmAssembleStretchHessian(const fmMat3* U, const fmMat3* V, const fmStretchDerivs* d,
                                     bool project, double* dPdF)
{
	memset(dPdF, 0, 81 * sizeof(double));
	fmMat3 Hm;
	memcpy(Hm.m, d->H, sizeof Hm.m);
	double* H = Hm.m;
	// Sylvester's criterion: a positive definite stretch block needs no eigen-decomposition.
	bool positive = H[0] > 0.0 && H[0] * H[4] - H[1] * H[3] > 0.0 && fmDet(&Hm) > 0.0;
	if (project && !positive)
	{
		fmMat3 Q;
		fmVec3 w;
		fmSymEigen3(&Hm, &w, &Q);
		double wc[3] = {fmMax(w.x, 0.0), fmMax(w.y, 0.0), fmMax(w.z, 0.0)};
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
				H[3 * i + j] = Q.m[3 * i] * wc[0] * Q.m[3 * j] +
				               Q.m[3 * i + 1] * wc[1] * Q.m[3 * j + 1] +
				               Q.m[3 * i + 2] * wc[2] * Q.m[3 * j + 2];
	}
	double D[3][9];
	for (int a = 0; a < 3; ++a)
		fmDyad(U, V, a, a, D[a]);
	for (int a = 0; a < 3; ++a)
		for (int b = 0; b < 3; ++b)
			fmAddOuter9Upper(dPdF, H[3 * a + b], D[a], D[b]);

	for (int k = 0; k < 3; ++k)
	{
		int i = s_pairs[k][0], j = s_pairs[k][1];
		double q = project ? fmMax(d->q[k], 0.0) : d->q[k];
		double r = project ? fmMax(d->r[k], 0.0) : d->r[k];
		double ij[9], ji[9], f[9], t[9];
		fmDyad(U, V, i, j, ij);
		fmDyad(U, V, j, i, ji);
		for (int e = 0; e < 9; ++e)
		{
			f[e] = (ij[e] + ji[e]) * 0.70710678118654752440;
			t[e] = (ij[e] - ji[e]) * 0.70710678118654752440;
		}
		fmAddOuter9Upper(dPdF, q, f, f);
		fmAddOuter9Upper(dPdF, r, t, t);
	}
	for (int r = 1; r < 9; ++r)
		for (int c = 0; c < r; ++c)
			dPdF[9 * r + c] = dPdF[9 * c + r];
}

// Fixed corotated without the SVD, for psi and P only: psi = mu |F - R|^2 + lambda/2 (J - 1)^2,
// P = 2 mu (F - R) + lambda (J - 1) cof F.
double fmCorotated_Stress(const fmMaterial* m, const fmMat3* F, const fmMat3* R, fmMat3* P)
{
	fmMat3 D = fmMatMulAdd(F, -1.0, R);
	double J = fmDet(F);
	if (P)
	{
		fmMat3 C = fmCofactor(F);
		for (int k = 0; k < 9; ++k)
			P->m[k] = 2.0 * m->mu * D.m[k] + m->lambda * (J - 1.0) * C.m[k];
	}
	return m->mu * fmDDot(&D, &D) + 0.5 * m->lambda * (J - 1.0) * (J - 1.0);
}

// With R from fmPolarRotationFast (the same R = U V^T as the SVD's when det F > 0). False where
// that declines F.
static bool fmCorotatedByPolar(const fmMaterial* m, const fmMat3* F, fmMat3* P, double* psi)
{
	fmMat3 R;
	if (!fmPolarRotationFast(F, &R))
		return false;
	*psi = fmCorotated_Stress(m, F, &R, P);
	return true;
}

double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF,
                               bool project)
{
	// Corotated psi and P come from the polar path wherever it takes F, whatever else is asked
	// for (psi must not depend on the outputs requested); the SVD then only serves dP/dF.
	double polarPsi;
	bool polar = material->model == fm_corotated && fmCorotatedByPolar(material, F, P, &polarPsi);
	if (polar && dPdF == NULL)
		return polarPsi;
	fmMat3 U, V;
	fmVec3 sv;
	fmSvd3(F, &U, &sv, &V);
	const double s[3] = {sv.x, sv.y, sv.z};
	fmStretchDerivs d;
	fmStretchEnergy(material, s, dPdF != NULL, &d);
	if (P && !polar)
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
				P->m[3 * i + j] = U.m[3 * i] * d.g[0] * V.m[3 * j] +
				                  U.m[3 * i + 1] * d.g[1] * V.m[3 * j + 1] +
				                  U.m[3 * i + 2] * d.g[2] * V.m[3 * j + 2];
	if (dPdF)
	{
		if (!d.hasModes)
			fmGuardedModes(s, &d);
		fmAssembleStretchHessian(&U, &V, &d, project, dPdF);
	}
	return polar ? polarPsi : d.psi;
}
