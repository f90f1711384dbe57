// two_bodies: body-body contact. A soft cube falls onto another resting on the floor; after two
// seconds it rests on top of it. Checks that neither sank into the other.
// Usage: two_bodies
#include <femto/femto.h>

#include <stdio.h>

static fmBodyId makeCube(fmWorldId world, fmVec3 lo, double size)
{
	fmTetMesh mesh;
	fmBodyId body = {0, 0, 0, 0};
	if (fmMakeBoxMesh(4, 4, 4, lo, fmAdd(lo, fmMakeVec3(size, size, size)), &mesh) != fm_ok)
		return body;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 500.0;
	fmCreateBody(world, &def, &body, NULL);
	fmFreeTetMesh(&mesh);
	return body;
}

int main(void)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	worldDef.floor.height = 0.0;
	worldDef.autoSubstep = true;
	worldDef.contact.bodies = true; // the default, spelled out
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId lower = makeCube(world, fmMakeVec3(0, 0, 0), 0.5);
	fmBodyId upper = makeCube(world, fmMakeVec3(0.1, 0.8, 0.1), 0.3);
	if (!fmBody_IsValid(lower) || !fmBody_IsValid(upper))
		return 1;
	int touching = 0;
	for (int frame = 0; frame < 120; ++frame)
	{
		if (fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok)
			return 1;
		fmContactEvent events[16];
		int count = fmWorld_GetContactEvents(world, events, 16);
		for (int i = 0; i < count && i < 16; ++i)
			if (events[i].begin && events[i].otherBody.index1 != 0)
				touching += 1;
	}
	fmBodyStats a = fmBody_GetStats(lower), b = fmBody_GetStats(upper);
	// The lower cube's top: its highest vertex.
	double x[3 * 125];
	fmBody_CopyPositions(lower, x, 125);
	double top = x[1];
	for (int i = 1; i < 125; ++i)
		top = x[3 * i + 1] > top ? x[3 * i + 1] : top;
	printf("lower cube top %.4f m, upper cube bottom %.4f m, %d body contact began; kinetic "
	       "%.2e J and %.2e J\n",
	       top, b.lowestY, touching, a.kineticEnergy, b.kineticEnergy);
	fmDestroyWorld(world);
	// Resting on it: above its top (within 1 cm: the contact thickness and the cubes' sag), not
	// fallen past it, and still.
	bool ok = touching >= 1 && b.lowestY > top - 0.01 && b.lowestY < top + 0.02 &&
	          a.lowestY > -0.01 && b.kineticEnergy < 0.1;
	return ok ? 0 : 1;
}
