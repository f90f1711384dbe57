// The triangle-mesh collider's shape (mesh_collider.c): a copy of the caller's triangles in the
// mesh's own frame, a bounding-volume hierarchy over them, and the angle-weighted
// pseudo-normals (Baerentzen and Aanaes 2005) that give the signed distance its sign: negative
// behind the nearest feature, which for a closed, consistently wound mesh is exactly its inside.
#pragma once

#include <femto/femto.h>

#include <stdbool.h>
#include <stddef.h>

typedef struct fmMeshNode
{
	fmVec3 lo, hi; // the box of the node's triangles
	int left;      // inner node: the first child (the second is left + 1); leaf: -1
	int first;     // leaf: its triangles are order[first, first + count)
	int count;
} fmMeshNode;

typedef struct fmMeshShape
{
	int vertexCount;
	int triangleCount;
	fmVec3* vertices;     // in the mesh's frame
	int* triangles;       // 3 per triangle
	fmVec3* faceNormal;   // unit (zero for a degenerate triangle)
	fmVec3* edgeNormal;   // 3 per triangle: edge k runs from corner k to corner k + 1
	fmVec3* vertexNormal; // angle-weighted over the vertex's triangles
	int* order;           // triangles in leaf order
	fmMeshNode* nodes;
	int nodeCount;
	struct fmMeshMotion* motion; // the vertices' motion, NULL until first set (mesh_motion.h)
	size_t bytes;                // what all the above take
} fmMeshShape;

// Bytes a shape of @p vertexCount vertices and @p triangleCount triangles keeps (its `bytes`):
// what a world's memory budget counts for a mesh collider.
size_t fmMeshShape_Bytes(int vertexCount, int triangleCount);

// Copy and prepare a validated mesh def; NULL when memory is short.
fmMeshShape* fmMeshShape_Create(const fmColliderDef* def);

// Release a shape (NULL is fine).
void fmMeshShape_Destroy(fmMeshShape* shape);

// What is wrong with a def's mesh arrays, or NULL: counts, finite coordinates within 1e9 m,
// corners in range, and some triangle of an area above round-off (a mesh of degenerate
// triangles only has no surface to hold a body with: a body fell through it, or hung on it).
const char* fmMeshShape_Problem(const fmColliderDef* def);

// The triangle of the surface point nearest @p p (mesh frame) and that point's barycentric
// weights; returns the squared distance.
double fmMeshShape_Nearest(const fmMeshShape* shape, fmVec3 p, int* triangle, double weights[3]);

// Signed distance from @p p (mesh frame) to the surface, and the outward unit normal there.
double fmMeshShape_Distance(const fmMeshShape* shape, fmVec3 p, fmVec3* normal);

// The first crossing of the segment p0 -> p1 (mesh frame) into the solid through a triangle's
// front, as a fraction in [0, 1], and that triangle's normal. False when there is none.
bool fmMeshShape_CastSegment(const fmMeshShape* shape, fmVec3 p0, fmVec3 p1, double* fraction,
                             fmVec3* normal);

// The triangles' edge slots (3 * triangle + edge, edge k from corner k to corner k + 1) in an
// order that puts the slots of one edge next to each other. False when memory is short.
bool fmMeshShape_SortEdges(const fmMeshShape* shape, int* slots);

// Bring the pseudo-normals and the hierarchy's boxes to the vertices now (moved in place, the
// triangles unchanged): O(triangles), @p edgeSlots from fmMeshShape_SortEdges.
void fmMeshShape_Reshape(fmMeshShape* shape, const int* edgeSlots);

// The box (mesh frame) of the whole mesh.
void fmMeshShape_Bounds(const fmMeshShape* shape, fmVec3* lo, fmVec3* hi);
