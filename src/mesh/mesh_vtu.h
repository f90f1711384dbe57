// VTK XML .vtu reading (mesh_vtu.c, docs/mesh-format.md).
#pragma once

#include <femto/mesh.h>

// Parse a whole .vtu (XML UnstructuredGrid) file held in memory: ascii, binary (base64) and
// appended (raw or base64) data arrays; zlib-compressed ones where femto was built with zlib.
fmResult fmParseVtu(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                    fmDiagnostic* diag);

// True when femto was built with zlib (compressed .vtu data can be read).
bool fmVtuHasZlib(void);
