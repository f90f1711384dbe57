// Internal: the per-model kernels behind fmMaterial_Evaluate (docs/materials.md).
// Each returns psi and fills P and dPdF (layout of material.h) when they are not NULL.
#pragma once

#include <femto/types.h>

// Below this volume ratio J = det F the ln J of the Neo-Hookean and Mooney-Rivlin energies is
// continued by its second-order Taylor polynomial (the invertible-FEM idea of Irving et al.
// 2004 applied to J), so the energy stays finite, C2 and restoring for J <= 0.
#define FM_LOG_J_CLAMP 0.2

// Energies of the principal stretches (SVD, docs/materials.md): fixed corotated and the user's
// fmStretchEnergyFcn.
double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
							   double* dPdF);

// Energies of the invariants (I1, I2, J) by the chain rule: Neo-Hookean and Mooney-Rivlin with the
// clamped ln J, and the user's fmInvariantEnergyFcn.
double fmInvariantModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
								 double* dPdF);
