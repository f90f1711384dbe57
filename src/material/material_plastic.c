// Plasticity's law (material_plastic.h). The return map is the classical one of J2 flow on the
// logarithmic strain (Simo, "Algorithms for static and dynamic multiplicative plasticity", CMAME
// 1992; de Souza Neto, Peric and Owen, "Computational Methods for Plasticity", ch. 14): with Fe = U
// diag(s) V^T, e = ln s, its deviator d = e - tr(e)/3 and the Kirchhoff stress's equivalent q = 3
// mu |d| sqrt(2/3) (Hencky's law, 2 mu d), a tet yields where q > sigma_y + H alpha; the flow
// dgamma = (q - sigma_y - H alpha) / (3 mu + H) (scaled by c h / (1 + c h) with a creep rate c:
// Perzyna's overstress, implicit in h) brings q down by 3 mu dgamma along d, alpha up by dgamma;
// the volume part of e stays. For any elastic law of femto's isotropic ones this is the same map
// (their stresses agree with Hencky's at the elastic strains a metal reaches; docs/materials.md).
#include "material/material_plastic.h"

#include "core/det_math.h"
#include "material/material.h"
#include "math/svd3.h"

#include <math.h>
#include <stdio.h>

bool fmPlasticity_Validate(const fmMaterial* m, char* why, size_t size)
{
	const fmPlasticity* p = &m->plasticity;
	const double values[4] = {p->yieldStress, p->hardening, p->creepRate, p->maxPlasticStrain};
	static const char* const names[4] = {"yieldStress", "hardening", "creepRate",
	                                     "maxPlasticStrain"};
	for (int k = 0; k < 4; ++k)
		if (!(values[k] >= 0.0 && isfinite(values[k])))
		{
			snprintf(why, size, "plasticity.%s = %g must be finite and >= 0", names[k], values[k]);
			return false;
		}
	bool any = p->hardening > 0.0 || p->creepRate > 0.0 || p->maxPlasticStrain > 0.0;
	if (!(p->yieldStress > 0.0) && any)
	{
		snprintf(why, size,
		         "plasticity needs a yieldStress > 0 (Pa; a yield strain times Young's modulus): "
		         "its hardening, creep rate or cap alone do nothing");
		return false;
	}
	fmMaterialModel model = m->model;
	if (p->yieldStress > 0.0 && (model == fm_linear || model == fm_stretchEnergy ||
	                             model == fm_invariantEnergy || model == fm_orthotropicLinear ||
	                             model == fm_orthotropicStvk || model == fm_fibreNeoHookean))
	{
		snprintf(why, size,
		         "plasticity goes with the isotropic large-strain models (stvk, corotated, "
		         "neohookean, mooney-rivlin, neohookean-isochoric), not %s",
		         fmMaterialModelName(model));
		return false;
	}
	return true;
}

// The material's von Mises stress sqrt(3/2) |dev tau| at @p F (tau = P F^T, Kirchhoff).
static double fmVonMises(const fmMaterial* m, const fmMat3* F)
{
	fmMat3 P;
	fmMaterial_Evaluate(m, F, &P, NULL);
	fmMat3 tau = fmMatMulT(&P, F);
	double pressure = fmTrace(&tau) / 3.0, dev2 = 0.0;
	for (int k = 0; k < 9; ++k)
	{
		double v = tau.m[k] - (k % 4 == 0 ? pressure : 0.0);
		dev2 += v * v;
	}
	return sqrt(1.5 * dev2);
}

// The elastic part with the log strain's deviator scaled by @p keep: U diag(exp(mean + keep d))
// V^T.
static fmMat3 fmReturned(const fmMat3* U, const fmMat3* V, double mean, const double d[3],
                         double keep)
{
	fmMat3 S = fmZero3();
	for (int k = 0; k < 3; ++k)
		S.m[4 * k] = fmDetExp(mean + keep * d[k]);
	fmMat3 US = fmMatMul(U, &S);
	return fmMatMulT(&US, V);
}

// Iterations of the flow that puts the returned state on the yield surface of the material's
// own stress (Hencky's 3 mu + H as the slope: each one gains two or more digits).
#define FM_PLASTIC_RETURN_ITERATIONS 6

double fmPlasticity_Share(const fmMaterial* m, double seconds)
{
	double c = m->plasticity.creepRate;
	return c > 0.0 && seconds > 0.0 && isfinite(seconds) ? c * seconds / (1.0 + c * seconds) : 1.0;
}

bool fmPlasticity_Return(const fmMaterial* m, const fmMat3* Fe, double share, double* alpha,
                         fmMat3* out, double stress[2])
{
	const fmPlasticity* p = &m->plasticity;
	if (!(p->yieldStress > 0.0) || (p->maxPlasticStrain > 0.0 && *alpha >= p->maxPlasticStrain))
		return false;
	// The yield test reads the material's own Kirchhoff stress (every law's is Hencky's 2 mu d
	// at a metal's elastic strains; at larger ones, a soft body hardened far, they part); a tet
	// inside its yield surface costs that one stress, no SVD.
	const double H = p->hardening, yield = p->yieldStress + H * *alpha;
	const double qm = fmVonMises(m, Fe);
	if (!(qm > yield) || !(fmDet(Fe) > 0.0))
		return false;
	fmMat3 U, V;
	fmVec3 sv;
	fmSvd3(Fe, &U, &sv, &V);
	double s[3] = {sv.x, sv.y, sv.z}, e[3], d[3];
	if (!(s[0] > 0.0 && s[1] > 0.0 && s[2] > 0.0))
		return false;
	for (int k = 0; k < 3; ++k)
		e[k] = fmMathLog(s[k]);
	double mean = (e[0] + e[1] + e[2]) / 3.0, norm2 = 0.0;
	for (int k = 0; k < 3; ++k)
	{
		d[k] = e[k] - mean;
		norm2 += d[k] * d[k];
	}
	const double mu = m->mu, slope = 3.0 * mu + H, q = 3.0 * mu * sqrt(2.0 / 3.0 * norm2);
	if (!(q > 0.0))
		return false;
	// The rate-independent flow: the log strain's deviator shrinks by 3 mu flow of Hencky's q
	// (the flow direction, radial), the flow chosen so that the returned state's stress is
	// yield + H flow.
	double flow = (qm - yield) / slope, returned = qm;
	fmMat3 Fr = *Fe;
	for (int it = 0; it <= FM_PLASTIC_RETURN_ITERATIONS; ++it)
	{
		flow = fmMin(fmMax(flow, 0.0), q / (3.0 * mu));
		Fr = fmReturned(&U, &V, mean, d, 1.0 - 3.0 * mu * flow / q);
		returned = fmVonMises(m, &Fr);
		double miss = returned - (yield + H * flow);
		if (!(fabs(miss) > 1e-12 * yield) || it == FM_PLASTIC_RETURN_ITERATIONS)
			break; // (the last one keeps the flow its state was made with)
		flow += miss / slope;
	}
	// Creep takes its share of it; the cap stops it.
	double take = share;
	if (p->maxPlasticStrain > 0.0 && take * flow > p->maxPlasticStrain - *alpha)
		take = (p->maxPlasticStrain - *alpha) / flow;
	if (take < 1.0)
	{
		flow *= take;
		Fr = fmReturned(&U, &V, mean, d, 1.0 - 3.0 * mu * flow / q);
		returned = fmVonMises(m, &Fr);
	}
	*out = Fr;
	*alpha += flow;
	if (stress != NULL)
	{
		stress[0] = qm;
		stress[1] = returned;
	}
	return true;
}
