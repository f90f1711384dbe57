// Moving mesh colliders (mesh_motion.c): vertices the caller sets every frame
// (fmCollider_SetMeshVertices), reached along straight lines over the next frame's substeps,
// with the pseudo-normals and the hierarchy's boxes brought along and the vertices' velocity
// over the frame added to the collider's own at its surface.
#pragma once

#include "contact/mesh_collider.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct fmWorld fmWorld;
typedef struct fmCollider fmCollider;

// The frame's stages of moving meshes. A world calls them through fmWorld.meshMotion, which
// fmMeshMotion_Reserve sets: a program that never moves a mesh (the web page) links none of them.
typedef struct fmMeshMotionStages
{
	void (*beginFrame)(fmWorld* world, double rate);
	void (*substep)(fmWorld* world, double fraction);
	void (*endFrame)(fmWorld* world, bool stepped);
} fmMeshMotionStages;

typedef struct fmMeshMotion
{
	fmVec3* from;   // the vertices at the frame's start (between frames: the vertices now)
	fmVec3* to;     // where the caller asked them to be at the next frame's end
	fmVec3* rest;   // as created
	int* edgeSlots; // fmMeshShape_SortEdges's order, kept for every reshape
	bool pending;   // `to` set for the next frame
	bool moving;    // the frame in progress (between frames: the last one) moves the vertices
	double rate;    // 1 / the frame's length (1/s) while the frame moves the vertices, else 0
	double far;     // m, the longest path of a vertex from `from` to `to` while pending
	// fmMeshMotion_VelocityAt, called through here as the stages are (fmMeshMotionStages)
	fmVec3 (*velocityAt)(const fmCollider* collider, fmVec3 p);
} fmMeshMotion;

// Bytes the motion of a shape keeps once set up (counted in the shape's `bytes`).
size_t fmMeshMotion_Bytes(const fmMeshShape* shape);

// Set up @p shape's motion (nothing when it has one) and @p world's stages. False when memory is
// short.
bool fmMeshMotion_Reserve(fmWorld* world, fmMeshShape* shape);

// Release the shape's motion (none is fine).
void fmMeshMotion_Release(fmMeshShape* shape);

// What is wrong with @p count vertices at @p bytes (fmVec3s, any alignment) for @p shape, or NULL.
const char* fmMeshMotion_Problem(const fmMeshShape* shape, const void* bytes, int count);

// The vertices (checked, motion reserved) the shape reaches at the end of the next frame.
void fmMeshMotion_SetTarget(fmMeshShape* shape, const fmVec3* vertices);

// The velocity (m/s) that the vertices' motion gives mesh collider @p c's surface point nearest
// @p p: the blend of its triangle's vertex velocities, turned by the collider's rotation; zero
// outside a moving frame.
fmVec3 fmMeshMotion_VelocityAt(const fmCollider* collider, fmVec3 p);

// The stages (fmMeshMotionStages). Start a frame whose length is 1 / @p rate seconds: the rate of
// every pending mesh.
void fmMeshMotion_BeginFrame(fmWorld* world, double rate);

// Place every moving mesh @p fraction of the way through the frame (its substep's end).
void fmMeshMotion_Substep(fmWorld* world, double fraction);

// End the frame: when it @p stepped, every moving mesh at its target, which is spent; when it
// failed, back where the frame started with the target kept. The velocities are zero again.
void fmMeshMotion_EndFrame(fmWorld* world, bool stepped);

// A snapshot's view: 1 when the shape was moved, 2 more while a target is pending.
int fmMeshMotion_Flags(const fmMeshShape* shape);

// Restore a snapshot's state: @p flags, the vertices at @p vertices when moved (else the rest
// shape) and the target at @p target when pending (fmVec3s, any alignment; checked, and the
// motion reserved when moved).
void fmMeshMotion_Restore(fmMeshShape* shape, int flags, const void* vertices, const void* target);
