// The C API's contract: ids never alias (stale ids from destroyed worlds and bodies stay
// invalid through any number of create/destroy cycles), body defs are validated for everything
// fmCreateBody relies on, every public call checks its arguments (an assert through the hook in
// debug builds, a safe result in every build), and bodies beyond the memory budget are refused.
#include "core/core.h"
#include "support.h"
#include "test.h"
#include "world/world.h"

#include <femto/femto.h>
#include <fenv.h>
#include <stdint.h>
#include <stdlib.h>

// @p count asserts were recorded: at least one where asserts are compiled in, none otherwise.
#define CHECK_ASSERTED(count)                                                                      \
	do                                                                                             \
	{                                                                                              \
		int n_ = (count);                                                                          \
		if (FM_TEST_ASSERTS_ON ? n_ < 1 : n_ != 0)                                                 \
			FAIL_AT("expected %s asserts, got %d", FM_TEST_ASSERTS_ON ? ">= 1" : "0", n_);         \
	} while (0)

// One call that must be refused with an assert (where asserts are compiled in).
#define REFUSED(call)                                                                              \
	do                                                                                             \
	{                                                                                              \
		fmTestRecordAssertsBegin();                                                                \
		call;                                                                                      \
		CHECK_ASSERTED(fmTestRecordAssertsEnd());                                                  \
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
	fmTestRecordAssertsBegin();
	fmDestroyBody(old); // a programmer error: asserts, and must not touch world B's body
	CHECK_INT(fmBody_GetVertexCount(old), 0);
	CHECK_ASSERTED(fmTestRecordAssertsEnd());
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

// ---- body defs --------------------------------------------------------------------------------

// Validate and create both reject the def with @p expected and a message containing @p text.
static void checkMeshRejected(int* failures_, const fmTetMesh* mesh, fmResult expected,
                              const char* text)
{
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	CHECK_INT(fmBodyDef_Validate(&def, &diag), expected);
	CHECK_STR_CONTAINS(diag.message, text);
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body;
	memset(&body, 0xff, sizeof body);
	size_t before = fmGetAllocatedBytes();
	CHECK_INT(fmCreateBody(world, &def, &body, &diag), expected);
	CHECK_STR_CONTAINS(diag.message, text);
	CHECK_INT(body.index1, 0);
	CHECK_INT(fmGetAllocatedBytes(), before);
	fmDestroyWorld(world);
}

TEST(body_def_validation_covers_everything_create_relies_on)
{
	fmTetMesh mesh = oneTetMesh();
	mesh.positions = NULL;
	checkMeshRejected(failures_, &mesh, fm_errParameter, "positions");
	mesh = oneTetMesh();
	mesh.tets = NULL;
	checkMeshRejected(failures_, &mesh, fm_errParameter, "tets");
	mesh = oneTetMesh();
	mesh.nodeCount = 0;
	checkMeshRejected(failures_, &mesh, fm_errEmpty, "no tets");
	mesh = oneTetMesh();
	mesh.tetCount = -3;
	checkMeshRejected(failures_, &mesh, fm_errEmpty, "no tets");
	mesh = oneTetMesh();
	mesh.tetCount = FM_MAX_TETS + 1;
	checkMeshRejected(failures_, &mesh, fm_errLimit, "FM_MAX_TETS");
	mesh = oneTetMesh();
	mesh.nodeCount = 3; // tet 0 refers to node 3
	checkMeshRejected(failures_, &mesh, fm_errIndex, "node 3");
	mesh = oneTetMesh();
	mesh.firstIndex = 1 << 30; // the messages add it to indices
	checkMeshRejected(failures_, &mesh, fm_errParameter, "firstIndex");

	int tets[4] = {0, 1, 2, -1};
	mesh = oneTetMesh();
	mesh.tets = tets;
	checkMeshRejected(failures_, &mesh, fm_errIndex, "node -1");
	tets[3] = 1;
	checkMeshRejected(failures_, &mesh, fm_errIndex, "repeats");

	double positions[12];
	memcpy(positions, s_tetNodes, sizeof positions);
	mesh = oneTetMesh();
	mesh.positions = positions;
	positions[7] = NAN;
	checkMeshRejected(failures_, &mesh, fm_errRange, "node 2");
	positions[7] = INFINITY;
	checkMeshRejected(failures_, &mesh, fm_errRange, "finite");
	positions[7] = 2.0 * FM_MAX_COORDINATE;
	checkMeshRejected(failures_, &mesh, fm_errRange, "FM_MAX_COORDINATE");
	positions[7] = 0.0; // node 2 at the origin: on top of node 0
	checkMeshRejected(failures_, &mesh, fm_errDegenerate, "tet 0");

	// Masses the integrators would divide by zero with: a subnormal particle mass.
	fmBodyDef def = fmDefaultBodyDef();
	mesh = oneTetMesh();
	def.mesh = &mesh;
	def.particleMass = 1e-320;
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &def, &body, &diag), fm_errRange);
	CHECK_STR_CONTAINS(diag.message, "mass");
	fmDestroyWorld(world);
}

TEST(create_body_leaves_the_callers_mesh_untouched)
{
	// One negatively oriented tet: the body flips its own copy.
	const int inverted[4] = {0, 2, 1, 3};
	fmTetMesh mesh = oneTetMesh();
	mesh.tets = (int*)inverted;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	CHECK_INT(inverted[1], 2);
	const int* tets = fmBody_GetTets(body);
	CHECK(tets != NULL && tets[0] == 0 && tets[1] == 2 && tets[2] == 3 && tets[3] == 1);
	fmDestroyWorld(world);
}

// ---- argument checks --------------------------------------------------------------------------

TEST(every_call_with_a_stale_id_asserts_and_returns_a_safe_value)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body = makeTetBody(world);
	fmDestroyWorld(world);
	fmVec3 zero = fmMakeVec3(0, 0, 0);
	double buffer[12] = {0};
	fmTetMesh mesh = oneTetMesh();
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmFloorDef floor = worldDef.floor;
	fmMaterial material = fmDefaultBodyDef().material;
	fmDiagnostic diag;
	int triangles = -1;

	fmTestRecordAssertsBegin();
	fmDestroyWorld(world);
	int count = fmTestRecordAssertsEnd();
	CHECK_ASSERTED(count);
	REFUSED(CHECK_INT(fmWorld_Step(world, 0.01, 1), fm_errInvalidId));
	REFUSED(CHECK_INT(fmWorld_GetLastError(world)->result, fm_errInvalidId));
	REFUSED(CHECK_INT(fmWorld_GetStepStats(world).steps, 0));
	REFUSED(fmWorld_SetGravity(world, zero));
	REFUSED(fmWorld_SetFloor(world, &floor));
	REFUSED(fmWorld_SetIntegrator(world, fm_implicit));
	REFUSED(CHECK(fmWorld_EstimateExplicitStep(world) == 0.0));
	REFUSED(CHECK_INT(fmCreateBody(world, &def, NULL, &diag), fm_errInvalidId));
	REFUSED(fmDestroyBody(body));
	REFUSED(CHECK_INT(fmBody_GetVertexCount(body), 0));
	REFUSED(CHECK_INT(fmBody_GetTetCount(body), 0));
	REFUSED(CHECK_INT(fmBody_CopyPositions(body, buffer, 1), fm_errInvalidId));
	REFUSED(CHECK_INT(fmBody_CopyVelocitiesFloat(body, (float*)buffer, 1), fm_errInvalidId));
	REFUSED(fmBody_SetPositions(body, buffer));
	REFUSED(fmBody_SetVelocities(body, buffer));
	REFUSED(CHECK(fmBody_GetMasses(body) == NULL));
	REFUSED(CHECK(fmBody_GetTets(body) == NULL));
	REFUSED(CHECK(fmBody_GetSurface(body, &triangles) == NULL && triangles == 0));
	REFUSED(fmBody_ApplyImpulse(body, zero));
	REFUSED(fmBody_ApplyVertexImpulse(body, 0, zero));
	REFUSED(CHECK_INT(fmBody_PinBox(body, zero, zero), 0));
	REFUSED(fmBody_SetPinned(body, 0, true));
	REFUSED(fmBody_SetPinnedAxes(body, 0, 1u));
	REFUSED(CHECK(!fmBody_IsPinned(body, 0)));
	REFUSED(CHECK_INT(fmBody_GetStats(body).invertedTets, 0));
	REFUSED(CHECK_INT(fmBody_SetMaterial(body, &material, &diag), fm_errInvalidId));
	REFUSED(CHECK(fmBody_ComputeElasticForces(body, buffer) == 0.0));
#undef STALE
	CHECK(!fmBody_IsValid(body));
	CHECK(!fmWorld_IsValid(world));
}

TEST(bad_arguments_assert_and_leave_the_body_unchanged)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body = makeTetBody(world);
	double before[12], after[12];
	CHECK_INT(fmBody_CopyPositions(body, before, 4), fm_ok);
	fmVec3 nan3 = fmMakeVec3(0, NAN, 0), one = fmMakeVec3(1, 1, 1);
	fmFloorDef badFloor = worldDef.floor;
	badFloor.restitution = 2.0;
	fmMaterial material = fmDefaultBodyDef().material;
	REFUSED(CHECK(fmCreateWorld(NULL).index1 == 0));
	REFUSED(CHECK_INT(fmWorld_SetFloor(world, NULL), fm_errParameter));
	// A bad value (a slider gone wrong) is bad input, not a programmer error: a result code and
	// the world's last error, no assert.
	fmTestRecordAssertsBegin();
	CHECK_INT(fmWorld_SetGravity(world, nan3), fm_errParameter);
	CHECK_INT(fmWorld_SetFloor(world, &badFloor), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "floor");
	CHECK_INT(fmTestRecordAssertsEnd(), 0);
	REFUSED(fmWorld_SetIntegrator(world, (fmIntegrator)7));
	REFUSED(fmBody_SetPositions(body, NULL));
	REFUSED(fmBody_SetVelocities(body, NULL));
	REFUSED(fmBody_ApplyImpulse(body, nan3));
	REFUSED(fmBody_ApplyVertexImpulse(body, 4, one));
	REFUSED(fmBody_ApplyVertexImpulse(body, -1, one));
	REFUSED(fmBody_ApplyVertexImpulse(body, 0, nan3));
	REFUSED(CHECK_INT(fmBody_PinBox(body, nan3, one), 0));
	REFUSED(CHECK_INT(fmBody_PinBox(body, one, nan3), 0));
	REFUSED(fmBody_SetPinned(body, 4, true));
	REFUSED(fmBody_SetPinnedAxes(body, -1, 1u));
	REFUSED(fmBody_SetPinnedAxes(body, 0, 8u));
	REFUSED(CHECK(!fmBody_IsPinned(body, 99)));
	REFUSED(CHECK(fmBody_SetMaterial(body, NULL, NULL) != fm_ok));
	REFUSED(CHECK(fmBody_ComputeElasticForces(body, NULL) == 0.0));
	REFUSED(CHECK(fmEstimateBodyMemory(NULL) == 0));
#undef BAD
	// Infinite bounds are a half-space, not a mistake.
	fmVec3 everywhere = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	fmTestRecordAssertsBegin();
	CHECK_INT(fmBody_PinBox(body, fmScale(-1.0, everywhere), fmMakeVec3(INFINITY, -1.0, 5.0)), 0);
	CHECK_INT(fmTestRecordAssertsEnd(), 0);
	// Nothing changed: the world steps as before, the body is where it was, at rest.
	CHECK_INT(fmBody_CopyPositions(body, after, 4), fm_ok);
	CHECK(memcmp(before, after, sizeof before) == 0);
	CHECK(fmBody_GetStats(body).kineticEnergy == 0.0);
	CHECK(!fmBody_IsPinned(body, 0));
	fmStepStats none = fmWorld_GetStepStats(world);
	CHECK_INT(none.steps, 0);
	CHECK_INT(fmWorld_Step(world, 0.003, 1), fm_ok);
	CHECK_INT(fmBody_CopyPositions(body, after, 4), fm_ok);
	CHECK(after[1] < before[1]); // gravity is still (0, -9.8, 0)
	CHECK_INT(fmBody_SetMaterial(body, &material, NULL), fm_ok);
	fmDestroyWorld(world);
}

// ---- memory budget ----------------------------------------------------------------------------

TEST(memory_budget_is_validated)
{
	fmWorldDef def = fmDefaultWorldDef();
	CHECK(def.memoryBudget == FM_DEFAULT_MEMORY_BUDGET);
	CHECK(def.memoryBudget >= ((size_t)1 << 31));
	fmDiagnostic diag;
	def.memoryBudget = 0;
	CHECK_INT(fmWorldDef_Validate(&def, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "memoryBudget");
	CHECK(fmCreateWorld(&def).index1 == 0);
	def.memoryBudget = 1000; // less than the body table
	CHECK_INT(fmWorldDef_Validate(&def, &diag), fm_errLimit);
	CHECK_STR_CONTAINS(diag.message, "maxBodies");
	def.memoryBudget = SIZE_MAX;
	CHECK_INT(fmWorldDef_Validate(&def, &diag), fm_ok);
}

// The estimate against what the body and the implicit solver really allocate (@p strength: a
// tearing material's, with the default averaging length, or 0).
static void checkEstimate(int* failures_, int cells, fmForceModel forceModel, double stiffness,
                          double strength)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(cells, cells, cells, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh),
	          fm_ok);
	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.integrator = fm_implicit;
	worldDef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.forceModel = forceModel;
	def.rayleighStiffness = stiffness;
	def.material.fracture.strength = strength;
	size_t estimate = fmEstimateBodyMemory(&def);
	size_t before = fmGetAllocatedBytes();
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	CHECK_INT(fmWorld_Step(world, 0.01, 1), fm_ok);
	double used = (double)(fmGetAllocatedBytes() - before);
	double ratio = (double)estimate / used;
	if (!(ratio > 0.9 && ratio < 1.25))
		FAIL_AT("%d^3 cells, force model %d, strength %g: estimate %zu bytes, used %.0f (ratio "
		        "%.3f)",
		        cells, (int)forceModel, strength, estimate, used, ratio);
	fmDestroyWorld(world);
	fmFreeTetMesh(&mesh);
}

TEST(memory_estimate_is_close_to_what_a_body_and_its_solver_allocate)
{
	checkEstimate(failures_, 3, fm_fem, 0.0, 0.0);
	checkEstimate(failures_, 12, fm_fem, 0.0, 0.0);
	checkEstimate(failures_, 12, fm_fem, 0.01, 0.0);
	checkEstimate(failures_, 12, fm_fvm, 0.0, 0.0);
	checkEstimate(failures_, 12, fm_massSpring, 0.0, 0.0);
	checkEstimate(failures_, 12, fm_fem, 0.0, 1e9); // (the crack state; never tears here)
}

TEST(a_body_beyond_the_memory_budget_is_refused_before_allocating)
{
	// Counts only: the estimate reads no array, so a huge "mesh" costs nothing to describe.
	fmTetMesh huge = oneTetMesh();
	huge.nodeCount = 281 * 281 * 281;
	huge.tetCount = 6 * 280 * 280 * 280; // box:280,280,280, under FM_MAX_TETS
	fmBodyDef hugeDef = fmDefaultBodyDef();
	hugeDef.mesh = &huge;
	CHECK(fmEstimateBodyMemory(&hugeDef) > FM_DEFAULT_MEMORY_BUDGET);

	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(8, 8, 8, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	size_t estimate = fmEstimateBodyMemory(&def);
	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.maxBodies = 4;
	// Room for one body and its table, not for two.
	worldDef.memoryBudget = 4 * sizeof(fmBody) + estimate + estimate / 2;
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId first, second;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &def, &first, &diag), fm_ok);
	size_t before = fmGetAllocatedBytes();
	CHECK_INT(fmCreateBody(world, &def, &second, &diag), fm_errLimit);
	CHECK_INT(fmGetAllocatedBytes(), before);
	CHECK_INT(second.index1, 0);
	CHECK_STR_CONTAINS(diag.message, "MiB");
	CHECK_STR_CONTAINS(diag.message, "memoryBudget");
	char bytes[32];
	snprintf(bytes, sizeof bytes, "%zu bytes", estimate);
	CHECK_STR_CONTAINS(diag.message, bytes);
	// Destroying the first body gives its share back.
	fmDestroyBody(first);
	CHECK_INT(fmCreateBody(world, &def, &second, &diag), fm_ok);
	fmDestroyWorld(world);
	fmFreeTetMesh(&mesh);
}

// Mesh colliders count against the memory budget as bodies do (1,024 of them reached 2.8 GB
// with the budget untouched): 800-triangle grounds fill a 2 MiB budget, the next is refused
// before anything is allocated, a body no longer fits beside them, and destroying one gives its
// share back.
TEST(mesh_colliders_count_against_the_memory_budget)
{
	enum
	{
		n = 20
	};
	fmVec3 vertices[(n + 1) * (n + 1)];
	int triangles[6 * n * n], t = 0;
	for (int j = 0; j <= n; ++j)
		for (int i = 0; i <= n; ++i)
			vertices[j * (n + 1) + i] = fmMakeVec3(i * 0.2, 0.0, j * 0.2);
	for (int j = 0; j < n; ++j)
		for (int i = 0; i < n; ++i)
		{
			int a = j * (n + 1) + i, c = a + n + 1;
			const int quad[6] = {a, c, a + 1, a + 1, c, c + 1};
			memcpy(triangles + 6 * t++, quad, sizeof quad);
		}
	fmColliderDef ground = fmDefaultColliderDef();
	ground.shape = fm_shapeMesh;
	ground.vertices = vertices;
	ground.vertexCount = (n + 1) * (n + 1);
	ground.triangles = triangles;
	ground.triangleCount = 2 * n * n;
	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.maxBodies = 4;
	worldDef.memoryBudget = 2u << 20;
	fmWorldId world = fmCreateWorld(&worldDef);
	fmColliderId ids[64];
	fmDiagnostic diag;
	int made = 0;
	while (made < 64 && fmCreateCollider(world, &ground, &ids[made], &diag) == fm_ok)
		++made;
	printf("  %d grounds of 800 triangles fit in 2 MiB; then: %s\n", made, diag.message);
	CHECK(made >= 4 && made < 64);
	CHECK_INT(diag.result, fm_errLimit);
	CHECK_STR_CONTAINS(diag.message, "a mesh collider of 800 triangles needs about");
	CHECK_STR_CONTAINS(diag.message, "memory budget of 2.0 MiB");
	size_t before = fmGetAllocatedBytes();
	fmColliderId refused;
	CHECK_INT(fmCreateCollider(world, &ground, &refused, &diag), fm_errLimit);
	CHECK_INT(fmGetAllocatedBytes(), before);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(8, 8, 8, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, &diag), fm_errLimit);
	fmDestroyCollider(ids[made - 1]);
	CHECK_INT(fmCreateCollider(world, &ground, &ids[made - 1], &diag), fm_ok);
	fmFreeTetMesh(&mesh);
	fmDestroyWorld(world);
}

// The copy-out read-back: positions and velocities in the mesh's numbering, as doubles or
// floats; a stale id or NULL buffer is a programmer error, a small buffer a result code.
TEST(copy_out_gives_the_state_in_the_mesh_numbering)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body = makeTetBody(world);
	double velocities[12];
	for (int k = 0; k < 12; ++k)
		velocities[k] = 0.1 * k - 0.35 + 1e-9 / 3.0; // not floats: the float copy must round
	fmBody_SetVelocities(body, velocities);
	CHECK_INT(fmWorld_Step(world, 0.003, 1), fm_ok);
	double x[12], v[12];
	float xf[12], vf[12];
	CHECK_INT(fmBody_CopyPositions(body, x, 4), fm_ok);
	CHECK_INT(fmBody_CopyVelocities(body, v, 4), fm_ok);
	CHECK_INT(fmBody_CopyPositionsFloat(body, xf, 4), fm_ok);
	CHECK_INT(fmBody_CopyVelocitiesFloat(body, vf, 4), fm_ok);
	// One symplectic Euler step from the mesh's nodes: vertex i (of distinct velocities) moved by
	// h times its own new velocity, both read back in the mesh's order.
	for (int i = 0; i < 4; ++i)
	{
		CHECK_NEAR(x[3 * i], s_tetNodes[3 * i] + 0.003 * v[3 * i], 1e-12);
	}
	int mismatches = 0;
	for (int k = 0; k < 12; ++k)
		mismatches += xf[k] != (float)x[k] || vf[k] != (float)v[k];
	CHECK_INT(mismatches, 0);
	// A larger buffer is fine and only 3 n values are written.
	double larger[15];
	larger[12] = 42.0;
	CHECK_INT(fmBody_CopyPositions(body, larger, 5), fm_ok);
	CHECK(memcmp(larger, x, sizeof x) == 0 && larger[12] == 42.0);
	fmDestroyWorld(world);
}

TEST(copy_out_errors_are_located_and_leave_the_buffer)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body = makeTetBody(world);
	double small[9] = {7, 7, 7, 7, 7, 7, 7, 7, 7};
	float smallFloat[9] = {7, 7, 7, 7, 7, 7, 7, 7, 7};
	// Too small: bad input, no assert; the buffer is untouched and the last error says why.
	fmTestRecordAssertsBegin();
	CHECK_INT(fmBody_CopyPositions(body, small, 3), fm_errLimit);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "fmBody_CopyPositions");
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "3 vertices is too small");
	CHECK_INT(fmBody_CopyVelocitiesFloat(body, smallFloat, 0), fm_errLimit);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "fmBody_CopyVelocitiesFloat");
	CHECK_INT(fmBody_CopyVelocities(body, small, -1), fm_errLimit);
	CHECK_INT(fmBody_CopyPositionsFloat(body, smallFloat, 3), fm_errLimit);
	CHECK_INT(fmTestRecordAssertsEnd(), 0);
	int changed = 0;
	for (int k = 0; k < 9; ++k)
		changed += small[k] != 7.0 || smallFloat[k] != 7.0f;
	CHECK_INT(changed, 0);
	// NULL buffers: programmer errors.
	REFUSED(CHECK_INT(fmBody_CopyPositions(body, NULL, 4), fm_errParameter));
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "buffer is NULL");
	REFUSED(CHECK_INT(fmBody_CopyVelocitiesFloat(body, NULL, 4), fm_errParameter));
	// A destroyed body in a live world: asserted, and the world's last error says so.
	fmDestroyBody(body);
	double x[12];
	REFUSED(CHECK_INT(fmBody_CopyVelocities(body, x, 4), fm_errInvalidId));
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "invalid or destroyed body id");
	fmDestroyWorld(world);
}

// The float copy rounds to nearest whatever rounding mode the host left (fp_env.h).
TEST(float_copy_rounds_to_nearest_under_any_host_rounding)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body = makeTetBody(world);
	double v[12];
	for (int k = 0; k < 12; ++k)
		v[k] = (k % 2 ? 1.0 : -1.0) * (1.0 + 0.75 * 0x1p-23); // 3/4 of a float ulp beyond 1
	fmBody_SetVelocities(body, v);
	float nearest[12], towardZero[12];
	CHECK_INT(fmBody_CopyVelocitiesFloat(body, nearest, 4), fm_ok);
	int rounding = fegetround();
	fesetround(FE_TOWARDZERO);
	fmResult r = fmBody_CopyVelocitiesFloat(body, towardZero, 4);
	fesetround(rounding);
	CHECK_INT(r, fm_ok);
	CHECK(memcmp(nearest, towardZero, sizeof nearest) == 0);
	CHECK(nearest[1] == 1.0f + 0x1p-23f && nearest[0] == -1.0f - 0x1p-23f);
	fmDestroyWorld(world);
}
