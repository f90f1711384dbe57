// Vertex block descent (vbd.c; Chen, Macklin et al., "Vertex Block Descent", SIGGRAPH 2024): the
// implicit step's incremental potential minimised one vertex at a time, a 3x3 Newton step per
// vertex with the projected Hessian of its own tets and its inertia, vertices of one colour
// (no shared tet) together, until the same relative residual as fmNewton_Solve. An alternative
// to Newton-PCG for measurement (fmWorldDef.implicitSolver); docs/implicit.md has the
// comparison.
#pragma once

#include "solver/newton.h"

// Minimise from body->x as fmNewton_Solve does (the same problem, stopping rule and result;
// iterations counts sweeps). Rayleigh stiffness damping (problem->useDamping) is not supported:
// the caller uses Newton then.
fmNewtonResult fmVbd_Solve(const fmElasticMesh* mesh, fmBodyState* state, fmImplicitCache* cache,
                           const fmNewtonProblem* problem);
