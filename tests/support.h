// Shared fixtures for the physics tests: the bouncy house and generated boxes as bodies.
#pragma once

#include <femto/femto.h>

// The seeds' house mesh (house2 scaled 0.4, centred, y/z swapped) moved by @p offset.
bool fmTestHouseMesh(fmTetMesh* mesh, fmVec3 offset);

// The seeds' bouncy house: house2 scaled 0.4, centred, y/z swapped, floor y = -3.
// Returns a null body id on failure. @p worldDef / @p bodyDef may be NULL for defaults.
fmBodyId fmTestMakeHouse(fmWorldId* world, const fmWorldDef* worldDef, const fmBodyDef* bodyDef);

// A box body [0,sx]x[0,sy]x[0,sz] in nx*ny*nz cubes; world without gravity and floor.
fmBodyId fmTestMakeBox(fmWorldId* world, int nx, int ny, int nz, fmVec3 size, fmMaterial material,
                       fmForceModel forceModel);

// A world def with no gravity, no floor.
fmWorldDef fmTestFreeWorldDef(void);

// A uniformly distributed random rotation (from a random unit quaternion, by rejection).
fmMat3 fmTestRandomRotation(void);

// Check the body's elastic forces at its current positions against minus the central finite
// difference (step 1e-6) of its elastic energy, every @p stride-th coordinate, within
// @p tolerance times the largest force. Restores the positions. Counts failures like CHECK.
void fmTestCheckForcesAreMinusGradient(int* failures_, fmBodyId body, int stride, double tolerance);

// The body's positions (velocities) read back through fmBody_CopyPositions
// (fmBody_CopyVelocities) into a buffer of the test support: valid until the next call of the
// same function. Exits the test program if the copy fails.
const double* fmTestPositions(fmBodyId body);
const double* fmTestVelocities(fmBodyId body);

// The body's momentum (kg m/s) and mass (kg), summed vertex by vertex.
fmVec3 fmTestMomentum(fmBodyId body);
double fmTestMass(fmBodyId body);

// Move every vertex by uniform noise in [-amplitude, amplitude) per coordinate.
void fmTestPerturb(fmBodyId body, double amplitude);

// A bar [0, length] along x on rollers: every vertex whose rest coordinate @p rest (3 a vertex)
// is 0 on an axis is held on that axis; with @p hold, the end x = length is held on a roller at
// x = length * stretch too (its vertices moved there). The other vertices keep their positions.
void fmTestBarOnRollers(fmBodyId body, const double* rest, double length, double stretch,
                        bool hold);

// Asserts are compiled in (debug builds, or FEMTO_ENABLE_ASSERT): argument errors reach the hook.
#if !defined(NDEBUG) || defined(FEMTO_ENABLE_ASSERT)
#define FM_TEST_ASSERTS_ON 1
#else
#define FM_TEST_ASSERTS_ON 0
#endif

// Route FM_ASSERT to a counter instead of the runner's hook (which counts asserts as failures).
void fmTestRecordAssertsBegin(void);

// Asserts recorded since fmTestRecordAssertsBegin().
int fmTestAssertCount(void);

// Restore the runner's hook; returns the asserts recorded since fmTestRecordAssertsBegin().
int fmTestRecordAssertsEnd(void);

// An argument error was reported: more asserts than @p before where asserts are compiled in,
// none otherwise (release builds only return a safe value).
#define CHECK_ASSERTED_SINCE(before)                                                               \
	do                                                                                             \
	{                                                                                              \
		int n_ = fmTestAssertCount() - (before);                                                   \
		if (FM_TEST_ASSERTS_ON ? n_ < 1 : n_ != 0)                                                 \
			FAIL_AT("expected %s asserts, got %d", FM_TEST_ASSERTS_ON ? ">= 1" : "0", n_);         \
	} while (0)
