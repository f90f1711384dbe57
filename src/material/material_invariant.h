// Energies of the invariants I1, I2, J (material_invariant.c, docs/materials.md).
#pragma once

#include <femto/types.h>

// Below this volume ratio J = det F the ln J of the Neo-Hookean and Mooney-Rivlin energies is
// continued by its second-order Taylor polynomial (the invertible-FEM idea of Irving et al.
// 2004 applied to J), so the energy stays finite, C2 and restoring for J <= 0.
#define FM_LOG_J_CLAMP 0.2

// l(J) = ln J continued below FM_LOG_J_CLAMP; out = {l, l', l''}.
void fmClampedLogJ(double J, double out[3]);

// d2v/dF2 of the three invariants v = (I1, I2, J) at F (@p I1 its first), added with weights
// w[0..2] to the 9x9 @p dPdF (row 3 i + j, column 3 k + l).
void fmAddInvariantCurvature(const fmMat3* F, double I1, const double w[3], double* dPdF);

// Neo-Hookean and Mooney-Rivlin with the clamped ln J, and the user's fmInvariantEnergyFcn, by
// the chain rule: psi, and P and dPdF (layout of material.h) when not NULL.
double fmInvariantModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P,
                                 double* dPdF);
