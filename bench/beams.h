// The TetGen beams of `femto bench` (beams.c): a 4 x 1 x 1 m beam (x in [-2, 2], y in [0, 1],
// z in [-0.5, 0.5]) described as a piecewise linear complex (.poly) and meshed at bench time by
// Debian's `tetgen`, found on PATH, in TetGen's own node and tet ordering. No tetgen, no beams: the
// bench says so and goes on.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// Mesh the beam for about @p nominal tets (1000, 10000, 100000 or 1000000: TetGen's maximum tet
/// volume chosen for that count, within about 15%) in @p folder with @p tetgen, the program's
/// path. Writes beamN.poly and tetgen's beamN.1.node and beamN.1.ele there (their paths in
/// @p node and @p ele, @p size bytes each), reads them with femto's TetGen reader and puts the
/// tet count in @p tets. Prints what went wrong (tetgen's own messages included) and returns
/// false on failure.
bool cliBenchBeam_Make(const char* tetgen, const char* folder, int nominal, char* node, char* ele,
                       size_t size, int* tets);
