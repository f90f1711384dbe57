// The floor, y = height with normal +y: its one home. Explicit steps get a position and velocity
// response after the step; implicit steps get per-vertex bounds inside the Newton solve and a
// velocity response after it. Both limit depenetration and book the floor's work in the body's
// energy ledger. (When colliders arrive the floor becomes one of them.)
//
// Depenetration is limited (as PhysX's max depenetration velocity): a vertex found below the
// floor rises by at most maxDepenetrationSpeed * dt a step (beyond undoing the step's own
// downward motion), and the push-out raises its normal velocity to at most that speed.
// Penetration that the step's own motion explains is removed at once, exactly as in the seeds;
// a body that starts (or is dragged) deep below the floor rises at the limit instead of being
// catapulted.
#include "floor.h"

#include <math.h>

// ---- explicit ---------------------------------------------------------------------------------

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

int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, double dt)
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

// ---- implicit ---------------------------------------------------------------------------------

// Floor response on velocities after the solve, for vertices resting on the floor. The solve
// already stopped them at the floor (perfectly inelastic positions); here the approach velocity
// is removed (or reflected by the restitution), and friction acts on the tangential velocity:
// stick zeroes it (the seeds), Coulomb reduces it by at most mu * (normal impulse) / m, the
// normal impulse being the floor's force from the solve times h plus the removed approach.
int fmFloor_ImplicitVelocities(const fmFloorDef* floor, fmBody* b, const fmImplicitCache* c,
                               double h)
{
	int contacts = 0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double* v = b->v + 3 * i;
		if ((b->pinned[i] & FM_PIN_Y) || b->x[3 * i + 1] > c->floorBound[i])
			continue;
		++contacts;
		double impulse = fmax(0.0, c->gradient[3 * i + 1]) * h; // N s, the floor's push
		if (v[1] < 0.0)
		{
			double e = floor->friction == fm_floorCoulomb ? floor->restitution : 0.0;
			impulse += (1.0 + e) * b->mass[i] * -v[1];
			v[1] = -e * v[1];
		}
		if (floor->friction == fm_floorStick)
		{
			v[0] = 0.0;
			v[2] = 0.0;
			continue;
		}
		double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
		double keep =
		    vt > 0.0 ? fmax(0.0, 1.0 - floor->frictionCoefficient * impulse / (b->mass[i] * vt))
		             : 0.0;
		v[0] *= keep;
		v[2] *= keep;
	}
	return contacts;
}

// Lowest y of every vertex this step: the floor, except for a vertex deep below it, which may
// rise by at most the depenetration speed times h (a body that starts below the floor is lifted
// out, not catapulted; docs/robustness.md).
void fmFloor_SetBounds(const fmFloorDef* floor, const fmBody* b, fmImplicitCache* c, double h)
{
	for (int i = 0; i < b->vertexCount; ++i)
		c->floorBound[i] =
		    fmin(floor->height, c->xStart[3 * i + 1] + floor->maxDepenetrationSpeed * h);
}

// Work the floor did on the body in the step (J), for the energy ledger: its push (the energy
// gradient it holds back) times the lift, on the vertices it lifts out from below its plane (at
// most the depenetration speed times h each). Stopping a vertex that comes from above is an
// inelastic impact: no work is booked for it.
double fmFloor_ImplicitWork(const fmBody* b, const fmImplicitCache* c, double floorHeight)
{
	double work = 0.0;
	for (int i = 0; i < b->vertexCount; ++i)
		if (!(b->pinned[i] & FM_PIN_Y) && c->floorBound[i] < floorHeight &&
		    b->x[3 * i + 1] <= c->floorBound[i])
			work += fmax(0.0, c->gradient[3 * i + 1]) *
			        fmax(0.0, b->x[3 * i + 1] - c->xStart[3 * i + 1]);
	return work;
}

bool fmFloor_Touches(const fmFloorDef* floor, const fmBody* b, int i)
{
	return floor->enabled && b->x[3 * i + 1] <= floor->height + 1e-9;
}

int fmFloor_CountContacts(const fmFloorDef* floor, const fmBody* b)
{
	int contacts = 0;
	for (int i = 0; i < b->vertexCount; ++i)
		contacts += fmFloor_Touches(floor, b, i);
	return contacts;
}
