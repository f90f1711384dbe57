// Snapshots: save a world, run it on, restore, run again: the same bits. Changes made after the
// save (material, gravity, pins, impulses) are undone by the restore; a snapshot of other bodies
// or colliders, or a truncated one, is refused and changes nothing. Contact scenes (a kinematic
// collider pushing a stack of two bodies on a ground collider) replay bit for bit, colliders,
// lagged friction, the last frame's pairs and sleep included.
#include "support.h"
#include "test.h"

#include "body/body.h"
#include "contact/collider.h"
#include "contact/contact_events.h"
#include "solver/solver_cache.h"
#include "world/snapshot.h"
#include "world/world.h"

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
	// Above the house's roof: it falls on it (contact in the snapshot).
	CHECK_INT(fmMakeBoxMesh(3, 2, 2, fmMakeVec3(-1, 2.3, -1), fmMakeVec3(1, 3.3, 1), &box), fm_ok);
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
	// The floor's reaction is part of the state the snapshot keeps.
	fmColliderId floor = fmWorld_GetFloorCollider(world);
	fmVec3 savedForce, firstForce, force;
	fmCollider_GetContactForce(floor, &savedForce, NULL);

	runOn(failures_, world, bodies, 2, 20, frame, substeps, false);
	size_t length;
	double* first = stateOf(bodies, 2, &length);
	fmStepStats firstStats = fmWorld_GetStepStats(world);
	fmCollider_GetContactForce(floor, &firstForce, NULL);

	// Disturb, run, restore, run again: the same bits as the first continuation.
	runOn(failures_, world, bodies, 2, 5, frame, substeps, true);
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
	fmCollider_GetContactForce(floor, &force, NULL);
	CHECK(memcmp(&force, &savedForce, sizeof force) == 0);
	runOn(failures_, world, bodies, 2, 20, frame, substeps, false);
	size_t length2;
	double* second = stateOf(bodies, 2, &length2);
	CHECK(length == length2);
	CHECK(memcmp(first, second, sizeof(double) * length) == 0);
	fmStepStats secondStats = fmWorld_GetStepStats(world);
	CHECK_INT(secondStats.newtonIterations, firstStats.newtonIterations);
	CHECK_INT(secondStats.cgIterations, firstStats.cgIterations);
	CHECK_INT(secondStats.contacts, firstStats.contacts);
	fmCollider_GetContactForce(floor, &force, NULL);
	CHECK(memcmp(&force, &firstForce, sizeof force) == 0);
	CHECK(integrator == fm_implicit || firstForce.y < 0.0); // explicit: landed by then
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

// Step worlds @p a and @p b @p frames implicit frames of 1/60 s each, then check that body
// @p x of a and body @p y of b are at the same positions, bit for bit.
static void stepTwins(int* failures_, fmWorldId a, fmWorldId b, int frames, fmBodyId x, fmBodyId y)
{
	for (int f = 0; f < frames; ++f)
	{
		CHECK_INT(fmWorld_Step(a, 1.0 / 60.0, 1), fm_ok);
		CHECK_INT(fmWorld_Step(b, 1.0 / 60.0, 1), fm_ok);
	}
	size_t n3 = 3 * (size_t)fmBody_GetVertexCount(x);
	CHECK(memcmp(fmGetBody(x)->state.x, fmGetBody(y)->state.x, sizeof(double) * n3) == 0);
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
	fmImplicitCache* cache = fmGetBody(body)->solverCache;
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
	CHECK(fmGetBody(twin)->solverCache == NULL);
	CHECK_INT(fmWorld_RestoreSnapshot(fresh, snapshot, size), fm_ok);
	const fmImplicitCache* restored = fmGetBody(twin)->solverCache;
	CHECK(restored != NULL && restored->coasted);
	CHECK_INT(restored != NULL ? restored->guessRecheck : -1, 5);
	// Both continue with the same bits.
	stepTwins(failures_, world, fresh, 10, body, twin);
	free(snapshot);
	fmDestroyWorld(world);
	fmDestroyWorld(fresh);
}

// ---- contact scenes
// ------------------------------------------------------------------------------

// A stack of two boxes on a ground collider (a plane, friction 0.8; no floor), and a kinematic
// box collider, a paddle turning about the vertical at 3 rad/s while it moves toward the stack at
// 0.2 m/s, that pushes the lower box.
typedef struct ContactScene
{
	fmWorldId world;
	fmBodyId bodies[2];
	fmColliderId colliders[2]; // the ground, the paddle
	double frame;
	int substeps;
} ContactScene;

static fmBodyId addBox(int* failures_, fmWorldId world, fmVec3 lo, fmVec3 hi)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(3, 3, 3, lo, hi, &mesh) != fm_ok)
		return none;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 500.0;
	def.smoothing = 0.0;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &def, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

static ContactScene makeContactScene(int* failures_, fmIntegrator integrator)
{
	ContactScene scene;
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.enabled = false;
	scene.world = fmCreateWorld(&wdef);
	scene.frame = 1.0 / 60.0;
	scene.substeps = integrator == fm_implicit ? 1 : 20;
	scene.bodies[0] =
	    addBox(failures_, scene.world, fmMakeVec3(-0.3, 0.02, -0.3), fmMakeVec3(0.3, 0.62, 0.3));
	scene.bodies[1] =
	    addBox(failures_, scene.world, fmMakeVec3(-0.2, 0.7, -0.2), fmMakeVec3(0.2, 1.1, 0.2));
	fmColliderDef ground = fmDefaultColliderDef(); // the plane y = 0
	ground.friction = 0.8;
	CHECK_INT(fmCreateCollider(scene.world, &ground, &scene.colliders[0], NULL), fm_ok);
	fmColliderDef paddle = fmDefaultColliderDef();
	paddle.shape = fm_shapeBox;
	paddle.center = fmMakeVec3(-0.75, 0.3, 0.0);
	paddle.halfExtents = fmMakeVec3(0.5, 0.1, 0.05);
	paddle.velocity = fmMakeVec3(0.2, 0.0, 0.0);
	paddle.angularVelocity = fmMakeVec3(0.0, 3.0, 0.0);
	paddle.friction = 0.5;
	CHECK_INT(fmCreateCollider(scene.world, &paddle, &scene.colliders[1], NULL), fm_ok);
	return scene;
}

static fmCollider* colliderOf(fmWorldId world, fmColliderId id)
{
	return &fmGetWorld(world)->colliders[id.index1 - 1];
}

// Bodies' positions and velocities, then each collider's position, rotation, velocity, angular
// velocity and last force and torque (caller frees).
static double* sceneState(const ContactScene* scene, size_t* length)
{
	size_t bodies;
	double* state = stateOf((fmBodyId*)scene->bodies, 2, &bodies);
	state = realloc(state, sizeof(double) * (bodies + 2 * 24));
	for (int k = 0; k < 2; ++k)
	{
		const fmCollider* c = colliderOf(scene->world, scene->colliders[k]);
		const fmVec3 v[5] = {c->position, c->def.velocity, c->def.angularVelocity, c->force,
		                     c->torque};
		memcpy(state + bodies + 24 * k, v, sizeof v);
		memcpy(state + bodies + 24 * k + 15, c->rotation.m, sizeof c->rotation.m);
	}
	*length = bodies + 2 * 24;
	return state;
}

static double largestDifference(const double* a, const double* b, size_t length)
{
	double largest = 0.0;
	for (size_t k = 0; k < length; ++k)
		largest = a[k] == b[k] ? largest : fmax(largest, fabs(a[k] - b[k]));
	return largest;
}

// The largest difference of the bodies' positions (m) between two scene states.
static double positionDifference(const ContactScene* scene, const double* a, const double* b)
{
	double largest = 0.0;
	size_t at = 0;
	for (int k = 0; k < 2; ++k)
	{
		size_t n3 = 3 * (size_t)fmBody_GetVertexCount(scene->bodies[k]);
		largest = fmax(largest, largestDifference(a + at, b + at, n3));
		at += 2 * n3;
	}
	return largest;
}

// Run @p frames frames: every step must succeed; the contact events of each frame into
// @p events (unless NULL), and how many of the frames' contacts were with the paddle and with the
// other body.
static void runScene(int* failures_, const ContactScene* scene, int frames, int* events,
                     int* paddle, int* bodyBody)
{
	fmContactPoint points[4096];
	for (int f = 0; f < frames; ++f)
	{
		CHECK_INT(fmWorld_Step(scene->world, scene->frame, scene->substeps), fm_ok);
		if (events != NULL)
			events[f] = fmWorld_GetContactEvents(scene->world, NULL, 0);
		int count = fmWorld_GetContacts(scene->world, points, 4096);
		for (int k = 0; k < count && k < 4096; ++k)
		{
			*paddle += points[k].collider.index1 == scene->colliders[1].index1;
			*bodyBody += points[k].otherBody.index1 != 0;
		}
	}
}

enum
{
	sceneSaveFrame = 40,
	sceneFrames = 30
};

// Restore @p snapshot and replay: the state and the frames' events after it, with the part of the
// restore that @p undo names taken back (the control: 1 the colliders keep the poses they have
// now, as before format version 3; 2 the lagged collider friction is cleared; 3 the last frame's
// pairs are forgotten).
static double* replay(int* failures_, const ContactScene* scene, const void* snapshot, size_t size,
                      int undo, int* events)
{
	fmCollider kept[2];
	for (int k = 0; k < 2; ++k)
		kept[k] = *colliderOf(scene->world, scene->colliders[k]);
	CHECK_INT(fmWorld_RestoreSnapshot(scene->world, snapshot, size), fm_ok);
	for (int k = 0; undo == 1 && k < 2; ++k)
	{
		colliderOf(scene->world, scene->colliders[k])->position = kept[k].position;
		colliderOf(scene->world, scene->colliders[k])->rotation = kept[k].rotation;
	}
	for (int k = 0; undo == 2 && k < 2; ++k)
	{
		fmBody* b = fmGetBody(scene->bodies[k]);
		memset(b->contact.frictionNext, 0, sizeof(double) * 8 * (size_t)b->mesh.vertexCount);
	}
	if (undo == 3)
		CHECK(fmContactEvents_SetFramePairs(fmGetWorld(scene->world), NULL, 0));
	int paddle = 0, bodyBody = 0;
	runScene(failures_, scene, sceneFrames, events, &paddle, &bodyBody);
	size_t length;
	return sceneState(scene, &length);
}

static int frictionVertices(const ContactScene* scene)
{
	int count = 0;
	for (int k = 0; k < 2; ++k)
	{
		const fmBody* b = fmGetBody(scene->bodies[k]);
		for (int i = 0; b->contact.frictionNext && i < b->mesh.vertexCount; ++i)
			count += b->contact.frictionNext[8 * i + 3] > 0.0;
	}
	return count;
}

static void checkContactReplay(int* failures_, fmIntegrator integrator)
{
	const char* name = integrator == fm_implicit ? "implicit" : "explicit";
	ContactScene scene = makeContactScene(failures_, integrator);
	int events[sceneFrames], replayed[sceneFrames], paddle = 0, bodyBody = 0;
	runScene(failures_, &scene, sceneSaveFrame, NULL, &paddle, &bodyBody); // landing
	size_t size = fmWorld_GetSnapshotSize(scene.world), written = 0;
	void* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, snapshot, size, &written), fm_ok);
	CHECK(written == size);
	int friction = frictionVertices(&scene);
	fmVec3 paddleAtSave = fmCollider_GetPosition(scene.colliders[1]);
	paddle = bodyBody = 0;
	runScene(failures_, &scene, sceneFrames, events, &paddle, &bodyBody);
	size_t length;
	double* first = sceneState(&scene, &length);
	fmVec3 paddleAfter = fmCollider_GetPosition(scene.colliders[1]);
	printf("  %s: %zu-byte snapshot at frame %d (%d vertices with lagged collider friction); %d "
	       "frames after it: %d contacts with the paddle, %d body-body, paddle moved %.3f m\n",
	       name, size, sceneSaveFrame, friction, sceneFrames, paddle, bodyBody,
	       paddleAfter.x - paddleAtSave.x);
	CHECK(paddle > 0 && bodyBody > 0);
	CHECK(integrator == fm_explicit || friction > 0);

	// The replay: every bit of the bodies and the colliders, and the same events.
	double* second = replay(failures_, &scene, snapshot, size, 0, replayed);
	bool same = memcmp(first, second, sizeof(double) * length) == 0;
	CHECK(same);
	CHECK(memcmp(events, replayed, sizeof events) == 0);
	printf("  %s: replay after a restore bit-identical (bodies, collider poses and forces, "
	       "events): %s\n",
	       name, same && memcmp(events, replayed, sizeof events) == 0 ? "yes" : "NO");
	// The controls: without the colliders' poses the replay differs, so does it without the
	// implicit friction; without the last frame's pairs the first frame's events differ.
	double* noPoses = replay(failures_, &scene, snapshot, size, 1, replayed);
	double posesOff = positionDifference(&scene, first, noPoses);
	CHECK(posesOff > 1e-3);
	double* noFriction = replay(failures_, &scene, snapshot, size, 2, replayed);
	double frictionOff = positionDifference(&scene, first, noFriction);
	CHECK(integrator == fm_explicit ? frictionOff == 0.0 : frictionOff > 0.0);
	free(replay(failures_, &scene, snapshot, size, 3, replayed));
	CHECK(replayed[0] != events[0]);
	printf("  %s controls: colliders left where they were: a body vertex ends %.3g m away; "
	       "friction cleared: %.3g m; pairs forgotten: %d events in the first frame instead "
	       "of %d\n",
	       name, posesOff, frictionOff, replayed[0], events[0]);
	free(noPoses);
	free(noFriction);
	free(first);
	free(second);
	free(snapshot);
	fmDestroyWorld(scene.world);
}

TEST(explicit_contact_scene_replays_bit_identically)
{
	checkContactReplay(failures_, fm_explicit);
}

TEST(implicit_contact_scene_replays_bit_identically)
{
	checkContactReplay(failures_, fm_implicit);
}

// A world with one small box above a mesh collider, a slab [-2, 2] x [-1, 0] x [-2, 2] whose
// first @p triangles triangles (12: closed; 10: its bottom left out) are given.
static fmWorldId makeMeshWorld(int* failures_, int triangles, fmBodyId* body)
{
	static const int faces[36] = {2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5,
	                              0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4};
	fmVec3 vertices[8];
	for (int k = 0; k < 8; ++k)
		vertices[k] = fmMakeVec3(k & 1 ? 2.0 : -2.0, k & 2 ? 0.0 : -1.0, k & 4 ? 2.0 : -2.0);
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef ground = fmDefaultColliderDef();
	ground.shape = fm_shapeMesh;
	ground.vertices = vertices;
	ground.vertexCount = 8;
	ground.triangles = faces;
	ground.triangleCount = triangles;
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &ground, &id, NULL), fm_ok);
	*body = addBox(failures_, world, fmMakeVec3(-0.2, 0.05, -0.2), fmMakeVec3(0.2, 0.45, 0.2));
	return world;
}

// The snapshot's bytes of a collider's position (the first copy of its three doubles), or NULL.
static unsigned char* findVec3(unsigned char* buffer, size_t size, fmVec3 v)
{
	for (size_t at = 0; at + sizeof v <= size; ++at)
		if (memcmp(buffer + at, &v, sizeof v) == 0)
			return buffer + at;
	return NULL;
}

// Restoring into a world whose colliders differ from the snapshot's is refused with the reason,
// and changes nothing: a collider created since, one destroyed and another created in its slot,
// a mesh collider of other triangles in a fresh world. Truncated and corrupted contact sections
// are refused too.
// A snapshot with 1 to 4 bytes changed anywhere (1,000 of them, from a fixed seed) is refused
// with fm_errParameter, and the refusals change nothing: the world's own snapshot afterwards is
// the same bytes as before them. (Before the checksum, 992 of 1,000 were restored.)
TEST(corrupted_snapshots_are_refused_and_change_nothing)
{
	ContactScene scene = makeContactScene(failures_, fm_implicit);
	int events[10], paddle = 0, bodyBody = 0;
	runScene(failures_, &scene, 10, events, &paddle, &bodyBody);
	size_t size = fmWorld_GetSnapshotSize(scene.world);
	unsigned char* saved = malloc(size);
	unsigned char* changed = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, saved, size, NULL), fm_ok);
	runScene(failures_, &scene, 2, events, &paddle, &bodyBody);
	size_t sizeNow = fmWorld_GetSnapshotSize(scene.world);
	unsigned char* now = malloc(sizeNow);
	unsigned char* after = malloc(sizeNow);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, now, sizeNow, NULL), fm_ok);
	uint64_t seed = 0x5eed;
	int refused = 0, byChecksum = 0;
	const int trials = 1000;
	for (int t = 0; t < trials; ++t)
	{
		memcpy(changed, saved, size);
		int bytes = 1 + t % 4;
		for (int k = 0; k < bytes; ++k)
		{
			seed = seed * 6364136223846793005ull + 1442695040888963407ull;
			size_t at = (size_t)((seed >> 11) % size);
			changed[at] ^= (unsigned char)(1 + (seed >> 3) % 255);
		}
		if (memcmp(changed, saved, size) == 0)
			changed[0] ^= 1; // two changes of one byte cancelled
		refused += fmWorld_RestoreSnapshot(scene.world, changed, size) == fm_errParameter;
		byChecksum += strstr(fmWorld_GetLastError(scene.world)->message, "checksum") != NULL;
	}
	printf("  %d of %d changed snapshots refused (%d by the checksum, the rest by the header)\n",
	       refused, trials, byChecksum);
	CHECK_INT(refused, trials);
	CHECK(byChecksum >= trials * 9 / 10);
	CHECK_INT(fmWorld_GetSnapshotSize(scene.world), sizeNow);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, after, sizeNow, NULL), fm_ok);
	CHECK(memcmp(now, after, sizeNow) == 0);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, saved, size), fm_ok); // the intact one
	free(saved), free(changed), free(now), free(after);
	fmDestroyWorld(scene.world);
}

TEST(colliders_that_differ_are_refused)
{
	ContactScene scene = makeContactScene(failures_, fm_implicit);
	int events[10], paddle = 0, bodyBody = 0;
	runScene(failures_, &scene, 10, events, &paddle, &bodyBody);
	size_t size = fmWorld_GetSnapshotSize(scene.world), length, length2;
	unsigned char* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, snapshot, size, NULL), fm_ok);
	fmVec3 paddleAtSave = fmCollider_GetPosition(scene.colliders[1]);
	runScene(failures_, &scene, 2, events, &paddle, &bodyBody);
	double* before = sceneState(&scene, &length);

	fmColliderDef sphere = fmDefaultColliderDef();
	sphere.shape = fm_shapeSphere;
	sphere.center = fmMakeVec3(3.0, 0.5, 0.0);
	fmColliderId extra;
	CHECK_INT(fmCreateCollider(scene.world, &sphere, &extra, NULL), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, snapshot, size), fm_errParameter);
	printf("  a collider created: %s\n", fmWorld_GetLastError(scene.world)->message);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(scene.world)->message,
	                   "the snapshot holds 2 colliders, the world 3");
	fmDestroyCollider(extra);

	// Cut short anywhere in its last 3 kB (the contact section and more), or a pose made NaN.
	int refused = 0, cuts = 0;
	for (size_t cut = size - 1; cut + 3072 >= size && cut > 0; --cut, ++cuts)
		refused += fmWorld_RestoreSnapshot(scene.world, snapshot, cut) == fm_errParameter;
	CHECK_INT(refused, cuts);
	unsigned char* corrupt = malloc(size);
	memcpy(corrupt, snapshot, size);
	unsigned char* at = findVec3(corrupt, size, paddleAtSave);
	CHECK(at != NULL);
	double nan = NAN;
	if (at != NULL)
		memcpy(at, &nan, sizeof nan);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, corrupt, size), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(scene.world)->message, "checksum does not match");
	fmSnapshot_Seal(corrupt, size); // past the checksum: the pose's own check
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, corrupt, size), fm_errParameter);
	printf("  %d cuts refused; a NaN pose: %s\n", refused,
	       fmWorld_GetLastError(scene.world)->message);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(scene.world)->message,
	                   "collider in slot 1 is truncated or has a non-finite pose");
	double* after = sceneState(&scene, &length2);
	CHECK(memcmp(before, after, sizeof(double) * length) == 0);
	free(after);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, snapshot, size), fm_ok); // the same colliders

	fmDestroyCollider(scene.colliders[1]); // another collider in the paddle's slot
	CHECK_INT(fmCreateCollider(scene.world, &sphere, &extra, NULL), fm_ok);
	CHECK_INT(extra.index1, scene.colliders[1].index1);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, snapshot, size), fm_errParameter);
	printf("  a collider replaced: %s\n", fmWorld_GetLastError(scene.world)->message);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(scene.world)->message,
	                   "collider in slot 1 (a box, generation 1) is not the world's (a sphere");

	// A mesh collider of other triangles, in a fresh world of the same bodies.
	fmBodyId body, twin;
	fmWorldId closed = makeMeshWorld(failures_, 12, &body);
	for (int f = 0; f < 20; ++f)
		CHECK_INT(fmWorld_Step(closed, 1.0 / 60.0, 1), fm_ok);
	const fmBody* resting = fmGetBody(body);
	int friction = 0;
	for (int i = 0; resting->contact.frictionNext && i < resting->mesh.vertexCount; ++i)
		friction += resting->contact.frictionNext[8 * i + 3] > 0.0;
	CHECK(friction > 0); // restored into a world that has no friction arrays yet
	size_t meshSize = fmWorld_GetSnapshotSize(closed);
	void* meshSnapshot = malloc(meshSize);
	CHECK_INT(fmWorld_SaveSnapshot(closed, meshSnapshot, meshSize, NULL), fm_ok);
	fmWorldId open = makeMeshWorld(failures_, 10, &twin);
	CHECK_INT(fmWorld_RestoreSnapshot(open, meshSnapshot, meshSize), fm_errParameter);
	printf("  a mesh of other triangles: %s\n", fmWorld_GetLastError(open)->message);
	printf("  the same mesh in a fresh world: restored, %d vertices with collider friction\n",
	       friction);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(open)->message,
	                   "mesh collider in slot 0 has 12 triangles and 8 vertices, the world's 10");
	fmWorldId same = makeMeshWorld(failures_, 12, &twin);
	CHECK_INT(fmWorld_RestoreSnapshot(same, meshSnapshot, meshSize), fm_ok);
	stepTwins(failures_, closed, same, 5, body, twin);
	fmDestroyWorld(closed);
	fmDestroyWorld(open);
	fmDestroyWorld(same);
	free(meshSnapshot);
	free(corrupt);
	free(before);
	free(snapshot);
	fmDestroyWorld(scene.world);
}

// Sleep survives a restore: a snapshot taken while the stack's sleep timers run falls asleep in
// the same frame after it (woken through the API instead, the timers start again and it sleeps
// later); one taken asleep restores asleep into a woken world and stays still, bit for bit,
// with no sleep or contact events.
static bool stackAsleep(fmBodyId* bodies)
{
	return !fmBody_IsAwake(bodies[0]) && !fmBody_IsAwake(bodies[1]);
}

static int framesUntilAsleep(int* failures_, fmWorldId world, fmBodyId* bodies, int most)
{
	for (int f = 1; f <= most; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		if (stackAsleep(bodies))
			return f;
	}
	return -1;
}

TEST(sleep_survives_a_restore)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.contact.enableSleep = true;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyId bodies[2] = {
	    addBox(failures_, world, fmMakeVec3(-0.3, 0.05, -0.3), fmMakeVec3(0.3, 0.65, 0.3)),
	    addBox(failures_, world, fmMakeVec3(-0.2, 0.75, -0.2), fmMakeVec3(0.2, 1.15, 0.2))};
	int f = 0; // until both sleep timers run
	while (f < 600 &&
	       !(fmGetBody(bodies[0])->sleepTimer > 0.1 && fmGetBody(bodies[1])->sleepTimer > 0.1))
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		++f;
	}
	size_t timingSize = fmWorld_GetSnapshotSize(world);
	void* timing = malloc(timingSize);
	CHECK_INT(fmWorld_SaveSnapshot(world, timing, timingSize, NULL), fm_ok);
	int first = framesUntilAsleep(failures_, world, bodies, 600);
	size_t length, length2;
	double* asleep = stateOf(bodies, 2, &length);
	size_t size = fmWorld_GetSnapshotSize(world);
	void* sleeping = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, sleeping, size, NULL), fm_ok);

	CHECK_INT(fmWorld_RestoreSnapshot(world, timing, timingSize), fm_ok);
	CHECK(!stackAsleep(bodies));
	int again = framesUntilAsleep(failures_, world, bodies, 600);
	double* asleepAgain = stateOf(bodies, 2, &length2);
	CHECK(memcmp(asleep, asleepAgain, sizeof(double) * length) == 0);
	CHECK_INT(fmWorld_RestoreSnapshot(world, timing, timingSize), fm_ok);
	fmBody_SetAwake(bodies[0], true); // the control: timers started again
	int restarted = framesUntilAsleep(failures_, world, bodies, 600);
	printf("  timers running at frame %d: asleep %d frames later; after a restore %d (same "
	       "bits: %s); woken through the API instead %d\n",
	       f, first, again,
	       memcmp(asleep, asleepAgain, sizeof(double) * length) == 0 ? "yes" : "NO", restarted);
	CHECK(first > 0 && again == first && restarted > first);

	// Asleep: woken and moved, restored asleep, still.
	fmBody_ApplyImpulse(bodies[1], fmMakeVec3(0.0, 0.5, 0.0));
	CHECK(!stackAsleep(bodies));
	for (int k = 0; k < 10; ++k)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(world, sleeping, size), fm_ok);
	CHECK(stackAsleep(bodies));
	int events = 0;
	for (int k = 0; k < 30; ++k)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		events += fmWorld_GetSleepEvents(world, NULL, 0) + fmWorld_GetContactEvents(world, NULL, 0);
	}
	double* still = stateOf(bodies, 2, &length2);
	printf("  restored asleep: %s, 30 frames later still (same bits: %s), %d events\n",
	       stackAsleep(bodies) ? "yes" : "NO",
	       memcmp(asleep, still, sizeof(double) * length) == 0 ? "yes" : "NO", events);
	CHECK(stackAsleep(bodies));
	CHECK(memcmp(asleep, still, sizeof(double) * length) == 0);
	CHECK_INT(events, 0);
	free(still);
	free(asleepAgain);
	free(asleep);
	free(sleeping);
	free(timing);
	fmDestroyWorld(world);
}

// A body keeps its barrier friction pairs (friction_anchor.h) until its next step, naming the
// other body: when that body is destroyed first, a snapshot of the world still restores into it.
TEST(snapshot_after_a_touching_body_is_destroyed_restores)
{
	ContactScene scene = makeContactScene(failures_, fm_implicit);
	int paddle = 0, bodyBody = 0;
	runScene(failures_, &scene, sceneSaveFrame, NULL, &paddle, &bodyBody); // stacked, touching
	CHECK(bodyBody > 0);
	fmBody_SetAwake(scene.bodies[1], false);
	fmDestroyBody(scene.bodies[0]);
	size_t size = fmWorld_GetSnapshotSize(scene.world), written = 0;
	void* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(scene.world, snapshot, size, &written), fm_ok);
	CHECK_INT(fmWorld_Step(scene.world, scene.frame, scene.substeps), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(scene.world, snapshot, written), fm_ok);
	CHECK_INT(fmWorld_Step(scene.world, scene.frame, scene.substeps), fm_ok);
	free(snapshot);
	fmDestroyWorld(scene.world);
}
