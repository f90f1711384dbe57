// Internal: the per-model kernels behind fmMaterial_Evaluate (docs/materials.md).
// Each returns psi and fills P and dPdF (layout of material.h) when they are not NULL.
#pragma once

#include <femto/types.h>

// Below this principal stretch the logarithm in the Neo-Hookean and Mooney-Rivlin energies is
// continued by its second-order Taylor polynomial (invertible FEM, Irving et al. 2004), so the
// energy stays finite and restoring for J <= 0.
#define FM_STRETCH_CLAMP 0.2

// Energies of the principal stretches (SVD, docs/materials.md): fixed corotated,
// clamped Neo-Hookean, clamped Mooney-Rivlin, and the user's fmStretchEnergyFcn.
double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
							   double* dPdF);

// The user's fmInvariantEnergyFcn of (I1, I2, J) by the chain rule.
double fmInvariantModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
								 double* dPdF);
