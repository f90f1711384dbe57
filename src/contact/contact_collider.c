// Surface vertices against colliders (contact_collider.h).
#include "contact/contact_collider.h"

#include "contact/collider.h"
#include "contact/contact.h"
#include "contact/contact_response.h"
#include "contact/penalty.h"
#include "core/core.h"
#include "core/det_math.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// Friction for vertex i's next implicit step (penalty.h): the contact normal, the Coulomb
// limit mu lambda (N; a stick collider's: lambda, with next[7] = 1, no limit), the surface's
// velocity and the stretch this step's friction ended with; a stick contact wins over friction,
// else the strongest of the step.
static void fmKeepFriction(fmBody* b, int i, fmVec3 n, double limit, fmVec3 surface, bool stick,
                           double h, int slot)
{
	double* next = b->contact.frictionNext + (size_t)FM_FRICTION_STRIDE * i;
	bool held = next[7] != 0.0;
	if (held != stick ? held : !(limit > next[3]))
		return;
	fmVec3 stretch = fmContactFriction_Stretch(b, i, b->state.x, b->contact.start, h);
	next[0] = n.x, next[1] = n.y, next[2] = n.z;
	next[3] = limit;
	next[4] = surface.x, next[5] = surface.y, next[6] = surface.z;
	next[7] = stick ? 1.0 : 0.0;
	next[8] = stretch.x, next[9] = stretch.y, next[10] = stretch.z;
	next[11] = FM_PENALTY_KAPPA;
	next[12] = slot + 1;
}

// A stick collider's response (infinite friction, as the seeds' floor): the relative velocity
// @p relative keeps its normal part (an approaching one reflected by the restitution @p e) and
// loses its tangential part.
static void fmStickImpact(fmVec3* relative, fmVec3 n, double e)
{
	double vn = fmDot(*relative, n);
	*relative = fmScale(vn < 0.0 ? -e * vn : vn, n);
}

// Where vertex i of body @p b goes back to against collider @p c (@p found: the position, the
// surface normal and the depth it was in, negative: a gap), or nothing (found->hit false) when
// it is outside and did not cross it, nor came within @p dHat of it (the colliders' barrier's
// reach, where the solve held it off; 0 without). Reads only: it runs on the workers
// (fmContactCollider_Collide).
static void fmFindVertexVsCollider(const fmWorld* w, const fmBody* b, int i, const fmCollider* c,
                                   double dHat, fmColliderFind* found)
{
	fmVec3 x = fmLoad(b->state.x, i), start = fmLoad(b->contact.start, i), n;
	double d = fmCollider_Distance(c, x, &n), fraction;
	double depth = -d;
	found->hit = true;
	// Under the barrier the solve placed it: no step crossed the surface, and one that started
	// inside comes out at the depenetration speed (its sink, penalty.h). No cast, no push.
	if (dHat > 0.0)
		found->hit = d < dHat;
	else if (fmCollider_CastSegment(c, start, x, 0.0, &fraction, &n))
	{
		// It came from outside the grown shape: back onto the surface where it entered it,
		// keeping the motion along the surface (a slide is not stopped by the test).
		fmVec3 entry = fmMulAdd(start, fraction, fmSub(x, start));
		depth = -fmDot(fmSub(x, entry), n);
		x = fmMulAdd(x, depth, n);
	}
	else if (depth > 0.0)
	{
		// Inside from the start of the substep (or grazing): out along the surface normal, by
		// at most the floor's depenetration speed beyond undoing the inward motion of the
		// substep (the vertex's own, and a kinematic collider's toward it).
		fmVec3 vc = fmCollider_VelocityAt(c, x);
		double inward = fmMax(0.0, -fmDot(fmSub(fmSub(x, start), fmScale(w->contactStep, vc)), n));
		double reach = fmMax(w->def.floor.maxDepenetrationSpeed * w->contactStep, inward);
		x = fmMulAdd(x, fmMin(depth, reach), n);
	}
	else
		found->hit = false;
	found->x = x;
	found->normal = n;
	found->depth = depth;
}

// Keep vertex @p i of body @p slot on or outside collider @p k, as @p found says (exact shapes:
// no gap, except the colliders' barrier's reach, @p thickness, the one between bodies, which
// also bounds what an implicit creep takes back):
// its position, the velocity response (restitution, friction), the collider's reaction, the
// contact list. Returns false when the contact list could not grow.
static bool fmVertexVsCollider(fmWorld* w, fmContactState* s, int slot, int i, int k,
                               const fmColliderFind* found, double thickness)
{
	fmBody* b = &w->bodies[slot];
	fmCollider* c = &w->colliders[k];
	fmVec3 x = found->x, n = found->normal, v = fmLoad(b->state.v, i);
	double depth = found->depth;
	fmVec3 before = fmLoad(b->state.x, i);
	fmVec3 vc = fmCollider_VelocityAt(c, x), relative = fmSub(v, vc);
	// After an implicit step the barrier (or the penalty) pushed the vertex off the collider
	// during the step: its normal impulse per mass (the penalty's kappa / h^2 depth h) bounds
	// friction too, unless friction already acted in the solve (lagged from the last step:
	// penalty.h).
	bool implicit = w->def.integrator == fm_implicit;
	double h = w->contactStep;
	double pushed = !implicit ? 0.0
	                : fmContact_ColliderBarrier(w)
	                    ? fmColliderBarrier_Push(-depth - fmContactPenalty_Sink(b, i), thickness, h)
	                : depth > 0.0 ? FM_PENALTY_KAPPA * depth / h
	                              : 0.0;
	fmVec3 solved = implicit ? fmContactFriction_Force(b, i, b->state.x, b->contact.start, h)
	                         : fmMakeVec3(0.0, 0.0, 0.0);
	bool inSolve = fmDot(solved, solved) > 0.0 ||
	               (implicit && b->contact.friction[FM_FRICTION_STRIDE * i + 3] > 0.0);
	if (c->def.stick)
		fmStickImpact(&relative, n, c->def.restitution);
	else
		fmContactResponse_Impact(&relative, n, c->def.restitution, c->def.friction,
		                         inSolve ? 0.0 : pushed);
	double mu = c->def.stick ? 1.0 : c->def.friction;
	if (pushed > 0.0)
		fmKeepFriction(b, i, n, mu * b->mesh.mass[i] * pushed / h, vc, c->def.stick, h, k);
	if (!fmContactState_LogVertex(s, b, slot, i))
		return false;
	// A creeping slip that friction or the stick takes back leaves the position too, except
	// under an explicit stick collider, which matches the seeds' stick floor (that keeps it).
	fmVec3 taken = fmSub(fmAdd(vc, relative), v);
	double creep = implicit || !c->def.stick
	                   ? fmContactResponse_CreepStep(w, taken, n, FM_CREEP_FRACTION * thickness)
	                   : 0.0;
	if (creep > 0.0)
		x = fmMulAdd(x, creep, fmMulAdd(taken, -fmDot(taken, n), n));
	s->colliderMoved = s->colliderMoved || x.x != before.x || x.y != before.y || x.z != before.z;
	fmStore(b->state.x, i, x);
	fmStore(b->state.v, i, fmAdd(vc, relative));
	fmContactResponse_KeepPins(b, i, before);
	// The collider's reaction: the velocity change here, and the implicit penalty's push
	// during the step (the solve's friction went to its collider before:
	// fmContactCollider_BookSolveFriction).
	fmVec3 impulse = fmMulAdd(fmScale(b->mesh.mass[i], fmSub(fmLoad(b->state.v, i), v)),
	                          b->mesh.mass[i] * pushed, n);
	c->impulse = fmSub(c->impulse, impulse);
	c->angularImpulse = fmSub(c->angularImpulse, fmCross(fmSub(x, c->position), impulse));
	fmContactPoint* p = fmContactState_NewPoint(s);
	if (p == NULL)
		return false;
	p->body = fmWorldBodyId(w, slot);
	p->vertex = b->userVertex[i];
	p->collider = fmWorldColliderId(w, k);
	p->point = fmLoad(b->state.x, i);
	p->normal = n;
	// How far inside the contact thickness, as between bodies, where the barrier has one.
	p->depth = fmContact_ColliderBarrier(w) ? thickness + depth : depth;
	p->impulse = fmDot(impulse, n);
	uint64_t key = ((uint64_t)(uint32_t)slot << 32) | (0x80000000u | (uint32_t)k);
	return fmContactState_RecordPair(s, key);
}

// The box of a body's surface vertices over the substep (where they started and are now).
static void fmSweptBox(const fmBody* b, fmVec3* lo, fmVec3* hi)
{
	*lo = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	*hi = fmScale(-1.0, *lo);
	for (int p = 0; p < b->contact.surfaceVertexCount; ++p)
	{
		int i = b->contact.surfaceVertex[p];
		fmVec3 x = fmLoad(b->state.x, i), x0 = fmLoad(b->contact.start, i);
		*lo = fmMakeVec3(fmMin(lo->x, fmMin(x.x, x0.x)), fmMin(lo->y, fmMin(x.y, x0.y)),
		                 fmMin(lo->z, fmMin(x.z, x0.z)));
		*hi = fmMakeVec3(fmMax(hi->x, fmMax(x.x, x0.x)), fmMax(hi->y, fmMax(x.y, x0.y)),
		                 fmMax(hi->z, fmMax(x.z, x0.z)));
	}
}

// Whether collider @p c may touch the box [lo, hi] (unbounded shapes always may).
static bool fmColliderNear(const fmCollider* c, fmVec3 lo, fmVec3 hi)
{
	fmVec3 clo, chi;
	if (!fmCollider_Bounds(c, &clo, &chi))
		return true;
	return !(lo.x > chi.x || lo.y > chi.y || lo.z > chi.z || hi.x < clo.x || hi.y < clo.y ||
	         hi.z < clo.z);
}

// A sleeping body is not moved by colliders; one that moves (kinematic or a moving mesh) into
// it wakes it at the end of the frame (island.h).
static void fmWakeIfPushed(fmBody* b, const fmCollider* c)
{
	if (!fmCollider_IsMoving(c))
		return;
	for (int p = 0; p < b->contact.surfaceVertexCount && !b->wakeRequested; ++p)
	{
		fmVec3 n;
		b->wakeRequested =
		    fmCollider_Distance(c, fmLoad(b->state.x, b->contact.surfaceVertex[p]), &n) < 0.0;
	}
}

typedef struct fmColliderTask
{
	const fmWorld* w;
	const fmBody* b;
	const fmCollider* c;
	double dHat;           // the colliders' barrier's reach (0: no barrier)
	fmColliderFind* finds; // per surface vertex of b
} fmColliderTask;

static void fmFindColliderRange(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmColliderTask* t = context;
	for (int p = start; p < end; ++p)
	{
		int i = t->b->contact.surfaceVertex[p];
		if (t->b->state.pinned[i] == FM_PIN_ALL)
			t->finds[p].hit = false;
		else
			fmFindVertexVsCollider(t->w, t->b, i, t->c, t->dHat, &t->finds[p]);
	}
}

void fmContactCollider_ForgetFriction(fmWorld* w, int slot)
{
	for (int b = 0; b < w->bodyCapacity; ++b)
	{
		fmBodyContact* c = &w->bodies[b].contact;
		int n = w->bodies[b].mesh.vertexCount;
		for (int i = 0; fmBody_IsLive(&w->bodies[b]) && i < n; ++i)
		{
			double* records[2] = {c->friction, c->frictionNext};
			for (int k = 0; k < 2; ++k)
				if (records[k] != NULL &&
				    records[k][(size_t)FM_FRICTION_STRIDE * i + 12] == slot + 1)
					memset(records[k] + (size_t)FM_FRICTION_STRIDE * i, 0,
					       FM_FRICTION_STRIDE * sizeof(double));
		}
	}
}

void fmContactCollider_BookSolveFriction(fmWorld* w, double h)
{
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		if (!fmIsland_Stepping(b) || b->contact.friction == NULL)
			continue;
		for (int p = 0; p < b->contact.surfaceVertexCount; ++p)
		{
			int i = b->contact.surfaceVertex[p];
			int k = (int)b->contact.friction[(size_t)FM_FRICTION_STRIDE * i + 12] - 1;
			if (k < 0 ||
			    (k != FM_FLOOR_SLOT && (k >= w->colliderCapacity || !w->colliders[k].inUse)))
				continue;
			fmVec3 impulse =
			    fmScale(h, fmContactFriction_Force(b, i, b->state.x, b->contact.start, h));
			if (fmDot(impulse, impulse) == 0.0)
				continue;
			fmCollider* c = fmWorldCollider(w, k);
			c->impulse = fmSub(c->impulse, impulse);
			c->angularImpulse = fmSub(c->angularImpulse,
			                          fmCross(fmSub(fmLoad(b->state.x, i), c->position), impulse));
		}
	}
}

bool fmContactCollider_Collide(fmWorld* w, fmContactState* s, double thickness)
{
	double dHat = fmContact_ColliderBarrier(w) ? thickness : 0.0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmBody* b = &w->bodies[slot];
		if (!fmBody_IsLive(b))
			continue;
		fmVec3 lo, hi;
		fmSweptBox(b, &lo, &hi);
		lo = fmSub(lo, fmMakeVec3(dHat, dHat, dHat));
		hi = fmAdd(hi, fmMakeVec3(dHat, dHat, dHat));
		for (int k = 0; k < w->colliderCapacity; ++k)
		{
			if (!w->colliders[k].inUse || !fmFiltersMeet(b->filter, w->colliders[k].def.filter) ||
			    !fmColliderNear(&w->colliders[k], lo, hi))
				continue;
			if (b->asleep)
			{
				fmWakeIfPushed(b, &w->colliders[k]);
				continue;
			}
			// Found on the workers (each vertex reads only its own state), applied in order.
			if (!fmGrowArray((void**)&s->colliderFinds, &s->colliderFindCapacity, 0,
			                 b->contact.surfaceVertexCount, sizeof(fmColliderFind)))
				return false;
			fmColliderTask task = {w, b, &w->colliders[k], dHat, s->colliderFinds};
			fmParallelForBalanced(&w->tasks, b->contact.surfaceVertexCount, FM_CONTACT_MIN_RANGE,
			                      fmFindColliderRange, &task);
			for (int p = 0; p < b->contact.surfaceVertexCount; ++p)
			{
				int i = b->contact.surfaceVertex[p];
				if (s->colliderFinds[p].hit &&
				    !fmVertexVsCollider(w, s, slot, i, k, &s->colliderFinds[p], thickness))
					return false;
			}
		}
	}
	return true;
}
