// Moving mesh colliders (src/contact/mesh_motion.c, fmCollider_SetMeshVertices): a ground raised
// by its vertices lifts a soft box with it, a ground whose vertices slide carries one along, the
// surface velocity is the blend of the nearest triangle's vertex velocities (turned with the
// collider), an inflating closed box pushes a body out without letting it in, a snapshot taken
// mid-motion continues bit-identically, and bad vertices are refused with the mesh unchanged.
#include "support.h"
#include "test.h"

#include "contact/collider.h"
#include "contact/contact.h"
#include "contact/mesh_motion.h"
#include "world/snapshot.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum
{
	GRID = 4,                                  // quads a side of the ground
	GROUND_VERTICES = (GRID + 1) * (GRID + 1), // its vertices
	GROUND_TRIANGLES = 2 * GRID * GRID
};

static const double frame = 1.0 / 60.0;

// A ground of GRID x GRID quads over [-1, 1]^2 at y = 0, its fronts facing +y.
static void groundMesh(fmVec3 vertices[GROUND_VERTICES], int triangles[3 * GROUND_TRIANGLES])
{
	int t = 0;
	for (int i = 0; i <= GRID; ++i)
		for (int j = 0; j <= GRID; ++j)
			vertices[i * (GRID + 1) + j] =
			    fmMakeVec3(-1.0 + 2.0 * i / GRID, 0.0, -1.0 + 2.0 * j / GRID);
	for (int i = 0; i < GRID; ++i)
		for (int j = 0; j < GRID; ++j)
		{
			int a = i * (GRID + 1) + j, b = a + 1, c = a + GRID + 1, d = c + 1;
			int quad[6] = {a, b, d, a, d, c}; // counter-clockwise seen from above
			memcpy(triangles + t, quad, sizeof quad);
			t += 6;
		}
}

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

static fmColliderId makeMesh(fmWorldId world, const fmVec3* vertices, int vertexCount,
                             const int* triangles, int triangleCount, bool stick)
{
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = fm_shapeMesh;
	def.vertices = vertices;
	def.vertexCount = vertexCount;
	def.triangles = triangles;
	def.triangleCount = triangleCount;
	def.stick = stick;
	fmColliderId id;
	memset(&id, 0, sizeof id);
	if (fmCreateCollider(world, &def, &id, NULL) != fm_ok)
		fprintf(stderr, "  the mesh collider was refused\n");
	return id;
}

// The ground of groundMesh as a mesh collider of @p world; its vertices (at rest) in @p vertices.
static fmColliderId makeGround(fmWorldId world, fmVec3 vertices[GROUND_VERTICES], bool stick)
{
	int triangles[3 * GROUND_TRIANGLES];
	groundMesh(vertices, triangles);
	return makeMesh(world, vertices, GROUND_VERTICES, triangles, GROUND_TRIANGLES, stick);
}

static fmCollider* colliderOf(fmWorldId world, fmColliderId id)
{
	return &fmGetWorld(world)->colliders[id.index1 - 1];
}

// A soft cube of side 0.2 m (3^3 cells, neo-Hookean, 1e5 Pa, 1000 kg/m^3) over [-0.1, 0.1] in x
// and z, its bottom at @p y.
static fmBodyId makeCube(fmWorldId world, double y)
{
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	fmTetMesh mesh;
	fmBodyId body;
	memset(&body, 0, sizeof body);
	if (fmMakeBoxMesh(3, 3, 3, fmMakeVec3(-0.1, y, -0.1), fmMakeVec3(0.1, y + 0.2, 0.1), &mesh) !=
	    fm_ok)
		return body;
	def.mesh = &mesh;
	if (fmCreateBody(world, &def, &body, NULL) != fm_ok)
		fprintf(stderr, "  the cube was refused\n");
	fmFreeTetMesh(&mesh);
	return body;
}

static fmWorldId groundWorld(fmIntegrator integrator)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = integrator;
	def.floor.enabled = false;
	return fmCreateWorld(&def);
}

// The mean of the body's velocities along @p axis (0 x, 1 y, 2 z).
static double meanVelocity(fmBodyId body, int axis)
{
	const double* v = fmTestVelocities(body);
	int n = fmBody_GetVertexCount(body);
	double sum = 0.0;
	for (int i = 0; i < n; ++i)
		sum += v[3 * i + axis];
	return sum / n;
}

// The lowest vertex's height above @p ground.
static double lowestAbove(fmBodyId body, double ground)
{
	const double* x = fmTestPositions(body);
	double lowest = INFINITY;
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		lowest = fmin(lowest, x[3 * i + 1] - ground);
	return lowest;
}

static int substepsOf(fmIntegrator integrator)
{
	return integrator == fm_explicit ? 20 : 2;
}

// A cube resting on the ground (0.5 s), then the ground's vertices raised at 0.5 m/s for 1 s: the
// cube rides up with it, its mean vertical velocity within 3 % of the ground's over the last
// half second, no vertex ever more than 1 mm below the ground. Both integrators.
TEST(raised_ground_lifts_a_resting_cube)
{
	const fmIntegrator integrators[2] = {fm_explicit, fm_implicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world = groundWorld(integrators[k]);
		fmVec3 vertices[GROUND_VERTICES];
		fmColliderId ground = makeGround(world, vertices, false);
		fmBodyId cube = makeCube(world, 0.0);
		const double speed = 0.5;
		double height = 0.0, deepest = 0.0, riding = 0.0, worstRide = 0.0;
		int failed = 0, sampled = 0;
		for (int f = 0; f < 90; ++f)
		{
			if (f >= 30)
			{
				height += speed * frame;
				for (int i = 0; i < GROUND_VERTICES; ++i)
					vertices[i].y = height;
				CHECK_INT(fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES), fm_ok);
			}
			failed += fmWorld_Step(world, frame, substepsOf(integrators[k])) != fm_ok;
			deepest = fmin(deepest, lowestAbove(cube, height));
			if (f >= 60)
			{
				double v = meanVelocity(cube, 1);
				riding += v;
				worstRide = fmax(worstRide, fabs(v - speed));
				++sampled;
			}
		}
		riding /= sampled;
		printf("  %s: %d failed frames, mean vertical velocity %.4f m/s (ground %.2f; worst frame "
		       "off by %.4f), deepest vertex %.2e m below the ground\n",
		       k == 0 ? "explicit" : "implicit", failed, riding, speed, worstRide, -deepest);
		CHECK_INT(failed, 0);
		CHECK_REL(riding, speed, 0.03, 0.0);
		CHECK(deepest > -1e-3);
		fmDestroyWorld(world);
	}
}

// Ground whose vertices slide along x at 0.3 m/s under a resting cube (a stick collider and a
// Coulomb one of friction 1): the cube is carried, its mean x velocity within 3 % of the ground's
// over the last half second, while the collider's own velocity stays zero. Both integrators.
TEST(sliding_ground_carries_a_resting_cube)
{
	for (int k = 0; k < 4; ++k)
	{
		fmIntegrator integrator = k < 2 ? fm_explicit : fm_implicit;
		bool stick = k % 2 == 0;
		fmWorldId world = groundWorld(integrator);
		fmVec3 vertices[GROUND_VERTICES];
		fmColliderId ground = makeGround(world, vertices, stick);
		colliderOf(world, ground)->def.friction = 1.0;
		fmBodyId cube = makeCube(world, 0.0);
		const double speed = 0.3;
		double carried = 0.0;
		int failed = 0, sampled = 0;
		for (int f = 0; f < 90; ++f)
		{
			if (f >= 30)
			{
				for (int i = 0; i < GROUND_VERTICES; ++i)
					vertices[i].x += speed * frame;
				CHECK_INT(fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES), fm_ok);
			}
			failed += fmWorld_Step(world, frame, substepsOf(integrator)) != fm_ok;
			if (f >= 60)
			{
				carried += meanVelocity(cube, 0);
				++sampled;
			}
		}
		carried /= sampled;
		printf("  %s, %s: %d failed frames, mean x velocity %.4f m/s (ground %.2f)\n",
		       integrator == fm_explicit ? "explicit" : "implicit", stick ? "stick" : "friction 1",
		       failed, carried, speed);
		CHECK_INT(failed, 0);
		CHECK_REL(carried, speed, 0.03, 0.0);
		fmDestroyWorld(world);
	}
}

typedef struct VelocityProbe
{
	fmWorldId world;
	fmColliderId collider;
	fmVec3 point;    // where the velocity is asked (world frame)
	fmVec3 velocity; // fmCollider_VelocityAt there in the last substep
	int substeps;
	int busy; // fmCollider_SetMeshVertices refused with fm_errBusy in a substep
} VelocityProbe;

static void probeVelocity(int substep, double time, void* context)
{
	(void)substep;
	(void)time;
	VelocityProbe* p = context;
	const fmCollider* c = colliderOf(p->world, p->collider);
	p->velocity = fmCollider_VelocityAt(c, p->point);
	p->busy += fmCollider_SetMeshVertices(p->collider, c->mesh->vertices, c->mesh->vertexCount) ==
	           fm_errBusy;
	++p->substeps;
}

// A turned ground (a quarter turn about z: its fronts face -x) stretched about its centre: each
// vertex moves at a (x, 0, z) / s in its own frame, so the surface's velocity is that linear field
// at the nearest point, turned. fmCollider_VelocityAt inside the frame's substeps gives it to
// round-off at points off the vertices and off the surface; zero after the frame, and again when
// no new vertices are set (a mesh that is not updated stops). Setting vertices within the step
// (its substep callback) is refused with fm_errBusy.
TEST(surface_velocity_blends_the_vertex_velocities)
{
	fmWorldDef def = fmTestFreeWorldDef();
	VelocityProbe probe;
	memset(&probe, 0, sizeof probe);
	def.substepCallback = probeVelocity;
	def.substepContext = &probe;
	fmWorldId world = fmCreateWorld(&def);
	fmVec3 rest[GROUND_VERTICES], vertices[GROUND_VERTICES];
	int triangles[3 * GROUND_TRIANGLES];
	groundMesh(rest, triangles);
	fmColliderDef cdef = fmDefaultColliderDef();
	cdef.shape = fm_shapeMesh;
	cdef.vertices = rest;
	cdef.vertexCount = GROUND_VERTICES;
	cdef.triangles = triangles;
	cdef.triangleCount = GROUND_TRIANGLES;
	cdef.center = fmMakeVec3(2.0, 1.0, 0.0);
	cdef.rotation = fmMakeVec3(0.0, 0.0, 0.5 * 3.14159265358979323846);
	CHECK_INT(fmCreateCollider(world, &cdef, &probe.collider, NULL), fm_ok);
	probe.world = world;
	makeCube(world, 5.0);                              // a body to step, far away
	const double rate = 0.6;                           // 1/s
	const fmVec3 local = fmMakeVec3(0.37, 0.2, -0.55); // above the ground, off its vertices
	const fmCollider* c = colliderOf(world, probe.collider);
	for (int i = 0; i < GROUND_VERTICES; ++i)
		vertices[i] =
		    fmMakeVec3(rest[i].x * (1.0 + rate * frame), 0.0, rest[i].z * (1.0 + rate * frame));
	CHECK_INT(fmCollider_SetMeshVertices(probe.collider, vertices, GROUND_VERTICES), fm_ok);
	probe.point = fmAdd(c->position, fmMatVec(&c->rotation, local));
	CHECK_INT(fmWorld_Step(world, frame, 4), fm_ok);
	// The nearest point is below `local` on the ground, which in the last substep has reached
	// its target: the vertices' velocities are rate times their rest positions, a linear field.
	double grown = 1.0 + rate * frame; // a point's rest position is where it is over this
	fmVec3 expected =
	    fmMatVec(&c->rotation, fmMakeVec3(rate * local.x / grown, 0.0, rate * local.z / grown));
	double error = fmLength(fmSub(probe.velocity, expected));
	fmVec3 after = fmCollider_VelocityAt(c, probe.point);
	printf("  %d substeps: velocity (%.6f, %.6f, %.6f), expected (%.6f, %.6f, %.6f), off by "
	       "%.1e; after the frame |v| = %.1e\n",
	       probe.substeps, probe.velocity.x, probe.velocity.y, probe.velocity.z, expected.x,
	       expected.y, expected.z, error, fmLength(after));
	CHECK_INT(probe.substeps, 4);
	CHECK_INT(probe.busy, 4);
	CHECK(error < 1e-12);
	CHECK(fmLength(after) == 0.0);
	CHECK(fmCollider_SweepSpeed(c) == 0.0);
	// Not set again: the next frame does not move it.
	CHECK_INT(fmWorld_Step(world, frame, 4), fm_ok);
	CHECK(fmLength(probe.velocity) == 0.0);
	CHECK(memcmp(c->mesh->vertices, vertices, sizeof vertices) == 0);
	fmDestroyWorld(world);
}

// A closed box mesh (12 triangles, half side 0.3 m) under a resting cube inflates by half its
// size over a second: the cube is pushed up with the top face (half a second after, its lowest
// vertex on the face at 0.45 m: at most 1 mm below, less than the contact thickness above, the
// implicit barrier's gap) and no vertex of it is ever inside the box by more than 1 mm.
// Both integrators.
TEST(inflating_closed_mesh_pushes_a_body_out)
{
	for (int k = 0; k < 2; ++k)
	{
		fmIntegrator integrator = k == 0 ? fm_explicit : fm_implicit;
		fmWorldId world = groundWorld(integrator);
		fmVec3 rest[8], vertices[8];
		int triangles[36];
		boxMesh(fmMakeVec3(0.3, 0.3, 0.3), rest, triangles);
		fmColliderId box = makeMesh(world, rest, 8, triangles, 12, false);
		const fmCollider* c = colliderOf(world, box);
		fmBodyId cube = makeCube(world, 0.3);
		int n = fmBody_GetVertexCount(cube), failed = 0;
		double deepest = INFINITY;
		for (int f = 0; f < 120; ++f)
		{
			double scale = 1.0 + 0.5 * fmin(fmax(f - 29, 0), 60) / 60.0;
			for (int i = 0; i < 8; ++i)
				vertices[i] = fmScale(scale, rest[i]);
			if (f >= 30 && f < 90)
				CHECK_INT(fmCollider_SetMeshVertices(box, vertices, 8), fm_ok);
			failed += fmWorld_Step(world, frame, substepsOf(integrator)) != fm_ok;
			const double* x = fmTestPositions(cube);
			for (int i = 0; i < n; ++i)
			{
				fmVec3 normal;
				fmVec3 p = fmMakeVec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
				deepest = fmin(deepest, fmCollider_Distance(c, p, &normal));
			}
		}
		double lowest = lowestAbove(cube, 0.45), gap = fmContact_Thickness(fmGetWorld(world));
		printf("  %s: %d failed frames, deepest vertex %.2e m inside, lowest vertex %.2e m above "
		       "the inflated top (contact thickness %.2e m)\n",
		       integrator == fm_explicit ? "explicit" : "implicit", failed, -deepest, lowest, gap);
		CHECK_INT(failed, 0);
		CHECK(deepest > -1e-3);
		CHECK(lowest > -1e-3 && lowest < gap);
		fmDestroyWorld(world);
	}
}

// The ground's vertices at frame @p f of the snapshot test: a travelling wave.
static void waveGround(const fmVec3* rest, fmVec3* vertices, int f)
{
	for (int i = 0; i < GROUND_VERTICES; ++i)
	{
		vertices[i] = rest[i];
		vertices[i].y = 0.05 * sin(3.0 * rest[i].x - 0.2 * f) + 0.004 * f;
	}
}

// Steps frames [first, last) of the snapshot test, setting the wave's vertices before each.
static bool runWave(fmWorldId world, fmColliderId ground, const fmVec3* rest, int first, int last,
                    int substeps)
{
	fmVec3 vertices[GROUND_VERTICES];
	bool ok = true;
	for (int f = first; f < last; ++f)
	{
		waveGround(rest, vertices, f);
		ok = fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES) == fm_ok && ok;
		fmResult r = fmWorld_Step(world, frame, substeps);
		if (r != fm_ok)
			printf("  frame %d: %s\n", f, fmWorld_GetLastError(world)->message);
		ok = r == fm_ok && ok;
	}
	return ok;
}

// A cube on a ground moved by a wave, implicit and explicit: a snapshot taken after 20 frames, its
// next target already set, continues bit-identically (positions, velocities, the ground's
// vertices) after 20 more frames; one taken before the ground ever moved puts it back to its
// creation shape and replays the same run bit for bit.
TEST(snapshot_mid_motion_continues_bit_identically)
{
	for (int k = 0; k < 2; ++k)
	{
		fmIntegrator integrator = k == 0 ? fm_implicit : fm_explicit;
		int substeps = substepsOf(integrator);
		fmWorldId world = groundWorld(integrator);
		fmVec3 rest[GROUND_VERTICES], next[GROUND_VERTICES];
		fmColliderId ground = makeGround(world, rest, false);
		const fmMeshShape* m = colliderOf(world, ground)->mesh;
		fmBodyId cube = makeCube(world, 0.06);
		int n3 = 3 * fmBody_GetVertexCount(cube);
		size_t startSize = fmWorld_GetSnapshotSize(world);
		void* start = malloc(startSize);
		CHECK_INT(fmWorld_SaveSnapshot(world, start, startSize, NULL), fm_ok);
		CHECK(runWave(world, ground, rest, 0, 20, substeps));
		waveGround(rest, next, 20);
		CHECK_INT(fmCollider_SetMeshVertices(ground, next, GROUND_VERTICES), fm_ok);
		size_t size = fmWorld_GetSnapshotSize(world);
		void* middle = malloc(size);
		CHECK_INT(fmWorld_SaveSnapshot(world, middle, size, NULL), fm_ok);
		CHECK_INT(fmWorld_Step(world, frame, substeps), fm_ok);
		CHECK(runWave(world, ground, rest, 21, 40, substeps));
		double* x = malloc(sizeof(double) * 2 * (size_t)n3);
		memcpy(x, fmTestPositions(cube), sizeof(double) * (size_t)n3);
		memcpy(x + n3, fmTestVelocities(cube), sizeof(double) * (size_t)n3);
		fmVec3 ends[GROUND_VERTICES];
		memcpy(ends, m->vertices, sizeof ends);
		// Restored mid-motion: the pending target is kept.
		CHECK_INT(fmWorld_RestoreSnapshot(world, middle, size), fm_ok);
		CHECK_INT(fmWorld_Step(world, frame, substeps), fm_ok);
		CHECK(runWave(world, ground, rest, 21, 40, substeps));
		bool same = memcmp(x, fmTestPositions(cube), sizeof(double) * (size_t)n3) == 0 &&
		            memcmp(x + n3, fmTestVelocities(cube), sizeof(double) * (size_t)n3) == 0 &&
		            memcmp(ends, m->vertices, sizeof ends) == 0;
		// Restored to before any motion: the creation shape, and the same run again.
		CHECK_INT(fmWorld_RestoreSnapshot(world, start, startSize), fm_ok);
		bool back = memcmp(rest, m->vertices, sizeof rest) == 0 && !m->motion->pending;
		CHECK(runWave(world, ground, rest, 0, 20, substeps));
		CHECK_INT(fmCollider_SetMeshVertices(ground, next, GROUND_VERTICES), fm_ok);
		CHECK_INT(fmWorld_Step(world, frame, substeps), fm_ok);
		CHECK(runWave(world, ground, rest, 21, 40, substeps));
		bool replayed = memcmp(x, fmTestPositions(cube), sizeof(double) * (size_t)n3) == 0 &&
		                memcmp(ends, m->vertices, sizeof ends) == 0;
		printf("  %s: back to the creation shape: %s, replayed with the same bits: %s\n",
		       k == 0 ? "implicit" : "explicit", back ? "yes" : "NO", replayed ? "yes" : "NO");
		CHECK(back);
		CHECK(replayed);
		printf("  %s: mid-motion restore continues with the same bits: %s\n",
		       k == 0 ? "implicit" : "explicit", same ? "yes" : "NO");
		CHECK(same);
		free(x);
		free(middle);
		free(start);
		fmDestroyWorld(world);
	}
}

// Refused: a collider that is not a mesh, a NULL array, another vertex count, a NaN vertex, one
// beyond FM_MAX_COORDINATE; each with fm_errParameter, the reason in the last error, and the mesh
// unchanged (a step after them does not move it, and nothing was set up for motion).
TEST(bad_mesh_vertices_are_refused)
{
	fmWorldId world = groundWorld(fm_implicit);
	fmVec3 vertices[GROUND_VERTICES];
	fmColliderId ground = makeGround(world, vertices, false);
	fmColliderDef sphere = fmDefaultColliderDef();
	sphere.shape = fm_shapeSphere;
	fmColliderId ball;
	CHECK_INT(fmCreateCollider(world, &sphere, &ball, NULL), fm_ok);
	fmVec3 moved[GROUND_VERTICES];
	for (int i = 0; i < GROUND_VERTICES; ++i)
		moved[i] = fmAdd(vertices[i], fmMakeVec3(0.0, 0.5, 0.0));
	CHECK_INT(fmCollider_SetMeshVertices(ball, moved, GROUND_VERTICES), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "a mesh collider");
	CHECK_INT(fmCollider_SetMeshVertices(ground, NULL, GROUND_VERTICES), fm_errParameter);
	CHECK_INT(fmCollider_SetMeshVertices(ground, moved, GROUND_VERTICES - 1), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "as many vertices");
	moved[7].y = NAN;
	CHECK_INT(fmCollider_SetMeshVertices(ground, moved, GROUND_VERTICES), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "finite vertices");
	moved[7].y = 2e9;
	CHECK_INT(fmCollider_SetMeshVertices(ground, moved, GROUND_VERTICES), fm_errParameter);
	moved[7].y = -INFINITY;
	CHECK_INT(fmCollider_SetMeshVertices(ground, moved, GROUND_VERTICES), fm_errParameter);
	makeCube(world, 0.0);
	CHECK_INT(fmWorld_Step(world, frame, 2), fm_ok);
	const fmMeshShape* m = colliderOf(world, ground)->mesh;
	CHECK(m->motion == NULL);
	CHECK(memcmp(m->vertices, vertices, sizeof vertices) == 0);
	fmDestroyWorld(world);
}

// A cube asleep on the ground (implicit) is woken by the ground's vertices rising under it (once
// the ground reaches it through the barrier's gap, within 10 frames), and slower than the sleep
// speed (0.02 m/s against 0.05) they keep it awake: over 1.5 s it rides 3 cm up with the ground,
// no vertex more than 1 mm below it.
TEST(slow_moving_mesh_wakes_and_keeps_awake)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = fm_implicit;
	def.floor.enabled = false;
	def.contact.enableSleep = true;
	fmWorldId world = fmCreateWorld(&def);
	fmVec3 vertices[GROUND_VERTICES];
	fmColliderId ground = makeGround(world, vertices, false);
	fmBodyId cube = makeCube(world, 0.0);
	for (int f = 0; f < 90; ++f)
		CHECK_INT(fmWorld_Step(world, frame, 2), fm_ok);
	bool slept = !fmBody_IsAwake(cube);
	const double speed = 0.02;
	double height = 0.0, deepest = 0.0;
	int asleep = 0, woke = -1;
	for (int f = 0; f < 90; ++f)
	{
		height += speed * frame;
		for (int i = 0; i < GROUND_VERTICES; ++i)
			vertices[i].y = height;
		CHECK_INT(fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES), fm_ok);
		CHECK_INT(fmWorld_Step(world, frame, 2), fm_ok);
		if (woke < 0 && fmBody_IsAwake(cube))
			woke = f;
		asleep += woke >= 0 && !fmBody_IsAwake(cube);
		deepest = fmin(deepest, lowestAbove(cube, height));
	}
	printf("  asleep before: %s; woken in frame %d of the rise; frames asleep after: %d; deepest "
	       "vertex %.2e m below the ground\n",
	       slept ? "yes" : "no", woke, asleep, -deepest);
	CHECK(slept);
	CHECK(woke >= 0 && woke <= 10);
	CHECK_INT(asleep, 0);
	CHECK(deepest > -1e-3);
	fmDestroyWorld(world);
}

// Fuzz-like: a ground whose vertices jump by up to 2 cm at random every frame, folding its
// triangles over, collapsing to a point for a frame and coming back, under a cube, implicit and
// explicit: every frame steps (or is refused and restored), the cube's positions stay finite,
// and a snapshot of the folded ground restores (the sanitizer builds run it for memory errors).
TEST(random_vertex_jumps_keep_the_state_finite)
{
	for (int k = 0; k < 2; ++k)
	{
		fmIntegrator integrator = k == 0 ? fm_implicit : fm_explicit;
		fmWorldId world = groundWorld(integrator);
		fmVec3 rest[GROUND_VERTICES], vertices[GROUND_VERTICES];
		fmColliderId ground = makeGround(world, rest, false);
		fmBodyId cube = makeCube(world, 0.01);
		int n3 = 3 * fmBody_GetVertexCount(cube), refused = 0, finite = 1;
		for (int f = 0; f < 40; ++f)
		{
			for (int i = 0; i < GROUND_VERTICES; ++i)
				vertices[i] = f == 20 ? fmMakeVec3(0.0, 0.0, 0.0)
				                      : fmAdd(rest[i], fmMakeVec3(fmTestRandom(-0.02, 0.02),
				                                                  fmTestRandom(-0.02, 0.02),
				                                                  fmTestRandom(-0.02, 0.02)));
			CHECK_INT(fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES), fm_ok);
			refused += fmWorld_Step(world, frame, substepsOf(integrator)) != fm_ok;
			const double* x = fmTestPositions(cube);
			for (int i = 0; i < n3; ++i)
				finite = finite && isfinite(x[i]);
		}
		size_t size = fmWorld_GetSnapshotSize(world);
		void* snapshot = malloc(size);
		CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, NULL), fm_ok);
		CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
		printf("  %s: %d of 40 frames refused, positions finite: %s\n",
		       integrator == fm_implicit ? "implicit" : "explicit", refused, finite ? "yes" : "NO");
		CHECK(finite);
		free(snapshot);
		fmDestroyWorld(world);
	}
}

// A snapshot whose saved mesh vertex is NaN or beyond FM_MAX_COORDINATE (resealed, so that the
// checksum passes) is refused with fm_errParameter naming the collider, the mesh unchanged.
TEST(snapshot_with_bad_mesh_vertices_is_refused)
{
	fmWorldId world = groundWorld(fm_implicit);
	fmVec3 vertices[GROUND_VERTICES];
	fmColliderId ground = makeGround(world, vertices, false);
	makeCube(world, 0.01);
	for (int i = 0; i < GROUND_VERTICES; ++i)
		vertices[i].y = 0.01 * i;
	CHECK_INT(fmCollider_SetMeshVertices(ground, vertices, GROUND_VERTICES), fm_ok);
	CHECK_INT(fmWorld_Step(world, frame, 2), fm_ok);
	const fmMeshShape* m = colliderOf(world, ground)->mesh;
	size_t size = fmWorld_GetSnapshotSize(world);
	unsigned char* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, NULL), fm_ok);
	unsigned char* at = NULL; // the saved vertices
	for (size_t i = 0; at == NULL && i + sizeof vertices <= size; ++i)
		at = memcmp(snapshot + i, m->vertices, sizeof vertices) == 0 ? snapshot + i : NULL;
	CHECK(at != NULL);
	const double bad[2] = {NAN, 2e9};
	for (int k = 0; at != NULL && k < 2; ++k)
	{
		memcpy(at + sizeof(fmVec3) * 7 + sizeof(double), &bad[k], sizeof(double));
		fmSnapshot_Seal(snapshot, size);
		CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_errParameter);
		CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "mesh vertex");
		CHECK(memcmp(m->vertices, vertices, sizeof vertices) == 0);
	}
	free(snapshot);
	fmDestroyWorld(world);
}
