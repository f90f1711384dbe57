// Internal mesh helpers shared by mesh.c and mesh_io.c.
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
