// Constitutive models: pure functions of the deformation gradient F (docs/materials.md).
// dP/dF is a 9x9 row-major matrix: dPdF[9 * (3 * i + j) + (3 * k + l)] = d P_ij / d F_kl,
// with P_ij = P.m[3 * i + j]. It is symmetric (P is a gradient).
#pragma once

#include <femto/types.h>

// StVK's volume floor (issue 29: inversion-safe StVK): StVK softens under strong compression (its
// stress peaks near a third of the volume lost and falls to zero as a tet flattens), so a loaded
// body turns tets inside out. Below J = det F = FM_STVK_FLOOR_J its energy gains
// psi(J) = kappa J0 ((J - J0) - J0 ln(J / J0)), J0 = FM_STVK_FLOOR_J and
// kappa = FM_STVK_FLOOR_STIFFNESS (lambda + 2 mu): zero with zero slope at J0, curvature kappa
// there, a push back along dJ/dF that grows like 1/J as the tet flattens. Below
// FM_STVK_FLOOR_JC it continues as its quadratic (finite at J = 0 and beyond, so a tet turned over
// is pushed back out: Irving et al. 2004's recovery), as Neo-Hookean's ln J does below its clamp.
// Above the floor StVK is the seeds' own, bit for bit.
#define FM_STVK_FLOOR_J 0.5
#define FM_STVK_FLOOR_JC 0.3
#define FM_STVK_FLOOR_STIFFNESS 4.0

// Whether the model's energy is a part without lambda plus a volume term in J alone
// (fmMaterial.nodalPressure moves that term onto vertex patches, fem/nodal_pressure.h).
bool fmMaterialModel_SplitsVolume(fmMaterialModel model);

// Energy density psi(F) (J/m^3). Every pointer output may be NULL to skip it:
// P = d psi / dF (Pa), dPdF (Pa). Returns psi.
double fmMaterial_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF);

// Like fmMaterial_Evaluate, but dPdF (not NULL) comes back projected onto the positive
// semi-definite cone: the same matrix as fmProjectPSD9 of the exact dP/dF, computed in closed
// form for every model but the user invariant energy (no 9x9 eigen-solve; that one uses
// fmProjectPSD9). For the implicit integrator's Newton steps.
double fmMaterial_EvaluateProjected(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                                    double* dPdF);

// StVK's dP/dF made positive semi-definite without an SVD, for the Newton matrix: the exact
// dP/dF is the stress term dF -> dF S plus a part that is PSD for lambda >= 0
// (dF : H dF = lambda tr(A)^2 + 2 mu |sym A|^2, A = F^T dF); with S (the second Piola-Kirchhoff
// stress) replaced by its positive part the sum is PSD. Where S is positive definite this is the
// exact dP/dF (fmMaterial_EvaluateProjected's matrix up to round-off); under compression it may
// keep curvature the nearest PSD matrix would drop. False (dPdF untouched) where it does not
// apply: not StVK, lambda < 0, or det F below the volume floor's FM_STVK_FLOOR_J.
bool fmMaterial_StvkClampedHessian(const fmMaterial* material, const fmMat3* F, double* dPdF);

// Neo-Hookean's dP/dF made positive semi-definite without an SVD, for the Newton matrix. With
// A = F^-1 dF and c = mu - lambda ln J the exact tangent's quadratic form is
// mu |dF|^2 + lambda tr(A)^2 + c |sym A|^2 - c |skew A|^2, indefinite only through the last term;
// since |skew A| <= |dF| / s_min (s_min the smallest singular value of F), keeping
// theta = min(1, mu s_min^2 / c) of that term makes the form PSD (s_min^2 from a lower bound on
// the smallest eigenvalue of F^T F). theta = 1, the exact tangent, wherever
// mu s_min^2 >= c (at rest and in tension); under compression the rotations keep up to
// mu (1 - s_min^2) of stiffness the nearest PSD matrix would drop. False (dPdF untouched) where it
// does not apply: not Neo-Hookean, lambda < 0, c < 0, or J below FM_LOG_J_CLAMP.
bool fmMaterial_NeoHookeanClampedHessian(const fmMaterial* material, const fmMat3* F, double* dPdF);

// The terms of the two tangents above, for a tet's stiffness straight from its shape gradients
// (forces.c): StVK's stress's positive part S+ (the tangent is dF -> dF S+ +
// mu (F F^T dF + F dF^T F) + lambda F (F : dF)); Neo-Hookean's G = F^-T and the weights t, k of
// its tangent mu dF + lambda G (G : dF) + t G dF^T G + k G G^T dF. False where the tangents
// decline.
bool fmMaterial_StvkClampedTerms(const fmMaterial* material, const fmMat3* F, fmMat3* Sp);

/// Neo-Hookean's clamped tangent's terms (fmMaterial_NeoHookeanClampedTerms).
typedef struct fmNeoHookeanTerms
{
	fmMat3 G; ///< F^-T
	double t; ///< the weight of dF -> G dF^T G: c - k
	double k; ///< the weight of dF -> G G^T dF: (1 - theta) c / 2
} fmNeoHookeanTerms;

bool fmMaterial_NeoHookeanClampedTerms(const fmMaterial* material, const fmMat3* F,
                                       fmNeoHookeanTerms* terms);

// Project a symmetric 9x9 matrix onto the positive semi-definite cone (clamp negative eigenvalues
// to zero) in place.
void fmProjectPSD9(double* A);

// StVK's volume floor (above) added to @p P and @p dPdF (each may be NULL) where det F is below
// it; returns its energy density (0 above it).
double fmMaterial_AddStvkFloor(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                               double* dPdF);

// StVK's volume floor as a function of J (above): its energy density, first and second
// derivatives in J into @p out (all zero at and above FM_STVK_FLOOR_J); false there.
bool fmMaterial_StvkFloor(const fmMaterial* material, double J, double out[3]);
