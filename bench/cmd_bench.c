// `femto bench`: how long explicit steps and implicit frames take on the house and on generated
// boxes of about 1k, 10k, 100k and 1M tets. Medians of several repetitions.
#include "commands.h"
#include "scene.h"

#include "bandwidth.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* const cliBenchHelp =
    "usage: femto bench [options]\n"
    "\n"
    "Time explicit StVK and Neo-Hookean steps (ns per tet per step) and implicit 1/60 s\n"
    "Neo-Hookean and corotated frames (ms per frame, Newton and CG iterations) on the bouncy\n"
    "house and on generated boxes of about 1k, 10k, 100k and 1M tets, and the machine's\n"
    "memory bandwidth (a triad) in the same run: every explicit row says what fraction of the\n"
    "bound (60 bytes a tet-step at that bandwidth) it reaches. Prints medians.\n"
    "\n"
    "options:\n"
    "  --quick            stop at 10k tets, 3 repetitions (a few seconds)\n"
    "  --max-tets N       skip meshes with more than N tets\n"
    "  --explicit         only the explicit benchmark\n"
    "  --implicit         only the implicit benchmark (default: explicit, then implicit;\n"
    "                     implicit stops at the 100k box)\n"
    "  --repeats R        repetitions per measurement (default 5, --quick 3)\n"
    "  --workers N        the most workers to time (default: the cores available); every\n"
    "                     explicit row runs on 1 and on N workers\n"
    "  --csv FILE         also write the results as CSV, one row per case:\n"
    "                     mesh,tets,integrator,model,workers,ns_per_tet_step,ms_per_frame,\n"
    "                     newton_per_frame,cg_per_frame,bound_ns_per_tet_step\n"
    "  --help             this text\n";

typedef struct cliBenchOptions
{
	bool quick;
	int maxTets;
	bool explicitSteps;
	bool implicitFrames;
	int repeats;
	int workers;
	const char* csvPath;
} cliBenchOptions;

// A benchmark mesh: the house, or a box of cells[0] x cells[1] x cells[2] cubes (6 tets each).
typedef struct cliBenchMesh
{
	const char* label;
	int cells[3];
} cliBenchMesh;

static const cliBenchMesh cliBenchMeshes[] = {
    {"house2", {0, 0, 0}},      {"box 1k", {6, 6, 5}},    {"box 10k", {12, 12, 12}},
    {"box 100k", {26, 26, 25}}, {"box 1M", {55, 55, 55}},
};
#define CLI_BENCH_MESH_COUNT ((int)(sizeof cliBenchMeshes / sizeof cliBenchMeshes[0]))

// Implicit frames on the 1M box take minutes each on a small machine: stop at the 100k box.
#define CLI_BENCH_IMPLICIT_MAX_TETS 200000

static int cliBenchTetCount(const cliBenchMesh* mesh)
{
	return mesh->cells[0] == 0 ? 1389 : 6 * mesh->cells[0] * mesh->cells[1] * mesh->cells[2];
}

static int cliCompareDoubles(const void* a, const void* b)
{
	double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

static double cliMedian(double* values, int count)
{
	qsort(values, (size_t)count, sizeof *values, cliCompareDoubles);
	return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

// A world with one body on the floor: the house as the demo, a box standing on the floor.
static bool cliBenchWorld(const cliBenchMesh* bench, fmIntegrator integrator, fmMaterialModel model,
                          int workers, double tolerance, cliSimulation* sim)
{
	cliScene scene;
	cliScene_MakeHouse(&scene);
	if (scene.bodies == NULL)
		return false;
	scene.worldDef.integrator = integrator;
	scene.worldDef.workerCount = workers;
	scene.worldDef.tolerance = tolerance;
	if (bench->cells[0] == 0 && model != fm_stvk)
		scene.bodies[0].def.material = fmMakeMaterialLame(model, 20000.0, 5000.0);
	if (bench->cells[0] != 0)
	{
		// A 1 m cube resting on the floor, density-based masses so refinement keeps the physics.
		cliBodySpec* body = &scene.bodies[0];
		body->meshSource = cli_meshBox;
		memcpy(body->boxCells, bench->cells, sizeof body->boxCells);
		body->boxMin = fmMakeVec3(-0.5, -3.0, -0.5);
		body->boxMax = fmMakeVec3(0.5, -2.0, 0.5);
		body->transform = fmDefaultMeshTransform();
		body->def.massMode = fm_massFromDensity;
		body->def.density = 1000.0;
		body->def.material = fmMakeMaterial(model, 1e6, 0.3);
	}
	bool ok = cliSimulation_Create(&scene, cli_stepCheckOff, sim);
	cliScene_Free(&scene);
	return ok;
}

typedef struct cliBenchRow
{
	const char* label;
	int tets;
	double nsPerTetStep;
	double stepsPerSecond;
	double msPerFrame;
	double newtonPerFrame;
	double cgPerFrame;
	bool failed;
} cliBenchRow;

static cliBenchRow cliBenchExplicit(const cliBenchMesh* bench, fmMaterialModel model, int workers,
                                    int repeats)
{
	cliBenchRow row = {bench->label, cliBenchTetCount(bench), 0, 0, 0, 0, 0, true};
	cliSimulation sim;
	if (!cliBenchWorld(bench, fm_explicit, model, workers, FM_TOLERANCE_ACCURATE, &sim))
		return row;
	// Stay safely inside the stability limit: a blow-up would measure the failure path.
	double dt = fmin(0.003, 0.5 * fmWorld_EstimateExplicitStep(sim.world));
	// Enough steps per repetition for ~50 ms of work at ~50 ns per tet per step.
	int steps = (int)fmax(1.0, fmin(1000.0, 1e6 / row.tets));
	double* samples = calloc((size_t)repeats, sizeof *samples);
	bool ok = samples != NULL && fmWorld_Step(sim.world, dt, 1) == fm_ok; // warm-up
	for (int r = 0; ok && r < repeats; ++r)
	{
		double start = cliNow();
		ok = fmWorld_Step(sim.world, dt * steps, steps) == fm_ok;
		samples[r] = (cliNow() - start) / steps;
	}
	if (ok)
	{
		double secondsPerStep = cliMedian(samples, repeats);
		row.nsPerTetStep = 1e9 * secondsPerStep / row.tets;
		row.stepsPerSecond = 1.0 / secondsPerStep;
		row.failed = false;
	}
	free(samples);
	cliSimulation_Destroy(&sim);
	return row;
}

static cliBenchRow cliBenchImplicit(const cliBenchMesh* bench, fmMaterialModel model,
                                    double tolerance, int repeats)
{
	cliBenchRow row = {bench->label, cliBenchTetCount(bench), 0, 0, 0, 0, 0, true};
	cliSimulation sim;
	if (!cliBenchWorld(bench, fm_implicit, model, 1, tolerance, &sim))
		return row;
	double* samples = calloc((size_t)repeats, sizeof *samples);
	double newton = 0.0, cg = 0.0;
	bool ok = samples != NULL;
	// One second first: the house lands (free flight costs no Newton iteration at all, since
	// every step starts from it), the boxes settle on the floor.
	for (int frame = 0; ok && frame < 60; ++frame)
		ok = fmWorld_Step(sim.world, 1.0 / 60.0, 1) == fm_ok;
	for (int r = 0; ok && r < repeats; ++r)
	{
		double start = cliNow();
		ok = fmWorld_Step(sim.world, 1.0 / 60.0, 1) == fm_ok;
		samples[r] = cliNow() - start;
		fmStepStats stats = fmWorld_GetStepStats(sim.world);
		newton += stats.newtonIterations;
		cg += stats.cgIterations;
	}
	if (ok)
	{
		row.msPerFrame = 1e3 * cliMedian(samples, repeats);
		row.newtonPerFrame = newton / repeats;
		row.cgPerFrame = cg / repeats;
		row.failed = false;
	}
	free(samples);
	cliSimulation_Destroy(&sim);
	return row;
}

static int cliParseBenchOptions(int argc, char** argv, cliBenchOptions* o)
{
	memset(o, 0, sizeof *o);
	o->maxTets = 2000000;
	bool onlyExplicit = false, onlyImplicit = false;
	o->repeats = 0;
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		const char* value = NULL;
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(cliBenchHelp, stdout);
			return cli_exitOk;
		}
		else if (strcmp(arg, "--quick") == 0)
			o->quick = true;
		else if (strcmp(arg, "--explicit") == 0)
			onlyExplicit = true;
		else if (strcmp(arg, "--implicit") == 0)
			onlyImplicit = true;
		else if (strcmp(arg, "--max-tets") == 0)
		{
			if ((value = cliOptionValue("bench", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseIntOption("bench", "--max-tets", value, 1, INT_MAX, &o->maxTets))
				return cli_exitUsage;
		}
		else if (strcmp(arg, "--repeats") == 0)
		{
			if ((value = cliOptionValue("bench", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseIntOption("bench", "--repeats", value, 1, 1000, &o->repeats))
				return cli_exitUsage;
		}
		else if (strcmp(arg, "--workers") == 0)
		{
			if ((value = cliOptionValue("bench", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseIntOption("bench", "--workers", value, 1, FM_MAX_WORKERS, &o->workers))
				return cli_exitUsage;
		}
		else if (strcmp(arg, "--csv") == 0)
		{
			if ((o->csvPath = cliOptionValue("bench", argc, argv, &i)) == NULL)
				return cli_exitUsage;
		}
		else
			return cliUsageError("bench", "unknown argument '%s'", arg);
	}
	if (onlyExplicit && onlyImplicit)
		return cliUsageError("bench", "give --explicit or --implicit, not both");
	o->explicitSteps = !onlyImplicit;
	o->implicitFrames = !onlyExplicit;
	if (o->quick && o->maxTets > 10368)
		o->maxTets = 10368;
	if (o->repeats == 0)
		o->repeats = o->quick ? 3 : 5;
	if (o->workers == 0)
		o->workers = cliCoresAvailable();
	return -1;
}

// The bytes an explicit tet-step must move at least (positions, forces and the tet's rest data,
// amortised), the figure for the memory-bandwidth bound.
#define CLI_BYTES_PER_TET_STEP 60.0

static void cliBenchExplicitRows(const cliBenchOptions* o, FILE* csv, const double* bandwidth,
                                 int* code)
{
	static const fmMaterialModel models[2] = {fm_stvk, fm_neoHookean};
	int counts[2] = {1, o->workers};
	printf("explicit steps (FEM, symplectic Euler), median of %d; bound = %.0f bytes a tet-step "
	       "at the triad bandwidth of that many threads\n",
	       o->repeats, CLI_BYTES_PER_TET_STEP);
	printf("%-10s %9s %-11s %7s %12s %10s %8s\n", "mesh", "tets", "model", "workers", "ns/tet/step",
	       "bound ns", "of bound");
	for (int m = 0; m < CLI_BENCH_MESH_COUNT; ++m)
		for (int k = 0; k < 2 && cliBenchTetCount(&cliBenchMeshes[m]) <= o->maxTets; ++k)
			for (int w = 0; w < (o->workers > 1 ? 2 : 1); ++w)
			{
				cliBenchRow row =
				    cliBenchExplicit(&cliBenchMeshes[m], models[k], counts[w], o->repeats);
				const char* model = fmMaterialModelName(models[k]);
				if (row.failed)
				{
					printf("%-10s %9d %-11s %7d %12s\n", row.label, row.tets, model, counts[w],
					       "failed");
					*code = cli_exitInput;
					continue;
				}
				double bound = bandwidth[w] > 0.0 ? 1e9 * CLI_BYTES_PER_TET_STEP / bandwidth[w] : 0;
				printf("%-10s %9d %-11s %7d %12.1f %10.2f %7.1f%%\n", row.label, row.tets, model,
				       counts[w], row.nsPerTetStep, bound,
				       bound > 0.0 ? 100.0 * bound / row.nsPerTetStep : 0.0);
				fflush(stdout);
				if (csv != NULL)
					fprintf(csv, "%s,%d,explicit,%s,%d,%.3f,,,,%.3f\n", row.label, row.tets, model,
					        counts[w], row.nsPerTetStep, bound);
			}
}

static void cliBenchImplicitRows(const cliBenchOptions* o, FILE* csv, int* code)
{
	static const fmMaterialModel models[2] = {fm_neoHookean, fm_corotated};
	static const double tolerances[2] = {FM_TOLERANCE_GAME, FM_TOLERANCE_ACCURATE};
	static const char* const names[2] = {"game", "1e-6"};
	printf("implicit backward Euler, 1/60 s frames after 1 s of settling, to the game tolerance "
	       "(1e-2) and to 1e-6, median of %d\n",
	       o->repeats);
	printf("%-10s %9s %-11s %-9s %11s %13s %10s\n", "mesh", "tets", "model", "tolerance",
	       "ms/frame", "Newton/frame", "CG/frame");
	for (int m = 0; m < CLI_BENCH_MESH_COUNT; ++m)
	{
		int tets = cliBenchTetCount(&cliBenchMeshes[m]);
		if (tets > o->maxTets || tets > CLI_BENCH_IMPLICIT_MAX_TETS)
			continue;
		for (int k = 0; k < 2; ++k)
			for (int t = 0; t < 2; ++t)
			{
				cliBenchRow row =
				    cliBenchImplicit(&cliBenchMeshes[m], models[k], tolerances[t], o->repeats);
				const char* model = fmMaterialModelName(models[k]);
				if (row.failed)
				{
					printf("%-10s %9d %-11s %-9s %11s\n", row.label, row.tets, model, names[t],
					       "failed");
					*code = cli_exitInput;
					continue;
				}
				printf("%-10s %9d %-11s %-9s %11.2f %13.1f %10.1f\n", row.label, row.tets, model,
				       names[t], row.msPerFrame, row.newtonPerFrame, row.cgPerFrame);
				fflush(stdout);
				if (csv != NULL)
					fprintf(csv, "%s,%d,implicit %s,%s,1,,%.3f,%.2f,%.1f,\n", row.label, row.tets,
					        names[t], model, row.msPerFrame, row.newtonPerFrame, row.cgPerFrame);
			}
	}
}

int cliBench(int argc, char** argv)
{
	cliBenchOptions o;
	int code = cliParseBenchOptions(argc, argv, &o);
	if (code >= 0)
		return code;
	FILE* csv = NULL;
	char csvTemp[CLI_MAX_PATH + 64];
	if (o.csvPath != NULL)
	{
		// Written under a temporary name and renamed when whole, as every output of the tool.
		snprintf(csvTemp, sizeof csvTemp, "%s.tmp", o.csvPath);
		csv = fopen(csvTemp, "w");
		if (csv == NULL)
		{
			perror(csvTemp);
			return cli_exitInput;
		}
		fprintf(csv, "mesh,tets,integrator,model,workers,ns_per_tet_step,ms_per_frame,"
		             "newton_per_frame,cg_per_frame,bound_ns_per_tet_step\n");
	}
	code = cli_exitOk;
	if (o.explicitSteps)
	{
		double bandwidth[2] = {cliTriadBandwidth(1), cliTriadBandwidth(o.workers)};
		printf("memory bandwidth (triad): %.1f GB/s on 1 thread, %.1f GB/s on %d (ratio %.2f)\n",
		       bandwidth[0] / 1e9, bandwidth[1] / 1e9, o.workers,
		       bandwidth[0] > 0.0 ? bandwidth[1] / bandwidth[0] : 0.0);
		cliBenchExplicitRows(&o, csv, bandwidth, &code);
	}
	if (o.implicitFrames)
		cliBenchImplicitRows(&o, csv, &code);
	if (csv != NULL && (fclose(csv) != 0 || rename(csvTemp, o.csvPath) != 0))
	{
		perror(o.csvPath);
		remove(csvTemp);
		code = cli_exitInput;
	}
	return code;
}
