// Explicit integration, as the seeds: symplectic Euler with a velocity damping factor and
// Laplacian velocity smoothing (GAMES103 HW3 1.1 and 1.4), then the floor.
#include "core.h"
#include "forces.h"
#include "integrator.h"

#include <string.h>

// v <- (1 - s) v + s * (average velocity of the tets around each vertex), the GAMES103 Smooth_V:
// every tet adds the sum of its 4 velocities to each of its vertices, divided by 4 * tets around.
static void fmSmoothVelocities(fmBody* b, double blend)
{
	double* sum = b->scratch;
	memset(sum, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	for (int t = 0; t < b->tetCount; ++t)
	{
		const int* n = b->tets + 4 * t;
		fmVec3 s = fmAdd(fmAdd(fmLoad(b->v, n[0]), fmLoad(b->v, n[1])),
						 fmAdd(fmLoad(b->v, n[2]), fmLoad(b->v, n[3])));
		for (int a = 0; a < 4; ++a)
			fmStore(sum, n[a], fmAdd(fmLoad(sum, n[a]), s));
	}
	for (int i = 0; i < b->vertexCount; ++i)
	{
		if (b->pinned[i] == FM_PIN_ALL)
			continue;
		fmVec3 average = fmScale(b->smoothWeight[i], fmLoad(sum, i));
		fmStore(b->v, i, fmAdd(fmScale(1.0 - blend, fmLoad(b->v, i)), fmScale(blend, average)));
		fmZeroPinnedAxes(b, i, b->v + 3 * i);
	}
}

// Rayleigh damping force -(alpha M + beta K) v, with K the (unprojected) stiffness at x.
static void fmAddRayleighForces(fmBody* b)
{
	if (b->rayleighMass > 0.0)
		for (int k = 0; k < 3 * b->vertexCount; ++k)
			b->f[k] -= b->rayleighMass * b->mass[k / 3] * b->v[k];
	if (b->rayleighStiffness > 0.0)
	{
		double* kv = b->scratch;
		memset(kv, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
		fmAddHessianProduct(b, b->x, b->v, kv, 0);
		for (int k = 0; k < 3 * b->vertexCount; ++k)
			b->f[k] -= b->rayleighStiffness * kv[k];
	}
}

fmResult fmExplicitStep(const fmWorld* world, fmBody* b, double dt)
{
	const int n = b->vertexCount;

	// 1. Gravity and elastic forces.
	for (int i = 0; i < n; ++i)
		fmStore(b->f, i, fmScale(b->mass[i], world->def.gravity));
	fmAddElasticForces(b, b->x, b->f);
	if (b->forceModel == fm_massSpring)
		fmAddSpringDamping(b, b->x, b->v, b->f);
	fmAddRayleighForces(b);

	// 2. Velocities: v = (v + dt f / m) * damping. Pinned vertices stay at rest.
	for (int i = 0; i < n; ++i)
	{
		if (b->pinned[i] == FM_PIN_ALL)
			continue;
		fmVec3 v = fmMulAdd(fmLoad(b->v, i), dt * b->invMass[i], fmLoad(b->f, i));
		fmStore(b->v, i, fmScale(b->damping, v));
		fmZeroPinnedAxes(b, i, b->v + 3 * i); // rollers: free only along their open axes
	}

	// 3. Laplacian smoothing of the velocities against high-frequency oscillation.
	if (b->smoothing > 0.0)
		fmSmoothVelocities(b, b->smoothing);

	// 4. Positions, then the floor.
	for (int i = 0; i < n; ++i)
		if (b->pinned[i] != FM_PIN_ALL)
			fmStore(b->x, i, fmMulAdd(fmLoad(b->x, i), dt, fmLoad(b->v, i)));
	fmApplyFloor(&world->def.floor, b, dt);
	return fm_ok;
}
