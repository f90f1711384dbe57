// What one fmWorld_Draw() gave, kept on the CPU: surfaces, lines, points and the floor plane.
// The renderer uploads it, framing takes its bounds. The lists keep their memory from frame to
// frame (no allocation per frame once the sizes settle).
#pragma once

#include "creases.h"

#include <femto/femto.h>

#include <stdbool.h>

/// One body's drawn surface, copied out of fmDrawTriangles (or, for a body with a render mesh,
/// that mesh: fmBody_CopyRenderPositionsFloat); colours always per vertex.
typedef struct fvSurface
{
	fmBodyId body;         ///< the body, or the null id for a collider
	fmColliderId collider; ///< the collider (fm_drawColliders), or the null id
	bool planeQuad;        ///< a plane collider drawn as a large quad (left out of the framing)
	int vertexCount;
	int triangleCount;
	float* positions; ///< 3 per vertex (m)
	float* normals;   ///< 3 per vertex, unit
	float* colors;    ///< 3 per vertex, RGB in [0, 1] (fmDrawTriangles.colors or .color)
	int* indices;     ///< 3 per triangle, into this surface's vertices
	int* vertices;    ///< the body's vertex index of each drawn vertex (-1 for a collider's or a
	                  ///< render mesh's)
	int vertexCapacity;
	int indexCapacity;
} fvSurface;

/// Everything drawn in one frame.
typedef struct fvDrawList
{
	fvSurface* surfaces;
	int surfaceCount;
	int surfaceCapacity;
	float* lines; ///< 6 floats a line end: x, y, z, r, g, b (two ends a segment)
	int lineVertexCount;
	int lineCapacity;
	float* points; ///< 7 floats a point: x, y, z, r, g, b, size (pixels)
	int pointCount;
	int pointCapacity;
	bool hasPlane;
	float planePoint[3];  ///< m
	float planeNormal[3]; ///< unit
	float planeColor[3];  ///< RGB in [0, 1]
	bool outOfMemory;     ///< something could not be stored (the rest is drawn)
	// Bodies' surfaces are drawn with normals split at creases (creases.h): a vertex per
	// triangle corner, through these buffers.
	fvCreases creases;
	float* cornerFloats; ///< 9 per triangle (corner normals), then 6 per vertex (position, colour)
	int cornerFloatCapacity;
	int* cornerInts; ///< 1 per vertex (the body's vertex numbers)
	int cornerIntCapacity;
} fvDrawList;

/// The angle (degrees) between two triangles beyond which their shared edge is drawn sharp.
#define FV_CREASE_DEGREES 40.0f

/// An empty list.
void fvDrawList_Init(fvDrawList* list);

/// Forget the last frame's contents, keeping the memory.
void fvDrawList_Clear(fvDrawList* list);

/// Release the memory.
void fvDrawList_Free(fvDrawList* list);

/// Clear the list and fill it with what fmWorld_Draw(@p world) draws with @p flags (fmDrawFlags).
/// Returns the library's result.
fmResult fvDrawList_Capture(fvDrawList* list, fmWorldId world, unsigned flags);

/// The debug-draw callbacks that append to @p list, with @p flags.
fmDebugDraw fvDrawList_Callbacks(fvDrawList* list, unsigned flags);

/// The box around the surfaces, lines and points (m). False when nothing was drawn.
bool fvDrawList_Bounds(const fvDrawList* list, float lo[3], float hi[3]);

/// The box a camera should frame: the bounds, and their shadow straight down on the floor
/// plane (the box's corners projected onto it), so the bodies and the floor under them are in
/// view. False when nothing was drawn.
bool fvDrawList_FramingBox(const fvDrawList* list, float lo[3], float hi[3]);

/// RGB in [0, 1] of a hex colour.
void fvHexToRgb(fmHexColor color, float rgb[3]);
