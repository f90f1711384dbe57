// gmsh_render_mesh: a Gmsh mesh simulated, a smooth high-resolution surface drawn. The tets come
// from a .msh file (fmLoadMesh reads Gmsh, VTK, Medit and TetGen files by extension); the render
// mesh, a sphere of 2562 vertices inside the cube (or any OBJ given as the second argument,
// fmLoadObj), rides on the tets by barycentric coordinates (fmBody_SetRenderMesh) and is read
// back each frame as floats with normals, ready for a GPU vertex buffer. Checks that the sphere
// fell with the cube and stayed inside it.
// Usage: gmsh_render_mesh MESH.msh [RENDER.obj]
#include <femto/femto.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

// A sphere of radius @p r about @p c: an icosahedron subdivided 4 times (2562 vertices, 5120
// triangles), every vertex pushed onto the sphere. Counter-clockwise seen from outside.
static void makeSphere(fmVec3 c, double r, fmSurfaceMesh* s)
{
	enum
	{
		levels = 4,
		maxVertices = 2562,
		maxTriangles = 5120
	};
	double* x = malloc(sizeof(double) * 3 * maxVertices);
	int* t = malloc(sizeof(int) * 3 * maxTriangles);
	int* next = malloc(sizeof(int) * 3 * maxTriangles);
	const double g = (1.0 + sqrt(5.0)) / 2.0;
	const double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
	                         {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
	                         {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
	const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
	                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
	                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
	                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
	int n = 12, m = 20;
	for (int i = 0; i < 12; ++i)
		for (int k = 0; k < 3; ++k)
			x[3 * i + k] = v[i][k];
	for (int i = 0; i < 60; ++i)
		t[i] = f[i / 3][i % 3];
	for (int level = 0; level < levels; ++level)
	{
		// Split each triangle in four; an edge's midpoint is shared by finding it among those
		// made so far (quadratic, but a few thousand vertices is nothing).
		int m2 = 0;
		for (int tri = 0; tri < m; ++tri)
		{
			int mid[3];
			for (int e = 0; e < 3; ++e)
			{
				int a = t[3 * tri + e], b = t[3 * tri + (e + 1) % 3];
				double p[3];
				for (int k = 0; k < 3; ++k)
					p[k] = 0.5 * (x[3 * a + k] + x[3 * b + k]);
				mid[e] = -1;
				for (int i = 12; i < n && mid[e] < 0; ++i)
					if (x[3 * i] == p[0] && x[3 * i + 1] == p[1] && x[3 * i + 2] == p[2])
						mid[e] = i;
				if (mid[e] < 0)
				{
					for (int k = 0; k < 3; ++k)
						x[3 * n + k] = p[k];
					mid[e] = n++;
				}
			}
			int* o = next + 3 * m2;
			int a = t[3 * tri], b = t[3 * tri + 1], cc = t[3 * tri + 2];
			int quads[12] = {a,      mid[0], mid[2], mid[0], b,      mid[1],
			                 mid[2], mid[1], cc,     mid[0], mid[1], mid[2]};
			for (int k = 0; k < 12; ++k)
				o[k] = quads[k];
			m2 += 4;
		}
		for (int k = 0; k < 3 * m2; ++k)
			t[k] = next[k];
		m = m2;
	}
	for (int i = 0; i < n; ++i)
	{
		fmVec3 p = fmLoad(x, i);
		fmStore(x, i, fmMulAdd(c, r / fmLength(p), p));
	}
	free(next);
	s->vertexCount = n;
	s->positions = x;
	s->triangleCount = m;
	s->triangles = t;
}

int main(int argc, char** argv)
{
	if (argc < 2)
	{
		fprintf(stderr, "usage: %s MESH.msh [RENDER.obj]\n", argv[0]);
		return 2;
	}
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadMesh(argv[1], &mesh, &diag) != fm_ok) // by extension: .msh, .vtu, .vtk, .mesh, .node
	{
		char text[1024];
		fprintf(stderr, "%s\n", fmDiagnostic_Format(&diag, text, sizeof text));
		return 1;
	}
	fmSurfaceMesh render;
	bool fromFile = argc > 2;
	if (fromFile && fmLoadObj(argv[2], &render, &diag) != fm_ok)
		return 1;
	if (!fromFile)
		makeSphere(fmMakeVec3(0.5, 0.5, 0.5), 0.45, &render); // inside the unit cube

	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.floor.height = -0.5;
	worldDef.autoSubstep = true; // a frame is split into stable substeps
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef bodyDef = fmDefaultBodyDef();
	bodyDef.mesh = &mesh;
	bodyDef.material = fmMakeMaterial(fm_neoHookean, 5e4, 0.3);
	bodyDef.massMode = fm_massFromDensity;
	bodyDef.density = 200.0; // foam
	fmBodyId body;
	if (fmCreateBody(world, &bodyDef, &body, &diag) != fm_ok)
		return 1;
	fmFreeTetMesh(&mesh);
	// The render mesh is in the tet mesh's frame at rest: bind it once.
	if (fmBody_SetRenderMesh(body, render.positions, render.vertexCount, render.triangles,
	                         render.triangleCount, &diag) != fm_ok)
		return 1;
	int n = fmBody_GetRenderVertexCount(body);
	float* positions = malloc(sizeof(float) * 3 * (size_t)n); // the GPU upload buffers
	float* normals = malloc(sizeof(float) * 3 * (size_t)n);
	double lowest = 0.0;
	for (int frame = 0; frame < 90; ++frame)
	{
		if (fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok)
			return 1;
		// Once a frame after the step: positions and smooth normals for the vertex buffer.
		if (fmBody_CopyRenderPositionsFloat(body, positions, normals, n) != fm_ok)
			return 1;
		lowest = positions[1];
		for (int i = 1; i < n; ++i)
			lowest = positions[3 * i + 1] < lowest ? positions[3 * i + 1] : lowest;
	}
	fmBodyStats stats = fmBody_GetStats(body);
	printf("%d render vertices, %d triangles; body lowest y %.3f m, render mesh lowest y %.3f m\n",
	       n, render.triangleCount, stats.lowestY, lowest);
	free(positions);
	free(normals);
	if (fromFile)
		fmFreeSurfaceMesh(&render);
	else
	{
		free(render.positions);
		free(render.triangles);
	}
	fmDestroyWorld(world);
	// The cube fell 0.5 m onto the floor; the sphere inside it went along, above the floor.
	return fromFile ||
	               (lowest > stats.lowestY && lowest < stats.lowestY + 0.2 && stats.lowestY < -0.45)
	           ? 0
	           : 1;
}
