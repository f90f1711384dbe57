// Compressible Neo-Hookean (docs/materials.md) written out for psi and P: with I1 = F:F,
// J = det F and dJ/dF = cof F, psi = mu/2 (I1 - 3) - mu l(J) + lambda/2 l(J)^2 gives
// P = mu F + (lambda l(J) - mu) l'(J) cof F. The tangent dP/dF stays with the general chain rule
// (material_invariant.c) and the analytic projection (material_stretch.c).
#include "material/material_neohookean.h"

#include "material/material_invariant.h"

double fmNeoHookean_Evaluate(const fmMaterial* material, const fmMat3* F, fmMat3* P)
{
	const double* f = F->m;
	const double mu = material->mu, lambda = material->lambda;
	fmMat3 C = fmCofactor(F);
	double J = f[0] * C.m[0] + f[1] * C.m[1] + f[2] * C.m[2]; // det F along the first row
	double I1 = 0.0;
	for (int k = 0; k < 9; ++k)
		I1 += f[k] * f[k];
	double l[3];
	fmClampedLogJ(J, l);
	if (P)
	{
		double k = (lambda * l[0] - mu) * l[1];
		for (int e = 0; e < 9; ++e)
			P->m[e] = mu * f[e] + k * C.m[e];
	}
	return 0.5 * mu * (I1 - 3.0) - mu * l[0] + 0.5 * lambda * l[0] * l[0];
}
