// Shared fixtures for the physics tests: the bouncy house and generated boxes as bodies.
#pragma once

#include <femto/femto.h>

// The seeds' bouncy house: house2 scaled 0.4, centred, y/z swapped, floor y = -3.
// Returns a null body id on failure. @p worldDef / @p bodyDef may be NULL for defaults.
fmBodyId fmTestMakeHouse(fmWorldId* world, const fmWorldDef* worldDef, const fmBodyDef* bodyDef);

// A box body [0,sx]x[0,sy]x[0,sz] in nx*ny*nz cubes; world without gravity and floor.
fmBodyId fmTestMakeBox(fmWorldId* world, int nx, int ny, int nz, fmVec3 size, fmMaterial material,
					   fmForceModel forceModel);

// A world def with no gravity, no floor.
fmWorldDef fmTestFreeWorldDef(void);
