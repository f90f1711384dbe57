// Small geometric queries shared by the contact stage, the mesh collider and the ray casts
// (geometry.c).
#pragma once

#include "core/det_math.h"

#include <femto/fm_math.h>

#include <stdbool.h>

// Whether the boxes [al, ah] and [bl, bh] meet (touching counts).
static inline bool fmBoxesMeet(fmVec3 al, fmVec3 ah, fmVec3 bl, fmVec3 bh)
{
	return !(ah.x < bl.x || al.x > bh.x || ah.y < bl.y || al.y > bh.y || ah.z < bl.z ||
	         al.z > bh.z);
}

// The componentwise least and greatest of @p a and @p b (fmMin, fmMax).
static inline fmVec3 fmMinVec(fmVec3 a, fmVec3 b)
{
	return fmMakeVec3(fmMin(a.x, b.x), fmMin(a.y, b.y), fmMin(a.z, b.z));
}

static inline fmVec3 fmMaxVec(fmVec3 a, fmVec3 b)
{
	return fmMakeVec3(fmMax(a.x, b.x), fmMax(a.y, b.y), fmMax(a.z, b.z));
}

// The point of triangle abc nearest p, as barycentric weights @p w (Ericson, Real-Time
// Collision Detection, 5.1.5). A weight that is exactly 0 means p's nearest point lies on the
// opposite edge (one zero) or on a corner (two zeros).
void fmClosestOnTriangle(fmVec3 p, fmVec3 a, fmVec3 b, fmVec3 c, double w[3]);

// Whether the segment o + t d, t in [0, 1], crosses the box [lo, hi] (slab test).
bool fmSegmentHitsBox(fmVec3 o, fmVec3 d, fmVec3 lo, fmVec3 hi);

// Fraction along o + t d, t in [0, 1], where it crosses triangle abc (either side), or -1
// (Moller-Trumbore).
double fmSegmentTriangle(fmVec3 o, fmVec3 d, fmVec3 a, fmVec3 b, fmVec3 c);
