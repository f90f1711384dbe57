// The C API's contract: ids never alias (stale ids from destroyed worlds and bodies stay
// invalid through any number of create/destroy cycles), body defs are validated for everything
// fmCreateBody relies on, every public call checks its arguments (an assert through the hook in
// debug builds, a safe result in every build), and bodies beyond the memory budget are refused.
#include "core.h"
#include "test.h"
#include "world.h"

#include <femto/femto.h>
#include <stdint.h>
#include <stdlib.h>

// FM_ASSERT reaches the hook only in builds with asserts (base.h).
#if !defined(NDEBUG) || defined(FEMTO_ENABLE_ASSERT)
#define API_ASSERTS_ON 1
#else
#define API_ASSERTS_ON 0
#endif

static int s_asserts;
static char s_lastAssert[256];
static fmAssertFcn* s_previousAssert;

static int recordAssert(const char* condition, const char* fileName, int lineNumber)
{
	snprintf(s_lastAssert, sizeof s_lastAssert, "%s at %s:%d", condition, fileName, lineNumber);
	++s_asserts;
	return 0;
}

// Route asserts to the recorder (the runner's hook counts them as failures).
static void recordAssertsBegin(void)
{
	s_previousAssert = fmGetAssertFcn();
	fmSetAssertFcn(recordAssert);
	s_asserts = 0;
	s_lastAssert[0] = 0;
}

// Restore the runner's hook; returns the asserts recorded since recordAssertsBegin().
static int recordAssertsEnd(void)
{
	fmSetAssertFcn(s_previousAssert);
	return s_asserts;
}

// @p count asserts were recorded: at least one where asserts are compiled in, none otherwise.
#define CHECK_ASSERTED(count)                                                                      \
	do                                                                                             \
	{                                                                                              \
		int n_ = (count);                                                                          \
		if (API_ASSERTS_ON ? n_ < 1 : n_ != 0)                                                     \
			FAIL_AT("expected %s asserts, got %d", API_ASSERTS_ON ? ">= 1" : "0", n_);             \
	} while (0)

static const double s_tetNodes[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const int s_tetTets[4] = {0, 1, 2, 3};

// A one-tet mesh on static arrays (the caller may point them elsewhere).
static fmTetMesh oneTetMesh(void)
{
	fmTetMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	mesh.nodeCount = 4;
	mesh.positions = (double*)s_tetNodes;
	mesh.tetCount = 1;
	mesh.tets = (int*)s_tetTets;
	return mesh;
}

static fmBodyId makeTetBody(fmWorldId world)
{
	fmTetMesh mesh = oneTetMesh();
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmBodyId body;
	memset(&body, 0, sizeof body);
	fmCreateBody(world, &def, &body, NULL);
	return body;
}

// ---- ids --------------------------------------------------------------------------------------

TEST(stale_body_id_of_a_destroyed_world_does_not_reach_the_next_world)
{
	fmWorldDef def = fmDefaultWorldDef();
	fmWorldId a = fmCreateWorld(&def);
	fmBodyId old = makeTetBody(a);
	CHECK(fmBody_IsValid(old));
	fmDestroyWorld(a);
	CHECK(!fmBody_IsValid(old));

	fmWorldId b = fmCreateWorld(&def);
	fmBodyId body = makeTetBody(b);
	CHECK(fmBody_IsValid(body));
	CHECK(!fmWorld_IsValid(a));
	CHECK(!fmBody_IsValid(old));
	recordAssertsBegin();
	fmDestroyBody(old); // a programmer error: asserts, and must not touch world B's body
	CHECK_INT(fmBody_GetVertexCount(old), 0);
	CHECK_ASSERTED(recordAssertsEnd());
	CHECK(fmBody_IsValid(body));
	CHECK_INT(fmBody_GetVertexCount(body), 4);
	fmDestroyWorld(b);
}

TEST(ids_never_alias_over_seventy_thousand_create_destroy_cycles)
{
	// 16-bit generations wrap after 65,536 cycles of a slot.
	fmWorldDef def = fmDefaultWorldDef();
	def.maxBodies = 1;
	fmWorldId firstWorld = fmCreateWorld(&def);
	fmBodyId firstBody = makeTetBody(firstWorld);
	fmDestroyBody(firstBody);
	fmBodyId secondBody = makeTetBody(firstWorld); // same slot, next generation
	CHECK(fmBody_IsValid(secondBody));
	CHECK(!fmBody_IsValid(firstBody));
	fmDestroyWorld(firstWorld);
	int aliased = 0, failed = 0;
	for (int cycle = 0; cycle < 70000; ++cycle)
	{
		fmWorldId world = fmCreateWorld(&def);
		fmBodyId body = makeTetBody(world);
		failed += !fmBody_IsValid(body);
		aliased +=
		    fmWorld_IsValid(firstWorld) || fmBody_IsValid(firstBody) || fmBody_IsValid(secondBody);
		fmDestroyBody(body);
		for (int again = 0; again < 1 && cycle % 7 == 0; ++again)
		{
			// Body slots cycle within one world as well.
			body = makeTetBody(world);
			aliased += fmBody_IsValid(firstBody) || fmBody_IsValid(secondBody);
			fmDestroyBody(body);
		}
		fmDestroyWorld(world);
	}
	CHECK_INT(failed, 0);
	CHECK_INT(aliased, 0);
}

TEST(a_body_slot_is_retired_before_its_generation_wraps)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.maxBodies = 2;
	fmWorldId world = fmCreateWorld(&def);
	fmWorld* w = fmGetWorld(world);
	CHECK(w != NULL);
	if (w == NULL)
		return;
	w->bodies[0].generation = UINT32_MAX - 1;
	fmBodyId last = makeTetBody(world); // takes generation UINT32_MAX
	CHECK_INT(last.index1, 1);
	CHECK(fmBody_IsValid(last));
	fmDestroyBody(last);
	fmBodyId next = makeTetBody(world); // slot 1 is retired: slot 2
	CHECK_INT(next.index1, 2);
	CHECK(!fmBody_IsValid(last));
	fmDestroyBody(next);
	fmBodyId none;
	fmTetMesh mesh = oneTetMesh();
	fmBodyDef bodyDef = fmDefaultBodyDef();
	bodyDef.mesh = &mesh;
	CHECK_INT(fmCreateBody(world, &bodyDef, &none, NULL), fm_ok); // slot 2 again
	CHECK_INT(none.index1, 2);
	fmDestroyWorld(world);
}

TEST(null_ids_are_invalid)
{
	fmWorldId world;
	fmBodyId body;
	memset(&world, 0, sizeof world);
	memset(&body, 0, sizeof body);
	CHECK(!fmWorld_IsValid(world));
	CHECK(!fmBody_IsValid(body));
	fmWorldDef def = fmDefaultWorldDef();
	fmWorldId live = fmCreateWorld(&def);
	fmBodyId liveBody = makeTetBody(live);
	CHECK(fmBody_IsValid(liveBody));
	body.world0 = liveBody.world0;
	body.worldGeneration = liveBody.worldGeneration;
	body.generation = liveBody.generation;
	CHECK(!fmBody_IsValid(body)); // index1 == 0 is null whatever the rest says
	fmDestroyWorld(live);
}
