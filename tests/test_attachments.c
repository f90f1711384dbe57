

// Attachments (docs/contact.md, "Attachments"): a soft body glued to a collider hangs from it
// with the collider carrying its weight (force and torque), follows it when it moves, and
// what the collider reports is exactly what the body received (Newton's third law across the
// glue); welded bodies move as one, carry each other's weight, and keep their total momentum;
// the glue and welds go with their collider or body, sleep with their islands, survive
// snapshots, and bad calls are refused with a located message.
#include "support.h"
#include "test.h"

#include "body/anchors.h"
#include "body/body.h"
#include "world/snapshot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The body's centre of mass (m).
static fmVec3 centreOf(fmBodyId body)
{
	const double* x = fmTestPositions(body);
	const double* m = fmBody_GetMasses(body);
	fmVec3 c = fmMakeVec3(0.0, 0.0, 0.0);
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		c = fmMulAdd(c, m[i], fmLoad(x, i));
	return fmScale(1.0 / fmTestMass(body), c);
}

// A 0.3 m Neo-Hookean box (3 cubes a side, 1e5 Pa, 500 kg/m^3: 13.5 kg) from @p lo, with the
// velocity damping factor @p damping (1: none, momentum-free).
static fmBodyId makeDampedBox(int* failures_, fmWorldId world, fmVec3 lo, double damping)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(3, 3, 3, lo, fmAdd(lo, fmMakeVec3(0.3, 0.3, 0.3)), &mesh), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 500.0;
	def.damping = damping;
	def.smoothing = 0.0; // off: it is not momentum-free
	fmBodyId body = {0};
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	return body;
}

static fmBodyId makeBox(int* failures_, fmWorldId world, fmVec3 lo)
{
	return makeDampedBox(failures_, world, lo, 1.0);
}

// The body's vertices (user numbering) with coordinate @p axis within 1e-9 of @p value; their
// count in @p count (at most 64).
static int facing(fmBodyId body, int axis, double value, int* vertices)
{
	const double* x = fmTestPositions(body);
	int count = 0;
	for (int i = 0; i < fmBody_GetVertexCount(body) && count < 64; ++i)
		if (fabs(x[3 * i + axis] - value) < 1e-9)
			vertices[count++] = i;
	return count;
}

// Two of makeDampedBox's boxes side by side from height @p y, welded across the face they
// share (its vertices pair up in the same order: the meshes are alike); the first's top face
// glued to @p plank unless it is the null id.
typedef struct WeldedPair
{
	fmBodyId a, b;
	int top[64], glued;              // a's top face, glued to the plank (0 without one)
	int right[64], left[64], welded; // a's right face, welded to b's left
} WeldedPair;

static WeldedPair makePair(int* failures_, fmWorldId world, double y, double damping,
                           fmColliderId plank)
{
	WeldedPair p;
	memset(&p, 0, sizeof p);
	p.a = makeDampedBox(failures_, world, fmMakeVec3(-0.3, y, -0.15), damping);
	p.b = makeDampedBox(failures_, world, fmMakeVec3(0.0, y, -0.15), damping);
	p.welded = facing(p.a, 0, 0.0, p.right);
	CHECK_INT(facing(p.b, 0, 0.0, p.left), p.welded);
	if (fmCollider_IsValid(plank))
	{
		p.glued = facing(p.a, 1, y + 0.3, p.top);
		CHECK_INT(fmBody_AttachToCollider(p.a, p.top, p.glued, plank, NULL), fm_ok);
	}
	CHECK_INT(fmBody_Weld(p.a, p.right, p.b, p.left, p.welded, NULL), fm_ok);
	return p;
}

// The widest gap between the pair's welded vertices (m).
static double weldGap(const WeldedPair* p)
{
	double gap = 0.0;
	for (int k = 0; k < p->welded; ++k)
		gap = fmax(gap, fmLength(fmSub(fmLoad(fmTestPositions(p->a), p->right[k]),
		                               fmLoad(fmTestPositions(p->b), p->left[k]))));
	return gap;
}

static fmWorldId makeWorld(bool implicit, fmVec3 gravity)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = implicit ? fm_implicit : fm_explicit;
	wdef.autoSubstep = !implicit;
	wdef.tolerance = FM_TOLERANCE_ACCURATE;
	wdef.floor.enabled = false;
	wdef.gravity = gravity;
	wdef.contact.enableSleep = false;
	return fmCreateWorld(&wdef);
}

// A plank (a box collider, 1.2 m long) at height 1 m, turned by @p angle about z.
static fmColliderId makePlank(int* failures_, fmWorldId world)
{
	fmColliderDef plank = fmDefaultColliderDef();
	plank.shape = fm_shapeBox;
	plank.center = fmMakeVec3(0.0, 1.0, 0.0);
	plank.halfExtents = fmMakeVec3(0.6, 0.05, 0.3);
	fmColliderId id = {0};
	CHECK_INT(fmCreateCollider(world, &plank, &id, NULL), fm_ok);
	return id;
}

// A box glued by its top face under a plank, its centre 0.3 m along the plank from the plank's
// centre: once it hangs still, the plank carries its weight and the torque of that weight.
TEST(glued_box_hangs_from_a_plank_which_carries_its_weight)
{
	for (int implicit = 1; implicit >= 0; --implicit)
	{
		fmWorldId world = makeWorld(implicit, fmMakeVec3(0.0, -9.8, 0.0));
		fmColliderId plank = makePlank(failures_, world);
		fmBodyId box = makeBox(failures_, world, fmMakeVec3(0.15, 0.65, -0.15));
		int top[64], n = facing(box, 1, 0.95, top);
		CHECK_INT(n, 16);
		CHECK_INT(fmBody_AttachToCollider(box, top, n, plank, NULL), fm_ok);
		CHECK_INT(fmBody_GetAttachmentCount(box), 16);
		double weight = 9.8 * fmTestMass(box);
		for (int frame = 0; frame < 180; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 8), fm_ok);
		fmVec3 force, torque;
		fmCollider_GetContactForce(plank, &force, &torque);
		fmVec3 lever = fmSub(centreOf(box), fmCollider_GetPosition(plank));
		fmVec3 expected = fmCross(lever, fmMakeVec3(0.0, -weight, 0.0));
		printf("  %s: the plank carries %.5f of the weight, torque %.5f of the lever's (%.3f m), "
		       "the box sags %.2f mm\n",
		       implicit ? "implicit" : "explicit", -force.y / weight, torque.z / expected.z,
		       lever.x, 1e3 * (0.95 - fmTestPositions(box)[3 * top[0] + 1]));
		CHECK_NEAR(force.y, -weight, 1e-3 * weight);
		CHECK_NEAR(force.x, 0.0, 1e-3 * weight);
		CHECK_NEAR(torque.z, expected.z, 1e-3 * fabs(expected.z));
		CHECK(fmLength(fmTestMomentum(box)) < 1e-3 * fmTestMass(box)); // it hangs still
		fmDestroyWorld(world);
	}
}

// A static solve of a box held by its glue alone (no pin): at equilibrium the springs carry the
// weight, so the glued vertices sag by the default's 1 mm on average (each spring is the body's
// weight over 1 mm shared among them).
TEST(static_solve_hangs_a_glued_box_by_its_springs)
{
	fmWorldId world = makeWorld(true, fmMakeVec3(0.0, -9.8, 0.0));
	fmColliderId plank = makePlank(failures_, world);
	fmBodyId box = makeBox(failures_, world, fmMakeVec3(0.15, 0.65, -0.15));
	int top[64], n = facing(box, 1, 0.95, top);
	CHECK_INT(fmBody_AttachToCollider(box, top, n, plank, NULL), fm_ok);
	double residual = 1.0;
	CHECK_INT(fmBody_SolveStatic(box, 1e-10, 50, &residual, NULL), fm_ok);
	double sag = 0.0;
	for (int k = 0; k < n; ++k)
		sag += (0.95 - fmTestPositions(box)[3 * top[k] + 1]) / n;
	// The default spring scales the weight with Earth's gravity when the world's is weaker, and
	// takes the world's when stronger: 9.81 here.
	double expected = 0.001 * 9.8 / 9.81;
	printf("  the glued vertices sag %.6f mm on average (the springs carry the weight at %.6f), "
	       "residual %.1e\n",
	       1e3 * sag, 1e3 * expected, residual);
	CHECK_NEAR(sag, expected, 1e-6 * expected);
	fmDestroyWorld(world);
}

// The plank swings and slides with the box glued under it: every frame the box's momentum change
// less gravity's impulse is minus the plank's force times the frame (Newton's third law across
// the glue), and the glued vertices stay by their points of the plank.
TEST(glue_obeys_the_third_law_on_a_moving_collider)
{
	for (int implicit = 1; implicit >= 0; --implicit)
	{
		fmWorldId world = makeWorld(implicit, fmMakeVec3(0.0, -9.8, 0.0));
		fmColliderId plank = makePlank(failures_, world);
		fmBodyId box = makeBox(failures_, world, fmMakeVec3(0.15, 0.65, -0.15));
		int top[64], n = facing(box, 1, 0.95, top);
		fmAttachDef def = fmDefaultAttachDef();
		def.dampingRatio = 0.5;
		CHECK_INT(fmBody_AttachToCollider(box, top, n, plank, &def), fm_ok);
		const double h = 1.0 / 60.0, weight = 9.8 * fmTestMass(box);
		double worst = 0.0, farthest = 0.0, angle = 0.0;
		for (int frame = 0; frame < 120; ++frame)
		{
			double t = frame * h, spin = 2.0 * cos(4.0 * t);
			angle += spin * h; // the collider turns at the frame's spin over the frame
			fmCollider_SetVelocity(plank, fmMakeVec3(0.5 * sin(3.0 * t), 0.0, 0.0),
			                       fmMakeVec3(0.0, 0.0, spin));
			fmVec3 before = fmTestMomentum(box);
			CHECK_INT(fmWorld_Step(world, h, implicit ? 1 : 8), fm_ok);
			fmVec3 force;
			fmCollider_GetContactForce(plank, &force, NULL);
			fmVec3 gained = fmSub(fmTestMomentum(box), before);
			fmVec3 residual = fmMulAdd(fmAdd(gained, fmMakeVec3(0.0, weight * h, 0.0)), h, force);
			worst = fmax(worst, fmLength(residual) / (weight * h));
			// The glued vertices by the plank's underside (y = -0.05 in its frame), turned with it.
			fmVec3 c = fmCollider_GetPosition(plank);
			for (int k = 0; k < n; ++k)
			{
				fmVec3 x = fmLoad(fmTestPositions(box), top[k]);
				fmVec3 down = fmMakeVec3(sin(angle), -cos(angle), 0.0); // the plank's -y
				farthest = fmax(farthest, fabs(fmDot(fmSub(x, c), down) - 0.05));
			}
		}
		printf("  %s: the third law's residual at most %.2e of m g dt; the glued vertices at most "
		       "%.2f mm off the plank's underside\n",
		       implicit ? "implicit" : "explicit", worst, 1e3 * farthest);
		CHECK(worst < (implicit ? 2e-5 : 1e-8));
		CHECK(farthest < 0.01);
		fmDestroyWorld(world);
	}
}

// A box glued to a kinematic collider moving at 1 m/s in zero gravity is carried along: its
// centre's velocity reaches the collider's.
TEST(glued_box_is_carried_by_its_collider)
{
	fmWorldId world = makeWorld(true, fmMakeVec3(0.0, 0.0, 0.0));
	fmColliderId plank = makePlank(failures_, world);
	fmBodyId box = makeBox(failures_, world, fmMakeVec3(-0.15, 0.65, -0.15));
	int top[64], n = facing(box, 1, 0.95, top);
	CHECK_INT(fmBody_AttachToCollider(box, top, n, plank, NULL), fm_ok);
	fmCollider_SetVelocity(plank, fmMakeVec3(1.0, 0.0, 0.0), fmMakeVec3(0.0, 0.0, 0.0));
	for (int frame = 0; frame < 60; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	fmVec3 v = fmScale(1.0 / fmTestMass(box), fmTestMomentum(box));
	fmVec3 moved = fmSub(centreOf(box), fmMakeVec3(0.0, 0.8, 0.0));
	printf("  after 1 s: the box's velocity (%.4f, %.4f) m/s, moved %.4f m (the plank 1 m)\n", v.x,
	       v.y, moved.x);
	CHECK_NEAR(v.x, 1.0, 0.01);
	CHECK_NEAR(moved.x, 1.0, 0.01);
	fmDestroyWorld(world);
}

// Two boxes side by side, welded across the face they share: hung from the plank by the first
// one's top alone, the plank carries both weights (the second hangs on the weld); in zero
// gravity, one kicked, the pair keeps its total momentum and moves as one.
TEST(welded_boxes_carry_each_other)
{
	for (int implicit = 1; implicit >= 0; --implicit)
	{
		fmWorldId world = makeWorld(implicit, fmMakeVec3(0.0, -9.8, 0.0));
		fmColliderId plank = makePlank(failures_, world);
		// Damped, so that the pair settles within the test's 4 s.
		WeldedPair pair = makePair(failures_, world, 0.6, 0.98, plank);
		CHECK_INT(fmBody_GetAttachmentCount(pair.b), pair.welded);
		double weight = 9.8 * (fmTestMass(pair.a) + fmTestMass(pair.b));
		for (int frame = 0; frame < 240; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 8), fm_ok);
		fmVec3 force;
		fmCollider_GetContactForce(plank, &force, NULL);
		double gap = weldGap(&pair);
		printf("  %s: the plank carries %.5f of both weights; the weld opens %.2f mm\n",
		       implicit ? "implicit" : "explicit", -force.y / weight, 1e3 * gap);
		CHECK_NEAR(force.y, -weight, 2e-3 * weight);
		CHECK(gap < 0.01); // the default weld: the lighter body's weight over about 1 mm
		fmDestroyWorld(world);
	}
}

// Two boxes welded side by side, the first kicked up and sideways in zero gravity: the pair
// spins and flies off as one, keeping the kick's momentum.
TEST(welded_pair_keeps_its_momentum)
{
	for (int implicit = 1; implicit >= 0; --implicit)
	{
		fmWorldId world = makeWorld(implicit, fmMakeVec3(0.0, 0.0, 0.0));
		WeldedPair pair = makePair(failures_, world, 0.65, 1.0, (fmColliderId){0});
		fmBodyId a = pair.a, b = pair.b;
		fmBody_ApplyImpulse(a, fmMakeVec3(0.0, 2.0, 1.0));
		fmVec3 start = fmAdd(fmTestMomentum(a), fmTestMomentum(b));
		double worst = 0.0, gap = 0.0;
		for (int frame = 0; frame < 120; ++frame)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 8), fm_ok);
			fmVec3 p = fmAdd(fmTestMomentum(a), fmTestMomentum(b));
			worst = fmax(worst, fmLength(fmSub(p, start)) / fmLength(start));
			gap = fmax(gap, weldGap(&pair));
		}
		printf("  %s: total momentum within %.2e of the kick's; the weld opens at most %.2f mm\n",
		       implicit ? "implicit" : "explicit", worst, 1e3 * gap);
		// Explicit: the two ends' forces are equal and opposite (round-off); implicit: the ends
		// meet at the midpoint of their predicted ends, within the solve's tolerance.
		CHECK(worst < (implicit ? 1e-4 : 1e-6));
		CHECK(gap < 0.01);
		fmDestroyWorld(world);
	}
}

// Two welded boxes falling freely fall as one body does: their centre drops g t^2 / 2 (the
// integrators' (1 + 1/n) g t^2 / 2 after n steps), the weld neither holding them back nor opening.
TEST(welded_pair_falls_freely)
{
	for (int implicit = 1; implicit >= 0; --implicit)
	{
		fmWorldId world = makeWorld(implicit, fmMakeVec3(0.0, -9.8, 0.0));
		WeldedPair pair = makePair(failures_, world, 0.6, 1.0, (fmColliderId){0});
		fmBodyId a = pair.a, b = pair.b;
		double y = centreOf(a).y, gap = 0.0;
		const int n = 30;
		int steps = 0;
		for (int frame = 0; frame < n; ++frame)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 8), fm_ok);
			steps += fmWorld_GetStepStats(world).steps;
			gap = fmax(gap, weldGap(&pair));
		}
		// Both integrators' positions take the new velocity: g h^2 k (k + 1) / 2 after k equal
		// steps (the explicit substeps are autoSubstep's, nearly equal).
		double t = n / 60.0, expected = 0.5 * 9.8 * t * t * (1.0 + 1.0 / steps);
		double fell = 0.5 * (y - centreOf(a).y + y - centreOf(b).y);
		printf("  %s: the pair fell %.5f m in %.2f s (a free body %.5f m); the weld opens at most "
		       "%.3f mm\n",
		       implicit ? "implicit" : "explicit", fell, t, expected, 1e3 * gap);
		CHECK_NEAR(fell, expected, 1e-3 * expected);
		CHECK(gap < 1e-3);
		fmDestroyWorld(world);
	}
}

// A snapshot taken while a glued box swings under a turning plank, restored after more frames:
// the run from it repeats bit for bit, its attachments with it; a world that lost them gets
// them back.
TEST(attachments_are_kept_in_snapshots)
{
	fmWorldId world = makeWorld(true, fmMakeVec3(0.0, -9.8, 0.0));
	fmColliderId plank = makePlank(failures_, world);
	WeldedPair pair = makePair(failures_, world, 0.6, 1.0, plank);
	fmBodyId a = pair.a, b = pair.b;
	fmCollider_SetVelocity(plank, fmMakeVec3(0.0, 0.0, 0.0), fmMakeVec3(0.0, 0.0, 0.5));
	for (int frame = 0; frame < 20; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	size_t size = fmWorld_GetSnapshotSize(world);
	unsigned char* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, NULL), fm_ok);
	int count = 3 * fmBody_GetVertexCount(b);
	double* first = malloc(sizeof(double) * (size_t)count);
	for (int frame = 0; frame < 20; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	memcpy(first, fmTestPositions(b), sizeof(double) * (size_t)count);
	fmBody_ClearAttachments(a);
	CHECK_INT(fmBody_GetAttachmentCount(a), 0);
	CHECK_INT(fmBody_GetAttachmentCount(b), 0); // the weld went at both ends
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
	CHECK_INT(fmBody_GetAttachmentCount(a), pair.glued + pair.welded);
	CHECK_INT(fmBody_GetAttachmentCount(b), pair.welded);
	for (int frame = 0; frame < 20; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK(memcmp(first, fmTestPositions(b), sizeof(double) * (size_t)count) == 0);
	// A record naming a vertex beyond the body is refused, the world untouched.
	fmAnchorRecord bad = fmAnchors_Record(fmGetBody(a), 0);
	size_t at = 0;
	for (size_t k = 0; k + sizeof bad <= size && at == 0; ++k)
		if (memcmp(snapshot + k, &bad, sizeof bad) == 0)
			at = k;
	CHECK(at > 0);
	bad.vertex = 1000;
	memcpy(snapshot + at, &bad, sizeof bad);
	fmSnapshot_Seal(snapshot, size); // a valid checksum: the record itself is refused
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "attachments");
	CHECK(memcmp(first, fmTestPositions(b), sizeof(double) * (size_t)count) == 0);
	free(first);
	free(snapshot);
	fmDestroyWorld(world);
}

// The glue goes with its collider and a weld with its partner; a body glued to a still collider
// sleeps, one glued to a moving collider does not, and welded bodies sleep together.
TEST(attachments_follow_their_colliders_and_bodies)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	wdef.contact.enableSleep = true;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderId plank = makePlank(failures_, world);
	WeldedPair pair = makePair(failures_, world, 0.6, 0.99, plank);
	fmBodyId a = pair.a, b = pair.b;
	int frame = 0;
	for (; frame < 600 && (fmBody_IsAwake(a) || fmBody_IsAwake(b)); ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	printf("  the welded pair hanging from a still plank fell asleep after %d frames\n", frame);
	CHECK(!fmBody_IsAwake(a) && !fmBody_IsAwake(b));
	// The plank starts to move: both wake, and stay awake while it moves.
	fmCollider_SetVelocity(plank, fmMakeVec3(0.1, 0.0, 0.0), fmMakeVec3(0.0, 0.0, 0.0));
	for (frame = 0; frame < 120; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK(fmBody_IsAwake(a) && fmBody_IsAwake(b));
	CHECK(centreOf(b).x > 0.15 + 0.1); // carried 0.2 m by the plank, through the weld
	// The plank destroyed: the glue goes, the pair falls; the second box destroyed: the weld goes.
	fmDestroyCollider(plank);
	double y = centreOf(a).y;
	for (frame = 0; frame < 30; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK_INT(fmBody_GetAttachmentCount(a), pair.welded);
	printf("  the plank destroyed: the pair fell %.3f m in 0.5 s (glued, it hangs within mm)\n",
	       y - centreOf(a).y);
	CHECK(centreOf(a).y < y - 0.05); // falling, slowed by the boxes' velocity damping
	fmDestroyBody(b);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK_INT(fmBody_GetAttachmentCount(a), 0);
	fmDestroyWorld(world);
}

// A call refused with @p expected and the world's last error holding @p message.
static void refused(int* failures_, fmWorldId world, fmResult result, fmResult expected,
                    const char* message)
{
	CHECK_INT(result, expected);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, message);
}

// Bad calls are refused with the world's last error naming the call and what was expected, the
// bodies' attachments unchanged.
TEST(bad_attachments_are_refused)
{
	fmWorldId world = makeWorld(true, fmMakeVec3(0.0, -9.8, 0.0));
	fmWorldId other = makeWorld(true, fmMakeVec3(0.0, -9.8, 0.0));
	fmColliderId plank = makePlank(failures_, world);
	fmColliderId elsewhere = makePlank(failures_, other);
	fmBodyId a = makeBox(failures_, world, fmMakeVec3(-0.3, 0.6, -0.15));
	fmBodyId b = makeBox(failures_, world, fmMakeVec3(0.0, 0.6, -0.15));
	fmBodyId c = makeBox(failures_, other, fmMakeVec3(0.0, 0.6, -0.15));
	int good[2] = {0, 1}, wrong[2] = {0, 64}, same[2] = {3, 1};
	fmAttachDef def = fmDefaultAttachDef();
	refused(failures_, world, fmBody_AttachToCollider(a, wrong, 2, plank, NULL), fm_errParameter,
	        "fmBody_AttachToCollider: entry 1 (vertex 64): expected a vertex index in [0, "
	        "vertexCount)");
	refused(failures_, world, fmBody_AttachToCollider(a, good, 2, elsewhere, NULL), fm_errParameter,
	        "expected a live collider of the body's world");
	refused(failures_, world, fmBody_AttachToCollider(a, good, 0, plank, NULL), fm_errParameter,
	        "expected count >= 1");
	def.stiffness = NAN;
	refused(failures_, world, fmBody_AttachToCollider(a, good, 2, plank, &def), fm_errParameter,
	        "a finite stiffness");
	def = fmDefaultAttachDef();
	def.internalValue = 0;
	refused(failures_, world, fmBody_Weld(a, good, b, good, 2, &def), fm_errParameter,
	        "fmDefaultAttachDef()");
	refused(failures_, world, fmBody_Weld(a, good, c, good, 2, NULL), fm_errParameter,
	        "two bodies of one world");
	refused(failures_, world, fmBody_Weld(a, same, a, good, 2, NULL), fm_errParameter,
	        "entry 1 (vertex 1): expected two different vertices");
	refused(failures_, world, fmBody_Weld(a, good, b, wrong, 2, NULL), fm_errParameter,
	        "fmBody_Weld (the other body): entry 1 (vertex 64)");
	CHECK_INT(fmBody_GetAttachmentCount(a), 0);
	CHECK_INT(fmBody_GetAttachmentCount(b), 0);
	int* many = malloc(sizeof(int) * 512);
	for (int k = 0; k < 512; ++k)
		many[k] = k % 64;
	CHECK_INT(fmBody_AttachToCollider(a, many, 500, plank, NULL), fm_ok);
	refused(failures_, world, fmBody_AttachToCollider(a, many, 100, plank, NULL), fm_errLimit,
	        "at most FM_MAX_ANCHORS_PER_VERTEX");
	CHECK_INT(fmBody_GetAttachmentCount(a), 500);
	free(many);
	fmDestroyWorld(other);
	fmDestroyWorld(world);
}

// The glued and welded pair under a turning plank, stepped on one worker and on two (the two
// boxes then step at once): the same bits.
TEST(attachments_give_the_same_bits_for_any_worker_count)
{
	double* result[2] = {NULL, NULL};
	int count = 0;
	for (int workers = 1; workers <= 2; ++workers)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_implicit;
		wdef.floor.enabled = false;
		wdef.workerCount = workers;
		fmWorldId world = fmCreateWorld(&wdef);
		fmColliderId plank = makePlank(failures_, world);
		fmBodyId b = makePair(failures_, world, 0.6, 1.0, plank).b;
		fmCollider_SetVelocity(plank, fmMakeVec3(0.0, 0.0, 0.0), fmMakeVec3(0.0, 0.0, 1.0));
		for (int frame = 0; frame < 30; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		count = 3 * fmBody_GetVertexCount(b);
		result[workers - 1] = malloc(sizeof(double) * (size_t)count);
		memcpy(result[workers - 1], fmTestPositions(b), sizeof(double) * (size_t)count);
		fmDestroyWorld(world);
	}
	CHECK(memcmp(result[0], result[1], sizeof(double) * (size_t)count) == 0);
	free(result[0]);
	free(result[1]);
}
