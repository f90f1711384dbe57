// Triangle-mesh colliders (src/contact/mesh_collider.c): a closed box mesh has the analytic box's
// signed distance and normals everywhere (inside, outside, at edges and corners, rotated and
// moved); an open ground is solid below; segment casts are exact; a house dropped on a mesh
// ramp rests on it; a fast body does not pass through a thin mesh wall; rays hit meshes.
#include "support.h"
#include "test.h"

#include "contact/collider.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The 8 corners and 12 outward counter-clockwise triangles of the box [-h, h].
static void boxMesh(fmVec3 h, fmVec3 vertices[8], int triangles[36])
{
	for (int i = 0; i < 8; ++i)
		vertices[i] = fmMakeVec3(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
	const int faces[36] = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5,  // -x, +x
	                       0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3,  // -y, +y
	                       0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6}; // -z, +z
	memcpy(triangles, faces, sizeof faces);
}

static fmCollider* colliderOf(fmWorldId world, fmColliderId id)
{
	fmWorld* w = fmGetWorld(world);
	return w ? &w->colliders[id.index1 - 1] : NULL;
}

// A closed box mesh, turned and moved, against the analytic box at random points (a third of
// them within 1 mm of the surface, where edges and corners decide the sign).
TEST(closed_mesh_matches_the_analytic_box)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmVec3 h = fmMakeVec3(0.5, 0.2, 0.3), vertices[8];
	int triangles[36];
	boxMesh(h, vertices, triangles);
	fmColliderDef box = fmDefaultColliderDef();
	box.shape = fm_shapeBox;
	box.center = fmMakeVec3(1.0, 2.0, -0.5);
	box.rotation = fmMakeVec3(0.3, -0.7, 0.4);
	box.halfExtents = h;
	fmColliderDef mesh = box;
	mesh.shape = fm_shapeMesh;
	mesh.vertices = vertices;
	mesh.vertexCount = 8;
	mesh.triangles = triangles;
	mesh.triangleCount = 12;
	fmColliderId boxId, meshId;
	CHECK_INT(fmCreateCollider(world, &box, &boxId, NULL), fm_ok);
	CHECK_INT(fmCreateCollider(world, &mesh, &meshId, NULL), fm_ok);
	memset(vertices, 0, sizeof vertices); // the collider keeps a copy
	const fmCollider* a = colliderOf(world, boxId);
	const fmCollider* b = colliderOf(world, meshId);
	double worstDistance = 0.0, worstNormal = 0.0;
	int inside = 0;
	for (int k = 0; k < 30000; ++k)
	{
		fmVec3 local =
		    fmMakeVec3(fmTestRandom(-1.0, 1.0), fmTestRandom(-1.0, 1.0), fmTestRandom(-1.0, 1.0));
		if (k % 3 == 0) // onto the surface, then 1 mm off it either way
		{
			fmVec3 n, p = fmAdd(box.center, local);
			double d = fmCollider_Distance(a, p, &n);
			local = fmSub(fmMulAdd(p, -d + fmTestRandom(-1e-3, 1e-3), n), box.center);
		}
		fmVec3 p = fmAdd(box.center, local), na, nb;
		double da = fmCollider_Distance(a, p, &na), db = fmCollider_Distance(b, p, &nb);
		inside += da < 0.0;
		worstDistance = fmax(worstDistance, fabs(da - db));
		if (fabs(da) > 1e-6)
			worstNormal = fmax(worstNormal, fmLength(fmSub(na, nb)));
	}
	printf("  30000 points (%d inside): distances agree to %.1e m, normals to %.1e\n", inside,
	       worstDistance, worstNormal);
	CHECK(inside > 3000);
	CHECK(worstDistance < 1e-12);
	CHECK(worstNormal < 1e-9);
	fmDestroyWorld(world);
}

// An open ground: a grid of 2 x 2 m squares at y = 0.1 x. Points above
// are outside, points below inside, and a segment from above enters where the plane says.
TEST(open_ground_is_solid_below)
{
	enum
	{
		N = 8
	};
	fmVec3 vertices[(N + 1) * (N + 1)];
	int triangles[6 * N * N], t = 0;
	for (int i = 0; i <= N; ++i)
		for (int j = 0; j <= N; ++j)
		{
			double x = -8.0 + 2.0 * i, z = -8.0 + 2.0 * j;
			vertices[i * (N + 1) + j] = fmMakeVec3(x, 0.1 * x, z);
		}
	for (int i = 0; i < N; ++i)
		for (int j = 0; j < N; ++j)
		{
			int a = i * (N + 1) + j, b = a + 1, c = a + N + 1, d = c + 1;
			// counter-clockwise seen from above (+y)
			int quad[6] = {a, b, d, a, d, c};
			memcpy(triangles + t, quad, sizeof quad);
			t += 6;
		}
	fmWorldDef wdef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = fm_shapeMesh;
	def.vertices = vertices;
	def.vertexCount = (N + 1) * (N + 1);
	def.triangles = triangles;
	def.triangleCount = 2 * N * N;
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &def, &id, NULL), fm_ok);
	const fmCollider* c = colliderOf(world, id);
	fmVec3 up = fmScale(1.0 / sqrt(1.01), fmMakeVec3(-0.1, 1.0, 0.0)), n;
	double worst = 0.0;
	for (int k = 0; k < 2000; ++k)
	{
		fmVec3 p =
		    fmMakeVec3(fmTestRandom(-7.0, 7.0), fmTestRandom(-1.0, 1.0), fmTestRandom(-7.0, 7.0));
		double expected = fmDot(up, fmSub(p, fmMakeVec3(p.x, 0.1 * p.x, p.z)));
		double d = fmCollider_Distance(c, p, &n);
		worst = fmax(worst, fabs(d - expected) + fmLength(fmSub(n, up)));
	}
	printf("  2000 points within 1 m of the ground: distance and normal off by %.1e\n", worst);
	CHECK(worst < 1e-9);
	double fraction = -1.0;
	CHECK(fmCollider_CastSegment(c, fmMakeVec3(1.0, 2.0, 1.0), fmMakeVec3(1.0, -2.0, 1.0), 0.0,
	                             &fraction, &n));
	CHECK_NEAR(fraction, (2.0 - 0.1) / 4.0, 1e-12);
	// From below (inside), a segment leaving through the back is no entry.
	CHECK(!fmCollider_CastSegment(c, fmMakeVec3(1.0, -2.0, 1.0), fmMakeVec3(1.0, 2.0, 1.0), 0.0,
	                              &fraction, &n));
	// Rays hit it from above with the face's normal.
	fmRayHit hit;
	CHECK(fmWorld_CastRay(world, fmMakeVec3(3.0, 5.0, 0.5), fmMakeVec3(0.0, -10.0, 0.0),
	                      fmDefaultFilter(), &hit));
	CHECK_NEAR(hit.point.y, 0.3, 1e-9);
	CHECK_NEAR(fmDot(hit.normal, up), 1.0, 1e-12);
	CHECK(hit.collider.index1 == id.index1);
	fmDestroyWorld(world);
}

// A ramp of 20 degrees made of two triangles (an open mesh, friction 0.8 > tan 20 = 0.36) catches a
// house set down on it (4 m tall, 5 cm above it): after 4 s no vertex is below the ramp beyond 1
// mm, it is at rest, and it is still on the ramp (not on the floor). Both integrators.
TEST(house_rests_on_a_mesh_ramp)
{
	const double angle = 20.0 * 3.14159265358979 / 180.0, slope = tan(angle);
	fmVec3 vertices[4] = {fmMakeVec3(-4.0, -4.0 * slope, -4.0), fmMakeVec3(4.0, 4.0 * slope, -4.0),
	                      fmMakeVec3(4.0, 4.0 * slope, 4.0), fmMakeVec3(-4.0, -4.0 * slope, 4.0)};
	int triangles[6] = {0, 2, 1, 0, 3, 2}; // counter-clockwise from above
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_implicit;
		fmWorldId world = fmCreateWorld(&wdef);
		fmColliderDef ramp = fmDefaultColliderDef();
		ramp.shape = fm_shapeMesh;
		ramp.vertices = vertices;
		ramp.vertexCount = 4;
		ramp.triangles = triangles;
		ramp.triangleCount = 2;
		ramp.friction = 0.8;
		fmColliderId id;
		CHECK_INT(fmCreateCollider(world, &ramp, &id, NULL), fm_ok);
		fmBodyDef def = fmDefaultBodyDef();
		def.material = fmMakeMaterial(fm_neoHookean, 3e6, 0.3);
		def.massMode = fm_massFromDensity;
		def.density = 500.0;
		def.smoothing = 0.0;
		fmTetMesh mesh;
		CHECK(fmTestHouseMesh(&mesh, fmMakeVec3(0.0, 0.0, 0.0)));
		// Turned to stand on the ramp, its floor 5 cm above it.
		double lowest = INFINITY;
		for (int i = 0; i < mesh.nodeCount; ++i)
			lowest = fmin(lowest, mesh.positions[3 * i + 1]);
		for (int i = 0; i < mesh.nodeCount; ++i)
		{
			double* p = mesh.positions + 3 * i;
			double x = p[0], y = p[1] - lowest + 0.05;
			p[0] = x * cos(angle) - y * sin(angle);
			p[1] = x * sin(angle) + y * cos(angle);
		}
		def.mesh = &mesh;
		fmBodyId house;
		CHECK_INT(fmCreateBody(world, &def, &house, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		int failed = 0;
		for (int f = 0; f < 240; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		}
		const double* x = fmTestPositions(house);
		double below = 0.0;
		for (int i = 0; i < fmBody_GetVertexCount(house); ++i)
			below = fmax(below, (slope * x[3 * i] - x[3 * i + 1]) / sqrt(1.0 + slope * slope));
		fmBodyStats stats = fmBody_GetStats(house);
		double total = 0.0;
		for (int i = 0; i < fmBody_GetVertexCount(house); ++i)
			total += fmBody_GetMasses(house)[i];
		double speed = sqrt(2.0 * stats.kineticEnergy / total);
		printf("  %d failed frames, deepest vertex %.2e m below the ramp, rms speed %.3f m/s, "
		       "lowest y %.3f\n",
		       failed, below, speed, stats.lowestY);
		CHECK_INT(failed, 0);
		CHECK(below < 1e-3);
		CHECK(speed < 0.05);
		CHECK(stats.lowestY > -2.0); // the floor is at -3
		fmDestroyWorld(world);
	}
}

// A body at 10 m/s against a 1 cm thick wall made of triangles (a closed box mesh), one
// implicit step a frame: it stops on its side.
TEST(no_tunnelling_through_a_thin_mesh)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	fmWorldId world = fmCreateWorld(&wdef);
	fmVec3 vertices[8];
	int triangles[36];
	boxMesh(fmMakeVec3(0.005, 1.0, 1.0), vertices, triangles);
	fmColliderDef wall = fmDefaultColliderDef();
	wall.shape = fm_shapeMesh;
	wall.center = fmMakeVec3(0.5, 0.0, 0.0);
	wall.vertices = vertices;
	wall.vertexCount = 8;
	wall.triangles = triangles;
	wall.triangleCount = 12;
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &wall, &id, NULL), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	fmTetMesh mesh;
	CHECK_INT(
	    fmMakeBoxMesh(3, 3, 3, fmMakeVec3(-0.2, -0.1, -0.1), fmMakeVec3(0.0, 0.1, 0.1), &mesh),
	    fm_ok);
	def.mesh = &mesh;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &def, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	int n = fmBody_GetVertexCount(body);
	double* v = calloc(3 * (size_t)n, sizeof(double));
	for (int i = 0; i < n; ++i)
		v[3 * i] = 10.0;
	fmBody_SetVelocities(body, v);
	free(v);
	for (int f = 0; f < 30; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	const double* x = fmTestPositions(body);
	double farthest = -INFINITY;
	for (int i = 0; i < n; ++i)
		farthest = fmax(farthest, x[3 * i]);
	printf("  farthest vertex at x = %.4f (the wall's near face at 0.495)\n", farthest);
	CHECK(farthest < 0.495 + 1e-9);
	fmDestroyWorld(world);
}

// Bad meshes are refused with what was expected.
TEST(bad_meshes_are_refused)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmVec3 vertices[3] = {fmMakeVec3(0, 0, 0), fmMakeVec3(1, 0, 0), fmMakeVec3(0, 0, 1)};
	int triangles[3] = {0, 1, 3};
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = fm_shapeMesh;
	def.vertices = vertices;
	def.vertexCount = 3;
	def.triangles = triangles;
	def.triangleCount = 1;
	fmColliderId id;
	fmDiagnostic diag;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "triangle corners in [0, vertexCount)") != NULL);
	triangles[2] = 2;
	vertices[1].y = NAN;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "finite vertices") != NULL);
	vertices[1].y = 0.0;
	def.triangles = NULL;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	def.triangles = triangles;
	def.triangleCount = 0;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	def.triangleCount = 1;
	// Degenerate triangles only: corners on a line, then all at one point (a scale of 1e-300).
	vertices[2] = fmMakeVec3(2, 0, 0);
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "a triangle of some area") != NULL);
	for (int k = 0; k < 3; ++k)
		vertices[k] = fmMakeVec3(1e-300 * k, 0, 0);
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	vertices[1] = fmMakeVec3(1, 0, 0), vertices[2] = fmMakeVec3(0, 0, 1);
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_ok);
	fmDestroyCollider(id);
	CHECK(!fmCollider_IsValid(id));
	fmDestroyWorld(world);
}
