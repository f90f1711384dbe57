// Isotropic energies written in the signed principal stretches s = (s0, s1, s2) of F = U diag(s)
// V^T (fmSvd3; s2 < 0 for an inverted tet): fixed corotated and the user's stretch energy. One assembly turns psi(s), its gradient and
// Hessian into P and dP/dF (Irving, Teran, Fedkiw 2004; Teran, Sifakis, Irving, Fedkiw 2005):
//   P = U diag(dpsi) V^T,
//   dP/dF = sum_ab d2psi_ab (u_a v_a^T)(u_b v_b^T)^T                      (stretch block)
//         + sum_{i<j} q_ij f_ij f_ij^T + r_ij t_ij t_ij^T                   (flip and twist)
// with f_ij, t_ij = (u_i v_j^T +- u_j v_i^T) / sqrt 2, q_ij = (dpsi_i - dpsi_j) / (s_i - s_j) and
// r_ij = (dpsi_i + dpsi_j) / (s_i + s_j).
#include "material.h"
#include "material_models.h"
#include "svd3.h"

#include <string.h>

// Relative gap below which two stretches count as equal in q_ij (the difference quotient
// becomes its limit). sqrt(machine epsilon) balances cancellation against truncation.
#define FM_STRETCH_GAP 1e-8

// Fixed corotated (Stomakhin et al. 2012): psi = mu sum (s_i - 1)^2 + lambda/2 (J - 1)^2, i.e.
// mu |F - R|^2 + lambda/2 (det F - 1)^2.
static double fmCorotatedStretch(const fmMaterial* m, const double s[3], double g[3], double* H)
{
	double J = s[0] * s[1] * s[2];
	double dJ[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
	double psi = 0.5 * m->lambda * (J - 1.0) * (J - 1.0);
	for (int i = 0; i < 3; ++i)
	{
		psi += m->mu * (s[i] - 1.0) * (s[i] - 1.0);
		g[i] = 2.0 * m->mu * (s[i] - 1.0) + m->lambda * (J - 1.0) * dJ[i];
	}
	if (H)
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
			{
				double v = m->lambda * dJ[i] * dJ[j];
				if (i == j)
					v += 2.0 * m->mu;
				else
					v += m->lambda * (J - 1.0) * s[3 - i - j]; // d2J/ds_i ds_j = the third stretch
				H[3 * i + j] = v;
			}
	return psi;
}

// psi(s), gradient and (when H is not NULL) Hessian of the material's stretch energy.
static double fmStretchEnergy(const fmMaterial* m, const double s[3], double g[3], double* H)
{
	switch (m->model)
	{
	case fm_corotated:
		return fmCorotatedStretch(m, s, g, H);
	default:
	{
		double psi = 0.0;
		g[0] = g[1] = g[2] = 0.0;
		if (H)
			memset(H, 0, 9 * sizeof(double));
		m->stretchEnergy(s, m->userParams, &psi, g, H);
		return psi;
	}
	}
}

// Adds w * a b^T to the 9x9 matrix A (a, b as vec of 3x3 row-major matrices).
static void fmAddOuter9(double* A, double w, const double* a, const double* b)
{
	if (w == 0.0)
		return;
	for (int r = 0; r < 9; ++r)
	{
		double wa = w * a[r];
		for (int c = 0; c < 9; ++c)
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

static void fmAssembleStretchHessian(const fmMat3* U, const fmMat3* V, const double s[3],
									 const double g[3], const double H[9], double* dPdF)
{
	memset(dPdF, 0, 81 * sizeof(double));
	double d[3][9];
	for (int a = 0; a < 3; ++a)
		fmDyad(U, V, a, a, d[a]);
	for (int a = 0; a < 3; ++a)
		for (int b = 0; b < 3; ++b)
			fmAddOuter9(dPdF, H[3 * a + b], d[a], d[b]);

	double scale = fmax(fabs(s[0]), 1e-150); // s[0] has the largest magnitude
	double gap = FM_STRETCH_GAP * scale;
	static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
	for (int k = 0; k < 3; ++k)
	{
		int i = pairs[k][0], j = pairs[k][1];
		// Flip mode: q -> d2psi_ii - d2psi_ij as s_i -> s_j (psi is symmetric).
		double q = s[i] - s[j] > gap ? (g[i] - g[j]) / (s[i] - s[j])
									 : 0.5 * (H[3 * i + i] + H[3 * j + j]) - H[3 * i + j];
		// Twist mode: s_i + s_j >= 0 by the ordering; it vanishes only where the rotation of F is
		// undefined (s_i = -s_j), where the bounded denominator keeps dP/dF finite.
		double r = (g[i] + g[j]) / fmax(s[i] + s[j], gap);
		double ij[9], ji[9], f[9], t[9];
		fmDyad(U, V, i, j, ij);
		fmDyad(U, V, j, i, ji);
		for (int e = 0; e < 9; ++e)
		{
			f[e] = (ij[e] + ji[e]) * 0.70710678118654752440;
			t[e] = (ij[e] - ji[e]) * 0.70710678118654752440;
		}
		fmAddOuter9(dPdF, q, f, f);
		fmAddOuter9(dPdF, r, t, t);
	}
}

double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF)
{
	fmMat3 U, V;
	fmVec3 sv;
	fmSvd3(F, &U, &sv, &V);
	const double s[3] = {sv.x, sv.y, sv.z};
	double g[3], H[9];
	double psi = fmStretchEnergy(material, s, g, dPdF ? H : NULL);
	if (P)
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
				P->m[3 * i + j] = U.m[3 * i] * g[0] * V.m[3 * j] + U.m[3 * i + 1] * g[1] * V.m[3 * j + 1] +
								  U.m[3 * i + 2] * g[2] * V.m[3 * j + 2];
	if (dPdF)
		fmAssembleStretchHessian(&U, &V, s, g, H, dPdF);
	return psi;
}
