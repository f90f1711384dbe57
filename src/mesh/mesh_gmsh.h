// Gmsh .msh 2.2 and 4.1 reading, ASCII and binary (mesh_gmsh.c, docs/mesh-format.md).
#pragma once

#include <femto/mesh.h>

// Parse a whole .msh file held in memory; @p name is used in diagnostics. On failure @p mesh is
// untouched and nothing is leaked.
fmResult fmParseGmsh(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                     fmDiagnostic* diag);
