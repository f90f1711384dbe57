// Squared distances between the primitives of two surfaces, with their exact gradients and
// Hessians, for barrier contact (distance.c). A stencil is 4 points: a point and a triangle
// (p, t0, t1, t2) or two edges (a0, a1, b0, b1). The distance is the true Euclidean one between
// the primitives; its formula depends on where the closest points lie (the type: two corners,
// a corner and an edge's line, a point and a triangle's plane, two edges' lines), and within each
// type it is a smooth function of the 12 coordinates, as in ipc-toolkit (distance_type.cpp).
#pragma once

#include <femto/fm_math.h>

#include <stdbool.h>

typedef enum fmDistanceType
{
	fm_distancePointPoint,    // |a - b|^2 of two stencil points
	fm_distancePointLine,     // a stencil point to the line through two others
	fm_distancePointPlane,    // a stencil point to the plane through three others
	fm_distanceLineLine,      // the lines through (0, 1) and (2, 3)
} fmDistanceType;

// Which formula applies and to which stencil points (indices 0 to 3; the first is the point for
// point-line and point-plane).
typedef struct fmDistanceStencil
{
	fmDistanceType type;
	int count;     // points involved: 2, 3, 4 or 4
	int vertex[4]; // their stencil indices
} fmDistanceStencil;

// The type of a point-triangle pair x = (p, t0, t1, t2): the region of the triangle nearest p.
fmDistanceStencil fmDistance_PointTriangleType(const fmVec3 x[4]);

// The type of an edge-edge pair x = (a0, a1, b0, b1): where the segments' nearest points lie.
// Nearly parallel edges never get the line-line type (its formula divides by |da x db|^2).
fmDistanceStencil fmDistance_EdgeEdgeType(const fmVec3 x[4]);

// The squared distance of stencil @p stencil at @p x; with @p gradient (12 doubles) and
// @p hessian (144, row-major) not NULL, its derivatives with respect to the 12 coordinates
// (zero for the points the type leaves out).
double fmDistance_Squared(const fmDistanceStencil* stencil, const fmVec3 x[4], double* gradient,
                          double* hessian);

// The nearest points of two edges x = (a0, a1, b0, b1): a0 + s (a1 - a0) and b0 + t (b1 - b0),
// s and t in [0, 1] (nearly parallel edges take s = 0).
void fmDistance_EdgeEdgeClosest(const fmVec3 x[4], double* s, double* t);

// The squared distances of a point and a triangle, and of two edges (type and value).
double fmDistance_PointTriangle(const fmVec3 x[4]);
double fmDistance_EdgeEdge(const fmVec3 x[4]);
