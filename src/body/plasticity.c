// Plasticity in a body (plasticity.h): the per-tet state and the flow after each substep; the
// law is material/material_plastic.c's.
#include "body/plasticity.h"

#include "body/body.h"
#include "core/core.h"
#include "core/det_math.h"
#include "material/material.h"
#include "material/material_plastic.h"
#include "solver/solver_cache.h"

#include <string.h>

// The rest data's change is seen by what keeps evaluations of it: the implicit solve's kept
// forces and Newton matrix. (The explicit kernels' blocks do not apply to a plastic body:
// tet_blocks.h.)
static void fmPlasticityRestMoved(fmBody* b)
{
	if (b->solverCache != NULL)
		fmSolverCache_RestMoved(b->solverCache);
	b->energyStale = true;
}

bool fmPlasticity_Allocate(fmBody* b)
{
	fmElasticMesh* m = &b->mesh;
	if (m->plasticStrain != NULL)
		return true;
	size_t count = (size_t)m->tetCount;
	m->plasticStrain = FM_ALLOC_ZERO(double, count);
	m->goodStrain = FM_ALLOC_ZERO(double, count);
	m->restDmInv = FM_ALLOC_ARRAY(fmMat3, count);
	m->goodDmInv = FM_ALLOC_ARRAY(fmMat3, count);
	if (m->plasticStrain == NULL || m->restDmInv == NULL || m->goodStrain == NULL ||
	    m->goodDmInv == NULL)
	{
		fmPlasticity_Free(b);
		return false;
	}
	memcpy(m->restDmInv, m->DmInv, sizeof(fmMat3) * count);
	memcpy(m->goodDmInv, m->DmInv, sizeof(fmMat3) * count);
	return true;
}

void fmPlasticity_Free(fmBody* b)
{
	fmElasticMesh* m = &b->mesh;
	size_t count = (size_t)m->tetCount;
	FM_FREE_ARRAY(m->plasticStrain, double, count);
	FM_FREE_ARRAY(m->goodStrain, double, count);
	FM_FREE_ARRAY(m->restDmInv, fmMat3, count);
	FM_FREE_ARRAY(m->goodDmInv, fmMat3, count);
	m->plasticStrain = m->goodStrain = NULL;
	m->restDmInv = m->goodDmInv = NULL;
	b->plasticKept = false;
}

void fmPlasticity_KeepGood(fmBody* b)
{
	fmElasticMesh* m = &b->mesh;
	if (m->plasticStrain == NULL)
		return;
	memcpy(m->goodDmInv, m->DmInv, sizeof(fmMat3) * (size_t)m->tetCount);
	memcpy(m->goodStrain, m->plasticStrain, sizeof(double) * (size_t)m->tetCount);
	b->plasticWorkGood = b->plasticWork;
	b->plasticKept = true;
}

void fmPlasticity_RestoreGood(fmBody* b)
{
	fmElasticMesh* m = &b->mesh;
	if (m->plasticStrain == NULL || !b->plasticKept)
		return;
	memcpy(m->DmInv, m->goodDmInv, sizeof(fmMat3) * (size_t)m->tetCount);
	memcpy(m->plasticStrain, m->goodStrain, sizeof(double) * (size_t)m->tetCount);
	b->plasticWork = b->plasticWorkGood;
	b->plasticKept = false;
	fmPlasticityRestMoved(b);
}

bool fmPlasticity_AnyFlows(const fmBody* b)
{
	const fmElasticMesh* m = &b->mesh;
	bool any = fmPlasticity_Flows(&m->material);
	for (int k = 0; k < m->materialCount; ++k)
		any = any || fmPlasticity_Flows(&m->materials[k]);
	return any;
}

bool fmPlasticity_Prepare(fmBody* b)
{
	return !fmPlasticity_AnyFlows(b) || fmPlasticity_Allocate(b);
}

void fmPlasticity_Unflowed(fmBody* b)
{
	fmElasticMesh* m = &b->mesh;
	if (m->plasticStrain == NULL)
		return;
	memcpy(m->DmInv, m->restDmInv, sizeof(fmMat3) * (size_t)m->tetCount);
	memset(m->plasticStrain, 0, sizeof(double) * (size_t)m->tetCount);
}

double fmPlasticity_Flow(fmBody* b, double h)
{
	fmElasticMesh* m = &b->mesh;
	if (m->plasticStrain == NULL)
		return 0.0;
	double largest = 0.0, work = 0.0;
	for (int t = 0; t < m->tetCount; ++t)
	{
		const fmMaterial* material = fmTetMaterial(m, t);
		if (!fmPlasticity_Flows(material))
			continue;
		fmMat3 F = fmTetDeformation(m, b->state.x, t), Fe;
		double alpha = m->plasticStrain[t], stress[2] = {0.0, 0.0};
		double share = fmPlasticity_Share(material, h);
		if (!fmPlasticity_Return(material, &F, share, &alpha, &Fe, stress))
			continue;
		// Dm^-1 Fp^-1 with the new Fp: Dm^-1 F^-1 Fe, so that Ds Dm^-1 is Fe.
		fmMat3 Finv, K;
		if (!fmInverse(&F, &Finv))
			continue;
		K = fmMatMul(&Finv, &Fe);
		// The stress along the flow, by the trapezoid from where it starts: rate-independent, the
		// yield surface the tet left (exact for linear hardening); creeping, the overstressed
		// trial state (the elastic energy the return takes).
		double start = share < 1.0 ? stress[0]
		                           : material->plasticity.yieldStress +
		                                 material->plasticity.hardening * m->plasticStrain[t];
		work += m->restVolume[t] * 0.5 * (start + stress[1]) * (alpha - m->plasticStrain[t]);
		m->DmInv[t] = fmMatMul(&m->DmInv[t], &K);
		double yieldStrain = material->plasticity.yieldStress / (3.0 * material->mu);
		largest = fmMax(largest, (alpha - m->plasticStrain[t]) / yieldStrain);
		m->plasticStrain[t] = alpha;
	}
	if (largest > 0.0)
	{
		b->plasticWork += work;
		fmPlasticityRestMoved(b);
	}
	return largest;
}

double fmPlasticity_LargestStrain(const fmBody* b)
{
	double largest = 0.0;
	for (int t = 0; b->mesh.plasticStrain != NULL && t < b->mesh.tetCount; ++t)
		largest = fmMax(largest, b->mesh.plasticStrain[t]);
	return largest;
}
