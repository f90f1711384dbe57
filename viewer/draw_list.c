// The fmDebugDraw callbacks of the viewer (draw_list.h): copy the library's batches, which are
// valid during the callback only, into arrays the list owns.
#include "draw_list.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void fvHexToRgb(fmHexColor color, float rgb[3])
{
	rgb[0] = (float)((color >> 16) & 0xffu) / 255.0f;
	rgb[1] = (float)((color >> 8) & 0xffu) / 255.0f;
	rgb[2] = (float)(color & 0xffu) / 255.0f;
}

void fvDrawList_Init(fvDrawList* list)
{
	memset(list, 0, sizeof *list);
}

void fvDrawList_Clear(fvDrawList* list)
{
	list->surfaceCount = 0;
	list->lineVertexCount = 0;
	list->pointCount = 0;
	list->hasPlane = false;
	list->outOfMemory = false;
}

static void fvSurface_Free(fvSurface* s)
{
	free(s->positions);
	free(s->normals);
	free(s->colors);
	free(s->indices);
	free(s->vertices);
}

void fvDrawList_Free(fvDrawList* list)
{
	for (int i = 0; i < list->surfaceCapacity; ++i)
		fvSurface_Free(&list->surfaces[i]);
	free(list->surfaces);
	free(list->lines);
	free(list->points);
	fvCreases_Free(&list->creases);
	free(list->cornerFloats);
	free(list->cornerInts);
	memset(list, 0, sizeof *list);
}

// Make room for @p count items of @p itemSize bytes in *array (capacity in items). Grows
// geometrically; false when the size overflows or memory is short (the array is kept).
static bool fvReserve(void** array, int* capacity, int count, size_t itemSize)
{
	if (count <= *capacity)
		return true;
	size_t wanted = (size_t)count + (size_t)count / 2 + 16;
	if (wanted > (size_t)INT32_MAX || wanted > SIZE_MAX / itemSize)
		return false;
	void* grown = realloc(*array, wanted * itemSize);
	if (grown == NULL)
		return false;
	*array = grown;
	*capacity = (int)wanted;
	return true;
}

// Grow one array of @p count items of @p itemSize bytes; false (array kept) when short.
static bool fvGrowArray(void** array, int count, size_t itemSize)
{
	void* grown = realloc(*array, itemSize * (size_t)count);
	if (grown == NULL)
		return false;
	*array = grown;
	return true;
}

static bool fvSurface_Reserve(fvSurface* s, int vertexCount, int triangleCount)
{
	if (vertexCount > s->vertexCapacity)
	{
		size_t vec3 = 3 * sizeof(float);
		if (!fvGrowArray((void**)&s->positions, vertexCount, vec3) ||
		    !fvGrowArray((void**)&s->normals, vertexCount, vec3) ||
		    !fvGrowArray((void**)&s->colors, vertexCount, vec3) ||
		    !fvGrowArray((void**)&s->vertices, vertexCount, sizeof(int)))
			return false;
		s->vertexCapacity = vertexCount;
	}
	if (3 * triangleCount > s->indexCapacity)
	{
		if (!fvGrowArray((void**)&s->indices, 3 * triangleCount, sizeof(int)))
			return false;
		s->indexCapacity = 3 * triangleCount;
	}
	return true;
}

// Colliders are drawn in a neutral grey whatever colour the library suggests: they are the
// scenery, the bodies are the subject.
static const float fvColliderGrey[3] = {0.62f, 0.62f, 0.60f};

// Area-weighted vertex normals of a surface (a collider batch without normals).
static void fvSurfaceNormals(fvSurface* s)
{
	memset(s->normals, 0, 3 * sizeof(float) * (size_t)s->vertexCount);
	for (int k = 0; k < s->triangleCount; ++k)
	{
		const int* t = s->indices + 3 * k;
		const float *a = s->positions + 3 * t[0], *b = s->positions + 3 * t[1],
		            *c = s->positions + 3 * t[2];
		float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
		float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
		float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
		              u[0] * v[1] - u[1] * v[0]};
		for (int corner = 0; corner < 3; ++corner)
			for (int i = 0; i < 3; ++i)
				s->normals[3 * t[corner] + i] += n[i];
	}
	for (int v = 0; v < s->vertexCount; ++v)
	{
		float* n = s->normals + 3 * v;
		float length = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int i = 0; i < 3; ++i)
			n[i] = length > 0.0f ? n[i] / length : (i == 1 ? 1.0f : 0.0f);
	}
}

// A collider's batch: grey, no body vertex numbers, normals computed when it comes without.
static void fvColliderSurface(fvSurface* s, const fmDrawTriangles* t)
{
	for (int i = 0; i < s->vertexCount; ++i)
	{
		s->vertices[i] = t->vertices != NULL ? t->vertices[i] : -1;
		memcpy(s->colors + 3 * i, fvColliderGrey, sizeof fvColliderGrey);
	}
	if (t->normals != NULL)
		memcpy(s->normals, t->normals, 3 * sizeof(float) * (size_t)s->vertexCount);
	else
		fvSurfaceNormals(s);
}

// The next surface of the list, with room for the counts; NULL (outOfMemory set) when short.
static fvSurface* fvNextSurface(fvDrawList* list, int vertexCount, int triangleCount)
{
	int oldCapacity = list->surfaceCapacity;
	if (vertexCount < 0 || triangleCount < 0 || vertexCount > INT32_MAX / 3 ||
	    triangleCount > INT32_MAX / 3 ||
	    !fvReserve((void**)&list->surfaces, &list->surfaceCapacity, list->surfaceCount + 1,
	               sizeof(fvSurface)))
	{
		list->outOfMemory = true;
		return NULL;
	}
	for (int i = oldCapacity; i < list->surfaceCapacity; ++i)
		memset(&list->surfaces[i], 0, sizeof list->surfaces[i]);
	fvSurface* s = &list->surfaces[list->surfaceCount];
	if (!fvSurface_Reserve(s, vertexCount, triangleCount))
	{
		list->outOfMemory = true;
		return NULL;
	}
	s->body = (fmBodyId){0, 0, 0, 0};
	s->collider = (fmColliderId){0, 0, 0, 0};
	s->planeQuad = false;
	s->vertexCount = vertexCount;
	s->triangleCount = triangleCount;
	return s;
}

// A body's surface drawn a vertex per triangle corner, each with its corner normal split at
// creases (FV_CREASE_DEGREES): hard edges stay sharp, curved parts smooth. When memory is short
// the smooth normals stay.
static void fvSplitCreases(fvDrawList* list, fvSurface* s)
{
	int v = s->vertexCount, t = s->triangleCount;
	size_t floats = 9 * (size_t)t + 6 * (size_t)v;
	if (floats > (size_t)INT32_MAX || 3 * (size_t)t > (size_t)INT32_MAX ||
	    !fvReserve((void**)&list->cornerFloats, &list->cornerFloatCapacity, (int)floats,
	               sizeof(float)) ||
	    !fvReserve((void**)&list->cornerInts, &list->cornerIntCapacity, v, sizeof(int)))
		return;
	float* corners = list->cornerFloats;
	float* x = corners + 9 * (size_t)t;
	float* rgb = x + 3 * (size_t)v;
	if (!fvCreases_CornerNormals(&list->creases, s->positions, v, s->indices, t, FV_CREASE_DEGREES,
	                             corners))
		return;
	memcpy(x, s->positions, sizeof(float) * 3 * (size_t)v);
	memcpy(rgb, s->colors, sizeof(float) * 3 * (size_t)v);
	memcpy(list->cornerInts, s->vertices, sizeof(int) * (size_t)v);
	if (!fvSurface_Reserve(s, 3 * t, t))
		return; // (the arrays kept their contents: the smooth surface is drawn)
	for (int k = 0; k < 3 * t; ++k)
	{
		int from = s->indices[k];
		memcpy(s->positions + 3 * k, x + 3 * from, 3 * sizeof(float));
		memcpy(s->colors + 3 * k, rgb + 3 * from, 3 * sizeof(float));
		memcpy(s->normals + 3 * k, corners + 3 * k, 3 * sizeof(float));
		s->vertices[k] = list->cornerInts[from];
		s->indices[k] = k;
	}
	s->vertexCount = 3 * t;
}

// Bodies in distinct colours by their slot, so a pile reads as bodies (the library's colour,
// the warm house, first; the web page's palette after it), a sleeping body dimmed toward grey
// as Box2D draws it.
static void fvBodyColor(const fmDrawTriangles* t, float rgb[3])
{
	static const float others[5][3] = {{0.25f, 0.55f, 0.85f},
	                                   {0.4f, 0.75f, 0.35f},
	                                   {0.85f, 0.75f, 0.3f},
	                                   {0.65f, 0.4f, 0.8f},
	                                   {0.3f, 0.75f, 0.75f}};
	int slot = (int)t->body.index1 - 1, k = slot % 6;
	if (k <= 0)
		fvHexToRgb(t->color, rgb);
	else
		memcpy(rgb, others[k - 1], sizeof others[0]);
	if (fmBody_IsValid(t->body) && !fmBody_IsAwake(t->body))
		for (int i = 0; i < 3; ++i)
			rgb[i] = 0.45f * rgb[i] + 0.55f * 0.55f;
}

// A body with a render mesh (fmBody_SetRenderMesh) is drawn as that mesh: the library's deformed
// render positions and normals, in the body's colour, split at creases as the tets' surface is.
// The stress view keeps the tets' surface, where the strain colours live. False (nothing added)
// when the body has none or it cannot be copied: the tets' surface is drawn instead.
static bool fvDrawRenderMesh(fvDrawList* list, const fmDrawTriangles* t)
{
	if (t->colors != NULL || !fmBody_IsValid(t->body))
		return false;
	int vertexCount = fmBody_GetRenderVertexCount(t->body), triangleCount = 0;
	const int* triangles = fmBody_GetRenderTriangles(t->body, &triangleCount);
	if (vertexCount <= 0 || triangles == NULL || triangleCount <= 0)
		return false;
	fvSurface* s = fvNextSurface(list, vertexCount, triangleCount);
	if (s == NULL || fmBody_CopyRenderPositionsFloat(t->body, s->positions, s->normals,
	                                                 s->vertexCapacity) != fm_ok)
		return false;
	s->body = t->body;
	memcpy(s->indices, triangles, 3 * (size_t)triangleCount * sizeof(int));
	float rgb[3];
	fvBodyColor(t, rgb);
	for (int i = 0; i < vertexCount; ++i)
	{
		memcpy(s->colors + 3 * i, rgb, sizeof rgb);
		s->vertices[i] = -1; // not the body's vertices
	}
	list->surfaceCount += 1;
	fvSplitCreases(list, s);
	return true;
}

static void fvDrawTriangles(const fmDrawTriangles* t, void* context)
{
	fvDrawList* list = context;
	if (t->body.index1 != 0 && fvDrawRenderMesh(list, t))
		return;
	fvSurface* s = fvNextSurface(list, t->vertexCount, t->triangleCount);
	if (s == NULL)
		return;
	size_t n = 3 * (size_t)t->vertexCount;
	s->body = t->body;
	s->collider = t->collider;
	memcpy(s->positions, t->positions, n * sizeof(float));
	memcpy(s->indices, t->indices, 3 * (size_t)t->triangleCount * sizeof(int));
	list->surfaceCount += 1;
	if (t->body.index1 == 0)
	{
		fvColliderSurface(s, t);
		return;
	}
	memcpy(s->normals, t->normals, n * sizeof(float));
	memcpy(s->vertices, t->vertices, (size_t)t->vertexCount * sizeof(int));
	if (t->colors != NULL)
		memcpy(s->colors, t->colors, n * sizeof(float));
	else
	{
		float rgb[3];
		fvBodyColor(t, rgb);
		for (size_t i = 0; i < n; ++i)
			s->colors[i] = rgb[i % 3];
	}
	fvSplitCreases(list, s);
}

static void fvDrawLines(const float* points, int lineCount, fmHexColor color, void* context)
{
	fvDrawList* list = context;
	if (lineCount <= 0)
		return;
	if (lineCount > INT32_MAX / 2 - list->lineVertexCount ||
	    !fvReserve((void**)&list->lines, &list->lineCapacity, list->lineVertexCount + 2 * lineCount,
	               6 * sizeof(float)))
	{
		list->outOfMemory = true;
		return;
	}
	float rgb[3];
	fvHexToRgb(color, rgb);
	float* out = list->lines + 6 * (size_t)list->lineVertexCount;
	for (int i = 0; i < 2 * lineCount; ++i, out += 6)
	{
		memcpy(out, points + 3 * (size_t)i, 3 * sizeof(float));
		memcpy(out + 3, rgb, 3 * sizeof(float));
	}
	list->lineVertexCount += 2 * lineCount;
}

static void fvDrawPoints(const float* points, int pointCount, float size, fmHexColor color,
                         void* context)
{
	fvDrawList* list = context;
	if (pointCount <= 0)
		return;
	if (pointCount > INT32_MAX - list->pointCount ||
	    !fvReserve((void**)&list->points, &list->pointCapacity, list->pointCount + pointCount,
	               7 * sizeof(float)))
	{
		list->outOfMemory = true;
		return;
	}
	float rgb[3];
	fvHexToRgb(color, rgb);
	float* out = list->points + 7 * (size_t)list->pointCount;
	for (int i = 0; i < pointCount; ++i, out += 7)
	{
		memcpy(out, points + 3 * (size_t)i, 3 * sizeof(float));
		memcpy(out + 3, rgb, 3 * sizeof(float));
		out[6] = size;
	}
	list->pointCount += pointCount;
}

// Half the side of the quad a plane collider beyond the first plane is drawn as (m).
#define FV_PLANE_QUAD_HALF 40.0f

// A plane after the first (the floor, or the first plane collider, which the renderer draws
// checkered with the shadows on it): a large grey quad around its point, facing its normal.
static void fvPlaneQuad(fvDrawList* list, fmVec3 point, fmVec3 normal)
{
	fvSurface* s = fvNextSurface(list, 4, 2);
	if (s == NULL)
		return;
	float n[3] = {(float)normal.x, (float)normal.y, (float)normal.z};
	float helper[3] = {fabsf(n[0]) > 0.9f ? 0.0f : 1.0f, 0.0f, fabsf(n[0]) > 0.9f ? 1.0f : 0.0f};
	float u[3] = {helper[1] * n[2] - helper[2] * n[1], helper[2] * n[0] - helper[0] * n[2],
	              helper[0] * n[1] - helper[1] * n[0]};
	float length = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
	for (int i = 0; i < 3; ++i)
		u[i] /= length > 0.0f ? length : 1.0f;
	float v[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
	static const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
	float p[3] = {(float)point.x, (float)point.y, (float)point.z};
	for (int c = 0; c < 4; ++c)
		for (int i = 0; i < 3; ++i)
		{
			s->positions[3 * c + i] =
			    p[i] + FV_PLANE_QUAD_HALF * (corners[c][0] * u[i] + corners[c][1] * v[i]);
			s->normals[3 * c + i] = n[i];
			s->colors[3 * c + i] = fvColliderGrey[i];
		}
	// Counter-clockwise seen from the normal's side: u x v = n.
	static const int quad[6] = {0, 1, 2, 0, 2, 3};
	memcpy(s->indices, quad, sizeof quad);
	for (int c = 0; c < 4; ++c)
		s->vertices[c] = -1;
	s->planeQuad = true;
	list->surfaceCount += 1;
}

static void fvDrawPlane(fmVec3 point, fmVec3 normal, fmHexColor color, void* context)
{
	fvDrawList* list = context;
	if (list->hasPlane)
	{
		fvPlaneQuad(list, point, normal);
		return;
	}
	list->hasPlane = true;
	list->planePoint[0] = (float)point.x;
	list->planePoint[1] = (float)point.y;
	list->planePoint[2] = (float)point.z;
	list->planeNormal[0] = (float)normal.x;
	list->planeNormal[1] = (float)normal.y;
	list->planeNormal[2] = (float)normal.z;
	fvHexToRgb(color, list->planeColor);
}

fmDebugDraw fvDrawList_Callbacks(fvDrawList* list, unsigned flags)
{
	fmDebugDraw draw = fmDefaultDebugDraw();
	draw.drawTriangles = fvDrawTriangles;
	draw.drawLines = fvDrawLines;
	draw.drawPoints = fvDrawPoints;
	draw.drawPlane = fvDrawPlane;
	draw.flags = flags;
	draw.context = list;
	return draw;
}

fmResult fvDrawList_Capture(fvDrawList* list, fmWorldId world, unsigned flags)
{
	fvDrawList_Clear(list);
	fmDebugDraw draw = fvDrawList_Callbacks(list, flags);
	return fmWorld_Draw(world, &draw);
}

static void fvGrow(float lo[3], float hi[3], const float* p)
{
	for (int k = 0; k < 3; ++k)
	{
		lo[k] = fminf(lo[k], p[k]);
		hi[k] = fmaxf(hi[k], p[k]);
	}
}

bool fvDrawList_Bounds(const fvDrawList* list, float lo[3], float hi[3])
{
	for (int k = 0; k < 3; ++k)
	{
		lo[k] = INFINITY;
		hi[k] = -INFINITY;
	}
	for (int s = 0; s < list->surfaceCount; ++s)
		for (int i = 0; i < list->surfaces[s].vertexCount && !list->surfaces[s].planeQuad; ++i)
			fvGrow(lo, hi, list->surfaces[s].positions + 3 * i);
	for (int i = 0; i < list->lineVertexCount; ++i)
		fvGrow(lo, hi, list->lines + 6 * i);
	for (int i = 0; i < list->pointCount; ++i)
		fvGrow(lo, hi, list->points + 7 * i);
	return lo[0] <= hi[0] && isfinite(lo[0]) && isfinite(hi[0]);
}

bool fvDrawList_FramingBox(const fvDrawList* list, float lo[3], float hi[3])
{
	if (!fvDrawList_Bounds(list, lo, hi))
		return false;
	if (!list->hasPlane)
		return true;
	const float* n = list->planeNormal;
	float box[2][3];
	memcpy(box[0], lo, sizeof box[0]);
	memcpy(box[1], hi, sizeof box[1]);
	for (int corner = 0; corner < 8; ++corner)
	{
		float p[3] = {box[corner & 1][0], box[(corner >> 1) & 1][1], box[(corner >> 2) & 1][2]};
		float height = 0.0f;
		for (int i = 0; i < 3; ++i)
			height += (p[i] - list->planePoint[i]) * n[i];
		for (int i = 0; i < 3; ++i)
			fvGrow(lo, hi,
			       (float[3]){p[0] - height * n[0], p[1] - height * n[1], p[2] - height * n[2]});
	}
	return true;
}
