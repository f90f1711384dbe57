// femto: the command-line tool. Dispatches to the commands (docs/cli.md).
#include "cli.h"
#include "commands.h"
#include "viewer_hook.h"

#include <stdio.h>
#include <string.h>

static const char* const cliMainHelp =
    "usage: femto <command> [options]\n"
    "\n"
    "Real-time finite-element soft bodies.\n"
    "\n"
    "commands:\n"
    "  run [SCENE.json]     simulate a scene (default: the built-in bouncy house)\n"
    "  info MESH            mesh statistics: counts, volumes, angles, quality, bad tets\n"
    "  convert IN OUT       a tet mesh between TetGen, Gmsh .msh, VTK .vtu (.vtk, .mesh in)\n"
    "  mesh IN OUT          a surface (OBJ, STL, OFF, PLY) to tets with TetGen or Gmsh\n"
    "  static SCENE.json    static equilibrium under gravity and pins\n"
    "  bench                explicit and implicit step timings\n"
    "  view [SCENE.json]    the interactive viewer: drag, jump, sliders (docs/viewer.md)\n"
    "\n"
    "  femto <command> --help   options of a command\n"
    "  femto --version          version of the tool and library\n"
    "\n"
    "Exit status: 0 ok, 1 bad input, I/O error or numerical failure, 2 usage error.\n"
    "Scene files: docs/scene-format.md. The tool: docs/cli.md.\n";

int main(int argc, char** argv)
{
	cliInstallLogHook();
	if (argc < 2)
	{
		fputs(cliMainHelp, stderr);
		return cli_exitUsage;
	}
	const char* command = argv[1];
	if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0 ||
	    strcmp(command, "help") == 0)
	{
		fputs(cliMainHelp, stdout);
		return cli_exitOk;
	}
	if (strcmp(command, "--version") == 0)
	{
		fmVersion v = fmGetVersion();
		printf("femto %d.%d.%d (library %d.%d.%d)\n", FM_VERSION_MAJOR, FM_VERSION_MINOR,
		       FM_VERSION_PATCH, v.major, v.minor, v.patch);
		return cli_exitOk;
	}
	// Each command sees its own name as argv[0].
	if (strcmp(command, "run") == 0)
		return cliRun(argc - 1, argv + 1);
	if (strcmp(command, "info") == 0)
		return cliInfo(argc - 1, argv + 1);
	if (strcmp(command, "convert") == 0)
		return cliConvert(argc - 1, argv + 1);
	if (strcmp(command, "mesh") == 0)
		return cliMesh(argc - 1, argv + 1);
	if (strcmp(command, "static") == 0)
		return cliStatic(argc - 1, argv + 1);
	if (strcmp(command, "bench") == 0)
		return cliBench(argc - 1, argv + 1);
	if (strcmp(command, "view") == 0)
		return cliView(argc - 1, argv + 1);
	if (command[0] == '-')
		return cliUsageError(NULL, "unknown option '%s'", command);
	return cliUsageError(
	    NULL, "unknown command '%s' (commands: run, info, convert, mesh, static, bench, view)",
	    command);
}
