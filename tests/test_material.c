// Constitutive models: stress = energy gradient and tangent = stress derivative (central finite
// differences) on random, near-singular, inverted and large deformations; rest state; rotation
// invariance and isotropy; small-strain agreement with linear elasticity; user energies; the
// inversion response; the PSD projection; parameters, validation and names.
#include "material/material.h"
#include "material/material_aniso.h"
#include "material/material_invariant.h"
#include "material/material_stretch.h"
#include "math/svd3.h"
#include "support.h"
#include "test.h"

#include <string.h>

// ---- helpers -----------------------------------------------------------------------------------

// R1 diag(a, b, c) R2 with random rotations.
static fmMat3 withStretches(double a, double b, double c)
{
	fmMat3 R1 = fmTestRandomRotation(), R2 = fmTestRandomRotation();
	fmMat3 D = {{a, 0, 0, 0, b, 0, 0, 0, c}};
	fmMat3 T = fmMatMul(&R1, &D);
	return fmMatMul(&T, &R2);
}

enum
{
	kGeneral,      // stretches in [0.6, 1.6]
	kNearSingular, // det ~ 1e-3
	kInverted,     // det < 0
	kLarge,        // stretches up to 3
	kKindCount
};
static const char* const s_kindNames[kKindCount] = {"general", "near-singular", "inverted",
                                                    "large"};

static fmMat3 randomF(int kind)
{
	switch (kind)
	{
	case kNearSingular:
		return withStretches(fmTestRandom(1.0, 1.5), fmTestRandom(0.6, 0.9),
		                     fmTestRandom(1e-3, 2e-3));
	case kInverted:
		return withStretches(fmTestRandom(1.1, 1.5), fmTestRandom(0.6, 1.0),
		                     -fmTestRandom(0.05, 0.5));
	case kLarge:
		return withStretches(fmTestRandom(2.0, 3.0), fmTestRandom(1.2, 1.8),
		                     fmTestRandom(0.4, 0.8));
	default:
		return withStretches(fmTestRandom(1.1, 1.6), fmTestRandom(0.85, 1.05),
		                     fmTestRandom(0.6, 0.8));
	}
}

// Neo-Hookean written by a user, as a function of the principal stretches (needs s > 0).
static void userNeoHookeanStretch(const double s[3], const void* params, double* psi,
                                  double dpsi[3], double* d2psi)
{
	const double* lm = (const double*)params; // lambda, mu
	double lnJ = log(s[0]) + log(s[1]) + log(s[2]);
	*psi = 0.5 * lm[1] * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] - 3.0) - lm[1] * lnJ +
	       0.5 * lm[0] * lnJ * lnJ;
	for (int i = 0; i < 3; ++i)
		dpsi[i] = lm[1] * s[i] + (lm[0] * lnJ - lm[1]) / s[i];
	if (d2psi)
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
				d2psi[3 * i + j] = lm[0] / (s[i] * s[j]) +
				                   (i == j ? lm[1] + (lm[1] - lm[0] * lnJ) / (s[i] * s[i]) : 0.0);
}

// The same Neo-Hookean as a function of the invariants (I1, I2, J) (needs J > 0).
static void userNeoHookeanInvariant(const double v[3], const void* params, double* psi,
                                    double dpsi[3], double* d2psi)
{
	const double* lm = (const double*)params;
	double lnJ = log(v[2]);
	*psi = 0.5 * lm[1] * (v[0] - 3.0) - lm[1] * lnJ + 0.5 * lm[0] * lnJ * lnJ;
	dpsi[0] = 0.5 * lm[1];
	dpsi[1] = 0.0;
	dpsi[2] = (lm[0] * lnJ - lm[1]) / v[2];
	if (d2psi)
	{
		for (int k = 0; k < 9; ++k)
			d2psi[k] = 0.0;
		d2psi[8] = (lm[0] + lm[1] - lm[0] * lnJ) / (v[2] * v[2]);
	}
}

static const double s_lameNH[2] = {4e4, 1e4}; // lambda, mu for the user energies

static fmMaterial testMaterial(fmMaterialModel model)
{
	fmMaterial m = fmMakeMaterialLame(model, s_lameNH[0], s_lameNH[1]);
	m.stretchEnergy = userNeoHookeanStretch;
	m.invariantEnergy = userNeoHookeanInvariant;
	m.userParams = s_lameNH;
	if (model == fm_mooneyRivlin)
		m.c01 = 0.2 * m.mu; // away from the default so the I2 term is well exercised
	if (fmMaterialModel_IsOrthotropic(model))
	{
		// A strongly orthotropic solid (a wood-like 10:1 contrast) with turned axes.
		fmOrthotropy o = {{3e5, 5e4, 3e4}, {0.35, 0.4, 0.3}, {2e4, 1.5e4, 1e4}};
		m = fmMakeOrthotropicMaterial(model, o);
	}
	if (fmMaterialModel_IsAnisotropic(model))
	{
		m.fibre = fmMakeVec3(1.0, 2.0, 0.5);
		m.sheet = fmMakeVec3(0.0, 0.3, 1.0);
		m.fibreStiffness = 3e4;
	}
	return m;
}

// Models defined for det F <= 0 (the user energies above use ln and are not).
static bool supportsInversion(fmMaterialModel model)
{
	return model != fm_stretchEnergy && model != fm_invariantEnergy;
}

static double maxAbs(const double* a, int n)
{
	double m = 0.0;
	for (int k = 0; k < n; ++k)
		m = fmax(m, fabs(a[k]));
	return m;
}

// ---- derivatives -------------------------------------------------------------------------------

TEST(rest_state_is_stress_free)
{
	for (int model = 0; model < fm_materialModelCount; ++model)
	{
		fmMaterial m = testMaterial((fmMaterialModel)model);
		fmMat3 F = fmIdentity3(), P;
		double dPdF[81];
		double psi = fmMaterial_Evaluate(&m, &F, &P, dPdF);
		CHECK_NEAR(psi, 0.0, 1e-12 * m.mu);
		CHECK_NEAR(maxAbs(P.m, 9), 0.0, 1e-12 * m.mu);
		CHECK(isfinite(maxAbs(dPdF, 81)));
	}
}

TEST(stress_is_energy_gradient)
{
	for (int model = 0; model < fm_materialModelCount; ++model)
		for (int kind = 0; kind < kKindCount; ++kind)
		{
			if (kind == kInverted && !supportsInversion((fmMaterialModel)model))
				continue;
			fmMaterial m = testMaterial((fmMaterialModel)model);
			for (int trial = 0; trial < 20; ++trial)
			{
				fmMat3 F = randomF(kind), P;
				fmMaterial_Evaluate(&m, &F, &P, NULL);
				double h = 1e-6, worst = 0.0, scale = maxAbs(P.m, 9) + m.mu;
				for (int e = 0; e < 9; ++e)
				{
					fmMat3 Fp = F, Fm = F;
					Fp.m[e] += h;
					Fm.m[e] -= h;
					double fd = (fmMaterial_Evaluate(&m, &Fp, NULL, NULL) -
					             fmMaterial_Evaluate(&m, &Fm, NULL, NULL)) /
					            (2.0 * h);
					worst = fmax(worst, fabs(fd - P.m[e]) / scale);
				}
				if (!(worst < 1e-6))
					FAIL_AT("%s on %s F: P differs from d psi/dF by %.3g (relative)",
					        fmMaterialModelName(m.model), s_kindNames[kind], worst);
			}
		}
}

TEST(tangent_is_stress_derivative_and_symmetric)
{
	for (int model = 0; model < fm_materialModelCount; ++model)
		for (int kind = 0; kind < kKindCount; ++kind)
		{
			if (kind == kInverted && !supportsInversion((fmMaterialModel)model))
				continue;
			fmMaterial m = testMaterial((fmMaterialModel)model);
			for (int trial = 0; trial < 20; ++trial)
			{
				fmMat3 F = randomF(kind);
				double dPdF[81];
				fmMaterial_Evaluate(&m, &F, NULL, dPdF);
				double h = 1e-6, worst = 0.0, asym = 0.0, scale = maxAbs(dPdF, 81) + m.mu;
				for (int c = 0; c < 9; ++c)
				{
					// Five-point central differences (error O(h^4)): near-singular F has large
					// third derivatives that the three-point stencil's O(h^2) error shows.
					fmMat3 Fp = F, Fm = F, Fp2 = F, Fm2 = F, Pp, Pm, Pp2, Pm2;
					Fp.m[c] += h;
					Fm.m[c] -= h;
					Fp2.m[c] += 2.0 * h;
					Fm2.m[c] -= 2.0 * h;
					fmMaterial_Evaluate(&m, &Fp, &Pp, NULL);
					fmMaterial_Evaluate(&m, &Fm, &Pm, NULL);
					fmMaterial_Evaluate(&m, &Fp2, &Pp2, NULL);
					fmMaterial_Evaluate(&m, &Fm2, &Pm2, NULL);
					for (int r = 0; r < 9; ++r)
					{
						double fd =
						    (8.0 * (Pp.m[r] - Pm.m[r]) - (Pp2.m[r] - Pm2.m[r])) / (12.0 * h);
						worst = fmax(worst, fabs(fd - dPdF[9 * r + c]) / scale);
						asym = fmax(asym, fabs(dPdF[9 * r + c] - dPdF[9 * c + r]) / scale);
					}
				}
				if (!(worst < 1e-6))
					FAIL_AT("%s on %s F: dP/dF differs from finite differences by %.3g",
					        fmMaterialModelName(m.model), s_kindNames[kind], worst);
				if (!(asym < 1e-12))
					FAIL_AT("%s on %s F: dP/dF asymmetric by %.3g", fmMaterialModelName(m.model),
					        s_kindNames[kind], asym);
			}
		}
}

TEST(only_requested_outputs_change_nothing)
{
	// psi and dP/dF do not depend on which other outputs were asked for.
	for (int model = 0; model < fm_materialModelCount; ++model)
	{
		fmMaterial m = testMaterial((fmMaterialModel)model);
		fmMat3 F = randomF(kGeneral), P;
		double a[81], b[81];
		double psi1 = fmMaterial_Evaluate(&m, &F, &P, a);
		double psi2 = fmMaterial_Evaluate(&m, &F, NULL, b);
		double psi3 = fmMaterial_Evaluate(&m, &F, NULL, NULL);
		CHECK(psi1 == psi2 && psi2 == psi3);
		CHECK(memcmp(a, b, sizeof a) == 0);
	}
}

// ---- invariance --------------------------------------------------------------------------------

TEST(rotation_invariance_and_isotropy)
{
	for (int model = 0; model < fm_materialModelCount; ++model)
		for (int kind = 0; kind < kKindCount; ++kind)
		{
			if (kind == kInverted && !supportsInversion((fmMaterialModel)model))
				continue;
			fmMaterial m = testMaterial((fmMaterialModel)model);
			for (int trial = 0; trial < 10; ++trial)
			{
				fmMat3 F = randomF(kind), R = fmTestRandomRotation(), P, PR;
				double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
				fmMat3 RF = fmMatMul(&R, &F), FR = fmMatMul(&F, &R);
				double psiRF = fmMaterial_Evaluate(&m, &RF, &PR, NULL);
				double tol = 1e-10 * (fabs(psi) + m.mu);
				if (fmMaterialModel_IsAnisotropic(m.model))
				{
					// Not isotropic: turning F's rest frame turns it against the fibres. Turning
					// the axes with it gives the same energy: with axes R A, psi(R F R^T) = psi(F).
					CHECK(fabs(fmMaterial_Evaluate(&m, &FR, NULL, NULL) - psi) > 1e-6 * m.mu);
					fmMaterial turned = m;
					turned.fibre = fmMatVec(&R, m.fibre);
					turned.sheet = fmMatVec(&R, m.sheet);
					fmMat3 RFRt = fmMatMulT(&RF, &R);
					CHECK_NEAR(fmMaterial_Evaluate(&turned, &RFRt, NULL, NULL), psi, tol);
				}
				if (model == fm_linear || model == fm_orthotropicLinear)
				{
					// Small-strain elasticity is not rotation invariant: a rigid rotation strains
					// it.
					CHECK(fabs(psiRF - psi) > 1e-3 * m.mu);
					continue;
				}
				CHECK_NEAR(psiRF, psi, tol);
				// Frame indifference of the stress too: P(RF) = R P(F).
				fmMat3 RP = fmMatMul(&R, &P);
				for (int e = 0; e < 9; ++e)
					CHECK_NEAR(PR.m[e], RP.m[e], 1e-9 * (maxAbs(P.m, 9) + m.mu));
				if (!fmMaterialModel_IsAnisotropic(m.model))
					CHECK_NEAR(fmMaterial_Evaluate(&m, &FR, NULL, NULL), psi, tol);
			}
		}
}

TEST(small_strain_matches_linear_elasticity)
{
	for (int model = 0; model < fm_materialModelCount; ++model)
	{
		if (model == fm_fibreNeoHookean)
			continue; // (its small strains: test_anisotropy.c)
		fmMaterial m = testMaterial((fmMaterialModel)model);
		fmMaterial lin = m;
		lin.model = fmMaterialModel_IsOrthotropic(m.model) ? fm_orthotropicLinear : fm_linear;
		// The tangent at rest is exactly the linear elasticity tensor (all stretches equal:
		// exercises the repeated-singular-value limits).
		fmMat3 I = fmIdentity3();
		double A[81], L[81];
		fmMaterial_Evaluate(&m, &I, NULL, A);
		fmMaterial_Evaluate(&lin, &I, NULL, L);
		for (int k = 0; k < 81; ++k)
			CHECK_NEAR(A[k], L[k], 1e-6 * (m.lambda + 2 * m.mu));
		// Energy and stress of a small symmetric strain agree to first order in the strain.
		for (int trial = 0; trial < 10; ++trial)
		{
			const double d = 1e-5;
			fmMat3 F = fmIdentity3();
			for (int i = 0; i < 3; ++i)
				for (int j = i; j < 3; ++j)
				{
					double e = d * fmTestRandom(-1, 1);
					F.m[3 * i + j] += e;
					if (i != j)
						F.m[3 * j + i] += e;
				}
			fmMat3 P, PL;
			double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
			double psiL = fmMaterial_Evaluate(&lin, &F, &PL, NULL);
			CHECK_REL(psi, psiL, 1e-3, 0.0);
			for (int e = 0; e < 9; ++e)
				CHECK_NEAR(P.m[e], PL.m[e], 1e-3 * maxAbs(PL.m, 9));
		}
	}
}

// ---- model-specific ----------------------------------------------------------------------------

// The seeds' StVK where det F >= FM_STVK_FLOOR_J; below it the same plus the volume floor
// psi(J) = kappa J0 ((J - J0) - J0 ln(J / J0)), kappa = 4 (lambda + 2 mu), J0 = FM_STVK_FLOOR_J
// (material.h), continued below FM_STVK_FLOOR_JC by its quadratic; its stress is psi'(J) cof F.
// (The finite-difference tests above check its derivatives.)
TEST(stvk_is_the_seeds_formula)
{
	fmMaterial m = fmMakeMaterialLame(fm_stvk, 20000, 5000);
	int floored = 0, below = 0;
	for (int trial = 0; trial < 40; ++trial)
	{
		fmMat3 F = randomF(trial % kKindCount), P;
		double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
		// GAMES103 HW3: G = (F^T F - I)/2, S = 2 mu G + lambda tr(G) I, P = F S.
		fmMat3 G = fmMatTMul(&F, &F), I = fmIdentity3();
		G = fmMatMulAdd(&G, -1.0, &I);
		G = fmMatScale(0.5, &G);
		fmMat3 S = fmMatScale(2.0 * 5000, &G);
		S = fmMatMulAdd(&S, 20000 * fmTrace(&G), &I);
		fmMat3 FS = fmMatMul(&F, &S);
		double seeds = 5000 * fmDDot(&G, &G) + 10000 * fmTrace(&G) * fmTrace(&G);
		double J = fmDet(&F), kappa = FM_STVK_FLOOR_STIFFNESS * (20000 + 2 * 5000);
		if (J < FM_STVK_FLOOR_J)
		{
			floored += 1;
			fmMat3 C = fmCofactor(&F);
			const double j0 = FM_STVK_FLOOR_J, jc = FM_STVK_FLOOR_JC;
			double a = J < jc ? jc : J, e = J - a;
			double slope = kappa * j0 * (1.0 - j0 / a), curvature = kappa * j0 * j0 / (a * a);
			FS = fmMatMulAdd(&FS, slope + curvature * e, &C);
			seeds +=
			    kappa * j0 * ((a - j0) - j0 * log(a / j0)) + slope * e + 0.5 * curvature * e * e;
			below += J < jc;
		}
		for (int e = 0; e < 9; ++e)
			CHECK_NEAR(P.m[e], FS.m[e], 1e-12 * maxAbs(FS.m, 9));
		CHECK_REL(psi, seeds, 1e-13, 0.0);
	}
	CHECK(floored > 0); // the compressed and inverted kinds reach the floor
	CHECK(below > 0);   // and its quadratic continuation
}

// The volume floor holds a flattening tet back harder the flatter it gets: its push along
// cof F, psi'(J), grows in magnitude as J falls (like 1/J down to FM_STVK_FLOOR_JC, then
// linearly), and is continuous there; at J = 0 it is kappa J0 (2 J0 / Jc - 1) (the quadratic
// floor before it gave kappa J0, too weak for a box crushed to 12% of its height explicit).
TEST(stvk_volume_floor_grows_as_a_tet_flattens)
{
	fmMaterial m = fmMakeMaterialLame(fm_stvk, 20000, 5000);
	const double kappa = FM_STVK_FLOOR_STIFFNESS * (20000 + 2 * 5000);
	double last = 0.0, f[3];
	for (double J = 0.499; J > -0.5; J -= 0.001)
	{
		CHECK(fmMaterial_StvkFloor(&m, J, f));
		CHECK(f[1] < last);
		CHECK(f[2] > 0.0);
		last = f[1];
	}
	CHECK(fmMaterial_StvkFloor(&m, 0.0, f));
	const double j0 = FM_STVK_FLOOR_J;
	CHECK_REL(f[1], -kappa * j0 * (2.0 * j0 / FM_STVK_FLOOR_JC - 1.0), 1e-12, 0.0);
	CHECK(f[1] < -2.0 * kappa * j0);
	double below[3], above[3];
	fmMaterial_StvkFloor(&m, FM_STVK_FLOOR_JC * (1.0 - 1e-9), below);
	fmMaterial_StvkFloor(&m, FM_STVK_FLOOR_JC * (1.0 + 1e-9), above);
	for (int k = 0; k < 3; ++k)
		CHECK_REL(below[k], above[k], 1e-6, 0.0);
	CHECK(!fmMaterial_StvkFloor(&m, FM_STVK_FLOOR_J, f) && f[0] == 0.0 && f[1] == 0.0);
}

TEST(corotated_is_fixed_corotated)
{
	// psi = mu |F - R|^2 + lambda/2 (J - 1)^2, P = 2 mu (F - R) + lambda (J - 1) cof F.
	fmMaterial m = fmMakeMaterial(fm_corotated, 1e5, 0.3);
	for (int trial = 0; trial < 40; ++trial)
	{
		fmMat3 F = randomF(trial % kKindCount), P;
		double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
		fmMat3 R = fmPolarRotation(&F), C = fmCofactor(&F);
		fmMat3 FR = fmMatMulAdd(&F, -1.0, &R);
		double J = fmDet(&F);
		fmMat3 expected = fmMatScale(2.0 * m.mu, &FR);
		expected = fmMatMulAdd(&expected, m.lambda * (J - 1.0), &C);
		for (int e = 0; e < 9; ++e)
			CHECK_NEAR(P.m[e], expected.m[e], 1e-10 * (maxAbs(expected.m, 9) + m.mu));
		CHECK_REL(psi, m.mu * fmDDot(&FR, &FR) + 0.5 * m.lambda * (J - 1) * (J - 1), 1e-10,
		          m.mu * 1e-6);
	}
}

TEST(mooney_rivlin_without_c01_is_neohookean)
{
	fmMaterial mr = fmMakeMaterial(fm_mooneyRivlin, 1e5, 0.4);
	mr.c01 = 0.0;
	fmMaterial nh = fmMakeMaterial(fm_neoHookean, 1e5, 0.4);
	for (int trial = 0; trial < 20; ++trial)
	{
		fmMat3 F = randomF(trial % kKindCount), P1, P2;
		CHECK_REL(fmMaterial_Evaluate(&mr, &F, &P1, NULL), fmMaterial_Evaluate(&nh, &F, &P2, NULL),
		          1e-13, 1.0);
		for (int e = 0; e < 9; ++e)
			CHECK_NEAR(P1.m[e], P2.m[e], 1e-10 * (maxAbs(P2.m, 9) + 1.0));
	}
	// The I2 part changes large-strain behaviour: uniaxial stretch costs a different energy.
	fmMaterial mrDefault = fmMakeMaterial(fm_mooneyRivlin, 1e5, 0.4);
	fmMat3 F = {{2, 0, 0, 0, 1, 0, 0, 0, 1}};
	CHECK(fabs(fmMaterial_Evaluate(&mrDefault, &F, NULL, NULL) -
	           fmMaterial_Evaluate(&nh, &F, NULL, NULL)) > 1e-3 * mr.mu);
}

TEST(user_energies_match_neohookean)
{
	fmMaterial nh = testMaterial(fm_neoHookean);
	fmMaterial st = testMaterial(fm_stretchEnergy);
	fmMaterial inv = testMaterial(fm_invariantEnergy);
	for (int trial = 0; trial < 60; ++trial)
	{
		// J above FM_LOG_J_CLAMP, where the built-in model is the plain Neo-Hookean.
		fmMat3 F =
		    trial % 3 == 0 ? withStretches(1.2, 1.2, 0.9) : randomF(trial % 2 ? kGeneral : kLarge);
		fmMat3 P0, P1, P2;
		double A0[81], A1[81], A2[81];
		double psi0 = fmMaterial_Evaluate(&nh, &F, &P0, A0);
		double psi1 = fmMaterial_Evaluate(&st, &F, &P1, A1);
		double psi2 = fmMaterial_Evaluate(&inv, &F, &P2, A2);
		CHECK_REL(psi1, psi0, 1e-12, nh.mu * 1e-6);
		CHECK_REL(psi2, psi0, 1e-12, nh.mu * 1e-6);
		double ps = maxAbs(P0.m, 9) + nh.mu, as = maxAbs(A0, 81);
		for (int e = 0; e < 9; ++e)
		{
			CHECK_NEAR(P1.m[e], P0.m[e], 1e-11 * ps);
			CHECK_NEAR(P2.m[e], P0.m[e], 1e-11 * ps);
		}
		for (int e = 0; e < 81; ++e)
		{
			CHECK_NEAR(A1[e], A0[e], 1e-7 * as);
			CHECK_NEAR(A2[e], A0[e], 1e-10 * as);
		}
	}
}

TEST(inverted_elements_are_pushed_back)
{
	// F = diag(1, 1, t): the energy must fall as t grows back towards 1 (P_zz < 0) for every
	// t <= 0.9, through zero and inversion, and stay finite and continuous across the clamp.
	const fmMaterialModel models[] = {fm_corotated, fm_neoHookean, fm_mooneyRivlin};
	const double ts[] = {-2.0, -1.0, -0.5, -0.1, 0.0, 0.05, FM_LOG_J_CLAMP, 0.5, 0.9};
	for (int k = 0; k < 3; ++k)
	{
		fmMaterial m = fmMakeMaterial(models[k], 1e5, 0.3);
		double prev = INFINITY;
		for (int i = 0; i < (int)(sizeof ts / sizeof ts[0]); ++i)
		{
			fmMat3 F = {{1, 0, 0, 0, 1, 0, 0, 0, ts[i]}}, P;
			double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
			CHECK(isfinite(psi));
			if (!(P.m[8] < 0.0))
				FAIL_AT("%s: P_zz = %g at t = %g does not push back", fmMaterialModelName(m.model),
				        P.m[8], ts[i]);
			CHECK(psi < prev);
			prev = psi;
		}
		// Continuity of the stress across the clamp.
		const double c = FM_LOG_J_CLAMP, h = 1e-9;
		fmMat3 Fa = {{1, 0, 0, 0, 1, 0, 0, 0, c - h}}, Fb = {{1, 0, 0, 0, 1, 0, 0, 0, c + h}}, Pa,
		       Pb;
		fmMaterial_Evaluate(&m, &Fa, &Pa, NULL);
		fmMaterial_Evaluate(&m, &Fb, &Pb, NULL);
		CHECK_NEAR(Pa.m[8], Pb.m[8], 1e-6 * m.mu);
	}
}

TEST(degenerate_deformations_stay_finite)
{
	// Flattened and collapsed tets (rank 2, rank 1, zero F) give finite energy, stress, tangent.
	fmMat3 cases[] = {{{1, 0, 0, 0, 1, 0, 0, 0, 0}},
	                  {{1, 2, 3, 2, 4, 6, -1, -2, -3}},
	                  {{0, 0, 0, 0, 0, 0, 0, 0, 0}},
	                  {{1, 0, 0, 0, -1, 0, 0, 0, 1e-12}}};
	for (int model = 0; model < fm_materialModelCount; ++model)
	{
		if (!supportsInversion((fmMaterialModel)model))
			continue;
		fmMaterial m = testMaterial((fmMaterialModel)model);
		for (int c = 0; c < 4; ++c)
		{
			fmMat3 P;
			double A[81];
			double psi = fmMaterial_Evaluate(&m, &cases[c], &P, A);
			CHECK(isfinite(psi) && isfinite(maxAbs(P.m, 9)) && isfinite(maxAbs(A, 81)));
		}
	}
}

// ---- PSD projection ----------------------------------------------------------------------------

// True when A + shift I is positive definite (Cholesky), an independent check of the spectrum.
static bool choleskyOk(const double* A, double shift)
{
	double L[81];
	for (int j = 0; j < 9; ++j)
	{
		double d = A[9 * j + j] + shift;
		for (int k = 0; k < j; ++k)
			d -= L[9 * j + k] * L[9 * j + k];
		if (!(d > 0.0))
			return false;
		L[9 * j + j] = sqrt(d);
		for (int i = j + 1; i < 9; ++i)
		{
			double s = A[9 * i + j];
			for (int k = 0; k < j; ++k)
				s -= L[9 * i + k] * L[9 * j + k];
			L[9 * i + j] = s / L[9 * j + j];
		}
	}
	return true;
}

TEST(psd_projection_is_the_nearest_psd_matrix)
{
	for (int trial = 0; trial < 200; ++trial)
	{
		double A[81], X[81], D[81];
		for (int i = 0; i < 9; ++i)
			for (int j = i; j < 9; ++j)
				A[9 * i + j] = A[9 * j + i] = fmTestRandom(-1, 1);
		memcpy(X, A, sizeof A);
		fmProjectPSD9(X);
		double norm = maxAbs(A, 81), tol = 1e-12 * 9 * norm;
		for (int k = 0; k < 81; ++k)
			D[k] = A[k] - X[k];
		// Nearest in the Frobenius norm <=> X PSD, A - X NSD, X (A - X) = 0 (same eigenvectors,
		// eigenvalues max(w, 0) and min(w, 0)).
		double negD[81];
		for (int k = 0; k < 81; ++k)
			negD[k] = -D[k];
		CHECK(choleskyOk(X, tol));
		CHECK(choleskyOk(negD, tol));
		double worst = 0.0, asym = 0.0;
		for (int i = 0; i < 9; ++i)
			for (int j = 0; j < 9; ++j)
			{
				double s = 0.0;
				for (int k = 0; k < 9; ++k)
					s += X[9 * i + k] * D[9 * k + j];
				worst = fmax(worst, fabs(s));
				asym = fmax(asym, fabs(X[9 * i + j] - X[9 * j + i]));
			}
		CHECK_NEAR(worst, 0.0, 1e-12 * 9 * norm * norm);
		CHECK(asym == 0.0);
	}
	// A positive definite matrix is its own projection.
	double A[81] = {0}, X[81];
	for (int i = 0; i < 9; ++i)
		for (int j = 0; j < 9; ++j)
			A[9 * i + j] = (i == j ? 10.0 : 0.0) + 1.0 / (1.0 + i + j);
	memcpy(X, A, sizeof A);
	fmProjectPSD9(X);
	CHECK(memcmp(A, X, sizeof A) == 0);
}

TEST(psd_projection_of_a_compressed_neohookean_tangent)
{
	// A strongly compressed Neo-Hookean tet has an indefinite tangent; after projection the
	// energy is convex along every direction.
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	fmMat3 F = withStretches(1.8, 0.3, 0.25);
	double A[81];
	fmMaterial_Evaluate(&m, &F, NULL, A);
	CHECK(!choleskyOk(A, 0.0));
	fmProjectPSD9(A);
	CHECK(choleskyOk(A, 1e-9 * maxAbs(A, 81)));
	double B[81];
	fmMaterial_EvaluateProjected(&m, &F, NULL, B);
	for (int e = 0; e < 81; ++e)
		CHECK_NEAR(B[e], A[e], 1e-9 * maxAbs(A, 81));

	// StVK crushed to half its length (J = 0.525, above the volume floor): even the 3x3 block
	// of d2psi/ds2 is indefinite (its diagonal is negative); the closed-form projection must
	// still match the numerical one.
	fmMaterial stvk = fmMakeMaterial(fm_stvk, 1e5, 0.3);
	F = withStretches(0.5, 1.05, 1.0);
	fmMaterial_Evaluate(&stvk, &F, NULL, A);
	fmMat3 Fd = {{0.5, 0, 0, 0, 1.05, 0, 0, 0, 1.0}};
	double Ad[81];
	fmMaterial_Evaluate(&stvk, &Fd, NULL, Ad);
	CHECK(Ad[0] < 0.0); // d2psi/ds0^2 in the principal frame
	fmProjectPSD9(A);
	fmMaterial_EvaluateProjected(&stvk, &F, NULL, B);
	for (int e = 0; e < 81; ++e)
		CHECK_NEAR(B[e], A[e], 1e-9 * maxAbs(A, 81));
}

TEST(analytic_projection_matches_numerical_projection)
{
	// fmMaterial_EvaluateProjected clamps the closed-form eigenvalues; it must give the same
	// matrix as the 9x9 eigen-solver, and the same psi and P as fmMaterial_Evaluate.
	for (int model = 0; model < fm_materialModelCount; ++model)
		for (int kind = 0; kind < kKindCount; ++kind)
		{
			if (kind == kInverted && !supportsInversion((fmMaterialModel)model))
				continue;
			fmMaterial m = testMaterial((fmMaterialModel)model);
			double worst = 0.0;
			for (int trial = 0; trial < 20; ++trial)
			{
				fmMat3 F = trial == 0 ? fmIdentity3() : randomF(kind), P0, P1;
				double A[81], B[81];
				double psi0 = fmMaterial_Evaluate(&m, &F, &P0, A);
				fmProjectPSD9(A);
				double psi1 = fmMaterial_EvaluateProjected(&m, &F, &P1, B);
				CHECK_REL(psi1, psi0, 1e-11, 1e-9 * m.mu);
				for (int e = 0; e < 9; ++e)
					CHECK_NEAR(P1.m[e], P0.m[e], 1e-11 * (maxAbs(P0.m, 9) + m.mu));
				double scale = maxAbs(A, 81) + m.mu;
				for (int e = 0; e < 81; ++e)
					worst = fmax(worst, fabs(A[e] - B[e]) / scale);
			}
			if (!(worst < 1e-7))
				FAIL_AT("%s on %s F: projected tangents differ by %.3g",
				        fmMaterialModelName(m.model), s_kindNames[kind], worst);
		}
}

// The Newton matrix's StVK tangent without an SVD (fmMaterial_StvkClampedHessian): the exact
// dP/dF with the second Piola-Kirchhoff stress S replaced by its positive part S+ (the
// difference I (x) (S+ - S), S+ from an independent eigen-decomposition), so the exact tangent
// where S is positive definite (tension), and PSD. Declined for another model, lambda < 0 and
// below the volume floor's J.
TEST(stvk_clamped_hessian_is_exact_in_tension_and_psd_under_compression)
{
	fmMaterial m = fmMakeMaterialLame(fm_stvk, 20000, 5000);
	int tension = 0, compression = 0;
	for (int trial = 0; trial < 400; ++trial)
	{
		// Every mix of stretch and compression above the floor's J = 0.5, and some stresses
		// with a repeated eigenvalue (two stretches alike).
		double a = fmTestRandom(0.8, 1.3), b = fmTestRandom(0.8, 1.3);
		fmMat3 F = withStretches(a, trial % 4 == 0 ? a : b, fmTestRandom(0.8, 1.3));
		double A[81], B[81];
		fmMaterial_Evaluate(&m, &F, NULL, A);
		CHECK(fmMaterial_StvkClampedHessian(&m, &F, B));
		fmMat3 C = fmMatTMul(&F, &F), S, Q;
		double trG = 0.5 * (C.m[0] + C.m[4] + C.m[8] - 3.0);
		for (int e = 0; e < 9; ++e)
			S.m[e] =
			    m.mu * (C.m[e] - (e % 4 == 0 ? 1.0 : 0.0)) + (e % 4 == 0 ? m.lambda * trG : 0.0);
		fmVec3 w;
		fmSymEigen3(&S, &w, &Q);
		const double wp[3] = {fmax(w.x, 0.0), fmax(w.y, 0.0), fmax(w.z, 0.0)};
		fmMat3 gap; // S+ - S
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
			{
				double v = -S.m[3 * i + j];
				for (int k = 0; k < 3; ++k)
					v += Q.m[3 * i + k] * wp[k] * Q.m[3 * j + k];
				gap.m[3 * i + j] = v;
			}
		tension += w.z > 0.0;
		compression += w.z < 0.0;
		double scale = maxAbs(A, 81);
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
				for (int k = 0; k < 3; ++k)
					for (int l = 0; l < 3; ++l)
					{
						int r = 9 * (3 * i + j) + (3 * k + l);
						CHECK_NEAR(B[r] - A[r], i == k ? gap.m[3 * l + j] : 0.0, 1e-9 * scale);
					}
		CHECK(choleskyOk(B, 1e-9 * scale));
	}
	CHECK(tension > 20 && compression > 20);
	double B[81];
	fmMat3 F = withStretches(0.5, 1.05, 0.9); // J = 0.4725: the volume floor's
	CHECK(!fmMaterial_StvkClampedHessian(&m, &F, B));
	fmMaterial nh = fmMakeMaterialLame(fm_neoHookean, 20000, 5000);
	fmMaterial auxetic = fmMakeMaterialLame(fm_stvk, -1000, 5000);
	F = withStretches(1.1, 1.0, 0.95);
	CHECK(!fmMaterial_StvkClampedHessian(&nh, &F, B));
	CHECK(!fmMaterial_StvkClampedHessian(&auxetic, &F, B));
}

// The Newton matrix's Neo-Hookean tangent without an SVD (fmMaterial_NeoHookeanClampedHessian):
// the exact dP/dF plus (1 - theta) c |skew(F^-1 dF)|^2 with c = mu - lambda ln J and
// theta = min(1, mu s_min^2 / c) (s_min from an independent eigen-decomposition of F^T F), so
// the exact tangent where theta = 1 (at rest, in tension), and PSD. Declined for another
// model, where c < 0 and below the log's clamp.
TEST(neohookean_clamped_hessian_is_exact_at_rest_and_psd_under_compression)
{
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	int exact = 0, clamped = 0;
	for (int trial = 0; trial < 400; ++trial)
	{
		fmMat3 F = trial == 0 ? fmTestRandomRotation()
		                      : withStretches(fmTestRandom(0.7, 1.3), fmTestRandom(0.7, 1.3),
		                                      fmTestRandom(0.7, 1.3));
		double A[81], B[81], J = fmDet(&F), c = m.mu - m.lambda * log(J);
		fmMaterial_Evaluate(&m, &F, NULL, A);
		CHECK(fmMaterial_NeoHookeanClampedHessian(&m, &F, B) == (c >= 0.0));
		if (c < 0.0)
			continue;
		fmMat3 C = fmMatTMul(&F, &F), Q, G = fmCofactor(&F);
		fmVec3 w;
		fmSymEigen3(&C, &w, &Q);
		double theta = fmin(1.0, m.mu * w.z / c), k = 0.5 * (1.0 - theta) * c;
		exact += theta == 1.0;
		clamped += theta < 1.0;
		for (int e = 0; e < 9; ++e)
			G.m[e] /= J; // F^-T
		double scale = maxAbs(A, 81);
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				for (int cc = 0; cc < 3; ++cc)
					for (int d = 0; d < 3; ++d)
					{
						// k (|F^-1 dF|^2 - tr((F^-1 dF)^2)) in dF's coordinates.
						double extra = -k * G.m[3 * a + d] * G.m[3 * cc + b];
						for (int e = 0; b == d && e < 3; ++e)
							extra += k * G.m[3 * a + e] * G.m[3 * cc + e];
						int r = 9 * (3 * a + b) + (3 * cc + d);
						CHECK_NEAR(B[r] - A[r], extra, 1e-9 * scale);
					}
		CHECK(choleskyOk(B, 1e-9 * scale));
	}
	CHECK(exact > 20 && clamped > 20);
	double B[81];
	fmMat3 F = withStretches(0.5, 0.6, 0.5); // J = 0.15: below the log's clamp
	CHECK(!fmMaterial_NeoHookeanClampedHessian(&m, &F, B));
	fmMaterial stvk = fmMakeMaterial(fm_stvk, 1e5, 0.3);
	F = withStretches(1.1, 1.0, 0.95);
	CHECK(!fmMaterial_NeoHookeanClampedHessian(&stvk, &F, B));
}

// ---- parameters, validation, names -------------------------------------------------------------

TEST(make_material_round_trips_youngs_modulus_and_poisson_ratio)
{
	const double E[] = {1e3, 1e5, 2e11};
	const double nu[] = {-0.9, -0.3, 0.0, 0.25, 0.3, 0.45, 0.499};
	for (int a = 0; a < 3; ++a)
		for (int b = 0; b < 7; ++b)
		{
			fmMaterial m = fmMakeMaterial(fm_neoHookean, E[a], nu[b]);
			double Eback = m.mu * (3.0 * m.lambda + 2.0 * m.mu) / (m.lambda + m.mu);
			double nuBack = m.lambda / (2.0 * (m.lambda + m.mu));
			CHECK_REL(Eback, E[a], 1e-12, 0.0);
			CHECK_NEAR(nuBack, nu[b], 1e-12);
			CHECK_REL(m.c01, m.mu / 8.0, 1e-15, 0.0);
			CHECK_INT(fmMaterial_Validate(&m, NULL), fm_ok);
		}
	fmMaterial seeds = fmMakeMaterialLame(fm_stvk, 20000, 5000);
	CHECK(seeds.lambda == 20000 && seeds.mu == 5000 && seeds.model == fm_stvk);
}

TEST(uniaxial_tension_recovers_youngs_modulus_and_poisson_ratio)
{
	// A bar pulled along x with free sides: find the lateral strain t with P_yy = P_zz = 0, then
	// stress / strain is E and -t / e is nu, for every model, at small strain.
	const double E = 1e5, nu = 0.3, e = 1e-6;
	for (int model = 0; model < fm_materialModelCount; ++model)
	{
		if (fmMaterialModel_IsOrthotropic((fmMaterialModel)model))
			continue; // (nine constants: test_anisotropy.c)
		fmMaterial m = testMaterial((fmMaterialModel)model);
		if (model != fm_stretchEnergy && model != fm_invariantEnergy)
			m = fmMakeMaterial((fmMaterialModel)model, E, nu);
		double Eexp = m.mu * (3 * m.lambda + 2 * m.mu) / (m.lambda + m.mu);
		double nuExp = m.lambda / (2 * (m.lambda + m.mu));
		double t = 0.0;
		fmMat3 P;
		for (int it = 0; it < 20; ++it)
		{
			fmMat3 F = {{1 + e, 0, 0, 0, 1 + t, 0, 0, 0, 1 + t}};
			double A[81];
			fmMaterial_Evaluate(&m, &F, &P, A);
			// d P_yy / dt = dP_yy/dF_yy + dP_yy/dF_zz
			t -= P.m[4] / (A[9 * 4 + 4] + A[9 * 4 + 8]);
		}
		fmMat3 F = {{1 + e, 0, 0, 0, 1 + t, 0, 0, 0, 1 + t}};
		fmMaterial_Evaluate(&m, &F, &P, NULL);
		CHECK_NEAR(P.m[4], 0.0, 1e-9 * Eexp * e);
		CHECK_NEAR(P.m[8], 0.0, 1e-6 * Eexp * e);
		CHECK_REL(P.m[0] / e, Eexp, 1e-4, 0.0);
		CHECK_REL(-t / e, nuExp, 1e-4, 0.0);
	}
}

static void expectInvalid(const fmMaterial* m, const char* hint, int* failures_)
{
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	CHECK_INT(fmMaterial_Validate(m, &diag), fm_errParameter);
	CHECK_INT(diag.result, fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, hint);
}

TEST(validation_names_the_bad_parameter)
{
	fmMaterial m = fmMakeMaterial(fm_neoHookean, -1e5, 0.3);
	expectInvalid(&m, "mu", failures_);
	m = fmMakeMaterial(fm_neoHookean, 0.0, 0.3);
	expectInvalid(&m, "must be > 0", failures_);
	m = fmMakeMaterialLame(fm_stvk, -4000, 5000); // nu < -1 equivalent: bulk modulus < 0
	expectInvalid(&m, "Poisson ratio in (-1, 0.5)", failures_);
	m = fmMakeMaterial(fm_neoHookean, 1e5, 0.5);
	expectInvalid(&m, "0.49", failures_);
	m = fmMakeMaterial(fm_neoHookean, 1e5, 0.7); // lambda < 0 and below -2/3 mu
	expectInvalid(&m, "lambda", failures_);
	m = fmMakeMaterial(fm_corotated, 1e5, 0.3);
	m.mu = NAN;
	expectInvalid(&m, "finite", failures_);
	m = fmMakeMaterial(fm_mooneyRivlin, 1e5, 0.3);
	m.c01 = 0.6 * m.mu;
	expectInvalid(&m, "c01", failures_);
	m.c01 = -1.0;
	expectInvalid(&m, "[0, mu/2]", failures_);
	m = fmMakeMaterial(fm_stretchEnergy, 1e5, 0.3);
	expectInvalid(&m, "stretchEnergy", failures_);
	m = fmMakeMaterial(fm_invariantEnergy, 1e5, 0.3);
	expectInvalid(&m, "invariantEnergy", failures_);
	m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.model = fm_materialModelCount;
	expectInvalid(&m, "unknown", failures_);

	// c01 only matters for Mooney-Rivlin; valid corner cases pass.
	m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.c01 = -5.0;
	CHECK_INT(fmMaterial_Validate(&m, NULL), fm_ok);
	m = fmMakeMaterial(fm_mooneyRivlin, 1e5, -0.5);
	m.c01 = 0.5 * m.mu;
	CHECK_INT(fmMaterial_Validate(&m, NULL), fm_ok);
	m = testMaterial(fm_stretchEnergy);
	CHECK_INT(fmMaterial_Validate(&m, NULL), fm_ok);
}

TEST(model_names_round_trip)
{
	for (int i = 0; i < fm_materialModelCount; ++i)
	{
		fmMaterialModel back = fm_materialModelCount;
		CHECK(fmMaterialModelFromName(fmMaterialModelName((fmMaterialModel)i), &back));
		CHECK_INT(back, i);
	}
	fmMaterialModel mm = fm_linear;
	CHECK(fmMaterialModelFromName("mooney-rivlin", &mm) && mm == fm_mooneyRivlin);
	CHECK(!fmMaterialModelFromName("neo-hookean", &mm));
	CHECK(!fmMaterialModelFromName(NULL, &mm));
	for (int i = 0; i < fm_forceModelCount; ++i)
	{
		fmForceModel back = fm_forceModelCount;
		CHECK(fmForceModelFromName(fmForceModelName((fmForceModel)i), &back));
		CHECK_INT(back, i);
	}
	fmForceModel fm = fm_fem;
	CHECK(fmForceModelFromName("mass-spring", &fm) && fm == fm_massSpring);
	CHECK(!fmForceModelFromName("springs", &fm));
	CHECK(strcmp(fmMaterialModelName(fm_materialModelCount), "unknown") == 0);
}
