// The seeds' velocity damping factor and Laplacian smoothing (velocity_filter.c), shared by
// both integrators.
#pragma once

#include "core/arena.h"
#include "fem/elastic_mesh.h"
#include "core/parallel.h"

// Apply the damping factor @p damping and the smoothing blend @p smoothing (fmBodyDef's), scaled from the seeds' 3 ms step to @p dt so that
// damping per second does not depend on the step. Smoothing takes a vector of 3n doubles from
// @p arena; it runs on @p tasks (NULL: serially), the same bits for any worker count, and with
// the kernels of @p level where the body has the explicit layout (the same bits on every level).
void fmFilterVelocities(const fmElasticMesh* mesh, fmBodyState* state, double damping,
                        double smoothing, double dt, fmArena* arena, fmSimdLevel level,
                        const fmTaskSystem* tasks);

// The damping factor of a step of @p dt: damping^(dt / 3 ms), 1 for a body without damping.
double fmVelocityFilter_DampingFactor(double damping, double dt);

// fmFilterVelocities without the damping factor (a step that has applied
// fmVelocityFilter_DampingFactor itself, in its velocity update: the same bits). A non-NULL
// @p then runs on each range of vertices right after their velocities are smoothed. Returns
// whether it smoothed (and so ran @p then on every vertex): false for a body without smoothing
// (or when the arena is short, which asserts).
bool fmVelocityFilter_Smooth(const fmElasticMesh* mesh, fmBodyState* state, double smoothing,
                             double dt, fmArena* arena, fmSimdLevel level,
                             const fmTaskSystem* tasks, const fmThenTask* then);
