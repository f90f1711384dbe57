// VTK legacy .vtk reading (ASCII and BINARY, UNSTRUCTURED_GRID; mesh_vtk.c,
// docs/mesh-format.md), and the cells-to-tets step the XML reader (mesh_vtu.h) shares.
#pragma once

#include "mesh/mesh_reader.h"

#include <femto/mesh.h>

// Parse a whole legacy .vtk file held in memory. On failure @p mesh is untouched.
fmResult fmParseVtkLegacy(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                          fmDiagnostic* diag);

// The cells in offsets/connectivity form (cell c has nodes conn[start[c] .. start[c + 1])).
typedef struct fmVtkCells
{
	long long count;
	long long* start; // count + 1
	int* conn;        // start[count] node numbers, each checked against the node count
	long long connCount;
	unsigned char* types; // count
	double* regions;      // count, or NULL
} fmVtkCells;

void fmVtkCells_Free(fmVtkCells* c);

// Tets from the cells into @p list: linear tets (type 10), quadratic ones (24) by their corners,
// other cell types counted as skipped; @p s locates errors (the CELL_TYPES or Piece).
fmResult fmVtkCells_ToTets(const fmVtkCells* c, fmTetList* list, const fmScan* s);
