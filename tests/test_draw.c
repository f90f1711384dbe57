// Debug drawing (fmWorld_Draw) and the step profile (fmWorld_GetProfile): what the callbacks
// receive is the body's geometry (positions, outward unit normals, the tets' edges, inverted
// tets, pins, targets), strain colours follow the analytic energy of a uniform stretch, and a
// second draw allocates nothing.
#include "support.h"
#include "test.h"

#include "contact/collider.h"
#include "draw/draw.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// What the callbacks saw.
typedef struct fmSeen
{
	int batches;
	int vertexCount;
	int triangleCount;
	float* positions; // copies of the last batch
	float* normals;
	float* colors;
	int* vertices;
	int lines[4]; // per colour kind: edges, inverted, targets, other
	int points;
	int planes;
	fmVec3 planePoint;
	fmVec3 planeNormal;
	fmHexColor lastPointColor;
} fmSeen;

static void seeTriangles(const fmDrawTriangles* t, void* context)
{
	fmSeen* s = context;
	s->batches += 1;
	s->vertexCount = t->vertexCount;
	s->triangleCount = t->triangleCount;
	free(s->positions);
	free(s->normals);
	free(s->colors);
	free(s->vertices);
	size_t n = (size_t)t->vertexCount;
	s->positions = malloc(sizeof(float) * 3 * n);
	s->normals = malloc(sizeof(float) * 3 * n);
	s->colors = t->colors ? malloc(sizeof(float) * 3 * n) : NULL;
	s->vertices = malloc(sizeof(int) * n);
	memcpy(s->positions, t->positions, sizeof(float) * 3 * n);
	memcpy(s->normals, t->normals, sizeof(float) * 3 * n);
	if (t->colors)
		memcpy(s->colors, t->colors, sizeof(float) * 3 * n);
	memcpy(s->vertices, t->vertices, sizeof(int) * n);
}

static void seeLines(const float* points, int count, fmHexColor color, void* context)
{
	(void)points;
	fmSeen* s = context;
	int kind = color == 0x303030u ? 0 : color == 0xff2020u ? 1 : color == 0x20d040u ? 2 : 3;
	s->lines[kind] += count;
}

static void seePoints(const float* points, int count, float size, fmHexColor color, void* context)
{
	(void)points;
	(void)size;
	fmSeen* s = context;
	s->points += count;
	s->lastPointColor = color;
}

static void seePlane(fmVec3 point, fmVec3 normal, fmHexColor color, void* context)
{
	(void)color;
	fmSeen* s = context;
	s->planes += 1;
	s->planePoint = point;
	s->planeNormal = normal;
}

static fmDebugDraw drawInto(fmSeen* seen, unsigned flags)
{
	memset(seen, 0, sizeof *seen);
	fmDebugDraw draw = fmDefaultDebugDraw();
	draw.drawTriangles = seeTriangles;
	draw.drawLines = seeLines;
	draw.drawPoints = seePoints;
	draw.drawPlane = seePlane;
	draw.flags = flags;
	draw.context = seen;
	return draw;
}

static void freeSeen(fmSeen* s)
{
	free(s->positions);
	free(s->normals);
	free(s->colors);
	free(s->vertices);
}

// The surface batch holds exactly the surface's vertices, at their positions (in the user's
// numbering), with unit normals pointing out of the convex box.
TEST(surface_batch_is_the_body_surface)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 3, 2, 4, fmMakeVec3(0.3, 0.2, 0.4),
	                              fmMakeMaterial(fm_stvk, 1e5, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
		return;
	fmSeen seen;
	fmDebugDraw draw = drawInto(&seen, fm_drawSurfaces);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	int triangles = 0;
	const int* surface = fmBody_GetSurface(body, &triangles);
	int n = fmBody_GetVertexCount(body);
	char* onSurface = calloc((size_t)n, 1);
	int surfaceVertices = 0;
	for (int k = 0; k < 3 * triangles; ++k)
		if (!onSurface[surface[k]]++)
			surfaceVertices += 1;
	CHECK_INT(seen.batches, 1);
	CHECK_INT(seen.triangleCount, triangles);
	CHECK_INT(seen.vertexCount, surfaceVertices);
	const double* x = fmTestPositions(body);
	bool positionsMatch = true, unit = true, outward = true, listed = true;
	for (int v = 0; v < seen.vertexCount; ++v)
	{
		int i = seen.vertices[v];
		listed = listed && i >= 0 && i < n && onSurface[i];
		const float* p = seen.positions + 3 * v;
		const float* m = seen.normals + 3 * v;
		for (int e = 0; e < 3; ++e)
			positionsMatch = positionsMatch && p[e] == (float)x[3 * i + e];
		unit = unit && fabs(m[0] * m[0] + m[1] * m[1] + m[2] * m[2] - 1.0) < 1e-5;
		double out = m[0] * (p[0] - 0.15) + m[1] * (p[1] - 0.1) + m[2] * (p[2] - 0.2);
		outward = outward && out > 0.0;
	}
	CHECK(listed);
	CHECK(positionsMatch);
	CHECK(unit);
	CHECK(outward);
	CHECK(seen.colors == NULL);
	free(onSurface);
	freeSeen(&seen);
	fmDestroyWorld(world);
}

// One cube of 6 tets has 19 edges (12 of the cube, 6 face diagonals, 1 body diagonal); a tet
// turned inside out gives its 6 edges in red; pins and the floor are drawn where they are.
TEST(edges_inverted_tets_pins_and_floor)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 1, 1, 1, fmMakeVec3(1, 1, 1),
	                              fmMakeMaterial(fm_neoHookean, 1e5, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
		return;
	fmSeen seen;
	fmDebugDraw draw = drawInto(&seen, fm_drawTetEdges | fm_drawInvertedTets | fm_drawPins);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK_INT(seen.lines[0], 19);
	CHECK_INT(seen.lines[1], 0);
	CHECK_INT(seen.points, 0);
	fmBody_SetPinned(body, 0, true);
	fmBody_SetPinned(body, 7, true);
	// Push one corner through the cube: the tets that hold it invert.
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	x[3 * 7] = x[3 * 7 + 1] = x[3 * 7 + 2] = -1.0;
	fmBody_SetPositions(body, x);
	int inverted = fmBody_GetStats(body).invertedTets;
	CHECK(inverted > 0);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK_INT(seen.lines[1], 6 * inverted);
	CHECK_INT(seen.points, 2);
	free(x);
	fmDestroyWorld(world);

	fmTestMakeHouse(&world, NULL, NULL); // the seeds' floor at y = -3
	draw = drawInto(&seen, fm_drawFloor);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK_INT(seen.planes, 1);
	CHECK_NEAR(seen.planePoint.y, -3.0, 0.0);
	CHECK_NEAR(seen.planeNormal.y, 1.0, 0.0);
	CHECK_INT(seen.batches, 0); // nothing else was asked for
	fmDestroyWorld(world);
}

// Targets: a point at each target and a line to its vertex.
TEST(targets_are_drawn)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1),
	                              fmMakeMaterial(fm_stvk, 1e5, 0.3), fm_fem);
	if (!fmBody_IsValid(body))
		return;
	int vertices[3] = {0, 4, 8};
	fmVec3 positions[3] = {{2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
	CHECK_INT(fmBody_SetTargets(body, vertices, positions, 3, 100.0), fm_ok);
	fmSeen seen;
	fmDebugDraw draw = drawInto(&seen, fm_drawTargets);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK_INT(seen.lines[2], 3);
	CHECK_INT(seen.points, 3);
	CHECK(seen.lastPointColor == 0x20d040u);
	fmDestroyWorld(world);
}

// A uniform stretch F = (1 + s) I of a St. Venant-Kirchhoff body has the Green strain e I,
// e = ((1 + s)^2 - 1) / 2, and the energy density psi = 3 mu e^2 + 9 lambda e^2 / 2 in every
// tet: every vertex gets the colour of the equivalent strain sqrt(2 psi / E) / 0.2; at rest,
// the ramp's start.
// Whether every vertex of the last batch has colour @p expected, within @p tolerance.
static bool allColoursAre(const fmSeen* seen, const float expected[3], float tolerance)
{
	bool all = seen->colors != NULL;
	for (int v = 0; all && v < seen->vertexCount; ++v)
		for (int c = 0; c < 3; ++c)
			all = all && fabsf(seen->colors[3 * v + c] - expected[c]) <= tolerance;
	return all;
}

TEST(strain_colours_follow_the_energy_density)
{
	const double E = 1e5, nu = 0.3, s = 0.05;
	fmWorldId world;
	fmBodyId body =
	    fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1), fmMakeMaterial(fm_stvk, E, nu), fm_fem);
	if (!fmBody_IsValid(body))
		return;
	fmSeen seen;
	fmDebugDraw draw = drawInto(&seen, fm_drawStress);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	float rest[3];
	fmStrainColor(0.0, rest);
	CHECK(seen.colors != NULL && seen.colors[0] == rest[0] && seen.colors[2] == rest[2]);
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	for (int k = 0; k < 3 * n; ++k)
		x[k] *= 1.0 + s;
	fmBody_SetPositions(body, x);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	double mu = E / (2.0 * (1.0 + nu)), lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
	double e = ((1.0 + s) * (1.0 + s) - 1.0) / 2.0;
	double psi = 3.0 * mu * e * e + 4.5 * lambda * e * e;
	float expected[3];
	fmStrainColor(sqrt(2.0 * psi / E) / 0.2, expected);
	CHECK(allColoursAre(&seen, expected, 1e-5f));
	CHECK(fabsf(expected[0] - rest[0]) > 0.1f || fabsf(expected[1] - rest[1]) > 0.1f);
	free(x);
	freeSeen(&seen);
	fmDestroyWorld(world);
}

// A 2 x 2 x 2 box of material @p m drawn with @p flag: every colour the ramp's zero at rest,
// then stretched on rollers by @p stretch and solved (the caller draws again). Null on failure.
static fmBodyId stretchedAndDrawn(int* failures_, fmMaterial m, unsigned flag, double stretch,
                                  fmWorldId* world, fmSeen* seen, fmDebugDraw* draw)
{
	fmBodyId body = fmTestMakeBox(world, 2, 2, 2, fmMakeVec3(1, 1, 1), m, fm_fem);
	CHECK(fmBody_IsValid(body));
	if (!fmBody_IsValid(body))
		return body;
	*draw = drawInto(seen, flag);
	CHECK_INT(fmWorld_Draw(*world, draw), fm_ok);
	float zero[3];
	fmStrainColor(0.0, zero);
	CHECK(allColoursAre(seen, zero, 0.0f));
	int n = fmBody_GetVertexCount(body);
	double* rest = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(rest, fmTestPositions(body), sizeof(double) * 3 * (size_t)n);
	fmTestBarOnRollers(body, rest, 1.0, stretch, true);
	CHECK_INT(fmBody_SolveStatic(body, 1e-10, 50, NULL, NULL), fm_ok);
	free(rest);
	return body;
}

// Plastic strain colours: a bar stretched past yield on rollers (uniform plastic strain alpha)
// is drawn in the ramp's colour of alpha at every vertex; an elastic body in its zero colour.
TEST(plastic_colours_follow_the_plastic_strain)
{
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	m.plasticity.yieldStress = 1e3;
	fmWorldId world;
	fmSeen seen;
	fmDebugDraw draw;
	fmBodyId body = stretchedAndDrawn(failures_, m, fm_drawPlastic, 1.05, &world, &seen, &draw);
	if (!fmBody_IsValid(body))
		return;
	double alpha = fmBody_GetStats(body).plasticStrain;
	CHECK(alpha > 0.03);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	float expected[3];
	fmStrainColor(alpha / FM_DRAW_FULL_STRAIN, expected);
	CHECK(allColoursAre(&seen, expected, 1e-4f));
	freeSeen(&seen);
	fmDestroyWorld(world);
}

// Damage colours: a tearing box at rest is drawn in the ramp's zero colour; stretched on
// rollers, every vertex in the colour of the largest damage (traction over strength,
// fmBody_ComputeDamage) of the tets around it.
TEST(damage_colours_follow_the_traction_over_strength)
{
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	m.fracture.strength = 1e6; // (nothing tears: the colours are what is read)
	fmWorldId world;
	fmSeen seen;
	fmDebugDraw draw;
	fmBodyId body = stretchedAndDrawn(failures_, m, fm_drawDamage, 1.2, &world, &seen, &draw);
	if (!fmBody_IsValid(body))
		return;
	int tets = fmBody_GetTetCount(body);
	double* tetDamage = malloc(sizeof(double) * (size_t)tets);
	double damage = fmBody_ComputeDamage(body, tetDamage);
	CHECK(damage > 0.05 && damage < 1.0);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	const int* corners = fmBody_GetTets(body);
	int wrong = 0, atMost = 0;
	for (int v = 0; v < seen.vertexCount; ++v)
	{
		double worst = 0.0;
		for (int e = 0; e < 4 * tets; ++e)
			if (corners[e] == seen.vertices[v])
				worst = fmax(worst, tetDamage[e / 4]);
		float expected[3];
		fmStrainColor(worst, expected);
		for (int c = 0; c < 3; ++c)
			wrong += fabsf(seen.colors[3 * v + c] - expected[c]) > 1e-4f;
		atMost += worst == damage;
	}
	CHECK_INT(wrong, 0);
	CHECK(atMost > 0);
	free(tetDamage);
	freeSeen(&seen);
	fmDestroyWorld(world);
}

// The first draw makes a body's buffers; later draws reuse them.
TEST(second_draw_allocates_nothing)
{
	fmWorldId world;
	fmBodyId body = fmTestMakeHouse(&world, NULL, NULL);
	if (!fmBody_IsValid(body))
		return;
	fmSeen seen;
	fmDebugDraw draw = drawInto(&seen, fm_drawAll);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 10), fm_ok); // the step's own buffers
	size_t before = fmGetAllocatedBytes();
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	size_t first = fmGetAllocatedBytes();
	CHECK(first > before);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 10), fm_ok);
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK(fmGetAllocatedBytes() == first);
	freeSeen(&seen);
	fmDestroyWorld(world);
}

// The profile: stages measured, none longer than the step.
TEST(profile_measures_the_stages)
{
	const fmIntegrator integrators[2] = {fm_explicit, fm_implicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef def = fmDefaultWorldDef();
		def.integrator = integrators[k];
		fmWorldId world;
		fmBodyId body = fmTestMakeHouse(&world, &def, NULL);
		if (!fmBody_IsValid(body))
			return;
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrators[k] == fm_explicit ? 10 : 1), fm_ok);
		fmProfile p = fmWorld_GetProfile(world);
		CHECK(p.step > 0.0);
		double first = integrators[k] == fm_explicit ? p.forces : p.solve;
		double second = integrators[k] == fm_explicit ? p.integrate : p.finish;
		CHECK(first > 0.0 && second > 0.0 && p.check > 0.0);
		CHECK(first + second + p.check <= p.step);
		fmDestroyWorld(world);
	}
}

// What a collider batch must be: every vertex on the shape's surface (to float precision), its
// normal the shape's outward normal there, and every triangle wound counter-clockwise from
// outside.
typedef struct fmColliderSeen
{
	const fmCollider* colliders[8];
	int batches;
	int planes;
	double worstDistance; // m
	double worstNormal;   // 1 - cos of the angle to a round shape's normal
	int inward;           // triangles wound the wrong way
} fmColliderSeen;

static void seeColliderTriangles(const fmDrawTriangles* t, void* context)
{
	fmColliderSeen* s = context;
	if (t->collider.index1 == 0 || t->vertices != NULL || t->body.index1 != 0)
		return;
	const fmCollider* c = s->colliders[t->collider.index1 - 1];
	s->batches += 1;
	for (int k = 0; k < t->vertexCount; ++k)
	{
		fmVec3 p =
		    fmMakeVec3(t->positions[3 * k], t->positions[3 * k + 1], t->positions[3 * k + 2]);
		fmVec3 m = fmMakeVec3(t->normals[3 * k], t->normals[3 * k + 1], t->normals[3 * k + 2]), n;
		double d = fmCollider_Distance(c, p, &n);
		s->worstDistance = fmax(s->worstDistance, fabs(d));
		// Round shapes: the exact normal (flat shapes carry their faces' normals, which the
		// winding test below checks)
		if (c->def.shape == fm_shapeSphere || c->def.shape == fm_shapeCapsule)
			s->worstNormal = fmax(s->worstNormal, 1.0 - fmDot(m, n));
	}
	for (int k = 0; k < t->triangleCount; ++k)
	{
		const int* i = t->indices + 3 * k;
		fmVec3 p[3], m = fmMakeVec3(0.0, 0.0, 0.0);
		for (int e = 0; e < 3; ++e)
		{
			p[e] = fmMakeVec3(t->positions[3 * i[e]], t->positions[3 * i[e] + 1],
			                  t->positions[3 * i[e] + 2]);
			m = fmAdd(m, fmMakeVec3(t->normals[3 * i[e]], t->normals[3 * i[e] + 1],
			                        t->normals[3 * i[e] + 2]));
		}
		fmVec3 face = fmCross(fmSub(p[1], p[0]), fmSub(p[2], p[0]));
		s->inward += fmLength(face) > 1e-12 && fmDot(face, m) <= 0.0;
	}
}

static void seeColliderPlane(fmVec3 point, fmVec3 normal, fmHexColor color, void* context)
{
	(void)point, (void)normal, (void)color;
	((fmColliderSeen*)context)->planes += 1;
}

// Colliders of every shape, turned and moved, are drawn where they are.
TEST(colliders_are_drawn_as_their_shapes)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmVec3 vertices[4] = {fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0), fmMakeVec3(0, 1, 0),
	                      fmMakeVec3(0, 0, 1)};
	int triangles[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}; // a closed tetrahedron
	fmColliderDef defs[5];
	for (int k = 0; k < 5; ++k)
	{
		defs[k] = fmDefaultColliderDef();
		defs[k].shape = (fmShapeType)k;
		defs[k].center = fmMakeVec3(1.0 + k, -0.5, 0.25 * k);
		defs[k].rotation = fmMakeVec3(0.2, 0.5, -0.3);
	}
	defs[2].halfExtents = fmMakeVec3(0.3, 0.2, 0.1);
	defs[3].a = fmMakeVec3(-1.0, 0.0, 0.5);
	defs[3].b = fmMakeVec3(0.0, 1.0, 0.0);
	defs[3].radius = 0.25;
	defs[4].vertices = vertices;
	defs[4].vertexCount = 4;
	defs[4].triangles = triangles;
	defs[4].triangleCount = 4;
	fmColliderSeen seen;
	memset(&seen, 0, sizeof seen);
	fmWorld* w = fmGetWorld(world);
	for (int k = 0; k < 5; ++k)
	{
		fmColliderId id;
		CHECK_INT(fmCreateCollider(world, &defs[k], &id, NULL), fm_ok);
		seen.colliders[k] = &w->colliders[id.index1 - 1];
	}
	fmDebugDraw draw = fmDefaultDebugDraw();
	draw.flags = fm_drawColliders;
	draw.drawTriangles = seeColliderTriangles;
	draw.drawPlane = seeColliderPlane;
	draw.context = &seen;
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	printf("  %d batches and %d plane: vertices within %.1e m of the shapes, normals within "
	       "%.1e of theirs, %d triangles wound inward\n",
	       seen.batches, seen.planes, seen.worstDistance, seen.worstNormal, seen.inward);
	CHECK_INT(seen.batches, 4);
	CHECK_INT(seen.planes, 1);
	CHECK(seen.worstDistance < 1e-6);
	CHECK(seen.worstNormal < 1e-5);
	CHECK_INT(seen.inward, 0);
	fmDestroyWorld(world);
}

// Contacts are drawn as points and, from each, a line along its normal as long as its share of
// the frame's strongest contact (at least a fifth) of 8% of the largest body: a box resting on
// a ground collider shows lines pointing up from the ground, none longer than 8% of its size.
// fmWorld_Draw with @p flags into only a lines and a points callback.
static fmResult drawLinesAndPoints(fmWorldId world, unsigned flags,
                                   void (*lines)(const float*, int, fmHexColor, void*),
                                   void (*points)(const float*, int, float, fmHexColor, void*),
                                   void* context)
{
	fmDebugDraw draw;
	memset(&draw, 0, sizeof draw);
	draw.drawLines = lines;
	draw.drawPoints = points;
	draw.flags = flags;
	draw.context = context;
	return fmWorld_Draw(world, &draw);
}

typedef struct ContactLines
{
	float points[3 * 256], lines[6 * 256];
	int pointCount, lineCount;
} ContactLines;

static void keepContactPoints(const float* points, int count, float size, fmHexColor color,
                              void* context)
{
	(void)size, (void)color;
	ContactLines* c = context;
	for (int k = 0; k < count && c->pointCount < 256; ++k)
		memcpy(c->points + 3 * c->pointCount++, points + 3 * k, 3 * sizeof(float));
}

static void keepContactLines(const float* points, int count, fmHexColor color, void* context)
{
	(void)color;
	ContactLines* c = context;
	for (int k = 0; k < count && c->lineCount < 256; ++k)
		memcpy(c->lines + 6 * c->lineCount++, points + 6 * k, 6 * sizeof(float));
}

TEST(contacts_are_drawn_with_their_normals)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef ground = fmDefaultColliderDef(); // the plane y = 0
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &ground, &id, NULL), fm_ok);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(0, 0.05, 0), fmMakeVec3(1, 1.05, 1), &mesh), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	for (int f = 0; f < 60; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	ContactLines seen;
	memset(&seen, 0, sizeof seen);
	CHECK_INT(
	    drawLinesAndPoints(world, fm_drawContacts, keepContactLines, keepContactPoints, &seen),
	    fm_ok);
	printf("  %d contact points, %d lines\n", seen.pointCount, seen.lineCount);
	CHECK(seen.pointCount > 0);
	CHECK_INT(seen.lineCount, seen.pointCount);
	double size = sqrt(3.0), longest = 0.0;
	for (int k = 0; k < seen.lineCount; ++k)
	{
		const float* l = seen.lines + 6 * k;
		CHECK(l[0] == seen.points[3 * k] && l[1] == seen.points[3 * k + 1] &&
		      l[2] == seen.points[3 * k + 2]);
		double dx = l[3] - l[0], dy = l[4] - l[1], dz = l[5] - l[2];
		double length = sqrt(dx * dx + dy * dy + dz * dz);
		longest = fmax(longest, length);
		CHECK(dy > 0.99 * length); // up, out of the ground
		CHECK(length >= 0.2 * 0.08 * size * 0.999 && length <= 0.08 * size * 1.001);
	}
	CHECK_NEAR(longest, 0.08 * size, 1e-6);
	fmDestroyWorld(world);
}

// A grab is drawn with the targets: a line from the grabbed point to the pointer's target and
// both ends as 12-pixel points, in the grab's colour (it showed as short target lines under the
// patch and 6-pixel dots).
typedef struct GrabSeen
{
	float line[6];
	int lines, points;
	float pointSize;
} GrabSeen;

static void grabLines(const float* points, int count, fmHexColor color, void* context)
{
	GrabSeen* g = context;
	if (color == 0xff40c0u && count == 1)
		memcpy(g->line, points, sizeof g->line), g->lines += 1;
}

static void grabPoints(const float* points, int count, float size, fmHexColor color, void* context)
{
	(void)points;
	GrabSeen* g = context;
	if (color == 0xff40c0u)
		g->points += count, g->pointSize = size;
}

TEST(a_grab_is_drawn_as_its_spring)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	fmWorldId world;
	fmBodyId body = fmTestMakeHouse(&world, &wdef, NULL);
	const double* x = fmTestPositions(body);
	fmVec3 at = fmMakeVec3(x[0], x[1], x[2]);
	fmGrabDef def = fmDefaultGrabDef();
	CHECK_INT(fmBody_Grab(body, at, &def), fm_ok);
	CHECK_INT(fmBody_MoveGrab(body, fmAdd(at, fmMakeVec3(0.0, 1.0, 0.0))), fm_ok);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 10), fm_ok);
	GrabSeen seen;
	memset(&seen, 0, sizeof seen);
	CHECK_INT(drawLinesAndPoints(world, fm_drawTargets, grabLines, grabPoints, &seen), fm_ok);
	fmVec3 point, target;
	CHECK(fmBody_GetGrab(body, &point, &target));
	CHECK_INT(seen.lines, 1);
	CHECK_INT(seen.points, 2);
	CHECK(seen.pointSize == 12.0f);
	CHECK_NEAR(seen.line[3], target.x, 1e-5);
	CHECK_NEAR(seen.line[4], target.y, 1e-5);
	CHECK_NEAR(seen.line[1], point.y, 1e-5);
	fmDestroyWorld(world);
}
