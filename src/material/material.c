// Materials: parameters, validation, names, the cheap polynomial models (linear, StVK) and the
// PSD projection of dP/dF. The SVD-based models live in material_stretch.c, Neo-Hookean,
// Mooney-Rivlin and the user invariant energy in material_invariant.c. Formulas: docs/materials.md.
#include "material/material.h"
#include "core/det_math.h"

#include "core/core.h"
#include "material/material_aniso.h"
#include "material/material_invariant.h"
#include "material/material_neohookean.h"
#include "material/material_plastic.h"
#include "material/material_stretch.h"
#include "math/svd3.h"

#include <math.h>
#include <string.h>

fmMaterial fmMakeMaterialLame(fmMaterialModel model, double lambda, double mu)
{
	fmMaterial m;
	memset(&m, 0, sizeof m);
	m.model = model;
	m.lambda = lambda;
	m.mu = mu;
	m.c01 = mu / 8.0; // Mooney-Rivlin default: a quarter of the shear stiffness from I2
	return m;
}

fmMaterial fmMakeMaterial(fmMaterialModel model, double youngsModulus, double poissonRatio)
{
	// Lame constants of isotropic linear elasticity (e.g. Game Development Reference, ch. 10).
	// Out-of-range input gives non-finite or negative constants that fmMaterial_Validate names.
	double nu = poissonRatio;
	double lambda = youngsModulus * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
	double mu = youngsModulus / (2.0 * (1.0 + nu));
	return fmMakeMaterialLame(model, lambda, mu);
}

fmMaterial fmMakeOrthotropicMaterial(fmMaterialModel model, fmOrthotropy constants)
{
	fmMaterial m = fmMakeMaterialLame(model, 0.0, 0.0);
	m.orthotropy = constants;
	fmMaterial_SetScale(&m);
	m.c01 = 0.0;
	return m;
}

fmOrthotropy fmTransverselyIsotropic(double eAlong, double eAcross, double nuAlong, double nuAcross,
                                     double gAlong)
{
	fmOrthotropy o = {{eAlong, eAcross, eAcross},
	                  {nuAlong, nuAlong, nuAcross},
	                  {gAlong, gAlong, eAcross / (2.0 * (1.0 + nuAcross))}};
	return o;
}

// The isotropic constants' checks (lambda, mu, c01); the orthotropic models' scale comes from
// their own constants (fmMaterial_SetScale) and is not checked here.
static fmResult fmValidateLame(const fmMaterial* m, fmDiagnostic* diag)
{
	if (!isfinite(m->lambda) || !isfinite(m->mu) || !isfinite(m->c01))
		return fmDiagError(
		    diag, fm_errParameter, NULL, 0, 0,
		    "material constants must be finite (lambda = %g, mu = %g, c01 = %g Pa); a "
		    "Poisson ratio of exactly 0.5 or -1 gives infinite lambda: use e.g. 0.49",
		    m->lambda, m->mu, m->c01);
	if (!(m->mu > 0.0))
		return fmDiagError(
		    diag, fm_errParameter, NULL, 0, 0,
		    "shear modulus mu = %g Pa must be > 0 (Young's modulus E > 0 and Poisson "
		    "ratio in (-1, 0.5) give mu = E / (2 (1 + nu)) > 0)",
		    m->mu);
	if (!(m->lambda > -2.0 / 3.0 * m->mu))
		return fmDiagError(
		    diag, fm_errParameter, NULL, 0, 0,
		    "lambda = %g Pa must be > -2/3 mu = %g Pa (a positive bulk modulus; Poisson "
		    "ratio in (-1, 0.5), e.g. 0.3)",
		    m->lambda, -2.0 / 3.0 * m->mu);
	if (m->model == fm_mooneyRivlin && !(m->c01 >= 0.0 && m->c01 <= 0.5 * m->mu))
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0,
		                   "Mooney-Rivlin c01 = %g Pa must be in [0, mu/2] = [0, %g] Pa (0 is "
		                   "Neo-Hookean; the default is mu/8 = %g)",
		                   m->c01, 0.5 * m->mu, m->mu / 8.0);
	if (m->model == fm_stretchEnergy && m->stretchEnergy == NULL)
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0,
		                   "model stretch-energy needs material.stretchEnergy, a function of the "
		                   "principal stretches (docs/materials.md has an example)");
	if (m->model == fm_invariantEnergy && m->invariantEnergy == NULL)
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0,
		                   "model invariant-energy needs material.invariantEnergy, a function of "
		                   "(I1, I2, J) (docs/materials.md has an example)");
	if (m->nodalPressure && !fmMaterialModel_SplitsVolume(m->model))
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0,
		                   "nodalPressure needs a model whose volume term is a function of J "
		                   "alone (linear, neohookean, mooney-rivlin, neohookean-isochoric), "
		                   "not %s",
		                   fmMaterialModelName(m->model));
	// Nearly incompressible (Poisson's ratio above 0.49): accepted, with a warning; linear tets
	// lock (unless the volume term is on vertex patches) and implicit solves may diverge
	// (refused then, with this cause named).
	if (m->lambda > FM_NEARLY_INCOMPRESSIBLE * m->mu)
		fmDiagWarn(diag, NULL, 0,
		           "lambda / mu = %.3g (a Poisson ratio of %.7g) makes the material nearly "
		           "incompressible: %s; 0.49 or less is safe",
		           m->lambda / m->mu, m->lambda / (2.0 * (m->lambda + m->mu)),
		           m->nodalPressure ? "explicit steps shrink with it and implicit solves may "
		                              "diverge"
		                            : "linear tets lock under it (set nodalPressure) and "
		                              "implicit solves may diverge");
	return fm_ok;
}

bool fmMaterialModel_SplitsVolume(fmMaterialModel model)
{
	return model == fm_linear || model == fm_neoHookean || model == fm_mooneyRivlin ||
	       model == fm_neoHookeanIsochoric;
}

fmResult fmMaterial_Validate(const fmMaterial* material, fmDiagnostic* diag)
{
	const fmMaterial* m = material;
	if (m == NULL)
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0, "material is NULL");
	if ((int)m->model < 0 || m->model >= fm_materialModelCount)
		return fmDiagError(
		    diag, fm_errParameter, NULL, 0, 0,
		    "material model %d is unknown; use one of fm_linear .. fm_fibreNeoHookean "
		    "(\"linear\", \"corotated\", \"stvk\", \"neohookean\", \"mooney-rivlin\", "
		    "\"stretch-energy\", \"invariant-energy\", \"neohookean-isochoric\", "
		    "\"orthotropic-linear\", \"orthotropic-stvk\", \"fibre-neohookean\")",
		    (int)m->model);
	char why[400];
	if (fmMaterialModel_IsAnisotropic(m->model) && !fmAniso_Validate(m, why, sizeof why))
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0, "%s", why);
	if (!fmPlasticity_Validate(m, why, sizeof why))
		return fmDiagError(diag, fm_errParameter, NULL, 0, 0, "%s", why);
	const fmFracture* f = &m->fracture;
	const double tear[3] = {f->strength, f->length, f->minVolume};
	static const char* const tearNames[3] = {"strength", "length", "minVolume"};
	for (int k = 0; k < 3; ++k)
		if (!(tear[k] >= 0.0 && isfinite(tear[k])))
			return fmDiagError(diag, fm_errParameter, NULL, 0, 0,
			                   "fracture.%s = %g must be finite and >= 0 (%s)", tearNames[k],
			                   tear[k],
			                   k == 0   ? "Pa; 0: unbreakable"
			                   : k == 1 ? "m"
			                            : "m^3");
	return fmMaterialModel_IsOrthotropic(m->model) ? fm_ok : fmValidateLame(m, diag);
}

static const char* const s_modelNames[fm_materialModelCount] = {
    "linear",
    "corotated",
    "stvk",
    "neohookean",
    "mooney-rivlin",
    "stretch-energy",
    "invariant-energy",
    "neohookean-isochoric",
    "orthotropic-linear",
    "orthotropic-stvk",
    "fibre-neohookean",
};

const char* fmMaterialModelName(fmMaterialModel model)
{
	if ((int)model < 0 || model >= fm_materialModelCount)
		return "unknown";
	return s_modelNames[model];
}

bool fmMaterialModelFromName(const char* name, fmMaterialModel* model)
{
	for (int i = 0; name != NULL && i < fm_materialModelCount; ++i)
		if (strcmp(name, s_modelNames[i]) == 0)
		{
			*model = (fmMaterialModel)i;
			return true;
		}
	return false;
}

static const char* const s_forceModelNames[fm_forceModelCount] = {"fem", "fvm", "mass-spring"};

const char* fmForceModelName(fmForceModel model)
{
	if ((int)model < 0 || model >= fm_forceModelCount)
		return "unknown";
	return s_forceModelNames[model];
}

bool fmForceModelFromName(const char* name, fmForceModel* model)
{
	for (int i = 0; name != NULL && i < fm_forceModelCount; ++i)
		if (strcmp(name, s_forceModelNames[i]) == 0)
		{
			*model = (fmForceModel)i;
			return true;
		}
	return false;
}

// Linear elasticity: eps = (F + F^T)/2 - I, psi = mu eps:eps + lambda/2 tr(eps)^2,
// P = 2 mu eps + lambda tr(eps) I, dP_ij/dF_kl = mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl.
static double fmLinear_Evaluate(const fmMaterial* m, const fmMat3* F, fmMat3* P, double* dPdF)
{
	fmMat3 eps;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			eps.m[3 * i + j] = 0.5 * (F->m[3 * i + j] + F->m[3 * j + i]) - (i == j ? 1.0 : 0.0);
	double tr = fmTrace(&eps);
	if (P)
	{
		*P = fmMatScale(2.0 * m->mu, &eps);
		for (int i = 0; i < 3; ++i)
			P->m[4 * i] += m->lambda * tr;
	}
	if (dPdF)
	{
		memset(dPdF, 0, 81 * sizeof(double));
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j)
			{
				dPdF[9 * (3 * i + j) + (3 * i + j)] += m->mu;
				dPdF[9 * (3 * i + j) + (3 * j + i)] += m->mu;
				if (i == j)
					for (int k = 0; k < 3; ++k)
						dPdF[9 * (4 * i) + 4 * k] += m->lambda;
			}
	}
	return m->mu * fmDDot(&eps, &eps) + 0.5 * m->lambda * tr * tr;
}

// St. Venant-Kirchhoff, the seeds' model: G = (F^T F - I)/2, S = 2 mu G + lambda tr(G) I,
// P = F S, psi = mu G:G + lambda/2 tr(G)^2. Differentiating P = F S:
// dP_ij/dF_kl = d_ik S_lj + mu (F_il F_kj + (F F^T)_ik d_jl) + lambda F_ij F_kl.
// Green strain G = (F^T F - I) / 2, written out: it is symmetric, so 6 entries, not 9. This is
// the explicit solver's inner loop (one call per tet per step).
static fmMat3 fmGreenStrain(const fmMat3* F)
{
	const double* f = F->m;
	double g00 = 0.5 * (f[0] * f[0] + f[3] * f[3] + f[6] * f[6] - 1.0);
	double g11 = 0.5 * (f[1] * f[1] + f[4] * f[4] + f[7] * f[7] - 1.0);
	double g22 = 0.5 * (f[2] * f[2] + f[5] * f[5] + f[8] * f[8] - 1.0);
	double g01 = 0.5 * (f[0] * f[1] + f[3] * f[4] + f[6] * f[7]);
	double g02 = 0.5 * (f[0] * f[2] + f[3] * f[5] + f[6] * f[8]);
	double g12 = 0.5 * (f[1] * f[2] + f[4] * f[5] + f[7] * f[8]);
	fmMat3 G = {{g00, g01, g02, g01, g11, g12, g02, g12, g22}};
	return G;
}

bool fmMaterial_StvkFloor(const fmMaterial* m, double J, double out[3])
{
	out[0] = out[1] = out[2] = 0.0;
	if (!(J < FM_STVK_FLOOR_J))
		return false;
	const double kappa = FM_STVK_FLOOR_STIFFNESS * (m->lambda + 2.0 * m->mu), j0 = FM_STVK_FLOOR_J;
	double at = J < FM_STVK_FLOOR_JC ? FM_STVK_FLOOR_JC : J;
	double psi = kappa * j0 * ((at - j0) - j0 * fmMathLog(at / j0));
	double slope = kappa * j0 * (1.0 - j0 / at), curvature = kappa * j0 * j0 / (at * at);
	double e = J - at; // below FM_STVK_FLOOR_JC: the quadratic continuation
	out[0] = psi + e * (slope + 0.5 * curvature * e);
	out[1] = slope + curvature * e;
	out[2] = curvature;
	return true;
}

double fmMaterial_AddStvkFloor(const fmMaterial* m, const fmMat3* F, fmMat3* P, double* dPdF)
{
	fmMat3 C = fmCofactor(F);
	double J = F->m[0] * C.m[0] + F->m[1] * C.m[1] + F->m[2] * C.m[2], f[3];
	if (!fmMaterial_StvkFloor(m, J, f))
		return 0.0;
	for (int k = 0; P != NULL && k < 9; ++k)
		P->m[k] += f[1] * C.m[k];
	for (int a = 0; dPdF != NULL && a < 9; ++a)
		for (int b = 0; b < 9; ++b)
		{
			// d^2 J / dF_ij dF_kl = e_ikm e_jln F_mn: nonzero for i != k and j != l.
			int i = a / 3, j = a % 3, k = b / 3, l = b % 3;
			double second = 0.0;
			if (i != k && j != l)
			{
				int mm = 3 - i - k, nn = 3 - j - l;
				double sign =
				    ((k - i + 3) % 3 == 1 ? 1.0 : -1.0) * ((l - j + 3) % 3 == 1 ? 1.0 : -1.0);
				second = sign * F->m[3 * mm + nn];
			}
			dPdF[9 * a + b] += f[2] * C.m[a] * C.m[b] + f[1] * second;
		}
	return f[0];
}

// StVK's second Piola-Kirchhoff stress at Green strain @p G: 2 mu G + lambda tr(G) I.
static fmMat3 fmStvkStress(const fmMaterial* m, const fmMat3* G)
{
	double tr = fmTrace(G);
	fmMat3 S = fmMatScale(2.0 * m->mu, G);
	for (int i = 0; i < 3; ++i)
		S.m[4 * i] += m->lambda * tr;
	return S;
}

// StVK's dP/dF at F with the stress term taken from @p S: dF -> dF S plus
// mu (F F^T dF + F dF^T F) + lambda F (F : dF). The exact tangent with S the second
// Piola-Kirchhoff stress.
static void fmStvkTangent(const fmMaterial* m, const fmMat3* F, const fmMat3* S, double* dPdF)
{
	fmMat3 B = fmMatMulT(F, F);
	const double* f = F->m;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			for (int k = 0; k < 3; ++k)
				for (int l = 0; l < 3; ++l)
				{
					double v = m->mu * f[3 * i + l] * f[3 * k + j] +
					           m->lambda * f[3 * i + j] * f[3 * k + l];
					if (i == k)
						v += S->m[3 * l + j];
					if (j == l)
						v += m->mu * B.m[3 * i + k];
					dPdF[9 * (3 * i + j) + (3 * k + l)] = v;
				}
}

static double fmStvk_Evaluate(const fmMaterial* m, const fmMat3* F, fmMat3* P, double* dPdF)
{
	fmMat3 G = fmGreenStrain(F);
	double tr = fmTrace(&G);
	fmMat3 S = fmStvkStress(m, &G);
	if (P)
		*P = fmMatMul(F, &S);
	if (dPdF)
		fmStvkTangent(m, F, &S, dPdF);
	return m->mu * fmDDot(&G, &G) + 0.5 * m->lambda * tr * tr +
	       fmMaterial_AddStvkFloor(m, F, P, dPdF);
}

// A lower bound on the smallest eigenvalue of the symmetric 3x3 @p S: Newton's method on its
// characteristic polynomial p(x) = det(S - x I) from Gershgorin's bound, below every root, where
// p is positive, decreasing and convex (p'' = 2 tr S - 6 x > 0 below the eigenvalues' mean): each
// iterate stays below the smallest eigenvalue and climbs to it.
#define FM_EIGEN_BOUND_STEPS 32
static double fmSmallestEigenBound3(const fmMat3* S)
{
	const double* s = S->m;
	double lo = fmMin(s[0] - fabs(s[1]) - fabs(s[2]),
	                  fmMin(s[4] - fabs(s[1]) - fabs(s[5]), s[8] - fabs(s[2]) - fabs(s[5])));
	// p(x) = -x^3 + c2 x^2 - c1 x + c0.
	double c2 = s[0] + s[4] + s[8];
	double c1 = s[0] * s[4] + s[0] * s[8] + s[4] * s[8] - s[1] * s[1] - s[2] * s[2] - s[5] * s[5];
	double c0 = fmDet(S);
	for (int k = 0; k < FM_EIGEN_BOUND_STEPS; ++k)
	{
		double p = ((-lo + c2) * lo - c1) * lo + c0;
		double slope = (-3.0 * lo + 2.0 * c2) * lo - c1;
		if (!(p > 0.0) || !(slope < 0.0))
			break;
		double next = lo - p / slope;
		if (!(next > lo))
			break;
		lo = next;
	}
	return lo;
}

// A unit eigenvector of the symmetric 3x3 @p S for its eigenvalue @p e: the largest row of
// adj(S - e I), whose rows are the cross products of two rows of S - e I (each orthogonal to
// the eigenvector). False where that row is not clearly above round-off (e repeated, or the
// other two eigenvalues within 1e-9 of each other relative to their distance from e).
static bool fmEigenvector3(const fmMat3* S, double e, fmVec3* v)
{
	const fmVec3 r0 = fmMakeVec3(S->m[0] - e, S->m[1], S->m[2]);
	const fmVec3 r1 = fmMakeVec3(S->m[3], S->m[4] - e, S->m[5]);
	const fmVec3 r2 = fmMakeVec3(S->m[6], S->m[7], S->m[8] - e);
	const fmVec3 c[3] = {fmCross(r1, r2), fmCross(r2, r0), fmCross(r0, r1)};
	double best = 0.0, rows = fmDot(r0, r0) + fmDot(r1, r1) + fmDot(r2, r2);
	int k = 0;
	for (int i = 0; i < 3; ++i)
		if (fmDot(c[i], c[i]) > best)
		{
			best = fmDot(c[i], c[i]);
			k = i;
		}
	if (!(best > 1e-18 * rows * rows))
		return false;
	*v = fmScale(1.0 / sqrt(best), c[k]);
	return true;
}

// @p S plus w v v^T.
static fmMat3 fmAddDyad3(const fmMat3* S, double w, fmVec3 v)
{
	const double a[3] = {v.x, v.y, v.z};
	fmMat3 out = *S;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			out.m[3 * i + j] += w * a[i] * a[j];
	return out;
}

// The positive part of the symmetric 3x3 @p S (its negative eigenvalues set to zero): S itself
// when positive definite (Sylvester's criterion); else from its smallest eigenvalue (the bound
// above, exact to round-off), the other two as the roots of what remains of the characteristic
// polynomial, and the eigenvector of the one eigenvalue that is removed (one negative) or kept
// (one positive). Where that eigenvector is not defined to round-off, S shifted by its smallest
// eigenvalue instead: positive semi-definite either way.
static fmMat3 fmPositivePart3(const fmMat3* S)
{
	const double* s = S->m;
	if (s[0] > 0.0 && s[0] * s[4] - s[1] * s[3] > 0.0 && fmDet(S) > 0.0)
		return *S;
	double lo = fmSmallestEigenBound3(S);
	if (lo >= 0.0)
		return *S;
	// The other two eigenvalues: x^2 - T x + D with T = tr S - lo, D = c1 - lo T.
	double c1 = s[0] * s[4] + s[0] * s[8] + s[4] * s[8] - s[1] * s[1] - s[2] * s[2] - s[5] * s[5];
	double T = s[0] + s[4] + s[8] - lo, D = c1 - lo * T;
	double high = 0.5 * (T + sqrt(fmMax(T * T - 4.0 * D, 0.0)));
	double middle = T - high;
	fmVec3 v;
	if (middle >= 0.0 && fmEigenvector3(S, lo, &v))
		return fmAddDyad3(S, -lo, v);
	fmMat3 zero = fmZero3();
	if (middle < 0.0 && high <= 0.0)
		return zero;
	if (middle < 0.0 && fmEigenvector3(S, high, &v))
		return fmAddDyad3(&zero, high, v);
	fmMat3 out = *S;
	for (int i = 0; i < 3; ++i)
		out.m[4 * i] -= lo;
	return out;
}

bool fmMaterial_StvkClampedTerms(const fmMaterial* m, const fmMat3* F, fmMat3* Sp)
{
	if (m->model != fm_stvk || !(m->lambda >= 0.0) || !(fmDet(F) >= FM_STVK_FLOOR_J))
		return false;
	fmMat3 G = fmGreenStrain(F);
	fmMat3 S = fmStvkStress(m, &G);
	*Sp = fmPositivePart3(&S);
	return true;
}

bool fmMaterial_StvkClampedHessian(const fmMaterial* m, const fmMat3* F, double* dPdF)
{
	fmMat3 Sp;
	if (!fmMaterial_StvkClampedTerms(m, F, &Sp))
		return false;
	fmStvkTangent(m, F, &Sp, dPdF);
	return true;
}

bool fmMaterial_NeoHookeanClampedTerms(const fmMaterial* m, const fmMat3* F,
                                       fmNeoHookeanTerms* terms)
{
	double J = fmDet(F);
	if (m->model != fm_neoHookean || !(m->lambda >= 0.0) || !(J >= FM_LOG_J_CLAMP))
		return false;
	double c = m->mu - m->lambda * fmMathLog(J);
	if (!(c >= 0.0))
		return false;
	fmMat3 C = fmMatTMul(F, F);
	double smallest = fmMax(fmSmallestEigenBound3(&C), 0.0); // <= s_min^2
	double theta = m->mu * smallest >= c ? 1.0 : m->mu * smallest / c;
	// |skew A|^2 = (|A|^2 - tr AA) / 2.
	terms->G = fmCofactor(F);
	for (int e = 0; e < 9; ++e)
		terms->G.m[e] /= J;
	terms->k = 0.5 * (1.0 - theta) * c;
	terms->t = c - terms->k;
	return true;
}

bool fmMaterial_NeoHookeanClampedHessian(const fmMaterial* m, const fmMat3* F, double* dPdF)
{
	fmNeoHookeanTerms terms;
	if (!fmMaterial_NeoHookeanClampedTerms(m, F, &terms))
		return false;
	fmMat3 W = fmMatMulT(&terms.G, &terms.G); // F^-T F^-1
	const double* g = terms.G.m;
	for (int a = 0; a < 3; ++a)
		for (int b = 0; b < 3; ++b)
			for (int cc = 0; cc < 3; ++cc)
				for (int d = 0; d < 3; ++d)
				{
					double v = m->lambda * g[3 * a + b] * g[3 * cc + d] +
					           terms.t * g[3 * a + d] * g[3 * cc + b];
					if (b == d)
						v += terms.k * W.m[3 * a + cc] + (a == cc ? m->mu : 0.0);
					dPdF[9 * (3 * a + b) + (3 * cc + d)] = v;
				}
	return true;
}

double fmMaterial_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF)
{
	switch (material->model)
	{
	case fm_linear:
		return fmLinear_Evaluate(material, F, P, dPdF);
	case fm_stvk:
		return fmStvk_Evaluate(material, F, P, dPdF);
	case fm_corotated:
	case fm_stretchEnergy:
		return fmStretchModel_Evaluate(material, F, P, dPdF, false);
	case fm_neoHookean:
	{
		// psi and P in closed form, whatever else is asked for (psi must not depend on it).
		double psi = fmNeoHookean_Evaluate(material, F, P);
		if (dPdF)
			fmInvariantModel_Evaluate(material, F, NULL, dPdF);
		return psi;
	}
	case fm_mooneyRivlin:
	case fm_invariantEnergy:
	case fm_neoHookeanIsochoric:
		return fmInvariantModel_Evaluate(material, F, P, dPdF);
	case fm_orthotropicLinear:
	case fm_orthotropicStvk:
	case fm_fibreNeoHookean:
		return fmAniso_EvaluateOwn(material, F, P, dPdF, false);
	default:
		FM_ASSERT(0 && "unknown material model (validate materials before use)");
		if (P)
			*P = fmZero3();
		if (dPdF)
			memset(dPdF, 0, 81 * sizeof(double));
		return NAN;
	}
}

double fmMaterial_EvaluateProjected(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                                    double* dPdF)
{
	switch (material->model)
	{
	case fm_linear:
		// Eigenvalues 2 mu (deviatoric), 0 (rotations) and 2 mu + 3 lambda (volume): already PSD
		// for every valid material.
		return fmLinear_Evaluate(material, F, P, dPdF);
	case fm_corotated:
	case fm_stvk:
	case fm_neoHookean:
	case fm_mooneyRivlin:
	case fm_stretchEnergy:
		return fmStretchModel_Evaluate(material, F, P, dPdF, true);
	case fm_orthotropicLinear:
	case fm_orthotropicStvk:
	case fm_fibreNeoHookean:
		return fmAniso_EvaluateOwn(material, F, P, dPdF, true);
	default:
	{
		double psi = fmMaterial_Evaluate(material, F, P, dPdF);
		if (dPdF)
			fmProjectPSD9(dPdF);
		return psi;
	}
	}
}

// Cholesky without storing the factor beyond need: true when A is positive definite, the
// common case near rest, which then needs no eigen-decomposition.
static bool fmIsPositiveDefinite9(const double* A)
{
	double L[81];
	for (int j = 0; j < 9; ++j)
	{
		double d = A[9 * j + j];
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

void fmProjectPSD9(double* A)
{
	// Work on the symmetric part so round-off asymmetry cannot leak through.
	for (int i = 0; i < 9; ++i)
		for (int j = i + 1; j < 9; ++j)
		{
			double s = 0.5 * (A[9 * i + j] + A[9 * j + i]);
			A[9 * i + j] = s;
			A[9 * j + i] = s;
		}
	if (fmIsPositiveDefinite9(A))
		return;
	// A = Q diag(w) Q^T; the nearest PSD matrix (Frobenius) keeps Q and clamps w at 0.
	double a[81], w[9], Q[81];
	memcpy(a, A, sizeof a);
	fmSymEigenN(a, 9, 1e-12, w, Q); // eigenvalues to ~1e-12 relative: ample for a Newton matrix
	for (int e = 0; e < 9; ++e)
		w[e] = fmMax(w[e], 0.0);
	for (int i = 0; i < 9; ++i)
		for (int j = i; j < 9; ++j)
		{
			double s = 0.0;
			for (int e = 0; e < 9; ++e)
				s += Q[9 * i + e] * w[e] * Q[9 * j + e];
			A[9 * i + j] = s;
			A[9 * j + i] = s;
		}
}
