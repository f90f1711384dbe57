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

static void fvDrawTriangles(const fmDrawTriangles* t, void* context)
{
	fvDrawList* list = context;
	int oldCapacity = list->surfaceCapacity;
	if (t->vertexCount < 0 || t->triangleCount < 0 || t->vertexCount > INT32_MAX / 3 ||
	    t->triangleCount > INT32_MAX / 3 ||
	    !fvReserve((void**)&list->surfaces, &list->surfaceCapacity, list->surfaceCount + 1,
	               sizeof(fvSurface)))
	{
		list->outOfMemory = true;
		return;
	}
	for (int i = oldCapacity; i < list->surfaceCapacity; ++i)
		memset(&list->surfaces[i], 0, sizeof list->surfaces[i]);
	fvSurface* s = &list->surfaces[list->surfaceCount];
	if (!fvSurface_Reserve(s, t->vertexCount, t->triangleCount))
	{
		list->outOfMemory = true;
		return;
	}
	size_t n = 3 * (size_t)t->vertexCount;
	s->body = t->body;
	s->vertexCount = t->vertexCount;
	s->triangleCount = t->triangleCount;
	memcpy(s->positions, t->positions, n * sizeof(float));
	memcpy(s->normals, t->normals, n * sizeof(float));
	memcpy(s->vertices, t->vertices, (size_t)t->vertexCount * sizeof(int));
	memcpy(s->indices, t->indices, 3 * (size_t)t->triangleCount * sizeof(int));
	if (t->colors != NULL)
		memcpy(s->colors, t->colors, n * sizeof(float));
	else
	{
		float rgb[3];
		fvHexToRgb(t->color, rgb);
		for (size_t i = 0; i < n; ++i)
			s->colors[i] = rgb[i % 3];
	}
	list->surfaceCount += 1;
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

static void fvDrawPlane(fmVec3 point, fmVec3 normal, fmHexColor color, void* context)
{
	fvDrawList* list = context;
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
		for (int i = 0; i < list->surfaces[s].vertexCount; ++i)
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
