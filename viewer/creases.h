// Normals split at sharp creases (creases.c), as renderers do: a surface smoothed across a hard
// edge (a house's wall meeting its roof) shows specular streaks and lumpy shading along it.
#pragma once

#include <stdbool.h>

/// Buffers kept from frame to frame (no allocation once the sizes settle).
typedef struct fvCreases
{
	float* faces; ///< 3 per triangle: its normal, area-weighted (twice the area long)
	int* start; ///< vertexCount + 1: the triangles at vertex v are around[start[v] .. start[v + 1])
	int* around; ///< 3 per triangle
	int faceCapacity, vertexCapacity;
} fvCreases;

/// The normal of each corner of each triangle (9 floats a triangle into @p corners): the
/// area-weighted mean of the normals of the triangles at that corner's vertex that make less
/// than @p degrees with the corner's own triangle. A vertex where every angle is below it gets
/// its smooth normal at every corner; one on a crease gets one normal a side. False when memory
/// is short (nothing written).
bool fvCreases_CornerNormals(fvCreases* c, const float* positions, int vertexCount,
                             const int* indices, int triangleCount, float degrees, float* corners);

/// Release the buffers.
void fvCreases_Free(fvCreases* c);
