#include "support.h"

#include <stddef.h>

fmWorldDef fmTestFreeWorldDef(void)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.gravity = fmMakeVec3(0, 0, 0);
	def.floor.enabled = false;
	return def;
}

fmBodyId fmTestMakeHouse(fmWorldId* world, const fmWorldDef* worldDef, const fmBodyDef* bodyDef)
{
	fmBodyId none = {0, 0, 0};
	fmTetMesh mesh;
	if (fmLoadTetGen(FEMTO_MESH_DIR "/house2.node", FEMTO_MESH_DIR "/house2.ele", &mesh, NULL) != fm_ok)
		return none;
	fmMeshTransform placement = fmDefaultMeshTransform();
	placement.scale = 0.4;
	placement.center = true;
	placement.swapYZ = true;
	fmTetMesh_Transform(&mesh, &placement);
	fmWorldDef wdef = worldDef ? *worldDef : fmDefaultWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef bdef = bodyDef ? *bodyDef : fmDefaultBodyDef();
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

fmBodyId fmTestMakeBox(fmWorldId* world, int nx, int ny, int nz, fmVec3 size, fmMaterial material,
					   fmForceModel forceModel)
{
	fmBodyId none = {0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(nx, ny, nz, fmMakeVec3(0, 0, 0), size, &mesh) != fm_ok)
		return none;
	fmWorldDef wdef = fmTestFreeWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = material;
	bdef.forceModel = forceModel;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.damping = 1.0;
	bdef.smoothing = 0.0;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}
