// `femto static`: the equilibrium shape of every body of a scene under gravity and its pins.
#include "commands.h"
#include "output.h"
#include "scene.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

const char* const cliStaticHelp =
    "usage: femto static SCENE.json [--export-node FILE] [options]\n"
    "\n"
    "Solve every body of the scene for static equilibrium under gravity, its loads and its\n"
    "pins (the floor is ignored; an unpinned body has no equilibrium). Prints the relative\n"
    "residual reached, |f| on the free vertices over the forces the problem puts on the body\n"
    "(weight, loads, the reactions of the pins and prescribed displacements), and writes the\n"
    "positions as TetGen .node (the input numbering).\n"
    "\n"
    "options:\n"
    "  --export-node FILE  write the equilibrium positions (FILE_B.node per body B when the\n"
    "                      scene has several bodies)\n"
    "  --tolerance T       relative residual to reach (default 1e-8)\n"
    "  --max-iterations N  Newton iterations per load step, 1 to 1000 (default 200)\n"
    "  --help              this text\n"
    "\n"
    "Exit status: 0 converged, 1 bad scene/file, I/O error or no convergence, 2 usage error.\n";

// What `femto static` was asked: the scene, where to export, the solve's tolerance and budget.
typedef struct cliStaticOptions
{
	const char* scenePath;
	const char* exportNode;
	double tolerance;
	int maxIterations;
} cliStaticOptions;

// Parse the command line into @p o: -1 to go on, else the exit code (help printed, usage error).
static int cliStaticParse(int argc, char** argv, cliStaticOptions* o)
{
	*o = (cliStaticOptions){NULL, NULL, 1e-8, 200};
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		const char* value = NULL;
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(cliStaticHelp, stdout);
			return cli_exitOk;
		}
		else if (strcmp(arg, "--export-node") == 0)
		{
			if ((o->exportNode = cliOptionValue("static", argc, argv, &i)) == NULL)
				return cli_exitUsage;
		}
		else if (strcmp(arg, "--tolerance") == 0)
		{
			if ((value = cliOptionValue("static", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseDouble(value, &o->tolerance) ||
			    !(o->tolerance >= FM_MIN_TOLERANCE && o->tolerance < 1.0))
				return cliUsageError("static",
				                     "--tolerance: expected a number in [%g, 1), got '%s'",
				                     FM_MIN_TOLERANCE, value);
		}
		else if (strcmp(arg, "--max-iterations") == 0)
		{
			if ((value = cliOptionValue("static", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseIntOption("static", "--max-iterations", value, 1, FM_MAX_NEWTON_ITERATIONS,
			                       &o->maxIterations))
				return cli_exitUsage;
		}
		else if (arg[0] == '-' && arg[1] != 0)
			return cliUsageError("static", "unknown option '%s'", arg);
		else if (o->scenePath == NULL)
			o->scenePath = arg;
		else
			return cliUsageError("static", "more than one scene ('%s' and '%s')", o->scenePath,
			                     arg);
	}
	if (o->scenePath == NULL)
		return cliUsageError("static", "missing SCENE.json");
	return -1;
}

// Solve body @p b and report it; its result.
static fmResult cliStaticSolve(const cliScene* scene, cliSimulation* sim, int b,
                               const cliStaticOptions* o)
{
	double residual = 0.0;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	double start = cliNow();
	fmResult result =
	    fmBody_SolveStatic(sim->bodies[b], o->tolerance, o->maxIterations, &residual, &diag);
	double seconds = cliNow() - start;
	fmBodyStats stats = fmBody_GetStats(sim->bodies[b]);
	printf("body %d           residual %.3g (tolerance %.3g) in %.3f s, %s\n", b, residual,
	       o->tolerance, seconds, result == fm_ok ? "converged" : fmResultName(result));
	printf("                 elastic energy %.6g J, lowest y %.6g m, inverted tets %d\n",
	       stats.elasticEnergy, stats.lowestY, stats.invertedTets);
	if (stats.plasticWork > 0.0)
		printf("                 plastic work %.6g J, largest plastic strain %.6g\n",
		       stats.plasticWork, stats.plasticStrain);
	if (result != fm_ok)
	{
		char prefix[CLI_MAX_PATH + 32];
		snprintf(prefix, sizeof prefix, "%s: bodies[%d]", scene->name, b);
		cliPrintDiagnostic(prefix, &diag);
	}
	return result;
}

int cliStatic(int argc, char** argv)
{
	cliStaticOptions o;
	int parsed = cliStaticParse(argc, argv, &o);
	if (parsed >= 0)
		return parsed;
	cliScene scene;
	if (!cliScene_Load(o.scenePath, &scene))
		return cli_exitInput;
	cliSimulation sim;
	if (!cliSimulation_Create(&scene, cli_stepCheckOff, &sim))
	{
		cliScene_Free(&scene);
		return cli_exitInput;
	}
	int code = cli_exitOk;
	bool exportable = true;
	for (int b = 0; b < sim.bodyCount && code == cli_exitOk; ++b)
	{
		fmResult result = cliStaticSolve(&scene, &sim, b, &o);
		if (result != fm_ok)
		{
			code = cli_exitInput;
			// A solve that stopped short keeps its best state: still worth exporting.
			exportable = exportable && result == fm_errNotConverged;
		}
	}
	if (exportable && o.exportNode != NULL)
	{
		if (!cliWriteNodes(o.exportNode, &sim, true))
			code = cli_exitInput;
		else if (code != cli_exitOk)
			cliWarn("%s: the best state reached was written, but it is not converged to the "
			        "tolerance %g (see the residuals above)",
			        o.exportNode, o.tolerance);
	}
	cliSimulation_Destroy(&sim);
	cliScene_Free(&scene);
	return code;
}
