// Floor contact for explicit integration: vertex-plane, y = height, normal +y.
//
// Depenetration is limited (as PhysX's max depenetration velocity): a vertex found below the
// floor rises by at most maxDepenetrationSpeed * dt a step (beyond undoing the step's own
// downward motion), and the push-out raises its normal velocity to at most that speed. Penetration
// that the step's own motion explains is removed at once, exactly as in the seeds; a body that
// starts (or is dragged) deep below the floor rises at the limit instead of being catapulted.
// The work of the push-outs (lift against gravity plus the change of normal kinetic energy),
// when positive, goes to the body's energy ledger.
#include "integrator.h"

#include <math.h>

// Lift vertex @p i out of the floor by at most the depenetration limit; returns the work done
// against gravity (J). The step moved the vertex by v dt already: the lift undoes a
// downward move and adds what an upward one lacks of the limit, so that the vertex rises by at most
// max(limit, v) dt in the step.
static double fmLiftOutOfFloor(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, int i, double dt)
{
	double* x = b->x + 3 * i;
	double penetration = floor->height - x[1], vIn = b->v[3 * i + 1];
	double reach = (fmax(floor->maxDepenetrationSpeed, vIn) - vIn) * dt;
	double lift = penetration <= reach ? penetration : reach;
	x[1] = penetration <= reach ? floor->height : x[1] + lift;
	// Work against gravity only: the elastic forces of a body that is blowing up would
	// otherwise book its explosion as work done on it. A deep vertex rises by its velocity
	// (set by the callers below), not by this lift.
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
			work += 0.5 * b->mass[i] * (v[1] * v[1] - vIn * vIn);
			continue;
		}
		// Coulomb: reflect the approaching normal velocity with restitution e; the normal
		// velocity change dvn bounds the tangential change by mu * dvn (friction cone). A vertex
		// still below the floor after its lift moves up at the depenetration speed, as in stick
		// mode, so that the body rises as a whole.
		double vn = v[1];
		double dvn = vn < 0.0 ? -(1.0 + floor->restitution) * vn : 0.0;
		v[1] = vn < 0.0 ? -floor->restitution * vn : vn;
		if (x[1] < h)
			v[1] = fmax(v[1], fmin(penetration / dt, pushLimit));
		work += 0.5 * b->mass[i] * (v[1] * v[1] - vIn * vIn);
		double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
		double scale = vt > 0.0 ? fmax(0.0, 1.0 - floor->frictionCoefficient * dvn / vt) : 0.0;
		v[0] *= scale;
		v[2] *= scale;
	}
	fmLedger_AddContactWork(b, work);
	return contacts;
}
