// Kinematic targets (targets.c): zero-length springs from chosen vertices to positions the
// caller moves every frame (fmBody_SetTargets), in both integrators, with their work booked in
// the body's energy ledger.
#pragma once

#include "body/body.h"
#include "solver/newton.h"

// Implicit: the springs' energy 1/2 k |x - p|^2 at @p x, and k (x - p) added to @p gradient
// when it is not NULL.
double fmTargets_Energy(const fmBody* body, const double* x, double* gradient);

// Implicit: y += k x over the pulled vertices (the springs' Hessian is k I per vertex).
void fmTargets_AddProduct(const fmBody* body, const double* x, double* y);

// Implicit: k I added to the pulled vertices' diagonal blocks of a block matrix (9 doubles a
// block; @p diagonal[i] is the slot of vertex i's diagonal block, or NULL for blocks stored
// one per vertex).
void fmTargets_AddDiagonal(const fmBody* body, const int* diagonal, double* values);

// The springs as a term of an implicit step's potential (energy, Hessian, products), for
// fmNewtonProblem.targets; @p body must outlive the solve.
fmNewtonTerm fmTargets_Term(const fmBody* body);

// Implicit: the springs' work over a step from @p xStart to the body's positions, with the
// forces at the end (backward Euler's).
double fmTargets_ImplicitWork(const fmBody* body, const double* xStart);
