// Fracture along tet faces (issue 34, item 2; body/fracture.h): a notched plate tears at one
// load on two meshes (the averaged stress's length makes it mesh-independent), a tear conserves
// mass and momentum exactly, a box dropped on a sharp edge breaks into pieces whose masses sum
// to the box's, snapshots hold the torn state, and bad parameters are refused.
#include "support.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// A plate [0, 0.1] x [0, 0.1] x [0, 0.01] of n x n x 1 cubes with a slot notch from the left
// edge at mid-height (x < 0.025, |y - 0.05| < 0.1 / 12): the tets whose centres lie in it are
// dropped and the unused nodes with them.
static bool notchedPlate(int n, fmTetMesh* out)
{
	fmTetMesh box;
	if (fmMakeBoxMesh(n, n, 1, fmMakeVec3(0, 0, 0), fmMakeVec3(0.1, 0.1, 0.01), &box) != fm_ok)
		return false;
	int* keep = calloc((size_t)box.nodeCount, sizeof(int));
	int* tets = malloc(sizeof(int) * 4 * (size_t)box.tetCount);
	int count = 0;
	for (int t = 0; t < box.tetCount; ++t)
	{
		double cx = 0.0, cy = 0.0;
		for (int a = 0; a < 4; ++a)
		{
			cx += 0.25 * box.positions[3 * box.tets[4 * t + a]];
			cy += 0.25 * box.positions[3 * box.tets[4 * t + a] + 1];
		}
		if (cx < 0.025 && fabs(cy - 0.05) < 0.1 / 12.0)
			continue;
		memcpy(tets + 4 * count++, box.tets + 4 * t, 4 * sizeof(int));
	}
	int nodes = 0;
	for (int e = 0; e < 4 * count; ++e)
		keep[tets[e]] = 1;
	for (int i = 0; i < box.nodeCount; ++i)
		keep[i] = keep[i] ? nodes++ : -1;
	memset(out, 0, sizeof *out);
	out->nodeCount = nodes;
	out->tetCount = count;
	out->positions = malloc(sizeof(double) * 3 * (size_t)nodes);
	out->tets = tets;
	for (int i = 0; i < box.nodeCount; ++i)
		if (keep[i] >= 0)
			memcpy(out->positions + 3 * keep[i], box.positions + 3 * i, 3 * sizeof(double));
	for (int e = 0; e < 4 * count; ++e)
		tets[e] = keep[tets[e]];
	free(keep);
	fmFreeTetMesh(&box);
	return true;
}

static void freePlate(fmTetMesh* mesh)
{
	free(mesh->positions);
	free(mesh->tets);
}

static fmMaterial plateMaterial(void)
{
	fmMaterial m = fmMakeMaterial(fm_linear, 1e6, 0.3);
	m.fracture.strength = 1e4;
	m.fracture.length = 0.02;
	return m;
}

// The plate's tearing load (N): the bottom edge held, the top edge pulled up by steps a static
// solve reaches, each step the one that brings the worst face to its strength (a linear body's
// sequentially linear analysis), tearing until the plate is in two; the largest reaction.
static double tearingLoad(int* failures_, int n)
{
	fmTetMesh mesh;
	CHECK(notchedPlate(n, &mesh));
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = plateMaterial();
	def.massMode = fm_massFromDensity;
	fmBodyId id;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &def, &id, &diag), fm_ok);
	const fmVec3 big = fmMakeVec3(1, 1, 1);
	fmBody_PinBox(id, fmMakeVec3(-1, -1, -1), fmMakeVec3(1, 1e-9, 1));
	double largest = 0.0, pulled = 0.0, step = 1e-5;
	int top = 0; // (the top edge's vertices: the first ones never split there)
	for (int i = 0; i < mesh.nodeCount; ++i)
		top += mesh.positions[3 * i + 1] > 0.1 - 1e-9;
	int* topVertex = malloc(sizeof(int) * (size_t)top);
	top = 0;
	for (int i = 0; i < mesh.nodeCount; ++i)
		if (mesh.positions[3 * i + 1] > 0.1 - 1e-9)
			topVertex[top++] = i;
	for (int round = 0; round < 1000 && fmBody_GetPieces(id, NULL) < 2; ++round)
	{
		CHECK(fmBody_PrescribeDisplacement(id, fmMakeVec3(-1, 0.1 - 1e-9, -1), big, 2u,
		                                   fmMakeVec3(0, step, 0), 0.0) > 0);
		pulled += step;
		double residual;
		CHECK_INT(fmBody_SolveStatic(id, 1e-10, 50, &residual, &diag), fm_ok);
		double* f = calloc(3 * (size_t)fmBody_GetVertexCount(id), sizeof(double));
		fmBody_ComputeElasticForces(id, f);
		double reaction = 0.0;
		for (int k = 0; k < top; ++k)
			reaction -= f[3 * topVertex[k] + 1];
		free(f);
		largest = fmax(largest, reaction);
		double worst = fmBody_ComputeDamage(id, NULL);
		CHECK(worst > 0.0);
		if (worst < 1.0)
			step = pulled * (1.01 / worst - 1.0);
		else
		{
			CHECK(fmBody_Fracture(id) > 0);
			step = 0.0;
		}
	}
	free(topVertex);
	if (getenv("FEMTO_TEST_VERBOSE"))
		printf("    n %d: %d faces broken, %d pieces, %d vertices, pulled %.4g mm\n", n,
		       fmBody_GetBrokenFaceCount(id), fmBody_GetPieces(id, NULL), fmBody_GetVertexCount(id),
		       1e3 * pulled);
	CHECK_INT(fmBody_GetPieces(id, NULL), 2);
	CHECK(fmBody_GetVertexCount(id) > mesh.nodeCount);
	fmDestroyWorld(world);
	freePlate(&mesh);
	return largest;
}

TEST(notched_plate_tears_at_one_load_on_two_meshes)
{
	double coarse = tearingLoad(failures_, 12), fine = tearingLoad(failures_, 24);
	printf("    notched plate: tearing load %.5g N (12 x 12 cubes), %.5g N (24 x 24): %.2f%%\n",
	       coarse, fine, 100.0 * (fine - coarse) / coarse);
	CHECK(coarse > 0.0 && fine > 0.0);
	CHECK(fabs(fine - coarse) <= 0.10 * coarse);
	// Below the unnotched section's 1e4 Pa x 0.1 m x 0.01 m = 10 N: the notch concentrates.
	CHECK(fine < 10.0 && coarse < 10.0);
}

// A 4 x 4 x 4 box of a tearing Neo-Hookean (strength @p strength) stretched to 1.6 times its
// height along y and moving: its faces across y are over strength.
static fmBodyId stretchedBox(fmWorldId* world, double strength)
{
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.fracture.strength = strength;
	fmBodyId id = fmTestMakeBox(world, 4, 4, 4, fmMakeVec3(0.2, 0.2, 0.2), m, fm_fem);
	int n = fmBody_GetVertexCount(id);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	double* v = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(id), sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
	{
		x[3 * i + 1] *= 1.6;
		v[3 * i] = 1.0 + x[3 * i + 1];
		v[3 * i + 1] = -2.0 * x[3 * i];
		v[3 * i + 2] = 0.5;
	}
	fmBody_SetPositions(id, x);
	fmBody_SetVelocities(id, v);
	free(x);
	free(v);
	return id;
}

// A tear shares each split vertex's mass among its copies by tet volume and gives each its
// velocity: mass and momentum are the body's before the tear, to round-off.
TEST(a_tear_conserves_mass_and_momentum)
{
	fmWorldId world;
	fmBodyId id = stretchedBox(&world, 1e3);
	CHECK(fmBody_IsValid(id));
	double mass = fmTestMass(id);
	fmVec3 momentum = fmTestMomentum(id);
	int before = fmBody_GetVertexCount(id);
	// A strength just under the faces across y's traction: those break (four layers), the
	// slanted faces (half the traction or less) hold.
	double worst = fmBody_ComputeDamage(id, NULL);
	CHECK(worst > 1.0);
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.fracture.strength = 1e3 * worst / 1.05;
	CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
	int broken = fmBody_Fracture(id);
	CHECK(broken > 0);
	CHECK_INT(fmBody_GetBrokenFaceCount(id), broken);
	CHECK(fmBody_GetVertexCount(id) > before);
	CHECK(fmBody_GetPieces(id, NULL) >= 2);
	CHECK_REL(fmTestMass(id), mass, 1e-13, 0.0);
	fmVec3 after = fmTestMomentum(id);
	CHECK_NEAR(after.x, momentum.x, 1e-13 * fmTestMass(id) * 4.0);
	CHECK_NEAR(after.y, momentum.y, 1e-13 * fmTestMass(id) * 4.0);
	CHECK_NEAR(after.z, momentum.z, 1e-13 * fmTestMass(id) * 4.0);
	// Every piece: a tet's corners are one piece's vertices.
	int* piece = malloc(sizeof(int) * (size_t)fmBody_GetTetCount(id));
	int pieces = fmBody_GetPieces(id, piece);
	CHECK(pieces >= 2);
	for (int t = 0; t < fmBody_GetTetCount(id); ++t)
		CHECK(piece[t] >= 0 && piece[t] < pieces);
	free(piece);
	CHECK_INT(pieces, 4);
	CHECK_INT(fmBody_Fracture(id), 0); // (what held holds at the same positions)
	fmDestroyWorld(world);
}

// A body whose material does not tear never breaks, whatever its stress.
TEST(an_untearing_body_never_breaks)
{
	fmWorldId world;
	fmBodyId id = stretchedBox(&world, 1e3);
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
	CHECK_NEAR(fmBody_ComputeDamage(id, NULL), 0.0, 0.0);
	CHECK_INT(fmBody_Fracture(id), 0);
	CHECK_INT(fmBody_GetPieces(id, NULL), 1);
	fmDestroyWorld(world);
}

// A box dropped on a sharp edge (a box collider turned 45 degrees) breaks into pieces; their
// masses sum to the box's, every frame steps, the pieces' surfaces stay apart; with 1 and 2
// workers the same bits.
static fmBodyId edgeDrop(int* failures_, int workers, fmWorldId* world)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 4, 4, fmMakeVec3(-0.1, 0.3, -0.1), fmMakeVec3(0.1, 0.5, 0.1), &mesh),
	          fm_ok);
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.workerCount = workers;
	wdef.integrator = fm_implicit;
	*world = fmCreateWorld(&wdef);
	fmColliderDef edge = fmDefaultColliderDef();
	edge.shape = fm_shapeBox;
	edge.center = fmMakeVec3(0.0, 0.0, 0.0);
	edge.halfExtents = fmMakeVec3(0.1, 0.1, 0.3);
	edge.rotation = fmMakeVec3(0.0, 0.0, 0.785398163397448);
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(*world, &edge, &collider, NULL), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 2e5, 0.3);
	def.material.fracture.strength = 4e3;
	def.massMode = fm_massFromDensity;
	fmBodyId id;
	CHECK_INT(fmCreateBody(*world, &def, &id, NULL), fm_ok);
	fmBody_ApplyImpulse(id, fmMakeVec3(0.0, -4.0, 0.0));
	fmFreeTetMesh(&mesh);
	return id;
}

static void dropOnEdge(int* failures_, int workers, double* positions, int* vertexCount,
                       int* pieces)
{
	fmWorldId world;
	fmBodyId id = edgeDrop(failures_, workers, &world);
	double mass = fmTestMass(id);
	for (int frame = 0; frame < 40; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	*pieces = fmBody_GetPieces(id, NULL);
	*vertexCount = fmBody_GetVertexCount(id);
	CHECK_REL(fmTestMass(id), mass, 1e-13, 0.0);
	memcpy(positions, fmTestPositions(id), sizeof(double) * 3 * (size_t)*vertexCount);
	fmContactAudit audit;
	CHECK_INT(fmWorld_AuditContact(world, &audit), fm_ok);
	CHECK_INT(audit.selfCrossings, 0);
	fmDestroyWorld(world);
}

TEST(a_box_dropped_on_an_edge_breaks_keeping_its_mass)
{
	double* one = malloc(sizeof(double) * 3 * 4 * 384);
	double* two = malloc(sizeof(double) * 3 * 4 * 384);
	int n1 = 0, n2 = 0, p1 = 0, p2 = 0;
	dropOnEdge(failures_, 1, one, &n1, &p1);
	dropOnEdge(failures_, 2, two, &n2, &p2);
	printf("    box on an edge: %d pieces, %d vertices (125 before)\n", p1, n1);
	CHECK(p1 >= 2);
	CHECK_INT(n1, n2);
	CHECK_INT(p1, p2);
	CHECK(n1 == n2 && memcmp(one, two, sizeof(double) * 3 * (size_t)n1) == 0);
	free(one);
	free(two);
}

// Ten frames from now: the body's vertex count and positions (a buffer the caller frees).
static double* tenFrames(int* failures_, fmWorldId world, fmBodyId id, int* count)
{
	for (int frame = 0; frame < 10; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	*count = fmBody_GetVertexCount(id);
	double* x = malloc(sizeof(double) * 3 * (size_t)*count);
	memcpy(x, fmTestPositions(id), sizeof(double) * 3 * (size_t)*count);
	return x;
}

// A snapshot holds the torn state: restored into the world it came from after more frames, or
// into a new world whose box never broke, the next frames are the same bits; a snapshot of the
// whole box restored into the torn world makes it whole again.
TEST(snapshots_hold_the_torn_state)
{
	fmWorldId world, fresh;
	fmBodyId id = edgeDrop(failures_, 1, &world);
	for (int frame = 0; frame < 60 && fmBody_GetPieces(id, NULL) < 2; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK(fmBody_GetPieces(id, NULL) >= 2);
	size_t size = fmWorld_GetSnapshotSize(world);
	void* torn = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, torn, size, NULL), fm_ok);
	int n1, n2, n3;
	double* first = tenFrames(failures_, world, id, &n1);
	CHECK_INT(fmWorld_RestoreSnapshot(world, torn, size), fm_ok);
	double* again = tenFrames(failures_, world, id, &n2);
	CHECK(n1 == n2 && memcmp(first, again, sizeof(double) * 3 * (size_t)n1) == 0);

	fmBodyId other = edgeDrop(failures_, 1, &fresh);
	int whole = fmBody_GetVertexCount(other);
	size_t wholeSize = fmWorld_GetSnapshotSize(fresh);
	void* untorn = malloc(wholeSize);
	CHECK_INT(fmWorld_SaveSnapshot(fresh, untorn, wholeSize, NULL), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(fresh, torn, size), fm_ok);
	CHECK_INT(fmBody_GetPieces(other, NULL), fmBody_GetPieces(id, NULL));
	double* there = tenFrames(failures_, fresh, other, &n3);
	CHECK(n1 == n3 && memcmp(first, there, sizeof(double) * 3 * (size_t)n1) == 0);
	CHECK_INT(fmWorld_RestoreSnapshot(fresh, untorn, wholeSize), fm_ok);
	CHECK_INT(fmBody_GetVertexCount(other), whole);
	CHECK_INT(fmBody_GetPieces(other, NULL), 1);
	CHECK_INT(fmBody_GetBrokenFaceCount(other), 0);
	free(first);
	free(again);
	free(there);
	free(torn);
	free(untorn);
	fmDestroyWorld(world);
	fmDestroyWorld(fresh);
}

// A body of particle masses (the seeds' 1 kg a vertex, which never came from volumes) shares a
// split vertex's mass by its tets' count: each copy holds its tets' share of the original's
// kilogram; the masses still sum to the vertex count.
TEST(particle_masses_are_shared_by_tet_count)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 4, 4, fmMakeVec3(0, 0, 0), fmMakeVec3(0.2, 0.2, 0.2), &mesh), fm_ok);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	def.material.fracture.strength = 1e3;
	fmBodyId id;
	CHECK_INT(fmCreateBody(world, &def, &id, NULL), fm_ok);
	int n = fmBody_GetVertexCount(id);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(id), sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
		x[3 * i + 1] *= 1.6;
	fmBody_SetPositions(id, x);
	free(x);
	fmMaterial m = def.material;
	m.fracture.strength = 1e3 * fmBody_ComputeDamage(id, NULL) / 1.05;
	CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
	CHECK(fmBody_Fracture(id) > 0);
	int count = fmBody_GetVertexCount(id), tets = fmBody_GetTetCount(id);
	CHECK(count > n);
	CHECK_REL(fmTestMass(id), (double)n, 1e-13, 0.0);
	// Each vertex's tets now, and its original's (the same corner of the same tet before).
	int* around = calloc((size_t)count, sizeof(int));
	int* whole = calloc((size_t)n, sizeof(int));
	const int* corners = fmBody_GetTets(id);
	for (int e = 0; e < 4 * tets; ++e)
	{
		around[corners[e]] += 1;
		whole[mesh.tets[e]] += 1;
	}
	const double* mass = fmBody_GetMasses(id);
	int wrong = 0;
	for (int e = 0; e < 4 * tets; ++e)
		wrong += fabs(mass[corners[e]] - (double)around[corners[e]] / whole[mesh.tets[e]]) > 1e-12;
	CHECK_INT(wrong, 0);
	free(around);
	free(whole);
	fmFreeTetMesh(&mesh);
	fmDestroyWorld(world);
}

// No slivers: the stretched box's tear cuts it into four layers of a quarter of its volume
// each; a smallest piece of 0.3 of the box holds every face (nothing may come off), 0.2 lets the
// four layers go.
TEST(a_tear_never_cuts_off_a_piece_below_the_smallest_volume)
{
	const double volume = 0.2 * 0.2 * 0.2;
	const double smallest[2] = {0.3 * volume, 0.2 * volume};
	const int pieces[2] = {1, 4};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBodyId id = stretchedBox(&world, 1e3);
		fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
		m.fracture.strength = 1e3 * fmBody_ComputeDamage(id, NULL) / 1.05;
		m.fracture.minVolume = smallest[k];
		CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
		int before = fmBody_GetVertexCount(id);
		int broken = fmBody_Fracture(id);
		CHECK_INT(fmBody_GetPieces(id, NULL), pieces[k]);
		CHECK(k == 0 ? broken == 0 && fmBody_GetVertexCount(id) == before : broken > 0);
		fmDestroyWorld(world);
	}
}

// A nodal material's volume term lives on its vertices; the criterion reads it back as the
// tets' pressure: a box stretched the same in every direction (a uniform J, where the patches'
// pressure is each tet's own) reads the per-tet body's damage, and tears as it does.
TEST(the_criterion_reads_the_nodal_pressure)
{
	double damage[2];
	int broken[2];
	for (int nodal = 0; nodal < 2; ++nodal)
	{
		fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.45);
		m.nodalPressure = nodal == 1;
		m.fracture.strength = 1e4;
		fmWorldId world;
		fmBodyId id = fmTestMakeBox(&world, 3, 3, 3, fmMakeVec3(0.3, 0.3, 0.3), m, fm_fem);
		int n = fmBody_GetVertexCount(id);
		double* x = malloc(sizeof(double) * 3 * (size_t)n);
		memcpy(x, fmTestPositions(id), sizeof(double) * 3 * (size_t)n);
		for (int k = 0; k < 3 * n; ++k)
			x[k] *= 1.1;
		fmBody_SetPositions(id, x);
		free(x);
		damage[nodal] = fmBody_ComputeDamage(id, NULL);
		broken[nodal] = fmBody_Fracture(id);
		fmDestroyWorld(world);
	}
	CHECK(damage[0] > 1.0);
	CHECK_REL(damage[1], damage[0], 1e-9, 0.0);
	CHECK_INT(broken[1], broken[0]);
}

// A snapshot of fewer vertices than the body has now is refused while something holds one of
// the vertices it would lose (here a target on a copy), and the world stays as it was.
TEST(a_less_torn_snapshot_is_refused_while_its_lost_vertices_are_held)
{
	fmWorldId world;
	fmBodyId id = stretchedBox(&world, 1e3);
	int whole = fmBody_GetVertexCount(id);
	size_t size = fmWorld_GetSnapshotSize(world);
	void* untorn = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, untorn, size, NULL), fm_ok);
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.fracture.strength = 1e3 * fmBody_ComputeDamage(id, NULL) / 1.05;
	CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
	CHECK(fmBody_Fracture(id) > 0);
	int torn = fmBody_GetVertexCount(id);
	int copy = torn - 1;
	fmVec3 at = fmMakeVec3(fmTestPositions(id)[3 * copy], fmTestPositions(id)[3 * copy + 1],
	                       fmTestPositions(id)[3 * copy + 2]);
	CHECK_INT(fmBody_SetTargets(id, &copy, &at, 1, 100.0), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(world, untorn, size), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "held by a target");
	CHECK_INT(fmBody_GetVertexCount(id), torn);
	CHECK_INT(fmBody_SetTargets(id, NULL, NULL, 0, 0.0), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(world, untorn, size), fm_ok);
	CHECK_INT(fmBody_GetVertexCount(id), whole);
	free(untorn);
	fmDestroyWorld(world);
}

// A render mesh is bound to tets, which a tear keeps: each render vertex follows its tet's
// piece. The stretched box torn into its four layers, each layer moved by its own offset: a
// render triangle inside each layer moves by that layer's offset.
TEST(a_render_mesh_follows_the_pieces)
{
	fmWorldId world;
	fmBodyId id = stretchedBox(&world, 1e3);
	// one small triangle in the middle of each layer (the layers are 0.08 m high after the
	// stretch; the rest shape's layers are 0.05 m)
	double vertices[4 * 9];
	int triangles[4 * 3];
	for (int layer = 0; layer < 4; ++layer)
	{
		double y = 0.05 * layer + 0.025;
		double corner[9] = {0.09, y, 0.09, 0.11, y, 0.09, 0.10, y, 0.11};
		memcpy(vertices + 9 * layer, corner, sizeof corner);
		for (int k = 0; k < 3; ++k)
			triangles[3 * layer + k] = 3 * layer + k;
	}
	CHECK_INT(fmBody_SetRenderMesh(id, vertices, 12, triangles, 4, NULL), fm_ok);
	fmMaterial m = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	m.fracture.strength = 1e3 * fmBody_ComputeDamage(id, NULL) / 1.05;
	CHECK_INT(fmBody_SetMaterial(id, &m, NULL), fm_ok);
	CHECK(fmBody_Fracture(id) > 0);
	double before[36], after[36];
	CHECK_INT(fmBody_CopyRenderPositions(id, before, NULL, 12), fm_ok);
	int tets = fmBody_GetTetCount(id), n = fmBody_GetVertexCount(id);
	int* piece = malloc(sizeof(int) * (size_t)tets);
	CHECK_INT(fmBody_GetPieces(id, piece), 4);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(x, fmTestPositions(id), sizeof(double) * 3 * (size_t)n);
	const int* corners = fmBody_GetTets(id);
	for (int e = 0; e < 4 * tets; ++e) // each vertex moved along x by its piece's number
		x[3 * corners[e]] = fmTestPositions(id)[3 * corners[e]] + piece[e / 4];
	fmBody_SetPositions(id, x);
	CHECK_INT(fmBody_CopyRenderPositions(id, after, NULL, 12), fm_ok);
	// The layers' pieces in order of height: the render triangles move by 0..3 in some order,
	// each by a whole offset, no two alike.
	int seen = 0;
	for (int layer = 0; layer < 4; ++layer)
	{
		double shift = after[9 * layer] - before[9 * layer];
		int offset = (int)lround(shift);
		CHECK_NEAR(shift, (double)offset, 1e-9);
		for (int k = 0; k < 3; ++k)
			CHECK_NEAR(after[9 * layer + 3 * k] - before[9 * layer + 3 * k], shift, 1e-9);
		seen |= 1 << offset;
	}
	CHECK_INT(seen, 15);
	free(piece);
	free(x);
	fmDestroyWorld(world);
}
