// Internal elastic forces and their derivatives, for every force model.
#pragma once

#include "body.h"
#include "force_fvm.h"
#include "force_spring.h"

// Deformation gradient of tet t at positions x: F = Ds Dm^-1.
fmMat3 fmTetDeformation(const fmBody* body, const double* x, int t);

// Add elastic forces at positions x into f (3 * vertexCount); returns the elastic energy (J).
// Dispatches on body->forceModel.
double fmAddElasticForces(const fmBody* body, const double* x, double* f);

// Elastic energy only (J).
double fmElasticEnergy(const fmBody* body, const double* x);

// Add the product of the (PSD-projected if @p project) elastic Hessian at x with dx into out:
// out += K(x) dx. Used by the implicit solver (matrix-free path) and by tests.
void fmAddHessianProduct(const fmBody* body, const double* x, const double* dx, double* out,
                         int project);

// Element stiffness matrix of tet t (12x12 row-major, node-major xyz; d^2 E / dx dx), projected
// to PSD if @p project.
void fmTetHessian(const fmBody* body, const double* x, int t, double* K, int project);
