// Corner normals split at creases (creases.h): each triangle's normal, the triangles around each
// vertex (a counting sort), and per corner the mean over the neighbours within the angle.
#include "creases.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool fvCreasesReserve(fvCreases* c, int vertexCount, int triangleCount)
{
	if (triangleCount > c->faceCapacity)
	{
		float* faces = realloc(c->faces, sizeof(float) * 3 * (size_t)triangleCount);
		if (faces != NULL)
			c->faces = faces;
		int* around = realloc(c->around, sizeof(int) * 3 * (size_t)triangleCount);
		if (around != NULL)
			c->around = around;
		if (faces == NULL || around == NULL)
			return false;
		c->faceCapacity = triangleCount;
	}
	if (vertexCount + 1 > c->vertexCapacity)
	{
		int* start = realloc(c->start, sizeof(int) * ((size_t)vertexCount + 1));
		if (start == NULL)
			return false;
		c->start = start;
		c->vertexCapacity = vertexCount + 1;
	}
	return true;
}

// Every triangle's area-weighted normal, and the triangles around every vertex.
static void fvCreasesPrepare(fvCreases* c, const float* x, int vertexCount, const int* indices,
                             int triangleCount)
{
	memset(c->start, 0, sizeof(int) * ((size_t)vertexCount + 1));
	for (int t = 0; t < triangleCount; ++t)
	{
		const int* v = indices + 3 * t;
		const float *a = x + 3 * v[0], *b = x + 3 * v[1], *d = x + 3 * v[2];
		float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
		float w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
		float* n = c->faces + 3 * t;
		n[0] = u[1] * w[2] - u[2] * w[1];
		n[1] = u[2] * w[0] - u[0] * w[2];
		n[2] = u[0] * w[1] - u[1] * w[0];
		for (int k = 0; k < 3; ++k)
			c->start[v[k] + 1] += 1;
	}
	for (int v = 0; v < vertexCount; ++v)
		c->start[v + 1] += c->start[v];
	for (int t = 0; t < triangleCount; ++t)
		for (int k = 0; k < 3; ++k)
			c->around[c->start[indices[3 * t + k]]++] = t;
	for (int v = vertexCount; v > 0; --v) // each start moved to the next one's: back
		c->start[v] = c->start[v - 1];
	c->start[0] = 0;
}

static float fvLength(const float n[3])
{
	return sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

bool fvCreases_CornerNormals(fvCreases* c, const float* positions, int vertexCount,
                             const int* indices, int triangleCount, float degrees, float* corners)
{
	if (vertexCount < 0 || triangleCount < 0 || !fvCreasesReserve(c, vertexCount, triangleCount))
		return false;
	fvCreasesPrepare(c, positions, vertexCount, indices, triangleCount);
	float limit = cosf(degrees * 3.14159265f / 180.0f);
	for (int t = 0; t < triangleCount; ++t)
	{
		const float* own = c->faces + 3 * t;
		float ownLength = fvLength(own);
		for (int k = 0; k < 3; ++k)
		{
			int v = indices[3 * t + k];
			float sum[3] = {0.0f, 0.0f, 0.0f};
			for (int e = c->start[v]; e < c->start[v + 1]; ++e)
			{
				const float* n = c->faces + 3 * c->around[e];
				float dot = own[0] * n[0] + own[1] * n[1] + own[2] * n[2];
				if (dot >= limit * ownLength * fvLength(n)) // (the own triangle always counts)
					for (int i = 0; i < 3; ++i)
						sum[i] += n[i];
			}
			float length = fvLength(sum);
			float* out = corners + 9 * (size_t)t + 3 * (size_t)k;
			for (int i = 0; i < 3; ++i)
				out[i] = length > 0.0f ? sum[i] / length : (i == 1 ? 1.0f : 0.0f);
		}
	}
	return true;
}

void fvCreases_Free(fvCreases* c)
{
	free(c->faces);
	free(c->start);
	free(c->around);
	memset(c, 0, sizeof *c);
}
