// The averaged nodal pressure tet (nodal_pressure.h): the nodal data, the patches' pressures and
// the forces, and the per-tet pieces the Newton matrix and the stability limit are made of.
#include "fem/nodal_pressure.h"

#include "core/core.h"
#include "core/det_math.h"
#include "fem/forces.h"
#include "material/material.h"
#include "material/material_invariant.h"

#include <math.h>
#include <string.h>

// The materials as given: `materials` for a body of regions, else `material` alone.
static const fmMaterial* fmUserMaterials(const fmElasticMesh* mesh, int* count)
{
	*count = mesh->materialCount > 0 ? mesh->materialCount : 1;
	return mesh->materialCount > 0 ? mesh->materials : &mesh->material;
}

// The law of a nodal material's volume term, and the material without it (@p part) and its
// stiffness k: lambda for linear and Neo-Hookean, lambda - 4 c01 for Mooney-Rivlin (whose
// (lambda - 4 c01)/2 l(J)^2 is the volume term), kappa = lambda + 2/3 mu for the isochoric
// split (kappa/2 (J - 1)^2).
static fmNodalLaw fmNodalSplit(fmMaterial* part, double* k)
{
	switch (part->model)
	{
	case fm_mooneyRivlin:
		*k = part->lambda - 4.0 * part->c01;
		part->lambda = 4.0 * part->c01;
		return fm_nodalLog;
	case fm_neoHookeanIsochoric:
		*k = part->lambda + 2.0 / 3.0 * part->mu;
		part->lambda = -2.0 / 3.0 * part->mu;
		return fm_nodalQuadratic;
	case fm_linear:
		*k = part->lambda;
		part->lambda = 0.0;
		return fm_nodalLinear;
	default: // fm_neoHookean (fmMaterial_Validate admits no other)
		*k = part->lambda;
		part->lambda = 0.0;
		return fm_nodalLog;
	}
}

void fmNodalPressure_Free(fmElasticMesh* mesh)
{
	int count;
	fmUserMaterials(mesh, &count);
	FM_FREE_ARRAY(mesh->tetParts, fmMaterial, count);
	FM_FREE_ARRAY(mesh->patchVolume, double, mesh->vertexCount);
	FM_FREE_ARRAY(mesh->patchBulk, double, mesh->vertexCount);
	FM_FREE_ARRAY(mesh->nodalPressure, double, mesh->vertexCount);
	FM_FREE_ARRAY(mesh->nodalCurvature, double, mesh->vertexCount);
	FM_FREE_ARRAY(mesh->patchVertices, int, mesh->patchMost);
	FM_FREE_ARRAY(mesh->patchGrads, fmVec3, mesh->patchMost);
	mesh->tetParts = NULL;
	mesh->patchVolume = mesh->patchBulk = mesh->nodalPressure = mesh->nodalCurvature = NULL;
	mesh->patchVertices = NULL;
	mesh->patchGrads = NULL;
	mesh->patchMost = 0;
}

// The tet parts, the law and the patches (zeroed, then summed over the nodal tets) from the
// materials as they are now, into the mesh's arrays (allocated, the flags' pattern unchanged).
static void fmFillNodal(fmElasticMesh* mesh)
{
	int count;
	const fmMaterial* user = fmUserMaterials(mesh, &count);
	for (int k = 0; k < count; ++k)
	{
		double bulk;
		mesh->tetParts[k] = user[k];
		if (user[k].nodalPressure)
			mesh->nodalLaw = (int)fmNodalSplit(&mesh->tetParts[k], &bulk);
	}
	memset(mesh->patchVolume, 0, sizeof(double) * (size_t)mesh->vertexCount);
	memset(mesh->patchBulk, 0, sizeof(double) * (size_t)mesh->vertexCount);
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmMaterial part = *fmTetUserMaterial(mesh, t);
		double bulk, quarter = 0.25 * mesh->restVolume[t];
		if (!part.nodalPressure)
			continue;
		fmNodalSplit(&part, &bulk);
		for (int a = 0; a < 4; ++a)
		{
			mesh->patchVolume[mesh->tets[4 * t + a]] += quarter;
			mesh->patchBulk[mesh->tets[4 * t + a]] += quarter * bulk;
		}
	}
}

fmResult fmNodalPressure_Prepare(fmElasticMesh* mesh, fmDiagnostic* diag)
{
	int count, law = -1, first = -1;
	const fmMaterial* user = fmUserMaterials(mesh, &count);
	for (int k = 0; k < count; ++k)
	{
		if (!user[k].nodalPressure)
			continue;
		fmMaterial part = user[k];
		double bulk;
		int own = (int)fmNodalSplit(&part, &bulk);
		if (law >= 0 && own != law)
			return fmDiagError(diag, fm_errParameter, "", 0, 0,
			                   "nodalPressure: the body's nodal materials share their vertices' "
			                   "volume term, so they need one volume law (%s and %s differ: "
			                   "linear, the log of J, or (J - 1)^2)",
			                   fmMaterialModelName(user[first].model),
			                   fmMaterialModelName(part.model));
		law = own;
		first = first < 0 ? k : first;
	}
	fmNodalPressure_Free(mesh);
	if (law < 0)
		return fm_ok;
	if (mesh->forceModel != fm_fem)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "nodalPressure needs the fem force model, not %s",
		                   fmForceModelName(mesh->forceModel));
	size_t n = (size_t)mesh->vertexCount;
	mesh->tetParts = FM_ALLOC_ARRAY(fmMaterial, count);
	mesh->patchVolume = FM_ALLOC_ARRAY(double, n);
	mesh->patchBulk = FM_ALLOC_ARRAY(double, n);
	mesh->nodalPressure = FM_ALLOC_ARRAY(double, n);
	mesh->nodalCurvature = FM_ALLOC_ARRAY(double, n);
	mesh->patchMost = fmNodalPressure_MaxPatch(mesh);
	mesh->patchVertices = FM_ALLOC_ARRAY(int, mesh->patchMost);
	mesh->patchGrads = FM_ALLOC_ARRAY(fmVec3, mesh->patchMost);
	if (mesh->tetParts == NULL || mesh->patchVolume == NULL || mesh->patchBulk == NULL ||
	    mesh->nodalPressure == NULL || mesh->nodalCurvature == NULL ||
	    (mesh->patchMost > 0 && (mesh->patchVertices == NULL || mesh->patchGrads == NULL)))
	{
		fmNodalPressure_Free(mesh);
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for the nodal pressure's patches");
	}
	fmFillNodal(mesh);
	return fm_ok;
}

void fmNodalPressure_Refresh(fmElasticMesh* mesh)
{
	if (fmNodalPressure_On(mesh))
		fmFillNodal(mesh);
}

bool fmNodalPressure_TetIsNodal(const fmElasticMesh* mesh, int t)
{
	return mesh->tetParts != NULL && fmTetMaterial(mesh, t)->nodalPressure;
}

// J_e of the law at F, and dJ/dF when @p gradient is not NULL.
static double fmLawJ(int law, const fmMat3* F, fmMat3* gradient)
{
	if (law == fm_nodalLinear)
	{
		if (gradient)
			*gradient = fmIdentity3();
		return F->m[0] + F->m[4] + F->m[8] - 2.0;
	}
	fmMat3 C = fmCofactor(F);
	if (gradient)
		*gradient = C;
	return F->m[0] * C.m[0] + F->m[1] * C.m[1] + F->m[2] * C.m[2];
}

// U(J) per unit stiffness and its first two derivatives into @p out.
static void fmLawU(int law, double J, double out[3])
{
	if (law != fm_nodalLog)
	{
		out[0] = 0.5 * (J - 1.0) * (J - 1.0);
		out[1] = J - 1.0;
		out[2] = 1.0;
		return;
	}
	double l[3];
	fmClampedLogJ(J, l);
	out[0] = 0.5 * l[0] * l[0];
	out[1] = l[0] * l[1];
	out[2] = l[1] * l[1] + l[0] * l[2];
}

double fmNodalPressure_State(const fmElasticMesh* mesh, const double* x, double* pressure,
                             double* curvature)
{
	const int n = mesh->vertexCount;
	double* sums = pressure; // S_a first, then p_a in place
	memset(sums, 0, sizeof(double) * (size_t)n);
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		if (!fmNodalPressure_TetIsNodal(mesh, t))
			continue;
		fmMat3 F = fmTetDeformation(mesh, x, t);
		double share = 0.25 * mesh->restVolume[t] * fmLawJ(mesh->nodalLaw, &F, NULL);
		for (int a = 0; a < 4; ++a)
			sums[mesh->tets[4 * t + a]] += share;
	}
	double energy = 0.0;
	for (int a = 0; a < n; ++a)
	{
		double V = mesh->patchVolume[a], U[3] = {0.0, 0.0, 0.0};
		if (V > 0.0)
			fmLawU(mesh->nodalLaw, sums[a] / V, U);
		energy += mesh->patchBulk[a] * U[0];
		pressure[a] = V > 0.0 ? mesh->patchBulk[a] / V * U[1] : 0.0;
		if (curvature)
			curvature[a] = V > 0.0 ? mesh->patchBulk[a] * U[2] / (V * V) : 0.0;
	}
	return energy;
}

double fmNodalPressure_TetMean(const fmElasticMesh* mesh, const double* pressure, int t)
{
	const int* n = mesh->tets + 4 * t;
	return 0.25 * (pressure[n[0]] + pressure[n[1]] + pressure[n[2]] + pressure[n[3]]);
}

void fmNodalPressure_TetGradients(const fmElasticMesh* mesh, const double* x, int t, fmVec3 grad[4])
{
	fmMat3 F = fmTetDeformation(mesh, x, t), dJ;
	fmLawJ(mesh->nodalLaw, &F, &dJ);
	fmVec3 g[4];
	fmShapeGradients(&mesh->DmInv[t], g);
	for (int a = 0; a < 4; ++a)
		grad[a] = fmScale(0.25 * mesh->restVolume[t], fmMatVec(&dJ, g[a]));
}

double fmNodalPressure_AddForces(const fmElasticMesh* mesh, const double* x, double* f)
{
	double* pressure = mesh->nodalPressure;
	double energy = fmNodalPressure_State(mesh, x, pressure, NULL);
	for (int t = 0; f != NULL && t < mesh->tetCount; ++t)
	{
		if (!fmNodalPressure_TetIsNodal(mesh, t))
			continue;
		double p = fmNodalPressure_TetMean(mesh, pressure, t);
		fmVec3 grad[4]; // V_e / 4 dJ_e/dx_b: the force is -4 p_e times it
		fmNodalPressure_TetGradients(mesh, x, t, grad);
		for (int a = 0; a < 4; ++a)
		{
			int v = mesh->tets[4 * t + a];
			fmStore(f, v, fmSub(fmLoad(f, v), fmScale(4.0 * p, grad[a])));
		}
	}
	return energy;
}

void fmNodalPressure_TetHessian(const fmElasticMesh* mesh, const double* x, int t, double p,
                                double* K)
{
	fmMat3 F = fmTetDeformation(mesh, x, t);
	double H[81] = {0.0};
	const double weights[3] = {0.0, 0.0, p}; // p d2J/dF2
	fmAddInvariantCurvature(&F, 0.0, weights, H);
	fmContractTetHessian(H, &mesh->DmInv[t], mesh->restVolume[t], K);
}

int fmNodalPressure_MaxPatch(const fmElasticMesh* mesh)
{
	int most = 0;
	for (int a = 0; a < mesh->vertexCount; ++a)
	{
		int around = mesh->vertexTetStart[a + 1] - mesh->vertexTetStart[a];
		most = around > most ? around : most;
	}
	return 4 * most;
}

int fmNodalPressure_Patch(const fmElasticMesh* mesh, const double* x, int a, int* vertices,
                          fmVec3* grads)
{
	int count = 0;
	for (int k = mesh->vertexTetStart[a]; k < mesh->vertexTetStart[a + 1]; ++k)
	{
		int t = mesh->vertexTets[k] / 4;
		if (!fmNodalPressure_TetIsNodal(mesh, t))
			continue;
		fmVec3 grad[4];
		fmNodalPressure_TetGradients(mesh, x, t, grad);
		for (int b = 0; b < 4; ++b)
		{
			int v = mesh->tets[4 * t + b], at = 0;
			while (at < count && vertices[at] != v)
				++at;
			if (at == count)
			{
				vertices[count] = v;
				grads[count++] = grad[b];
			}
			else
				grads[at] = fmAdd(grads[at], grad[b]);
		}
	}
	return count;
}

// The tet terms' blocks: V_e p_e d2J_e/dx2 at each tet's mean pressure.
static void fmVisitTetTerms(const fmElasticMesh* mesh, const double* x, const double* pressure,
                            int project, fmNodalBlockFcn* visit, void* context)
{
	// Linear: J is linear in x. Projected (the implicit step's matrix): left out, Gauss-Newton on
	// the volume term (c_a s_a s_a^T alone is PSD); projecting it costs a 9x9 eigen-solve a tet
	// for a quarter of the frame and no fewer Newton steps (docs/materials.md).
	if (mesh->nodalLaw == fm_nodalLinear || project)
		return;
	double K[144], block[9];
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		if (!fmNodalPressure_TetIsNodal(mesh, t))
			continue;
		fmNodalPressure_TetHessian(mesh, x, t, fmNodalPressure_TetMean(mesh, pressure, t), K);
		for (int a = 0; a < 4; ++a)
			for (int b = 0; b < 4; ++b)
			{
				for (int r = 0; r < 9; ++r)
					block[r] = K[12 * (3 * a + r / 3) + (3 * b + r % 3)];
				visit(context, mesh->tets[4 * t + a], mesh->tets[4 * t + b], block);
			}
	}
}

// A patch's rank-one term c s s^T at once: its vertices and their gradients.
typedef void fmNodalPatchFcn(void* context, double c, int count, const int* vertices,
                             const fmVec3* grads);

// The Hessian's blocks to @p visit, each patch's term to @p patch instead when it is not NULL
// (a product or a diagonal: O(patch) instead of O(patch^2)).
static void fmVisitHessian(const fmElasticMesh* mesh, const double* x, int project,
                           fmNodalBlockFcn* visit, fmNodalPatchFcn* patch, void* context)
{
	double* pressure = mesh->nodalPressure;
	double* curvature = mesh->nodalCurvature;
	int* vertices = mesh->patchVertices;
	fmVec3* grads = mesh->patchGrads;
	fmNodalPressure_State(mesh, x, pressure, curvature);
	for (int a = 0; a < mesh->vertexCount; ++a)
	{
		double c = project ? fmMax(curvature[a], 0.0) : curvature[a];
		int count = c != 0.0 ? fmNodalPressure_Patch(mesh, x, a, vertices, grads) : 0;
		if (patch != NULL)
		{
			patch(context, c, count, vertices, grads);
			continue;
		}
		for (int b = 0; b < count; ++b)
			for (int d = 0; d < count; ++d)
			{
				const double sb[3] = {grads[b].x, grads[b].y, grads[b].z};
				const double sd[3] = {grads[d].x, grads[d].y, grads[d].z};
				double block[9];
				for (int r = 0; r < 9; ++r)
					block[r] = c * sb[r / 3] * sd[r % 3];
				visit(context, vertices[b], vertices[d], block);
			}
	}
	fmVisitTetTerms(mesh, x, pressure, project, visit, context);
}

void fmNodalPressure_VisitHessian(const fmElasticMesh* mesh, const double* x, int project,
                                  fmNodalBlockFcn* visit, void* context)
{
	fmVisitHessian(mesh, x, project, visit, NULL, context);
}

typedef struct fmNodalProduct
{
	const double* dx;
	double* out;
} fmNodalProduct;

static void fmAddBlockProduct(void* context, int row, int column, const double block[9])
{
	fmNodalProduct* p = context;
	fmVec3 u = fmLoad(p->dx, column);
	fmVec3 y = {block[0] * u.x + block[1] * u.y + block[2] * u.z,
	            block[3] * u.x + block[4] * u.y + block[5] * u.z,
	            block[6] * u.x + block[7] * u.y + block[8] * u.z};
	fmStore(p->out, row, fmAdd(fmLoad(p->out, row), y));
}

// c s (s . dx) added to out.
static void fmAddPatchProduct(void* context, double c, int count, const int* vertices,
                              const fmVec3* grads)
{
	fmNodalProduct* p = context;
	double dot = 0.0;
	for (int b = 0; b < count; ++b)
		dot += fmDot(grads[b], fmLoad(p->dx, vertices[b]));
	for (int b = 0; b < count; ++b)
		fmStore(p->out, vertices[b], fmMulAdd(fmLoad(p->out, vertices[b]), c * dot, grads[b]));
}

void fmNodalPressure_AddProduct(const fmElasticMesh* mesh, const double* x, const double* dx,
                                double* out, int project)
{
	fmNodalProduct p = {dx, out};
	fmVisitHessian(mesh, x, project, fmAddBlockProduct, fmAddPatchProduct, &p);
}

static void fmAddDiagonalBlock(void* context, int row, int column, const double block[9])
{
	double* blocks = context;
	for (int r = 0; row == column && r < 9; ++r)
		blocks[9 * (size_t)row + r] += block[r];
}

// c s_b s_b^T added to each vertex's diagonal block.
static void fmAddPatchDiagonal(void* context, double c, int count, const int* vertices,
                               const fmVec3* grads)
{
	double* blocks = context;
	for (int b = 0; b < count; ++b)
	{
		const double s[3] = {grads[b].x, grads[b].y, grads[b].z};
		for (int r = 0; r < 9; ++r)
			blocks[9 * (size_t)vertices[b] + r] += c * s[r / 3] * s[r % 3];
	}
}

void fmNodalPressure_AddDiagonal(const fmElasticMesh* mesh, const double* x, double* blocks,
                                 int project)
{
	fmVisitHessian(mesh, x, project, fmAddDiagonalBlock, fmAddPatchDiagonal, blocks);
}

static void fmAddBlockRowSums(void* context, int row, int column, const double block[9])
{
	(void)column;
	double* rowSum = context;
	for (int r = 0; r < 9; ++r)
		rowSum[3 * row + r / 3] += fabs(block[r]);
}

void fmNodalPressure_AddRowSums(const fmElasticMesh* mesh, const double* x, double* rowSum)
{
	// Each visited block's absolute row sums: at least those of the blocks summed.
	fmNodalPressure_VisitHessian(mesh, x, 0, fmAddBlockRowSums, rowSum);
}
