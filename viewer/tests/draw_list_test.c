// The viewer's draw list with collider batches (fm_drawColliders), fed through its fmDebugDraw
// callbacks as fmWorld_Draw calls them: a collider batch (body null) is grey, has no body
// vertex numbers and gets normals when it comes without; a body batch keeps its colour and
// numbers; the first plane is the floor, later planes become quads left out of the framing.
// Exit status: the number of failed checks.
#include "draw_list.h"

#include <math.h>
#include <stdio.h>

static int s_failures;

#define CHECK(cond)                                                                                \
	do                                                                                             \
	{                                                                                              \
		if (!(cond))                                                                               \
		{                                                                                          \
			fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond);               \
			++s_failures;                                                                          \
		}                                                                                          \
	} while (0)

int main(void)
{
	fvDrawList list;
	fvDrawList_Init(&list);
	fmDebugDraw draw = fvDrawList_Callbacks(&list, fm_drawAll);
	// A ground triangle facing +y (counter-clockwise seen from above), no normals, no numbers.
	static const float ground[9] = {0, 0, 0, 0, 0, 1, 1, 0, 0};
	static const int triangle[3] = {0, 1, 2};
	fmDrawTriangles collider = {{0, 0, 0, 0}, {1, 1, 0, 1}, 3,        1,    ground,
	                            NULL,         NULL,         triangle, NULL, 0xff0000};
	// A body's triangle, red, with its own numbers and normals.
	static const float body[9] = {0, 1, 0, 1, 1, 0, 0, 2, 0};
	static const float normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
	static const int numbers[3] = {7, 8, 9};
	fmDrawTriangles soft = {{1, 1, 0, 1}, {0, 0, 0, 0}, 3,        1,       body,
	                        normals,      NULL,         triangle, numbers, 0xff0000};
	draw.drawTriangles(&collider, draw.context);
	draw.drawTriangles(&soft, draw.context);
	CHECK(list.surfaceCount == 2);
	const fvSurface* c = &list.surfaces[0];
	CHECK(c->body.index1 == 0 && c->collider.index1 == 1);
	CHECK(c->vertices[0] == -1 && c->vertices[2] == -1);
	CHECK(fabsf(c->colors[0] - c->colors[1]) < 0.05f && c->colors[0] > 0.4f && c->colors[0] < 0.8f);
	CHECK(fabsf(c->normals[1] - 1.0f) < 1e-6f && fabsf(c->normals[0]) < 1e-6f);
	const fvSurface* b = &list.surfaces[1];
	CHECK(b->body.index1 == 1 && b->vertices[1] == 8);
	CHECK(b->colors[0] == 1.0f && b->colors[1] == 0.0f && b->normals[2] == 1.0f);
	// The floor, then a plane collider (a wall facing +x at x = 5).
	draw.drawPlane((fmVec3){0, -3, 0}, (fmVec3){0, 1, 0}, 0x808080, draw.context);
	draw.drawPlane((fmVec3){5, 0, 0}, (fmVec3){1, 0, 0}, 0x808080, draw.context);
	CHECK(list.hasPlane && list.planePoint[1] == -3.0f);
	CHECK(list.surfaceCount == 3 && list.surfaces[2].planeQuad);
	const fvSurface* q = &list.surfaces[2];
	float u[3], v[3], n[3];
	for (int i = 0; i < 3; ++i)
	{
		u[i] = q->positions[3 * q->indices[1] + i] - q->positions[3 * q->indices[0] + i];
		v[i] = q->positions[3 * q->indices[2] + i] - q->positions[3 * q->indices[0] + i];
		CHECK(fabsf(q->positions[3 * i] - 5.0f) < 1e-4f); // every corner on the wall
	}
	n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2],
	n[2] = u[0] * v[1] - u[1] * v[0];
	CHECK(n[0] > 0.0f); // wound to face its normal
	float lo[3], hi[3];
	CHECK(fvDrawList_Bounds(&list, lo, hi));
	CHECK(hi[0] <= 1.0f && lo[2] >= 0.0f && hi[1] <= 2.0f); // the 80 m quad is not framed
	fvDrawList_Free(&list);
	printf("%s: %d failed\n", s_failures ? "FAIL" : "ok", s_failures);
	return s_failures;
}
