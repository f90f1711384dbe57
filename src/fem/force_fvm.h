// The finite-volume force model (force_fvm.c): stress on area-weighted rest face normals
// (Teran et al. 2003).
#pragma once

#include "body/body.h"

// Rest-face normals (body->fvmNormals); 0 on success, non-zero when memory is short.
int fmBuildFvmNormals(fmBody* body);

// FVM forces at positions x: add into f, return the elastic energy (J).
double fmAddFvmForces(const fmBody* body, const double* x, double* f);
