// Collider triangles for the debug draw (draw_shapes.h).
#include "draw/draw_shapes.h"

#include "core/core.h"
#include "core/det_math.h"

#include <math.h>
#include <string.h>

// Latitude and longitude divisions of spheres and capsules.
#define FM_SHAPE_RINGS 12
#define FM_SHAPE_SEGMENTS 24

static bool fmShapeReserve(fmShapeBuffer* s, int vertices, int triangles)
{
	if (vertices > s->vertexCapacity)
	{
		float* p = FM_ALLOC_ARRAY(float, 3 * (size_t)vertices);
		float* n = FM_ALLOC_ARRAY(float, 3 * (size_t)vertices);
		if (p == NULL || n == NULL)
		{
			FM_FREE_ARRAY(p, float, 3 * (size_t)vertices);
			FM_FREE_ARRAY(n, float, 3 * (size_t)vertices);
			return false;
		}
		FM_FREE_ARRAY(s->positions, float, 3 * (size_t)s->vertexCapacity);
		FM_FREE_ARRAY(s->normals, float, 3 * (size_t)s->vertexCapacity);
		s->positions = p;
		s->normals = n;
		s->vertexCapacity = vertices;
	}
	if (triangles > s->triangleCapacity)
	{
		int* k = FM_ALLOC_ARRAY(int, 3 * (size_t)triangles);
		if (k == NULL)
			return false;
		FM_FREE_ARRAY(s->indices, int, 3 * (size_t)s->triangleCapacity);
		s->indices = k;
		s->triangleCapacity = triangles;
	}
	s->vertexCount = vertices;
	s->triangleCount = triangles;
	return true;
}

static void fmShapeVertex(fmShapeBuffer* s, int k, fmVec3 p, fmVec3 n)
{
	float* x = s->positions + 3 * (size_t)k;
	float* u = s->normals + 3 * (size_t)k;
	x[0] = (float)p.x, x[1] = (float)p.y, x[2] = (float)p.z;
	u[0] = (float)n.x, u[1] = (float)n.y, u[2] = (float)n.z;
}

static void fmShapeTriangle(fmShapeBuffer* s, int t, int a, int b, int c)
{
	s->indices[3 * t] = a, s->indices[3 * t + 1] = b, s->indices[3 * t + 2] = c;
}

// A sphere of @p radius about the collider's centre; a capsule's halves are moved apart by
// its rotated half segment (the upper hemisphere toward +segment).
static bool fmFillRound(fmShapeBuffer* s, const fmCollider* c, double radius, fmVec3 half)
{
	const int rings = FM_SHAPE_RINGS, segments = FM_SHAPE_SEGMENTS;
	if (!fmShapeReserve(s, (rings + 1) * (segments + 1), 2 * rings * segments))
		return false;
	fmVec3 axis = fmLength(half) > 0.0 ? fmScale(1.0 / fmLength(half), half) : fmMakeVec3(0, 1, 0);
	fmVec3 side = fabs(axis.x) < 0.9 ? fmMakeVec3(1, 0, 0) : fmMakeVec3(0, 1, 0);
	fmVec3 e1 = fmScale(1.0 / fmLength(fmCross(axis, side)), fmCross(axis, side));
	fmVec3 e2 = fmCross(axis, e1);
	const double pi = 3.14159265358979323846;
	for (int r = 0; r <= rings; ++r)
	{
		double sr, cr;
		fmDetSinCos(pi * r / rings, &sr, &cr);
		for (int g = 0; g <= segments; ++g)
		{
			double sg, cg;
			fmDetSinCos(2.0 * pi * g / segments, &sg, &cg);
			fmVec3 n = fmAdd(fmScale(cr, axis), fmAdd(fmScale(sr * cg, e1), fmScale(sr * sg, e2)));
			fmVec3 p = fmMulAdd(c->position, radius, n);
			p = fmMulAdd(p, r <= rings / 2 ? 1.0 : -1.0, half);
			fmShapeVertex(s, r * (segments + 1) + g, p, n);
		}
	}
	int t = 0;
	for (int r = 0; r < rings; ++r)
		for (int g = 0; g < segments; ++g)
		{
			int a = r * (segments + 1) + g, b = a + 1, d = a + segments + 1, e = d + 1;
			fmShapeTriangle(s, t++, a, d, b);
			fmShapeTriangle(s, t++, b, d, e);
		}
	return true;
}

// A box: 4 vertices with the face's normal on each of its 6 faces.
static bool fmFillBox(fmShapeBuffer* s, const fmCollider* c)
{
	if (!fmShapeReserve(s, 24, 12))
		return false;
	const double h[3] = {c->def.halfExtents.x, c->def.halfExtents.y, c->def.halfExtents.z};
	for (int f = 0; f < 6; ++f)
	{
		int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
		double sign = f % 2 ? 1.0 : -1.0;
		for (int k = 0; k < 4; ++k)
		{
			double local[3], normal[3] = {0.0, 0.0, 0.0};
			local[axis] = sign * h[axis];
			// counter-clockwise seen from outside: (u, v) turns the right way for +axis
			double su = (k == 1 || k == 2) ? 1.0 : -1.0, sv = k >= 2 ? 1.0 : -1.0;
			local[u] = su * h[u] * sign;
			local[v] = sv * h[v];
			normal[axis] = sign;
			fmVec3 p = fmMakeVec3(local[0], local[1], local[2]);
			fmVec3 n = fmMakeVec3(normal[0], normal[1], normal[2]);
			fmShapeVertex(s, 4 * f + k, fmAdd(c->position, fmMatVec(&c->rotation, p)),
			              fmMatVec(&c->rotation, n));
		}
		fmShapeTriangle(s, 2 * f, 4 * f, 4 * f + 1, 4 * f + 2);
		fmShapeTriangle(s, 2 * f + 1, 4 * f, 4 * f + 2, 4 * f + 3);
	}
	return true;
}

// A triangle mesh with flat normals (each triangle its own three vertices).
static bool fmFillMesh(fmShapeBuffer* s, const fmCollider* c)
{
	const fmMeshShape* m = c->mesh;
	if (!fmShapeReserve(s, 3 * m->triangleCount, m->triangleCount))
		return false;
	for (int t = 0; t < m->triangleCount; ++t)
	{
		fmVec3 n = fmMatVec(&c->rotation, m->faceNormal[t]);
		for (int k = 0; k < 3; ++k)
		{
			fmVec3 p = m->vertices[m->triangles[3 * t + k]];
			fmShapeVertex(s, 3 * t + k, fmAdd(c->position, fmMatVec(&c->rotation, p)), n);
		}
		fmShapeTriangle(s, t, 3 * t, 3 * t + 1, 3 * t + 2);
	}
	return true;
}

bool fmShapeBuffer_Fill(fmShapeBuffer* s, const fmCollider* c)
{
	switch (c->def.shape)
	{
	case fm_shapeSphere:
		return fmFillRound(s, c, c->def.radius, fmMakeVec3(0.0, 0.0, 0.0));
	case fm_shapeCapsule:
		return fmFillRound(s, c, c->def.radius, fmMatVec(&c->rotation, c->halfSegment));
	case fm_shapeBox:
		return fmFillBox(s, c);
	case fm_shapeMesh:
		return fmFillMesh(s, c);
	default:
		s->vertexCount = s->triangleCount = 0;
		return true;
	}
}

void fmShapeBuffer_Free(fmShapeBuffer* s)
{
	FM_FREE_ARRAY(s->positions, float, 3 * (size_t)s->vertexCapacity);
	FM_FREE_ARRAY(s->normals, float, 3 * (size_t)s->vertexCapacity);
	FM_FREE_ARRAY(s->indices, int, 3 * (size_t)s->triangleCapacity);
	memset(s, 0, sizeof *s);
}
