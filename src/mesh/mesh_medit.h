// Medit .mesh reading (ASCII; mesh_medit.c, docs/mesh-format.md).
#pragma once

#include <femto/mesh.h>

// Parse a whole .mesh file held in memory. On failure @p mesh is untouched.
fmResult fmParseMedit(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                      fmDiagnostic* diag);
