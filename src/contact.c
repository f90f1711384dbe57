// Floor contact for explicit integration: vertex-plane, y = height, normal +y.
#include "integrator.h"

#include <math.h>

int fmApplyFloor(const fmFloorDef* floor, fmBody* b, double dt)
{
	if (!floor->enabled)
		return 0;
	const double h = floor->height;
	int contacts = 0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		double* x = b->x + 3 * i;
		double* v = b->v + 3 * i;
		if ((b->pinned[i] & FM_PIN_Y) || x[1] >= h) // a vertex held in y does not touch
			continue;
		++contacts;
		if (floor->friction == fm_floorStick)
		{
			// GAMES103 HW3 1.1: tangential velocity zeroed; the penetration depth is turned into
			// an upward velocity (it pushes the vertex out over the next step).
			v[0] = 0.0;
			v[2] = 0.0;
			v[1] += (h - x[1]) / dt;
			x[1] = h;
			continue;
		}
		// Coulomb: reflect the approaching normal velocity with restitution e; the normal
		// velocity change dvn bounds the tangential change by mu * dvn (friction cone).
		x[1] = h;
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
	return contacts;
}
