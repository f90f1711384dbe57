// Scripted drags (fmWorld_GrabRay, fmBody_MoveGrab): a fixed-seed stream of grabs, each held for
// 60 frames, a tenth of them flicks at 20 to 30 m/s, on the seeds' house (their Lame constants,
// Neo-Hookean) in both integrators, a three-house pile (the barrier) and the clamped
// cantilever. Every frame must pass the library's health checks (finite, energy within the
// ledger) and leave no tet inverted. The implicit scenes take the game tolerance (a game's
// setting). Counts: 1000 drags on the house implicit, 300 explicit (its grabbed frames take the
// substeps the stability limit asks for, about seven times the scene's ten), 1000 on the
// cantilever and 1000 on the pile; at most 4 under FEMTO_TEST_QUICK (the sanitizers);
// FEMTO_DRAGS sets them all.
#include "support.h"
#include "test.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DRAG_FRAMES 60
#define DRAG_MAX_BODIES 3

typedef struct DragScene
{
	const char* name;
	fmWorldId world;
	fmBodyId bodies[DRAG_MAX_BODIES];
	int count;
	fmIntegrator integrator;
	double frame; // s
	int substeps;
} DragScene;

typedef struct DragTally
{
	int drags, flicks, misses, refused, inverted, frames;
	double fastest; // m/s, the fastest target speed
	char firstError[600];
} DragTally;

static uint32_t dragRandom(uint32_t* state)
{
	*state = *state * 1664525u + 1013904223u;
	return *state >> 8;
}

// Uniform in [lo, hi).
static double dragUniform(uint32_t* state, double lo, double hi)
{
	return lo + (hi - lo) * (dragRandom(state) & 0xffffff) / 16777216.0;
}

static fmVec3 dragDirection(uint32_t* state)
{
	fmVec3 d;
	do
		d = fmMakeVec3(dragUniform(state, -1, 1), dragUniform(state, -1, 1),
		               dragUniform(state, -1, 1));
	while (fmLength(d) < 0.1 || fmLength(d) > 1.0);
	return fmScale(1.0 / fmLength(d), d);
}

// One frame and its checks: refused, inverted tets in any body.
static void dragFrame(DragScene* s, DragTally* t)
{
	fmResult r = fmWorld_Step(s->world, s->frame, s->substeps);
	t->frames += 1;
	if (r != fm_ok)
	{
		if (t->refused++ == 0)
			snprintf(t->firstError, sizeof t->firstError, "%s",
			         fmWorld_GetLastError(s->world)->message);
	}
	for (int b = 0; b < s->count; ++b)
		t->inverted += fmBody_GetStats(s->bodies[b]).invertedTets;
}

// A ray at a random body from a random side, aimed within a third of its size of its centre.
static bool dragGrab(DragScene* s, uint32_t* state, fmBodyId* body, fmVec3* point)
{
	const fmBodyId b = s->bodies[dragRandom(state) % (uint32_t)s->count];
	fmBodyStats stats = fmBody_GetStats(b);
	double size = 2.0; // the house's and the cantilever's scale (m)
	fmVec3 aim = fmAdd(stats.centerOfMass, fmScale(size / 3.0, dragDirection(state)));
	fmVec3 from = fmAdd(aim, fmScale(5.0 * size, dragDirection(state)));
	fmGrabDef def = fmDefaultGrabDef();
	fmRayHit hit;
	if (!fmWorld_GrabRay(s->world, from, fmScale(2.0, fmSub(aim, from)), fmDefaultFilter(), &def,
	                     &hit))
		return false;
	*body = hit.body;
	*point = hit.point;
	return true;
}

// Drag @p body from @p point for DRAG_FRAMES frames: a flick (a straight throw at 20-30 m/s for
// 5 frames, then held) or a slow wander (a random point within 1 m reached along a smooth path).
static void dragOne(DragScene* s, uint32_t* state, bool flick, fmBodyId body, fmVec3 point,
                    DragTally* t)
{
	fmVec3 direction = dragDirection(state);
	double speed = flick ? dragUniform(state, 20.0, 30.0) : dragUniform(state, 0.1, 1.0);
	fmVec3 target = point;
	for (int f = 1; f <= DRAG_FRAMES; ++f)
	{
		double time = f * s->frame;
		if (flick)
			target = fmAdd(point, fmScale(speed * fmin(time, 5.0 * s->frame), direction));
		else
			target = fmAdd(point, fmScale(speed * time * (1.0 - 0.5 * time), direction));
		fmBody_MoveGrab(body, target);
		dragFrame(s, t);
	}
	t->fastest = fmax(t->fastest, speed);
	fmBody_ReleaseGrab(body);
	dragFrame(s, t);
}

static void dragScene(int* failures_, DragScene* s, int drags, uint32_t seed)
{
	DragTally t;
	memset(&t, 0, sizeof t);
	uint32_t state = seed;
	for (int settle = 0; settle < 60; ++settle)
		dragFrame(s, &t);
	while (t.drags < drags && t.misses < 10 * drags)
	{
		fmBodyId body;
		fmVec3 point;
		if (!dragGrab(s, &state, &body, &point))
		{
			t.misses += 1;
			continue;
		}
		bool flick = t.drags % 10 == 9;
		dragOne(s, &state, flick, body, point, &t);
		t.flicks += flick;
		t.drags += 1;
	}
	printf("  %s: %d drags (%d flicks, up to %.1f m/s), %d frames: %d refused, %d inverted tets "
	       "summed over frames%s%s\n",
	       s->name, t.drags, t.flicks, t.fastest, t.frames, t.refused, t.inverted,
	       t.refused ? "; first: " : "", t.firstError);
	CHECK_INT(t.drags, drags);
	CHECK_INT(t.refused, 0);
	CHECK_INT(t.inverted, 0);
}

// @p full drags (FEMTO_DRAGS overrides it; FEMTO_TEST_QUICK makes it at most 4: one of them
// can be a flick only with 10, so under the sanitizers the drags are slow ones).
static int dragCount(int full)
{
	const char* asked = getenv("FEMTO_DRAGS");
	return asked != NULL ? atoi(asked) : fmTestCount(full, full < 4 ? full : 4);
}

static fmBodyId dragHouse(int* failures_, fmWorldId world, fmVec3 offset)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (!fmTestHouseMesh(&mesh, offset))
		return none;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterialLame(fm_neoHookean, 20000.0, 5000.0);
	fmBodyId body;
	fmResult r = fmCreateBody(world, &def, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

TEST(drags_on_the_house_implicit)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = fm_implicit;
	def.tolerance = FM_TOLERANCE_GAME;
	DragScene s = {"house, implicit", fmCreateWorld(&def), {{0}}, 1, fm_implicit, 1.0 / 60.0, 1};
	s.bodies[0] = dragHouse(failures_, s.world, fmMakeVec3(0, 0, 0));
	dragScene(failures_, &s, dragCount(1000), 29u);
	fmDestroyWorld(s.world);
}

TEST(drags_on_the_house_explicit)
{
	fmWorldDef def = fmDefaultWorldDef();
	DragScene s = {"house, explicit", fmCreateWorld(&def), {{0}}, 1, fm_explicit, 0.03, 10};
	s.bodies[0] = dragHouse(failures_, s.world, fmMakeVec3(0, 0, 0));
	dragScene(failures_, &s, dragCount(300), 31u);
	fmDestroyWorld(s.world);
}

// Three houses dropped on each other (the barrier holds them apart), Coulomb floor, the game
// tolerance.
TEST(drags_on_the_pile)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = fm_implicit;
	def.tolerance = FM_TOLERANCE_GAME;
	def.floor.friction = fm_floorCoulomb;
	DragScene s = {
	    "three-house pile, implicit", fmCreateWorld(&def), {{0}}, 3, fm_implicit, 1.0 / 60.0, 1};
	for (int h = 0; h < 3; ++h)
		s.bodies[h] = dragHouse(failures_, s.world, fmMakeVec3(0.3 * h, 4.3 * h, 0.0));
	dragScene(failures_, &s, dragCount(1000), 37u);
	fmDestroyWorld(s.world);
}

// The scene file's beam: 2 m, E = 10 MPa, clamped at x = 0, no floor, the game tolerance.
TEST(drags_on_the_cantilever)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(20, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(2, 0.2, 0.2), &mesh), fm_ok);
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = fm_implicit;
	def.tolerance = FM_TOLERANCE_GAME;
	def.floor.enabled = false;
	DragScene s = {
	    "cantilever, implicit", fmCreateWorld(&def), {{0}}, 1, fm_implicit, 1.0 / 60.0, 1};
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.4);
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	CHECK_INT(fmCreateBody(s.world, &bdef, &s.bodies[0], NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	CHECK(fmBody_PinBox(s.bodies[0], fmMakeVec3(-0.01, -1, -1), fmMakeVec3(0.01, 1, 1)) > 0);
	dragScene(failures_, &s, dragCount(1000), 41u);
	fmDestroyWorld(s.world);
}
