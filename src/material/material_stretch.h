// Energies of the principal stretches (material_stretch.c, docs/materials.md).
#pragma once

#include <femto/types.h>

#include <stdbool.h>

// Relative gap below which two principal stretches count as equal when a difference quotient
// of the energy gradient is needed (sqrt of machine epsilon balances cancellation and
// truncation).
#define FM_STRETCH_GAP 1e-8

// Fixed corotated psi and, when not NULL, P = 2 mu (F - R) + lambda (J - 1) cof F, given F's
// rotation R (fmPolarRotationFast, or the batched polar kernel of tet_kernel.h: the same bits).
double fmCorotated_Stress(const fmMaterial* material, const fmMat3* F, const fmMat3* R, fmMat3* P);

// Fixed corotated, the user's fmStretchEnergyFcn, and StVK / Neo-Hookean / Mooney-Rivlin in
// stretches: psi, and P and dPdF (layout of material.h) when not NULL. With project, dPdF is
// projected onto the PSD cone analytically (its eigenvectors are known in closed form).
double fmStretchModel_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF,
                               bool project);
