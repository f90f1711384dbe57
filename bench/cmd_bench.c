// `femto bench`: how long explicit steps and implicit frames take on the house and on generated
// boxes of about 1k, 10k, 100k and 1M tets. Medians of several repetitions.
#include "commands.h"
#include "scene.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* const cliBenchHelp =
    "usage: femto bench [options]\n"
    "\n"
    "Time explicit StVK steps (ns per tet per step, steps per second) and implicit 1/60 s\n"
    "frames (ms per frame, Newton and CG iterations) on the bouncy house and on generated\n"
    "boxes of about 1k, 10k, 100k and 1M tets. Prints medians of the repetitions.\n"
    "\n"
    "options:\n"
    "  --quick            stop at 10k tets, 3 repetitions (a few seconds)\n"
    "  --max-tets N       skip meshes with more than N tets\n"
    "  --explicit         only the explicit benchmark\n"
    "  --implicit         only the implicit benchmark (default: explicit, then implicit;\n"
    "                     implicit stops at the 100k box)\n"
    "  --repeats R        repetitions per measurement (default 5, --quick 3)\n"
    "  --csv FILE         also write the results as CSV\n"
    "  --help             this text\n";

typedef struct cliBenchOptions
{
	bool quick;
	int maxTets;
	bool explicitSteps;
	bool implicitFrames;
	int repeats;
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
static bool cliBenchWorld(const cliBenchMesh* bench, fmIntegrator integrator, cliSimulation* sim)
{
	cliScene scene;
	cliScene_MakeHouse(&scene);
	if (scene.bodies == NULL)
		return false;
	scene.worldDef.integrator = integrator;
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
		body->def.material = fmMakeMaterial(fm_stvk, 1e6, 0.3);
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

static cliBenchRow cliBenchExplicit(const cliBenchMesh* bench, int repeats)
{
	cliBenchRow row = {bench->label, cliBenchTetCount(bench), 0, 0, 0, 0, 0, true};
	cliSimulation sim;
	if (!cliBenchWorld(bench, fm_explicit, &sim))
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

static cliBenchRow cliBenchImplicit(const cliBenchMesh* bench, int repeats)
{
	cliBenchRow row = {bench->label, cliBenchTetCount(bench), 0, 0, 0, 0, 0, true};
	cliSimulation sim;
	if (!cliBenchWorld(bench, fm_implicit, &sim))
		return row;
	double* samples = calloc((size_t)repeats, sizeof *samples);
	double newton = 0.0, cg = 0.0;
	bool ok = samples != NULL;
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
	return -1;
}

int cliBench(int argc, char** argv)
{
	cliBenchOptions o;
	int code = cliParseBenchOptions(argc, argv, &o);
	if (code >= 0)
		return code;
	FILE* csv = NULL;
	if (o.csvPath != NULL)
	{
		csv = fopen(o.csvPath, "w");
		if (csv == NULL)
		{
			perror(o.csvPath);
			return cli_exitInput;
		}
		fprintf(csv, "benchmark,mesh,tets,ns_per_tet_step,steps_per_second,ms_per_frame,"
		             "newton_per_frame,cg_per_frame\n");
	}
	code = cli_exitOk;
	if (o.explicitSteps)
	{
		printf("explicit StVK steps (FEM, symplectic Euler), median of %d\n", o.repeats);
		printf("%-10s %9s %14s %12s\n", "mesh", "tets", "ns/tet/step", "steps/s");
		for (int m = 0; m < CLI_BENCH_MESH_COUNT; ++m)
		{
			if (cliBenchTetCount(&cliBenchMeshes[m]) > o.maxTets)
				continue;
			cliBenchRow row = cliBenchExplicit(&cliBenchMeshes[m], o.repeats);
			if (row.failed)
			{
				printf("%-10s %9d %14s\n", row.label, row.tets, "failed");
				code = cli_exitInput;
				continue;
			}
			printf("%-10s %9d %14.1f %12.0f\n", row.label, row.tets, row.nsPerTetStep,
			       row.stepsPerSecond);
			fflush(stdout);
			if (csv != NULL)
				fprintf(csv, "explicit,%s,%d,%.3f,%.1f,,,\n", row.label, row.tets, row.nsPerTetStep,
				        row.stepsPerSecond);
		}
	}
	if (o.implicitFrames)
	{
		printf("implicit backward Euler, 1/60 s frames, median of %d\n", o.repeats);
		printf("%-10s %9s %11s %13s %10s\n", "mesh", "tets", "ms/frame", "Newton/frame",
		       "CG/frame");
		for (int m = 0; m < CLI_BENCH_MESH_COUNT; ++m)
		{
			int tets = cliBenchTetCount(&cliBenchMeshes[m]);
			if (tets > o.maxTets || tets > CLI_BENCH_IMPLICIT_MAX_TETS)
				continue;
			cliBenchRow row = cliBenchImplicit(&cliBenchMeshes[m], o.repeats);
			if (row.failed)
			{
				printf("%-10s %9d %11s\n", row.label, row.tets, "failed");
				code = cli_exitInput;
				continue;
			}
			printf("%-10s %9d %11.2f %13.1f %10.1f\n", row.label, row.tets, row.msPerFrame,
			       row.newtonPerFrame, row.cgPerFrame);
			fflush(stdout);
			if (csv != NULL)
				fprintf(csv, "implicit,%s,%d,,,%.3f,%.2f,%.1f\n", row.label, row.tets,
				        row.msPerFrame, row.newtonPerFrame, row.cgPerFrame);
		}
	}
	if (csv != NULL && fclose(csv) != 0)
	{
		perror(o.csvPath);
		code = cli_exitInput;
	}
	return code;
}
