// Steps that keep every tet's orientation (inversion.c): the line search of an implicit solve
// starts no further than the fraction of its step at which a tet would lose all but a share of
// its volume (IPC's filter, Li et al. 2020, supplement; the IPC code's
// computeInjectiveStepSize_3d), so that no accepted iterate of a Neo-Hookean-class body turns a
// tet inside out, whatever the step.
#pragma once

#include "fem/elastic_mesh.h"

#include <stdbool.h>

// The share of a tet's volume a step may take away at the most: the filter stops a step where a
// tet keeps FM_INVERSION_KEEP of the volume it had.
#define FM_INVERSION_KEEP 0.2

// The largest t in (0, 1] such that on the way from @p x to x + t @p direction every tet keeps
// more than @p keep of its volume at x; 1 when none comes near. Tets already flat or inverted at
// x do not limit the step.
double fmInversion_StepLimit(const fmElasticMesh* mesh, const double* x, const double* direction,
                             double keep);

// Whether a tet positively oriented at @p from is flat or inverted at @p to.
bool fmInversion_Any(const fmElasticMesh* mesh, const double* from, const double* to);

// Whether the mesh's materials need positive volumes (their energy has ln J: Neo-Hookean and
// Mooney-Rivlin), which the implicit solve then keeps.
bool fmInversion_Needed(const fmElasticMesh* mesh);
