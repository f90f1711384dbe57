// FEM forces: minus the energy gradient, zero under rigid motion, balanced, patch test,
// Hessian against finite differences of the forces.
#include "body/body.h"
#include "fem/forces.h"
#include "material/material.h"
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static const fmMaterialModel s_models[] = {fm_stvk, fm_corotated, fm_neoHookean, fm_mooneyRivlin};
#define MODEL_COUNT ((int)(sizeof s_models / sizeof s_models[0]))

static fmMaterial testMaterial(fmMaterialModel model)
{
	return fmMakeMaterial(model, 1e5, 0.3);
}

TEST(forces_are_minus_energy_gradient)
{
	for (int m = 0; m < MODEL_COUNT; ++m)
	{
		fmWorldId world;
		fmBodyId body =
		    fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1), testMaterial(s_models[m]), fm_fem);
		CHECK(fmBody_IsValid(body));
		if (!fmBody_IsValid(body))
			return;
		fmTestPerturb(body, 0.08);
		fmTestCheckForcesAreMinusGradient(failures_, body, 5, 1e-5);
		fmDestroyWorld(world);
	}
}

// Rotation by angle a about a unit axis (Rodrigues).
static fmMat3 rotation(fmVec3 axis, double a)
{
	axis = fmScale(1.0 / fmLength(axis), axis);
	double c = cos(a), s = sin(a), t = 1 - c;
	fmMat3 R = {{t * axis.x * axis.x + c, t * axis.x * axis.y - s * axis.z,
	             t * axis.x * axis.z + s * axis.y, t * axis.x * axis.y + s * axis.z,
	             t * axis.y * axis.y + c, t * axis.y * axis.z - s * axis.x,
	             t * axis.x * axis.z - s * axis.y, t * axis.y * axis.z + s * axis.x,
	             t * axis.z * axis.z + c}};
	return R;
}

TEST(zero_force_at_rest_and_under_rigid_motion)
{
	for (int m = 0; m < MODEL_COUNT; ++m)
	{
		fmWorldId world;
		fmBodyId body =
		    fmTestMakeBox(&world, 2, 3, 2, fmMakeVec3(1, 2, 1), testMaterial(s_models[m]), fm_fem);
		if (!fmBody_IsValid(body))
		{
			CHECK(0);
			return;
		}
		int n = fmBody_GetVertexCount(body);
		double* f = malloc(sizeof(double) * 3 * (size_t)n);
		double* x = malloc(sizeof(double) * 3 * (size_t)n);
		double e = fmBody_ComputeElasticForces(body, f);
		CHECK_NEAR(e, 0.0, 1e-12);
		for (int k = 0; k < 3 * n; ++k)
			CHECK_NEAR(f[k], 0.0, 1e-9);
		fmMat3 R = rotation(fmMakeVec3(0.3, -1.0, 0.7), 2.1);
		fmVec3 shift = fmMakeVec3(5.0, -2.0, 1.5);
		const double* X = fmTestPositions(body);
		for (int i = 0; i < n; ++i)
			fmStore(x, i, fmAdd(fmMatVec(&R, fmLoad(X, i)), shift));
		fmBody_SetPositions(body, x);
		e = fmBody_ComputeElasticForces(body, f);
		// Scale: the force a 1% strain would give on a unit face, E * 0.01 * 1 m^2 / nodes.
		CHECK_NEAR(e, 0.0, 1e-7);
		for (int k = 0; k < 3 * n; ++k)
			CHECK_NEAR(f[k], 0.0, 1e-6);
		free(f);
		free(x);
		fmDestroyWorld(world);
	}
}

TEST(internal_forces_balance_and_have_no_torque)
{
	for (int m = 0; m < MODEL_COUNT; ++m)
	{
		fmWorldId world;
		fmBodyId body = fmTestMakeBox(&world, 3, 2, 2, fmMakeVec3(1.5, 1, 1),
		                              testMaterial(s_models[m]), fm_fem);
		if (!fmBody_IsValid(body))
		{
			CHECK(0);
			return;
		}
		fmTestPerturb(body, 0.1);
		int n = fmBody_GetVertexCount(body);
		double* f = malloc(sizeof(double) * 3 * (size_t)n);
		fmBody_ComputeElasticForces(body, f);
		const double* x = fmTestPositions(body);
		fmVec3 net = {0, 0, 0}, torque = {0, 0, 0};
		double scale = 0.0;
		for (int i = 0; i < n; ++i)
		{
			net = fmAdd(net, fmLoad(f, i));
			torque = fmAdd(torque, fmCross(fmLoad(x, i), fmLoad(f, i)));
			scale = fmax(scale, fmLength(fmLoad(f, i)));
		}
		CHECK(scale > 1.0);
		CHECK_NEAR(fmLength(net), 0.0, 1e-10 * scale);
		CHECK_NEAR(fmLength(torque), 0.0, 1e-10 * scale);
		free(f);
		fmDestroyWorld(world);
	}
}

// Patch test: under x = A X + b every interior node is in equilibrium (uniform stress).
TEST(patch_test_uniform_deformation)
{
	fmMaterialModel models[] = {fm_linear, fm_stvk, fm_corotated, fm_neoHookean, fm_mooneyRivlin};
	for (int m = 0; m < 5; ++m)
	{
		fmWorldId world;
		fmBodyId body =
		    fmTestMakeBox(&world, 3, 3, 3, fmMakeVec3(1, 1, 1), testMaterial(models[m]), fm_fem);
		if (!fmBody_IsValid(body))
		{
			CHECK(0);
			return;
		}
		fmMat3 A = {{1.1, 0.05, -0.02, 0.03, 0.92, 0.04, -0.01, 0.06, 1.05}};
		int n = fmBody_GetVertexCount(body);
		double* x = malloc(sizeof(double) * 3 * (size_t)n);
		double* f = malloc(sizeof(double) * 3 * (size_t)n);
		const double* X = fmTestPositions(body);
		for (int i = 0; i < n; ++i)
			fmStore(x, i, fmAdd(fmMatVec(&A, fmLoad(X, i)), fmMakeVec3(0.3, 0.2, 0.1)));
		double* rest = malloc(sizeof(double) * 3 * (size_t)n);
		memcpy(rest, X, sizeof(double) * 3 * (size_t)n);
		fmBody_SetPositions(body, x);
		fmBody_ComputeElasticForces(body, f);
		double scale = 0.0;
		int interior = 0;
		for (int i = 0; i < n; ++i)
			scale = fmax(scale, fmLength(fmLoad(f, i)));
		CHECK(scale > 0.0);
		for (int i = 0; i < n; ++i)
		{
			fmVec3 p = fmLoad(rest, i);
			bool inside = p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9 &&
			              p.z > 1e-9 && p.z < 1 - 1e-9;
			if (!inside)
				continue;
			++interior;
			CHECK_NEAR(fmLength(fmLoad(f, i)), 0.0, 1e-10 * scale);
		}
		CHECK_INT(interior, 8);
		free(x);
		free(f);
		free(rest);
		fmDestroyWorld(world);
	}
}

// K dx must equal the directional derivative of -f: (f(x - h dx) - f(x + h dx)) / 2h.
TEST(hessian_matches_force_differences)
{
	for (int m = 0; m < MODEL_COUNT; ++m)
	{
		fmWorldId world;
		fmBodyId id =
		    fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1), testMaterial(s_models[m]), fm_fem);
		if (!fmBody_IsValid(id))
		{
			CHECK(0);
			return;
		}
		fmTestPerturb(id, 0.05);
		const fmBody* body = fmGetBody(id);
		int n = body->mesh.vertexCount;
		size_t bytes = sizeof(double) * 3 * (size_t)n;
		double *dx = malloc(bytes), *kdx = calloc(1, bytes), *xp = malloc(bytes),
		       *xm = malloc(bytes);
		double *fp = calloc(1, bytes), *fm = calloc(1, bytes);
		for (int k = 0; k < 3 * n; ++k)
			dx[k] = fmTestRandom(-1, 1);
		const double h = 1e-6;
		for (int k = 0; k < 3 * n; ++k)
		{
			xp[k] = body->state.x[k] + h * dx[k];
			xm[k] = body->state.x[k] - h * dx[k];
		}
		fmAddHessianProduct(&body->mesh, body->state.x, dx, kdx, 0);
		fmAddElasticForces(&body->mesh, xp, fp);
		fmAddElasticForces(&body->mesh, xm, fm);
		double scale = 0.0;
		for (int k = 0; k < 3 * n; ++k)
			scale = fmax(scale, fabs(kdx[k]));
		CHECK(scale > 0.0);
		for (int k = 0; k < 3 * n; ++k)
			CHECK_NEAR(kdx[k], (fm[k] - fp[k]) / (2 * h), 1e-5 * scale);

		// The assembled 12x12 element matrices give the same product.
		double* kdx2 = calloc(1, bytes);
		for (int t = 0; t < body->mesh.tetCount; ++t)
		{
			double K[144];
			fmTetHessian(&body->mesh, body->state.x, t, K, 0);
			const int* nodes = body->mesh.tets + 4 * t;
			for (int r = 0; r < 12; ++r)
				for (int c = 0; c < 12; ++c)
					kdx2[3 * nodes[r / 3] + r % 3] += K[12 * r + c] * dx[3 * nodes[c / 3] + c % 3];
		}
		for (int k = 0; k < 3 * n; ++k)
			CHECK_NEAR(kdx2[k], kdx[k], 1e-9 * scale);
		free(dx), free(kdx), free(xp), free(xm), free(fp), free(fm), free(kdx2);
		fmDestroyWorld(world);
	}
}

// The Newton matrix's tet blocks for StVK and Neo-Hookean come straight from the clamped
// tangents' terms (fmTetHessian with project = 1): the same 12x12 as the clamped 9x9 tangent
// contracted with the shape gradients, on boxes strained and squashed at random.
TEST(tet_blocks_from_the_clamped_terms_match_the_contracted_tangent)
{
	const fmMaterialModel models[2] = {fm_stvk, fm_neoHookean};
	for (int mi = 0; mi < 2; ++mi)
		for (int pass = 0; pass < 2; ++pass)
		{
			fmWorldId world;
			fmBodyId id = fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1),
			                            fmMakeMaterial(models[mi], 1e5, 0.3), fm_fem);
			if (!fmBody_IsValid(id))
			{
				CHECK(0);
				return;
			}
			fmTestPerturb(id, pass == 0 ? 0.05 : 0.15);
			const fmBody* b = fmGetBody(id);
			int taken = 0;
			for (int t = 0; t < b->mesh.tetCount; ++t)
			{
				fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
				double dPdF[81], K[144];
				const fmMaterial* m = &b->mesh.material;
				bool clamped = models[mi] == fm_stvk
				                   ? fmMaterial_StvkClampedHessian(m, &F, dPdF)
				                   : fmMaterial_NeoHookeanClampedHessian(m, &F, dPdF);
				if (!clamped)
					continue;
				++taken;
				fmTetHessian(&b->mesh, b->state.x, t, K, 1);
				const fmMat3* D = &b->mesh.DmInv[t];
				double g[4][3];
				for (int a = 1; a < 4; ++a)
					for (int j = 0; j < 3; ++j)
						g[a][j] = D->m[3 * (a - 1) + j];
				for (int j = 0; j < 3; ++j)
					g[0][j] = -(g[1][j] + g[2][j] + g[3][j]);
				double Kref[144], scale = 0.0;
				for (int r = 0; r < 12; ++r)
					for (int c = 0; c < 12; ++c)
					{
						int a = r / 3, i = r % 3, bb = c / 3, k = c % 3;
						double v = 0.0;
						for (int j = 0; j < 3; ++j)
							for (int l = 0; l < 3; ++l)
								v += g[a][j] * g[bb][l] * dPdF[9 * (3 * i + j) + (3 * k + l)];
						Kref[12 * r + c] = b->mesh.restVolume[t] * v;
						scale = fmax(scale, fabs(Kref[12 * r + c]));
					}
				for (int e = 0; e < 144; ++e)
					CHECK_NEAR(K[e], Kref[e], 1e-10 * scale);
			}
			printf("  %s, perturbed %.2f: %d of %d tets from the terms\n",
			       fmMaterialModelName(models[mi]), pass == 0 ? 0.05 : 0.15, taken,
			       b->mesh.tetCount);
			CHECK(taken > b->mesh.tetCount / 2);
			fmDestroyWorld(world);
		}
}

// The seeds' explicit formula, written out as in the Unity code, gives the same forces.
TEST(stvk_matches_the_seed_formula)
{
	fmWorldId world;
	fmBodyId id = fmTestMakeBox(&world, 1, 1, 1, fmMakeVec3(1, 1, 1),
	                            fmMakeMaterialLame(fm_stvk, 20000, 5000), fm_fem);
	if (!fmBody_IsValid(id))
	{
		CHECK(0);
		return;
	}
	fmTestPerturb(id, 0.2);
	const fmBody* b = fmGetBody(id);
	size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
	double *f = calloc(1, bytes), *seed = calloc(1, bytes);
	fmAddElasticForces(&b->mesh, b->state.x, f);
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		fmMat3 G = fmMatTMul(&F, &F);
		for (int k = 0; k < 9; ++k)
			G.m[k] = 0.5 * (G.m[k] - (k % 4 == 0));
		fmMat3 S = fmMatScale(2 * 5000.0, &G);
		for (int k = 0; k < 3; ++k)
			S.m[4 * k] += 20000.0 * fmTrace(&G);
		fmMat3 FS = fmMatMul(&F, &S);
		fmMat3 result = fmMatMulT(&FS, &b->mesh.DmInv[t]);
		double scale = -1.0 / (fmDet(&b->mesh.DmInv[t]) * 6.0);
		const int* n = b->mesh.tets + 4 * t;
		for (int a = 1; a < 4; ++a)
			for (int c = 0; c < 3; ++c)
			{
				seed[3 * n[a] + c] += scale * result.m[3 * c + a - 1];
				seed[3 * n[0] + c] -= scale * result.m[3 * c + a - 1];
			}
	}
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		CHECK_NEAR(f[k], seed[k], 1e-9 * (1 + fabs(seed[k])));
	free(f);
	free(seed);
	fmDestroyWorld(world);
}
