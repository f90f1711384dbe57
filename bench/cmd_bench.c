// `femto bench`: how long explicit steps and implicit frames take on the house, on generated
// boxes and on TetGen beams of about 1k, 10k, 100k and 1M tets, against the machine's memory
// bandwidth measured in the same run; contact piles (contact.h), frames in motion and many small
// bodies (motion.h), start-up (startup.h); optionally a plot (plot.h) and Bullet side by side
// (peers.h). Medians of several repetitions.
#include "commands.h"
#include "scene.h"

#include "bandwidth.h"
#include "contact.h"
#include "meshes.h"
#include "motion.h"
#include "options.h"
#include "peers.h"
#include "plot.h"
#include "report.h"
#include "startup.h"
#include "tools.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* const cliBenchHelp =
    "usage: femto bench [options]\n"
    "\n"
    "Time explicit StVK and Neo-Hookean steps (ns per tet per step) and implicit 1/60 s\n"
    "Neo-Hookean and corotated frames (ms per frame, Newton and CG iterations) on the bouncy\n"
    "house, on generated boxes and on TetGen beams (meshed by `tetgen` when it is on PATH) of\n"
    "about 1k, 10k, 100k and 1M tets, and the machine's memory bandwidth (a triad) and its\n"
    "threads' scaling on work in registers in the same run: every explicit row says what\n"
    "fraction of the bound (60 bytes a tet-step at that bandwidth) it reaches. Prints\n"
    "medians. When femto-bench-bullet was built (Bullet found at configure time), Bullet's\n"
    "deformable world runs on the same meshes up to 10k tets.\n"
    "\n"
    "options:\n"
    "  --quick            stop at 10k tets, 3 repetitions (motion: the house; 100 props)\n"
    "  --max-tets N       skip meshes of more than N tets (beams count by their nominal size)\n"
    "  --meshes LIST      the families, comma-separated: house, box, beam, contact, motion,\n"
    "                     startup (default all; contact: three houses stacked, StVK and\n"
    "                     Neo-Hookean, implicit; ten houses piled on the floor, explicit and\n"
    "                     implicit; each with the same houses apart and the ratio; a 100k box\n"
    "                     on a mesh ground: ms per frame (median, 95th percentile, worst),\n"
    "                     contacts, the share of the step in the broad and narrow phases;\n"
    "                     motion: a drop, a clamped swing, a drag and the seeds' jump on the\n"
    "                     house and on bars of 1k, 10k and 100k tets, each frame its fastest\n"
    "                     of the interleaved repeats: median, 95th percentile, worst, Newton\n"
    "                     and CG, the distance from the 1e-6 path; then 1,000 props beside one\n"
    "                     alone; startup: a TetGen file to a first implicit step, by stage)\n"
    "  --explicit         only the explicit benchmark\n"
    "  --implicit         only the implicit benchmark (default: explicit, then implicit;\n"
    "                     implicit stops at 100k tets)\n"
    "  --repeats R        repetitions per measurement (default 5, --quick 3)\n"
    "  --frames F         frames of 1/60 s each motion scene and the props run (default\n"
    "                     120; the first, the world's setup, is not counted)\n"
    "  --workers N        the most workers to time (default: the cores available); every\n"
    "                     explicit row and the implicit game-tolerance rows run on 1 and on N\n"
    "                     workers\n"
    "  --csv FILE         also write the results as CSV, one row per case:\n"
    "                     mesh,tets,integrator,model,workers,ns_per_tet_step,ms_per_frame,\n"
    "                     newton_per_frame,cg_per_frame,bound_ns_per_tet_step,contacts,\n"
    "                     contact_share,broad_phase_share,narrow_phase_share,scene,p95_ms,\n"
    "                     worst_ms,newton_worst,cg_worst,accuracy,load_ms,create_ms,\n"
    "                     first_step_ms\n"
    "  --plot FILE.png    plot explicit StVK ns per tet-step against tets, and the frames in\n"
    "                     motion, with gnuplot (when on PATH); default with --csv: the CSV's\n"
    "                     name with .png\n"
    "  --no-plot          no plot\n"
    "  --peers            require the Bullet peer rows (an error when there is no peer)\n"
    "  --no-peers         no peer rows (default: when femto-bench-bullet was built)\n"
    "  --bullet PROGRAM   the femto-bench-bullet to run (implies --peers)\n"
    "  --simd LEVEL       the explicit kernels' instruction set for every row: auto (default),\n"
    "                     avx512, avx2, sse2, scalar, or off (the double-precision reference)\n"
    "  --deterministic    every world with cross-machine determinism (its cost)\n"
    "  --implicit-solver S  newton (default) or vbd (vertex block descent) for the implicit rows\n"
    "  --help             this text\n";

// Implicit frames on the 1M meshes take minutes each on a small machine: stop at 100k.
#define CLI_BENCH_IMPLICIT_MAX_TETS 200000

// The bytes an explicit tet-step must move at least (positions, forces and the tet's rest data,
// amortised), the figure for the memory-bandwidth bound.
#define CLI_BYTES_PER_TET_STEP 60.0

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

// Median ns per tet per step of explicit steps; false when a step failed.
static bool cliBenchExplicit(const cliBenchMesh* mesh, const cliBenchWorld* settings, int repeats,
                             double* nsPerTetStep)
{
	cliSimulation sim;
	if (!cliBenchMesh_World(mesh, settings, &sim))
		return false;
	// Stay safely inside the stability limit: a blow-up would measure the failure path.
	double dt = fmin(0.003, 0.5 * fmWorld_EstimateExplicitStep(sim.world));
	// One frame of enough steps for ~250 ms of work at ~25 ns per tet per step, and at least
	// the demo's 10 substeps: the frame's own work (the energy ledger, the health check, the
	// good state kept for a restore) is spread over its substeps as in a game.
	int steps = (int)fmax(10.0, fmin(1000.0, 1e7 / mesh->tets));
	double* samples = calloc((size_t)repeats, sizeof *samples);
	bool ok = samples != NULL && fmWorld_Step(sim.world, dt, 1) == fm_ok; // warm-up
	for (int r = 0; ok && r < repeats; ++r)
	{
		double start = cliNow();
		ok = fmWorld_Step(sim.world, dt * steps, steps) == fm_ok;
		samples[r] = (cliNow() - start) / steps;
	}
	if (ok)
		*nsPerTetStep = 1e9 * cliMedian(samples, repeats) / mesh->tets;
	free(samples);
	cliSimulation_Destroy(&sim);
	return ok;
}

// Median ms per 1/60 s implicit frame after one second, mean Newton and CG iterations a frame.
static bool cliBenchImplicit(const cliBenchMesh* mesh, const cliBenchWorld* settings, int repeats,
                             cliBenchResult* row)
{
	cliSimulation sim;
	if (!cliBenchMesh_World(mesh, settings, &sim))
		return false;
	double* samples = calloc((size_t)repeats, sizeof *samples);
	double newton = 0.0, cg = 0.0;
	bool ok = samples != NULL;
	// One second first: the house lands (free flight costs no Newton iteration at all, since
	// every step starts from it), the boxes and beams settle on the floor.
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
		row->msPerFrame = 1e3 * cliMedian(samples, repeats);
		row->newtonPerFrame = newton / repeats;
		row->cgPerFrame = cg / repeats;
	}
	free(samples);
	cliSimulation_Destroy(&sim);
	return ok;
}

// The run's shared state.
typedef struct cliBenchRun
{
	const cliBenchOptions* options;
	const cliBenchMeshSet* meshes;
	const char* folder; ///< the temporary folder, or NULL
	cliBenchReport report;
	double bandwidth[2]; ///< triad bytes per second on 1 and on options->workers threads
	int code;
} cliBenchRun;

static void cliBenchExplicitRow(cliBenchRun* run, const cliBenchMesh* mesh, fmMaterialModel model,
                                int w)
{
	int workers = w == 0 ? 1 : run->options->workers;
	const char* name = fmMaterialModelName(model);
	cliBenchResult row = cliBenchResult_Make(mesh, "explicit", name, workers);
	cliBenchWorld settings = {fm_explicit,
	                          model,
	                          workers,
	                          FM_TOLERANCE_ACCURATE,
	                          run->options->simd,
	                          run->options->deterministic,
	                          fm_solverNewton,
	                          false,
	                          0.0,
	                          false,
	                          0,
	                          0.0,
	                          false,
	                          0.0};
	if (!cliBenchExplicit(mesh, &settings, run->options->repeats, &row.nsPerTetStep))
	{
		printf("%-10s %9d %-11s %7d %12s\n", mesh->label, mesh->tets, name, workers, "failed");
		run->code = cli_exitInput;
		return;
	}
	double bound = run->bandwidth[w] > 0.0 ? 1e9 * CLI_BYTES_PER_TET_STEP / run->bandwidth[w] : 0;
	row.boundNs = bound;
	row.scene = "steps";
	printf("%-10s %9d %-11s %7d %12.1f %10.2f %7.1f%%\n", mesh->label, mesh->tets, name, workers,
	       row.nsPerTetStep, bound, bound > 0.0 ? 100.0 * bound / row.nsPerTetStep : 0.0);
	fflush(stdout);
	if (!cliBenchReport_Add(&run->report, &row))
		run->code = cli_exitInput;
}

// The machine's triad bandwidth on 1 and N threads, measured and printed once a run.
static void cliBenchBandwidth(cliBenchRun* run)
{
	const cliBenchOptions* o = run->options;
	if (run->bandwidth[0] > 0.0)
		return;
	cliTriadBandwidths(o->workers, &run->bandwidth[0], &run->bandwidth[1]);
	printf("memory bandwidth (triad): %.1f GB/s on 1 thread, %.1f GB/s on %d (ratio %.2f)\n",
	       run->bandwidth[0] / 1e9, run->bandwidth[1] / 1e9, o->workers,
	       run->bandwidth[0] > 0.0 ? run->bandwidth[1] / run->bandwidth[0] : 0.0);
}

static void cliBenchExplicitRows(cliBenchRun* run)
{
	static const fmMaterialModel models[2] = {fm_stvk, fm_neoHookean};
	const cliBenchOptions* o = run->options;
	cliBenchBandwidth(run);
	printf("explicit steps (FEM, symplectic Euler), median of %d; bound = %.0f bytes a tet-step "
	       "at the triad bandwidth of that many threads\n",
	       o->repeats, CLI_BYTES_PER_TET_STEP);
	printf("%-10s %9s %-11s %7s %12s %10s %8s\n", "mesh", "tets", "model", "workers", "ns/tet/step",
	       "bound ns", "of bound");
	for (int m = 0; m < run->meshes->count; ++m)
		for (int k = 0; k < 2; ++k)
			for (int w = 0; w < (o->workers > 1 ? 2 : 1); ++w)
				cliBenchExplicitRow(run, &run->meshes->meshes[m], models[k], w);
}

static void cliBenchImplicitRow(cliBenchRun* run, const cliBenchMesh* mesh, fmMaterialModel model,
                                int t, int workers)
{
	static const double tolerances[2] = {FM_TOLERANCE_GAME, FM_TOLERANCE_ACCURATE};
	static const char* const names[2] = {"game", "1e-6"};
	static const char* const integrators[2] = {"implicit game", "implicit 1e-6"};
	const char* name = fmMaterialModelName(model);
	cliBenchResult row = cliBenchResult_Make(mesh, integrators[t], name, workers);
	row.scene = "rest";
	cliBenchWorld settings = {fm_implicit,
	                          model,
	                          workers,
	                          tolerances[t],
	                          run->options->simd,
	                          run->options->deterministic,
	                          run->options->solver,
	                          false,
	                          0.0,
	                          false,
	                          0,
	                          0.0,
	                          false,
	                          0.0};
	if (!cliBenchImplicit(mesh, &settings, run->options->repeats, &row))
	{
		printf("%-10s %9d %-11s %-9s %7d %11s\n", mesh->label, mesh->tets, name, names[t], workers,
		       "failed");
		run->code = cli_exitInput;
		return;
	}
	printf("%-10s %9d %-11s %-9s %7d %11.2f %13.1f %10.1f\n", mesh->label, mesh->tets, name,
	       names[t], workers, row.msPerFrame, row.newtonPerFrame, row.cgPerFrame);
	fflush(stdout);
	if (!cliBenchReport_Add(&run->report, &row))
		run->code = cli_exitInput;
}

static void cliBenchImplicitRows(cliBenchRun* run)
{
	static const fmMaterialModel models[2] = {fm_neoHookean, fm_corotated};
	printf("implicit backward Euler, 1/60 s frames after 1 s of settling, to the game tolerance "
	       "(1e-2) and to 1e-6, median of %d\n",
	       run->options->repeats);
	printf("%-10s %9s %-11s %-9s %7s %11s %13s %10s\n", "mesh", "tets", "model", "tolerance",
	       "workers", "ms/frame", "Newton/frame", "CG/frame");
	for (int m = 0; m < run->meshes->count; ++m)
	{
		const cliBenchMesh* mesh = &run->meshes->meshes[m];
		if (mesh->tets > CLI_BENCH_IMPLICIT_MAX_TETS)
			continue;
		// The game preset on 1 and on N workers, 1e-6 on one.
		for (int k = 0; k < 2; ++k)
			for (int t = 0; t < 2; ++t)
			{
				cliBenchImplicitRow(run, mesh, models[k], t, 1);
				if (t == 0 && run->options->workers > 1)
					cliBenchImplicitRow(run, mesh, models[k], t, run->options->workers);
			}
	}
}

// Issue 34's laws against Neo-Hookean on the run's first mesh (the house by default): an
// explicit tet-step and an implicit frame at rest (game tolerance), 1 worker, each with its
// ratio to Neo-Hookean's; the plastic row (yield strain 1%) pays its yield test every substep
// (and its flow where the drop yields); the nodal row, the volume term on vertex patches (the
// double-precision force path and the square Newton pattern); the fracture row, a strength that
// never tears: the criterion each frame pays (every tet's stress, every shared face's traction).
static void cliBenchLawRows(cliBenchRun* run)
{
	// Neo-Hookean three times: elastic, plastic at a yield strain of 1%, with the nodal pressure.
	enum
	{
		lawCount = 7
	};
	static const fmMaterialModel laws[lawCount] = {
	    fm_neoHookean,      fm_neoHookean, fm_orthotropicLinear, fm_orthotropicStvk,
	    fm_fibreNeoHookean, fm_neoHookean, fm_neoHookean};
	static const char* const names[lawCount] = {
	    NULL, "neohookean-plastic", NULL, NULL, NULL, "neohookean-nodal", "neohookean-fracture"};
	const cliBenchOptions* o = run->options;
	const cliBenchMesh* mesh = &run->meshes->meshes[0];
	printf("material laws on %s (%d tets), 1 worker, median of %d: the cost against "
	       "Neo-Hookean's\n",
	       mesh->label, mesh->tets, o->repeats);
	printf("%-20s %12s %8s %11s %8s\n", "model", "ns/tet/step", "ratio", "ms/frame", "ratio");
	double explicitNs[lawCount] = {0}, implicitMs[lawCount] = {0};
	for (int k = 0; k < lawCount; ++k)
	{
		const char* name = names[k] != NULL ? names[k] : fmMaterialModelName(laws[k]);
		cliBenchWorld settings = {fm_explicit, laws[k],
		                          1,           FM_TOLERANCE_GAME,
		                          o->simd,     o->deterministic,
		                          o->solver,   false,
		                          0.0,         false,
		                          0,           k == 1 ? 0.01 : 0.0,
		                          k == 5,      k == 6 ? 1e12 : 0.0};
		cliBenchResult step = cliBenchResult_Make(mesh, "explicit", name, 1);
		cliBenchResult frame = cliBenchResult_Make(mesh, "implicit game", name, 1);
		step.scene = frame.scene = "laws";
		bool ok =
		    !o->explicitSteps || cliBenchExplicit(mesh, &settings, o->repeats, &step.nsPerTetStep);
		settings.integrator = fm_implicit;
		ok = ok && (!o->implicitFrames || cliBenchImplicit(mesh, &settings, o->repeats, &frame));
		if (!ok)
		{
			printf("%-20s %12s\n", name, "failed");
			run->code = cli_exitInput;
			continue;
		}
		explicitNs[k] = step.nsPerTetStep;
		implicitMs[k] = frame.msPerFrame;
		printf("%-20s %12.1f %7.2fx %11.3f %7.2fx\n", name, explicitNs[k],
		       explicitNs[0] > 0.0 ? explicitNs[k] / explicitNs[0] : 0.0, implicitMs[k],
		       implicitMs[0] > 0.0 ? implicitMs[k] / implicitMs[0] : 0.0);
		fflush(stdout);
		if ((o->explicitSteps && !cliBenchReport_Add(&run->report, &step)) ||
		    (o->implicitFrames && !cliBenchReport_Add(&run->report, &frame)))
			run->code = cli_exitInput;
	}
}

// Where the Bullet peer is, before anything is timed: "" when there is none (said why unless
// --no-peers); false when --peers or --bullet asked for one that is not there.
static bool cliBenchFindPeer(const cliBenchOptions* o, char* program, size_t size)
{
	char why[CLI_MAX_PATH + 128];
	program[0] = '\0';
	if (o->peers == cli_peersOff || cliBenchPeer_Find(o->bulletPath, program, why, size))
		return true;
	program[0] = '\0';
	if (o->peers == cli_peersRequired)
	{
		cliError("bench: --peers: %s", why);
		return false;
	}
	printf("peers: skipped: %s\n", why);
	return true;
}

// The Bullet peer's rows when there is one (and the implicit rows to compare with).
static void cliBenchPeerRows(cliBenchRun* run, const char* program)
{
	if (program[0] == '\0')
		return;
	if (!run->options->implicitFrames || run->folder == NULL)
	{
		printf("peers: skipped: %s\n", run->folder == NULL ? "no temporary folder for the mesh"
		                                                   : "they compare with the implicit "
		                                                     "rows, and --explicit was given");
		return;
	}
	if (!cliBenchPeer_Rows(program, run->meshes, run->folder, run->options->repeats, &run->report))
		run->code = cli_exitInput;
}

// The plot: --plot FILE, or the CSV's name with .png, unless --no-plot.
static void cliBenchPlot(cliBenchRun* run)
{
	const cliBenchOptions* o = run->options;
	char path[CLI_MAX_PATH], title[256];
	if (o->noPlot || (o->plotPath == NULL && o->csvPath == NULL))
		return;
	if (o->plotPath != NULL)
		snprintf(path, sizeof path, "%s", o->plotPath);
	else
	{
		size_t length = strlen(o->csvPath);
		if (length > 4 && strcmp(o->csvPath + length - 4, ".csv") == 0)
			length -= 4;
		if (snprintf(path, sizeof path, "%.*s.png", (int)length, o->csvPath) >= (int)sizeof path)
		{
			cliError("%s: path too long for the plot beside it", o->csvPath);
			run->code = cli_exitInput;
			return;
		}
	}
	if (run->bandwidth[0] > 0.0)
		snprintf(title, sizeof title, "femto bench; triad %.1f GB/s on 1 thread, %.1f GB/s on %d",
		         run->bandwidth[0] / 1e9, run->bandwidth[1] / 1e9, o->workers);
	else
		snprintf(title, sizeof title, "femto bench");
	if (cliBenchPlot_Write(&run->report, path, run->folder, title) == cli_plotFailed)
		run->code = cli_exitInput;
}

int cliBench(int argc, char** argv)
{
	cliBenchOptions o;
	int code = cliBenchParseOptions(argc, argv, &o);
	if (code >= 0)
		return code;
	char peer[CLI_MAX_PATH];
	if (!cliBenchFindPeer(&o, peer, sizeof peer))
		return cli_exitInput;
	cliBenchRun run;
	memset(&run, 0, sizeof run);
	run.options = &o;
	run.code = cli_exitOk;
	if (!cliBenchReport_Open(&run.report, o.csvPath))
		return cli_exitInput;
	// The beams, the peer's meshes and the gnuplot script go to a private temporary folder.
	char folder[CLI_MAX_PATH];
	run.folder = cliBenchTempDir_Make(folder, sizeof folder) ? folder : NULL;
	cliBenchMeshSet meshes;
	if (!cliBenchMeshSet_Make(o.families, o.maxTets, run.folder, &meshes))
		run.code = cli_exitInput;
	else
	{
		run.meshes = &meshes;
		// The machine's lines for the rows that time frames on its workers (the bodies, the
		// frames in motion), in the same run.
		bool machine = meshes.count > 0 || (o.families & (1u << cli_benchMotion)) != 0;
		if (o.workers > 1 && machine)
			printf("compute scaling (independent work in registers, %d threads against 1): "
			       "%.2fx; the reference for the workers' speed-ups below\n",
			       o.workers, cliComputeScaling(o.workers));
		if (machine && !(o.explicitSteps && meshes.count > 0))
			cliBenchBandwidth(&run);
		if (o.explicitSteps && meshes.count > 0)
			cliBenchExplicitRows(&run);
		if (o.implicitFrames && meshes.count > 0)
			cliBenchImplicitRows(&run);
		if (meshes.count > 0)
			cliBenchLawRows(&run);
		if ((o.families & (1u << cli_benchContact)) != 0)
			cliBenchContactRows(&o, &run.report, run.folder, &run.code);
		if ((o.families & (1u << cli_benchMotion)) != 0)
		{
			cliBenchMotionRows(&o, &meshes, &run.report, &run.code);
			if (o.implicitFrames)
				cliBenchPropsRows(&o, &run.report, &run.code);
		}
		if ((o.families & (1u << cli_benchStartup)) != 0 && o.implicitFrames)
			cliBenchStartupRows(&o, run.folder, &run.report, &run.code);
		cliBenchPeerRows(&run, peer);
		cliBenchPlot(&run);
	}
	cliBenchMeshSet_Free(&meshes);
	if (run.folder != NULL)
		cliBenchTempDir_Remove(run.folder);
	if (!cliBenchReport_Close(&run.report))
		run.code = cli_exitInput;
	return run.code;
}
