// The game loop's fixed step (src/world/step.c): fmWorld_Advance steps whole frames of the
// accumulated real time and no more than maxFrames, the same bits as the frames stepped by hand;
// the interpolated copies lie on the straight line between the last two frames (positions and
// render meshes); a teleport, a restored snapshot or a frame stepped without the clock leaves
// nothing to interpolate from; bad clocks are refused.
#include "support.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static fmBodyId dropBox(int* failures_, fmWorldId* world)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.floor.height = 0.0;
	*world = fmCreateWorld(&def);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(0.0, 0.5, 0.0), fmMakeVec3(0.4, 0.9, 0.4), &mesh),
	          fm_ok);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	fmBodyId body;
	CHECK_INT(fmCreateBody(*world, &bdef, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	return body;
}

TEST(advance_steps_the_whole_frames_the_time_holds)
{
	fmWorldId byClock, byHand;
	fmBodyId a = dropBox(failures_, &byClock), b = dropBox(failures_, &byHand);
	fmFixedStep clock = fmDefaultFixedStep();
	clock.substeps = 8;
	// Uneven real frames (a game's): 8 rounds of 0.125 s, then 0.01 s: 1.01 s in all, 60 whole
	// frames of 1/60 s and 0.01 s left over.
	const double pieces[6] = {0.007, 0.031, 0.016, 0.05, 0.0, 0.021};
	int stepped = 0;
	for (int k = 0; k < 49; ++k)
	{
		int frames = 0;
		CHECK_INT(fmWorld_Advance(byClock, &clock, k < 48 ? pieces[k % 6] : 0.01, &frames), fm_ok);
		CHECK(frames <= clock.maxFrames);
		stepped += frames;
	}
	printf("  1.01 s of real time in 49 uneven pieces: %d frames, %.4f s left (alpha %.3f)\n",
	       stepped, clock.accumulator, clock.alpha);
	CHECK_INT(stepped, 60);
	CHECK_NEAR(clock.accumulator, 0.01, 1e-12);
	CHECK_NEAR(clock.alpha, 0.6, 1e-10);
	for (int f = 0; f < 60; ++f)
		CHECK_INT(fmWorld_Step(byHand, 1.0 / 60.0, 8), fm_ok);
	int n = fmBody_GetVertexCount(a);
	CHECK(memcmp(fmTestPositions(a), fmTestPositions(b), sizeof(double) * 3 * (size_t)n) == 0);
	// A hitch of a whole second steps maxFrames and drops the rest: the game slows down.
	int frames = 0;
	CHECK_INT(fmWorld_Advance(byClock, &clock, 1.0, &frames), fm_ok);
	CHECK_INT(frames, 4);
	CHECK(clock.accumulator >= 0.0 && clock.accumulator < clock.frameTime);
	fmDestroyWorld(byClock);
	fmDestroyWorld(byHand);
}

TEST(interpolated_copies_lie_between_the_last_two_frames)
{
	fmWorldId world;
	fmBodyId body = dropBox(failures_, &world);
	const double v[9] = {0.1, 0.6, 0.1, 0.3, 0.6, 0.1, 0.1, 0.8, 0.3};
	const int tri[3] = {0, 1, 2};
	CHECK_INT(fmBody_SetRenderMesh(body, v, 3, tri, 1, NULL), fm_ok);
	fmFixedStep clock = fmDefaultFixedStep();
	int n = fmBody_GetVertexCount(body), frames = 0;
	float* now = malloc(sizeof(float) * 3 * (size_t)n);
	float* got = malloc(sizeof(float) * 3 * (size_t)n);
	// Before any advance: the positions now, whatever alpha.
	CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, 0.3, got, n), fm_ok);
	CHECK_INT(fmBody_CopyPositionsFloat(body, now, n), fm_ok);
	CHECK(memcmp(got, now, sizeof(float) * 3 * (size_t)n) == 0);
	CHECK_INT(fmWorld_Advance(world, &clock, 0.1, &frames), fm_ok);
	double before[3 * 64];
	CHECK(n <= 64);
	memcpy(before, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	CHECK_INT(fmWorld_Advance(world, &clock, 1.0 / 60.0, &frames), fm_ok);
	CHECK_INT(frames, 1);
	const double* after = fmTestPositions(body);
	const double alphas[3] = {0.0, 0.25, 1.0};
	double worst = 0.0;
	for (int k = 0; k < 3; ++k)
	{
		CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, alphas[k], got, n), fm_ok);
		for (int i = 0; i < 3 * n; ++i)
			worst = fmax(worst, fabs(got[i] - (before[i] + alphas[k] * (after[i] - before[i]))));
	}
	printf("  interpolated positions off the line by at most %.2e m (float rounding)\n", worst);
	CHECK(worst < 1e-6);
	// The render mesh of the interpolated positions: its vertex 0 (bound in one tet) moved a
	// quarter of its frame's motion.
	float r0[9], r1[9], rq[9], normals[9];
	CHECK_INT(fmBody_CopyInterpolatedRenderPositionsFloat(body, 0.0, r0, NULL, 3), fm_ok);
	CHECK_INT(fmBody_CopyInterpolatedRenderPositionsFloat(body, 1.0, r1, NULL, 3), fm_ok);
	CHECK_INT(fmBody_CopyInterpolatedRenderPositionsFloat(body, 0.25, rq, normals, 3), fm_ok);
	float nowRender[9];
	CHECK_INT(fmBody_CopyRenderPositionsFloat(body, nowRender, NULL, 3), fm_ok);
	CHECK(memcmp(r1, nowRender, sizeof r1) == 0);
	CHECK(r0[1] > r1[1] + 1e-4); // it was falling
	for (int i = 0; i < 9; ++i)
		CHECK_NEAR(rq[i], r0[i] + 0.25 * (r1[i] - r0[i]), 1e-6);
	CHECK_NEAR(normals[0] * normals[0] + normals[1] * normals[1] + normals[2] * normals[2], 1.0,
	           1e-6);
	// A teleport: nothing to interpolate from (no streak across the jump).
	// fmBody_SetPositions takes the user's numbering, as the copies give it.
	double user[3 * 64];
	CHECK_INT(fmBody_CopyPositions(body, user, n), fm_ok);
	for (int i = 0; i < 3 * n; i += 3)
		user[i] += 5.0;
	fmBody_SetPositions(body, user);
	CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, 0.0, got, n), fm_ok);
	for (int i = 0; i < 3 * n; ++i)
		CHECK_NEAR(got[i], user[i], 1e-6);
	// A restored snapshot, and a frame stepped without the clock: the positions now.
	size_t size = fmWorld_GetSnapshotSize(world);
	void* saved = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, saved, size, NULL), fm_ok);
	CHECK_INT(fmWorld_Advance(world, &clock, 1.0 / 60.0, &frames), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(world, saved, size), fm_ok);
	CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, 0.0, got, n), fm_ok);
	CHECK_INT(fmBody_CopyPositionsFloat(body, now, n), fm_ok);
	CHECK(memcmp(got, now, sizeof(float) * 3 * (size_t)n) == 0);
	CHECK_INT(fmWorld_Advance(world, &clock, 1.0 / 60.0, &frames), fm_ok);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, 0.0, got, n), fm_ok);
	CHECK_INT(fmBody_CopyPositionsFloat(body, now, n), fm_ok);
	CHECK(memcmp(got, now, sizeof(float) * 3 * (size_t)n) == 0);
	free(saved);
	// Out of range, refused.
	CHECK_INT(fmBody_CopyInterpolatedPositionsFloat(body, 1.5, got, n), fm_errParameter);
	CHECK_INT(fmBody_CopyInterpolatedRenderPositionsFloat(body, -0.1, r0, NULL, 3),
	          fm_errParameter);
	free(now);
	free(got);
	fmDestroyWorld(world);
}

TEST(bad_clocks_are_refused)
{
	fmWorldId world;
	fmBodyId body = dropBox(failures_, &world);
	(void)body;
	fmFixedStep clock = fmDefaultFixedStep();
	int frames = -1;
	CHECK_INT(fmWorld_Advance(world, &clock, -0.01, &frames), fm_errParameter);
	CHECK_INT(frames, 0);
	CHECK(strstr(fmWorld_GetLastError(world)->message, "elapsed") != NULL);
	CHECK_INT(fmWorld_Advance(world, &clock, NAN, NULL), fm_errParameter);
	CHECK_INT(fmWorld_Advance(world, &clock, INFINITY, NULL), fm_errParameter);
	fmFixedStep bad = clock;
	bad.frameTime = 0.0;
	CHECK_INT(fmWorld_Advance(world, &bad, 0.1, NULL), fm_errParameter);
	bad = clock;
	bad.maxFrames = 0;
	CHECK_INT(fmWorld_Advance(world, &bad, 0.1, NULL), fm_errParameter);
	bad = clock;
	bad.substeps = 1 << 16; // substeps of 0.25 ms: fine; of 2.5e-13 s below, refused
	bad.frameTime = 1e-8;
	CHECK_INT(fmWorld_Advance(world, &bad, 0.1, NULL), fm_errParameter);
	bad = clock;
	bad.accumulator = 1.0;
	CHECK_INT(fmWorld_Advance(world, &bad, 0.1, NULL), fm_errParameter);
	fmFixedStep unmade;
	memset(&unmade, 0, sizeof unmade);
	unmade.frameTime = 0.01;
	unmade.substeps = 1;
	unmade.maxFrames = 1;
	CHECK_INT(fmWorld_Advance(world, &unmade, 0.1, NULL), fm_errParameter);
	CHECK(strstr(fmWorld_GetLastError(world)->message, "fmDefaultFixedStep") != NULL);
	fmWorldId stale = world;
	fmDestroyWorld(world);
	CHECK_INT(fmWorld_Advance(stale, &clock, 0.1, NULL), fm_errInvalidId);
}
