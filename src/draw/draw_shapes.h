// Triangles of the colliders' shapes for fmWorld_Draw (draw_shapes.c): spheres and capsules as
// latitude-longitude meshes, boxes with flat faces, triangle meshes as they are, all placed at
// the collider's pose now.
#pragma once

#include "contact/collider.h"

#include <stdbool.h>

typedef struct fmShapeBuffer
{
	int vertexCount;
	int triangleCount;
	int vertexCapacity;
	int triangleCapacity;
	float* positions; // 3 per vertex
	float* normals;   // 3 per vertex, unit
	int* indices;     // 3 per triangle, counter-clockwise from outside
} fmShapeBuffer;

// Fill @p buffer with collider @p c's triangles (a plane has none: drawn by drawPlane). False
// when the buffer could not grow.
bool fmShapeBuffer_Fill(fmShapeBuffer* buffer, const fmCollider* c);

// Release the arrays; safe on a zeroed buffer.
void fmShapeBuffer_Free(fmShapeBuffer* buffer);
