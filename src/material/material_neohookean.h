// The compressible Neo-Hookean energy and stress in closed form (material_neohookean.c), the
// implicit and explicit steps' inner loop for that model.
#pragma once

#include <femto/types.h>

// psi = mu/2 (I1 - 3) - mu l(J) + lambda/2 l(J)^2 (l: the clamped ln J of
// material_invariant.h) and, when @p P is not NULL, P = mu F + (lambda l - mu) l'(J) cof F.
// The same function as the Mooney-Rivlin chain rule with c01 = 0, about 3x fewer operations.
double fmNeoHookean_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P);
