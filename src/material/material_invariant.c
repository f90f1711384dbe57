// Energies of the invariants v = (I1, I2, J): compressible Neo-Hookean and Mooney-Rivlin (with
// ln J continued below FM_LOG_J_CLAMP) and the user's invariant energy. By the chain rule:
//   I1 = F:F                         dI1/dF = 2 F
//   I2 = ((tr C)^2 - C:C) / 2        dI2/dF = 2 (I1 F - F C),  C = F^T F
//   J  = det F                       dJ/dF  = cof F
// P = sum_a psi_a dv_a/dF and dP/dF = sum_ab psi_ab dv_a/dF (dv_b/dF)^T + sum_a psi_a d2v_a/dF2.
#include "material/material_invariant.h"
#include "core/det_math.h"
#include "material/material.h"
#include "material/material_stretch.h"

#include <string.h>

// Levi-Civita sign of a permutation (a, b, c) of (0, 1, 2).
static double fmPermutationSign(int a, int b)
{
	return (b - a + 3) % 3 == 1 ? 1.0 : -1.0;
}

void fmAddInvariantCurvature(const fmMat3* F, double I1, const double w[3], double* dPdF)
{
	const double* f = F->m;
	fmMat3 C = fmMatTMul(F, F), B = fmMatMulT(F, F);
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			for (int k = 0; k < 3; ++k)
				for (int l = 0; l < 3; ++l)
				{
					int ik = i == k, jl = j == l;
					// d2 I1 = 2 d_ik d_jl
					double h1 = 2.0 * ik * jl;
					// d2 I2 = 2 (2 F_ij F_kl + I1 d_ik d_jl - d_ik C_lj - F_il F_kj - B_ik d_jl)
					double h2 = 2.0 * (2.0 * f[3 * i + j] * f[3 * k + l] + I1 * ik * jl -
					                   ik * C.m[3 * l + j] - f[3 * i + l] * f[3 * k + j] -
					                   B.m[3 * i + k] * jl);
					// d2 J / dF_ij dF_kl = eps_ikq eps_jls F_qs
					double h3 = 0.0;
					if (i != k && j != l)
						h3 = fmPermutationSign(i, k) * fmPermutationSign(j, l) *
						     f[3 * (3 - i - k) + (3 - j - l)];
					dPdF[9 * (3 * i + j) + (3 * k + l)] += w[0] * h1 + w[1] * h2 + w[2] * h3;
				}
}

// ln J for J >= FM_LOG_J_CLAMP, continued below by its second-order Taylor polynomial at the
// clamp: C2, finite for J <= 0, increasing and concave there, so -mu lnJ + lambda/2 lnJ^2 keeps
// growing as a tet collapses and inverts and its gradient (along cof F) pushes it back.
// out = {l, l', l''}.
void fmClampedLogJ(double J, double out[3])
{
	const double c = FM_LOG_J_CLAMP;
	if (J >= c)
	{
		out[0] = fmMathLog(J); // det_math.h: femto's own log in deterministic mode
		out[1] = 1.0 / J;
		out[2] = -1.0 / (J * J);
		return;
	}
	double d = J - c;
	out[0] = fmMathLog(c) + d / c - d * d / (2.0 * c * c);
	out[1] = 1.0 / c - d / (c * c);
	out[2] = -1.0 / (c * c);
}

// Compressible Mooney-Rivlin (docs/materials.md), params = {lambda, mu, c01}:
// psi = C10 (I1 - 3) + C01 (I2 - 3) - (mu + 2 C01) l(J) + (lambda - 4 C01)/2 l(J)^2,
// C10 = mu/2 - C01. Linear elasticity with (lambda, mu) at small strain; C01 = 0 is the
// classic compressible Neo-Hookean mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2.
static void fmMooneyRivlinEnergy(const double v[3], const void* params, double* psi, double dpsi[3],
                                 double* d2psi)
{
	const double* p = (const double*)params;
	double lambda = p[0], mu = p[1], c01 = p[2];
	double c10 = 0.5 * mu - c01, a = mu + 2.0 * c01, b = lambda - 4.0 * c01;
	double l[3];
	fmClampedLogJ(v[2], l);
	*psi = c10 * (v[0] - 3.0) + c01 * (v[1] - 3.0) - a * l[0] + 0.5 * b * l[0] * l[0];
	dpsi[0] = c10;
	dpsi[1] = c01;
	dpsi[2] = (b * l[0] - a) * l[1];
	if (d2psi)
	{
		memset(d2psi, 0, 9 * sizeof(double));
		d2psi[8] = b * l[1] * l[1] + (b * l[0] - a) * l[2];
	}
}

// J^-2/3 for J >= FM_LOG_J_CLAMP, continued below by its second-order Taylor polynomial at the
// clamp (as ln J in fmClampedLogJ): C2, finite for J <= 0, and decreasing there (the parabola's
// vertex lies at 1.6 times the clamp), so the isochoric term C10 g(J) I1 keeps growing as a tet
// collapses and inverts. out = {g, g', g''}.
static void fmClampedIsochoric(double J, double out[3])
{
	const double c = FM_LOG_J_CLAMP;
	double at = J >= c ? J : c;
	double g = fmMathPow(at, -2.0 / 3.0);
	double g1 = -2.0 / 3.0 * g / at, g2 = 10.0 / 9.0 * g / (at * at);
	if (J >= c)
	{
		out[0] = g;
		out[1] = g1;
		out[2] = g2;
		return;
	}
	double d = J - c;
	out[0] = g + g1 * d + 0.5 * g2 * d * d;
	out[1] = g1 + g2 * d;
	out[2] = g2;
}

// CalculiX's and Abaqus's Neo-Hookean, params = {lambda, mu}: the isochoric split
// psi = C10 (J^-2/3 I1 - 3) + (J - 1)^2 / D1 with C10 = mu/2 and 1/D1 = kappa/2,
// kappa = lambda + 2/3 mu the bulk modulus: linear elasticity with (lambda, mu) at small strain.
static void fmIsochoricNeoHookeanEnergy(const double v[3], const void* params, double* psi,
                                        double dpsi[3], double* d2psi)
{
	const double* p = (const double*)params;
	double c10 = 0.5 * p[1], halfKappa = 0.5 * (p[0] + 2.0 / 3.0 * p[1]);
	double g[3];
	fmClampedIsochoric(v[2], g);
	double dJ = v[2] - 1.0;
	*psi = c10 * (g[0] * v[0] - 3.0) + halfKappa * dJ * dJ;
	dpsi[0] = c10 * g[0];
	dpsi[1] = 0.0;
	dpsi[2] = c10 * g[1] * v[0] + 2.0 * halfKappa * dJ;
	if (d2psi)
	{
		memset(d2psi, 0, 9 * sizeof(double));
		d2psi[2] = d2psi[6] = c10 * g[1];
		d2psi[8] = c10 * g[2] * v[0] + 2.0 * halfKappa;
	}
}

double fmInvariantModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                                 double* dPdF)
{
	fmInvariantEnergyFcn* energy = material->invariantEnergy;
	const void* params = material->userParams;
	double builtin[3] = {material->lambda, material->mu, 0.0};
	if (material->model != fm_invariantEnergy)
	{
		if (material->model == fm_mooneyRivlin)
			builtin[2] = material->c01;
		energy = material->model == fm_neoHookeanIsochoric ? fmIsochoricNeoHookeanEnergy
		                                                   : fmMooneyRivlinEnergy;
		params = builtin;
	}

	fmMat3 C = fmMatTMul(F, F);
	double I1 = fmTrace(&C);
	double v[3] = {I1, 0.5 * (I1 * I1 - fmDDot(&C, &C)), fmDet(F)};
	double psi = 0.0, g[3] = {0, 0, 0}, H[9];
	if (dPdF)
		memset(H, 0, sizeof H);
	energy(v, params, &psi, g, dPdF ? H : NULL);
	if (!P && !dPdF)
		return psi;

	fmMat3 FC = fmMatMul(F, &C);
	fmMat3 d[3];
	d[0] = fmMatScale(2.0, F);
	d[1] = fmMatMulAdd(&FC, -I1, F);
	d[1] = fmMatScale(-2.0, &d[1]); // 2 (I1 F - F C)
	d[2] = fmCofactor(F);
	if (P)
		for (int e = 0; e < 9; ++e)
			P->m[e] = g[0] * d[0].m[e] + g[1] * d[1].m[e] + g[2] * d[2].m[e];
	if (dPdF)
	{
		memset(dPdF, 0, 81 * sizeof(double));
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
			{
				double w = H[3 * a + b];
				if (w == 0.0)
					continue;
				for (int r = 0; r < 9; ++r)
					for (int c = 0; c < 9; ++c)
						dPdF[9 * r + c] += w * d[a].m[r] * d[b].m[c];
			}
		fmAddInvariantCurvature(F, I1, g, dPdF);
	}
	return psi;
}
