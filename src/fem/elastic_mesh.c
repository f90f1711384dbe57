// The elastic mesh's and the state's arrays (see elastic_mesh.h).
#include "fem/elastic_mesh.h"

#include "core/core.h"
#include "fem/nodal_pressure.h"
#include "material/material.h"
#include "material/material_aniso.h"

fmMat3 fmTetDeformation(const fmElasticMesh* mesh, const double* x, int t)
{
	const int* n = mesh->tets + 4 * t;
	fmVec3 x0 = fmLoad(x, n[0]);
	fmMat3 Ds = fmMat3FromColumns(fmSub(fmLoad(x, n[1]), x0), fmSub(fmLoad(x, n[2]), x0),
	                              fmSub(fmLoad(x, n[3]), x0));
	return fmMatMul(&Ds, &mesh->DmInv[t]);
}

double fmTetEvaluate(const fmElasticMesh* mesh, int t, const fmMat3* F, fmMat3* P, double* dPdF,
                     bool project)
{
	const fmMaterial* m = fmTetMaterial(mesh, t);
	if (mesh->fibres != NULL && fmMaterialModel_IsAnisotropic(m->model))
	{
		fmMat3 R = fmMaterial_Axes(m, &mesh->fibres[t]);
		return fmAniso_Evaluate(m, &R, F, P, dPdF, project);
	}
	return project ? fmMaterial_EvaluateProjected(m, F, P, dPdF)
	               : fmMaterial_Evaluate(m, F, P, dPdF);
}

bool fmElasticMesh_IsLinear(const fmElasticMesh* mesh)
{
	for (int k = 0; k < mesh->materialCount; ++k)
		if (mesh->materials[k].model != fm_linear &&
		    mesh->materials[k].model != fm_orthotropicLinear)
			return false;
	return mesh->material.model == fm_linear || mesh->material.model == fm_orthotropicLinear;
}

bool fmElasticMesh_Allocate(fmElasticMesh* mesh, int vertexCount, int tetCount)
{
	size_t n = (size_t)vertexCount, m = (size_t)tetCount;
	mesh->vertexCount = vertexCount;
	mesh->tetCount = tetCount;
	mesh->x0 = FM_ALLOC_ARRAY(double, 3 * n);
	mesh->mass = FM_ALLOC_ZERO(double, n);
	mesh->smoothWeight = FM_ALLOC_ZERO(double, n);
	mesh->vertexTetStart = FM_ALLOC_ZERO(int, n + 1);
	mesh->vertexTets = FM_ALLOC_ARRAY(int, 4 * m);
	mesh->tets = FM_ALLOC_ARRAY(int, 4 * m);
	mesh->DmInv = FM_ALLOC_ARRAY(fmMat3, m);
	mesh->restVolume = FM_ALLOC_ARRAY(double, m);
	return mesh->x0 && mesh->mass && mesh->smoothWeight && mesh->vertexTetStart &&
	       mesh->vertexTets && mesh->tets && mesh->DmInv && mesh->restVolume;
}

void fmElasticMesh_Free(fmElasticMesh* mesh)
{
	size_t n = (size_t)mesh->vertexCount, m = (size_t)mesh->tetCount;
	FM_FREE_ARRAY(mesh->x0, double, 3 * n);
	FM_FREE_ARRAY(mesh->mass, double, n);
	FM_FREE_ARRAY(mesh->smoothWeight, double, n);
	FM_FREE_ARRAY(mesh->vertexTetStart, int, n + 1);
	FM_FREE_ARRAY(mesh->vertexTets, int, 4 * m);
	FM_FREE_ARRAY(mesh->tets, int, 4 * m);
	FM_FREE_ARRAY(mesh->DmInv, fmMat3, m);
	FM_FREE_ARRAY(mesh->restVolume, double, m);
	FM_FREE_ARRAY(mesh->edges, int, 2 * (size_t)mesh->edgeCount);
	FM_FREE_ARRAY(mesh->restLength, double, mesh->edgeCount);
	FM_FREE_ARRAY(mesh->springK, double, mesh->edgeCount);
	FM_FREE_ARRAY(mesh->fvmNormals, fmVec3, 4 * m);
	fmFree(mesh->surface);
	FM_FREE_ARRAY(mesh->materials, fmMaterial, mesh->materialCount);
	FM_FREE_ARRAY(mesh->tetMaterial, uint16_t, m);
	FM_FREE_ARRAY(mesh->fibres, fmVec3, m);
	FM_FREE_ARRAY(mesh->plasticStrain, double, m);
	FM_FREE_ARRAY(mesh->restDmInv, fmMat3, m);
	FM_FREE_ARRAY(mesh->goodDmInv, fmMat3, m);
	FM_FREE_ARRAY(mesh->goodStrain, double, m);
	fmNodalPressure_Free(mesh);
}

bool fmBodyState_Allocate(fmBodyState* state, int vertexCount)
{
	size_t n = (size_t)vertexCount;
	state->x = FM_ALLOC_ARRAY(double, 3 * n);
	state->v = FM_ALLOC_ZERO(double, 3 * n);
	state->f = FM_ALLOC_ZERO(double, 3 * n);
	state->invMass = FM_ALLOC_ZERO(double, n);
	state->pinned = FM_ALLOC_ZERO(uint8_t, n);
	return state->x && state->v && state->f && state->invMass && state->pinned;
}

void fmBodyState_Free(fmBodyState* state, int vertexCount)
{
	size_t n = (size_t)vertexCount;
	FM_FREE_ARRAY(state->x, double, 3 * n);
	FM_FREE_ARRAY(state->v, double, 3 * n);
	FM_FREE_ARRAY(state->f, double, 3 * n);
	FM_FREE_ARRAY(state->invMass, double, n);
	FM_FREE_ARRAY(state->pinned, uint8_t, n);
}
