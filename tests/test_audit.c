// The contact audit (fmWorld_AuditContact): analytic cases with known answers.
#include "support.h"
#include "test.h"

#include "core/timer.h"

#include <stdlib.h>

// A box body of nx * ny * nz cubes spanning [lo, hi] in @p world (no gravity).
static fmBodyId auditBox(int* failures_, fmWorldId world, int nx, int ny, int nz, fmVec3 lo,
                         fmVec3 hi, bool selfCollision)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(nx, ny, nz, lo, hi, &mesh) != fm_ok)
		return none;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.selfCollision = selfCollision;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &def, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

static fmContactAudit audit(int* failures_, fmWorldId world)
{
	fmContactAudit a;
	memset(&a, 0, sizeof a);
	CHECK_INT(fmWorld_AuditContact(world, &a), fm_ok);
	return a;
}

// No gravity, no floor, no contact between the bodies: the audit's cases are made overlapping
// on purpose (a world with body contact refuses such bodies).
static fmWorldId freeWorld(void)
{
	fmWorldDef def = fmTestFreeWorldDef();
	def.contact.bodies = false;
	return fmCreateWorld(&def);
}

#define CHECK_CLEAN(a)                                                                             \
	do                                                                                             \
	{                                                                                              \
		CHECK_INT((a).crossings, 0);                                                               \
		CHECK_INT((a).selfCrossings, 0);                                                           \
		CHECK_INT((a).verticesInside, 0);                                                          \
		CHECK_INT((a).invertedTets, 0);                                                            \
		CHECK_INT((a).firstCrossing.body.index1, 0);                                               \
		CHECK_INT((a).firstInside.body.index1, 0);                                                 \
	} while (0)

TEST(two_boxes_apart)
{
	fmWorldId world = freeWorld();
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), false);
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(1.5, 0, 0), fmMakeVec3(2.5, 1, 1), false);
	fmContactAudit a = audit(failures_, world);
	CHECK_INT(a.bodies, 2);
	CHECK_CLEAN(a);
	fmDestroyWorld(world);
}

// B = [0.75, 1.75] x [0.1, 0.9]^2 through A = [0, 1]^3, both of 2^3 cubes (vertices every half
// cell): B's face x = 0.75 has its 9 vertices inside A (the centre 0.25 deep), A's face x = 1 its
// centre inside B (0.25 deep).
TEST(box_pushed_through_another)
{
	fmWorldId world = freeWorld();
	fmBodyId a = auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1),
	                      false);
	fmBodyId b = auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0.75, 0.1, 0.1),
	                      fmMakeVec3(1.75, 0.9, 0.9), false);
	fmContactAudit r = audit(failures_, world);
	CHECK(r.crossings > 0);
	CHECK_INT(r.selfCrossings, 0);
	CHECK_INT(r.verticesInside, 10);
	CHECK_NEAR(r.deepest, 0.25, 1e-12);
	CHECK_INT(r.invertedTets, 0);
	CHECK_INT(r.firstCrossing.body.index1, a.index1);
	CHECK_INT(r.firstCrossing.otherBody.index1, b.index1);
	CHECK_INT(r.firstInside.body.index1, a.index1);
	CHECK_INT(r.firstInside.otherBody.index1, b.index1);
	// A's vertex inside B is A's face centre (1, 0.5, 0.5).
	const double* x = fmTestPositions(a);
	int v = r.firstInside.vertex[0];
	CHECK(v >= 0 && v < fmBody_GetVertexCount(a));
	if (v >= 0 && v < fmBody_GetVertexCount(a))
		CHECK(x[3 * v] == 1.0 && x[3 * v + 1] == 0.5 && x[3 * v + 2] == 0.5);
	CHECK_NEAR(r.firstInside.depth, 0.25, 1e-12);
	fmDestroyWorld(world);
}

TEST(tet_inverted_by_hand)
{
	fmWorldId world = freeWorld();
	fmBodyId box = auditBox(failures_, world, 1, 1, 1, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1),
	                        false);
	CHECK_CLEAN(audit(failures_, world));
	// Move tet 0's first vertex through the plane of the other three, along their normal, to
	// its mirror image: only tets around that vertex can turn, and tet 0 does.
	const int* tets = fmBody_GetTets(box);
	int n = fmBody_GetVertexCount(box);
	double x[3 * 8];
	CHECK_INT(n, 8);
	if (n != 8)
		return;
	memcpy(x, fmTestPositions(box), sizeof x);
	fmVec3 p = fmLoad(x, tets[0]), a = fmLoad(x, tets[1]), b = fmLoad(x, tets[2]),
	       c = fmLoad(x, tets[3]);
	fmVec3 normal = fmCross(fmSub(b, a), fmSub(c, a));
	double s = fmDot(normal, fmSub(p, a)) / fmDot(normal, normal);
	fmStore(x, tets[0], fmSub(p, fmScale(2.0 * s, normal)));
	fmBody_SetPositions(box, x);
	fmContactAudit r = audit(failures_, world);
	fmBodyStats stats = fmBody_GetStats(box);
	CHECK(r.invertedTets >= 1);
	CHECK_INT(r.invertedTets, stats.invertedTets);
	CHECK_INT(r.firstInverted.body.index1, box.index1);
	// tet 0 in the user's order is inverted; the first one found is some inverted tet.
	CHECK(r.firstInverted.index >= 0 && r.firstInverted.index < fmBody_GetTetCount(box));
	fmDestroyWorld(world);
}

TEST(single_tet_inverted)
{
	fmWorldId world = freeWorld();
	double nodes[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	int tet[4] = {0, 1, 2, 3};
	fmTetMesh mesh = {0};
	mesh.nodeCount = 4;
	mesh.tetCount = 1;
	mesh.positions = nodes;
	mesh.tets = tet;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	CHECK_INT(audit(failures_, world).invertedTets, 0);
	nodes[11] = -0.5; // the apex through its base
	fmBody_SetPositions(body, nodes);
	fmContactAudit r = audit(failures_, world);
	CHECK_INT(r.invertedTets, 1);
	CHECK_INT(r.firstInverted.index, 0);
	nodes[11] = 0.0; // flat: det F = 0 counts
	fmBody_SetPositions(body, nodes);
	CHECK_INT(audit(failures_, world).invertedTets, 1);
	fmDestroyWorld(world);
}

// A bar [0, 4] x [0, 0.5] x [0, 0.5] of 8 x 1 x 1 cubes folded at x = 2: its second half turned
// back over the first, 0.25 higher, so that the halves pass through each other.
static int foldedBar(int* failures_, bool selfCollision, fmContactAudit* r)
{
	fmWorldId world = freeWorld();
	fmBodyId bar = auditBox(failures_, world, 8, 1, 1, fmMakeVec3(0, 0, 0),
	                        fmMakeVec3(4, 0.5, 0.5), selfCollision);
	int n = fmBody_GetVertexCount(bar);
	double x[3 * 64];
	CHECK(n > 0 && n <= 64);
	if (n <= 0 || n > 64)
		n = 0;
	else
		memcpy(x, fmTestPositions(bar), sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
		if (x[3 * i] > 2.0)
		{
			x[3 * i] = 4.0 - x[3 * i] + 0.1;
			x[3 * i + 1] += 0.25;
		}
	fmBody_SetPositions(bar, x);
	*r = audit(failures_, world);
	fmDestroyWorld(world);
	return bar.index1;
}

TEST(fold_with_self_collision)
{
	fmContactAudit on, off;
	int bar = foldedBar(failures_, true, &on);
	foldedBar(failures_, false, &off);
	printf("  folded bar: %d self crossings, %d inverted tets\n", on.selfCrossings,
	       on.invertedTets);
	CHECK(on.selfCrossings > 0);
	CHECK_INT(on.crossings, 0);
	CHECK_INT(on.verticesInside, 0);
	CHECK_INT(on.firstSelfCrossing.body.index1, bar);
	CHECK_INT(on.firstSelfCrossing.otherBody.index1, bar);
	CHECK_INT(off.selfCrossings, 0);
	CHECK_INT(off.invertedTets, on.invertedTets);
}

TEST(near_touching_pair)
{
	// 1e-9 apart: nothing; 1e-9 into each other: B's bottom face centre inside A and A's top
	// face centre inside B (the other vertices of those faces are on the other's side faces).
	const double gaps[2] = {1e-9, -1e-9};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world = freeWorld();
		auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), false);
		auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 1 + gaps[k], 0),
		         fmMakeVec3(1, 2 + gaps[k], 1), false);
		fmContactAudit r = audit(failures_, world);
		CHECK_INT(r.verticesInside, k == 0 ? 0 : 2);
		if (k == 0)
			CHECK_CLEAN(r);
		else
			CHECK_NEAR(r.deepest, 1e-9, 1e-15);
		fmDestroyWorld(world);
	}
}

TEST(degenerate_touching)
{
	// Shared faces exactly coplanar, aligned or shifted half a cell: touching, not crossing, and
	// no vertex strictly inside; the same answer with the bodies in either order.
	const double shifts[3] = {0.0, 0.25, 0.5};
	for (int k = 0; k < 3; ++k)
		for (int order = 0; order < 2; ++order)
		{
			fmWorldId world = freeWorld();
			fmVec3 lo[2] = {fmMakeVec3(0, 0, 0), fmMakeVec3(shifts[k], 1, 0)};
			for (int b = 0; b < 2; ++b)
			{
				fmVec3 l = lo[b ^ order];
				auditBox(failures_, world, 2, 2, 2, l, fmAdd(l, fmMakeVec3(1, 1, 1)), false);
			}
			fmContactAudit r = audit(failures_, world);
			CHECK_CLEAN(r);
			fmDestroyWorld(world);
		}
}

// @p count houses (4 m wide) on the floor in rows of 5, @p spacing m apart, settled for
// @p frames frames; without contact between them when they are made overlapping (closer than
// 4 m: a world with body contact refuses them).
static fmWorldId houses(int* failures_, int count, double spacing, int frames)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.contact.bodies = spacing >= 4.0;
	fmWorldId world = fmCreateWorld(&wdef);
	for (int h = 0; h < count; ++h)
	{
		fmTetMesh mesh;
		CHECK(fmTestHouseMesh(&mesh, fmMakeVec3(spacing * (h % 5), 0.0, spacing * (h / 5))));
		fmBodyDef def = fmDefaultBodyDef();
		def.mesh = &mesh;
		fmBodyId body;
		CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
	}
	for (int f = 0; f < frames; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	return world;
}

TEST(house_resting_on_the_floor)
{
	fmWorldId world = houses(failures_, 1, 5.0, 120);
	fmContactAudit r = audit(failures_, world);
	CHECK_INT(r.bodies, 1);
	CHECK_CLEAN(r);
	fmDestroyWorld(world);
}

// The audit's cost (printed) for 3 and 10 houses 5 m apart, and 10 houses 3.2 m apart (0.8 m into
// each other), which it must find.
TEST(houses_cost)
{
	const int counts[3] = {3, 10, 10};
	const double spacings[3] = {5.0, 5.0, 3.2};
	for (int k = 0; k < 3; ++k)
	{
		fmWorldId world = houses(failures_, counts[k], spacings[k], 0);
		double start = fmSeconds();
		fmContactAudit r = audit(failures_, world);
		double ms = 1e3 * (fmSeconds() - start);
		printf("  %d houses %.1f m apart: %.2f ms, %d crossings, %d vertices inside (deepest %.3f "
		       "m)\n",
		       counts[k], spacings[k], ms, r.crossings, r.verticesInside, r.deepest);
		if (k < 2)
			CHECK_CLEAN(r);
		else
			CHECK(r.crossings > 0 && r.verticesInside > 0 && r.deepest > 0.3);
		fmDestroyWorld(world);
	}
}

// What the substep callback sees: each substep's index and the frame's time reached, with a
// world it can audit mid-step.
typedef struct SubstepLog
{
	fmWorldId world;
	int calls;
	int lastIndex;
	double lastTime;
	bool ordered;
	int audited;
} SubstepLog;

static void logSubstep(int substep, double time, void* context)
{
	SubstepLog* log = context;
	log->ordered = log->ordered && substep == log->lastIndex + 1 && time > log->lastTime;
	log->lastIndex = substep;
	log->lastTime = time;
	log->calls += 1;
	fmContactAudit a;
	log->audited += fmWorld_AuditContact(log->world, &a) == fm_ok && a.bodies == 2;
}

// fmWorldDef.substepCallback runs after every substep (5 a frame, 4 frames), in order, with the
// frame's time reached ending at the frame's time, and the world can be audited from it.
TEST(every_substep_can_be_audited)
{
	SubstepLog log = {{0, 0}, 0, -1, 0.0, true, 0};
	fmWorldDef def = fmTestFreeWorldDef();
	def.substepCallback = logSubstep;
	def.substepContext = &log;
	fmWorldId world = fmCreateWorld(&def);
	log.world = world;
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), false);
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(2, 0, 0), fmMakeVec3(3, 1, 1), false);
	for (int frame = 0; frame < 4; ++frame)
	{
		log.lastIndex = -1;
		log.lastTime = 0.0;
		CHECK_INT(fmWorld_Step(world, 0.01, 5), fm_ok);
		CHECK_INT(log.lastIndex, 4);
		CHECK_NEAR(log.lastTime, 0.01, 1e-15);
	}
	CHECK(log.ordered);
	CHECK_INT(log.calls, 20);
	CHECK_INT(log.audited, 20);
	fmDestroyWorld(world);
}

// A body whose positions went non-finite has no surface to audit: fm_errNumerical, the output
// untouched, no read or write outside the grids (the sanitizer build runs this).
TEST(non_finite_positions_are_refused)
{
	fmWorldId world = freeWorld();
	fmBodyId a = auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), false);
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(2, 0, 0), fmMakeVec3(3, 1, 1), false);
	int n = fmBody_GetVertexCount(a);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	CHECK_INT(fmBody_CopyPositions(a, x, n), fm_ok);
	x[4] = NAN;
	x[7] = INFINITY;
	fmBody_SetPositions(a, x);
	free(x);
	fmContactAudit result;
	memset(&result, 0x5a, sizeof result);
	unsigned char before[sizeof result];
	memcpy(before, &result, sizeof result);
	CHECK_INT(fmWorld_AuditContact(world, &result), fm_errNumerical);
	CHECK(memcmp(before, &result, sizeof result) == 0);
	fmDestroyWorld(world);
}

// The substep callback may read the world, not step it: a nested fmWorld_Step is refused with
// fm_errBusy, writing nothing, and the frame in progress goes on.
typedef struct NestedStep
{
	fmWorldId world;
	fmResult nested;
} NestedStep;

static void stepFromCallback(int substep, double time, void* context)
{
	(void)substep;
	(void)time;
	NestedStep* n = context;
	n->nested = fmWorld_Step(n->world, 0.01, 1);
}

TEST(the_substep_callback_cannot_step_the_world)
{
	NestedStep nested = {{0, 0}, fm_ok};
	fmWorldDef def = fmTestFreeWorldDef();
	def.substepCallback = stepFromCallback;
	def.substepContext = &nested;
	fmWorldId world = fmCreateWorld(&def);
	nested.world = world;
	auditBox(failures_, world, 2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), false);
	CHECK_INT(fmWorld_Step(world, 0.01, 2), fm_ok);
	CHECK_INT(nested.nested, fm_errBusy);
	CHECK_INT(fmWorld_GetStepStats(world).steps, 2);
	CHECK_INT(fmWorld_GetLastError(world)->result, fm_ok);
	fmDestroyWorld(world);
}
