// `femto convert IN OUT`: a tet mesh from one file format to another (docs/cli.md).
#include "commands.h"
#include "scene.h"

#include <stdio.h>
#include <string.h>

const char* const cliConvertHelp =
    "usage: femto convert IN OUT\n"
    "\n"
    "Read the tet mesh IN (TetGen .node/.ele, Gmsh .msh 2.2 or 4.1, VTK .vtk or .vtu, Medit\n"
    ".mesh; chosen by the extension) and write it as OUT: .node (with the .ele beside it),\n"
    ".msh (Gmsh 4.1 ASCII) or .vtu (ASCII). Only tets are read: other elements are counted in\n"
    "a warning and left out. Regions (Gmsh physical tags, Medit references, TetGen's first tet\n"
    "attribute) are kept. Coordinates are written to round trip exactly.\n"
    "\n"
    "Exit status: 0 ok; 1 unreadable or malformed input, or OUT cannot be written; 2 usage\n"
    "error (also an OUT extension femto does not write).\n";

int cliConvert(int argc, char** argv)
{
	const char* paths[2] = {NULL, NULL};
	int pathCount = 0;
	for (int i = 1; i < argc; ++i)
	{
		if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
		{
			fputs(cliConvertHelp, stdout);
			return cli_exitOk;
		}
		if (argv[i][0] == '-' && argv[i][1] != 0)
			return cliUsageError("convert", "unknown option '%s'", argv[i]);
		if (pathCount == 2)
			return cliUsageError("convert", "too many arguments ('%s')", argv[i]);
		paths[pathCount++] = argv[i];
	}
	if (pathCount < 2)
		return cliUsageError("convert", "expected IN and OUT mesh files");
	fmMeshFormat out = fmMeshFormatFromPath(paths[1]);
	if (out != fm_meshFormatTetGen && out != fm_meshFormatGmsh && out != fm_meshFormatVtu)
		return cliUsageError("convert", "'%s': femto writes .node (with .ele), .msh or .vtu",
		                     paths[1]);
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult result = fmLoadMesh(paths[0], &mesh, &diag);
	if (result != fm_ok)
	{
		cliPrintDiagnostic(NULL, &diag);
		return cli_exitInput;
	}
	result = fmWriteMesh(paths[1], &mesh, NULL, &diag);
	if (result != fm_ok)
	{
		cliPrintDiagnostic(NULL, &diag);
		fmFreeTetMesh(&mesh);
		return cli_exitInput;
	}
	printf("%s (%s) -> %s (%s): %d nodes, %d tets%s\n", paths[0],
	       fmMeshFormatName(fmMeshFormatFromPath(paths[0])), paths[1], fmMeshFormatName(out),
	       mesh.nodeCount, mesh.tetCount, mesh.tetAttributeCount > 0 ? ", with regions" : "");
	fmFreeTetMesh(&mesh);
	return cli_exitOk;
}
