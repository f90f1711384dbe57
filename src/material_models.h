// Internal: the per-model kernels behind fmMaterial_Evaluate (docs/materials.md).
// Each returns psi and fills P and dPdF (layout of material.h) when they are not NULL.
#pragma once

#include <femto/types.h>

// Relative gap below which two principal stretches count as equal when a difference quotient
// of the energy gradient is needed (sqrt of machine epsilon balances cancellation and
// truncation).
#define FM_STRETCH_GAP 1e-8

// Below this volume ratio J = det F the ln J of the Neo-Hookean and Mooney-Rivlin energies is
// continued by its second-order Taylor polynomial (the invertible-FEM idea of Irving et al.
// 2004 applied to J), so the energy stays finite, C2 and restoring for J <= 0.
#define FM_LOG_J_CLAMP 0.2

// l(J) = ln J continued below FM_LOG_J_CLAMP; out = {l, l', l''}.
void fmClampedLogJ(double J, double out[3]);

// Energies of the principal stretches (SVD, docs/materials.md): fixed corotated, the user's
// fmStretchEnergyFcn, and StVK / Neo-Hookean / Mooney-Rivlin. With project, dPdF is projected onto
// the PSD cone analytically (its eigenvectors are known in closed form).
double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF,
                               bool project);

// Energies of the invariants (I1, I2, J) by the chain rule: Neo-Hookean and Mooney-Rivlin with the
// clamped ln J, and the user's fmInvariantEnergyFcn.
double fmInvariantModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                                 double* dPdF);
