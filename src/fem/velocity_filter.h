// The seeds' velocity damping factor and Laplacian smoothing (velocity_filter.c), shared by
// both integrators.
#pragma once

#include "core/arena.h"
#include "fem/elastic_mesh.h"
#include "core/parallel.h"

// The seeds' step (s): the damping factor and the smoothing blend are what one such step does.
#define FM_SEED_STEP 0.003

// Apply the damping factor @p damping and the smoothing blend @p smoothing (fmBodyDef's, per
// seeds' step) for a step of @p seedSteps seeds' steps (dt / FM_SEED_STEP), so that damping per
// second does not depend on the step. Smoothing takes a vector of 3n doubles from @p arena; it
// runs on @p tasks (NULL: serially), the same bits for any worker count, and with the kernels of
// @p level where the mesh has the explicit layout (the same bits on every level).
void fmFilterVelocities(const fmElasticMesh* mesh, fmBodyState* state, double damping,
                        double smoothing, double seedSteps, fmArena* arena, fmSimdLevel level,
                        const fmTaskSystem* tasks);

// The damping factor of a step of @p seedSteps seeds' steps: damping^seedSteps, 1 without
// damping.
double fmVelocityFilter_DampingFactor(double damping, double seedSteps);

// fmFilterVelocities without the damping factor (a step that has applied
// fmVelocityFilter_DampingFactor itself, in its velocity update: the same bits). A non-NULL
// @p then runs on each range of vertices right after their velocities are smoothed. Returns
// whether it smoothed (and so ran @p then on every vertex): false for a body without smoothing
// (or when the arena is short, which asserts).
bool fmVelocityFilter_Smooth(const fmElasticMesh* mesh, fmBodyState* state, double smoothing,
                             double seedSteps, fmArena* arena, fmSimdLevel level,
                             const fmTaskSystem* tasks, const fmThenTask* then);
