// The viewer's draw list with collider batches (fm_drawColliders), fed through its fmDebugDraw
// callbacks as fmWorld_Draw calls them: a collider batch (body null) is grey, has no body
// vertex numbers and gets normals when it comes without; a body batch keeps its colour and
// numbers; the first plane is the floor, later planes become quads left out of the framing; a
// body with a render mesh is drawn as it.
// Exit status: the number of failed checks.
#include "camera.h"
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

// The camera kept above the floor (issue 31: an upward orbit put the eye under it, the floor
// became an opaque ceiling): orbits of every size up and down, from targets above the floor and
// one panned below it, a horizontal floor and a tilted one; the eye ends at least 2% of the
// distance above, and a move that keeps it above is left alone.
static void checkCameraAboveFloor(void)
{
	const float point[3] = {0.0f, -3.0f, 0.0f};
	const float tilt = 0.3f, tilted[3] = {sinf(tilt), cosf(tilt), 0.0f};
	const float up[3] = {0.0f, 1.0f, 0.0f};
	const float* normals[2] = {up, tilted};
	for (int n = 0; n < 2; ++n)
		for (int k = 0; k < 40; ++k)
		{
			fvCamera c = fvCamera_Default();
			c.target[1] = k % 4 == 3 ? -3.5f : -2.0f + 0.1f * (float)k; // once below the floor
			c.distance = 0.5f + 0.5f * (float)k;
			fvCamera_Orbit(&c, 13.0f * (float)k, -25.0f * (float)(k % 9)); // up to 60 degrees up
			fvCamera_KeepAbove(&c, point, normals[n]);
			float eye[3];
			fvCamera_Eye(&c, eye);
			const float* m = normals[n];
			float height = (eye[0] - point[0]) * m[0] + (eye[1] - point[1]) * m[1] +
			               (eye[2] - point[2]) * m[2];
			CHECK(height >= 0.0199f * c.distance);
			CHECK(c.pitch >= -89.0f && c.pitch <= 89.0f);
		}
	fvCamera high = fvCamera_Default(); // 20 degrees down from 10 m: clear already
	fvCamera before = high;
	fvCamera_KeepAbove(&high, point, up);
	CHECK(high.pitch == before.pitch && high.target[1] == before.target[1]);
}

// A body's surface is drawn with normals split at creases: a cube (every edge 90 degrees)
// given smooth vertex normals is drawn a vertex per corner, each with its face's normal; a
// gently folded sheet (10 degrees) keeps one smooth normal per vertex at all its corners.
static void checkCreases(void)
{
	static const float cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
	                               0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
	static const int faces[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
	                              2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
	float smooth[24];
	for (int i = 0; i < 24; ++i)
		smooth[i] = (cube[i] - 0.5f) / sqrtf(0.75f);
	static const int numbers[8] = {0, 1, 2, 3, 4, 5, 6, 7};
	fvDrawList list;
	fvDrawList_Init(&list);
	fmDebugDraw draw = fvDrawList_Callbacks(&list, fm_drawAll);
	fmDrawTriangles box = {{1, 1, 0, 1}, {0, 0, 0, 0}, 8,     12,      cube,
	                       smooth,       NULL,         faces, numbers, 0xff8000};
	draw.drawTriangles(&box, draw.context);
	CHECK(list.surfaceCount == 1 && list.surfaces[0].vertexCount == 36);
	const fvSurface* s = &list.surfaces[0];
	for (int t = 0; t < 12 && s->vertexCount == 36; ++t)
	{
		const float* a = s->positions + 9 * t;
		float u[3] = {a[3] - a[0], a[4] - a[1], a[5] - a[2]},
		      v[3] = {a[6] - a[0], a[7] - a[1], a[8] - a[2]};
		float n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
		              u[0] * v[1] - u[1] * v[0]};
		float length = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int k = 0; k < 3; ++k)
			for (int i = 0; i < 3; ++i)
				CHECK(fabsf(s->normals[9 * t + 3 * k + i] - n[i] / length) < 1e-5f);
		CHECK(s->vertices[3 * t] == faces[3 * t]); // the body's numbers follow the corners
	}
	// A sheet of two triangles folded by 10 degrees along its diagonal: smooth.
	const float fold = 10.0f * 3.14159265f / 180.0f;
	const float sheet[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, sinf(fold) * 0.7071f};
	static const int pair[6] = {0, 1, 2, 0, 2, 3};
	fmDrawTriangles folded = {{1, 1, 0, 1}, {0, 0, 0, 0}, 4,    2,       sheet,
	                          smooth,       NULL,         pair, numbers, 0xff8000};
	fvDrawList_Clear(&list);
	draw.drawTriangles(&folded, draw.context);
	s = &list.surfaces[0];
	CHECK(s->vertexCount == 6);
	for (int i = 0; i < 3 && s->vertexCount == 6; ++i) // vertex 0: corner 0 of both triangles
		CHECK(fabsf(s->normals[i] - s->normals[9 + i]) < 1e-6f);
	// Two bodies the library gives one colour are drawn in two: a pile reads as bodies.
	fmDrawTriangles second = folded;
	second.body = (fmBodyId){2, 1, 0, 1};
	fvDrawList_Clear(&list);
	draw.drawTriangles(&folded, draw.context);
	draw.drawTriangles(&second, draw.context);
	CHECK(list.surfaceCount == 2);
	if (list.surfaceCount == 2)
	{
		const float *a = list.surfaces[0].colors, *b = list.surfaces[1].colors;
		CHECK(fabsf(a[0] - b[0]) + fabsf(a[1] - b[1]) + fabsf(a[2] - b[2]) > 0.3f);
	}
	fvDrawList_Free(&list);
}

// A body with a render mesh is drawn as it (issue 31 item 8): one tet (4 surface triangles)
// carrying an octahedron inside it (8 triangles) is drawn with the octahedron's triangles, at
// the positions fmBody_CopyRenderPositionsFloat gives; the stress view and a cleared render
// mesh draw the tet's surface.
static void checkRenderMesh(void)
{
	double nodes[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	int tet[4] = {0, 1, 2, 3};
	fmTetMesh mesh = {0};
	mesh.nodeCount = 4, mesh.positions = nodes, mesh.tetCount = 1, mesh.tets = tet;
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	fmBodyId body;
	CHECK(fmCreateBody(world, &def, &body, NULL) == fm_ok);
	const double c = 0.2, r = 0.1; // an octahedron around (c, c, c), well inside the tet
	double octahedron[18] = {c + r, c,     c, c - r, c, c,     c, c + r, c,
	                         c,     c - r, c, c,     c, c + r, c, c,     c - r};
	static const int faces[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
	                              2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
	CHECK(fmBody_SetRenderMesh(body, octahedron, 6, faces, 8, NULL) == fm_ok);
	float expected[18];
	CHECK(fmBody_CopyRenderPositionsFloat(body, expected, NULL, 6) == fm_ok);
	fvDrawList list;
	fvDrawList_Init(&list);
	CHECK(fvDrawList_Capture(&list, world, fm_drawSurfaces) == fm_ok);
	CHECK(list.surfaceCount == 1);
	const fvSurface* s = &list.surfaces[0];
	CHECK(s->triangleCount == 8);
	for (int k = 0; k < 3 * s->triangleCount && s->triangleCount == 8; ++k)
		for (int i = 0; i < 3; ++i)
			CHECK(fabsf(s->positions[3 * s->indices[k] + i] - expected[3 * faces[k] + i]) < 1e-6f);
	CHECK(fvDrawList_Capture(&list, world, fm_drawSurfaces | fm_drawStress) == fm_ok);
	CHECK(list.surfaceCount == 1 && list.surfaces[0].triangleCount == 4);
	fmBody_ClearRenderMesh(body);
	CHECK(fvDrawList_Capture(&list, world, fm_drawSurfaces) == fm_ok);
	CHECK(list.surfaceCount == 1 && list.surfaces[0].triangleCount == 4);
	fvDrawList_Free(&list);
	fmDestroyWorld(world);
}

int main(void)
{
	checkCameraAboveFloor();
	checkCreases();
	checkRenderMesh();
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
