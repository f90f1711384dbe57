// Ray picking (picking.h). A linear pass over the triangles: the house's 1.4k surface triangles
// take microseconds, and a pick happens once per click.
#include "picking.h"

#include <math.h>

static void fvSub(const float* a, const float* b, float out[3])
{
	out[0] = a[0] - b[0], out[1] = a[1] - b[1], out[2] = a[2] - b[2];
}

static void fvCrossProduct(const float a[3], const float b[3], float out[3])
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

static float fvDot(const float a[3], const float b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Möller and Trumbore, "Fast, minimum storage ray/triangle intersection" (1997): the distance
// along the ray, or a negative number for a miss.
static float fvRayTriangle(const float o[3], const float d[3], const float* a, const float* b,
                           const float* c)
{
	float e1[3], e2[3], p[3], t[3], q[3];
	fvSub(b, a, e1);
	fvSub(c, a, e2);
	fvCrossProduct(d, e2, p);
	float det = fvDot(e1, p);
	if (fabsf(det) < 1e-12f)
		return -1.0f;
	float inverse = 1.0f / det;
	fvSub(o, a, t);
	float u = fvDot(t, p) * inverse;
	if (u < 0.0f || u > 1.0f)
		return -1.0f;
	fvCrossProduct(t, e1, q);
	float v = fvDot(d, q) * inverse;
	if (v < 0.0f || u + v > 1.0f)
		return -1.0f;
	return fvDot(e2, q) * inverse;
}

// The corner of triangle @p k of @p s closest to @p point.
static void fvClosestCorner(const fvSurface* s, int k, const float point[3], fvPick* pick)
{
	float best = INFINITY;
	for (int corner = 0; corner < 3; ++corner)
	{
		int local = s->indices[3 * k + corner];
		const float* p = s->positions + 3 * local;
		float d[3];
		fvSub(p, point, d);
		float distance = fvDot(d, d);
		if (distance < best)
		{
			best = distance;
			pick->vertex = s->vertices[local];
			pick->vertexAt[0] = p[0], pick->vertexAt[1] = p[1], pick->vertexAt[2] = p[2];
		}
	}
}

bool fvPick_Ray(const fvDrawList* list, const float origin[3], const float direction[3],
                fvPick* pick)
{
	float nearest = INFINITY;
	int hitSurface = -1, hitTriangle = -1;
	for (int s = 0; s < list->surfaceCount; ++s)
	{
		const fvSurface* surface = &list->surfaces[s];
		for (int k = 0; k < surface->triangleCount; ++k)
		{
			const int* t = surface->indices + 3 * k;
			float distance =
			    fvRayTriangle(origin, direction, surface->positions + 3 * t[0],
			                  surface->positions + 3 * t[1], surface->positions + 3 * t[2]);
			if (distance > 0.0f && distance < nearest)
				nearest = distance, hitSurface = s, hitTriangle = k;
		}
	}
	if (hitSurface < 0)
		return false;
	pick->surface = hitSurface;
	pick->distance = nearest;
	for (int i = 0; i < 3; ++i)
		pick->point[i] = origin[i] + nearest * direction[i];
	fvClosestCorner(&list->surfaces[hitSurface], hitTriangle, pick->point, pick);
	return true;
}
