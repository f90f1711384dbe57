// Internal elastic forces and their derivatives, for every force model.
#pragma once

#include "core/arena.h"
#include "core/parallel.h"
#include "fem/elastic_mesh.h"

// inverted[t - first] = !(det F > 0) for tets [first, end) at positions x (F and det with the
// bits of fmTetDeformation and fmDet), eight tets at a time on the CPU's vectors.
void fmInvertedTets(const fmElasticMesh* mesh, const double* x, int first, int end,
                    unsigned char* inverted);

// fmStiffeningProxy (stability.h) of tets [first, end) at positions x, eight tets at a time on
// the CPU's vectors: the same value, bit for bit (F and det as fmInvertedTets).
double fmStiffeningProxyTets(const fmElasticMesh* mesh, const double* x, int first, int end);

// Add elastic forces at positions x into f (3 * vertexCount); returns the elastic energy (J).
// Dispatches on body->forceModel.
double fmAddElasticForces(const fmElasticMesh* mesh, const double* x, double* f);

// FEM forces of tets [first, end) at positions x without touching shared data: the force on
// node a of tet t into forces[12 t + 3 a ...], its energy into energies[t]. With
// fmGatherTetForces() this gives the same bits as fmAddElasticForces() (the sums run in the
// same order), for any split of the tets.
void fmTetForces(const fmElasticMesh* mesh, const double* x, int first, int end, double* forces,
                 double* energies);

// f[i] += the forces of fmTetForces() on vertex i, in tet order, for vertices [first, end).
void fmGatherTetForces(const fmElasticMesh* mesh, const double* forces, int first, int end,
                       double* f);

// fmAddElasticForces() on the world's workers (FEM: per-tet forces, a gather per vertex in tet
// order, the energies summed in tet order: the same bits), buffers from @p arena; serial for
// one worker, a NULL @p tasks or other force models.
double fmAddElasticForcesOn(const fmElasticMesh* mesh, const double* x, double* f,
                            const fmTaskSystem* tasks, fmArena* arena);

// fmElasticEnergy() on the world's workers, the same bits.
double fmElasticEnergyOn(const fmElasticMesh* mesh, const double* x, const fmTaskSystem* tasks,
                         fmArena* arena);

// Elastic energy only (J).
double fmElasticEnergy(const fmElasticMesh* mesh, const double* x);

// Add the product of the (PSD-projected if @p project) elastic Hessian at x with dx into out:
// out += K(x) dx. Used by the implicit solver (matrix-free path) and by tests.
void fmAddHessianProduct(const fmElasticMesh* mesh, const double* x, const double* dx, double* out,
                         int project);

// Element stiffness matrix of tet t (12x12 row-major, node-major xyz; d^2 E / dx dx), projected
// to PSD if @p project.
void fmTetHessian(const fmElasticMesh* mesh, const double* x, int t, double* K, int project);

// Gradients of the linear shape functions: dF_ij / dx_{a,i} = g[a][j].
void fmShapeGradients(const fmMat3* DmInv, fmVec3 g[4]);

// K = V0 B^T (dP/dF) B, the 12x12 stiffness of a tet whose stress tangent is @p dPdF (9x9).
void fmContractTetHessian(const double* dPdF, const fmMat3* DmInv, double V0, double* K);
