// Loads and boundary conditions: pressure and nodal-force patch tests against the analytic
// uniaxial solution, a prescribed-displacement patch test with its reaction force, follower
// against fixed pressure under a rotation, loaded dynamic runs in the energy ledger, the
// isochoric Neo-Hookean under uniaxial stretch, per-region materials in series.
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

#define EPS 1e-9

static fmVec3 v3(double x, double y, double z)
{
	return fmMakeVec3(x, y, z);
}

// Rollers on the faces x = 0, y = 0 and z = 0 of the unit cube: each held on its normal axis.
static void pinRollers(fmBodyId body)
{
	const double big = 10.0;
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(EPS, big, big), 1u);
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(big, EPS, big), 2u);
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(big, big, EPS), 4u);
}

// Largest deviation of the displacement from u = (ex x, ey y, ez z) over every vertex.
static double uniformStrainError(fmBodyId body, const double* rest, double ex, double ey, double ez)
{
	const double* x = fmTestPositions(body);
	double worst = 0.0;
	const double e[3] = {ex, ey, ez};
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		for (int k = 0; k < 3; ++k)
			worst = fmax(worst, fabs(x[3 * i + k] - rest[3 * i + k] * (1.0 + e[k])));
	return worst;
}

static double* copyRest(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	double* rest = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(rest, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	return rest;
}

// Pressure patch test: a unit cube of a linear material under a uniform pressure p on its face
// x = 1, rollers on the faces x = 0, y = 0, z = 0, is in uniaxial stress: strain -p/E along x
// and nu p/E across, at every vertex (linear tets represent a uniform strain exactly).
TEST(pressure_patch_test_matches_uniaxial_stress)
{
	const double E = 1e6, nu = 0.3, p = 1e3;
	for (int follower = 0; follower < 2; ++follower)
	{
		fmWorldId world;
		fmBodyId body =
		    fmTestMakeBox(&world, 3, 3, 3, v3(1, 1, 1), fmMakeMaterial(fm_linear, E, nu), fm_fem);
		CHECK(fmBody_IsValid(body));
		double* rest = copyRest(body);
		pinRollers(body);
		int triangles = fmBody_AddPressure(body, v3(1 - EPS, -1, -1), v3(2, 2, 2), p, follower);
		CHECK_INT(triangles, 2 * 3 * 3);
		// The resultant is p A along -x.
		int n = fmBody_GetVertexCount(body);
		double* f = malloc(sizeof(double) * 3 * (size_t)n);
		fmBody_ComputeLoadForces(body, f);
		double sum[3] = {0, 0, 0};
		for (int i = 0; i < n; ++i)
			for (int k = 0; k < 3; ++k)
				sum[k] += f[3 * i + k];
		CHECK_NEAR(sum[0], -p, 1e-9 * p);
		CHECK_NEAR(sum[1], 0.0, 1e-9 * p);
		double residual = 1.0;
		fmDiagnostic diag;
		fmResult r = fmBody_SolveStatic(body, 1e-10, 30, &residual, &diag);
		CHECK_INT(r, fm_ok);
		double error = uniformStrainError(body, rest, -p / E, nu * p / E, nu * p / E);
		// Fixed direction: exact to solver tolerance. Follower: the loaded face shrinks by the
		// lateral strain (2 nu p/E of its area), a second-order difference.
		double tolerance = follower ? 3.0 * nu * p / E * p / E : 1e-9;
		printf("  %s pressure: largest deviation from the analytic displacement %.3g m "
		       "(strain %.3g), residual %.2g\n",
		       follower ? "follower" : "fixed", error, p / E, residual);
		CHECK(error <= tolerance);
		free(f);
		free(rest);
		fmDestroyWorld(world);
	}
}

// The same cube under nodal forces equal to the pressure's consistent nodal loads (applied
// vertex by vertex through small boxes): the same uniform solution, so nodal forces carry the
// pressure's resultant exactly.
TEST(nodal_forces_equal_to_the_pressure_resultant)
{
	const double E = 1e6, nu = 0.25, p = 500.0;
	fmWorldId world;
	fmBodyId body =
	    fmTestMakeBox(&world, 2, 2, 2, v3(1, 1, 1), fmMakeMaterial(fm_linear, E, nu), fm_fem);
	CHECK(fmBody_IsValid(body));
	double* rest = copyRest(body);
	int n = fmBody_GetVertexCount(body);
	pinRollers(body);
	fmBody_AddPressure(body, v3(1 - EPS, -1, -1), v3(2, 2, 2), p, false);
	double* f = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_ComputeLoadForces(body, f);
	fmBody_ClearLoads(body);
	double total = 0.0;
	int loaded = 0;
	for (int i = 0; i < n; ++i)
		if (f[3 * i] != 0.0)
		{
			const double* X = rest + 3 * i;
			fmVec3 lo = v3(X[0] - 1e-6, X[1] - 1e-6, X[2] - 1e-6);
			fmVec3 hi = v3(X[0] + 1e-6, X[1] + 1e-6, X[2] + 1e-6);
			CHECK_INT(fmBody_AddNodalForce(body, lo, hi, v3(f[3 * i], f[3 * i + 1], f[3 * i + 2])),
			          1);
			total += f[3 * i];
			++loaded;
		}
	CHECK_INT(loaded, 9);
	CHECK_NEAR(total, -p, 1e-9 * p);
	double residual = 1.0;
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 30, &residual, NULL), fm_ok);
	double error = uniformStrainError(body, rest, -p / E, nu * p / E, nu * p / E);
	printf("  nodal forces: resultant %.6g N, deviation %.3g m\n", total, error);
	CHECK(error <= 1e-9);
	free(f);
	free(rest);
	fmDestroyWorld(world);
}

// Sum of the x component of the elastic forces on the vertices of the face x = 1.
static double faceForceX(fmBodyId body, const double* rest)
{
	int n = fmBody_GetVertexCount(body);
	double* f = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_ComputeElasticForces(body, f);
	double sum = 0.0;
	for (int i = 0; i < n; ++i)
		if (rest[3 * i] > 1.0 - EPS)
			sum += f[3 * i];
	free(f);
	return sum;
}

// Prescribed-displacement patch test: the face x = 1 moved by d along x (its other axes free),
// rollers on the others: uniform strain eps = d along x, -nu eps across, and the face's
// reaction E A eps (uniaxial stress).
TEST(prescribed_displacement_patch_test_and_reaction)
{
	const double E = 2e6, nu = 0.3, d = 1e-3;
	fmWorldId world;
	fmBodyId body =
	    fmTestMakeBox(&world, 3, 3, 3, v3(1, 1, 1), fmMakeMaterial(fm_linear, E, nu), fm_fem);
	CHECK(fmBody_IsValid(body));
	double* rest = copyRest(body);
	pinRollers(body);
	CHECK_INT(
	    fmBody_PrescribeDisplacement(body, v3(1 - EPS, -1, -1), v3(2, 2, 2), 1u, v3(d, 0, 0), 0.0),
	    16);
	double residual = 1.0;
	fmDiagnostic diag;
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 30, &residual, &diag), fm_ok);
	double error = uniformStrainError(body, rest, d, -nu * d, -nu * d);
	double reaction = -faceForceX(body, rest);
	printf("  prescribed stretch %.3g: deviation %.3g m, reaction %.6g N (E A eps = %.6g N)\n", d,
	       error, reaction, E * d);
	CHECK(error <= 1e-10);
	CHECK_REL(reaction, E * d, 1e-8, 0.0);
	free(rest);
	fmDestroyWorld(world);
}

// Rotate every vertex of the body by 90 degrees about z (x -> y, y -> -x) about the origin.
static void rotateBody(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
	{
		double px = x[3 * i], py = x[3 * i + 1];
		x[3 * i] = -py;
		x[3 * i + 1] = px;
	}
	fmBody_SetPositions(body, x);
	free(x);
}

static fmVec3 loadResultant(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	double* f = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_ComputeLoadForces(body, f);
	fmVec3 sum = v3(0, 0, 0);
	for (int i = 0; i < n; ++i)
		sum = fmAdd(sum, v3(f[3 * i], f[3 * i + 1], f[3 * i + 2]));
	free(f);
	return sum;
}

// A follower pressure turns with the body: after a rigid 90-degree rotation its resultant has
// turned from -x to -y. A fixed-direction pressure keeps its reference direction. Then a
// cantilever bent by a large tip pressure: the follower load turns with the tip and bends it
// less far down (part of it pushes along the beam), the fixed one keeps pushing straight down.
TEST(follower_pressure_turns_with_the_body_fixed_does_not)
{
	const double p = 100.0;
	fmVec3 results[2];
	for (int follower = 0; follower < 2; ++follower)
	{
		fmWorldId world;
		fmBodyId body = fmTestMakeBox(&world, 2, 2, 2, v3(1, 1, 1),
		                              fmMakeMaterial(fm_neoHookean, 1e5, 0.3), fm_fem);
		fmBody_AddPressure(body, v3(1 - EPS, -1, -1), v3(2, 2, 2), p, follower);
		rotateBody(body);
		results[follower] = loadResultant(body);
		fmDestroyWorld(world);
	}
	printf("  after a 90-degree turn: fixed (%.3g, %.3g) N, follower (%.3g, %.3g) N\n",
	       results[0].x, results[0].y, results[1].x, results[1].y);
	CHECK_NEAR(results[0].x, -p, 1e-9 * p);
	CHECK_NEAR(results[0].y, 0.0, 1e-9 * p);
	CHECK_NEAR(results[1].x, 0.0, 1e-9 * p);
	CHECK_NEAR(results[1].y, -p, 1e-9 * p);

	// Cantilever 4 x 0.5 x 0.5 m clamped at x = 0, pressure on its top face near the tip, bent
	// by about a quarter of its length.
	double tip[2][2], ratio[2], slope[2];
	for (int follower = 0; follower < 2; ++follower)
	{
		fmWorldId world;
		fmBodyId body = fmTestMakeBox(&world, 8, 1, 1, v3(4, 0.5, 0.5),
		                              fmMakeMaterial(fm_neoHookean, 1e6, 0.3), fm_fem);
		fmBody_PinBox(body, v3(-1, -1, -1), v3(EPS, 1, 1));
		CHECK(fmBody_AddPressure(body, v3(3.5 - EPS, 0.5 - EPS, -1), v3(5, 1, 1), 5000.0,
		                         follower) == 2);
		double* rest = copyRest(body);
		double residual = 1.0;
		fmDiagnostic diag;
		fmResult r = fmBody_SolveStatic(body, 1e-8, 50, &residual, &diag);
		CHECK_INT(r, fm_ok);
		if (r != fm_ok)
			printf("  %s\n", diag.message);
		const double* x = fmTestPositions(body);
		tip[follower][0] = tip[follower][1] = 0.0;
		double edge[2][2] = {{0, 0}, {0, 0}}; // top edge z = 0 at rest x = 3.5 and x = 4
		for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		{
			const double* X = rest + 3 * i;
			if (X[0] > 4.0 - EPS)
			{
				tip[follower][0] += 0.25 * (x[3 * i] - X[0]);
				tip[follower][1] += 0.25 * (x[3 * i + 1] - X[1]);
			}
			if (X[1] > 0.5 - EPS && X[2] < EPS && X[0] > 3.5 - EPS)
				for (int k = 0; k < 2; ++k)
					edge[X[0] > 4.0 - EPS][k] = x[3 * i + k];
		}
		// The loaded face's outward normal in the xy plane is (-a_y, a_x), a its edge along
		// the beam; the pressure's resultant points against it.
		slope[follower] = -(edge[1][1] - edge[0][1]) / (edge[1][0] - edge[0][0]);
		fmVec3 resultant = loadResultant(body);
		ratio[follower] = resultant.x / resultant.y;
		free(rest);
		fmDestroyWorld(world);
	}
	printf("  cantilever tip displacement: fixed (%.4f, %.4f) m, follower (%.4f, %.4f) m; "
	       "load Fx/Fy: fixed %.4g, follower %.4g (the deformed face's n_x/n_y %.4g)\n",
	       tip[0][0], tip[0][1], tip[1][0], tip[1][1], ratio[0], ratio[1], slope[1]);
	CHECK(tip[0][1] < -0.6); // a large deflection: the load's direction matters
	CHECK(tip[1][1] < -0.6);
	CHECK_NEAR(ratio[0], 0.0, 1e-12);
	// The follower load stays normal to the deformed face at equilibrium (the lagged load's
	// fixed point), turned toward the clamp: it pulls the tip further back.
	CHECK(ratio[1] > 0.1);
	CHECK_REL(ratio[1], slope[1], 1e-2, 0.0); // the quad is not quite planar
	CHECK(tip[1][0] < tip[0][0] - 0.005);
}

// A free body under the same nodal force on every vertex accelerates at F / M (no gravity, no
// floor), in both integrators, and no frame is refused by the energy ledger.
TEST(constant_nodal_force_accelerates_at_f_over_m)
{
	for (int implicit = 0; implicit < 2; ++implicit)
	{
		fmWorldId world;
		fmBodyId body =
		    fmTestMakeBox(&world, 2, 2, 2, v3(1, 1, 1), fmMakeMaterial(fm_stvk, 1e5, 0.3), fm_fem);
		fmWorld_SetIntegrator(world, implicit ? fm_implicit : fm_explicit);
		int n = fmBody_GetVertexCount(body);
		CHECK_INT(fmBody_AddNodalForce(body, v3(-1, -1, -1), v3(2, 2, 2), v3(0, 0, 2.0)), n);
		double mass = 0.0;
		const double* m = fmBody_GetMasses(body);
		for (int i = 0; i < n; ++i)
			mass += m[i];
		double z0 = fmBody_GetStats(body).centerOfMass.z;
		const double T = 0.5;
		int frames = 30, steps = 10 * frames, refused = 0;
		for (int frame = 0; frame < frames; ++frame)
			refused += fmWorld_Step(world, T / frames, 10) != fm_ok;
		double a = 2.0 * n / mass;
		double travelled = fmBody_GetStats(body).centerOfMass.z - z0;
		// Symplectic and backward Euler both take v += h a, then x += h v: after N steps
		// x = a h^2 N (N + 1) / 2 = a T^2 / 2 (1 + 1/N), exactly for a rigid motion.
		double expected = 0.5 * a * T * T * (1.0 + 1.0 / steps);
		printf("  %s: centre moved %.9f m, a T^2/2 (1 + 1/N) = %.9f m (a = F/M = %.4g m/s^2), "
		       "refused frames %d\n",
		       implicit ? "implicit" : "explicit", travelled, expected, a, refused);
		CHECK_INT(refused, 0);
		CHECK_REL(travelled, expected, implicit ? 1e-5 : 1e-9, 0.0); // implicit: Newton tolerance
		fmDestroyWorld(world);
	}
}

// A clamped beam under a sudden follower pressure and a gravity-free prescribed stretch
// oscillates for two seconds in both integrators: every frame passes the energy ledger, and the
// stretched face ends where it was sent.
TEST(loaded_dynamic_runs_pass_the_energy_ledger)
{
	for (int implicit = 0; implicit < 2; ++implicit)
	{
		fmWorldId world;
		fmBodyId body = fmTestMakeBox(&world, 6, 2, 2, v3(3, 0.5, 0.5),
		                              fmMakeMaterial(fm_neoHookean, 2e5, 0.3), fm_fem);
		fmWorld_SetIntegrator(world, implicit ? fm_implicit : fm_explicit);
		fmBody_PinBox(body, v3(-1, -1, -1), v3(EPS, 1, 1));
		CHECK(fmBody_AddPressure(body, v3(-1, 0.5 - EPS, -1), v3(4, 1, 1), 300.0, true) > 0);
		CHECK(fmBody_AddNodalForce(body, v3(3 - EPS, -1, -1), v3(4, 1, 1), v3(0, 0, 5.0)) > 0);
		CHECK_INT(fmBody_PrescribeDisplacement(body, v3(3 - EPS, -1, -1), v3(4, 1, 1), 1u,
		                                       v3(0.3, 0, 0), 0.5),
		          9);
		int refused = 0;
		for (int frame = 0; frame < 120; ++frame)
		{
			fmResult r = fmWorld_Step(world, 1.0 / 60.0, implicit ? 2 : 40);
			if (r != fm_ok && refused++ == 0)
				printf("  frame %d: %s\n", frame, fmWorld_GetLastError(world)->message);
		}
		fmBodyStats stats = fmBody_GetStats(body);
		double endX = 0.0;
		const double* x = fmTestPositions(body);
		for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
			endX = fmax(endX, x[3 * i]);
		printf("  %s: refused frames %d, work booked %.4g J, energy %.4g J, stretched face at "
		       "x = %.6f\n",
		       implicit ? "implicit" : "explicit", refused, stats.work,
		       stats.kineticEnergy + stats.elasticEnergy, endX);
		CHECK_INT(refused, 0);
		CHECK(stats.work > 0.0);
		CHECK_NEAR(endX, 3.3, 1e-12);
		fmDestroyWorld(world);
	}
}

// d psi / d lambda and d psi / d l of the isochoric Neo-Hookean at F = diag(lambda, l, l).
static void isochoricDerivatives(double c10, double kappa, double lambda, double l, double* dLambda,
                                 double* dl)
{
	double J = lambda * l * l, I1 = lambda * lambda + 2.0 * l * l;
	double g = pow(J, -2.0 / 3.0), g1 = -2.0 / 3.0 * g / J;
	*dLambda = c10 * (g1 * l * l * I1 + g * 2.0 * lambda) + kappa * (J - 1.0) * l * l;
	*dl = c10 * (g1 * 2.0 * lambda * l * I1 + g * 4.0 * l) + kappa * (J - 1.0) * 2.0 * lambda * l;
}

// The isochoric Neo-Hookean cube stretched to 1.3 by a prescribed displacement, rollers on the
// other faces (uniaxial stress): the lateral stretch makes d psi / d l = 0 and the reaction per
// reference area is the nominal stress d psi / d lambda (psi = C10 (J^-2/3 I1 - 3) +
// kappa/2 (J - 1)^2), both found here by bisection on the formula.
TEST(isochoric_neohookean_uniaxial_stretch)
{
	const double E = 1e6, nu = 0.45, stretch = 1.3;
	fmMaterial material = fmMakeMaterial(fm_neoHookeanIsochoric, E, nu);
	double c10 = 0.5 * material.mu, kappa = material.lambda + 2.0 / 3.0 * material.mu;
	double lo = 0.5, hi = 1.0, nominal = 0.0, dl = 0.0;
	for (int it = 0; it < 200; ++it)
	{
		double mid = 0.5 * (lo + hi);
		isochoricDerivatives(c10, kappa, stretch, mid, &nominal, &dl);
		if (dl > 0.0)
			hi = mid;
		else
			lo = mid;
	}
	double lateral = 0.5 * (lo + hi);
	isochoricDerivatives(c10, kappa, stretch, lateral, &nominal, &dl);

	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 2, 2, 2, v3(1, 1, 1), material, fm_fem);
	double* rest = copyRest(body);
	pinRollers(body);
	fmBody_PrescribeDisplacement(body, v3(1 - EPS, -1, -1), v3(2, 2, 2), 1u,
	                             v3(stretch - 1.0, 0, 0), 0.0);
	double residual = 1.0;
	fmDiagnostic diag;
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 50, &residual, &diag), fm_ok);
	double error = uniformStrainError(body, rest, stretch - 1.0, lateral - 1.0, lateral - 1.0);
	double reaction = -faceForceX(body, rest);
	double measured = 0.0;
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		measured = fmax(measured, fmTestPositions(body)[3 * i + 1]);
	printf("  stretch %.2f: lateral %.6f (analytic %.6f), nominal stress %.6g Pa (analytic "
	       "%.6g Pa; incompressible 2 C10 (l - l^-2) = %.6g Pa)\n",
	       stretch, measured, lateral, reaction, nominal,
	       2.0 * c10 * (stretch - 1.0 / (stretch * stretch)));
	CHECK(error < 1e-8);
	CHECK_REL(reaction, nominal, 1e-7, 0.0);
	free(rest);
	fmDestroyWorld(world);
}

// A bar 2 m long along x, 0.5 m square, region 1 (x < 1) of E1 and region 2 (x > 1) of E2,
// both linear with nu = 0, rollers at its end x = 0 and its sides y = 0, z = 0, pulled by a
// pressure -s on its end x = 2: in series, each half stretches by its own compliance, s / E1
// and s / E2, exactly (uniform strain in each).
TEST(two_region_bar_in_series_stretches_each_by_its_compliance)
{
	const double E1 = 1e6, E2 = 3e6, s = 1e4;
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(8, 2, 2, v3(0, 0, 0), v3(2, 0.5, 0.5), &mesh), fm_ok);
	double* regions = malloc(sizeof(double) * (size_t)mesh.tetCount);
	for (int t = 0; t < mesh.tetCount; ++t)
	{
		double cx = 0.0;
		for (int a = 0; a < 4; ++a)
			cx += 0.25 * mesh.positions[3 * (mesh.tets[4 * t + a] - mesh.firstIndex)];
		regions[t] = cx < 1.0 ? 1.0 : 2.0;
	}
	fmTetMesh withRegions = mesh;
	withRegions.tetAttributeCount = 1;
	withRegions.tetAttributes = regions;
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &withRegions;
	def.material = fmMakeMaterial(fm_stvk, 1e3, 0.3); // no tet keeps it
	const fmMaterial materials[2] = {fmMakeMaterial(fm_linear, E1, 0.0),
	                                 fmMakeMaterial(fm_linear, E2, 0.0)};
	const int ids[2] = {2, 1};
	// Ids in another order than the materials: region 2 gets materials[0] = E1 below.
	def.regionMaterials = materials;
	def.regionIds = ids;
	def.regionCount = 2;
	fmBodyId body;
	fmDiagnostic diag;
	// Without region numbers in the mesh the def is refused.
	def.mesh = &mesh;
	CHECK_INT(fmCreateBody(world, &def, &body, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "region numbers");
	def.mesh = &withRegions;
	CHECK_INT(fmCreateBody(world, &def, &body, &diag), fm_ok);
	free(regions);
	fmFreeTetMesh(&mesh);
	double* rest = copyRest(body);
	const double big = 10.0;
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(EPS, big, big), 1u);
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(big, EPS, big), 2u);
	fmBody_PinBoxAxes(body, v3(-big, -big, -big), v3(big, big, EPS), 4u);
	fmBody_AddPressure(body, v3(2 - EPS, -1, -1), v3(3, 1, 1), -s, false);
	double residual = 1.0;
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 30, &residual, &diag), fm_ok);
	const double* x = fmTestPositions(body);
	double worst = 0.0, middle = 0.0, end = 0.0;
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
	{
		double X = rest[3 * i];
		// Region 2 (x < 1) has E2, region 1 (x > 1) has E1, as the ids map them.
		double u = X <= 1.0 ? s / E2 * X : s / E2 + s / E1 * (X - 1.0);
		worst = fmax(worst, fabs(x[3 * i] - X - u));
		if (fabs(X - 1.0) < EPS)
			middle = x[3 * i] - X;
		if (fabs(X - 2.0) < EPS)
			end = x[3 * i] - X;
	}
	printf("  stretch of the first metre %.6g m (s/E = %.6g), of the second %.6g m (s/E = %.6g); "
	       "largest deviation %.3g m\n",
	       middle, s / E2, end - middle, s / E1, worst);
	CHECK(worst < 1e-10);
	CHECK_REL(middle, s / E2, 1e-8, 0.0);
	CHECK_REL(end - middle, s / E1, 1e-8, 0.0);
	// The explicit step uses each tet's material too: at the static solution the elastic and
	// load forces balance at every free vertex.
	int n = fmBody_GetVertexCount(body);
	double* f = malloc(sizeof(double) * 3 * (size_t)n);
	double* load = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_ComputeElasticForces(body, f);
	fmBody_ComputeLoadForces(body, load);
	double unbalanced = 0.0;
	for (int i = 0; i < n; ++i)
		if (rest[3 * i] > EPS)
			unbalanced = fmax(unbalanced, fabs(f[3 * i] + load[3 * i]));
	CHECK(unbalanced < 1e-6 * s);
	// Replacing the material drops the regions: the bar is then uniform.
	fmMaterial one = fmMakeMaterial(fm_linear, E1, 0.0);
	CHECK_INT(fmBody_SetMaterial(body, &one, NULL), fm_ok);
	fmBody_SetPositions(body, rest);
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 30, &residual, &diag), fm_ok);
	x = fmTestPositions(body);
	for (int i = 0; i < n; ++i)
		if (fabs(rest[3 * i] - 2.0) < EPS)
			CHECK_REL(x[3 * i] - rest[3 * i], 2.0 * s / E1, 1e-8, 0.0);
	free(f);
	free(load);
	free(rest);
	fmDestroyWorld(world);
}

// Programmer errors in the load calls (NaN, an empty box, bad axes, a negative time, a stale
// id) return -1 and change nothing; a box that catches nothing returns 0; a load on a body
// with no support makes the static solve refuse with a reason.
TEST(load_calls_refuse_bad_arguments)
{
	fmWorldId world;
	fmBodyId body =
	    fmTestMakeBox(&world, 1, 1, 1, v3(1, 1, 1), fmMakeMaterial(fm_linear, 1e5, 0.3), fm_fem);
	const fmVec3 lo = v3(-1, -1, -1), hi = v3(2, 2, 2);
	fmTestRecordAssertsBegin();
	int before = fmTestAssertCount();
	CHECK_INT(fmBody_AddNodalForce(body, lo, hi, v3(NAN, 0, 0)), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmBody_AddNodalForce(body, hi, lo, v3(1, 0, 0)), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmBody_AddPressure(body, lo, hi, INFINITY, true), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmBody_PinBoxAxes(body, lo, hi, 8u), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmBody_PrescribeDisplacement(body, lo, hi, 0u, v3(0, 0, 0), 1.0), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmBody_PrescribeDisplacement(body, lo, hi, 1u, v3(1, 0, 0), -1.0), -1);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	fmBodyId stale = {0, 0, 0, 0};
	CHECK_INT(fmBody_AddNodalForce(stale, lo, hi, v3(1, 0, 0)), -1);
	CHECK_ASSERTED_SINCE(before);
	fmTestRecordAssertsEnd();
	// Nothing was added: no load, no pin.
	fmVec3 sum = loadResultant(body);
	CHECK(sum.x == 0.0 && sum.y == 0.0 && sum.z == 0.0);
	CHECK(!fmBody_IsPinned(body, 0));
	CHECK_INT(fmBody_AddNodalForce(body, v3(5, 5, 5), v3(6, 6, 6), v3(1, 0, 0)), 0);
	CHECK_INT(fmBody_AddPressure(body, v3(-1, -1, -1), v3(0.5, 0.5, 2), 10.0, false), 0);
	CHECK_INT(fmBody_AddNodalForce(body, lo, hi, v3(1, 0, 0)), 8);
	fmDiagnostic diag;
	CHECK_INT(fmBody_SolveStatic(body, 1e-8, 10, NULL, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "no pinned vertex");
	fmBody_ClearLoads(body);
	sum = loadResultant(body);
	CHECK(sum.x == 0.0);
	fmDestroyWorld(world);
}
