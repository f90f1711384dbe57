// Internal elastic forces and their derivatives, for every force model.
#pragma once

#include "body.h"

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

// FVM forces (force_fvm.c): add into f, return energy.
double fmAddFvmForces(const fmBody* body, const double* x, double* f);

// Mass-spring forces (force_spring.c): add into f, return energy. Builds nothing.
double fmAddSpringForces(const fmBody* body, const double* x, double* f);
// Dashpot coefficient of spring e (N s/m) and its unit direction at x; 0 if it has none.
double fmSpringDashpot(const fmBody* body, const double* x, int e, fmVec3* direction);
// Mass-spring damping forces on relative edge velocities: add into f.
void fmAddSpringDamping(const fmBody* body, const double* x, const double* v, double* f);
// Mass-spring edge Hessian (6x6, PSD-projected if @p project) of edge e.
void fmSpringHessian(const fmBody* body, const double* x, int e, double* K, int project);
// Young's modulus of a material from its Lame constants: mu (3 lambda + 2 mu) / (lambda + mu).
double fmYoungsModulus(const fmMaterial* m);
// Rest-face normals for the FVM model (force_fvm.c); 0 on success.
int fmBuildFvmNormals(fmBody* body);
// Build the edge list and spring stiffness from the tets and material (called by fmCreateBody).
int fmBuildSprings(fmBody* body);
