// Plasticity (issue 34, item 1): the return map against the von Mises law written out here; a
// bar stretched past yield on rollers and let go keeps the permanent set of the analytic 1D law
// with linear hardening; the energy balance of a plastic beam swinging down under gravity
// (work = kinetic + elastic + plastic work); creep; the cap; snapshots keep the bent state.
// (Against CalculiX: test_calculix.c.)
#include "material/material.h"
#include "material/material_plastic.h"
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

// diag(a, b, c) turned by random rotations on both sides.
static fmMat3 turnedStretches(double a, double b, double c)
{
	fmMat3 R1 = fmTestRandomRotation(), R2 = fmTestRandomRotation();
	fmMat3 D = {{a, 0, 0, 0, b, 0, 0, 0, c}};
	fmMat3 T = fmMatMul(&R1, &D);
	return fmMatMul(&T, &R2);
}

// The material's own von Mises stress at F: sqrt(3/2) |dev tau|, tau = P F^T (Kirchhoff).
static double vonMises(const fmMaterial* m, const fmMat3* F)
{
	fmMat3 P;
	fmMaterial_Evaluate(m, F, &P, NULL);
	fmMat3 tau = fmMatMulT(&P, F);
	double mean = (tau.m[0] + tau.m[4] + tau.m[8]) / 3.0, dev2 = 0.0;
	for (int k = 0; k < 9; ++k)
		dev2 += (tau.m[k] - (k % 4 == 0 ? mean : 0.0)) * (tau.m[k] - (k % 4 == 0 ? mean : 0.0));
	return sqrt(1.5 * dev2);
}

TEST(return_map_is_the_von_mises_law)
{
	// A deformation of logarithmic strains (e, -e/2, -e/2) + v (volume): it flows exactly when
	// the material's von Mises stress q passes sigma_y + H alpha; the returned state sits on the
	// hardened yield surface of the material's stress, keeps its volume and principal
	// directions, and its log strain's deviator shrinks along itself (radial return).
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	m.plasticity.yieldStress = 2e3;
	m.plasticity.hardening = 1e5;
	const double mu = m.mu;
	for (int trial = 0; trial < 40; ++trial)
	{
		double e = fmTestRandom(-0.01, 0.01), v = fmTestRandom(-0.002, 0.002);
		double alpha0 = fmTestRandom(0.0, 0.004), alpha = alpha0;
		fmMat3 R1 = fmTestRandomRotation(), R2 = fmTestRandomRotation();
		fmMat3 D = {{exp(e + v), 0, 0, 0, exp(-e / 2 + v), 0, 0, 0, exp(-e / 2 + v)}};
		fmMat3 T = fmMatMul(&R1, &D), F = fmMatMul(&T, &R2), out;
		double q = vonMises(&m, &F), yield = 2e3 + 1e5 * alpha0, stress[2] = {0.0, 0.0};
		bool flowed = fmPlasticity_Return(&m, &F, 1.0, &alpha, &out, stress);
		CHECK(flowed == (q > yield));
		if (!flowed)
		{
			CHECK(alpha == alpha0);
			continue;
		}
		// On the hardened yield surface of the material's own stress, to round-off.
		CHECK_REL(vonMises(&m, &out), 2e3 + 1e5 * alpha, 1e-9, 0.0);
		CHECK_REL(stress[1], 2e3 + 1e5 * alpha, 1e-9, 0.0);
		CHECK_REL(stress[0], q, 1e-12, 0.0);
		// Hencky's flow, (q - yield) / (3 mu + H), to the two laws' difference at 1% strain.
		CHECK_REL(alpha - alpha0, (q - yield) / (3.0 * mu + 1e5), 0.05, 0.0);
		// Radial: the log strain's deviator keeps its direction and the volume stays.
		fmMat3 Rt = fmTranspose(&R1), R2t = fmTranspose(&R2), A = fmMatMul(&Rt, &out);
		fmMat3 Dr = fmMatMul(&A, &R2t);
		double eNew = log(Dr.m[0]) - v;
		CHECK(eNew * e > 0.0 && fabs(eNew) < fabs(e));
		CHECK_NEAR(log(Dr.m[4]) - v, -eNew / 2, 1e-12);
		CHECK_NEAR(Dr.m[1], 0.0, 1e-12);
		CHECK_NEAR(fmDet(&out), fmDet(&F), 1e-12);
	}
	// Creep: a step of h at rate c takes c h / (1 + c h) of the flow; the cap stops it.
	fmMat3 F = turnedStretches(1.01, 1.0 / sqrt(1.01), 1.0 / sqrt(1.01)), out;
	double full = 0.0, creep = 0.0, capped = 0.0;
	fmPlasticity_Return(&m, &F, 1.0, &full, &out, NULL);
	m.plasticity.creepRate = 10.0;
	CHECK_NEAR(fmPlasticity_Share(&m, 0.01), 0.1 / 1.1, 1e-15);
	CHECK(fmPlasticity_Share(&m, 0.0) == 1.0 && fmPlasticity_Share(&m, INFINITY) == 1.0);
	fmPlasticity_Return(&m, &F, fmPlasticity_Share(&m, 0.01), &creep, &out, NULL);
	CHECK_NEAR(creep, full * 0.1 / 1.1, 1e-14);
	m.plasticity.creepRate = 0.0;
	m.plasticity.maxPlasticStrain = 0.5 * full;
	fmPlasticity_Return(&m, &F, 1.0, &capped, &out, NULL);
	CHECK_NEAR(capped, 0.5 * full, 1e-15);
	CHECK(!fmPlasticity_Return(&m, &F, 1.0, &capped, &out, NULL)); // at its cap: elastic
	// Validation names the parameter.
	fmDiagnostic diag;
	m.plasticity.hardening = -1.0;
	CHECK_INT(fmMaterial_Validate(&m, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "plasticity.hardening") != NULL);
	fmMaterial lin = fmMakeMaterial(fm_linear, 1e6, 0.3);
	lin.plasticity.yieldStress = 1e3;
	CHECK_INT(fmMaterial_Validate(&lin, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "not linear") != NULL);
}

// A 2 x 1 x 1 bar on rollers at x = 0, y = 0, z = 0; its end x = 2 held on a roller at
// 2 stretch (when @p hold) or free. Solved to equilibrium; returns the end's x.
static double solveBar(int* failures_, fmBodyId body, const double* rest, double stretch, bool hold)
{
	int n = fmBody_GetVertexCount(body);
	fmTestBarOnRollers(body, rest, 2.0, stretch, hold);
	double residual = 1.0;
	fmDiagnostic diag;
	fmResult r = fmBody_SolveStatic(body, 1e-10, 50, &residual, &diag);
	CHECK_INT(r, fm_ok);
	if (r != fm_ok)
		printf("  %s\n", diag.message);
	double end = 0.0;
	const double* p = fmTestPositions(body);
	for (int i = 0; i < n; ++i)
		if (rest[3 * i] > 2.0 - 1e-9)
			end = p[3 * i];
	return end;
}

TEST(a_bar_stretched_past_yield_keeps_the_analytic_permanent_set)
{
	// Pulled to a log strain of 2% in ten increments and let go: with E = 1 MPa, sigma_y = 1 kPa
	// (yield strain 1e-3), H = 100 kPa, the uniaxial law sigma = (sigma_y + H eps) / (1 + H / E)
	// leaves the plastic strain alpha = eps - sigma / E, a permanent stretch exp(alpha).
	const double E = 1e6, sy = 1e3, H = 1e5, strain = 0.02;
	for (int model = 0; model < 2; ++model)
	{
		fmMaterial m = fmMakeMaterial(model == 0 ? fm_neoHookean : fm_stvk, E, 0.3);
		m.plasticity.yieldStress = sy;
		m.plasticity.hardening = H;
		fmWorldId world;
		fmBodyId body = fmTestMakeBox(&world, 4, 2, 2, fmMakeVec3(2, 1, 1), m, fm_fem);
		int n = fmBody_GetVertexCount(body);
		double* rest = malloc(sizeof(double) * 3 * (size_t)n);
		memcpy(rest, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
		for (int k = 1; k <= 10; ++k)
			solveBar(failures_, body, rest, exp(strain * k / 10.0), true);
		double sigma = (sy + H * strain) / (1.0 + H / E), alpha = strain - sigma / E;
		fmBodyStats loaded = fmBody_GetStats(body);
		double end = solveBar(failures_, body, rest, 1.0, false);
		fmBodyStats s = fmBody_GetStats(body);
		printf("  %-10s: permanent set %.7f (analytic %.7f), plastic strain %.7f, plastic work "
		       "%.5g J (analytic %.5g)\n",
		       fmMaterialModelName(m.model), log(end / 2.0), alpha, s.plasticStrain, s.plasticWork,
		       2.0 * (sy * alpha + 0.5 * H * alpha * alpha));
		// The elastic law is Hencky's only to first order in the elastic strain (1e-3 here).
		CHECK_REL(log(end / 2.0), alpha, 2e-3, 0.0);
		CHECK_REL(s.plasticStrain, alpha, 2e-3, 0.0);
		CHECK_REL(loaded.plasticStrain, alpha, 2e-3, 0.0);
		// The plastic work of uniaxial flow: V (sigma_y alpha + H alpha^2 / 2), V = 2 m^3.
		CHECK_REL(s.plasticWork, 2.0 * (sy * alpha + 0.5 * H * alpha * alpha), 5e-3, 0.0);
		free(rest);
		fmDestroyWorld(world);
	}
}

// A 1 m x 0.1 m x 0.1 m beam clamped at x = 0, held straight and let go under gravity in an
// explicit world without damping: it swings down and bends for good at its root.
static fmWorldId swingingBeam(fmBodyId* body, double yieldStress, double creepRate,
                              bool autoSubstep)
{
	fmTetMesh mesh;
	fmMakeBoxMesh(10, 1, 1, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0.1, 0.1), &mesh);
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.enabled = false;
	wdef.autoSubstep = autoSubstep;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 5e5, 0.3);
	bdef.material.plasticity.yieldStress = yieldStress;
	bdef.material.plasticity.hardening = yieldStress > 0.0 ? 5e4 : 0.0;
	bdef.material.plasticity.creepRate = creepRate;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.damping = 1.0;
	bdef.smoothing = 0.0;
	fmCreateBody(world, &bdef, body, NULL);
	fmFreeTetMesh(&mesh);
	fmBody_PinBox(*body, fmMakeVec3(-1, -1, -1), fmMakeVec3(1e-6, 1, 1));
	return world;
}

TEST(a_plastic_beam_swinging_down_closes_its_energy_balance)
{
	// Gravity's work = kinetic + elastic + plastic work, every frame within 0.5% of the swing's
	// work (explicit, no damping, the steps' own error is what is left: with fixed steps 0.022,
	// 0.009, 0.006 J of 72 J at 100, 400, 1600 substeps a frame); rate-independent and creeping
	// (20 per second); the beam ends bent.
	const double creep[2] = {0.0, 20.0};
	for (int c = 0; c < 2; ++c)
	{
		fmBodyId body;
		fmWorldId world = swingingBeam(&body, 2e3, creep[c], true);
		double worst = 0.0;
		fmBodyStats s = fmBody_GetStats(body);
		for (int frame = 0; frame < 60; ++frame)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
			s = fmBody_GetStats(body);
			double balance =
			    s.work - (s.kineticEnergy + s.elasticEnergy + s.plasticWork - s.initialEnergy);
			worst = fmax(worst, fabs(balance));
		}
		worst /= s.work; // the imbalance of every frame against the whole swing's work
		printf("  creep %g/s, 1 s: work %.5g J, kinetic %.4g, elastic %.4g, plastic %.4g J; "
		       "largest imbalance %.2g of the work; largest plastic strain %.4f, tip %.4f m\n",
		       creep[c], s.work, s.kineticEnergy, s.elasticEnergy, s.plasticWork, worst,
		       s.plasticStrain, s.lowestY);
		CHECK(s.plasticWork > 0.05 * s.work); // it bent for good
		CHECK(worst < 5e-3);
		fmDestroyWorld(world);
	}
}

TEST(a_refused_frame_undoes_its_flow)
{
	// A frame that fails (explicit substeps 40 times the stability limit of a stiffened body: it
	// explodes) goes back to its start: positions, and the plastic state its substeps flowed.
	fmBodyId body;
	fmWorldId world = swingingBeam(&body, 2e3, 0.0, false);
	for (int frame = 0; frame < 10; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 400), fm_ok);
	fmBodyStats before = fmBody_GetStats(body);
	CHECK(before.plasticWork > 0.0);
	// A thousand times stiffer (the same yield strain), stepped at 40 times its stability limit.
	fmMaterial stiff = fmMakeMaterial(fm_neoHookean, 5e8, 0.3);
	stiff.plasticity.yieldStress = 2e6;
	stiff.plasticity.hardening = 5e7;
	CHECK_INT(fmBody_SetMaterial(body, &stiff, NULL), fm_ok);
	before = fmBody_GetStats(body);
	double limit = fmWorld_EstimateExplicitStep(world);
	CHECK(40.0 * limit < 1.0 / 60.0);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, (int)ceil(1.0 / 60.0 / (40.0 * limit))),
	          fm_errNumerical);
	fmBodyStats after = fmBody_GetStats(body);
	CHECK(after.plasticWork == before.plasticWork);
	CHECK(after.plasticStrain == before.plasticStrain);
	CHECK_REL(after.elasticEnergy, before.elasticEnergy, 1e-12, 0.0);
	fmDestroyWorld(world);
}

// World @p world saved into a new buffer (the caller frees it), its size into @p size.
static void* saveWorld(int* failures_, fmWorldId world, size_t* size)
{
	size_t capacity = fmWorld_GetSnapshotSize(world);
	void* buffer = malloc(capacity);
	CHECK_INT(fmWorld_SaveSnapshot(world, buffer, capacity, size), fm_ok);
	return buffer;
}

TEST(snapshots_keep_the_bent_state)
{
	// Saved mid-swing, stepped on, restored, stepped on again: the same bits (positions, plastic
	// strain, plastic work); a snapshot taken before any flow brings the straight rest back.
	fmBodyId body;
	fmWorldId world = swingingBeam(&body, 2e3, 0.0, true);
	size_t beforeSize = 0, size = 0;
	void* before = saveWorld(failures_, world, &beforeSize);
	for (int frame = 0; frame < 20; ++frame)
		fmWorld_Step(world, 1.0 / 60.0, 1);
	void* middle = saveWorld(failures_, world, &size);
	for (int frame = 0; frame < 20; ++frame)
		fmWorld_Step(world, 1.0 / 60.0, 1);
	int n = fmBody_GetVertexCount(body);
	double* first = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(first, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	fmBodyStats a = fmBody_GetStats(body);
	CHECK_INT(fmWorld_RestoreSnapshot(world, middle, size), fm_ok);
	for (int frame = 0; frame < 20; ++frame)
		fmWorld_Step(world, 1.0 / 60.0, 1);
	fmBodyStats b = fmBody_GetStats(body);
	CHECK(memcmp(first, fmTestPositions(body), sizeof(double) * 3 * (size_t)n) == 0);
	CHECK(a.plasticWork == b.plasticWork && a.plasticStrain == b.plasticStrain);
	CHECK(a.plasticWork > 0.0);
	// Before any flow: restored, the body is the straight unflowed beam again.
	CHECK_INT(fmWorld_RestoreSnapshot(world, before, beforeSize), fm_ok);
	fmBodyStats c = fmBody_GetStats(body);
	CHECK(c.plasticWork == 0.0 && c.plasticStrain == 0.0);
	CHECK_NEAR(c.elasticEnergy, 0.0, 1e-12);
	free(first);
	free(before);
	free(middle);
	fmDestroyWorld(world);
}

TEST(a_snapshot_from_before_a_body_was_plastic_restores_its_rest_shape)
{
	// Saved elastic, made plastic (fmBody_SetMaterial), bent, restored: the body has no plastic
	// strain, no plastic work and its rest shape (zero elastic energy at rest).
	fmBodyId body;
	fmWorldId world = swingingBeam(&body, 0.0, 0.0, true);
	size_t written = 0;
	void* elastic = saveWorld(failures_, world, &written);
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 5e5, 0.3);
	m.plasticity.yieldStress = 2e3;
	CHECK_INT(fmBody_SetMaterial(body, &m, NULL), fm_ok);
	for (int frame = 0; frame < 20; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK(fmBody_GetStats(body).plasticStrain > 0.0);
	CHECK_INT(fmWorld_RestoreSnapshot(world, elastic, written), fm_ok);
	fmBodyStats s = fmBody_GetStats(body);
	CHECK(s.plasticStrain == 0.0 && s.plasticWork == 0.0);
	CHECK_NEAR(s.elasticEnergy, 0.0, 1e-12);
	free(elastic);
	fmDestroyWorld(world);
}
