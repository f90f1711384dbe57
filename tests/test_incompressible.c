// Nearly incompressible bodies (issue 34, item 4): the averaged nodal pressure
// (fem/nodal_pressure.h). Its forces are minus its energy's gradient and its Hessian the forces'
// derivative (finite differences, every law, exact and projected), the assembled Newton matrix
// holds the patches' couplings, a uniform stretch gives each tet the per-tet model's stress (the
// patch test: the average of a constant is the constant), and the tet part keeps no volume
// stiffness. (The cantilever against CalculiX as the mesh is refined: test_calculix.c; the house
// dropped at nu = 0.4999: below.)
#include "body/body.h"
#include "core/parallel.h"
#include "fem/forces.h"
#include "fem/nodal_pressure.h"
#include "material/material.h"
#include "solver/bsr.h"
#include "solver/solver_cache.h"
#include "support.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const fmMaterialModel s_laws[] = {fm_linear, fm_neoHookean, fm_mooneyRivlin,
                                         fm_neoHookeanIsochoric};
#define LAW_COUNT ((int)(sizeof s_laws / sizeof s_laws[0]))

static fmMaterial nodalMaterial(fmMaterialModel model, double nu)
{
	fmMaterial m = fmMakeMaterial(model, 1e5, nu);
	m.nodalPressure = true;
	return m;
}

// A 2x3x2 box of the law, perturbed by 5% of its size (squeezed and stretched tets).
static fmBodyId perturbedBox(fmWorldId* world, fmMaterialModel model)
{
	fmBodyId id =
	    fmTestMakeBox(world, 2, 3, 2, fmMakeVec3(1, 1.5, 1), nodalMaterial(model, 0.45), fm_fem);
	if (fmBody_IsValid(id))
		fmTestPerturb(id, 0.05);
	return id;
}

// K dx against (f(x - h dx) - f(x + h dx)) / 2h, and the projected K positive semi-definite.
static void checkHessian(int* failures_, const fmElasticMesh* mesh, const double* x)
{
	int n3 = 3 * mesh->vertexCount;
	size_t bytes = sizeof(double) * (size_t)n3;
	double *dx = malloc(bytes), *kdx = calloc(1, bytes), *xp = malloc(bytes), *xm = malloc(bytes);
	double *fp = calloc(1, bytes), *fm = calloc(1, bytes);
	const double h = 1e-6;
	for (int k = 0; k < n3; ++k)
	{
		dx[k] = fmTestRandom(-1, 1);
		xp[k] = x[k] + h * dx[k];
		xm[k] = x[k] - h * dx[k];
	}
	fmAddHessianProduct(mesh, x, dx, kdx, 0);
	fmAddElasticForces(mesh, xp, fp);
	fmAddElasticForces(mesh, xm, fm);
	double scale = 0.0, worst = 0.0;
	for (int k = 0; k < n3; ++k)
		scale = fmax(scale, fabs(kdx[k]));
	for (int k = 0; k < n3; ++k)
		worst = fmax(worst, fabs(kdx[k] - (fm[k] - fp[k]) / (2 * h)));
	CHECK(scale > 0.0);
	CHECK(worst <= 1e-5 * scale);
	memset(kdx, 0, bytes);
	fmAddHessianProduct(mesh, x, dx, kdx, 1);
	double quad = 0.0;
	for (int k = 0; k < n3; ++k)
		quad += dx[k] * kdx[k];
	CHECK(quad >= 0.0);
	free(dx);
	free(kdx);
	free(xp);
	free(xm);
	free(fp);
	free(fm);
}

// Every law: the forces are minus the energy's gradient, the Hessian the forces' derivative.
TEST(nodal_derivatives_match_finite_differences)
{
	for (int m = 0; m < LAW_COUNT; ++m)
	{
		fmWorldId world;
		fmBodyId id = perturbedBox(&world, s_laws[m]);
		CHECK(fmBody_IsValid(id));
		if (!fmBody_IsValid(id))
			return;
		const fmBody* body = fmGetBody(id);
		CHECK(fmNodalPressure_On(&body->mesh));
		fmTestCheckForcesAreMinusGradient(failures_, id, 1, 1e-6);
		for (int trial = 0; trial < 3; ++trial)
			checkHessian(failures_, &body->mesh, body->state.x);
		fmDestroyWorld(world);
	}
}

// The diagonal blocks of every visited block, summed (the reference for the fast diagonal).
static void sumDiagonal(void* context, int row, int column, const double block[9])
{
	double* blocks = context;
	for (int r = 0; row == column && r < 9; ++r)
		blocks[9 * (size_t)row + r] += block[r];
}

// The Newton matrix assembled on the square pattern gives the matrix-free product, and the
// matrix-free path's diagonal (each patch's rank-one term at once) the visited blocks' diagonal.
TEST(nodal_assembled_matrix_gives_the_product)
{
	fmWorldId world;
	fmBodyId id = perturbedBox(&world, fm_neoHookean);
	CHECK(fmBody_IsValid(id));
	if (!fmBody_IsValid(id))
		return;
	fmBody* body = fmGetBody(id);
	const fmElasticMesh* mesh = &body->mesh;
	fmImplicitCache* c = fmSolverCache_Get(&body->solverCache, mesh);
	CHECK(c != NULL);
	if (c == NULL)
		return;
	int n3 = 3 * mesh->vertexCount;
	double* values = calloc(9 * (size_t)c->pattern.blocks, sizeof(double));
	double *dx = malloc(sizeof(double) * (size_t)n3), *y = calloc((size_t)n3, sizeof(double));
	double* z = calloc((size_t)n3, sizeof(double));
	for (int project = 0; project < 2; ++project)
	{
		memset(values, 0, sizeof(double) * 9 * (size_t)c->pattern.blocks);
		memset(y, 0, sizeof(double) * (size_t)n3);
		memset(z, 0, sizeof(double) * (size_t)n3);
		for (int k = 0; k < n3; ++k)
			dx[k] = fmTestRandom(-1, 1);
		fmSolverCache_AddStiffness(mesh, c, body->state.x, 1.0, project, values, NULL);
		fmBsr_Multiply(&c->pattern, values, dx, y);
		fmAddHessianProduct(mesh, body->state.x, dx, z, project);
		double scale = 0.0, worst = 0.0;
		for (int k = 0; k < n3; ++k)
		{
			scale = fmax(scale, fabs(z[k]));
			worst = fmax(worst, fabs(y[k] - z[k]));
		}
		CHECK(worst <= 1e-12 * scale);
		size_t n9 = 9 * (size_t)mesh->vertexCount;
		double *fast = calloc(n9, sizeof(double)), *slow = calloc(n9, sizeof(double));
		fmNodalPressure_AddDiagonal(mesh, body->state.x, fast, project);
		fmNodalPressure_VisitHessian(mesh, body->state.x, project, sumDiagonal, slow);
		for (size_t k = 0; k < n9; ++k)
			CHECK_NEAR(fast[k], slow[k], 1e-12 * scale);
		free(fast);
		free(slow);
	}
	free(values);
	free(dx);
	free(y);
	free(z);
	fmDestroyWorld(world);
}

// A uniform deformation: every patch has the tets' J, so each tet's stress is the per-tet
// model's (the forces of the interior vertices balance, the energy is the same); and without its
// volume term the tet part is stiff in shear only (a pure dilation costs mu-sized energy, not
// lambda-sized).
TEST(nodal_pressure_passes_the_patch_test)
{
	const fmMat3 A = {{1.03, 0.02, -0.01, 0.01, 0.97, 0.015, -0.02, 0.01, 1.05}};
	for (int m = 0; m < LAW_COUNT; ++m)
	{
		fmWorldId worlds[2];
		fmMaterial nodal = nodalMaterial(s_laws[m], 0.49), tet = nodal;
		tet.nodalPressure = false;
		fmBodyId a = fmTestMakeBox(&worlds[0], 3, 3, 3, fmMakeVec3(1, 1, 1), nodal, fm_fem);
		fmBodyId b = fmTestMakeBox(&worlds[1], 3, 3, 3, fmMakeVec3(1, 1, 1), tet, fm_fem);
		CHECK(fmBody_IsValid(a) && fmBody_IsValid(b));
		if (!fmBody_IsValid(a) || !fmBody_IsValid(b))
			return;
		fmBody *ba = fmGetBody(a), *bb = fmGetBody(b);
		int n = ba->mesh.vertexCount;
		for (int i = 0; i < n; ++i)
		{
			fmVec3 p = fmMatVec(&A, fmLoad(ba->mesh.x0, i));
			fmStore(ba->state.x, i, p);
			fmStore(bb->state.x, i, p);
		}
		double *fa = calloc(3 * (size_t)n, sizeof(double)),
		       *fb = calloc(3 * (size_t)n, sizeof(double));
		double ea = fmAddElasticForces(&ba->mesh, ba->state.x, fa);
		double eb = fmAddElasticForces(&bb->mesh, bb->state.x, fb);
		CHECK_NEAR(ea, eb, 1e-12 * fabs(eb));
		double scale = 0.0, worst = 0.0;
		for (int k = 0; k < 3 * n; ++k)
		{
			scale = fmax(scale, fabs(fb[k]));
			worst = fmax(worst, fabs(fa[k] - fb[k]));
		}
		CHECK(worst <= 1e-10 * scale);
		// The tet part alone under a 1% dilation: psi' = O(mu eps^2), far below lambda's.
		const fmMaterial* part = fmTetMaterial(&ba->mesh, 0);
		fmMat3 I = fmIdentity3(), F = fmMatScale(1.01, &I);
		double psi = fmMaterial_Evaluate(part, &F, NULL, NULL);
		double full = fmMaterial_Evaluate(&tet, &F, NULL, NULL);
		CHECK(psi < 0.1 * full);
		free(fa);
		free(fb);
		fmDestroyWorld(worlds[0]);
		fmDestroyWorld(worlds[1]);
	}
}

// What the nodal pressure refuses: a model without a J-only volume term, another force model.
TEST(nodal_pressure_refuses_what_it_cannot_split)
{
	fmMaterial m = nodalMaterial(fm_stvk, 0.45);
	fmDiagnostic diag;
	CHECK_INT(fmMaterial_Validate(&m, &diag), fm_errParameter);
	CHECK(strstr(diag.message, "nodalPressure") != NULL && strstr(diag.message, "stvk") != NULL);
	fmWorldId world;
	fmBodyId id = fmTestMakeBox(&world, 2, 2, 2, fmMakeVec3(1, 1, 1),
	                            nodalMaterial(fm_neoHookean, 0.45), fm_fvm);
	CHECK(!fmBody_IsValid(id));
	fmDestroyWorld(world);
}

// The volume of the body's tets at its positions now (m^3).
static double bodyVolume(const fmBody* b)
{
	double volume = 0.0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		volume += b->mesh.restVolume[t] * fmDet(&F);
	}
	return volume;
}

// The house as rubber (Neo-Hookean, E = 30 kPa, nu = 0.4999, the nodal pressure) dropped 1 m
// onto a frictional floor at the frame step: implicit, one step a 1/60 s frame for 3 s; explicit,
// automatic substeps for 1.2 s (FEMTO_TEST_QUICK, under the sanitizers: dropped 0.3 m, 0.75 s
// and 0.5 s, past the rebound). No step fails, no tet inverts, the volume stays within 0.5% of its
// rest volume, the centre of mass rises again after the impact (it bounces), and the implicit
// house comes to rest (within its 3 s).
static void dropRubberHouse(int* failures_, fmIntegrator integrator, int frames, bool rests)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.height = fmTestCount(0, 1) ? -2.3 : -3.0; // the house's lowest point is at -2
	wdef.integrator = integrator;
	wdef.autoSubstep = integrator == fm_explicit;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = 0.5;
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.material = fmMakeMaterial(fm_neoHookean, 3e4, 0.4999);
	bdef.material.nodalPressure = true;
	bdef.damping = 1.0;
	bdef.smoothing = 0.0;
	fmWorldId world;
	fmBodyId id = fmTestMakeHouse(&world, &wdef, &bdef);
	CHECK(fmBody_IsValid(id));
	if (!fmBody_IsValid(id))
		return;
	const fmBody* b = fmGetBody(id);
	const double rest = bodyVolume(b);
	double lowest = 1e9, highestAfter = -1e9, worstVolume = 0.0, peakKinetic = 0.0;
	int inverted = 0;
	fmResult r = fm_ok;
	for (int f = 0; f < frames && r == fm_ok; ++f)
	{
		r = fmWorld_Step(world, 1.0 / 60.0, 1);
		fmBodyStats s = fmBody_GetStats(id);
		inverted += s.invertedTets;
		worstVolume = fmax(worstVolume, fabs(bodyVolume(b) / rest - 1.0));
		peakKinetic = fmax(peakKinetic, s.kineticEnergy);
		if (s.centerOfMass.y < lowest)
		{
			lowest = s.centerOfMass.y;
			highestAfter = lowest;
		}
		highestAfter = fmax(highestAfter, s.centerOfMass.y);
	}
	CHECK_INT(r, fm_ok);
	fmBodyStats s = fmBody_GetStats(id);
	printf("  %s: rebound %.3g m, volume within %.3g%%, kinetic energy %.3g J (peak %.3g J)\n",
	       integrator == fm_implicit ? "implicit" : "explicit", highestAfter - lowest,
	       100.0 * worstVolume, s.kineticEnergy, peakKinetic);
	CHECK_INT(inverted, 0);
	CHECK(worstVolume < 0.005);
	CHECK(highestAfter - lowest > 0.01);
	if (rests)
		CHECK(s.kineticEnergy < 1e-3 * peakKinetic);
	fmDestroyWorld(world);
}

TEST(nearly_incompressible_house_drops_bounces_and_rests)
{
	int implicitFrames = fmTestCount(180, 45);
	dropRubberHouse(failures_, fm_implicit, implicitFrames, implicitFrames == 180);
	dropRubberHouse(failures_, fm_explicit, fmTestCount(72, 30), false);
}

// A nodal body's frames are the same bits on 1 and 3 workers (the patches' passes are serial
// after the parallel tet passes): a 12 x 12 x 12 box (two of the parallel force passes' ranges
// and more) of rubber landing on the floor, 6 implicit frames and 3 explicit ones (under the
// sanitizers 3 and 1).
static double* nodalBoxRun(int* failures_, fmIntegrator integrator, int workers, size_t* length)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.workerCount = workers;
	wdef.floor.height = -0.05;
	wdef.autoSubstep = integrator == fm_explicit;
	fmWorldId world = fmCreateWorld(&wdef);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(12, 12, 12, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = nodalMaterial(fm_neoHookean, 0.499);
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	fmBodyId body;
	CHECK_INT(fmCreateBody(world, &bdef, &body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	CHECK(fmGetBody(body)->mesh.tetCount >= 2 * FM_PARALLEL_MIN_RANGE);
	int frames = integrator == fm_implicit ? fmTestCount(6, 3) : fmTestCount(3, 1);
	for (int f = 0; f < frames; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	size_t n3 = 3 * (size_t)fmBody_GetVertexCount(body);
	double* out = malloc(sizeof(double) * 2 * n3);
	memcpy(out, fmTestPositions(body), sizeof(double) * n3);
	memcpy(out + n3, fmTestVelocities(body), sizeof(double) * n3);
	*length = 2 * n3;
	fmDestroyWorld(world);
	return out;
}

TEST(nodal_bodies_are_bit_identical_for_any_worker_count)
{
	for (int k = 0; k < 2; ++k)
	{
		fmIntegrator integrator = k == 0 ? fm_implicit : fm_explicit;
		size_t length, other;
		double* serial = nodalBoxRun(failures_, integrator, 1, &length);
		double* parallel = nodalBoxRun(failures_, integrator, 3, &other);
		CHECK(length == other);
		CHECK(memcmp(serial, parallel, sizeof(double) * length) == 0);
		free(serial);
		free(parallel);
	}
}

// A snapshot of a nodal body restores its frames to the bit (its kept Newton matrix on the
// square pattern included), also after the body took another nodal material (the tets' parts
// and the patches' bulk are the restored material's), and is refused by a body whose volume
// term is per tet (the record's matrix has the other pattern).
TEST(nodal_snapshots_restore_to_the_bit)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.height = -0.02;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyId body;
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(3, 3, 3, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = nodalMaterial(fm_neoHookean, 0.499);
	CHECK_INT(fmCreateBody(world, &bdef, &body, NULL), fm_ok);
	for (int f = 0; f < 5; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	size_t size = fmWorld_GetSnapshotSize(world), written = 0;
	void* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, &written), fm_ok);
	int n3 = 3 * fmBody_GetVertexCount(body);
	double* first = malloc(sizeof(double) * (size_t)n3);
	for (int f = 0; f < 5; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	memcpy(first, fmTestPositions(body), sizeof(double) * (size_t)n3);
	fmMaterial other = fmMakeMaterial(fm_linear, 3e6, 0.3);
	other.nodalPressure = true;
	CHECK_INT(fmBody_SetMaterial(body, &other, NULL), fm_ok);
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, written), fm_ok);
	for (int f = 0; f < 5; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	CHECK(memcmp(first, fmTestPositions(body), sizeof(double) * (size_t)n3) == 0);
	fmMaterial perTet = nodalMaterial(fm_neoHookean, 0.499);
	perTet.nodalPressure = false;
	CHECK_INT(fmBody_SetMaterial(body, &perTet, NULL), fm_ok);
	CHECK(fmWorld_RestoreSnapshot(world, snapshot, written) != fm_ok);
	free(first);
	free(snapshot);
	fmFreeTetMesh(&mesh);
	fmDestroyWorld(world);
}

// A nodal body at rest with nothing pulling is in balance: the static solve's round-off floor
// counts the material's whole stiffness, its volume term included.
TEST(nodal_static_solve_at_rest_converges)
{
	fmWorldId world;
	fmWorldDef wdef = fmTestFreeWorldDef();
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.material = nodalMaterial(fm_neoHookean, 0.4999);
	fmBodyId id = fmTestMakeHouse(&world, &wdef, &bdef); // (its rest forces' round-off: 1e-16)
	CHECK(fmBody_IsValid(id));
	if (!fmBody_IsValid(id))
		return;
	for (int i = 0; i < fmBody_GetVertexCount(id); ++i)
		fmBody_SetPinned(id, i, fmTestPositions(id)[3 * i + 1] < -1.9);
	double residual = 1.0;
	fmDiagnostic diag;
	CHECK_INT(fmBody_SolveStatic(id, 1e-8, 20, &residual, &diag), fm_ok);
	CHECK(residual <= 1e-8);
	fmDestroyWorld(world);
}

// The memory estimate counts the square pattern's blocks (and the patches), so a budget holds.
TEST(nodal_memory_estimate_counts_the_square_pattern)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(8, 8, 8, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = nodalMaterial(fm_neoHookean, 0.45);
	size_t nodal = fmEstimateBodyMemory(&def);
	def.material.nodalPressure = false;
	size_t perTet = fmEstimateBodyMemory(&def);
	fmBsrMatrix square;
	CHECK(fmBsr_Build(&square, mesh.nodeCount, mesh.tets, mesh.tetCount));
	CHECK(fmBsr_Square(&square));
	CHECK(nodal > perTet);
	CHECK(nodal >= 9 * sizeof(double) * (size_t)square.blocks);
	fmBsr_Free(&square);
	fmFreeTetMesh(&mesh);
}
