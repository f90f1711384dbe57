// The TetGen beams (beams.h): write the .poly, run tetgen -pq with a volume bound, read the result.
#include "beams.h"

#include "cli.h"
#include "tools.h"

#include <stdio.h>
#include <string.h>

// TetGen's maximum tet volume (-a, m^3) for each nominal size, measured with Debian's tetgen
// 1.5.0 and -q (radius-edge ratio 2): 1136, 10596, 101444 and 990590 tets.
static const struct
{
	int nominal;
	const char* maxVolume;
} cliBeamVolumes[] = {
    {1000, "0.0105"}, {10000, "0.00085"}, {100000, "0.00008"}, {1000000, "0.0000078"}};

// The 8 corners and 6 quadrilateral facets of the beam, 1-based as TetGen's examples.
static const char cliBeamPoly[] = "# femto bench: a 4 x 1 x 1 m beam\n"
                                  "8 3 0 0\n"
                                  "1 -2 0 -0.5\n2 2 0 -0.5\n3 2 1 -0.5\n4 -2 1 -0.5\n"
                                  "5 -2 0 0.5\n6 2 0 0.5\n7 2 1 0.5\n8 -2 1 0.5\n"
                                  "6 0\n"
                                  "1\n4 1 2 3 4\n1\n4 5 6 7 8\n1\n4 1 2 6 5\n"
                                  "1\n4 2 3 7 6\n1\n4 3 4 8 7\n1\n4 4 1 5 8\n"
                                  "0\n0\n";

static const char* cliBeamMaxVolume(int nominal)
{
	for (size_t i = 0; i < sizeof cliBeamVolumes / sizeof cliBeamVolumes[0]; ++i)
		if (cliBeamVolumes[i].nominal == nominal)
			return cliBeamVolumes[i].maxVolume;
	return NULL;
}

static bool cliBeamWritePoly(const char* path)
{
	FILE* file = fopen(path, "w");
	if (file == NULL)
	{
		cliError("bench: %s: cannot open for writing", path);
		return false;
	}
	bool ok = fputs(cliBeamPoly, file) >= 0;
	ok = fclose(file) == 0 && ok;
	if (!ok)
		cliError("bench: %s: write error", path);
	return ok;
}

// Print the last lines tetgen wrote (its error message) after a failed run.
static void cliBeamShowLog(const char* log)
{
	FILE* file = fopen(log, "r");
	char line[512], last[4][512];
	int count = 0;
	while (file != NULL && fgets(line, sizeof line, file) != NULL)
		snprintf(last[count++ % 4], sizeof last[0], "%s", line);
	for (int i = count > 4 ? count - 4 : 0; i < count; ++i)
		fprintf(stderr, "  tetgen: %s", last[i % 4]);
	if (file != NULL)
		fclose(file);
}

static bool cliBeamRunTetgen(const char* tetgen, const char* folder, const char* poly,
                             const char* maxVolume)
{
	char log[CLI_MAX_PATH], switches[64], command[4 * CLI_MAX_PATH];
	if (!cliJoinPath(log, sizeof log, folder, "tetgen.log"))
		return false;
	// -p: mesh the .poly; -q: quality (radius-edge ratio 2); -a: maximum volume; -F: no .face
	// or .edge files; -Q: quiet.
	snprintf(switches, sizeof switches, "-pqFQa%s", maxVolume);
	command[0] = '\0';
	if (!cliBenchAppendQuoted(command, sizeof command, tetgen) ||
	    !cliBenchAppendQuoted(command, sizeof command, switches) ||
	    !cliBenchAppendQuoted(command, sizeof command, poly) ||
	    !cliBenchAppendText(command, sizeof command, " >") ||
	    !cliBenchAppendQuoted(command, sizeof command, log) ||
	    !cliBenchAppendText(command, sizeof command, " 2>&1"))
	{
		cliError("bench: the tetgen command for %s is too long", poly);
		return false;
	}
	int status = cliBenchRunCommand(command);
	if (status == 0)
		return true;
	cliError("bench: %s %s %s failed (exit status %d)", tetgen, switches, poly, status);
	cliBeamShowLog(log);
	return false;
}

bool cliBenchBeam_Make(const char* tetgen, const char* folder, int nominal, char* node, char* ele,
                       size_t size, int* tets)
{
	const char* maxVolume = cliBeamMaxVolume(nominal);
	char name[64], poly[CLI_MAX_PATH];
	if (maxVolume == NULL)
	{
		cliError("bench: no TetGen volume bound for a beam of %d tets", nominal);
		return false;
	}
	snprintf(name, sizeof name, "beam%d.poly", nominal);
	if (!cliJoinPath(poly, sizeof poly, folder, name) || !cliBeamWritePoly(poly) ||
	    !cliBeamRunTetgen(tetgen, folder, poly, maxVolume))
		return false;
	snprintf(name, sizeof name, "beam%d.1.node", nominal);
	if (!cliJoinPath(node, size, folder, name))
		return false;
	snprintf(name, sizeof name, "beam%d.1.ele", nominal);
	if (!cliJoinPath(ele, size, folder, name))
		return false;
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmLoadTetGen(node, ele, &mesh, &diag) != fm_ok)
	{
		cliPrintDiagnostic("bench: tetgen's beam", &diag);
		return false;
	}
	*tets = mesh.tetCount;
	fmFreeTetMesh(&mesh);
	return true;
}
