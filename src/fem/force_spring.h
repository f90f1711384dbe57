// The mass-spring force model on the tet edges (force_spring.c, docs/force-models.md).
#pragma once

#include "fem/elastic_mesh.h"

// Young's modulus of a material from its Lame constants: mu (3 lambda + 2 mu) / (lambda + mu).
double fmYoungsModulus(const fmMaterial* m);

// Build the edge list and spring stiffness from the tets and material (called by fmCreateBody);
// 0 on success.
int fmBuildSprings(fmElasticMesh* mesh);

// Mass-spring energy at x (J).
double fmSpringEnergy(const fmElasticMesh* mesh, const double* x);

// Mass-spring forces at x: add into f, return the energy (J). Builds nothing.
double fmAddSpringForces(const fmElasticMesh* mesh, const double* x, double* f);

// Dashpot coefficient of spring e (N s/m) and its unit direction at x; 0 if it has none.
double fmSpringDashpot(const fmElasticMesh* mesh, const double* invMass, const double* x, int e, fmVec3* direction);

// Mass-spring damping forces on relative edge velocities: add into f.
void fmAddSpringDamping(const fmElasticMesh* mesh, const double* invMass, const double* x, const double* v, double* f);

// Mass-spring edge Hessian (6x6, PSD-projected if @p project) of edge e.
void fmSpringHessian(const fmElasticMesh* mesh, const double* x, int e, double* K, int project);
