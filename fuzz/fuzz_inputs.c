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
