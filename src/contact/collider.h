// Rigid colliders (collider.c): planes, spheres, boxes and capsules, static or kinematic, with
// the signed distance, the segment cast and the surface velocity the contact stage needs, and
// the impulse the bodies gave each one over the last step.
#pragma once

#include <femto/femto.h>

#include "contact/mesh_collider.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct fmWorld fmWorld;

typedef struct fmCollider
{
	uint32_t generation; // of the collider in the slot
	bool inUse;
	fmColliderDef def;     // as created (a plane's normal normalised)
	fmVec3 position;       // the centre now (plane: normal * offset; capsule: the midpoint)
	fmMat3 rotation;       // the orientation now (relative to the local shape below)
	fmVec3 localNormal;    // plane: the normal before rotation
	fmVec3 halfSegment;    // capsule: (b - a) / 2 before rotation
	fmMeshShape* mesh;     // mesh: the triangles and their hierarchy (owned)
	fmVec3 impulse;        // N s the bodies gave it in the current step
	fmVec3 angularImpulse; // N m s about its centre, likewise
	fmVec3 force;          // N, the last step's impulse over its length
	fmVec3 torque;         // N m, likewise
} fmCollider;

// Set a collider up from a validated def. False when memory is short (a mesh's copy).
bool fmCollider_Init(fmCollider* collider, const fmColliderDef* def);

// Release what a collider owns and mark its slot free.
void fmCollider_Release(fmCollider* collider);

// The collider's box now, or false when it is unbounded (a plane).
bool fmCollider_Bounds(const fmCollider* collider, fmVec3* lo, fmVec3* hi);

// The collider's thinnest extent (m): a sphere's or capsule's diameter, a box's smallest side, a
// mesh's smallest side of its box; INFINITY for a plane (a half-space cannot be passed through).
double fmCollider_Thickness(const fmCollider* collider);

// The fastest the collider's material moves (m/s): |v| plus |omega| times its box's half
// diagonal.
double fmCollider_SweepSpeed(const fmCollider* collider);

// Signed distance (m, negative inside) from @p p to the collider's surface, and the outward
// unit normal there.
double fmCollider_Distance(const fmCollider* collider, fmVec3 p, fmVec3* normal);

// The first point of the segment p0 -> p1 inside the collider grown by @p margin, as a fraction
// of the segment in [0, 1], and the grown surface's outward normal there. False when the
// segment stays outside, starts inside, or starts on the surface heading out (the distance
// query handles those).
bool fmCollider_CastSegment(const fmCollider* collider, fmVec3 p0, fmVec3 p1, double margin,
                            double* fraction, fmVec3* normal);

// Whether the collider moves in the frame in progress (between frames: the last one): a
// velocity, an angular velocity, or a mesh's vertices (fmCollider_SetMeshVertices).
bool fmCollider_IsMoving(const fmCollider* collider);

// The velocity (m/s) of the collider's material at @p p.
fmVec3 fmCollider_VelocityAt(const fmCollider* collider, fmVec3 p);

// The collider an id names (its world in @p world when given), or NULL when stale.
fmCollider* fmGetCollider(fmColliderId id, fmWorld** world);

// Whether two filters collide: each one's category is in the other's mask.
bool fmFiltersMeet(fmFilter a, fmFilter b);

// The rotation matrix of an axis-angle vector (Rodrigues).
fmMat3 fmRotationFromAxisAngle(fmVec3 axisAngle);
