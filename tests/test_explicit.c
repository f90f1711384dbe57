// Explicit integration: energy behaviour without damping, and the bouncy house end to end.
#include "support.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static double totalEnergy(fmBodyId body)
{
	fmBodyStats s = fmBody_GetStats(body);
	return s.kineticEnergy + s.elasticEnergy;
}

// Symplectic Euler conserves a shadow energy: with no damping, gravity or floor the total
// energy oscillates in a narrow band around its start value instead of drifting.
TEST(undamped_energy_stays_in_a_band)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 3, 2, 2, fmMakeVec3(1.5, 1, 1),
	                              fmMakeMaterial(fm_stvk, 1e5, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
	{
		CHECK(0);
		return;
	}
	// Initial stretch along x by 5%.
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
		x[3 * i] *= 1.05;
	fmBody_SetPositions(body, x);
	free(x);
	double e0 = totalEnergy(body);
	CHECK(e0 > 0.0);
	// The measured energy (velocities half a step off the positions) deviates from the
	// conserved shadow energy by O(dt omega); at 2% of the stability limit that is < 1%.
	double dt = 0.02 * fmWorld_EstimateExplicitStep(world);
	double lo = e0, hi = e0, firstMean = 0.0, lastMean = 0.0;
	for (int frame = 0; frame < 500; ++frame)
	{
		CHECK_INT(fmWorld_Step(world, 10 * dt, 10), fm_ok);
		double e = totalEnergy(body);
		lo = fmin(lo, e);
		hi = fmax(hi, e);
		firstMean += frame < 100 ? e / 100 : 0.0;
		lastMean += frame >= 400 ? e / 100 : 0.0;
	}
	printf("  energy band over 5000 steps: [%.6g, %.6g] J around %.6g J (%.3f%%), drift %.3g%%\n",
	       lo, hi, e0, 100.0 * (hi - lo) / e0, 100.0 * (lastMean - firstMean) / e0);
	CHECK(fabs(lastMean - firstMean) < 0.005 * e0);
	CHECK((hi - lo) < 0.02 * e0);
	fmDestroyWorld(world);
}

// The house falls, touches the floor, bounces, comes to rest on it; never sinks below it.
TEST(bouncy_house_falls_bounces_and_rests)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeHouse(&world, NULL, NULL);
	CHECK(fmBody_IsValid(body));
	if (!fmBody_IsValid(body))
		return;
	CHECK_INT(fmBody_GetVertexCount(body), 400);
	CHECK_INT(fmBody_GetTetCount(body), 1389);
	double startY = fmBody_GetStats(body).centerOfMass.y;
	int touchFrame = -1, bounceFrame = -1;
	double lowest = 0.0;
	for (int frame = 0; frame < 400; ++frame) // 12 s of 10 x 3 ms
	{
		fmResult r = fmWorld_Step(world, 0.03, 10);
		CHECK_INT(r, fm_ok);
		if (r != fm_ok)
			break;
		fmBodyStats s = fmBody_GetStats(body);
		CHECK(isfinite(s.kineticEnergy) && isfinite(s.centerOfMass.y));
		lowest = fmin(lowest, s.lowestY);
		const double* v = fmTestVelocities(body);
		const double* m = fmBody_GetMasses(body);
		double momentumY = 0.0;
		for (int i = 0; i < 400; ++i)
			momentumY += m[i] * v[3 * i + 1];
		if (touchFrame < 0 && s.lowestY <= -3.0 + 1e-9)
			touchFrame = frame;
		if (touchFrame >= 0 && bounceFrame < 0 && momentumY > 0.0)
			bounceFrame = frame;
	}
	fmBodyStats end = fmBody_GetStats(body);
	printf(
	    "  touched at frame %d, rebound at frame %d, lowest y %.6f, end: com y %.4f (start %.4f), "
	    "KE %.3g J, inverted %d\n",
	    touchFrame, bounceFrame, lowest, end.centerOfMass.y, startY, end.kineticEnergy,
	    end.invertedTets);
	CHECK(touchFrame > 0);
	CHECK(bounceFrame > touchFrame);
	CHECK(lowest >= -3.0 - 1e-9);
	CHECK(end.kineticEnergy < 1e-3);
	CHECK_NEAR(end.lowestY, -3.0, 1e-3);
	CHECK_INT(end.invertedTets, 0);

	// The seeds' space-bar jump, stronger: the whole house leaves the floor.
	fmBody_ApplyImpulse(body, fmMakeVec3(0, 3.0, 0));
	double highest = -3.0;
	for (int frame = 0; frame < 20; ++frame)
	{
		CHECK_INT(fmWorld_Step(world, 0.03, 10), fm_ok);
		highest = fmax(highest, fmBody_GetStats(body).lowestY);
	}
	printf("  after the impulse the lowest vertex rose to y = %.4f\n", highest);
	CHECK(highest > -3.0 + 0.1);
	fmDestroyWorld(world);
}

// Pinned vertices never move; everything else hangs below them.
TEST(pinned_vertices_stay)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 4, 1, 1, fmMakeVec3(2, 0.5, 0.5),
	                              fmMakeMaterial(fm_stvk, 2e5, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
	{
		CHECK(0);
		return;
	}
	fmWorld_SetGravity(world, fmMakeVec3(0, -9.8, 0));
	int pinned = fmBody_PinBox(body, fmMakeVec3(-1, -1, -1), fmMakeVec3(1e-9, 1, 1));
	CHECK_INT(pinned, 4);
	CHECK_INT(fmBody_PinBox(body, fmMakeVec3(10, 10, 10), fmMakeVec3(11, 11, 11)), 0);
	int n = fmBody_GetVertexCount(body);
	double* rest = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(rest, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	double dt = 0.5 * fmWorld_EstimateExplicitStep(world);
	for (int frame = 0; frame < 200; ++frame)
		CHECK_INT(fmWorld_Step(world, 10 * dt, 10), fm_ok);
	const double* x = fmTestPositions(body);
	double tipDrop = 0.0;
	for (int i = 0; i < n; ++i)
	{
		if (fmBody_IsPinned(body, i))
			CHECK(memcmp(x + 3 * i, rest + 3 * i, 3 * sizeof(double)) == 0);
		else
			tipDrop = fmax(tipDrop, rest[3 * i + 1] - x[3 * i + 1]);
	}
	CHECK(tipDrop > 1e-4);
	free(rest);
	fmDestroyWorld(world);
}

// Coulomb floor: a block sliding on the floor decelerates at mu g, as a rigid block would.
TEST(coulomb_floor_decelerates_at_mu_g)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 2, 1, 2, fmMakeVec3(0.4, 0.1, 0.4),
	                              fmMakeMaterial(fm_corotated, 1e6, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
	{
		CHECK(0);
		return;
	}
	fmFloorDef floor = fmDefaultFloorDef();
	floor.friction = fm_floorCoulomb;
	floor.frictionCoefficient = 0.4;
	CHECK_INT(fmWorld_SetFloor(world, &floor), fm_ok);
	CHECK_INT(fmWorld_SetGravity(world, fmMakeVec3(0, -9.8, 0)), fm_ok);
	fmBody_ApplyImpulse(body, fmMakeVec3(2.0, 0, 0));
	double dt = 0.5 * fmWorld_EstimateExplicitStep(world);
	double t = 0.0, v0 = 2.0;
	// Slide for 0.3 s: v should drop by mu g t.
	while (t < 0.3)
	{
		CHECK_INT(fmWorld_Step(world, dt, 1), fm_ok);
		t += dt;
	}
	const double* v = fmTestVelocities(body);
	const double* m = fmBody_GetMasses(body);
	double p = 0.0, mass = 0.0;
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
	{
		p += m[i] * v[3 * i];
		mass += m[i];
	}
	double expected = v0 - 0.4 * 9.8 * t;
	printf("  mean vx after %.3f s: %.4f m/s, rigid-block Coulomb %.4f m/s\n", t, p / mass,
	       expected);
	CHECK_NEAR(p / mass, expected, 0.05 * v0);
	fmDestroyWorld(world);
}
