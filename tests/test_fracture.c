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
