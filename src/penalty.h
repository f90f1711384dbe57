// The implicit step's contact penalty (penalty.c): inside the Newton solve, each surface vertex
// closer than the gap to a collider, or to the frozen plane of another body's surface near it,
// adds the energy k/2 (gap - d)^2, with d the signed distance and k = kappa m / h^2 (a stiffness
// that scales with the step's own inertia term), its gradient and its Gauss-Newton Hessian k n n^T.
// The contact stage after the solve then removes what penetration is left and applies friction
// (contact.c).
#pragma once

#include "body.h"
#include "collider.h"

// Stiffness of the penalty relative to the inertia term m / h^2 (dimensionless): a vertex
// resting on a collider under its own weight sinks g h^2 / kappa into it.
#define FM_PENALTY_KAPPA 100.0

typedef struct fmContactPenalty
{
	const fmCollider* colliders; // the world's collider slots
	int colliderCount;           // slots (unused ones are skipped)
	double stiffness;            // kappa / h^2 (1/s^2): k = stiffness * m
	double thickness;            // m, the gap kept from the planes of other bodies
	                             // (body->contactPlane, made before the step by contact.c);
	                             // colliders are kept at their surface, without a gap
} fmContactPenalty;

// The penalty's energy at @p x (J), with its gradient added to @p gradient when not NULL.
double fmContactPenalty_Energy(const fmContactPenalty* penalty, const fmBody* body, const double* x,
                               double* gradient);

// The work (J) the penalty's push did on the body over a step from @p xStart to its positions:
// the forces at the end (backward Euler's) times the motion, its positive part.
double fmContactPenalty_Work(const fmContactPenalty* penalty, const fmBody* body,
                             const double* xStart);

// Its Gauss-Newton Hessian k n n^T added to the vertices' diagonal blocks (9 doubles a block;
// @p diagonal[i] the slot of vertex i's block, NULL for one block per vertex).
void fmContactPenalty_AddHessian(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* x, const int* diagonal, double* values);

// y += the Hessian at @p at times @p dx (the matrix-free product).
void fmContactPenalty_AddProduct(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* at, const double* dx, double* y);
