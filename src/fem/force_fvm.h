// The finite-volume force model (force_fvm.c): stress on area-weighted rest face normals
// (Teran et al. 2003).
#pragma once

#include "fem/elastic_mesh.h"

// Rest-face normals (body->fvmNormals); 0 on success, non-zero when memory is short.
int fmBuildFvmNormals(fmElasticMesh* mesh);

// FVM forces at positions x: add into f, return the elastic energy (J).
double fmAddFvmForces(const fmElasticMesh* mesh, const double* x, double* f);
