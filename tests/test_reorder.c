// A body keeps its vertices and tets in its own order (reorder.c, body.c); every public call
// speaks the user's numbering. A mesh and the same mesh with its vertices and tets shuffled
// give the same body, vertex for vertex through the shuffle.
#include "support.h"
#include "test.h"

#include "body/body.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// @p mesh with vertex i renamed perm[i] and tet t moved to place tetPerm[t] (caller frees).
static fmTetMesh shuffled(const fmTetMesh* mesh, const int* perm, const int* tetPerm)
{
	fmTetMesh s = *mesh;
	s.positions = malloc(sizeof(double) * 3 * (size_t)mesh->nodeCount);
	s.tets = malloc(sizeof(int) * 4 * (size_t)mesh->tetCount);
	for (int i = 0; i < mesh->nodeCount; ++i)
		memcpy(s.positions + 3 * perm[i], mesh->positions + 3 * i, sizeof(double) * 3);
	for (int t = 0; t < mesh->tetCount; ++t)
		for (int a = 0; a < 4; ++a)
			s.tets[4 * tetPerm[t] + a] = perm[mesh->tets[4 * t + a]];
	return s;
}

static void randomPermutation(int* p, int n)
{
	for (int i = 0; i < n; ++i)
		p[i] = i;
	for (int i = n - 1; i > 0; --i)
	{
		int j = (int)fmTestRandom(0, i + 1);
		j = j > i ? i : j;
		int t = p[i];
		p[i] = p[j], p[j] = t;
	}
}

// A body of @p mesh on the seeds' floor, vertex @p pinned pinned and @p kicked kicked, after 40
// explicit steps: its positions (caller frees).
static double* simulate(int* failures_, const fmTetMesh* mesh, int pinned, int kicked,
                        fmWorldId* world, fmBodyId* body)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = mesh;
	CHECK_INT(fmCreateBody(*world, &def, body, NULL), fm_ok);
	fmBody_SetPinned(*body, pinned, true);
	fmBody_ApplyVertexImpulse(*body, kicked, fmMakeVec3(0.5, 1.0, 0.0));
	CHECK_INT(fmWorld_Step(*world, 0.12, 40), fm_ok);
	double* x = malloc(sizeof(double) * 3 * (size_t)mesh->nodeCount);
	CHECK_INT(fmBody_CopyPositions(*body, x, mesh->nodeCount), fm_ok);
	return x;
}

TEST(a_shuffled_mesh_gives_the_same_body_in_the_users_numbering)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 3, 3, fmMakeVec3(-1, -2.9, -0.5), fmMakeVec3(1, -2, 0.5), &mesh),
	          fm_ok);
	int n = mesh.nodeCount, m = mesh.tetCount;
	int* perm = malloc(sizeof(int) * (size_t)n);
	int* tetPerm = malloc(sizeof(int) * (size_t)m);
	fmTestSeed(11);
	randomPermutation(perm, n);
	randomPermutation(tetPerm, m);
	fmTetMesh other = shuffled(&mesh, perm, tetPerm);

	fmWorldId worldA, worldB;
	fmBodyId a, b;
	double* xa = simulate(failures_, &mesh, 0, 7, &worldA, &a);
	double* xb = simulate(failures_, &other, perm[0], perm[7], &worldB, &b);
	double moved = 0.0, err = 0.0;
	for (int i = 0; i < n; ++i)
		for (int k = 0; k < 3; ++k)
		{
			err = fmax(err, fabs(xa[3 * i + k] - xb[3 * perm[i] + k]));
			moved = fmax(moved, fabs(xa[3 * i + k] - mesh.positions[3 * i + k]));
		}
	CHECK(moved > 1e-3); // it fell and was kicked
	CHECK(err < 1e-9);   // summation orders differ, nothing else
	CHECK(fmBody_IsPinned(b, perm[0]) && !fmBody_IsPinned(b, perm[1]));
	for (int k = 0; k < 3; ++k)
		CHECK(xb[3 * perm[0] + k] == mesh.positions[k]); // the pinned vertex stayed

	// Masses, tets and surface in the user's numbering and order.
	const double* ma = fmBody_GetMasses(a);
	const double* mb = fmBody_GetMasses(b);
	for (int i = 0; i < n; ++i)
		CHECK(ma[i] == mb[perm[i]]);
	const int* tb = fmBody_GetTets(b);
	for (int t = 0; t < m; ++t)
	{
		int same = 0; // the user's tet, its nodes perhaps swapped by orientation
		for (int p = 0; p < 4; ++p)
			for (int q = 0; q < 4; ++q)
				same += tb[4 * t + p] == other.tets[4 * t + q];
		CHECK_INT(same, 4);
	}
	int triA, triB;
	const int* sa = fmBody_GetSurface(a, &triA);
	const int* sb = fmBody_GetSurface(b, &triB);
	CHECK_INT(triA, triB);
	double areaA = 0.0, areaB = 0.0; // the same surface: the same area from the user's positions
	for (int k = 0; k < triA; ++k)
	{
		fmVec3 p[3], q[3];
		for (int c = 0; c < 3; ++c)
			p[c] = fmLoad(mesh.positions, sa[3 * k + c]),
			q[c] = fmLoad(other.positions, sb[3 * k + c]);
		areaA += fmLength(fmCross(fmSub(p[1], p[0]), fmSub(p[2], p[0])));
		areaB += fmLength(fmCross(fmSub(q[1], q[0]), fmSub(q[2], q[0])));
	}
	CHECK_REL(areaA, areaB, 1e-12, 0.0);

	// Forces in the user's numbering.
	double* fa = calloc(3 * (size_t)n, sizeof(double));
	double* fb = calloc(3 * (size_t)n, sizeof(double));
	fmBody_ComputeElasticForces(a, fa);
	fmBody_ComputeElasticForces(b, fb);
	double scale = 0.0, ferr = 0.0;
	for (int i = 0; i < n; ++i)
		for (int k = 0; k < 3; ++k)
		{
			scale = fmax(scale, fabs(fa[3 * i + k]));
			ferr = fmax(ferr, fabs(fa[3 * i + k] - fb[3 * perm[i] + k]));
		}
	CHECK(scale > 0.0 && ferr <= 1e-9 * scale);

	// The body's own order is not the user's (else this test would prove nothing).
	const fmBody* body = fmGetBody(b);
	int moves = 0;
	for (int i = 0; body != NULL && i < n; ++i)
		moves += body->userVertex[i] != i;
	CHECK(moves > n / 2);

	free(fa), free(fb), free(xa), free(xb), free(perm), free(tetPerm);
	free(other.positions), free(other.tets);
	fmFreeTetMesh(&mesh);
	fmDestroyWorld(worldA);
	fmDestroyWorld(worldB);
}
