// Render meshes (fmBody_SetRenderMesh): a surface embedded in a body's tets by barycentric
// coordinates. Physics: a rigid motion of the body moves the render mesh by exactly the same
// motion (inside and just outside the tets), an affine stretch is reproduced exactly, and a
// smooth non-affine deformation to first order: the error falls as h^2 when the tets halve.
#include "support.h"
#include "test.h"

#include "body/body.h"
#include "draw/render_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Random render vertices in [lo, hi]^3 (some outside the unit box when lo < 0 or hi > 1), and
// one flat square at z = 0.5 (two triangles, normal +z) on vertices 0..3.
static double* makeRenderPoints(int count, double lo, double hi, int** triangles)
{
	double* p = malloc(sizeof(double) * 3 * (size_t)count);
	for (int i = 0; i < 3 * count; ++i)
		p[i] = fmTestRandom(lo, hi);
	const double square[12] = {0.2, 0.2, 0.5, 0.8, 0.2, 0.5, 0.8, 0.8, 0.5, 0.2, 0.8, 0.5};
	memcpy(p, square, sizeof square);
	static const int tris[6] = {0, 1, 2, 0, 2, 3};
	*triangles = malloc(sizeof tris);
	memcpy(*triangles, tris, sizeof tris);
	return p;
}

static fmBodyId makeUnitBox(fmWorldId* world, int cells)
{
	return fmTestMakeBox(world, cells, cells, cells, fmMakeVec3(1, 1, 1),
	                     fmMakeMaterial(fm_neoHookean, 1e5, 0.3), fm_fem);
}

// Move every body vertex by @p map and return the largest error of the render vertices against
// the same map applied to their rest positions (and the normal of the square to @p normal).
typedef fmVec3 fmTestMap(fmVec3 p, double amount);

static double deformAndCompare(fmBodyId body, const double* rest, int count, fmTestMap* map,
                               double amount, double* normalError, fmVec3 normal)
{
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_CopyPositions(body, x, n);
	for (int i = 0; i < n; ++i)
		fmStore(x, i, map(fmLoad(x, i), amount));
	fmBody_SetPositions(body, x);
	double* out = malloc(sizeof(double) * 3 * (size_t)count);
	double* normals = malloc(sizeof(double) * 3 * (size_t)count);
	fmResult r = fmBody_CopyRenderPositions(body, out, normals, count);
	double worst = r == fm_ok ? 0.0 : INFINITY;
	for (int i = 0; i < count && r == fm_ok; ++i)
		worst = fmax(worst, fmLength(fmSub(fmLoad(out, i), map(fmLoad(rest, i), amount))));
	if (normalError != NULL)
	{
		*normalError = 0.0;
		for (int i = 0; i < 4; ++i)
			*normalError = fmax(*normalError, fmLength(fmSub(fmLoad(normals, i), normal)));
	}
	free(x);
	free(out);
	free(normals);
	return worst;
}

static fmMat3 s_rotation;

static fmVec3 rigidMap(fmVec3 p, double amount)
{
	return fmAdd(fmMatVec(&s_rotation, p), fmMakeVec3(amount, -2.0 * amount, 0.5 * amount));
}

static fmVec3 stretchMap(fmVec3 p, double amount)
{
	return fmMakeVec3((1.0 + amount) * p.x + 0.3 * amount * p.y, p.y, (1.0 - 0.5 * amount) * p.z);
}

// A smooth bend: quadratic in the coordinates, so linear interpolation errs by O(h^2).
static fmVec3 bendMap(fmVec3 p, double amount)
{
	return fmMakeVec3(p.x, p.y + amount * p.x * p.x, p.z + amount * p.x * p.y);
}

TEST(rigid_motion_exact)
{
	fmWorldId world;
	fmBodyId body = makeUnitBox(&world, 3);
	int* triangles = NULL;
	const int count = 500;
	// 10% beyond the box on every side: vertices outside follow their nearest tet's map.
	double* rest = makeRenderPoints(count, -0.1, 1.1, &triangles);
	fmDiagnostic diag;
	CHECK_INT(fmBody_SetRenderMesh(body, rest, count, triangles, 2, &diag), fm_ok);
	CHECK(diag.warningCount == 1);
	CHECK_STR_CONTAINS(diag.warning, "outside the body's tets");
	CHECK_INT(fmBody_GetRenderVertexCount(body), count);
	int triangleCount = 0;
	CHECK(fmBody_GetRenderTriangles(body, &triangleCount) != NULL);
	CHECK_INT(triangleCount, 2);
	s_rotation = fmTestRandomRotation();
	double normalError = 0.0;
	double error = deformAndCompare(body, rest, count, rigidMap, 3.0, &normalError,
	                                fmMatVec(&s_rotation, fmMakeVec3(0, 0, 1)));
	printf("  rigid motion: largest render vertex error %.3g m, normal error %.3g\n", error,
	       normalError);
	CHECK_NEAR(error, 0.0, 1e-12);
	CHECK_NEAR(normalError, 0.0, 1e-12);
	// Floats: the same numbers rounded.
	float* f = malloc(sizeof(float) * 3 * count);
	float* fn = malloc(sizeof(float) * 3 * count);
	double* d = malloc(sizeof(double) * 3 * count);
	CHECK_INT(fmBody_CopyRenderPositionsFloat(body, f, fn, count), fm_ok);
	CHECK_INT(fmBody_CopyRenderPositions(body, d, NULL, count), fm_ok);
	for (int i = 0; i < 3 * count; ++i)
		CHECK(f[i] == (float)d[i]);
	free(f);
	free(fn);
	free(d);
	free(rest);
	free(triangles);
	fmDestroyWorld(world);
}

TEST(affine_stretch_exact_smooth_bend_first_order)
{
	fmWorldId world;
	fmBodyId body = makeUnitBox(&world, 2);
	int* triangles = NULL;
	const int count = 400;
	double* rest = makeRenderPoints(count, 0.0, 1.0, &triangles);
	fmDiagnostic diag;
	CHECK_INT(fmBody_SetRenderMesh(body, rest, count, triangles, 2, &diag), fm_ok);
	CHECK_INT(diag.warningCount, 0); // all inside
	double error = deformAndCompare(body, rest, count, stretchMap, 0.5, NULL, fmMakeVec3(0, 0, 0));
	printf("  affine stretch: largest error %.3g m\n", error);
	CHECK_NEAR(error, 0.0, 1e-12);
	fmDestroyWorld(world);
	// The bend on 2, 4 and 8 cells a side: the error shrinks about 4 times per halving.
	double errors[3];
	for (int level = 0; level < 3; ++level)
	{
		body = makeUnitBox(&world, 2 << level);
		CHECK_INT(fmBody_SetRenderMesh(body, rest, count, triangles, 2, NULL), fm_ok);
		errors[level] =
		    deformAndCompare(body, rest, count, bendMap, 0.2, NULL, fmMakeVec3(0, 0, 0));
		fmDestroyWorld(world);
	}
	printf("  bend 0.2: errors %.3g, %.3g, %.3g m on h = 1/2, 1/4, 1/8 (ratios %.2f, %.2f)\n",
	       errors[0], errors[1], errors[2], errors[0] / errors[1], errors[1] / errors[2]);
	// Interpolating a quadratic on tets of edge h errs by at most |D2 phi| h^2 / 8 per axis.
	CHECK(errors[0] > 0.0 && errors[0] < 0.2 * 0.5 * 0.5);
	CHECK(errors[0] / errors[1] > 3.0 && errors[1] / errors[2] > 3.0);
	free(rest);
	free(triangles);
}

TEST(bad_input_and_no_mesh)
{
	fmWorldId world;
	fmBodyId body = makeUnitBox(&world, 2);
	double p[6] = {0.5, 0.5, 0.5, 0.2, 0.2, 0.2};
	double out[6];
	int bad[3] = {0, 1, 2};
	fmDiagnostic diag;
	CHECK_INT(fmBody_CopyRenderPositions(body, out, NULL, 2), fm_errEmpty);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message, "no render mesh");
	CHECK_INT(fmBody_SetRenderMesh(body, p, 2, bad, 1, &diag), fm_errIndex);
	CHECK_STR_CONTAINS(diag.message, "triangle 0 refers to vertex 2");
	p[4] = NAN;
	CHECK_INT(fmBody_SetRenderMesh(body, p, 2, NULL, 0, &diag), fm_errRange);
	p[4] = 0.2;
	CHECK_INT(fmBody_SetRenderMesh(body, p, 0, NULL, 0, &diag), fm_errParameter);
	CHECK_INT(fmBody_SetRenderMesh(body, p, 2, NULL, 0, &diag), fm_ok);
	CHECK_INT(fmBody_CopyRenderPositions(body, out, NULL, 1), fm_errLimit);
	CHECK_INT(fmBody_CopyRenderPositions(body, out, NULL, 2), fm_ok);
	CHECK_NEAR(out[0], 0.5, 1e-15);
	CHECK_NEAR(out[5], 0.2, 1e-15);
	fmBody_ClearRenderMesh(body);
	CHECK_INT(fmBody_GetRenderVertexCount(body), 0);
	fmDestroyWorld(world);
}

// The grid search finds what a search of every tet finds: on TetGen's irregular cube, points
// inside get a tet that contains them and points up to 0.3 m outside one at the smallest
// distance any tet has; so do points up to 20 m away, outside the grid, which the tree over the
// tets binds (the grid's rings took about 1 ms a vertex there).
TEST(grid_search_matches_brute_force)
{
	fmTetMesh mesh;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/tetgen_cube.node", FEMTO_TEST_DATA "/tetgen_cube.ele",
	                       &mesh, NULL),
	          fm_ok);
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	fmBodyId id;
	CHECK_INT(fmCreateBody(world, &bdef, &id, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	const int count = 400;
	double* p = malloc(sizeof(double) * 3 * count);
	for (int i = 0; i < 3 * count; ++i)
		p[i] = i < 900 ? fmTestRandom(-0.3, 1.3) : fmTestRandom(-20.0, 21.0);
	CHECK_INT(fmBody_SetRenderMesh(id, p, count, NULL, 0, NULL), fm_ok);
	const fmBody* body = fmGetBody(id);
	int outside = 0;
	double worst = 0.0;
	for (int i = 0; i < count; ++i)
	{
		double w[4];
		fmVec3 q = fmLoad(p, i);
		int tet = fmRenderMesh_Binding(body, i, w);
		CHECK(tet >= 0 && tet < body->mesh.tetCount);
		double found = fmRenderMesh_TetDistance(body, tet, q), best = INFINITY;
		for (int t = 0; t < body->mesh.tetCount; ++t)
			best = fmin(best, fmRenderMesh_TetDistance(body, t, q));
		worst = fmax(worst, found - best);
		outside += best > 0.0;
		if (!(found <= best + 1e-12 * fmax(1.0, best)))
			FAIL_AT("point %d: the grid's tet is %.17g m away, the nearest %.17g m", i, found,
			        best);
		// The weights reproduce the point (an affine map is exact, extrapolated or not).
		fmVec3 back = fmMakeVec3(0, 0, 0);
		for (int k = 0; k < 4; ++k)
			back = fmMulAdd(back, w[k], fmLoad(body->mesh.x0, body->mesh.tets[4 * tet + k]));
		CHECK_NEAR(fmLength(fmSub(back, q)), 0.0, 1e-12);
	}
	printf("  %d of %d points outside; largest excess over the brute-force distance %.3g m\n",
	       outside, count, worst);
	CHECK(outside > 50 && outside < count); // both kinds were tested
	free(p);
	fmDestroyWorld(world);
}
