// The explicit integrator's stability limit: the largest step symplectic Euler takes without
// blowing up, estimated at the body's current deformation (stability.c).
#pragma once

#include "core/arena.h"
#include "fem/elastic_mesh.h"

// Largest stable explicit step (s) of the mesh at the positions of @p state, or INFINITY when
// nothing constrains it. Gershgorin's bound on the largest eigenvalue of M^-1 K(x), with K(x)
// the true (unprojected) tangent stiffness at the current deformation, gives omega_max; the
// step is 0.9 * 2 / omega_max. Takes one vector of 3n doubles from @p arena.
double fmExplicitStepLimit(const fmElasticMesh* mesh, const fmBodyState* state, fmArena* arena);

// A cheap measure of how far the deformation to @p x may have stiffened the mesh: the largest over
// its tets of max(|F|^2, |F|^4 / (4 J^2)), bounds on sigma_max^2 and 1 / sigma_min^2 (sigma_min >=
// 2 J / |F|^2). INFINITY when a tet is inverted or degenerate. The adaptive explicit substeps
// re-evaluate the limit when it moves.
double fmStiffeningProxy(const fmElasticMesh* mesh, const double* x);

// The same over tets [@p start, @p end): the proxy is their largest, so ranges taken on any
// workers in any order give the same value.
double fmStiffeningProxyRange(const fmElasticMesh* mesh, const double* x, int start, int end);
