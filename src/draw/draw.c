// fmWorld_Draw (draw.h): each body's surface (compacted to its surface vertices, smooth
// normals, strain colours), tet edges, inverted tets, pins, kinematic targets and the contact
// list's points as float arrays for the caller's callbacks, the floor plane and the colliders.
#include "draw/draw.h"
#include "core/det_math.h"

#include "draw/draw_shapes.h"

#include "body/fracture.h"
#include "body/targets.h"
#include "contact/contact_events.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "material/material.h"
#include "material/material_aniso.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Colours of what the library draws (0xRRGGBB).
#define FM_COLOR_BODY 0xd9a066u
#define FM_COLOR_EDGES 0x303030u
#define FM_COLOR_INVERTED 0xff2020u
#define FM_COLOR_PINS 0x2060ffu
#define FM_COLOR_TARGETS 0x20d040u
#define FM_COLOR_GRAB 0xff40c0u
#define FM_COLOR_CONTACTS 0xffd000u
#define FM_COLOR_FLOOR 0x9a9a9au
#define FM_COLOR_COLLIDERS 0x8c9aa8u
#define FM_COLOR_FIBRES 0x40c0ffu

// A contact's line: at most this fraction of the largest body's size (the strongest contact's).
#define FM_DRAW_CONTACT_LINE 0.08

// Point size (pixels) of a grab's ends.
#define FM_DRAW_GRAB_POINT_SIZE 12.0f

// Point sizes (pixels) of pins, targets and contacts.
#define FM_DRAW_POINT_SIZE 6.0f

typedef struct fmDrawCache
{
	int vertexCount;   // surface vertices
	int triangleCount; // surface triangles
	int* vertex;       // vertexCount: the body's index of each drawn vertex
	int* user;         // vertexCount: the user's index of each drawn vertex
	int* indices;      // 3 per triangle, into the drawn vertices
	float* positions;  // 3 per drawn vertex
	float* normals;    // 3 per drawn vertex
	float* colors;     // 3 per drawn vertex
	int edgeCount;     // the tets' unique edges (made on the first wireframe draw)
	int* edges;        // 2 per edge, the body's vertex indices
	float* lines;      // 6 per line
	int lineCapacity;
	float* points;     // 3 per point, one per body vertex at most
	int pointCapacity; // the body's vertices
	int damageTets;    // tets of the damage scratch (made on the first damage draw of a torn body)
	double* damage;    // each tet's damage
} fmDrawCache;

// Release a draw cache; NULL is fine.
static void fmDrawCache_Free(fmDrawCache* c)
{
	if (c == NULL)
		return;
	size_t n = (size_t)c->vertexCount, m = (size_t)c->triangleCount;
	FM_FREE_ARRAY(c->vertex, int, n);
	FM_FREE_ARRAY(c->user, int, n);
	FM_FREE_ARRAY(c->indices, int, 3 * m);
	FM_FREE_ARRAY(c->positions, float, 3 * n);
	FM_FREE_ARRAY(c->normals, float, 3 * n);
	FM_FREE_ARRAY(c->colors, float, 3 * n);
	FM_FREE_ARRAY(c->edges, int, 2 * (size_t)c->edgeCount);
	FM_FREE_ARRAY(c->damage, double, c->damageTets);
	FM_FREE_ARRAY(c->lines, float, 6 * (size_t)c->lineCapacity);
	FM_FREE_ARRAY(c->points, float, 3 * (size_t)c->pointCapacity);
	FM_FREE_ARRAY(c, fmDrawCache, 1);
}

void fmStrainColor(double level, float rgb[3])
{
	static const float ramp[5][3] = {{0.15f, 0.25f, 0.95f},
	                                 {0.1f, 0.8f, 0.9f},
	                                 {0.2f, 0.85f, 0.25f},
	                                 {0.95f, 0.9f, 0.15f},
	                                 {0.95f, 0.15f, 0.1f}};
	double s = 4.0 * fmMin(fmMax(level, 0.0), 1.0);
	int k = s >= 4.0 ? 3 : (int)s;
	float u = (float)(s - k);
	for (int e = 0; e < 3; ++e)
		rgb[e] = (1.0f - u) * ramp[k][e] + u * ramp[k + 1][e];
}

void fmDraw_StrainColor(double strain, float rgb[3])
{
	FM_ASSERT(rgb != NULL);
	if (rgb != NULL)
		fmStrainColor(isfinite(strain) ? strain / FM_DRAW_FULL_STRAIN : 1.0, rgb);
}

// The surface's vertices, compacted in order of first use by the triangles.
static bool fmDrawCacheSurface(const fmBody* b, fmDrawCache* c)
{
	int* map = FM_ALLOC_ARRAY(int, b->mesh.vertexCount);
	if (map == NULL)
		return false;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		map[i] = -1;
	int count = 0;
	for (int k = 0; k < 3 * b->mesh.triangleCount; ++k)
		if (map[b->mesh.surface[k]] < 0)
			map[b->mesh.surface[k]] = count++;
	size_t n = (size_t)count, m = (size_t)b->mesh.triangleCount;
	c->vertexCount = count;
	c->triangleCount = b->mesh.triangleCount;
	c->vertex = FM_ALLOC_ARRAY(int, n);
	c->user = FM_ALLOC_ARRAY(int, n);
	c->indices = FM_ALLOC_ARRAY(int, 3 * m);
	c->positions = FM_ALLOC_ARRAY(float, 3 * n);
	c->normals = FM_ALLOC_ARRAY(float, 3 * n);
	c->colors = FM_ALLOC_ARRAY(float, 3 * n);
	c->points = FM_ALLOC_ARRAY(float, 3 * (size_t)b->mesh.vertexCount);
	c->pointCapacity = b->mesh.vertexCount;
	bool ok =
	    c->vertex && c->user && c->indices && c->positions && c->normals && c->colors && c->points;
	for (int i = 0; ok && i < b->mesh.vertexCount; ++i)
		if (map[i] >= 0)
		{
			c->vertex[map[i]] = i;
			c->user[map[i]] = b->userVertex[i];
		}
	for (int k = 0; ok && k < 3 * b->mesh.triangleCount; ++k)
		c->indices[k] = map[b->mesh.surface[k]];
	FM_FREE_ARRAY(map, int, b->mesh.vertexCount);
	return ok;
}

static void fmReleaseDrawCache(void* cache)
{
	fmDrawCache_Free(cache);
}

static fmDrawCache* fmGetDrawCache(fmBody* b)
{
	if (b->drawCache.data != NULL)
		return b->drawCache.data;
	fmDrawCache* c = FM_ALLOC_ZERO(fmDrawCache, 1);
	if (c == NULL)
		return NULL;
	if (!fmDrawCacheSurface(b, c))
	{
		fmDrawCache_Free(c);
		return NULL;
	}
	fmAttachment_Set(&b->drawCache, c, fmReleaseDrawCache);
	return c;
}

// Positions and area-weighted unit normals of the drawn vertices.
static void fmDrawGeometry(const fmBody* b, fmDrawCache* c)
{
	for (int v = 0; v < c->vertexCount; ++v)
		for (int e = 0; e < 3; ++e)
		{
			c->positions[3 * v + e] = (float)b->state.x[3 * c->vertex[v] + e];
			c->normals[3 * v + e] = 0.0f;
		}
	for (int t = 0; t < c->triangleCount; ++t)
	{
		const int* tri = c->indices + 3 * t;
		const float* p0 = c->positions + 3 * tri[0];
		const float* p1 = c->positions + 3 * tri[1];
		const float* p2 = c->positions + 3 * tri[2];
		float a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
		float d[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
		float n[3] = {a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2],
		              a[0] * d[1] - a[1] * d[0]};
		for (int k = 0; k < 3; ++k)
			for (int e = 0; e < 3; ++e)
				c->normals[3 * tri[k] + e] += n[e];
	}
	for (int v = 0; v < c->vertexCount; ++v)
	{
		float* n = c->normals + 3 * v;
		float length = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		float scale = length > 0.0f ? 1.0f / length : 0.0f;
		for (int e = 0; e < 3; ++e)
			n[e] *= scale;
		if (length == 0.0f)
			n[1] = 1.0f;
	}
}

// Strain colours: each drawn vertex gets the mean equivalent strain sqrt(2 psi / E) of the tets
// around it (psi the strain energy density), on the blue-to-red ramp up to FM_DRAW_FULL_STRAIN.
static void fmDrawStrainColors(const fmBody* b, fmDrawCache* c)
{
	double E = fmYoungsModulus(&b->mesh.material);
	for (int v = 0; v < c->vertexCount; ++v)
	{
		int i = c->vertex[v];
		double sum = 0.0;
		int count = b->mesh.vertexTetStart[i + 1] - b->mesh.vertexTetStart[i];
		for (int k = b->mesh.vertexTetStart[i]; k < b->mesh.vertexTetStart[i + 1]; ++k)
		{
			int t = b->mesh.vertexTets[k] / 4;
			fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
			double psi = fmTetEvaluate(&b->mesh, t, &F, NULL, NULL, false);
			sum += E > 0.0 && psi > 0.0 ? sqrt(2.0 * psi / E) : 0.0;
		}
		double strain = count > 0 ? sum / count : 0.0;
		fmStrainColor(isfinite(strain) ? strain / FM_DRAW_FULL_STRAIN : 1.0, c->colors + 3 * v);
	}
}

// Plastic strain colours: each drawn vertex gets the mean equivalent plastic strain of the tets
// around it (0 for a body that has none) on the same ramp.
static void fmDrawPlasticColors(const fmBody* b, fmDrawCache* c)
{
	for (int v = 0; v < c->vertexCount; ++v)
	{
		int i = c->vertex[v], count = b->mesh.vertexTetStart[i + 1] - b->mesh.vertexTetStart[i];
		double sum = 0.0;
		for (int k = b->mesh.vertexTetStart[i];
		     b->mesh.plasticStrain != NULL && k < b->mesh.vertexTetStart[i + 1]; ++k)
			sum += b->mesh.plasticStrain[b->mesh.vertexTets[k] / 4];
		fmStrainColor(count > 0 ? sum / count / FM_DRAW_FULL_STRAIN : 0.0, c->colors + 3 * v);
	}
}

// Damage colours: each drawn vertex gets the largest damage (traction over strength, 1 tears)
// of the tets around it on the strain ramp (0 for a body that cannot tear).
static void fmDrawDamageColors(const fmBody* b, fmDrawCache* c)
{
	int m = b->mesh.tetCount;
	if (b->cracks != NULL && c->damage == NULL)
	{
		c->damage = FM_ALLOC_ARRAY(double, m);
		c->damageTets = c->damage != NULL ? m : 0;
	}
	bool known = b->cracks != NULL && c->damage != NULL;
	if (known)
		fmFracture_Damage(b, c->damage, NULL);
	for (int v = 0; v < c->vertexCount; ++v)
	{
		int i = c->vertex[v];
		double worst = 0.0;
		for (int k = b->mesh.vertexTetStart[i]; known && k < b->mesh.vertexTetStart[i + 1]; ++k)
			worst = fmMax(worst, c->damage[b->mesh.vertexTets[k] / 4]);
		fmStrainColor(fmMin(worst, 1.0), c->colors + 3 * v);
	}
}

static void fmDrawSurface(fmBody* b, fmBodyId id, fmDrawCache* c, const fmDebugDraw* draw)
{
	fmDrawGeometry(b, c);
	bool stress = (draw->flags & (fm_drawStress | fm_drawPlastic | fm_drawDamage)) != 0;
	if (draw->flags & fm_drawStress)
		fmDrawStrainColors(b, c);
	else if (draw->flags & fm_drawPlastic)
		fmDrawPlasticColors(b, c);
	else if (stress)
		fmDrawDamageColors(b, c);
	fmDrawTriangles batch;
	memset(&batch, 0, sizeof batch);
	batch.body = id;
	batch.vertexCount = c->vertexCount;
	batch.triangleCount = c->triangleCount;
	batch.positions = c->positions;
	batch.normals = c->normals;
	batch.colors = stress ? c->colors : NULL;
	batch.indices = c->indices;
	batch.vertices = c->user;
	batch.color = FM_COLOR_BODY;
	draw->drawTriangles(&batch, draw->context);
}

// Room for @p count lines in the cache.
static bool fmReserveLines(fmDrawCache* c, int count)
{
	if (count <= c->lineCapacity)
		return true;
	float* lines = FM_ALLOC_ARRAY(float, 6 * (size_t)count);
	if (lines == NULL)
		return false;
	FM_FREE_ARRAY(c->lines, float, 6 * (size_t)c->lineCapacity);
	c->lines = lines;
	c->lineCapacity = count;
	return true;
}

// The tets' unique edges: pairs (i < j) from every tet, sorted by (i, j), duplicates dropped.
static int fmCompareEdges(const void* a, const void* b)
{
	const int* p = a;
	const int* q = b;
	return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

static bool fmDrawCacheEdges(const fmBody* b, fmDrawCache* c)
{
	if (c->edges != NULL || b->mesh.tetCount == 0)
		return true;
	size_t all = 6 * (size_t)b->mesh.tetCount;
	int* pairs = FM_ALLOC_ARRAY(int, 2 * all);
	if (pairs == NULL)
		return false;
	static const int corner[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
	for (int t = 0; t < b->mesh.tetCount; ++t)
		for (int e = 0; e < 6; ++e)
		{
			int i = b->mesh.tets[4 * t + corner[e][0]], j = b->mesh.tets[4 * t + corner[e][1]];
			pairs[2 * (6 * (size_t)t + e)] = i < j ? i : j;
			pairs[2 * (6 * (size_t)t + e) + 1] = i < j ? j : i;
		}
	qsort(pairs, all, 2 * sizeof(int), fmCompareEdges);
	int unique = 0;
	for (size_t k = 0; k < all; ++k)
		if (unique == 0 || fmCompareEdges(pairs + 2 * (unique - 1), pairs + 2 * k) != 0)
		{
			pairs[2 * unique] = pairs[2 * k];
			pairs[2 * unique + 1] = pairs[2 * k + 1];
			unique += 1;
		}
	c->edges = FM_ALLOC_ARRAY(int, 2 * (size_t)unique);
	if (c->edges != NULL)
	{
		memcpy(c->edges, pairs, sizeof(int) * 2 * (size_t)unique);
		c->edgeCount = unique;
	}
	FM_FREE_ARRAY(pairs, int, 2 * all);
	return c->edges != NULL;
}

static void fmPutLine(float* line, const double* a, const double* b)
{
	for (int e = 0; e < 3; ++e)
	{
		line[e] = (float)a[e];
		line[3 + e] = (float)b[e];
	}
}

static bool fmDrawTetEdges(const fmBody* b, fmDrawCache* c, const fmDebugDraw* draw)
{
	if (!fmDrawCacheEdges(b, c) || !fmReserveLines(c, c->edgeCount))
		return false;
	for (int k = 0; k < c->edgeCount; ++k)
		fmPutLine(c->lines + 6 * k, b->state.x + 3 * c->edges[2 * k],
		          b->state.x + 3 * c->edges[2 * k + 1]);
	draw->drawLines(c->lines, c->edgeCount, FM_COLOR_EDGES, draw->context);
	return true;
}

// The six edges of every inverted tet (det F <= 0).
static bool fmDrawInverted(const fmBody* b, fmDrawCache* c, const fmDebugDraw* draw)
{
	static const int corner[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
	int inverted = fmBodyCountInverted(b);
	if (inverted == 0)
		return true;
	if (!fmReserveLines(c, 6 * inverted))
		return false;
	int count = 0;
	for (int t = 0; t < b->mesh.tetCount && count < 6 * inverted; ++t)
	{
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t);
		if (fmDet(&F) > 0.0)
			continue;
		for (int e = 0; e < 6; ++e)
			fmPutLine(c->lines + 6 * (count + e),
			          b->state.x + 3 * b->mesh.tets[4 * t + corner[e][0]],
			          b->state.x + 3 * b->mesh.tets[4 * t + corner[e][1]]);
		count += 6;
	}
	draw->drawLines(c->lines, count, FM_COLOR_INVERTED, draw->context);
	return true;
}

// The deformed fibre F a of every anisotropic tet: a line through its centre, half its size
// (the cube root of its rest volume) long at rest, stretching with the fibre.
static bool fmDrawFibres(const fmBody* b, fmDrawCache* c, const fmDebugDraw* draw)
{
	const fmElasticMesh* m = &b->mesh;
	if (!fmReserveLines(c, m->tetCount))
		return false;
	int count = 0;
	for (int t = 0; t < m->tetCount; ++t)
	{
		const fmMaterial* material = fmTetMaterial(m, t);
		if (!fmMaterialModel_IsAnisotropic(material->model))
			continue;
		fmMat3 R = fmMaterial_Axes(material, m->fibres != NULL ? &m->fibres[t] : NULL);
		fmMat3 F = fmTetDeformation(m, b->state.x, t);
		fmVec3 half = fmScale(0.25 * fmMathPow(m->restVolume[t], 1.0 / 3.0),
		                      fmMatVec(&F, fmMakeVec3(R.m[0], R.m[3], R.m[6])));
		fmVec3 centre = {0, 0, 0};
		for (int a = 0; a < 4; ++a)
			centre = fmAdd(centre, fmScale(0.25, fmLoad(b->state.x, m->tets[4 * t + a])));
		double ends[6];
		fmStore(ends, 0, fmSub(centre, half));
		fmStore(ends, 1, fmAdd(centre, half));
		fmPutLine(c->lines + 6 * count++, ends, ends + 3);
	}
	if (count > 0)
		draw->drawLines(c->lines, count, FM_COLOR_FIBRES, draw->context);
	return true;
}

// Points at the pinned vertices.
static void fmDrawPins(const fmBody* b, fmDrawCache* c, const fmDebugDraw* draw)
{
	int count = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (b->state.pinned[i] != 0)
		{
			for (int e = 0; e < 3; ++e)
				c->points[3 * count + e] = (float)b->state.x[3 * i + e];
			count += 1;
		}
	if (count > 0)
		draw->drawPoints(c->points, count, FM_DRAW_POINT_SIZE, FM_COLOR_PINS, draw->context);
}

// Targets and attachments: their positions as points, and a line from each to its vertex.
static bool fmDrawTargets(const fmBody* b, fmDrawCache* c, const fmDebugDraw* draw)
{
	int n = fmTargets_Count(b);
	if (n == 0)
		return true;
	if (!fmReserveLines(c, n))
		return false;
	for (int t = 0; t < n; ++t)
		fmPutLine(c->lines + 6 * t, fmTargets_At(b, t)->position,
		          b->state.x + 3 * fmTargets_At(b, t)->vertex);
	if (draw->drawLines)
		draw->drawLines(c->lines, n, FM_COLOR_TARGETS, draw->context);
	if (draw->drawPoints)
	{
		int count = n < b->mesh.vertexCount ? n : b->mesh.vertexCount;
		for (int t = 0; t < count; ++t)
			for (int e = 0; e < 3; ++e)
				c->points[3 * t + e] = (float)fmTargets_At(b, t)->position[e];
		draw->drawPoints(c->points, count, FM_DRAW_POINT_SIZE, FM_COLOR_TARGETS, draw->context);
	}
	return true;
}

// A grab: the spring from the grabbed patch's point to the pointer's target, and both ends as
// large points, so a drag shows what pulls where (its per-vertex targets alone are short lines
// and small points under the patch).
static void fmDrawGrab(fmBodyId id, const fmDebugDraw* draw)
{
	fmVec3 point, target;
	if (!fmBody_GetGrab(id, &point, &target))
		return;
	const float ends[6] = {(float)point.x,  (float)point.y,  (float)point.z,
	                       (float)target.x, (float)target.y, (float)target.z};
	if (draw->drawLines)
		draw->drawLines(ends, 1, FM_COLOR_GRAB, draw->context);
	if (draw->drawPoints)
		draw->drawPoints(ends, 2, FM_DRAW_GRAB_POINT_SIZE, FM_COLOR_GRAB, draw->context);
}

// Everything the flags ask for of one body; false when a buffer could not be had.
static bool fmDrawBody(fmBody* b, fmBodyId id, const fmDebugDraw* draw)
{
	fmDrawCache* c = fmGetDrawCache(b);
	if (c == NULL)
		return false;
	unsigned flags = draw->flags;
	if ((flags & (fm_drawSurfaces | fm_drawStress | fm_drawPlastic | fm_drawDamage)) &&
	    draw->drawTriangles)
		fmDrawSurface(b, id, c, draw);
	bool ok = true;
	if ((flags & fm_drawTetEdges) && draw->drawLines)
		ok = fmDrawTetEdges(b, c, draw);
	if (ok && (flags & fm_drawInvertedTets) && draw->drawLines)
		ok = fmDrawInverted(b, c, draw);
	if (ok && (flags & fm_drawFibres) && draw->drawLines)
		ok = fmDrawFibres(b, c, draw);
	if ((flags & fm_drawPins) && draw->drawPoints)
		fmDrawPins(b, c, draw);
	if (ok && (flags & fm_drawTargets))
		ok = fmDrawTargets(b, c, draw);
	if (flags & fm_drawTargets)
		fmDrawGrab(id, draw);
	return ok;
}

// The last substep's contacts (the floor, colliders, other bodies) as points.
// The contact points, and from each a line along its normal (from the other thing toward the
// vertex) as long as FM_DRAW_CONTACT_LINE of the largest body's size times its force over the
// frame's largest, at least a fifth of it: where the contacts push, and which push hardest.
static bool fmDrawContactList(fmWorld* w, const fmDebugDraw* draw)
{
	const fmContactPoint* points;
	int count = fmContactEvents_Points(w, &points);
	if (count == 0)
		return true;
	if (count > w->drawPointCapacity)
	{
		float* fresh = FM_ALLOC_ARRAY(float, FM_DRAW_CONTACT_FLOATS*(size_t)count);
		if (fresh == NULL)
			return false;
		FM_FREE_ARRAY(w->drawPoints, float, FM_DRAW_CONTACT_FLOATS*(size_t)w->drawPointCapacity);
		w->drawPoints = fresh;
		w->drawPointCapacity = count;
	}
	double size = 0.0, strongest = 0.0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			size = fmMax(size, w->bodies[i].mesh.restSize);
	for (int k = 0; k < count; ++k)
		strongest = fmMax(strongest, fabs(points[k].impulse));
	float* lines = w->drawPoints + 3 * (size_t)count;
	for (int k = 0; k < count; ++k)
	{
		const fmContactPoint* p = &points[k];
		double share = strongest > 0.0 ? fabs(p->impulse) / strongest : 0.0;
		fmVec3 tip = fmMulAdd(p->point, FM_DRAW_CONTACT_LINE * size * fmMax(share, 0.2), p->normal);
		const float at[9] = {(float)p->point.x, (float)p->point.y, (float)p->point.z,
		                     (float)p->point.x, (float)p->point.y, (float)p->point.z,
		                     (float)tip.x,      (float)tip.y,      (float)tip.z};
		memcpy(w->drawPoints + 3 * k, at, 3 * sizeof(float));
		memcpy(lines + 6 * k, at + 3, 6 * sizeof(float));
	}
	draw->drawPoints(w->drawPoints, count, FM_DRAW_POINT_SIZE, FM_COLOR_CONTACTS, draw->context);
	if (draw->drawLines != NULL)
		draw->drawLines(lines, count, FM_COLOR_CONTACTS, draw->context);
	return true;
}

static void fmReleaseShapeBuffer(void* buffer)
{
	fmShapeBuffer_Free(buffer);
	FM_FREE_ARRAY(buffer, fmShapeBuffer, 1);
}

// Every collider: planes through drawPlane, the other shapes' triangles through drawTriangles.
static bool fmDrawColliders(fmWorld* w, const fmDebugDraw* draw)
{
	if (w->drawShape.data == NULL)
		fmAttachment_Set(&w->drawShape, FM_ALLOC_ZERO(fmShapeBuffer, 1), fmReleaseShapeBuffer);
	fmShapeBuffer* shape = w->drawShape.data;
	if (shape == NULL)
		return false;
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		const fmCollider* c = &w->colliders[k];
		if (!c->inUse)
			continue;
		if (c->def.shape == fm_shapePlane)
		{
			if (draw->drawPlane)
				draw->drawPlane(c->position, fmMatVec(&c->rotation, c->localNormal),
				                FM_COLOR_COLLIDERS, draw->context);
			continue;
		}
		if (draw->drawTriangles == NULL)
			continue;
		if (!fmShapeBuffer_Fill(shape, c))
			return false;
		fmDrawTriangles batch;
		memset(&batch, 0, sizeof batch);
		batch.collider = fmWorldColliderId(w, k);
		batch.vertexCount = shape->vertexCount;
		batch.triangleCount = shape->triangleCount;
		batch.positions = shape->positions;
		batch.normals = shape->normals;
		batch.indices = shape->indices;
		batch.color = FM_COLOR_COLLIDERS;
		draw->drawTriangles(&batch, draw->context);
	}
	return true;
}

fmDebugDraw fmDefaultDebugDraw(void)
{
	fmDebugDraw draw;
	memset(&draw, 0, sizeof draw);
	draw.flags = fm_drawSurfaces | fm_drawFloor | fm_drawTargets | fm_drawColliders;
	return draw;
}

static fmResult fmWorldDrawIn(fmWorldId worldId, const fmDebugDraw* draw)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && draw != NULL);
	if (w == NULL)
		return fm_errInvalidId;
	if (draw == NULL)
		return fm_errParameter;
	if ((draw->flags & fm_drawFloor) && draw->drawPlane && w->def.floor.enabled)
		draw->drawPlane(fmMakeVec3(0.0, w->def.floor.height, 0.0), fmMakeVec3(0.0, 1.0, 0.0),
		                FM_COLOR_FLOOR, draw->context);
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		fmBodyId id = fmWorldBodyId(w, i);
		if (!fmDrawBody(b, id, draw))
			return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
			                   "fmWorld_Draw: out of memory for body %d's draw buffers", i);
	}
	if ((draw->flags & fm_drawColliders) && !fmDrawColliders(w, draw))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmWorld_Draw: out of memory for the collider triangles");
	if ((draw->flags & fm_drawContacts) && draw->drawPoints && !fmDrawContactList(w, draw))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "fmWorld_Draw: out of memory for the contact points");
	return fm_ok;
}

fmResult fmWorld_Draw(fmWorldId worldId, const fmDebugDraw* draw)
{
	fmWorld* w = fmGetWorld(worldId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	fmResult r = fmWorldDrawIn(worldId, draw);
	fmFpEnv_Leave(&env);
	return r;
}
