// Floor contact for explicit integration: vertex-plane, y = height, normal +y.
//
// Depenetration is limited (as PhysX's max depenetration velocity): a vertex found below the
// floor is lifted by at most max(maxDepenetrationSpeed, its own approach speed) * dt a step,
// and the push-out raises its normal velocity to at most maxDepenetrationSpeed. Penetration
// that the step's own motion explains is removed at once, exactly as in the seeds; a body that
// starts (or is dragged) deep below the floor rises at the limit instead of being catapulted.
// The positive work of every push-out goes to the body's energy ledger.
#include "integrator.h"

#include <math.h>

// Lift vertex @p i out of the floor by at most the depenetration limit; returns the work done
// against gravity (J).
static double fmLiftOutOfFloor(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, int i, double dt)
{
	double* x = b->x + 3 * i;
	double penetration = floor->height - x[1];
	double reach = fmax(floor->maxDepenetrationSpeed, -b->v[3 * i + 1]) * dt;
	double lift = penetration <= reach ? penetration : reach;
	x[1] = penetration <= reach ? floor->height : x[1] + lift;
	return -b->mass[i] * gravity.y * lift;
}

int fmApplyFloor(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, double dt)
{
	if (!floor->enabled)
		return 0;
	const double h = floor->height;
	const double pushLimit = floor->maxDepenetrationSpeed;
	int contacts = 0;
	double work = 0.0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double* x = b->x + 3 * i;
		double* v = b->v + 3 * i;
		if ((b->pinned[i] & FM_PIN_Y) || x[1] >= h) // a vertex held in y does not touch
			continue;
		++contacts;
		double penetration = h - x[1], vIn = v[1];
		work += fmLiftOutOfFloor(floor, gravity, b, i, dt);
		if (floor->friction == fm_floorStick)
		{
			// GAMES103 HW3 1.1: tangential velocity zeroed; the penetration depth is turned into
			// an upward velocity (it pushes the vertex out over the next step), up to the limit.
			v[0] = 0.0;
			v[2] = 0.0;
			v[1] = fmin(vIn + penetration / dt, fmax(vIn, pushLimit));
			work += 0.5 * b->mass[i] * fmax(0.0, v[1] * v[1] - vIn * vIn);
			continue;
		}
		// Coulomb: reflect the approaching normal velocity with restitution e; the normal
		// velocity change dvn bounds the tangential change by mu * dvn (friction cone).
		double vn = v[1];
		if (vn >= 0.0)
			continue;
		double dvn = -(1.0 + floor->restitution) * vn;
		v[1] = -floor->restitution * vn;
		double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
		double scale = vt > 0.0 ? fmax(0.0, 1.0 - floor->frictionCoefficient * dvn / vt) : 0.0;
		v[0] *= scale;
		v[2] *= scale;
	}
	fmLedger_AddContactWork(b, work);
	return contacts;
}
