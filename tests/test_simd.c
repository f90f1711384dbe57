// The batched float kernels of the explicit step (tet_blocks.c, tet_kernel.c): their forces
// against the double-precision reference kernel at small, large, compressed and inverted
// deformation, the same bits on every instruction set and any number of workers, and the
// run-time choice of the instruction set.
#include "support.h"
#include "test.h"

#include "body/body.h"
#include "core/det_math.h"
#include "core/simd.h"
#include "fem/forces.h"
#include "fem/stability.h"
#include "fem/tet_blocks.h"
#include "material/material.h"
#include "material/material_invariant.h"
#include "material/material_neohookean.h"
#include "material/material_stretch.h"
#include "math/svd3.h"
#include "solver/kernels/bsr_kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// A box of cells^3 cubes on a 1 m cube in a default world.
static fmBody* makeCube(int* failures_, fmWorldId* world, int cells, fmMaterialModel model)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(cells, cells, cells, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh),
	          fm_ok);
	fmWorldDef wdef = fmDefaultWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(model, 1e6, 0.3);
	fmBodyId id;
	CHECK_INT(fmCreateBody(*world, &def, &id, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	return fmGetBody(id);
}

static fmBodyId makeBox(fmWorldId* world, fmMaterialModel model)
{
	return fmTestMakeBox(world, 4, 3, 3, fmMakeVec3(1.0, 0.75, 0.75),
	                     fmMakeMaterial(model, 1e6, 0.3), fm_fem);
}

// The batched forces at the body's positions (caller frees; every colour's blocks are split
// one to a range, so a small body runs on every worker too); their energy into @p energy, the
// count of inverted tets into @p inverted (may be NULL).
static double* batchedForcesCounting(const fmBody* b, fmSimdLevel level, int workers,
                                     double* energy, int* inverted)
{
	fmTetBlocks* blocks = fmTetBlocks_Create(&b->mesh, workers);
	double* f = calloc(3 * (size_t)b->mesh.vertexCount, sizeof *f);
	if (blocks == NULL || f == NULL)
	{
		fmTetBlocks_Destroy(blocks);
		free(f);
		return NULL;
	}
	fmWorldDef def = fmDefaultWorldDef();
	def.workerCount = workers;
	fmTaskSystem tasks;
	fmTaskSystem_Init(&tasks, &def);
	*energy = fmTetBlocks_AddForces(blocks, &b->mesh, b->state.x, NULL, f, level, &tasks, true,
	                                inverted, NULL);
	fmTaskSystem_Shutdown(&tasks);
	fmTetBlocks_Destroy(blocks);
	return f;
}

static double* batchedForces(const fmBody* b, fmSimdLevel level, int workers, double* energy)
{
	return batchedForcesCounting(b, level, workers, energy, NULL);
}

// The body's energy in linear elasticity with its material's Lame constants: every model's to
// a relative O(strain) at small strain, and free of the cancellation that leaves the double
// reference of Neo-Hookean (mu/2 (I1 - 3) - mu ln J, terms of first order) with about 1e-16 / e^2
// relative error at strain e (1e-2 at 1e-7).
static double linearEnergy(const fmBody* b)
{
	fmMaterial linear = b->mesh.material;
	linear.model = fm_linear;
	double energy = 0.0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		energy += b->mesh.restVolume[t] * fmMaterial_Evaluate(&linear, &F, NULL, NULL);
	}
	return energy;
}

// max |batched - reference| / max |reference| of the forces at the body's positions; the
// relative error of the batched energy into @p energyError (against the double reference, or
// with @p smallStrain against linear elasticity's).
static double relativeError(int* failures_, const fmBody* b, double* energyError, bool smallStrain)
{
	size_t n3 = 3 * (size_t)b->mesh.vertexCount;
	double* ref = calloc(n3, sizeof *ref);
	double energy = 0.0;
	double* fast = batchedForces(b, fm_simdScalar, 1, &energy);
	*energyError = INFINITY;
	CHECK(ref != NULL && fast != NULL);
	if (ref == NULL || fast == NULL)
	{
		free(ref), free(fast);
		return INFINITY;
	}
	double reference = fmAddElasticForces(&b->mesh, b->state.x, ref);
	if (smallStrain)
		reference = linearEnergy(b);
	*energyError = fabs(energy - reference) / fabs(reference);
	double err = 0.0, scale = 0.0;
	for (size_t k = 0; k < n3; ++k)
	{
		err = fmax(err, fabs(fast[k] - ref[k]));
		scale = fmax(scale, fabs(ref[k]));
	}
	free(ref), free(fast);
	return scale > 0.0 ? err / scale : err;
}

// Map every vertex X to X + amplitude * (sin of its coordinates): a smooth, non-affine field.
static void deform(fmBody* b, double amplitude)
{
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		const double* X = b->mesh.x0 + 3 * i;
		b->state.x[3 * i + 0] = X[0] + amplitude * sin(3.0 * X[1] + 1.0);
		b->state.x[3 * i + 1] = X[1] + amplitude * sin(2.0 * X[2] + 2.0 * X[0]);
		b->state.x[3 * i + 2] = X[2] + amplitude * sin(4.0 * X[0] - X[1]);
	}
}

TEST(batched_forces_match_the_reference_kernel)
{
	const fmMaterialModel models[] = {fm_linear,       fm_stvk,      fm_neoHookean,
	                                  fm_mooneyRivlin, fm_corotated, fm_neoHookeanIsochoric};
	// From 1e-7 strain (where forming F = I + H in float would lose every digit) to 30% strain.
	const double amplitudes[] = {1e-7, 1e-4, 1e-2, 0.1};
	double worstEnergy = 0.0;
	for (int m = 0; m < 6; ++m)
		for (int a = 0; a < 4; ++a)
		{
			fmWorldId world;
			fmBody* b = fmGetBody(makeBox(&world, models[m]));
			CHECK(b != NULL);
			if (b == NULL)
				return;
			deform(b, amplitudes[a]);
			// A fixed displacement of the whole body must not matter (u = x - X in double).
			for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
				b->state.x[k] += 1000.0;
			double energyErr, err = relativeError(failures_, b, &energyErr, a == 0);
			if (!(err < 5e-7)) // float: about 1e-7 measured
				FAIL_AT("%s at amplitude %g: relative error %g", fmMaterialModelName(models[m]),
				        amplitudes[a], err);
			// The energy too, at every strain (Neo-Hookean's in a form that does not cancel; at
			// 1e-7 against linear elasticity's).
			if (!(energyErr < 1e-6))
				FAIL_AT("%s at amplitude %g: energy's relative error %g",
				        fmMaterialModelName(models[m]), amplitudes[a], energyErr);
			worstEnergy = fmax(worstEnergy, energyErr);
			fmDestroyWorld(world);
		}
	printf("  energies within %.2g (relative) of the double-precision reference (at strain 1e-7: "
	       "of linear elasticity)\n",
	       worstEnergy);
}

// Uniform dilation and compression, F = s I: J = s^3 from 0.008 (below the ln J clamp of 0.2)
// to 64, and inverted (s < 0): the Neo-Hookean and Mooney-Rivlin ln J and its continuation, and
// the corotated polar iteration and its reference fallback for near-flat and inverted tets
// (J < 0.1).
TEST(batched_forces_follow_the_reference_through_compression_and_inversion)
{
	const double scales[] = {-0.5, 0.2, 0.5, 0.58, 0.6, 0.9, 0.999, 1.001, 1.5, 4.0};
	const fmMaterialModel models[] = {fm_neoHookean, fm_mooneyRivlin, fm_neoHookeanIsochoric,
	                                  fm_corotated};
	for (int c = 0; c < 40; ++c)
	{
		int s = c % 10;
		fmMaterialModel model = models[c / 10];
		fmWorldId world;
		fmBody* b = fmGetBody(makeBox(&world, model));
		CHECK(b != NULL);
		if (b == NULL)
			return;
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			b->state.x[k] =
			    scales[s] * b->mesh.x0[k] + (k % 3 == 1 ? 0.01 * b->mesh.x0[k - 1] : 0.0);
		double energyErr, err = relativeError(failures_, b, &energyErr, false);
		// 1e-7 above the clamp, 2.4e-6 far below it. Isochoric Neo-Hookean at F = 0.5 I (J =
		// 0.125, below the clamp) is the exception: its stress's terms nearly cancel there (mu g F
		// = 1.94 mu, C10 g' I1 cof F = -1.49 mu, kappa (J - 1) cof F = -0.47 mu at nu = 0.3: the
		// net is 1% of them), so float's 1e-7 of the terms is 1e-5 of the net (measured 1.0e-5).
		double bound = model == fm_neoHookeanIsochoric && scales[s] == 0.5 ? 2e-5 : 5e-6;
		if (!(err < bound) || !(energyErr < 5e-6))
			FAIL_AT("%s, F = %g I (plus shear): relative error %g, energy's %g",
			        fmMaterialModelName(model), scales[s], err, energyErr);
		fmDestroyWorld(world);
	}
}

// A rotated body: F = R (I + H) has entries of order 1 whatever the strain, and float carries
// them to about 1e-7, so the stress error is about 1e-7 (lambda + 2 mu) absolute instead of
// relative: at strain e the forces are good to about 1e-7 / e (docs/performance.md). Measured:
// 1.4e-7 / strain (StVK) and 2.9e-7 / strain (Neo-Hookean); the bound has a margin of 10.
TEST(batched_forces_of_a_rotated_body_are_good_to_float_precision_of_the_rotation)
{
	const double strains[] = {1e-5, 1e-3, 1e-1};
	const fmMaterialModel models[] = {fm_stvk, fm_neoHookean, fm_mooneyRivlin,
	                                  fm_neoHookeanIsochoric, fm_corotated};
	fmMat3 R = fmTestRandomRotation();
	for (int m = 0; m < 5; ++m)
		for (int s = 0; s < 3; ++s)
		{
			fmWorldId world;
			fmBody* b = fmGetBody(makeBox(&world, models[m]));
			if (b == NULL)
			{
				CHECK(0);
				return;
			}
			deform(b, strains[s]);
			for (int i = 0; i < b->mesh.vertexCount; ++i)
				fmStore(b->state.x, i, fmMatVec(&R, fmLoad(b->state.x, i)));
			double energyErr, err = relativeError(failures_, b, &energyErr, false);
			if (!(err < 3e-6 / strains[s] + 5e-7) || !(energyErr < 3e-6 / strains[s] + 5e-7))
				FAIL_AT("%s rotated at strain %g: relative error %g, energy's %g",
				        fmMaterialModelName(models[m]), strains[s], err, energyErr);
			fmDestroyWorld(world);
		}
}

TEST(every_instruction_set_and_worker_count_gives_the_same_bits)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 12, fm_neoHookean);
	if (b == NULL)
		return;
	deform(b, 0.05);
	size_t bytes = 3 * (size_t)b->mesh.vertexCount * sizeof(double);
	double scalarEnergy = 0.0, energy = 0.0;
	double* scalar = batchedForces(b, fm_simdScalar, 1, &scalarEnergy);
	int compared = 0;
	for (int level = fm_simdScalar; level <= (int)fmSimd_Detect(); ++level)
		for (int workers = 1; workers <= 4; ++workers)
		{
			double* f = batchedForces(b, (fmSimdLevel)level, workers, &energy);
			CHECK(scalar != NULL && f != NULL);
			if (scalar != NULL && f != NULL &&
			    (memcmp(f, scalar, bytes) != 0 || memcmp(&energy, &scalarEnergy, sizeof energy)))
				FAIL_AT("%s on %d workers differs from scalar on one",
				        fmSimdLevelName((fmSimdLevel)level), workers);
			free(f);
			compared += 1;
		}
	printf("  scalar .. %s on 1-4 workers (%d runs, %d tets): the same bits\n",
	       fmSimdLevelName(fmSimd_Detect()), compared, b->mesh.tetCount);
	free(scalar);
	fmDestroyWorld(world);
}

// The explicit step's per-vertex stages (the blocks' sums with gravity, velocities, the
// smoothing's blend, positions: fmVertexKernel_GatherSums, _Velocities, _Blend, _Positions) at
// every instruction set: the same bits as the scalar variant, with pinned vertices and rollers
// among the vertices the vectors take four at a time (a group with one takes the general path).
// A pinned vertex stays where it is, a roller's pinned axes keep their coordinates.
TEST(the_explicit_vertex_stages_give_the_same_bits_on_every_instruction_set)
{
	const int frames = 12;
	double* first = NULL;
	size_t bytes = 0;
	int compared = 0;
	for (int level = fm_simdScalar; level <= (int)fmSimd_Detect(); ++level)
	{
		fmTetMesh mesh;
		CHECK_INT(fmMakeBoxMesh(5, 4, 4, fmMakeVec3(0, 0.2, 0), fmMakeVec3(1.25, 1.2, 1), &mesh),
		          fm_ok);
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_explicit;
		wdef.simd = (fmSimdLevel)level;
		wdef.floor.height = 0.0;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = fmDefaultBodyDef();
		def.mesh = &mesh;
		def.material = fmMakeMaterial(fm_stvk, 2e5, 0.3);
		def.damping = 0.99;
		def.smoothing = 0.2;
		fmBodyId id;
		CHECK_INT(fmCreateBody(world, &def, &id, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		const int n = fmBody_GetVertexCount(id);
		fmBody_SetPinned(id, 0, true);
		fmBody_SetPinnedAxes(id, n / 2, 1u);     // a roller held in x
		fmBody_SetPinnedAxes(id, n / 2 + 5, 6u); // one held in y and z
		double* start = malloc(sizeof(double) * 3 * (size_t)n);
		CHECK_INT(fmBody_CopyPositions(id, start, n), fm_ok);
		for (int frame = 0; frame < frames; ++frame)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 10), fm_ok);
		bytes = sizeof(double) * 6 * (size_t)n;
		double* state = malloc(bytes);
		CHECK_INT(fmBody_CopyPositions(id, state, n), fm_ok);
		CHECK_INT(fmBody_CopyVelocities(id, state + 3 * n, n), fm_ok);
		CHECK(memcmp(state, start, 3 * sizeof(double)) == 0);
		CHECK(state[3 * (n / 2)] == start[3 * (n / 2)]);
		CHECK(state[3 * (n / 2 + 5) + 1] == start[3 * (n / 2 + 5) + 1] &&
		      state[3 * (n / 2 + 5) + 2] == start[3 * (n / 2 + 5) + 2]);
		CHECK(fabs(state[3 * (n - 1) + 1] - start[3 * (n - 1) + 1]) > 1e-3); // it moved
		if (first == NULL)
			first = state;
		else
		{
			if (memcmp(state, first, bytes) != 0)
				FAIL_AT("%s differs from scalar", fmSimdLevelName((fmSimdLevel)level));
			free(state);
		}
		free(start);
		compared += 1;
		fmDestroyWorld(world);
	}
	printf("  scalar .. %s (%d levels): the same bits after %d frames\n",
	       fmSimdLevelName(fmSimd_Detect()), compared, frames);
	CHECK(compared >= 2);
	free(first);
}

// The layout the force pass relies on: every tet in one lane of one block, and every vertex
// listed once in each block that holds it, its entries in block order (the order its force sums
// are added in), and in no other block.
TEST(every_vertex_gathers_each_of_its_blocks_once_in_block_order)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 14, fm_stvk);
	fmTetBlocks* tb = b ? fmTetBlocks_Create(&b->mesh, 1) : NULL;
	CHECK(tb != NULL);
	if (tb == NULL)
		return;
	int* holds = calloc((size_t)tb->entryCount, sizeof(int)); // tets using each entry
	int* seen = calloc((size_t)b->mesh.tetCount, sizeof(int));
	int lanes = 0;
	for (int k = 0; k < tb->blockCount; ++k)
		for (int j = tb->blockStart[k]; j < tb->blockStart[k + 1]; ++j)
			for (int l = 0; l < tb->laneCount[j]; ++l, ++lanes)
				for (int a = 0; a < 4; ++a)
				{
					int e = tb->blockVertexStart[k] + tb->batches[j].row[a][l] / 4;
					if (e >= tb->blockVertexStart[k + 1])
						FAIL_AT("block %d: node %d of lane %d out of its list", k, a, l);
					else
						holds[e] += 1;
				}
	CHECK_INT(lanes, b->mesh.tetCount); // every tet once
	int placed = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		int last = -1;
		for (int q = tb->vertexEntryStart[i]; q < tb->vertexEntryStart[i + 1]; ++q, ++placed)
		{
			int e = tb->vertexEntries[q];
			if (tb->blockVertices[e] != i || holds[e] == 0 || e <= last)
				FAIL_AT("vertex %d: entry %d (of vertex %d, %d tets) after %d", i, e,
				        tb->blockVertices[e], holds[e], last);
			last = e;
		}
	}
	CHECK_INT(placed, tb->entryCount); // every entry gathered by its vertex
	// The tets around a vertex sum to its valence: no block misses one of them.
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		int tets = 0;
		for (int q = tb->vertexEntryStart[i]; q < tb->vertexEntryStart[i + 1]; ++q)
			tets += holds[tb->vertexEntries[q]];
		if (tets != b->mesh.vertexTetStart[i + 1] - b->mesh.vertexTetStart[i])
			FAIL_AT("vertex %d: %d tets in its blocks, %d around it", i, tets,
			        b->mesh.vertexTetStart[i + 1] - b->mesh.vertexTetStart[i]);
	}
	printf("  %d tets in %d blocks, %d block vertices (%.2f a tet)\n", b->mesh.tetCount,
	       tb->blockCount, tb->entryCount, (double)tb->entryCount / b->mesh.tetCount);
	free(holds), free(seen);
	fmTetBlocks_Destroy(tb);
	fmDestroyWorld(world);
}

TEST(simd_levels_resolve_to_what_the_cpu_has)
{
	fmSimdLevel best = fmSimd_Detect();
	CHECK(best >= fm_simdScalar && best <= fm_simdAvx512);
	CHECK_INT(fmSimd_Resolve(fm_simdAuto), best);
	CHECK_INT(fmSimd_Resolve(fm_simdOff), fm_simdOff);
	CHECK_INT(fmSimd_Resolve(fm_simdScalar), fm_simdScalar);
	CHECK(fmSimd_Resolve(fm_simdAvx512) <= best);
	for (int level = 0; level < fm_simdLevelCount; ++level)
	{
		fmSimdLevel back;
		CHECK(fmSimdLevelFromName(fmSimdLevelName((fmSimdLevel)level), &back));
		CHECK_INT(back, level);
	}
	fmSimdLevel none;
	CHECK(!fmSimdLevelFromName("avx1024", &none));
	fmWorldDef def = fmDefaultWorldDef();
	def.simd = (fmSimdLevel)99;
	CHECK_INT(fmWorldDef_Validate(&def, NULL), fm_errParameter);
}

// The explicit step takes the float kernels for an ordinary body and the double-precision
// reference for a very stiff one, whose strains float cannot resolve under rotation.
TEST(very_stiff_bodies_take_the_double_precision_kernel)
{
	const double moduli[] = {1e6, 1e12};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldId world;
		fmBody* b = fmGetBody(fmTestMakeBox(&world, 3, 3, 3, fmMakeVec3(1, 1, 1),
		                                    fmMakeMaterial(fm_stvk, moduli[k], 0.3), fm_fem));
		if (b == NULL)
		{
			CHECK(0);
			return;
		}
		b->mesh.totalMass = 1000.0; // density 1000 kg/m^3: typical strain 1e-2 and 1e-8
		CHECK_INT(fmWorld_Step(world, 1e-6, 1), fm_ok);
		CHECK(b->mesh.tetBlocks != NULL);
		if (b->mesh.tetBlocks != NULL)
			CHECK(fmTetBlocks_Accurate(b->mesh.tetBlocks, &b->mesh) == (k == 0));
		fmDestroyWorld(world);
	}
}

// The smoothing sums of the explicit kernels' vertex graph are the seeds' per-tet sums (each
// tet adds the sum of its 4 velocities to each of its vertices), on 1 to 4 workers and on every
// instruction set the CPU has alike.
TEST(smoothing_sums_are_the_seeds_tet_sums)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 9, fm_stvk);
	fmTetBlocks* tb = b ? fmTetBlocks_Create(&b->mesh, 4) : NULL;
	CHECK(tb != NULL);
	if (tb == NULL)
		return;
	size_t n3 = 3 * (size_t)b->mesh.vertexCount;
	double* v = malloc(sizeof(double) * n3);
	double* seeds = calloc(n3, sizeof(double));
	double* sums = calloc(n3, sizeof(double));
	double* other = calloc(n3, sizeof(double));
	fmTestSeed(17);
	for (size_t k = 0; k < n3; ++k)
		v[k] = fmTestRandom(-2.0, 2.0);
	for (int t = 0; t < b->mesh.tetCount; ++t)
		for (int c = 0; c < 3; ++c)
		{
			const int* n = b->mesh.tets + 4 * t;
			double s = v[3 * n[0] + c] + v[3 * n[1] + c] + v[3 * n[2] + c] + v[3 * n[3] + c];
			for (int a = 0; a < 4; ++a)
				seeds[3 * n[a] + c] += s;
		}
	fmTetBlocks_SmoothingSums(tb, v, sums, fm_simdScalar, NULL);
	double err = 0.0;
	for (size_t k = 0; k < n3; ++k)
		err = fmax(err, fabs(sums[k] - seeds[k]));
	CHECK(err < 1e-12);
	for (int workers = 2; workers <= 4; ++workers)
	{
		fmWorldDef def = fmDefaultWorldDef();
		def.workerCount = workers;
		fmTaskSystem tasks;
		fmTaskSystem_Init(&tasks, &def);
		fmTetBlocks_SmoothingSums(tb, v, other, fmSimd_Detect(), &tasks);
		fmTaskSystem_Shutdown(&tasks);
		CHECK(memcmp(sums, other, sizeof(double) * n3) == 0);
	}
	for (int level = fm_simdScalar; level <= (int)fmSimd_Detect(); ++level)
	{
		memset(other, 0, sizeof(double) * n3);
		fmTetBlocks_SmoothingSums(tb, v, other, (fmSimdLevel)level, NULL);
		CHECK(memcmp(sums, other, sizeof(double) * n3) == 0);
	}
	free(v), free(seeds), free(sums), free(other);
	fmTetBlocks_Destroy(tb);
	fmDestroyWorld(world);
}

// A kernel's variants as a list {scalar, baseline, avx2, avx512} (the last two on x86-64).
#if defined(__x86_64__) || defined(_M_X64)
#define KERNEL_VARIANTS(kernel)                                                                    \
	{                                                                                              \
		kernel##_scalar, kernel##_baseline, kernel##_avx2, kernel##_avx512                         \
	}
#else
#define KERNEL_VARIANTS(kernel)                                                                    \
	{                                                                                              \
		kernel##_scalar, kernel##_baseline                                                         \
	}
#endif

// Whether the CPU runs variant @p v of a kernel list {scalar, baseline, avx2, avx512}.
static bool cpuRunsVariant(int v)
{
	return !((v == 2 && fmSimd_Detect() < fm_simdAvx2) ||
	         (v == 3 && fmSimd_Detect() < fm_simdAvx512));
}

// The batched polar kernel of the implicit solver's corotated tets (tet_kernel.h): on every
// instruction set the CPU has, the same bits and the same refusals as fmPolarRotationFast, one
// matrix at a time, for rotations with small and large stretches, flat, inverted and non-finite
// matrices side by side in one batch (each lane stops on its own).
TEST(batched_polar_rotations_are_the_scalar_ones_bit_for_bit)
{
	fmPolarKernelFcn* kernels[] = KERNEL_VARIANTS(fmTetKernel_Polar);
	const int kernelCount = (int)(sizeof kernels / sizeof kernels[0]);
	int compared = 0, refused = 0, differ = 0;
	for (int round = 0; round < 200; ++round)
	{
		fmPolarBatch batch;
		fmMat3 F[FM_POLAR_LANES];
		for (int l = 0; l < FM_POLAR_LANES; ++l)
		{
			// Stretches from 1e-6 to 2 (lane by lane a different scale), a flat or inverted
			// matrix every few lanes, a NaN now and then.
			double strain = pow(10.0, fmTestRandom(-6.0, 0.3));
			fmMat3 R = fmTestRandomRotation(), S = fmIdentity3();
			for (int k = 0; k < 9; ++k)
				S.m[k] += strain * fmTestRandom(-1.0, 1.0);
			if ((round + l) % 7 == 3)
				S.m[0] = -S.m[0]; // inverted
			if ((round + l) % 11 == 5)
				S.m[8] = S.m[4] = 1e-5; // near flat
			F[l] = fmMatMul(&R, &S);
			if ((round + l) % 53 == 7)
				F[l].m[4] = NAN;
			for (int k = 0; k < 9; ++k)
				batch.F[k][l] = F[l].m[k];
		}
		bool ok[FM_POLAR_LANES];
		fmMat3 R[FM_POLAR_LANES];
		for (int l = 0; l < FM_POLAR_LANES; ++l)
		{
			ok[l] = fmPolarRotationFast(&F[l], &R[l]);
			refused += !ok[l];
		}
		for (int v = 0; v < kernelCount; ++v)
		{
			if (!cpuRunsVariant(v))
				continue;
			fmPolarBatch b = batch;
			kernels[v](&b);
			for (int l = 0; l < FM_POLAR_LANES; ++l, ++compared)
			{
				bool same = b.ok[l] == ok[l];
				for (int k = 0; same && ok[l] && k < 9; ++k)
					same = memcmp(&b.R[k][l], &R[l].m[k], sizeof(double)) == 0;
				if (!same && ++differ <= 5)
					FAIL_AT("kernel %d, round %d, lane %d: ok %d against %d", v, round, l, b.ok[l],
					        ok[l]);
			}
		}
	}
	CHECK_INT(differ, 0);
	CHECK(refused > 0 && refused < 200 * FM_POLAR_LANES / 2);
	printf("  %d lanes compared, %d matrices refused by both\n", compared, refused);
}

// The same bits, or both NaN (a NaN's payload may follow the operand order the compiler chose).
static bool sameDouble(double a, double b)
{
	return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

// One tet of a force batch by the scalar path: F = Ds Dm^-1, the material (Neo-Hookean:
// fmNeoHookean_Evaluate; StVK: fmMaterial_Evaluate, not ok where its volume floor acts; corotated:
// fmPolarRotationFast and fmCorotated_Stress, not ok where the former declines F), and
// fmAddTetForces' forces -V0 P Dm^-T (node a's, and their sum from 0.0 in node order).
static double forceLane(const fmMaterial* m, const fmMat3* Ds, const fmMat3* DmInv, double V0,
                        double force[4][3], bool* ok)
{
	fmMat3 F = fmMatMul(Ds, DmInv), P, R, C = fmCofactor(&F);
	double J = F.m[0] * C.m[0] + F.m[1] * C.m[1] + F.m[2] * C.m[2], floor[3];
	*ok = m->model == fm_neoHookean ||
	      (m->model == fm_stvk ? !fmMaterial_StvkFloor(m, J, floor) : fmPolarRotationFast(&F, &R));
	if (!*ok)
		return 0.0;
	double psi = m->model == fm_neoHookean ? fmNeoHookean_Evaluate(m, &F, &P)
	             : m->model == fm_stvk     ? fmMaterial_Evaluate(m, &F, &P, NULL)
	                                       : fmCorotated_Stress(m, &F, &R, &P);
	fmMat3 H = fmMatMulT(&P, DmInv);
	fmVec3 sum = {0, 0, 0};
	for (int a = 1; a < 4; ++a)
	{
		fmVec3 fa = fmScale(-V0, fmColumn(&H, a - 1));
		sum = fmAdd(sum, fa);
		force[a][0] = fa.x, force[a][1] = fa.y, force[a][2] = fa.z;
	}
	force[0][0] = sum.x, force[0][1] = sum.y, force[0][2] = sum.z;
	return psi;
}

// A force kernel of the implicit force passes (tet_kernel.h) of every instruction set the CPU
// has against the scalar path one tet at a time, bit for bit, for small and large strains,
// compression (below Neo-Hookean's ln J clamp), inverted and non-finite tets side by side.
// Returns how many lanes were compressed below the clamp or inverted.
static int checkForceKernels(int* failures_, fmMaterialModel model,
                             fmForceBatchKernelFcn* const* kernels, int kernelCount)
{
	const fmMaterial m = fmMakeMaterial(model, 1e6, 0.45);
	int compared = 0, special = 0, differ = 0, declined = 0;
	fmTestSeed(29);
	for (int round = 0; round < 200; ++round)
	{
		fmForceBatch batch;
		batch.mu = m.mu, batch.lambda = m.lambda;
		double psi[FM_FORCE_LANES], force[FM_FORCE_LANES][4][3];
		bool ok[FM_FORCE_LANES];
		for (int l = 0; l < FM_FORCE_LANES; ++l)
		{
			double strain = pow(10.0, fmTestRandom(-6.0, 0.0));
			fmMat3 R = fmTestRandomRotation(), S = fmIdentity3(), DmInv;
			for (int k = 0; k < 9; ++k)
			{
				S.m[k] += strain * fmTestRandom(-1.0, 1.0);
				DmInv.m[k] = (k % 4 == 0 ? 20.0 : 0.0) + fmTestRandom(-2.0, 2.0);
			}
			if ((round + l) % 5 == 2)
				S.m[0] = S.m[4] = 0.3; // below the clamp
			if ((round + l) % 7 == 3)
				S.m[0] = -S.m[0]; // inverted
			fmMat3 F = fmMatMul(&R, &S), Dm = fmIdentity3(), Ds;
			fmInverse(&DmInv, &Dm);
			Ds = fmMatMul(&F, &Dm);
			if ((round + l) % 53 == 7)
				Ds.m[4] = NAN;
			double V0 = fmTestRandom(1e-6, 1e-3);
			for (int k = 0; k < 9; ++k)
				batch.Ds[k][l] = Ds.m[k], batch.dmInv[k][l] = DmInv.m[k];
			batch.volume[l] = V0;
			psi[l] = forceLane(&m, &Ds, &DmInv, V0, force[l], &ok[l]);
			declined += !ok[l];
			fmMat3 Fk = fmMatMul(&Ds, &DmInv);
			special += fmDet(&Fk) < FM_LOG_J_CLAMP;
		}
		for (int v = 0; v < kernelCount; ++v)
		{
			if (!cpuRunsVariant(v))
				continue;
			fmForceBatch b = batch;
			kernels[v](&b);
			for (int l = 0; l < FM_FORCE_LANES; ++l, ++compared)
			{
				bool same = b.ok[l] == ok[l];
				if (same && ok[l])
				{
					same = sameDouble(b.psi[l], psi[l]);
					for (int a = 0; a < 4; ++a)
						for (int i = 0; i < 3; ++i)
							same = same && sameDouble(b.force[a][i][l], force[l][a][i]);
				}
				if (!same && ++differ <= 5)
					FAIL_AT("kernel %d, round %d, lane %d: psi %.17g against %.17g, ok %d/%d", v,
					        round, l, b.psi[l], psi[l], b.ok[l], ok[l]);
			}
		}
	}
	CHECK_INT(differ, 0);
	CHECK(model == fm_neoHookean ? declined == 0
	      : model == fm_stvk     ? declined >= special && declined < compared / kernelCount
	                             : declined > 0 && declined < special);
	printf("  %d lanes compared, %d below the clamp or inverted, %d left to the scalar path\n",
	       compared, special, declined);
	return special;
}

TEST(batched_neo_hookean_forces_are_the_scalar_ones_bit_for_bit)
{
	fmForceBatchKernelFcn* kernels[] = KERNEL_VARIANTS(fmTetKernel_NeoHookean);
	CHECK(checkForceKernels(failures_, fm_neoHookean, kernels,
	                        (int)(sizeof kernels / sizeof kernels[0])) > 0);
}

// The corotated force kernel: its own polar iteration declines the same tets as
// fmPolarRotationFast (inverted, nearly flat, non-finite), which the pass then leaves to the
// scalar path.
TEST(batched_corotated_forces_are_the_scalar_ones_bit_for_bit)
{
	fmForceBatchKernelFcn* kernels[] = KERNEL_VARIANTS(fmTetKernel_Corotated);
	CHECK(checkForceKernels(failures_, fm_corotated, kernels,
	                        (int)(sizeof kernels / sizeof kernels[0])) > 0);
}

#if !defined(__EMSCRIPTEN__) // (the browser's build has no batched StVK: the .wasm line)
// The StVK force kernel: the seeds' model without its volume floor, which the kernel leaves to
// the scalar path (every tet compressed below the floor's J or inverted, none else).
TEST(batched_stvk_forces_are_the_scalar_ones_bit_for_bit)
{
	fmForceBatchKernelFcn* kernels[] = KERNEL_VARIANTS(fmTetKernel_Stvk);
	CHECK(checkForceKernels(failures_, fm_stvk, kernels,
	                        (int)(sizeof kernels / sizeof kernels[0])) > 0);
}
#endif

// ---- the sparse rows' kernels (bsr_kernel.c) ---------------------------------------------------

// The largest error of rows [first, end) of (L + D) z = r (lower: blocks left of the diagonal;
// diagonal: the diagonal block with the fixed DOFs cut out), over free DOFs, relative to the
// size of the terms. With lower false: D (z0 - z) = U z (the backward sweep from z0).
static double sweepError(const fmBsrMatrix* m, const double* values, const uint8_t* fixed,
                         const double* rhs, const double* z, int first, int end, bool lower)
{
	double worst = 0.0;
	for (int i = first; i < end; ++i)
		for (int e = 0; e < 3; ++e)
		{
			if (fixed[3 * i + e])
				continue;
			double left = 0.0, right = lower ? rhs[3 * i + e] : 0.0, size = fabs(right);
			for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
			{
				int j = m->columns[k];
				const double* a = values + 9 * (size_t)k + 3 * e;
				for (int f = 0; f < 3; ++f)
				{
					if (j == i && !fixed[3 * i + f])
					{
						double d = lower ? z[3 * i + f] : rhs[3 * i + f] - z[3 * i + f];
						left += a[f] * d, size += fabs(a[f] * d);
					}
					else if (j >= first && j < end && (lower ? j < i : j > i))
						(lower ? (left += a[f] * z[3 * j + f]) : (right += a[f] * z[3 * j + f])),
						    size += fabs(a[f] * z[3 * j + f]);
				}
			}
			worst = fmax(worst, fabs(left - right) / size);
		}
	return worst;
}

// The product and the Gauss-Seidel sweeps of a random block matrix on a tet mesh's pattern, with
// fixed DOFs and on a part of the rows: each solves its triangle to round-off, and every
// instruction set the CPU has gives the scalar variant's bits.
TEST(sparse_row_kernels_solve_their_triangles_with_the_same_bits_on_every_instruction_set)
{
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(4, 3, 3, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBsrMatrix m;
	CHECK(fmBsr_Build(&m, mesh.nodeCount, mesh.tets, mesh.tetCount));
	const int rows = m.rows, n = 3 * rows;
	double* values = malloc(sizeof(double) * 9 * (size_t)m.blocks);
	double* diagonal = malloc(sizeof(double) * 9 * (size_t)rows);
	double* blockInverse = malloc(sizeof(double) * 9 * (size_t)rows);
	uint8_t* fixed = malloc((size_t)n);
	double *x = malloc(sizeof(double) * (size_t)n), *out[4][3];
	for (int k = 0; k < 9 * m.blocks; ++k)
		values[k] = fmTestRandom(-1.0, 1.0);
	for (int i = 0; i < rows; ++i)
	{
		double* D = values + 9 * (size_t)m.diagonal[i];
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < r; ++c)
				D[3 * c + r] = D[3 * r + c];
		for (int r = 0; r < 3; ++r)
			D[4 * r] = fmTestRandom(10.0, 20.0);
		memcpy(diagonal + 9 * (size_t)i, D, sizeof(double) * 9);
	}
	for (int k = 0; k < n; ++k)
	{
		x[k] = fmTestRandom(-1.0, 1.0);
		fixed[k] = fmTestRandom(0.0, 1.0) < 0.1;
	}
	fmBsr_InvertDiagonalBlocks(rows, diagonal, fixed, false, blockInverse);
	fmBsrKernels kernels[] = {
		{fmBsrKernel_MultiplyRows_scalar, fmBsrKernel_ForwardSweep_scalar,
		 fmBsrKernel_BackwardSweep_scalar},
		{fmBsrKernel_MultiplyRows_baseline, fmBsrKernel_ForwardSweep_baseline,
		 fmBsrKernel_BackwardSweep_baseline},
#if defined(__x86_64__) || defined(_M_X64)
		{fmBsrKernel_MultiplyRows_avx2, fmBsrKernel_ForwardSweep_avx2,
		 fmBsrKernel_BackwardSweep_avx2},
		{fmBsrKernel_MultiplyRows_avx512, fmBsrKernel_ForwardSweep_avx512,
		 fmBsrKernel_BackwardSweep_avx512},
#endif
	};
	const int kernelCount = (int)(sizeof kernels / sizeof kernels[0]);
	const int first = rows / 3, end = 2 * rows / 3; // a part: its rows ignore the others
	int differ = 0, ran = 0;
	for (int v = 0; v < kernelCount; ++v)
	{
		for (int o = 0; o < 3; ++o)
			out[v][o] = calloc((size_t)n, sizeof(double));
		if (!cpuRunsVariant(v))
			continue;
		ran += 1;
		kernels[v].multiplyRows(&m, values, x, out[v][0], 0, rows);
		kernels[v].forwardSweep(&m, values, blockInverse, fixed, x, out[v][1], first, end);
		memcpy(out[v][2], out[v][1], sizeof(double) * (size_t)n);
		kernels[v].backwardSweep(&m, values, blockInverse, fixed, out[v][2], first, end);
		for (int o = 0; o < 3; ++o)
			if (memcmp(out[v][o], out[0][o], sizeof(double) * (size_t)n) != 0 && ++differ <= 5)
				FAIL_AT("variant %d, kernel %d: not the scalar variant's bits", v, o);
	}
	// The product against the definition, one DOF at a time.
	double worst = 0.0;
	for (int i = 0; i < rows; ++i)
		for (int e = 0; e < 3; ++e)
		{
			double s = 0.0, size = 0.0;
			for (int k = m.rowStart[i]; k < m.rowStart[i + 1]; ++k)
				for (int f = 0; f < 3; ++f)
				{
					double term = values[9 * (size_t)k + 3 * e + f] * x[3 * m.columns[k] + f];
					s += term, size += fabs(term);
				}
			worst = fmax(worst, fabs(out[0][0][3 * i + e] - s) / size);
		}
	double forward = sweepError(&m, values, fixed, x, out[0][1], first, end, true);
	double backward = sweepError(&m, values, fixed, out[0][1], out[0][2], first, end, false);
	bool untouched = true, fixedZero = true;
	for (int k = 0; k < n; ++k)
	{
		bool inside = k >= 3 * first && k < 3 * end;
		untouched = untouched && (inside || (out[0][1][k] == 0.0 && out[0][2][k] == 0.0));
		fixedZero = fixedZero && (!fixed[k] || (out[0][1][k] == 0.0 && out[0][2][k] == 0.0));
	}
	printf("  %d variants; relative errors: product %.2g, forward %.2g, backward %.2g\n", ran,
	       worst, forward, backward);
	CHECK_INT(differ, 0);
	CHECK(worst < 1e-14);
	CHECK(forward < 1e-13 && backward < 1e-13);
	CHECK(untouched && fixedZero);
	for (int v = 0; v < kernelCount; ++v)
		for (int o = 0; o < 3; ++o)
			free(out[v][o]);
	free(values), free(diagonal), free(blockInverse), free(fixed), free(x);
	fmBsr_Free(&m);
	fmFreeTetMesh(&mesh);
}

// The Neo-Hookean batch's fill (fmTetKernel_FillForceBatch_*) on every instruction set the CPU
// has: each lane's edge matrix, Dm^-1 and V0 of a moved box, bit for bit as one tet at a time.
TEST(batched_neo_hookean_fill_gathers_each_tets_edges_and_rest_data)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 3, fm_neoHookean);
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		b->state.x[k] += fmTestRandom(-0.05, 0.05);
	fmForceBatchFillFcn* fills[] = KERNEL_VARIANTS(fmTetKernel_FillForceBatch);
	const int fillCount = (int)(sizeof fills / sizeof fills[0]);
	int compared = 0, differ = 0;
	for (int v = 0; v < fillCount; ++v)
	{
		if (!cpuRunsVariant(v))
			continue;
		for (int first = 0; first + FM_FORCE_LANES <= b->mesh.tetCount; first += FM_FORCE_LANES)
		{
			fmForceBatch batch;
			fills[v](b->state.x, b->mesh.tets, b->mesh.DmInv, b->mesh.restVolume, first, &batch);
			for (int l = 0; l < FM_FORCE_LANES; ++l, ++compared)
			{
				const int* n = b->mesh.tets + 4 * (first + l);
				bool same = batch.volume[l] == b->mesh.restVolume[first + l];
				for (int i = 0; i < 3; ++i)
					for (int k = 0; k < 3; ++k)
					{
						double edge = b->state.x[3 * n[k + 1] + i] - b->state.x[3 * n[0] + i];
						same = same && memcmp(&batch.Ds[3 * i + k][l], &edge, sizeof edge) == 0 &&
						       memcmp(&batch.dmInv[3 * i + k][l],
						              &b->mesh.DmInv[first + l].m[3 * i + k], sizeof(double)) == 0;
					}
				if (!same && ++differ <= 5)
					FAIL_AT("variant %d, tet %d: not its edges or rest data", v, first + l);
			}
		}
	}
	CHECK_INT(differ, 0);
	CHECK(compared >= 2 * (b->mesh.tetCount / FM_FORCE_LANES) * FM_FORCE_LANES); // scalar, baseline
	fmDestroyWorld(world);
}

// The inverted-tet flags of the frame's health check (fmInvertedTets, eight tets at a time on
// the CPU's vectors) against fmDet of fmTetDeformation one tet at a time, on a box shaken hard
// enough to turn some of its tets inside out.
TEST(inverted_tets_are_flagged_as_one_tet_at_a_time)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 3, fm_neoHookean);
	fmTestSeed(31);
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		b->state.x[k] += fmTestRandom(-0.25, 0.25);
	unsigned char* flags = malloc((size_t)b->mesh.tetCount);
	fmInvertedTets(&b->mesh, b->state.x, 0, b->mesh.tetCount, flags);
	int inverted = 0, differ = 0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		bool expected = !(fmDet(&F) > 0.0);
		inverted += expected;
		differ += flags[t] != expected;
	}
	printf("  %d of %d tets inverted\n", inverted, b->mesh.tetCount);
	CHECK_INT(differ, 0);
	CHECK(inverted > 0 && inverted < b->mesh.tetCount);
	CHECK_INT(fmBodyCountInverted(b), inverted);
	free(flags);
	fmDestroyWorld(world);
}

// The stiffening proxy of autoSubstep (fmStiffeningProxy, eight tets at a time on the CPU's
// vectors) against its formula one tet at a time, bit for bit, on a box deformed from gently to
// hard and on one shaken inside out (INFINITY), over every range of its tets from a tet on.
TEST(the_stiffening_proxy_is_the_one_tet_at_a_time_value_bit_for_bit)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 3, fm_neoHookean);
	fmTestSeed(37);
	const double amplitudes[4] = {0.0, 0.01, 0.1, 0.25};
	for (int a = 0; a < 4; ++a)
	{
		deform(b, amplitudes[a] < 0.2 ? amplitudes[a] : 0.0);
		for (int k = 0; a == 3 && k < 3 * b->mesh.vertexCount; ++k)
			b->state.x[k] += fmTestRandom(-0.25, 0.25);
		int differ = 0;
		for (int first = 0; first < b->mesh.tetCount; first += 5)
		{
			double expected = 1.0;
			for (int t = first; t < b->mesh.tetCount; ++t)
			{
				fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
				double J = fmDet(&F), I1 = 0.0;
				for (int k = 0; k < 9; ++k)
					I1 += F.m[k] * F.m[k];
				double p = !(J > 0.0) ? INFINITY : fmMax(I1, I1 * I1 / (4.0 * J * J));
				expected = fmMax(expected, p);
			}
			double got = fmStiffeningProxyRange(&b->mesh, b->state.x, first, b->mesh.tetCount);
			differ += memcmp(&got, &expected, sizeof got) != 0;
			if (first == 0)
				printf("  amplitude %.2f: proxy %.17g\n", amplitudes[a], got);
		}
		CHECK_INT(differ, 0);
		double whole = fmStiffeningProxy(&b->mesh, b->state.x);
		CHECK(a == 3 ? isinf(whole) : isfinite(whole) && whole >= 1.0);
	}
	fmDestroyWorld(world);
}

// The count of inverted tets the health check takes from the explicit kernels' energy pass (their
// float det F proves most tets upright; the rest are rechecked in double) against
// fmBodyCountInverted, on every instruction set and worker count: a box at rest, shaken from
// gently to inside out, with tets flattened to within rounding of zero volume, and with a vertex
// thrown far enough that float's det F overflows.
TEST(the_energy_pass_counts_the_inverted_tets_exactly)
{
	fmWorldId world;
	fmBody* b = makeCube(failures_, &world, 8, fm_stvk); // 3072 tets: six blocks
	if (b == NULL)
		return;
	fmTestSeed(47);
	const double amplitudes[] = {0.0, 0.01, 0.05, 0.2, 0.01, 0.01}; // the cells are 0.125 m
	for (int c = 0; c < 6; ++c)
	{
		for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
			b->state.x[k] = b->mesh.x0[k] + fmTestRandom(-amplitudes[c], amplitudes[c]);
		int nearFlat = 0;
		for (int t = 0; c == 4 && t < b->mesh.tetCount; t += 5)
		{
			// Node 3 onto the plane of the other three (a point of it in rounding).
			const int* n = b->mesh.tets + 4 * t;
			fmVec3 x0 = fmLoad(b->state.x, n[0]), x1 = fmLoad(b->state.x, n[1]),
			       x2 = fmLoad(b->state.x, n[2]);
			fmVec3 p = fmAdd(x0, fmAdd(fmScale(0.3, fmSub(x1, x0)), fmScale(0.4, fmSub(x2, x0))));
			fmStore(b->state.x, n[3], p);
		}
		if (c == 5)
			b->state.x[3 * 17 + 1] = 1e30;
		for (int t = 0; t < b->mesh.tetCount; ++t)
		{
			fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
			nearFlat += fabs(fmDet(&F)) < 1e-6;
		}
		int expected = fmBodyCountInverted(b);
		printf("  shaken by %g m%s: %d inverted, %d with |det F| < 1e-6\n", amplitudes[c],
		       c == 4   ? ", every fifth tet flattened"
		       : c == 5 ? ", a vertex at 1e30 m"
		                : "",
		       expected, nearFlat);
		CHECK(c != 3 || expected > 0);
		CHECK(c != 4 || nearFlat > 0);
		for (int level = fm_simdScalar; level <= (int)fmSimd_Detect(); ++level)
			for (int workers = 1; workers <= 3; workers += 2)
			{
				double energy;
				int counted = -1;
				free(batchedForcesCounting(b, (fmSimdLevel)level, workers, &energy, &counted));
				if (counted != expected)
					FAIL_AT("case %d, %s on %d workers: %d inverted counted, %d expected", c,
					        fmSimdLevelName((fmSimdLevel)level), workers, counted, expected);
			}
	}
	fmDestroyWorld(world);
}
