// The fuzz actions: everything a user's file goes through, from parsing to the first step.
#include "fuzz_inputs.h"

#include <femto/femto.h>

static const char s_node[] = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
static const char s_ele[] = "1 4 0\n1 1 2 3 4\n";

// Bodies only for small meshes: the fuzzer wants many executions per second.
static void fmFuzzSimulate(const fmTetMesh* mesh)
{
	if (mesh->tetCount > 2000)
		return;
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef bodyDef = fmDefaultBodyDef();
	bodyDef.mesh = mesh;
	fmBodyId body;
	fmDiagnostic diag;
	if (fmCreateBody(world, &bodyDef, &body, &diag) == fm_ok)
		fmWorld_Step(world, 0.003, 1);
	fmDestroyWorld(world);
}

static void fmFuzzMesh(const char* node, size_t nodeSize, const char* ele, size_t eleSize)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadTetGenFromMemory(node, nodeSize, "fuzz.node", ele, eleSize, "fuzz.ele", &mesh,
	                           &diag) != fm_ok)
		return;
	fmMeshInfo info;
	fmTetMesh_GetInfo(&mesh, &info);
	int* triangles = NULL;
	int triangleCount = 0;
	if (fmTetMesh_ExtractSurface(&mesh, &triangles, &triangleCount) == fm_ok)
		fmFree(triangles);
	fmFuzzSimulate(&mesh);
	fmFreeTetMesh(&mesh);
}

void fmFuzzTetGen(const uint8_t* data, size_t size)
{
	const char* text = (const char*)data;
	for (size_t i = 0; i + 3 <= size; ++i)
		if (text[i] == '%' && text[i + 1] == '%' && text[i + 2] == '\n' &&
		    (i == 0 || text[i - 1] == '\n'))
		{
			fmFuzzMesh(text, i, text + i + 3, size - i - 3);
			return;
		}
	fmFuzzMesh(text, size, s_ele, sizeof s_ele - 1);
	fmFuzzMesh(s_node, sizeof s_node - 1, text, size);
}

void fmFuzzFace(const uint8_t* data, size_t size)
{
	for (int first = 0; first < 2; ++first)
	{
		int* triangles = NULL;
		int count = 0;
		if (fmLoadTetGenFaceFromMemory((const char*)data, size, "fuzz.face", 100, first, &triangles,
		                               &count, NULL) == fm_ok)
			fmFree(triangles);
	}
}

// A small surface as a mesh collider under a one-cube box, stepped once.
static void fmFuzzObjCollider(const fmSurfaceMesh* surface)
{
	if (surface->triangleCount > 2000)
		return;
	fmWorldDef worldDef = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&worldDef);
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = fm_shapeMesh;
	def.vertices = (const fmVec3*)surface->positions; // three doubles a vertex, as fmVec3
	def.vertexCount = surface->vertexCount;
	def.triangles = surface->triangles;
	def.triangleCount = surface->triangleCount;
	fmColliderId collider;
	fmTetMesh box;
	fmBodyId body;
	if (fmCreateCollider(world, &def, &collider, NULL) == fm_ok &&
	    fmMakeBoxMesh(1, 1, 1, fmMakeVec3(0, 0.5, 0), fmMakeVec3(1, 1.5, 1), &box) == fm_ok)
	{
		fmBodyDef bodyDef = fmDefaultBodyDef();
		bodyDef.mesh = &box;
		if (fmCreateBody(world, &bodyDef, &body, NULL) == fm_ok)
			fmWorld_Step(world, 0.003, 1);
		fmFreeTetMesh(&box);
	}
	fmDestroyWorld(world);
}

void fmFuzzObj(const uint8_t* data, size_t size)
{
	fmSurfaceMesh surface;
	fmDiagnostic diag;
	if (fmLoadObjFromMemory((const char*)data, size, "fuzz.obj", &surface, &diag) != fm_ok)
		return;
	for (int k = 0; k < 3 * surface.triangleCount; ++k)
		if (surface.triangles[k] < 0 || surface.triangles[k] >= surface.vertexCount)
			__builtin_trap();
	fmMeshTransform transform = fmDefaultMeshTransform();
	transform.center = true;
	transform.swapYZ = true;
	fmSurfaceMesh_Transform(&surface, &transform);
	fmFuzzObjCollider(&surface);
	fmFreeSurfaceMesh(&surface);
}

static void fmFuzzMeshFormat(fmMeshFormat format, const uint8_t* data, size_t size)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadMeshFromMemory(data, size, "fuzz", format, &mesh, &diag) != fm_ok)
		return;
	fmMeshInfo info;
	fmTetMesh_GetInfo(&mesh, &info);
	int* triangles = NULL;
	int triangleCount = 0;
	if (fmTetMesh_ExtractSurface(&mesh, &triangles, &triangleCount) == fm_ok)
		fmFree(triangles);
	fmFuzzSimulate(&mesh);
	fmFreeTetMesh(&mesh);
}

void fmFuzzGmsh(const uint8_t* data, size_t size)
{
	fmFuzzMeshFormat(fm_meshFormatGmsh, data, size);
}

void fmFuzzVtk(const uint8_t* data, size_t size)
{
	fmFuzzMeshFormat(fm_meshFormatVtk, data, size);
}

void fmFuzzVtu(const uint8_t* data, size_t size)
{
	fmFuzzMeshFormat(fm_meshFormatVtu, data, size);
}

void fmFuzzMedit(const uint8_t* data, size_t size)
{
	fmFuzzMeshFormat(fm_meshFormatMedit, data, size);
}
