// The start-up rows of `femto bench` (startup.h).
#include "startup.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

// The boxes: about 10k, 100k and 1M tets (a 1 m cube of cells^3 cubes, 6 tets each).
static const struct
{
	const char* label;
	int cells;
} cliStartupBoxes[] = {{"box 10k", 12}, {"box 100k", 26}, {"box 1M", 55}};
#define CLI_STARTUP_BOX_COUNT ((int)(sizeof cliStartupBoxes / sizeof cliStartupBoxes[0]))

// Meshes above this many tets are started once (their first implicit step takes seconds).
#define CLI_STARTUP_ONCE_TETS 200000

// What one start-up took (ms).
typedef struct cliStartupTimes
{
	double load, create, first, second;
} cliStartupTimes;

// Write the box of @p cells cells a side as TetGen files in @p folder; false with a message.
static bool cliStartupWrite(const char* folder, int cells, char* node, char* ele, size_t size)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (!cliJoinPath(node, size, folder, "startup.node") ||
	    !cliJoinPath(ele, size, folder, "startup.ele"))
		return false;
	if (fmMakeBoxMesh(cells, cells, cells, fmMakeVec3(-0.5, 0.0, -0.5), fmMakeVec3(0.5, 1.0, 0.5),
	                  &mesh) != fm_ok)
	{
		cliError("bench: start-up: out of memory for a box of %d cells a side", cells);
		return false;
	}
	bool ok = fmWriteTetGenNode(node, &mesh, NULL, &diag) == fm_ok &&
	          fmWriteTetGenEle(ele, &mesh, &diag) == fm_ok;
	if (!ok)
		cliPrintDiagnostic("bench: start-up", &diag);
	fmFreeTetMesh(&mesh);
	return ok;
}

// One start-up from the files: read, create (implicit, the game tolerance, the Coulomb floor at
// the box's foot), two steps. False with a message.
static bool cliStartupOnce(const cliBenchOptions* o, const char* node, const char* ele,
                           cliStartupTimes* t)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	double start = cliNow();
	if (fmLoadTetGen(node, ele, &mesh, &diag) != fm_ok)
	{
		cliPrintDiagnostic("bench: start-up", &diag);
		return false;
	}
	t->load = 1e3 * (cliNow() - start);
	start = cliNow();
	fmWorldDef def = cliBenchFloorWorldDef(o, o->workers);
	fmWorldId world = fmCreateWorld(&def);
	fmBodyDef body = cliBenchBoxBodyDef(&mesh);
	fmBodyId id;
	bool ok = fmWorld_IsValid(world) && fmCreateBody(world, &body, &id, &diag) == fm_ok;
	fmFreeTetMesh(&mesh);
	t->create = 1e3 * (cliNow() - start);
	start = cliNow();
	ok = ok && fmWorld_Step(world, 1.0 / 60.0, 1) == fm_ok;
	t->first = 1e3 * (cliNow() - start);
	start = cliNow();
	ok = ok && fmWorld_Step(world, 1.0 / 60.0, 1) == fm_ok;
	t->second = 1e3 * (cliNow() - start);
	if (!ok)
		cliError("bench: start-up: %s",
		         fmWorld_IsValid(world) ? fmWorld_GetLastError(world)->message : diag.message);
	fmDestroyWorld(world);
	return ok;
}

// The row of one box: its files written, started the run's repeats (or once), each stage's
// fastest kept.
static bool cliStartupRow(const cliBenchOptions* o, const char* folder, int box,
                          cliBenchReport* report)
{
	char node[CLI_MAX_PATH], ele[CLI_MAX_PATH];
	cliBenchMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	mesh.family = cli_benchBox;
	snprintf(mesh.label, sizeof mesh.label, "%s", cliStartupBoxes[box].label);
	int cells = cliStartupBoxes[box].cells;
	mesh.tets = 6 * cells * cells * cells;
	if (!cliStartupWrite(folder, cells, node, ele, sizeof node))
		return false;
	int repeats = mesh.tets > CLI_STARTUP_ONCE_TETS ? 1 : o->repeats;
	cliStartupTimes best = {INFINITY, INFINITY, INFINITY, INFINITY}, t;
	for (int r = 0; r < repeats; ++r)
	{
		if (!cliStartupOnce(o, node, ele, &t))
			return false;
		best = (cliStartupTimes){fmin(best.load, t.load), fmin(best.create, t.create),
		                         fmin(best.first, t.first), fmin(best.second, t.second)};
	}
	double total = best.load + best.create + best.first;
	printf("%-9s %8d %7d %10.1f %10.1f %11.1f %10.1f %11.1f\n", mesh.label, mesh.tets, o->workers,
	       best.load, best.create, best.first, total, best.second);
	fflush(stdout);
	cliBenchResult row = cliBenchResult_Make(&mesh, "implicit game", "neohookean", o->workers);
	row.scene = "startup";
	row.msPerFrame = best.second;
	row.loadMs = best.load;
	row.createMs = best.create;
	row.firstStepMs = best.first;
	return cliBenchReport_Add(report, &row);
}

void cliBenchStartupRows(const cliBenchOptions* o, const char* folder, cliBenchReport* report,
                         int* code)
{
	int most = o->quick && o->maxTets > 10368 ? 10368 : o->maxTets;
	printf("start-up: a TetGen file to a body's first implicit step (Neo-Hookean box on the "
	       "floor, the game tolerance), each stage its fastest of %d (once above %d tets), ms\n",
	       o->repeats, CLI_STARTUP_ONCE_TETS);
	if (folder == NULL)
	{
		printf("start-up: skipped: no temporary folder to write the meshes in\n");
		return;
	}
	printf("%-9s %8s %7s %10s %10s %11s %10s %11s\n", "mesh", "tets", "workers", "read", "create",
	       "first step", "total", "second step");
	for (int k = 0; k < CLI_STARTUP_BOX_COUNT; ++k)
	{
		int cells = cliStartupBoxes[k].cells;
		if (6 * cells * cells * cells > most)
			break;
		if (!cliStartupRow(o, folder, k, report))
		{
			printf("%-9s failed\n", cliStartupBoxes[k].label);
			*code = cli_exitInput;
		}
	}
}
