// Kinematic targets (fmBody_SetTargets): zero-length springs that drag vertices, in both
// integrators. Physics: a free body pulled on every vertex to a translated copy of itself goes
// there and stops (the springs' only equilibrium), the pull moves the centre of mass the way
// the net spring force says, the work shows in the energy ledger, and no stiffness makes an
// explicit substep unstable.
#include "support.h"
#include "test.h"

#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static fmBodyId makeCube(fmWorldId* world, fmIntegrator integrator, double damping)
{
	fmTetMesh mesh;
	fmBodyId none = {0, 0, 0, 0};
	if (fmMakeBoxMesh(3, 3, 3, fmMakeVec3(0, 0, 0), fmMakeVec3(0.3, 0.3, 0.3), &mesh) != fm_ok)
		return none;
	fmWorldDef wdef = fmTestFreeWorldDef();
	wdef.integrator = integrator;
	*world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.damping = damping;
	bdef.smoothing = 0.0;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

// Every vertex pulled to its rest position moved by @p shift.
static void targetAllShifted(int* failures_, fmBodyId body, fmVec3 shift, double stiffness)
{
	int n = fmBody_GetVertexCount(body);
	int* vertices = malloc(sizeof(int) * (size_t)n);
	fmVec3* positions = malloc(sizeof(fmVec3) * (size_t)n);
	const double* x = fmTestPositions(body);
	for (int i = 0; i < n; ++i)
	{
		vertices[i] = i;
		positions[i] =
		    fmMakeVec3(x[3 * i] + shift.x, x[3 * i + 1] + shift.y, x[3 * i + 2] + shift.z);
	}
	CHECK_INT(fmBody_SetTargets(body, vertices, positions, n, stiffness), fm_ok);
	CHECK_INT(fmBody_GetTargetCount(body), n);
	free(vertices);
	free(positions);
}

// The translated copy is the only state where every spring is slack and the body unstrained:
// implicit steps (dissipative) and damped explicit ones end there.
TEST(free_body_goes_to_translated_targets)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBodyId body =
		    makeCube(&world, integrators[k], integrators[k] == fm_explicit ? 0.99 : 1.0);
		CHECK(fmBody_IsValid(body));
		if (!fmBody_IsValid(body))
			return;
		int n = fmBody_GetVertexCount(body);
		double* start = malloc(sizeof(double) * 3 * (size_t)n);
		memcpy(start, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
		const fmVec3 shift = {0.05, -0.02, 0.03};
		targetAllShifted(failures_, body, shift, 500.0);
		for (int frame = 0; frame < 600; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrators[k] == fm_explicit ? 20 : 1),
			          fm_ok);
		const double* x = fmTestPositions(body);
		double worst = 0.0;
		for (int i = 0; i < n; ++i)
		{
			worst = fmax(worst, fabs(x[3 * i] - start[3 * i] - shift.x));
			worst = fmax(worst, fabs(x[3 * i + 1] - start[3 * i + 1] - shift.y));
			worst = fmax(worst, fabs(x[3 * i + 2] - start[3 * i + 2] - shift.z));
		}
		printf("  %s: farthest vertex %.2e m from its target after 10 s\n",
		       integrators[k] == fm_explicit ? "explicit" : "implicit", worst);
		CHECK(worst < 1e-4);
		free(start);
		fmDestroyWorld(world);
	}
}

// One vertex pulled sideways: over the first step the centre of mass accelerates along the
// spring, at k d / M (Newton's second law; the elastic forces sum to zero).
TEST(pull_accelerates_the_centre_of_mass)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBodyId body = makeCube(&world, integrators[k], 1.0);
		if (!fmBody_IsValid(body))
			return;
		fmBodyStats before = fmBody_GetStats(body);
		const double* x = fmTestPositions(body);
		int vertex = 0;
		fmVec3 target = {x[0] + 0.01, x[1], x[2]};
		const double stiffness = 50.0, h = 1e-3;
		CHECK_INT(fmBody_SetTargets(body, &vertex, &target, 1, stiffness), fm_ok);
		CHECK_INT(fmWorld_Step(world, h, 1), fm_ok);
		fmBodyStats after = fmBody_GetStats(body);
		// x_com moves by a h^2 after one step from rest (symplectic and backward Euler alike).
		double mass = 0.0;
		const double* masses = fmBody_GetMasses(body);
		for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
			mass += masses[i];
		double expected = stiffness * 0.01 / mass * h * h;
		double moved = after.centerOfMass.x - before.centerOfMass.x;
		printf("  %s: centre of mass moved %.4e m, k d h^2 / M = %.4e m\n",
		       integrators[k] == fm_explicit ? "explicit" : "implicit", moved, expected);
		CHECK_REL(moved, expected, 0.02, 0.0);
		CHECK(fabs(after.centerOfMass.y - before.centerOfMass.y) < 1e-3 * expected);
		fmDestroyWorld(world);
	}
}

// A target dragged around a circle for two seconds: every frame passes the health checks, the
// ledger books the springs' work, and the body follows.
TEST(dragging_feeds_the_ledger_and_stays_healthy)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBodyId body = makeCube(&world, integrators[k], 1.0);
		if (!fmBody_IsValid(body))
			return;
		const double* x = fmTestPositions(body);
		int vertex = 0;
		fmVec3 anchor = {x[0], x[1], x[2]};
		for (int frame = 0; frame < 120; ++frame)
		{
			double angle = 2.0 * 3.14159265358979 * frame / 60.0;
			fmVec3 target = {anchor.x + 0.1 * sin(angle), anchor.y + 0.1 * (1.0 - cos(angle)),
			                 anchor.z};
			CHECK_INT(fmBody_SetTargets(body, &vertex, &target, 1, 2000.0), fm_ok);
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrators[k] == fm_explicit ? 20 : 1),
			          fm_ok);
		}
		fmBodyStats stats = fmBody_GetStats(body);
		printf("  %s: work booked %.3e J, energy now %.3e J\n",
		       integrators[k] == fm_explicit ? "explicit" : "implicit", stats.work,
		       stats.kineticEnergy + stats.elasticEnergy);
		CHECK(stats.work > 0.0);
		CHECK(stats.kineticEnergy + stats.elasticEnergy <= 1.01 * stats.work + 1e-9);
		fmDestroyWorld(world);
	}
}

// A spring far stiffer than an explicit substep can integrate (1e12 N/m on grams of mass) is
// limited to mass / h^2: the body does not explode and the vertex reaches its target.
TEST(explicit_stiffness_is_limited_for_stability)
{
	fmWorldId world;
	fmBodyId body = makeCube(&world, fm_explicit, 0.99);
	if (!fmBody_IsValid(body))
		return;
	const double* x = fmTestPositions(body);
	int vertex = 5;
	fmVec3 target = {x[15] + 0.02, x[16], x[17]};
	CHECK_INT(fmBody_SetTargets(body, &vertex, &target, 1, 1e12), fm_ok);
	for (int frame = 0; frame < 60; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 20), fm_ok);
	x = fmTestPositions(body);
	double gap = fabs(x[15] - target.x) + fabs(x[16] - target.y) + fabs(x[17] - target.z);
	CHECK(gap < 5e-3);
	fmDestroyWorld(world);
}

// Vertex block descent does not model targets: an implicit world that asks for it takes the
// Newton solver for a body with targets (the same bits as asking for Newton).
TEST(targets_take_the_newton_solver)
{
	double* result[2];
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBodyId body = makeCube(&world, fm_implicit, 1.0);
		if (!fmBody_IsValid(body))
			return;
		if (k == 1)
		{
			fmWorldDef* def = &fmGetWorld(world)->def;
			def->implicitSolver = fm_solverVbd;
		}
		int vertex = 3;
		fmVec3 target = {0.5, 0.5, 0.5};
		CHECK_INT(fmBody_SetTargets(body, &vertex, &target, 1, 100.0), fm_ok);
		for (int frame = 0; frame < 5; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		int n = fmBody_GetVertexCount(body);
		result[k] = malloc(sizeof(double) * 3 * (size_t)n);
		memcpy(result[k], fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
		if (k == 1)
			CHECK(memcmp(result[0], result[1], sizeof(double) * 3 * (size_t)n) == 0);
		fmDestroyWorld(world);
	}
	free(result[0]);
	free(result[1]);
}

// Bad sets are refused with a reason, and the previous set stays; count 0 clears.
TEST(bad_targets_are_refused)
{
	fmWorldId world;
	fmBodyId body = makeCube(&world, fm_implicit, 1.0);
	if (!fmBody_IsValid(body))
		return;
	int n = fmBody_GetVertexCount(body);
	int vertex[2] = {0, 1};
	fmVec3 p[2] = {{0, 0, 0}, {0.1, 0, 0}};
	CHECK_INT(fmBody_SetTargets(body, vertex, p, 2, 10.0), fm_ok);
	int bad = n;
	CHECK_INT(fmBody_SetTargets(body, &bad, p, 1, 10.0), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "vertex index");
	fmVec3 nan = {NAN, 0, 0};
	CHECK_INT(fmBody_SetTargets(body, vertex, &nan, 1, 10.0), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "finite position");
	fmVec3 far = {2e9, 0, 0};
	CHECK_INT(fmBody_SetTargets(body, vertex, &far, 1, 10.0), fm_errParameter);
	CHECK_INT(fmBody_SetTargets(body, vertex, p, 1, -1.0), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "stiffness");
	CHECK_INT(fmBody_SetTargets(body, vertex, p, 1, INFINITY), fm_errParameter);
	CHECK_INT(fmBody_SetTargets(body, vertex, p, -1, 10.0), fm_errParameter);
	CHECK_INT(fmBody_SetTargets(body, NULL, NULL, 3, 10.0), fm_errParameter);
	CHECK_INT(fmBody_GetTargetCount(body), 2); // kept through the errors
	CHECK_INT(fmBody_SetTargets(body, NULL, NULL, 0, 0.0), fm_ok);
	CHECK_INT(fmBody_GetTargetCount(body), 0);
	fmDestroyWorld(world);
}
