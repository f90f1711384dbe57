// Anisotropic materials (issue 34, item 3): the orthotropic stiffness is the inverse of its
// engineering constants' compliance (written out here); orthotropic constants that describe an
// isotropic solid give the isotropic models; a fibre-reinforced bar stretched along and across
// its fibres (per-tet fibres, a static solve) gives the analytic moduli and their ratio at small
// strain, and the analytic uniaxial answer at 20% stretch. (Statics against CalculiX:
// test_calculix.c; derivatives and frame invariance: test_material.c.)
#include "material/material.h"
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

// The axes of a fibre and a sheet as the columns of Q (Gram-Schmidt, written out here).
static fmMat3 axesOf(fmVec3 fibre, fmVec3 sheet)
{
	fmVec3 a = fmScale(1.0 / fmLength(fibre), fibre);
	fmVec3 b = fmMulAdd(sheet, -fmDot(sheet, a), a);
	b = fmScale(1.0 / fmLength(b), b);
	return fmMat3FromColumns(a, b, fmCross(a, b));
}

// Q A Q^T
static fmMat3 turned(const fmMat3* Q, const fmMat3* A)
{
	fmMat3 QA = fmMatMul(Q, A);
	return fmMatMulT(&QA, Q);
}

TEST(orthotropic_stiffness_inverts_the_compliance)
{
	// Six unit stresses in the material's axes; the strain each causes comes from the
	// compliance of the engineering constants; the stress at that strain must be the stress.
	const fmOrthotropy o = {{3e5, 5e4, 3e4}, {0.35, 0.4, 0.3}, {2e4, 1.5e4, 1e4}};
	fmMaterial m = fmMakeOrthotropicMaterial(fm_orthotropicLinear, o);
	m.fibre = fmMakeVec3(1.0, 2.0, 0.5);
	m.sheet = fmMakeVec3(0.0, 0.3, 1.0);
	CHECK_INT(fmMaterial_Validate(&m, NULL), fm_ok);
	const fmMat3 Q = axesOf(m.fibre, m.sheet);
	const double S[3][3] = {{1 / o.E[0], -o.nu[0] / o.E[0], -o.nu[1] / o.E[0]},
	                        {-o.nu[0] / o.E[0], 1 / o.E[1], -o.nu[2] / o.E[1]},
	                        {-o.nu[1] / o.E[0], -o.nu[2] / o.E[1], 1 / o.E[2]}};
	const int shear[3][2] = {{0, 1}, {0, 2}, {1, 2}};
	const double s = 1e3; // Pa
	for (int c = 0; c < 6; ++c)
	{
		fmMat3 sigma = fmZero3(), eps = fmZero3();
		if (c < 3)
		{
			sigma.m[4 * c] = s;
			for (int i = 0; i < 3; ++i)
				eps.m[4 * i] = S[i][c] * s;
		}
		else
		{
			int i = shear[c - 3][0], j = shear[c - 3][1];
			sigma.m[3 * i + j] = sigma.m[3 * j + i] = s;
			eps.m[3 * i + j] = eps.m[3 * j + i] = s / (2.0 * o.G[c - 3]);
		}
		fmMat3 F = turned(&Q, &eps), expected = turned(&Q, &sigma), P;
		for (int i = 0; i < 3; ++i)
			F.m[4 * i] += 1.0;
		double psi = fmMaterial_Evaluate(&m, &F, &P, NULL);
		for (int e = 0; e < 9; ++e)
			CHECK_NEAR(P.m[e], expected.m[e], 1e-10 * s);
		CHECK_REL(psi, 0.5 * fmDDot(&sigma, &eps), 1e-10, 0.0);
	}
	// Not positive definite: nu12 above sqrt(E1 / E2) = 2.45 is refused, naming the rule.
	fmOrthotropy bad = o;
	bad.nu[0] = 2.5;
	fmMaterial b = fmMakeOrthotropicMaterial(fm_orthotropicLinear, bad);
	fmDiagnostic diag;
	CHECK_INT(fmMaterial_Validate(&b, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "positive definite") != NULL);
	b = m;
	b.orthotropy.G[2] = 0.0;
	CHECK_INT(fmMaterial_Validate(&b, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "G23") != NULL);
}

TEST(isotropic_constants_give_the_isotropic_models)
{
	// A transversely isotropic solid whose constants are one isotropic solid's: the same
	// stresses as linear and StVK at any deformation (StVK above its volume floor), whatever
	// the axes; its Voigt average is that solid's lambda and mu.
	const double E = 2e5, nu = 0.3;
	fmOrthotropy o = fmTransverselyIsotropic(E, E, nu, nu, E / (2.0 * (1.0 + nu)));
	const fmMaterialModel pairs[2][2] = {{fm_orthotropicLinear, fm_linear},
	                                     {fm_orthotropicStvk, fm_stvk}};
	for (int p = 0; p < 2; ++p)
	{
		fmMaterial a = fmMakeOrthotropicMaterial(pairs[p][0], o);
		fmMaterial iso = fmMakeMaterial(pairs[p][1], E, nu);
		CHECK_REL(a.lambda, iso.lambda, 1e-12, 0.0);
		CHECK_REL(a.mu, iso.mu, 1e-12, 0.0);
		for (int trial = 0; trial < 20; ++trial)
		{
			fmMat3 R = fmTestRandomRotation();
			a.fibre = fmMatVec(&R, fmMakeVec3(1, 0, 0));
			a.sheet = fmMatVec(&R, fmMakeVec3(0.3, 1, 0));
			fmMat3 F = fmTestRandomRotation(), P, PI;
			for (int e = 0; e < 9; ++e)
				F.m[e] += fmTestRandom(-0.2, 0.2);
			if (fmDet(&F) < 0.6)
				continue;
			double psi = fmMaterial_Evaluate(&a, &F, &P, NULL);
			double psiI = fmMaterial_Evaluate(&iso, &F, &PI, NULL);
			CHECK_REL(psi, psiI, 1e-10, 1e-12 * E);
			for (int e = 0; e < 9; ++e)
				CHECK_NEAR(P.m[e], PI.m[e], 1e-10 * E);
		}
	}
}

// A 2 x 1 x 1 bar on rollers at x = 0, y = 0 and z = 0, its end x = 2 moved to 2 (1 + e) on a
// roller, solved to equilibrium (to 1e-10: a strain of 1e-5 changes the energy by little more
// than its round-off): the nominal stress, the end's reaction over the rest area 1 m^2;
// the lateral stretches along y and z (the homogeneous map checked at every node). Fibres per
// tet when @p fibre is not NULL (every tet @p fibre, alternating its sign).
static double stretchBar(int* failures_, fmMaterial material, const fmVec3* fibre, double e,
                         double lateral[2])
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(2, 1, 1), &mesh), fm_ok);
	fmVec3* fibres = fibre != NULL ? malloc(sizeof(fmVec3) * (size_t)mesh.tetCount) : NULL;
	for (int t = 0; fibres != NULL && t < mesh.tetCount; ++t)
		fibres[t] = fmScale(t % 2 == 0 ? 1.0 : -3.0, *fibre);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = material;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.tetFibres = fibres;
	fmBodyId body;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_ok);
	free(fibres);
	fmFreeTetMesh(&mesh);
	int n = fmBody_GetVertexCount(body);
	double* rest = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(rest, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	fmTestBarOnRollers(body, rest, 2.0, 1.0 + e, true);
	double residual = 1.0;
	fmResult r = fmBody_SolveStatic(body, 1e-10, 50, &residual, &diag);
	CHECK_INT(r, fm_ok);
	if (r != fm_ok)
		printf("  %s\n", diag.message);
	const double* p = fmTestPositions(body);
	lateral[0] = lateral[1] = 0.0;
	for (int i = 0; i < n; ++i)
		if (rest[3 * i + 1] > 1.0 - 1e-9 && rest[3 * i + 2] > 1.0 - 1e-9)
		{
			lateral[0] = p[3 * i + 1];
			lateral[1] = p[3 * i + 2];
		}
	double worst = 0.0, reaction = 0.0;
	for (int i = 0; i < n; ++i)
	{
		worst = fmax(worst, fabs(p[3 * i] - (1.0 + e) * rest[3 * i]));
		worst = fmax(worst, fabs(p[3 * i + 1] - lateral[0] * rest[3 * i + 1]));
		worst = fmax(worst, fabs(p[3 * i + 2] - lateral[1] * rest[3 * i + 2]));
	}
	CHECK(worst < 1e-9); // m, of a 2 m bar
	double* f = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_ComputeElasticForces(body, f);
	for (int i = 0; i < n; ++i)
		if (rest[3 * i] > 2.0 - 1e-9)
			reaction -= f[3 * i];
	free(f);
	free(rest);
	fmDestroyWorld(world);
	return reaction; // the rest area is 1 m^2
}

// Neo-Hookean with a fibre term, F = diag(l1, l2, l3), the fibre along axis @p axis: the
// nominal stress P_ii (the closed form written out: mu l + (lambda ln J - mu) / l, plus
// k / 2 (l^2 - 1) l along the fibre).
static double fibreStress(double lambda, double mu, double k, const double l[3], int axis, int i)
{
	double J = l[0] * l[1] * l[2];
	double P = mu * l[i] + (lambda * log(J) - mu) / l[i];
	return i == axis ? P + 0.5 * k * (l[i] * l[i] - 1.0) * l[i] : P;
}

// The lateral stretch (axis @p i) that frees P_ii with the others held, by bisection.
static double freeLateral(double lambda, double mu, double k, double l[3], int axis, int i)
{
	double lo = 0.3, hi = 1.5;
	for (int it = 0; it < 200; ++it)
	{
		l[i] = 0.5 * (lo + hi);
		if (fibreStress(lambda, mu, k, l, axis, i) > 0.0)
			hi = l[i];
		else
			lo = l[i];
	}
	return l[i];
}

TEST(fibre_reinforced_bar_along_and_across_its_fibres)
{
	const double E = 1e5, nu = 0.3, k = 4e5;
	fmMaterial m = fmMakeMaterial(fm_fibreNeoHookean, E, nu);
	m.fibreStiffness = k;
	const double lambda = m.lambda, mu = m.mu;
	// Small strain: along the fibre E + k exactly; across, the inverse of the compliance's
	// entry, from C = the isotropic stiffness plus k on C_1111 (Cramer's rule).
	double C[3][3];
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			C[i][j] = lambda + (i == j ? 2.0 * mu : 0.0) + (i == 0 && j == 0 ? k : 0.0);
	double det = C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) -
	             C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0]) +
	             C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]);
	double along = E + k, across = det / (C[0][0] * C[2][2] - C[0][2] * C[2][0]);
	const double e = 1e-5; // (smaller strains change the energy by its round-off)
	double lateral[2];
	const fmVec3 x = {1, 0, 0}, y = {0, 1, 0};
	double sAlong = stretchBar(failures_, m, &x, e, lateral) / e;
	double sAcross = stretchBar(failures_, m, &y, e, lateral) / e;
	m.fibre = y; // the material's own fibre, no per-tet field: the same
	double sMaterial = stretchBar(failures_, m, NULL, e, lateral) / e;
	m.fibre = fmMakeVec3(0, 0, 0);
	printf("  strain 1e-5: along %.8g Pa (analytic %.8g), across %.8g Pa (analytic %.8g), "
	       "ratio %.6f (analytic %.6f)\n",
	       sAlong, along, sAcross, across, sAlong / sAcross, along / across);
	// (Their finite-strain terms are of order e: 1e-5 of each.)
	CHECK_REL(sAlong, along, 1e-4, 0.0);
	CHECK_REL(sAcross, across, 1e-4, 0.0);
	CHECK_REL(sAlong / sAcross, along / across, 1e-4, 0.0);
	CHECK_REL(sMaterial, sAcross, 1e-9, 0.0);
	// 20% stretch along and across: the uniaxial answer, lateral stretches free.
	for (int axis = 0; axis < 2; ++axis)
	{
		double l[3] = {1.2, 1.0, 1.0};
		for (int it = 0; it < 60; ++it) // the two lateral stretches, each freed in turn
		{
			freeLateral(lambda, mu, k, l, axis, 1);
			freeLateral(lambda, mu, k, l, axis, 2);
		}
		double expected = fibreStress(lambda, mu, k, l, axis, 0);
		double s = stretchBar(failures_, m, axis == 0 ? &x : &y, 0.2, lateral);
		printf("  20%% stretch %s the fibres: stress %.9g Pa (analytic %.9g), lateral %.9f, "
		       "%.9f (analytic %.9f, %.9f)\n",
		       axis == 0 ? "along " : "across", s, expected, lateral[0], lateral[1], l[1], l[2]);
		CHECK_REL(s, expected, 1e-8, 0.0);
		CHECK_NEAR(lateral[0], l[1], 1e-9);
		CHECK_NEAR(lateral[1], l[2], 1e-9);
	}
}

TEST(body_def_refuses_bad_fibres_and_springs)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(1, 1, 1, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmVec3* fibres = calloc((size_t)mesh.tetCount, sizeof(fmVec3));
	for (int t = 0; t < mesh.tetCount; ++t)
		fibres[t] = fmMakeVec3(1, 0, 0);
	fibres[mesh.tetCount - 1] = fmMakeVec3(0, 0, 0);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_fibreNeoHookean, 1e5, 0.3);
	bdef.tetFibres = fibres;
	fmBodyId body;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "tetFibres[") != NULL);
	fibres[mesh.tetCount - 1] = fmMakeVec3(NAN, 0, 0);
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_errParameter);
	bdef.tetFibres = NULL;
	bdef.forceModel = fm_massSpring;
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "anisotropic") != NULL);
	bdef.forceModel = fm_fem;
	bdef.material.fibreStiffness = -1.0;
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "fibreStiffness") != NULL);
	// A mass-spring body refuses an anisotropic material later too.
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	bdef.forceModel = fm_massSpring;
	CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_ok);
	fmMaterial fibre = fmMakeMaterial(fm_fibreNeoHookean, 1e5, 0.3);
	CHECK_INT(fmBody_SetMaterial(body, &fibre, &diag), fm_errParameter);
	free(fibres);
	fmFreeTetMesh(&mesh);
	fmDestroyWorld(world);
}

// A 0.4 m box of material @p m dropped 0.3 m onto the floor (y = 0) and left 2 s, 1/60 s frames:
// every frame steps, the box lands and rests on the floor (implicit; explicit rings down), no tet
// inverts, and its kinetic and elastic energy stay within the ledger's bound (the start plus the
// work done on it).
static void dropBox(int* failures_, fmMaterial m, fmIntegrator integrator)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 4, 4, fmMakeVec3(0, 0.3, 0), fmMakeVec3(0.4, 0.7, 0.4), &mesh),
	          fm_ok);
	fmVec3* fibres = malloc(sizeof(fmVec3) * (size_t)mesh.tetCount);
	for (int t = 0; t < mesh.tetCount; ++t) // a field: fibres turning around y
		fibres[t] = fmMakeVec3(cos(0.01 * t), 0.3, sin(0.01 * t));
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.height = 0.0;
	wdef.integrator = integrator;
	wdef.autoSubstep = integrator == fm_explicit;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = m;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.tetFibres = m.model == fm_fibreNeoHookean ? fibres : NULL;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &bdef, &body, NULL), fm_ok);
	free(fibres);
	fmFreeTetMesh(&mesh);
	int worstInverted = 0, frame = 0;
	double excess = 0.0;
	fmResult r = fm_ok;
	for (; frame < 120 && r == fm_ok; ++frame)
	{
		r = fmWorld_Step(world, 1.0 / 60.0, 1);
		fmBodyStats s = fmBody_GetStats(body);
		worstInverted = s.invertedTets > worstInverted ? s.invertedTets : worstInverted;
		excess = fmax(excess, s.kineticEnergy + s.elasticEnergy - s.initialEnergy - s.work);
	}
	fmBodyStats s = fmBody_GetStats(body);
	printf("  %-19s %-8s: %d frames, lowest %.4f m, centre %.4f m, kinetic %.3g J, inverted %d, "
	       "energy over the ledger %.3g J\n",
	       fmMaterialModelName(m.model), integrator == fm_explicit ? "explicit" : "implicit", frame,
	       s.lowestY, s.centerOfMass.y, s.kineticEnergy, worstInverted, excess);
	CHECK_INT(r, fm_ok);
	CHECK(s.lowestY > -0.01 && s.lowestY < 0.01);              // on the floor
	CHECK(s.centerOfMass.y > 0.15 && s.centerOfMass.y < 0.25); // resting, not squashed
	// Implicit steps damp what explicit ones leave ringing (their damping, 0.999 per 3 ms, only).
	CHECK(s.kineticEnergy < (integrator == fm_explicit ? 1e-2 : 1e-4) * 64 * 9.81 * 0.3);
	CHECK_INT(worstInverted, 0);
	CHECK(excess <= 1e-6 * 64 * 9.81 * 0.3);
	fmDestroyWorld(world);
}

TEST(anisotropic_boxes_drop_and_rest_in_both_integrators)
{
	fmMaterial ortho = fmMakeOrthotropicMaterial(fm_orthotropicStvk,
	                                             fmTransverselyIsotropic(3e5, 1e5, 0.3, 0.35, 4e4));
	ortho.fibre = fmMakeVec3(1, 1, 0);
	fmMaterial fibre = fmMakeMaterial(fm_fibreNeoHookean, 1e5, 0.3);
	fibre.fibreStiffness = 3e5;
	for (int integrator = 0; integrator < 2; ++integrator)
	{
		dropBox(failures_, ortho, (fmIntegrator)integrator);
		dropBox(failures_, fibre, (fmIntegrator)integrator);
	}
}
