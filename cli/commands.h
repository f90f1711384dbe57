// The femto commands; each returns the process exit code (cli_exit*).
#pragma once

/// `femto run [SCENE] [options]`: simulate and write results.
int cliRun(int argc, char** argv);

/// `femto info MESH [MESH.ele]`: mesh statistics.
int cliInfo(int argc, char** argv);

/// `femto convert IN OUT`: a tet mesh from one file format to another.
int cliConvert(int argc, char** argv);

/// `femto mesh IN OUT [options]`: a surface (OBJ, STL, OFF, PLY) to a tet mesh by TetGen or Gmsh.
int cliMesh(int argc, char** argv);

/// `femto static SCENE [options]`: static equilibrium of every body.
int cliStatic(int argc, char** argv);

/// `femto bench [options]`: timings of explicit and implicit steps.
int cliBench(int argc, char** argv);

/// Help texts, printed by `femto CMD --help`.
extern const char* const cliRunHelp;
extern const char* const cliInfoHelp;
extern const char* const cliConvertHelp;
extern const char* const cliMeshHelp;
extern const char* const cliStaticHelp;
extern const char* const cliBenchHelp;
