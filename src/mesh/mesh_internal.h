// Internal mesh helpers shared by mesh.c and mesh_tetgen.c.
#pragma once

#include <femto/mesh.h>

#include <stddef.h>

// Allocate an array that is handed to the user and released with fmFree(): the allocator's free
// hook needs the size, so it is stored in a 64-byte header in front of the returned pointer
// (64 keeps the array 64-byte aligned). NULL on failure.
void* fmAllocUser(size_t size);

// A tet is degenerate when |6 V| <= FM_DEGENERATE_RATIO * (longest edge)^3: relative to its own
// size, so the test does not depend on units. A regular tet has 6 V / L^3 = 0.707.
#define FM_DEGENERATE_RATIO 1e-12

// Apply a placement (scale, centre, swap y and z, translate: fmTetMesh_Transform's) to @p n
// points of 3 doubles (mesh.c).
void fmTransformPoints(double* x, int n, const fmMeshTransform* transform);

// ---- shared by the mesh readers (mesh_tetgen.c) -----------------------------------------------------

// The start of every load from a path: clear @p diag, zero @p mesh, and refuse a missing mesh or
// a def not made by fmDefaultMeshLoadDef (fm_errParameter).
fmResult fmStartLoad(fmTetMesh* mesh, const fmMeshLoadDef* def, fmDiagnostic* diag);

// fm_errIndex naming both tets (and their lines, when @p lines is not NULL) when two tets use
// the same four nodes.
fmResult fmCheckDuplicateTets(const fmTetMesh* m, const int* lines, const char* name,
                              fmDiagnostic* diag);

// One warning when nodes are used by no tet (they are kept and do not move).
void fmWarnUnreferenced(const fmTetMesh* m, const char* name, fmDiagnostic* diag);

// ---- shared by the writers (mesh_tetgen.c, mesh_format.c)
// ----------------------------------------

// fmWriteTetGenNode, with @p commit false leaving the written file staged (mesh_file.h:
// fmCommitFile or fmDiscardFile), so that fmWriteMesh puts the .node and the .ele in place
// together or neither.
fmResult fmWriteTetGenNodeFile(const char* path, const fmTetMesh* mesh, const double* positions,
                               bool commit, fmDiagnostic* diag);
