// Continuous collision detection for barrier contact: the first time two primitives moving
// linearly come within a minimum distance, by additive CCD (Li et al. 2021, "Codimensional
// Incremental Potential Contact", section 4 and algorithm 1): safe advances, each the current
// gap over an upper bound of the closing speed, until the gap shrinks to a fraction of where it
// started. Conservative by construction up to rounding: a time it returns leaves the primitives
// apart (ccd.c).
#pragma once

#include <femto/fm_math.h>

#include <stdbool.h>

// The first time t in [0, @p tMax] at which the 4-point stencil x + t dx, a point-triangle
// (p, t0, t1, t2) or, with @p edgeEdge, an edge-edge pair (a0, a1, b0, b1), would come within
// @p minDistance (m, >= 0); the advance stops at (1 - @p eta) of the starting gap (eta in (0, 1),
// 0.9 typical). INFINITY when they do not within tMax; 0 when they start within minDistance.
double fmCcd_Additive(bool edgeEdge, const fmVec3 x[4], const fmVec3 dx[4], double minDistance,
                      double eta, double tMax);
