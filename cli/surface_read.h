// Triangle surfaces for `femto mesh` (surface_read.c): STL (ASCII and binary), OFF and ASCII PLY,
// read into a plain surface with errors located by file and line (binary STL: byte offset).
#pragma once

#include "cli.h"

#include <stdio.h>

/// A triangle surface being read: malloc'd arrays, released by cliSurface_Free.
typedef struct cliSurface
{
	int vertexCount;
	double* x; ///< 3 per vertex
	int triangleCount;
	int* triangles; ///< 3 per triangle, 0-based, as the file winds them
	int vertexCapacity;
	int triangleCapacity;
} cliSurface;

/// The surface formats read here (OBJ goes through the library's fmLoadObj).
typedef enum cliSurfaceFormat
{
	cli_surfaceStl, ///< binary when the size is 84 + 50 times the facet count, else ASCII
	cli_surfaceOff, ///< Geomview OFF, polygons fan-triangulated
	cli_surfacePly, ///< PLY in ASCII: the vertex element's x, y, z and the face element's lists
} cliSurfaceFormat;

/// Read @p size bytes of @p data (modified in place; need not be NUL-terminated: a copy is
/// made) named @p name in diagnostics. On failure prints "name:line: what was expected" to
/// @p messages (NULL: silent, for the fuzzer) and returns false with @p surface empty. Counts are
/// limited to FM_MAX_SURFACE_VERTICES and FM_MAX_SURFACE_TRIANGLES; STL corners with equal
/// coordinates are welded into one vertex.
bool cliReadSurface(const char* name, const char* data, size_t size, cliSurfaceFormat format,
                    FILE* messages, cliSurface* surface);

/// Add a vertex or a triangle (false when a limit or memory runs out).
bool cliSurface_AddVertex(cliSurface* s, double x, double y, double z);
bool cliSurface_AddTriangle(cliSurface* s, int a, int b, int c);

/// Release the arrays and zero the surface. Safe on a zeroed surface.
void cliSurface_Free(cliSurface* s);
