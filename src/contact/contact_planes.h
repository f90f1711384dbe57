// The frozen planes of an implicit step (contact_planes.c): before the step, each surface vertex's
// nearest triangle of another body within the step's reach, and each pair of surface edges of
// two bodies within it, become planes the step's penalty keeps the vertex or edge in front of
// (penalty.h): each body's solve sees the others frozen where they started. Rules: planes only
// for steps longer than FM_PLANE_STEP_FACTOR times every body's explicit stability limit, and
// not in the pieces of a cut step (fmContact_Pieces), where the stage's projection alone keeps
// bodies apart; the planes come from the same parallel detection, in the same fixed order.
#pragma once

#include "contact/contact_state.h"

// Implicit steps no longer than this times a body's explicit stability limit keep bodies apart
// by the contact stage's projection alone, without frozen planes in the solve.
#define FM_PLANE_STEP_FACTOR 2.0

// Before an implicit step (with state->predict the step: the motion's horizon): each surface vertex's nearest triangle of another body that the
// step's motion may reach, frozen as a plane (n, n . q) in b->contactPlane for the step's
// penalty (penalty.h), NaN where there is none; and each pair of surface edges of two bodies
// within that reach, frozen as a plane for each edge (b->edgePlanes).
bool fmContactPlanes_Predict(fmWorld* world, fmContactState* state, double thickness);
