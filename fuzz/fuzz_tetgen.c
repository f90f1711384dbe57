// Fuzz the TetGen .node/.ele readers and everything a loaded mesh goes through before it is
// simulated (orientation, statistics, surface extraction, body creation).
//
// Input: the .node text, then a line "%%", then the .ele text. Without the separator the input
// is tried as a .node (with a one-tet .ele) and as an .ele (with a four-node .node).
#include <femto/femto.h>

#include <stdint.h>
#include <string.h>

static const char s_node[] = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
static const char s_ele[] = "1 4 0\n1 1 2 3 4\n";

static void fmFuzzMesh(const char* node, size_t nodeSize, const char* ele, size_t eleSize)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadTetGenFromMemory(node, nodeSize, "fuzz.node", ele, eleSize, "fuzz.ele", &mesh, &diag) !=
		fm_ok)
		return;
	fmMeshInfo info;
	fmTetMesh_GetInfo(&mesh, &info);
	int* triangles = NULL;
	int triangleCount = 0;
	if (fmTetMesh_ExtractSurface(&mesh, &triangles, &triangleCount) == fm_ok)
		fmFree(triangles);
	// Bodies only for small meshes: the fuzzer wants many executions per second.
	if (mesh.tetCount <= 2000)
	{
		fmWorldDef worldDef = fmDefaultWorldDef();
		fmWorldId world = fmCreateWorld(&worldDef);
		fmBodyDef bodyDef = fmDefaultBodyDef();
		bodyDef.mesh = &mesh;
		fmBodyId body;
		if (fmCreateBody(world, &bodyDef, &body, &diag) == fm_ok)
			fmWorld_Step(world, 0.003, 1);
		fmDestroyWorld(world);
	}
	fmFreeTetMesh(&mesh);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const char* text = (const char*)data;
	for (size_t i = 0; i + 3 <= size; ++i)
		if (text[i] == '%' && text[i + 1] == '%' && text[i + 2] == '\n' && (i == 0 || text[i - 1] == '\n'))
		{
			fmFuzzMesh(text, i, text + i + 3, size - i - 3);
			return 0;
		}
	fmFuzzMesh(text, size, s_ele, sizeof s_ele - 1);
	fmFuzzMesh(s_node, sizeof s_node - 1, text, size);
	return 0;
}
