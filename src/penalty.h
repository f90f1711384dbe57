// The implicit step's contact penalty (penalty.c): inside the Newton solve, each surface vertex
// closer than the contact thickness to a collider adds the energy k/2 (thickness - d)^2, with
// d the signed distance and k = kappa m / h^2 (a stiffness that scales with the step's own
// inertia term), its gradient and its Gauss-Newton Hessian k n n^T. The contact stage after
// the solve then removes what penetration is left and applies friction (contact.c).
#pragma once

#include "body.h"
#include "collider.h"

// Stiffness of the penalty relative to the inertia term m / h^2 (dimensionless): a vertex
// resting on a collider under its own weight sinks g h^2 / kappa into the thickness band.
#define FM_PENALTY_KAPPA 100.0

typedef struct fmContactPenalty
{
	const fmCollider* colliders; // the world's collider slots
	int colliderCount;           // slots (unused ones are skipped)
	double thickness;            // m
	double stiffness;            // kappa / h^2 (1/s^2): k = stiffness * m
} fmContactPenalty;

// The penalty's energy at @p x (J), with its gradient added to @p gradient when not NULL.
double fmContactPenalty_Energy(const fmContactPenalty* penalty, const fmBody* body,
                               const double* x, double* gradient);

// Its Gauss-Newton Hessian k n n^T added to the vertices' diagonal blocks (9 doubles a block;
// @p diagonal[i] the slot of vertex i's block, NULL for one block per vertex).
void fmContactPenalty_AddHessian(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* x, const int* diagonal, double* values);

// y += the Hessian at @p at times @p dx (the matrix-free product).
void fmContactPenalty_AddProduct(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* at, const double* dx, double* y);
