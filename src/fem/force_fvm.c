// Elastic forces by the finite volume method (Teran, Blemker, Ng Thow Hing, Fedkiw 2003).
//
// Each tet's Piola stress P acts on its rest faces: the traction on a face with outward rest
// normal N and area A is P N A. A vertex collects one third of the traction of each of its
// three faces in the tet (the median-dual cell around it), so f_a = -P b_a with
// b_a = (1/3) sum_{faces at a} A N. The four b_a sum to zero, so momentum is conserved by
// construction. For linear tets b_a = V0 g_a (g_a the shape-function gradient), which makes FVM
// and FEM agree to round-off; the test in test_force_models.c checks it. We keep FVM as its
// own geometric path (normals from the rest faces, not from Dm^-1) because that is the method
// users choose it for, and because it is what generalises to non-simplex cells.
#include "fem/force_fvm.h"

#include "core/core.h"
#include "material/material.h"

// Face opposite each local vertex, wound so that its normal points out of a positive tet.
static const int s_faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// Area-weighted outward normal of face (p, q, r): (q - p) x (r - p) / 2.
static fmVec3 fmFaceAreaNormal(fmVec3 p, fmVec3 q, fmVec3 r)
{
	return fmScale(0.5, fmCross(fmSub(q, p), fmSub(r, p)));
}

int fmBuildFvmNormals(fmElasticMesh* mesh)
{
	mesh->fvmNormals = FM_ALLOC_ARRAY(fmVec3, 4 * (size_t)mesh->tetCount);
	if (mesh->fvmNormals == NULL)
		return 1;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		const int* n = mesh->tets + 4 * t;
		fmVec3 an[4];
		for (int o = 0; o < 4; ++o)
			an[o] = fmFaceAreaNormal(fmLoad(mesh->x0, n[s_faces[o][0]]),
			                         fmLoad(mesh->x0, n[s_faces[o][1]]),
			                         fmLoad(mesh->x0, n[s_faces[o][2]]));
		// Vertex a touches every face but the one opposite it.
		for (int a = 0; a < 4; ++a)
		{
			fmVec3 sum = {0, 0, 0};
			for (int o = 0; o < 4; ++o)
				if (o != a)
					sum = fmAdd(sum, an[o]);
			mesh->fvmNormals[4 * t + a] = fmScale(1.0 / 3.0, sum);
		}
	}
	return 0;
}

double fmAddFvmForces(const fmElasticMesh* mesh, const double* x, double* f)
{
	double energy = 0.0;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(mesh, x, t);
		fmMat3 P;
		energy += mesh->restVolume[t] * fmTetEvaluate(mesh, t, &F, &P, NULL, false);
		const int* n = mesh->tets + 4 * t;
		for (int a = 0; a < 4; ++a)
		{
			fmVec3 fa = fmScale(-1.0, fmMatVec(&P, mesh->fvmNormals[4 * t + a]));
			fmStore(f, n[a], fmAdd(fmLoad(f, n[a]), fa));
		}
	}
	return energy;
}
