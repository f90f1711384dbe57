// The floor, y = height with normal +y: its one home. Explicit steps get a position and velocity
// response after the step; implicit steps get per-vertex bounds inside the Newton solve and a
// velocity response after it. Both limit depenetration and book the floor's work in the body's
// energy ledger. The vertices it held and the impulses it gave them are kept per body
// (fmFloorHit) for the contact stage, which reports the floor as the world's plane collider.
//
// Depenetration is limited (as PhysX's max depenetration velocity): a vertex found below the
// floor rises by at most maxDepenetrationSpeed * dt a step (beyond undoing the step's own
// downward motion), and the push-out raises its normal velocity to at most that speed.
// Penetration that the step's own motion explains is removed at once, exactly as in the seeds;
// a body that starts (or is dragged) deep below the floor rises at the limit instead of being
// catapulted.
#include "contact/floor.h"
#include "core/det_math.h"

#include "contact/collider.h"
#include "contact/penalty.h"
#include "core/core.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool fmFloor_Applies(const fmFloorDef* floor, const fmBody* b)
{
	return floor->enabled && fmFiltersMeet(floor->filter, b->filter);
}

// Note that the floor held vertex @p i of @p b, @p depth below it, giving it @p impulse (N s).
static bool fmAddHit(fmBody* b, int i, double depth, fmVec3 impulse)
{
	if (b->contact.floorHitCount == b->contact.floorHitCapacity &&
	    !fmGrowArray((void**)&b->contact.floorHits, &b->contact.floorHitCapacity,
	                 b->contact.floorHitCount, b->contact.floorHitCount + 1, sizeof(fmFloorHit)))
		return false;
	fmFloorHit hit = {i, depth, impulse};
	b->contact.floorHits[b->contact.floorHitCount++] = hit;
	return true;
}

// The impulse (N s) that took vertex @p i of @p b from velocity @p before to its velocity now.
static fmVec3 fmImpulseSince(const fmBody* b, int i, const double before[3])
{
	const double* v = b->state.v + 3 * i;
	return fmScale(b->mesh.mass[i],
	               fmMakeVec3(v[0] - before[0], v[1] - before[1], v[2] - before[2]));
}

// ---- explicit ---------------------------------------------------------------------------------

// Lift vertex @p i out of the floor by at most the depenetration limit; returns the work done
// against gravity (J). The step moved the vertex by v dt already: the lift undoes a
// downward move and adds what an upward one lacks of the limit, so that the vertex rises by at most
// max(limit, v) dt in the step.
static double fmLiftOutOfFloor(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, int i, double dt)
{
	double* x = b->state.x + 3 * i;
	double penetration = floor->height - x[1], vIn = b->state.v[3 * i + 1];
	double reach = (fmMax(floor->maxDepenetrationSpeed, vIn) - vIn) * dt;
	double lift = penetration <= reach ? penetration : reach;
	x[1] = penetration <= reach ? floor->height : x[1] + lift;
	// Work against gravity only: the elastic forces of a body that is blowing up would
	// otherwise book its explosion as work done on it. A deep vertex rises by its velocity
	// (set by the callers below), not by this lift.
	return -b->mesh.mass[i] * gravity.y * lift;
}

// The explicit response of vertex @p i, found @p penetration below the floor with velocity vIn
// along y; returns the kinetic energy it adds along y (J).
static double fmRespondExplicit(const fmFloorDef* floor, fmBody* b, int i, double penetration,
                                double vIn, double dt)
{
	const double h = floor->height, pushLimit = floor->maxDepenetrationSpeed;
	double* x = b->state.x + 3 * i;
	double* v = b->state.v + 3 * i;
	if (floor->friction == fm_floorStick)
	{
		// GAMES103 HW3 1.1: tangential velocity zeroed; the penetration depth is turned into an
		// upward velocity (it pushes the vertex out over the next step), up to the limit.
		v[0] = 0.0;
		v[2] = 0.0;
		v[1] = fmMin(vIn + penetration / dt, fmMax(vIn, pushLimit));
		return 0.5 * b->mesh.mass[i] * (v[1] * v[1] - vIn * vIn);
	}
	// Coulomb: reflect the approaching normal velocity with restitution e; the normal velocity
	// change dvn bounds the tangential change by mu * dvn (friction cone). A vertex still below
	// the floor after its lift moves up at the depenetration speed, as in stick mode, so that
	// the body rises as a whole.
	double vn = v[1];
	double dvn = vn < 0.0 ? -(1.0 + floor->restitution) * vn : 0.0;
	v[1] = vn < 0.0 ? -floor->restitution * vn : vn;
	if (x[1] < h)
		v[1] = fmMax(v[1], fmMin(penetration / dt, pushLimit));
	double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
	double scale = vt > 0.0 ? fmMax(0.0, 1.0 - floor->frictionCoefficient * dvn / vt) : 0.0;
	// The substep moved the vertex by dt v already: the slip friction takes back leaves the
	// position too where it is a creep (slower than the depenetration speed), as the contact
	// stage's (fmContactResponse_CreepStep); a faster one is an impact's.
	double taken = (1.0 - scale) * vt;
	double back = taken <= pushLimit ? (1.0 - scale) * dt : 0.0;
	x[0] -= back * v[0];
	x[2] -= back * v[2];
	v[0] *= scale;
	v[2] *= scale;
	return 0.5 * b->mesh.mass[i] * (v[1] * v[1] - vIn * vIn);
}

// The response of vertex @p i, which the floor takes.
static void fmRespondVertex(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, int i, double dt,
                            fmFloorResponse* r)
{
	const double* v = b->state.v + 3 * i;
	const double before[3] = {v[0], v[1], v[2]};
	r->depth = floor->height - b->state.x[3 * i + 1];
	r->liftWork = fmLiftOutOfFloor(floor, gravity, b, i, dt);
	r->pushEnergy = fmRespondExplicit(floor, b, i, r->depth, before[1], dt);
	r->impulse = fmImpulseSince(b, i, before);
}

// The doubles of a fmFloorTaken's responses and of its three ints a vertex.
static size_t fmResponseDoubles(size_t n)
{
	return n * sizeof(fmFloorResponse) / sizeof(double);
}

static size_t fmListDoubles(size_t n)
{
	return (3 * n * sizeof(int) + sizeof(double) - 1) / sizeof(double);
}

size_t fmFloorTaken_Bytes(size_t vertexCount)
{
	return fmArena_Bytes(1, fmResponseDoubles(vertexCount)) +
	       fmArena_Bytes(1, fmListDoubles(vertexCount));
}

bool fmFloorTaken_Make(fmFloorTaken* taken, fmArena* arena, int vertexCount)
{
	const size_t n = (size_t)vertexCount;
	taken->responses = (fmFloorResponse*)fmArena_DoublesUninit(arena, fmResponseDoubles(n));
	int* ints = (int*)fmArena_DoublesUninit(arena, fmListDoubles(n));
	taken->vertex = ints;
	taken->count = ints != NULL ? ints + n : NULL;
	taken->rangeEnd = ints != NULL ? ints + 2 * n : NULL;
	return taken->responses != NULL && ints != NULL;
}

void fmFloor_RespondRange(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, int start, int end,
                          double dt, fmFloorTaken* taken)
{
	if (start >= end) // (an engine's job system may hand out an empty range: nothing to list)
		return;
	int count = 0;
	// fmFloor_Takes with the arrays in locals (the responses move only the vertex they take).
	const uint8_t* pinned = b->state.pinned;
	const double* x = b->state.x;
	const double height = floor->height;
	for (int i = start; i < end; ++i)
		if (!(pinned[i] & FM_PIN_Y) && !(x[3 * i + 1] >= height))
		{
			taken->vertex[start + count] = i;
			fmRespondVertex(floor, gravity, b, i, dt, taken->responses + start + count);
			++count;
		}
	taken->count[start] = count;
	taken->rangeEnd[start] = end;
}

// Books the response @p r of vertex @p i: its work, and its hit in body->floorHits.
static bool fmCollectResponse(fmBody* b, int i, const fmFloorResponse* r, double* work)
{
	*work += r->liftWork;
	*work += r->pushEnergy;
	return fmAddHit(b, i, r->depth, r->impulse);
}

int fmFloor_ApplyExplicit(const fmFloorDef* floor, fmVec3 gravity, fmBody* b, double dt,
                          const fmFloorTaken* taken, double* workDone)
{
	b->contact.floorHitCount = 0;
	*workDone = 0.0;
	if (!fmFloor_Applies(floor, b))
		return 0;
	int contacts = 0;
	double work = 0.0;
	bool listed = true;
	for (int start = 0; taken != NULL && start < b->mesh.vertexCount;
	     start = taken->rangeEnd[start])
		for (int k = start; k < start + taken->count[start]; ++k, ++contacts)
			listed = fmCollectResponse(b, taken->vertex[k], taken->responses + k, &work) && listed;
	for (int i = 0; taken == NULL && i < b->mesh.vertexCount; ++i)
	{
		if (!fmFloor_Takes(b, i, floor->height))
			continue;
		fmFloorResponse own;
		fmRespondVertex(floor, gravity, b, i, dt, &own);
		++contacts;
		listed = fmCollectResponse(b, i, &own, &work) && listed;
	}
	*workDone = work;
	return listed ? contacts : -1;
}

// ---- implicit ---------------------------------------------------------------------------------

// Whether vertex i had the floor's friction in this step's solve (penalty.h: a record of the
// floor's, told by its cap, lagged from the step before).
static bool fmFloorFrictionInSolve(const fmBody* b, int i)
{
	const double* f = b->contact.friction + (size_t)FM_FRICTION_STRIDE * i;
	return f[3] > 0.0 && f[11] == FM_FRICTION_STIFFNESS;
}

static int fmCompareInts(const void* a, const void* b)
{
	int x = *(const int*)a, y = *(const int*)b;
	return (x > y) - (x < y);
}

// The Coulomb floor's friction for vertex i's next solve (penalty.h): the limit mu times the
// floor's push @p force (N) in this one, anchored by the stretch this step's friction ended with.
// Kept for surface vertices (the ones the solve's friction term visits) where stronger than what
// is there.
static void fmKeepFloorFriction(const fmFloorDef* floor, fmBody* b, int i, double force,
                                const fmImplicitCache* c, double h)
{
	double* next = b->contact.frictionNext;
	double limit = floor->frictionCoefficient * force;
	if (!(limit > next[(size_t)FM_FRICTION_STRIDE * i + 3]) ||
	    bsearch(&i, b->contact.surfaceVertex, (size_t)b->contact.surfaceVertexCount, sizeof(int),
	            fmCompareInts) == NULL)
		return;
	next += (size_t)FM_FRICTION_STRIDE * i;
	fmVec3 stretch = fmContactFriction_Stretch(b, i, b->state.x, c->xStart, h);
	memset(next, 0, FM_FRICTION_STRIDE * sizeof(double));
	next[1] = 1.0;
	next[3] = limit;
	next[8] = stretch.x, next[9] = stretch.y, next[10] = stretch.z;
	next[11] = FM_FRICTION_STIFFNESS;
	next[12] = FM_FLOOR_SLOT + 1;
}

// Floor response on velocities after the solve, for vertices resting on the floor. The solve
// already stopped them at the floor (perfectly inelastic positions); here the approach velocity
// is removed (or reflected by the restitution), and friction acts on the tangential velocity:
// stick zeroes it (the seeds), Coulomb reduces it by at most mu * (normal impulse) / m, the
// normal impulse being the floor's force from the solve times h plus the removed approach.
int fmFloor_ImplicitVelocities(const fmFloorDef* floor, fmBody* b, const fmImplicitCache* c,
                               double h, bool frictionInSolve)
{
	b->contact.floorHitCount = 0;
	int contacts = 0;
	bool listed = true;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		double* v = b->state.v + 3 * i;
		if ((b->state.pinned[i] & FM_PIN_Y) || b->state.x[3 * i + 1] > c->floorBound[i])
			continue;
		++contacts;
		const double before[3] = {v[0], v[1], v[2]};
		double push = fmMax(0.0, c->gradient[3 * i + 1]) * h; // N s, the floor's push in the solve
		// Friction in the solve already answered the push; the velocity keeps the rest.
		double impulse = frictionInSolve && fmFloorFrictionInSolve(b, i) ? 0.0 : push;
		if (frictionInSolve)
			fmKeepFloorFriction(floor, b, i, push / h, c, h);
		if (v[1] < 0.0)
		{
			double e = floor->friction == fm_floorCoulomb ? floor->restitution : 0.0;
			impulse += (1.0 + e) * b->mesh.mass[i] * -v[1];
			v[1] = -e * v[1];
		}
		if (floor->friction == fm_floorStick)
		{
			v[0] = 0.0;
			v[2] = 0.0;
		}
		else
		{
			double vt = sqrt(v[0] * v[0] + v[2] * v[2]);
			double keep = vt > 0.0 ? fmMax(0.0, 1.0 - floor->frictionCoefficient * impulse /
			                                              (b->mesh.mass[i] * vt))
			                       : 0.0;
			v[0] *= keep;
			v[2] *= keep;
		}
		fmVec3 given = fmImpulseSince(b, i, before);
		given.y += push;
		listed = listed && fmAddHit(b, i, fmMax(0.0, floor->height - b->state.x[3 * i + 1]), given);
	}
	return listed ? contacts : -1;
}

// Lowest y of every vertex this step: the floor, except for a vertex deep below it, which may
// rise by at most the depenetration speed times h (a body that starts below the floor is lifted
// out, not catapulted; docs/robustness.md).
void fmFloor_SetBounds(const fmFloorDef* floor, const fmBody* b, fmImplicitCache* c, double h)
{
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		c->floorBound[i] =
		    fmMin(floor->height, c->xStart[3 * i + 1] + floor->maxDepenetrationSpeed * h);
}

// Work the floor did on the body in the step (J), for the energy ledger: its push (the energy
// gradient it holds back) times the lift, on the vertices it lifts out from below its plane (at
// most the depenetration speed times h each). Stopping a vertex that comes from above is an
// inelastic impact: no work is booked for it.
double fmFloor_ImplicitWork(const fmBody* b, const fmImplicitCache* c, double floorHeight)
{
	double work = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (!(b->state.pinned[i] & FM_PIN_Y) && c->floorBound[i] < floorHeight &&
		    b->state.x[3 * i + 1] <= c->floorBound[i])
			work += fmMax(0.0, c->gradient[3 * i + 1]) *
			        fmMax(0.0, b->state.x[3 * i + 1] - c->xStart[3 * i + 1]);
	return work;
}
