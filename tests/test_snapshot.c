// Snapshots: save a world, run it on, restore, run again: the same bits. Changes made after the
// save (material, gravity, pins, impulses) are undone by the restore; a snapshot of other bodies
// or a truncated one is refused and changes nothing.
#include "support.h"
#include "test.h"

#include "body.h"
#include "solver_cache.h"

#include <stdlib.h>
#include <string.h>

// Positions and velocities of every body, concatenated (caller frees).
static double* stateOf(fmBodyId* bodies, int count, size_t* length)
{
	size_t total = 0;
	for (int b = 0; b < count; ++b)
		total += 6 * (size_t)fmBody_GetVertexCount(bodies[b]);
	double* out = malloc(sizeof(double) * total);
	size_t at = 0;
	for (int b = 0; b < count; ++b)
	{
		size_t n3 = 3 * (size_t)fmBody_GetVertexCount(bodies[b]);
		memcpy(out + at, fmTestPositions(bodies[b]), sizeof(double) * n3);
		memcpy(out + at + n3, fmTestVelocities(bodies[b]), sizeof(double) * n3);
		at += 2 * n3;
	}
	*length = total;
	return out;
}

// Run @p frames frames of the world; with @p disturb, change what a restore must undo first.
static void runOn(int* failures_, fmWorldId world, fmBodyId* bodies, int count, int frames,
                  double frame, int substeps, bool disturb)
{
	if (disturb)
	{
		fmMaterial softer = fmMakeMaterialLame(fm_neoHookean, 8000.0, 2000.0);
		CHECK_INT(fmBody_SetMaterial(bodies[0], &softer, NULL), fm_ok);
		CHECK_INT(fmWorld_SetGravity(world, fmMakeVec3(1.0, -20.0, 0.0)), fm_ok);
		fmBody_SetPinned(bodies[count - 1], 3, true);
		fmBody_ApplyImpulse(bodies[0], fmMakeVec3(0.0, 2.0, 0.0));
	}
	for (int k = 0; k < frames; ++k)
		CHECK_INT(fmWorld_Step(world, frame, substeps), fm_ok);
}

static void checkContinuesBitIdentically(int* failures_, fmIntegrator integrator)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	fmBodyDef bdef = fmDefaultBodyDef(); // the seeds' house material: stable at their 3 ms
	if (integrator == fm_implicit)
		bdef.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	fmWorldId world;
	fmBodyId bodies[2];
	bodies[0] = fmTestMakeHouse(&world, &wdef, &bdef);
	fmTetMesh box;
	CHECK_INT(fmMakeBoxMesh(3, 2, 2, fmMakeVec3(-3, 0, -1), fmMakeVec3(-1, 1, 1), &box), fm_ok);
	bdef.mesh = &box;
	bdef.forceModel = fm_massSpring;
	CHECK_INT(fmCreateBody(world, &bdef, &bodies[1], NULL), fm_ok);
	fmFreeTetMesh(&box);
	double frame = integrator == fm_implicit ? 1.0 / 60.0 : 0.03;
	int substeps = integrator == fm_implicit ? 1 : 10;

	runOn(failures_, world, bodies, 2, 30, frame, substeps, false); // falling, landing
	size_t size = fmWorld_GetSnapshotSize(world), written = 0;
	void* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size - 1, &written), fm_errLimit);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, &written), fm_ok);
	CHECK(written == size);

	runOn(failures_, world, bodies, 2, 20, frame, substeps, false);
	size_t length;
	double* first = stateOf(bodies, 2, &length);
	fmStepStats firstStats = fmWorld_GetStepStats(world);

	// Disturb, run, restore, run again: the same bits as the first continuation.
	runOn(failures_, world, bodies, 2, 5, frame, substeps, true);
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
	runOn(failures_, world, bodies, 2, 20, frame, substeps, false);
	size_t length2;
	double* second = stateOf(bodies, 2, &length2);
	CHECK(length == length2);
	CHECK(memcmp(first, second, sizeof(double) * length) == 0);
	fmStepStats secondStats = fmWorld_GetStepStats(world);
	CHECK_INT(secondStats.newtonIterations, firstStats.newtonIterations);
	CHECK_INT(secondStats.cgIterations, firstStats.cgIterations);
	printf("  %s: %zu-byte snapshot, continuation bit-identical: %s\n",
	       integrator == fm_implicit ? "implicit" : "explicit", size,
	       memcmp(first, second, sizeof(double) * length) == 0 ? "yes" : "NO");

	// A truncated snapshot, or one of other bodies, is refused and changes nothing.
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size / 2), fm_errParameter);
	double* untouched = stateOf(bodies, 2, &length2);
	CHECK(memcmp(second, untouched, sizeof(double) * length) == 0);
	fmDestroyBody(bodies[1]);
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "bodies were created or destroyed");
	unsigned char junk[64] = {0};
	CHECK_INT(fmWorld_RestoreSnapshot(world, junk, sizeof junk), fm_errParameter);
	free(untouched);
	free(first);
	free(second);
	free(snapshot);
	fmDestroyWorld(world);
}

TEST(explicit_world_continues_bit_identically)
{
	checkContinuesBitIdentically(failures_, fm_explicit);
}

TEST(implicit_world_continues_bit_identically)
{
	checkContinuesBitIdentically(failures_, fm_implicit);
}

// A box resting on the floor at the game tolerance, in a world of its own.
static fmBodyId makeRestingBox(fmWorldId* world)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.tolerance = FM_TOLERANCE_GAME;
	wdef.floor.height = -1e-3;
	*world = fmCreateWorld(&wdef);
	fmTetMesh mesh;
	fmBodyId none = {0, 0, 0, 0};
	if (fmMakeBoxMesh(4, 2, 4, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0.5, 1), &mesh) != fm_ok)
		return none;
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

// The implicit solver's warm start (which first guess the last step took: a body at rest
// starts from x + h v; and when the other is tried again) is part of a snapshot, restored into a
// world whose solver state has drifted and into a fresh world that has taken no implicit step yet.
TEST(implicit_warm_start_is_saved)
{
	fmWorldId world, fresh;
	fmBodyId body = makeRestingBox(&world);
	CHECK(fmBody_IsValid(body));
	for (int frame = 0; frame < 60; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	fmImplicitCache* cache = fmGetBody(body)->implicitCache;
	CHECK(cache != NULL && cache->coasted);
	size_t size = fmWorld_GetSnapshotSize(world), written = 0;
	void* snapshot = malloc(size);
	cache->guessRecheck = 5; // as if the free flight had just lost clearly
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, &written), fm_ok);
	cache->coasted = false;
	cache->guessRecheck = 0;
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
	CHECK(cache->coasted);
	CHECK_INT(cache->guessRecheck, 5);

	fmBodyId twin = makeRestingBox(&fresh);
	CHECK(fmGetBody(twin)->implicitCache == NULL);
	CHECK_INT(fmWorld_RestoreSnapshot(fresh, snapshot, size), fm_ok);
	const fmImplicitCache* restored = fmGetBody(twin)->implicitCache;
	CHECK(restored != NULL && restored->coasted);
	CHECK_INT(restored != NULL ? restored->guessRecheck : -1, 5);
	// Both continue with the same bits.
	for (int frame = 0; frame < 10; ++frame)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		CHECK_INT(fmWorld_Step(fresh, 1.0 / 60.0, 1), fm_ok);
	}
	size_t n3 = 3 * (size_t)fmBody_GetVertexCount(body);
	CHECK(memcmp(fmGetBody(body)->x, fmGetBody(twin)->x, sizeof(double) * n3) == 0);
	free(snapshot);
	fmDestroyWorld(world);
	fmDestroyWorld(fresh);
}
