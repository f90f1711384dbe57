// `femto info`: what a mesh holds and how good its tets are.
#include "commands.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* const cliInfoHelp =
    "usage: femto info MESH [MESH.ele]\n"
    "       femto info builtin:house2\n"
    "\n"
    "Print node and tet counts, volumes, dihedral angles, quality, surface, bad tets and\n"
    "bounds of a tet mesh: TetGen .node (the .ele defaults to the one beside it), Gmsh .msh\n"
    "(2.2, 4.1, ASCII or binary), VTK .vtk or .vtu, Medit .mesh (docs/mesh-format.md). Only\n"
    "tets are read; other elements are counted in a warning.\n"
    "\n"
    "Angles, quality and degeneracy are measured scale-free (any units work); a volume that\n"
    "a double cannot hold is reported as out of range.\n"
    "\n"
    "Exit status: 0 ok; 1 unreadable or malformed mesh, degenerate tets (listed) or volumes\n"
    "out of range; 2 usage error.\n";

// Degenerate tets listed in the file's numbering, at most this many.
#define CLI_MAX_LISTED_TETS 20

static void cliPrintMeshInfo(const fmMeshInfo* info)
{
	printf("nodes            %d (%d unreferenced)\n", info->nodeCount, info->unreferencedNodes);
	printf("tets             %d\n", info->tetCount);
	printf("surface          %d triangles\n", info->surfaceTriangleCount);
	if (info->volumeOutOfRangeTets > 0 || !isfinite(info->totalVolume))
		printf("volume           out of the range of a double: %d tets have volumes beyond\n"
		       "                 1e-308 to 1e308 m^3 (are the coordinates in metres?)\n",
		       info->volumeOutOfRangeTets);
	else
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

static int cliCompareDoubles(const void* a, const void* b)
{
	double p = *(const double*)a, q = *(const double*)b;
	return p < q ? -1 : (p > q);
}

// "regions          2 (5: 100 tets, 6: 20 tets)": the first tet attribute (TetGen's region
// attribute, Gmsh's physical tag, Medit's reference), the first few values listed.
static void cliPrintRegions(const fmTetMesh* mesh)
{
	if (mesh->tetAttributeCount < 1 || mesh->tetCount < 1)
		return;
	double* values = malloc(sizeof(double) * (size_t)mesh->tetCount);
	if (values == NULL)
		return;
	for (int t = 0; t < mesh->tetCount; ++t)
		values[t] = mesh->tetAttributes[(size_t)t * (size_t)mesh->tetAttributeCount];
	qsort(values, (size_t)mesh->tetCount, sizeof(double), cliCompareDoubles);
	int distinct = 0;
	for (int t = 0; t < mesh->tetCount; ++t)
		distinct += t == 0 || values[t] != values[t - 1];
	printf("regions          %d (first tet attribute:", distinct);
	int listed = 0;
	for (int t = 0, start = 0; t < mesh->tetCount && listed < 8; ++t)
		if (t + 1 == mesh->tetCount || values[t + 1] != values[t])
		{
			printf("%s %.6g: %d tets", listed ? "," : "", values[t], t + 1 - start);
			start = t + 1;
			++listed;
		}
	printf("%s)\n", distinct > listed ? ", ..." : "");
	free(values);
}

// "degenerate at    tets 5 7 12 ..." in the file's numbering, the first CLI_MAX_LISTED_TETS.
static void cliListDegenerateTets(const fmTetMesh* mesh, int count)
{
	printf("degenerate at    tets");
	int listed = 0;
	for (int t = 0; t < mesh->tetCount && listed < CLI_MAX_LISTED_TETS; ++t)
	{
		fmTetQuality quality;
		if (fmTetMesh_GetTetQuality(mesh, t, &quality) == fm_ok && quality.degenerate)
		{
			printf(" %d", t + mesh->firstIndex);
			++listed;
		}
	}
	if (count > listed)
		printf(" (and %d more)", count - listed);
	printf(" (numbered as in the file)\n");
}

// Load the mesh `femto info` names: builtin:house2, a .node/.ele pair, or any format by its
// extension (a .node loads the .ele beside it); @p elePath gets what the report calls its tets.
static fmResult cliInfoLoad(const char* const* paths, int pathCount, fmTetMesh* mesh, char* elePath,
                            size_t elePathSize, fmDiagnostic* diag)
{
	if (strcmp(paths[0], "builtin:house2") == 0 && pathCount == 1)
	{
		snprintf(elePath, elePathSize, "builtin:house2.ele");
		return cliLoadHouseMesh(mesh, diag);
	}
	if (pathCount == 2)
	{
		snprintf(elePath, elePathSize, "%s", paths[1]);
		return fmLoadTetGen(paths[0], elePath, mesh, diag);
	}
	fmMeshFormat format = fmMeshFormatFromPath(paths[0]);
	size_t length = strlen(paths[0]);
	if (format == fm_meshFormatTetGen && length >= 5 &&
	    strcmp(paths[0] + length - 5, ".node") == 0 && length < elePathSize)
		snprintf(elePath, elePathSize, "%.*s.ele", (int)(length - 5), paths[0]);
	else
		snprintf(elePath, elePathSize, "%s", fmMeshFormatName(format));
	return fmLoadMesh(paths[0], mesh, diag);
}

// The report of a loaded mesh; exit 1 when a body cannot be made from it.
static int cliInfoReport(const char* path, const char* elePath, fmTetMesh* mesh)
{
	fmMeshInfo info;
	fmResult result = fmTetMesh_GetInfo(mesh, &info);
	if (result != fm_ok)
	{
		cliError("%s: cannot compute mesh statistics: %s", path, fmResultMessage(result));
		return cli_exitInput;
	}
	printf("mesh             %s, %s\n", path, elePath);
	cliPrintMeshInfo(&info);
	cliPrintRegions(mesh);
	int code = cli_exitOk;
	if (info.degenerateTets > 0)
	{
		cliListDegenerateTets(mesh, info.degenerateTets);
		cliError("%s: %d degenerate tets (zero volume relative to their size): a body cannot be "
		         "made from this mesh",
		         path, info.degenerateTets);
		code = cli_exitInput;
	}
	if (info.volumeOutOfRangeTets > 0)
	{
		cliError("%s: %d tets have volumes out of the range of a double: a body cannot be made "
		         "from this mesh",
		         path, info.volumeOutOfRangeTets);
		code = cli_exitInput;
	}
	return code;
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
		return cliUsageError("info", "missing MESH");
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	char elePath[CLI_MAX_PATH];
	if (cliInfoLoad(paths, pathCount, &mesh, elePath, sizeof elePath, &diag) != fm_ok)
	{
		cliPrintDiagnostic(NULL, &diag);
		return cli_exitInput;
	}
	int code = cliInfoReport(paths[0], elePath, &mesh);
	fmFreeTetMesh(&mesh);
	return code;
}
