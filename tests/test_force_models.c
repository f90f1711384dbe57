// Force models (FEM, FVM, mass-spring) and the material models seen through whole bodies:
// FVM = FEM, spring forces and Hessians against finite differences, the spring stiffness rule,
// spring damping, E and nu measured back from a cube, inversion recovery, the house with every
// model.
#include "body/body.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static const fmMaterialModel s_models[] = {fm_linear, fm_corotated, fm_stvk, fm_neoHookean,
                                           fm_mooneyRivlin};
#define MODEL_COUNT ((int)(sizeof s_models / sizeof s_models[0]))

static double* copyPositions(fmBodyId body)
{
	size_t n3 = 3 * (size_t)fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * n3);
	memcpy(x, fmTestPositions(body), sizeof(double) * n3);
	return x;
}

static double maxAbs(const double* a, int n)
{
	double m = 0.0;
	for (int k = 0; k < n; ++k)
		m = fmax(m, fabs(a[k]));
	return m;
}

TEST(fvm_matches_fem_to_roundoff)
{
	for (int m = 0; m < MODEL_COUNT; ++m)
	{
		fmMaterial material = fmMakeMaterial(s_models[m], 1e5, 0.3);
		fmWorldId w1, w2;
		fmBodyId fem = fmTestMakeBox(&w1, 3, 2, 2, fmMakeVec3(1.5, 1, 1), material, fm_fem);
		fmBodyId fvm = fmTestMakeBox(&w2, 3, 2, 2, fmMakeVec3(1.5, 1, 1), material, fm_fvm);
		CHECK(fmBody_IsValid(fem) && fmBody_IsValid(fvm));
		fmTestSeed(7 + (unsigned)m);
		fmTestPerturb(fem, 0.1);
		fmBody_SetPositions(fvm, fmTestPositions(fem));
		int n3 = 3 * fmBody_GetVertexCount(fem);
		double* f1 = calloc((size_t)n3, sizeof(double));
		double* f2 = calloc((size_t)n3, sizeof(double));
		double e1 = fmBody_ComputeElasticForces(fem, f1);
		double e2 = fmBody_ComputeElasticForces(fvm, f2);
		CHECK_REL(e1, e2, 1e-13, 0.0);
		double scale = maxAbs(f1, n3);
		CHECK(scale > 0.0);
		for (int k = 0; k < n3; ++k)
			CHECK_NEAR(f1[k], f2[k], 1e-11 * scale);
		free(f1);
		free(f2);
		fmDestroyWorld(w1);
		fmDestroyWorld(w2);
	}
}

TEST(spring_forces_are_minus_energy_gradient)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 2, 2, 1, fmMakeVec3(1, 1, 0.5),
	                              fmMakeMaterial(fm_stvk, 1e4, 0.25), fm_massSpring);
	CHECK(fmBody_IsValid(body));
	fmTestSeed(3);
	fmTestPerturb(body, 0.1);
	fmTestCheckForcesAreMinusGradient(failures_, body, 1, 1e-6);
	fmDestroyWorld(world);
}

TEST(spring_hessian_matches_force_differences)
{
	fmWorldId world;
	fmBodyId id = fmTestMakeBox(&world, 1, 2, 1, fmMakeVec3(1, 1, 1),
	                            fmMakeMaterial(fm_stvk, 1e4, 0.25), fm_massSpring);
	fmTestSeed(5);
	fmTestPerturb(id, 0.15);
	const fmBody* body = fmGetBody(id);
	int n3 = 3 * body->mesh.vertexCount;
	double* dx = calloc((size_t)n3, sizeof(double));
	double* Kdx = calloc((size_t)n3, sizeof(double));
	// The body's own arrays (its internal order), as the internal functions below take them.
	double* xp = malloc(sizeof(double) * (size_t)n3);
	double* xm = malloc(sizeof(double) * (size_t)n3);
	memcpy(xp, body->state.x, sizeof(double) * (size_t)n3);
	memcpy(xm, body->state.x, sizeof(double) * (size_t)n3);
	double* fp = calloc((size_t)n3, sizeof(double));
	double* fm = calloc((size_t)n3, sizeof(double));
	const double h = 1e-6;
	for (int k = 0; k < n3; ++k)
	{
		dx[k] = fmTestRandom(-1, 1);
		xp[k] += h * dx[k];
		xm[k] -= h * dx[k];
	}
	fmAddHessianProduct(&body->mesh, body->state.x, dx, Kdx, 0);
	fmAddSpringForces(&body->mesh, xp, fp);
	fmAddSpringForces(&body->mesh, xm, fm);
	double scale = maxAbs(Kdx, n3);
	CHECK(scale > 0.0);
	for (int k = 0; k < n3; ++k)
		CHECK_NEAR(Kdx[k], -(fp[k] - fm[k]) / (2 * h), 1e-6 * scale);
	// The projected edge Hessians are positive semi-definite: dx^T K dx >= 0 for any dx.
	memset(Kdx, 0, sizeof(double) * (size_t)n3);
	fmAddHessianProduct(&body->mesh, body->state.x, dx, Kdx, 1);
	double quad = 0.0;
	for (int k = 0; k < n3; ++k)
		quad += dx[k] * Kdx[k];
	CHECK(quad >= 0.0);
	free(dx);
	free(Kdx);
	free(xp);
	free(xm);
	free(fp);
	free(fm);
	fmDestroyWorld(world);
}

// k_e = E sum(V) / L^2 stores the continuum dilation energy 9/2 K eps^2 V exactly at nu = 1/4.
TEST(spring_stiffness_rule_matches_bulk_modulus_at_quarter_poisson)
{
	const double E = 2e4, eps = 1e-3;
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 3, 2, 2, fmMakeVec3(1.5, 1, 1),
	                              fmMakeMaterial(fm_stvk, E, 0.25), fm_massSpring);
	double* x = copyPositions(body);
	for (int k = 0; k < 3 * fmBody_GetVertexCount(body); ++k)
		x[k] *= 1.0 + eps;
	fmBody_SetPositions(body, x);
	double* f = calloc(3 * (size_t)fmBody_GetVertexCount(body), sizeof(double));
	double energy = fmBody_ComputeElasticForces(body, f);
	double K = E / (3.0 * (1.0 - 2.0 * 0.25));
	CHECK_REL(energy, 4.5 * K * eps * eps * 1.5, 1e-9, 0.0);
	free(x);
	free(f);
	fmDestroyWorld(world);
}

// Spring damping acts along edges on relative velocity: momentum is kept, energy only falls.
TEST(spring_damping_dissipates_and_keeps_momentum)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_stvk, 1e4, 0.25);
	bdef.forceModel = fm_massSpring;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000;
	bdef.damping = 1.0;
	bdef.smoothing = 0.0;
	bdef.springDamping = 0.5;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &bdef, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	double dt = 0.05 * fmWorld_EstimateExplicitStep(world);
	int n = fmBody_GetVertexCount(body);
	double* v = calloc(3 * (size_t)n, sizeof(double));
	fmTestSeed(11);
	for (int k = 0; k < 3 * n; ++k)
		v[k] = fmTestRandom(-0.5, 0.5);
	fmBody_SetVelocities(body, v);
	const double* mass = fmBody_GetMasses(body);
	fmVec3 p0 = {0, 0, 0};
	for (int i = 0; i < n; ++i)
		p0 = fmAdd(p0, fmScale(mass[i], fmLoad(v, i)));
	fmBodyStats s = fmBody_GetStats(body);
	double previous = s.kineticEnergy + s.elasticEnergy;
	double first = previous;
	int increases = 0;
	for (int step = 0; step < 2000; ++step)
	{
		CHECK_INT(fmWorld_Step(world, dt, 1), fm_ok);
		s = fmBody_GetStats(body);
		double total = s.kineticEnergy + s.elasticEnergy;
		increases += total > previous * (1.0 + 1e-3);
		previous = total;
	}
	CHECK_INT(increases, 0);
	CHECK(previous < 0.5 * first);
	const double* vel = fmTestVelocities(body);
	fmVec3 p1 = {0, 0, 0};
	for (int i = 0; i < n; ++i)
		p1 = fmAdd(p1, fmScale(mass[i], fmLoad(vel, i)));
	CHECK_NEAR(fmLength(fmSub(p1, p0)), 0.0, 1e-9 * (1.0 + fmLength(p0)));
	free(v);
	fmDestroyWorld(world);
}

// Elastic energy of the body under the affine map x = diag(1+ex, 1+t, 1+t) X.
static double stretchedEnergy(fmBodyId body, const double* rest, double ex, double t, double* work)
{
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
	{
		x[3 * i] = (1.0 + ex) * rest[3 * i];
		x[3 * i + 1] = (1.0 + t) * rest[3 * i + 1];
		x[3 * i + 2] = (1.0 + t) * rest[3 * i + 2];
	}
	fmBody_SetPositions(body, x);
	free(x);
	return fmBody_ComputeElasticForces(body, work);
}

// Lateral strain that a free cube takes under axial strain ex: the minimiser of the energy
// over t (golden-section search).
static double lateralStrain(fmBodyId body, const double* rest, double ex, double* work)
{
	const double g = 0.5 * (sqrt(5.0) - 1.0);
	double a = -ex, b = ex;
	double c = b - g * (b - a), d = a + g * (b - a);
	double fc = stretchedEnergy(body, rest, ex, c, work),
	       fd = stretchedEnergy(body, rest, ex, d, work);
	for (int it = 0; it < 80; ++it)
	{
		if (fc < fd)
		{
			b = d, d = c, fd = fc;
			c = b - g * (b - a);
			fc = stretchedEnergy(body, rest, ex, c, work);
		}
		else
		{
			a = c, c = d, fc = fd;
			d = a + g * (b - a);
			fd = stretchedEnergy(body, rest, ex, d, work);
		}
	}
	return 0.5 * (a + b);
}

// A free cube pulled uniaxially: with the laterally relaxed state, sigma / eps gives E back and
// -t / eps gives nu back. At eps = 1e-4 the geometric nonlinearity is O(eps), so 1e-3 is tight.
TEST(uniaxial_pull_measures_youngs_modulus_and_poisson_ratio)
{
	const double E = 3e5, nu = 0.35, eps = 1e-4;
	const fmForceModel forceModels[] = {fm_fem, fm_fvm};
	for (int m = 0; m < MODEL_COUNT; ++m)
		for (int k = 0; k < 2; ++k)
		{
			fmWorldId world;
			fmBodyId body = fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1),
			                              fmMakeMaterial(s_models[m], E, nu), forceModels[k]);
			double* rest = copyPositions(body);
			double* work = calloc(3 * (size_t)fmBody_GetVertexCount(body), sizeof(double));
			double t = lateralStrain(body, rest, eps, work);
			const double h = 1e-7;
			double tp = lateralStrain(body, rest, eps + h, work);
			double tm = lateralStrain(body, rest, eps - h, work);
			// dW/d eps along the relaxed path = axial force * length = sigma * V (V = 1).
			double sigma = (stretchedEnergy(body, rest, eps + h, tp, work) -
			                stretchedEnergy(body, rest, eps - h, tm, work)) /
			               (2 * h);
			CHECK_REL(sigma / eps, E, 1e-3, 0.0);
			CHECK_REL(-t / eps, nu, 1e-3, 0.0);
			free(rest);
			free(work);
			fmDestroyWorld(world);
		}
}

static const char s_tetNode[] = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
static const char s_tetEle[] = "1 4 0\n0 0 1 2 3\n";

// One tet with its apex pushed through the opposite face, released: it must come back.
static void checkInversionRecovery(int* failures_, fmMaterialModel model, fmForceModel forceModel)
{
	fmTetMesh mesh;
	CHECK_INT(fmLoadTetGenFromMemory(s_tetNode, sizeof s_tetNode - 1, "tet.node", s_tetEle,
	                                 sizeof s_tetEle - 1, "tet.ele", &mesh, NULL),
	          fm_ok);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(model, 1e4, 0.3);
	bdef.forceModel = forceModel;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000;
	bdef.damping = 0.97; // per 3 ms: 0.995 per 0.5 ms step
	bdef.smoothing = 0.0;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &bdef, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	double x[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -0.6};
	fmBody_SetPositions(body, x);
	CHECK_INT(fmBody_GetStats(body).invertedTets, 1);
	for (int step = 0; step < 4000; ++step)
	{
		fmResult r = fmWorld_Step(world, 5e-4, 1);
		if (r != fm_ok)
		{
			FAIL_AT("%s step %d: %s", fmMaterialModelName(model), step,
			        fmWorld_GetLastError(world)->message);
			break;
		}
	}
	fmBodyStats s = fmBody_GetStats(body);
	CHECK_INT(s.invertedTets, 0);
	CHECK(isfinite(s.elasticEnergy) && isfinite(s.kineticEnergy));
	fmDestroyWorld(world);
}

TEST(inverted_tet_recovers_with_corotated_and_neohookean)
{
	checkInversionRecovery(failures_, fm_corotated, fm_fem);
	checkInversionRecovery(failures_, fm_neoHookean, fm_fem);
	checkInversionRecovery(failures_, fm_corotated, fm_fvm);
	checkInversionRecovery(failures_, fm_neoHookean, fm_fvm);
}

// The seeds' house and time step with every material and every force model: it falls, lands,
// stays above the floor, never inverts, never fails.
TEST(house_is_stable_with_every_model_and_force_model)
{
	const fmForceModel forceModels[] = {fm_fem, fm_fvm, fm_massSpring};
	for (int m = 0; m < MODEL_COUNT; ++m)
		for (int k = 0; k < 3; ++k)
		{
			fmBodyDef bdef = fmDefaultBodyDef();
			bdef.material = fmMakeMaterialLame(s_models[m], 20000, 5000);
			bdef.forceModel = forceModels[k];
			fmWorldId world;
			fmBodyId body = fmTestMakeHouse(&world, NULL, &bdef);
			CHECK(fmBody_IsValid(body));
			double lowest = 1e30;
			for (int frame = 0; frame < 60; ++frame)
			{
				fmResult r = fmWorld_Step(world, 0.03, 10);
				if (r != fm_ok)
				{
					FAIL_AT("%s/%s frame %d: %s", fmMaterialModelName(s_models[m]),
					        fmForceModelName(forceModels[k]), frame,
					        fmWorld_GetLastError(world)->message);
					break;
				}
				lowest = fmin(lowest, fmBody_GetStats(body).lowestY);
			}
			fmBodyStats s = fmBody_GetStats(body);
			CHECK(lowest > -3.0 - 1e-9);
			CHECK(lowest < -2.9); // it reached the floor
			CHECK_INT(s.invertedTets, 0);
			CHECK(isfinite(s.kineticEnergy));
			fmDestroyWorld(world);
		}
}
