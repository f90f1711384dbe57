// What `femto mesh` checks in a surface before it hands it to TetGen or Gmsh (surface_check.c):
// the meshers need a closed, non-self-intersecting surface of sane coordinates, and say little
// useful when they do not get one (a temporary file's "0 points", a signal 6, an assertion).
#pragma once

#include "surface_read.h"

#include <stdbool.h>

/// Check @p s (read from @p path) and say on stderr what is wrong with it, if anything, naming
/// the first offending triangle or edge and counting the others: coordinates that are not
/// finite or beyond FM_MAX_COORDINATE, a flat box, triangles with a repeated vertex or no area,
/// edges that belong to one triangle (an open surface) or to more than two (not a manifold), and
/// pairs of triangles that cross each other (an edge of one through the other). True when it is
/// fit to mesh.
bool cliSurface_Check(const char* path, const cliSurface* s);
