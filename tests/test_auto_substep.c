// Automatic substeps (fmWorldDef.autoSubstep, the scenes' "substeps": "auto"): a frame of 1/60 s
// given to fmWorld_Step as one step is split into substeps of at most 0.3 of the estimated
// stability limit. Physics: a stiff cube meshed by TetGen, and a cube whose mesh has slivers
// (dihedral angles under 5 degrees, which shrink the stable step), dropped on the floor, stay
// finite, uninverted and within their energy for two seconds; the same frames taken as single
// steps fail (the check can fail).
#include "support.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The drop: a 1 m cube (density 1000 kg/m^3, Neo-Hookean E = 1 MPa, nu = 0.3) 0.1 m above the
// floor, @p frames frames of 1/60 s, each one fmWorld_Step(1/60, 1). Returns the first failure
// (fm_ok if none); @p steps gets the substeps taken, @p inverted the inverted tets at the end and
// @p lowest the lowest vertex reached.
static fmResult dropCube(const fmTetMesh* mesh, bool autoSubstep, int frames, long* steps,
                         int* inverted, double* lowest)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.gravity = fmMakeVec3(0, -9.8, 0);
	wdef.floor.enabled = true;
	wdef.floor.height = -0.1;
	wdef.autoSubstep = autoSubstep;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = mesh;
	bdef.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &bdef, &body, NULL);
	*steps = 0;
	*lowest = INFINITY;
	for (int frame = 0; frame < frames && r == fm_ok; ++frame)
	{
		r = fmWorld_Step(world, 1.0 / 60.0, 1);
		*steps += fmWorld_GetStepStats(world).steps;
		fmBodyStats stats = fmBody_GetStats(body);
		*lowest = fmin(*lowest, stats.lowestY);
		if (r == fm_ok && !(stats.kineticEnergy < 1e4))
			r = fm_errNumerical; // runaway: the cube's drop releases about 1 kJ at most
	}
	*inverted = fmBody_GetStats(body).invertedTets;
	fmDestroyWorld(world);
	return r;
}

static void checkStableOnlyWithAuto(int* failures_, const fmTetMesh* mesh, const char* what)
{
	long steps = 0;
	int inverted = 0;
	double lowest = 0.0;
	fmResult r = dropCube(mesh, true, 120, &steps, &inverted, &lowest);
	printf("  %s, auto substeps: %s after 120 frames, %ld substeps (%.1f a frame), lowest y %.4f "
	       "m, %d inverted\n",
	       what, fmResultName(r), steps, steps / 120.0, lowest, inverted);
	CHECK_INT(r, fm_ok);
	CHECK_INT(inverted, 0);
	CHECK(lowest > -0.11 && lowest < -0.09); // it reached the floor and stayed on it
	CHECK(steps > 120);                      // it did split the frames
	long plainSteps = 0;
	r = dropCube(mesh, false, 120, &plainSteps, &inverted, &lowest);
	printf("  %s, one step a frame: %s\n", what, fmResultName(r));
	CHECK(r != fm_ok);
}

TEST(tetgen_mesh_stable_at_the_frame_time)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/tetgen_cube.node", FEMTO_TEST_DATA "/tetgen_cube.ele",
	                       &mesh, &diag),
	          fm_ok);
	checkStableOnlyWithAuto(failures_, &mesh, "TetGen cube (715 tets)");
	fmFreeTetMesh(&mesh);
}

// A 4 x 4 x 4 box mesh whose interior node nearest (0.5, 0.5, 0.5) is moved along the diagonal
// until a tet around it is a sliver (a dihedral angle under 5 degrees), none inverted.
static bool makeSliverCube(fmTetMesh* mesh, double* minDihedral)
{
	if (fmMakeBoxMesh(4, 4, 4, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), mesh) != fm_ok)
		return false;
	int node = -1;
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		const double* p = mesh->positions + 3 * i;
		if (fabs(p[0] - 0.5) + fabs(p[1] - 0.5) + fabs(p[2] - 0.5) < 1e-12)
			node = i;
	}
	double* p = mesh->positions + 3 * node;
	for (double s = 0.05; s < 0.25; s += 0.0025)
	{
		p[0] = p[1] = p[2] = 0.5 + s;
		fmMeshInfo info;
		if (fmTetMesh_GetInfo(mesh, &info) != fm_ok || info.invertedTets > 0 ||
		    info.degenerateTets > 0)
			break;
		*minDihedral = info.minDihedralDeg;
		if (info.minDihedralDeg < 5.0)
			return true;
	}
	return false;
}

TEST(sliver_mesh_stable_at_the_frame_time)
{
	fmTetMesh mesh;
	double minDihedral = 90.0;
	CHECK(makeSliverCube(&mesh, &minDihedral));
	printf("  sliver cube: smallest dihedral angle %.2f degrees\n", minDihedral);
	CHECK(minDihedral < 5.0);
	checkStableOnlyWithAuto(failures_, &mesh, "sliver cube (384 tets)");
	fmFreeTetMesh(&mesh);
}
