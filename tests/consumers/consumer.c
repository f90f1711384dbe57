// A program that uses femto as a project outside it would (scripts/check-consumers.sh builds it
// three ways: find_package after cmake --install, pkg-config, add_subdirectory): a box body in a
// world, stepped for half a second; it must have fallen as free fall says, and a Gmsh mesh given
// as text must load through the installed headers.
#include <femto/femto.h>

#include <stdio.h>
#include <string.h>

static const char s_msh[] = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n"
                            "1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                            "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";

int main(void)
{
	fmVersion version = fmGetVersion();
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadMeshFromMemory(s_msh, strlen(s_msh), "tet.msh", fm_meshFormatGmsh, &mesh, &diag) !=
	        fm_ok ||
	    mesh.tetCount != 1)
	{
		fprintf(stderr, "consumer: the Gmsh text did not load: %s\n", diag.message);
		return 1;
	}
	fmFreeTetMesh(&mesh);
	if (fmMakeBoxMesh(2, 2, 2, fmMakeVec3(-0.5, 1.0, -0.5), fmMakeVec3(0.5, 2.0, 0.5), &mesh) !=
	    fm_ok)
		return 1;
	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.floor.height = -10.0;
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef bodyDef = fmDefaultBodyDef();
	bodyDef.mesh = &mesh;
	fmBodyId body;
	if (fmCreateBody(world, &bodyDef, &body, &diag) != fm_ok)
	{
		fprintf(stderr, "consumer: %s\n", diag.message);
		return 1;
	}
	fmFreeTetMesh(&mesh);
	double before = fmBody_GetStats(body).centerOfMass.y;
	for (int frame = 0; frame < 25; ++frame) // 0.5 s in frames of 10 x 2 ms
		if (fmWorld_Step(world, 0.02, 10) != fm_ok)
			return 1;
	double after = fmBody_GetStats(body).centerOfMass.y;
	fmDestroyWorld(world);
	// Free fall: 0.5 g t^2 = 1.23 m; the default body's damping takes some of it.
	double fell = before - after;
	printf("femto %d.%d.%d: the box fell %.3f m in 0.5 s\n", version.major, version.minor,
	       version.patch, fell);
	return fell > 1.0 && fell < 1.23 ? 0 : 1;
}
