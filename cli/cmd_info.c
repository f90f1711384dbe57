// `femto info`: what a mesh holds and how good its tets are.
#include "commands.h"
#include "scene.h"

#include <stdio.h>
#include <string.h>

const char* const cliInfoHelp =
    "usage: femto info MESH.node [MESH.ele]\n"
    "       femto info builtin:house2\n"
    "\n"
    "Print node and tet counts, volumes, dihedral angles, quality, surface, bad tets and\n"
    "bounds of a TetGen mesh. The .ele defaults to the one beside the .node.\n"
    "\n"
    "Exit status: 0 ok, 1 unreadable or malformed mesh, 2 usage error.\n";

static void cliPrintMeshInfo(const fmMeshInfo* info)
{
	printf("nodes            %d (%d unreferenced)\n", info->nodeCount, info->unreferencedNodes);
	printf("tets             %d\n", info->tetCount);
	printf("surface          %d triangles\n", info->surfaceTriangleCount);
	printf("volume           %.6g m^3 total, tets from %.6g to %.6g m^3\n", info->totalVolume,
	       info->minVolume, info->maxVolume);
	printf("dihedral angles  %.3f to %.3f degrees\n", info->minDihedralDeg, info->maxDihedralDeg);
	printf("min quality      %.4f (radius ratio 3 r_in / r_circ, 1 = regular)\n", info->minQuality);
	printf("inverted tets    %d\n", info->invertedTets);
	if (info->invertedTets == info->tetCount && info->tetCount > 0)
		printf("                 (every tet is wound the other way: bodies reorient them, so\n"
		       "                 this is harmless; swap_yz in a scene flips them back too)\n");
	printf("degenerate tets  %d\n", info->degenerateTets);
	printf("bad tets         %d (degenerate, or a dihedral angle < 5 degrees)\n", info->badTets);
	printf("bounds           [%.6g %.6g %.6g] to [%.6g %.6g %.6g] m\n", info->boundsMin.x,
	       info->boundsMin.y, info->boundsMin.z, info->boundsMax.x, info->boundsMax.y,
	       info->boundsMax.z);
}

int cliInfo(int argc, char** argv)
{
	const char* paths[2] = {NULL, NULL};
	int pathCount = 0;
	for (int i = 1; i < argc; ++i)
	{
		if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
		{
			fputs(cliInfoHelp, stdout);
			return cli_exitOk;
		}
		if (argv[i][0] == '-' && argv[i][1] != 0)
			return cliUsageError("info", "unknown option '%s'", argv[i]);
		if (pathCount == 2)
			return cliUsageError("info", "too many arguments ('%s')", argv[i]);
		paths[pathCount++] = argv[i];
	}
	if (pathCount == 0)
		return cliUsageError("info", "missing MESH.node");

	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult result;
	char elePath[CLI_MAX_PATH];
	if (strcmp(paths[0], "builtin:house2") == 0 && pathCount == 1)
	{
		result = cliLoadHouseMesh(&mesh, &diag);
		snprintf(elePath, sizeof elePath, "builtin:house2.ele");
	}
	else
	{
		size_t length = strlen(paths[0]);
		if (pathCount == 2)
			snprintf(elePath, sizeof elePath, "%s", paths[1]);
		else if (length >= 5 && strcmp(paths[0] + length - 5, ".node") == 0 &&
		         length < sizeof elePath)
			snprintf(elePath, sizeof elePath, "%.*s.ele", (int)(length - 5), paths[0]);
		else
			return cliUsageError("info", "'%s' does not end in .node: name the .ele too", paths[0]);
		result = fmLoadTetGen(paths[0], elePath, &mesh, &diag);
	}
	if (result != fm_ok)
	{
		cliPrintDiagnostic(NULL, &diag);
		return cli_exitInput;
	}
	fmMeshInfo info;
	result = fmTetMesh_GetInfo(&mesh, &info);
	if (result != fm_ok)
	{
		cliError("%s: cannot compute mesh statistics: %s", paths[0], fmResultMessage(result));
		fmFreeTetMesh(&mesh);
		return cli_exitInput;
	}
	printf("mesh             %s, %s\n", paths[0], elePath);
	cliPrintMeshInfo(&info);
	fmFreeTetMesh(&mesh);
	return cli_exitOk;
}
