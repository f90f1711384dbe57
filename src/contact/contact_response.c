// The contact responses' shared rules (contact_response.h).
#include "contact/contact_response.h"

#include "contact/floor.h"
#include "core/core.h"
#include "core/det_math.h"

#include <math.h>

double fmContactResponse_Impact(fmVec3* relative, fmVec3 n, double e, double mu, double pushed)
{
	double vn = fmDot(*relative, n);
	if (vn >= 0.0 && pushed <= 0.0)
		return 0.0;
	double change = vn < 0.0 ? -(1.0 + e) * vn : 0.0;
	fmVec3 tangent = fmMulAdd(*relative, -vn, n);
	double speed = fmLength(tangent);
	double keep = speed > 0.0 ? fmMax(0.0, 1.0 - mu * (change + pushed) / speed) : 0.0;
	*relative = fmAdd(fmScale(vn < 0.0 ? -e * vn : vn, n), fmScale(keep, tangent));
	return change;
}

double fmContactResponse_CreepStep(const fmWorld* w, fmVec3 dv, fmVec3 n, double limit)
{
	double h = w->contactStep;
	fmVec3 along = fmMulAdd(dv, -fmDot(dv, n), n);
	return h * fmLength(along) <= limit ? h : 0.0;
}

double fmContactResponse_PairCreep(const fmWorld* w, double thickness)
{
	return (w->def.integrator == fm_implicit ? FM_CREEP_FRACTION : FM_PAIR_CREEP_FRACTION) *
	       thickness;
}

double fmContactResponse_Reach(double start, double closing, double thickness, double depen)
{
	double approach = fmMax(0.0, closing);
	if (start >= thickness)
		return approach - (start - thickness);
	return start >= 0.0 ? approach : approach + fmMin(-start, depen);
}

double fmContactResponse_DepenetrationStep(const fmWorld* w)
{
	return w->def.floor.maxDepenetrationSpeed * w->contactStep;
}

void fmContactResponse_KeepPins(fmBody* b, int i, fmVec3 x0)
{
	const double before[3] = {x0.x, x0.y, x0.z};
	for (int e = 0; e < 3; ++e)
		if (fmIsDofPinned(&b->state, 3 * i + e))
		{
			b->state.x[3 * i + e] = before[e];
			b->state.v[3 * i + e] = 0.0;
		}
}

void fmContactResponse_KeepAboveFloor(const fmWorld* w, fmBody* b, int i)
{
	const fmFloorDef* floor = &w->def.floor;
	if (fmFloor_Applies(floor, b) && b->state.x[3 * i + 1] < floor->height &&
	    !(b->state.pinned[i] & FM_PIN_Y))
		b->state.x[3 * i + 1] = floor->height;
}

double fmContactResponse_InverseMass(const fmBody* b, int i)
{
	return b->state.pinned[i] == FM_PIN_ALL || b->asleep ? 0.0 : 1.0 / b->mesh.mass[i];
}

double fmContactResponse_PairFriction(const fmWorld* w, const fmBody* a, const fmBody* b)
{
	double fa = a->friction >= 0.0 ? a->friction : w->def.contact.friction;
	double fb = b->friction >= 0.0 ? b->friction : w->def.contact.friction;
	return sqrt(fa * fb);
}
