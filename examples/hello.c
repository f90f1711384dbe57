// hello: load a TetGen mesh, drop it on the floor for two seconds, print where it is.
// Usage: hello MESH.node MESH.ele
#include <femto/femto.h>
#include <stdio.h>

int main(int argc, char** argv)
{
	if (argc < 3)
	{
		fprintf(stderr, "usage: %s MESH.node MESH.ele\n", argv[0]);
		return 2;
	}
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadTetGen(argv[1], argv[2], &mesh, &diag) != fm_ok)
	{
		char text[1024];
		fprintf(stderr, "%s\n", fmDiagnostic_Format(&diag, text, sizeof text));
		return 1;
	}
	fmMeshTransform placement = fmDefaultMeshTransform();
	placement.scale = 0.4;
	placement.center = true;
	placement.swapYZ = true; // the bouncy house is modelled z-up
	fmTetMesh_Transform(&mesh, &placement);

	fmWorldDef worldDef = fmDefaultWorldDef(); // gravity, floor at y = -3
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef bodyDef = fmDefaultBodyDef(); // StVK, lambda 20000, mu 5000, 1 kg per vertex
	bodyDef.mesh = &mesh;
	fmBodyId body;
	if (fmCreateBody(world, &bodyDef, &body, &diag) != fm_ok)
		return 1;
	fmFreeTetMesh(&mesh); // the body keeps its own copy

	for (int frame = 0; frame < 66; ++frame) // 66 frames of 10 x 3 ms
		if (fmWorld_Step(world, 0.03, 10) != fm_ok)
			return 1;
	fmBodyStats stats = fmBody_GetStats(body);
	printf("centre of mass (%.3f, %.3f, %.3f), lowest y %.3f, kinetic energy %.4f J\n",
	       stats.centerOfMass.x, stats.centerOfMass.y, stats.centerOfMass.z, stats.lowestY,
	       stats.kineticEnergy);
	fmDestroyWorld(world);
	return 0;
}
