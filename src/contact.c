// The contact stage (contact.h).
//
// Model (docs/contact.md): contact keeps a gap of `thickness` between a body's surface
// vertices and whatever they touch. After each substep (explicit) or each implicit step:
// 1. kinematic colliders move;
// 2. each surface vertex found inside a collider, or whose motion in the substep crossed it
//    (a swept test: no tunnelling through thin colliders), is put back on its surface; its velocity
//    relative to the collider loses its approaching normal part (or has it reflected by the
//    restitution) and its tangential part shrinks by at most mu times the normal change (Coulomb's
//    cone);
// 3. body-body: each surface vertex is tested against the other bodies' surface triangles near
//    it (spatial hash); a vertex inside the thickness of a triangle is pushed out along the
//    triangle's normal and the triangle the other way, by inverse masses (momentum is kept),
//    in a few Gauss-Seidel passes; then the same velocity response between the vertex and the
//    triangle's point.
//    Once a frame, a vertex no triangle's reach found but another body's tet holds (embedded.h)
//    is pushed toward that body's nearest surface triangle at the depenetration speed.
// Everything runs in a fixed order (bodies, vertices, colliders, triangles ascending), serially:
// the same bits for any number of workers.
#include "contact.h"
#include "det_math.h"

#include "broad_phase.h"
#include "collider.h"
#include "core.h"
#include "embedded.h"
#include "energy_ledger.h"
#include "floor.h"
#include "force_spring.h"
#include "forces.h"
#include "geometry.h"
#include "island.h"
#include "material.h"
#include "penalty.h"
#include "timer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The automatic thickness: this fraction of the smallest body's bounding-box diagonal.
#define FM_CONTACT_THICKNESS_FRACTION 0.01

// Detection items a task range takes at least (each is a box test, or a hash query and its
// narrow tests).
#define FM_CONTACT_MIN_RANGE 64

// Where a vertex goes back to against a collider (fmFindVertexVsCollider).
typedef struct fmColliderFind
{
	fmVec3 x;      // its position on the collider's surface
	fmVec3 normal; // the surface's outward normal there
	double depth;  // m, how far in it was
	bool hit;      // false: outside, and it did not cross the surface
} fmColliderFind;

// A vertex the contact stage changed, with its state before (the ledger's bookkeeping).
typedef struct fmTouched
{
	int body;
	int vertex;
	fmVec3 x;
	fmVec3 v;
} fmTouched;

// A vertex against a triangle of another body.
typedef struct fmPairContact
{
	int body;     // the vertex's body slot
	int vertex;   // its index in the body
	int other;    // the triangle's body slot
	int triangle; // its index in the other body's surface
	double w[3];  // barycentric weights of the triangle's point nearest the vertex
	fmVec3 normal;
	double depth;
	double impulse;
	double reach;  // m, the most the projections may still separate the pair in this substep
	bool embedded; // the vertex was inside the other body, beyond any triangle's reach
} fmPairContact;

// What one worker of the parallel detection found (fmDetect): its queries' buffers, the edge
// contacts it found in item order, its broad-phase time and whether memory ran short. Each on
// cache lines of its own: the workers write theirs at every query.
typedef struct fmWorkerFinds
{
	_Alignas(64) fmHashQuery query;
	fmHashQuery tetQuery; // for the tet hash (embedded.h)
	struct fmEdgeContact* edges;
	int edgeCount;
	int edgeCapacity;
	double broadPhase; // s
	bool failed;
} fmWorkerFinds;

// An edge of one body's surface within the thickness of an edge of another's (both ways
// between the bodies' surfaces, the endpoints excluded: those are vertex-triangle contacts).
typedef struct fmEdgeContact
{
	int body, other; // body slots, body < other
	int a[2], b[2];  // the edges' vertices
	double s, t;     // the closest points' parameters along a and b
	fmVec3 normal;   // unit, from b's edge toward a's
	double reach;    // m, the most the projections may still separate them in this substep
	double impulse;  // N s
	int item;        // the detection item (surface edge) that found it, for a fixed order
	int sequence;    // its place among that item's contacts
} fmEdgeContact;

struct fmContactState
{
	fmSpatialHash hash;
	fmTetHash tetHash; // the near bodies' tets: vertices embedded deeper than the reach
	bool tetHashReady; // built for this detection (the frame's first)
	int triangleCapacity;
	fmVec3* lower; // per global triangle: its box
	fmVec3* upper;
	int* triangleBody;                     // per global triangle: its body slot
	int* triangleIndex;                    // per global triangle: its index in that body's surface
	fmWorkerFinds workers[FM_MAX_WORKERS]; // the parallel detection's per-worker buffers
	fmColliderFind* colliderFinds;         // per surface vertex of the body against a collider
	int colliderFindCapacity;
	int* items; // the detection's items: (body slot, vertex or surface edge) pairs
	int itemCapacity;
	fmPairContact* found; // per vertex item: its contact, where hit[k]
	uint8_t* hit;
	int foundCapacity;
	fmVec3* bodyLower; // per body slot: its surface's box, grown (the mid phase)
	fmVec3* bodyUpper;
	bool* bodyNear;    // per body slot: another body's box (or its own, self-colliding) overlaps
	double* bodySpeed; // per body slot: its surface vertices' fastest speed (fmContact_Pieces)
	int bodyBoxCapacity;
	int triangleCount; // the triangles in the hash (those of bodies near another)
	fmPairContact* pairContacts;
	int pairContactCount;
	int pairContactCapacity;
	fmEdgeContact* edgeContacts;
	int edgeContactCount;
	int edgeContactCapacity;
	fmContactPoint* points; // the last substep's contacts
	int pointCount;
	int pointCapacity;
	uint64_t* pairs; // pairs that touched during the frame (sorted and made unique at its end)
	int pairCount;
	int pairCapacity;
	uint64_t* lastPairs; // the previous frame's
	int lastPairCount;
	int lastPairCapacity;
	fmContactEvent* events;
	int eventCount;
	int eventCapacity;
	fmTouched* touched; // the vertices the substep's contacts changed, with their old state
	int touchedCount;
	int touchedCapacity;
	int* tets; // scratch: the tets around a body's touched vertices
	int tetCapacity;
	double* forces; // scratch: a spring body's forces
	int forceCapacity;
	double predict; // s: motion bounds add |v| predict (the implicit step's planes, made before
	                // the step), 0 after it
};

// ---- small buffers -----------------------------------------------------------------------------

void fmContact_Free(fmContactState* s)
{
	if (s == NULL)
		return;
	fmSpatialHash_Free(&s->hash);
	fmTetHash_Free(&s->tetHash);
	size_t t = (size_t)s->triangleCapacity;
	FM_FREE_ARRAY(s->lower, fmVec3, t);
	FM_FREE_ARRAY(s->upper, fmVec3, t);
	FM_FREE_ARRAY(s->triangleBody, int, t);
	FM_FREE_ARRAY(s->triangleIndex, int, t);
	for (int k = 0; k < FM_MAX_WORKERS; ++k)
	{
		fmHashQuery_Free(&s->workers[k].query);
		fmHashQuery_Free(&s->workers[k].tetQuery);
		FM_FREE_ARRAY(s->workers[k].edges, fmEdgeContact, s->workers[k].edgeCapacity);
	}
	FM_FREE_ARRAY(s->items, int, s->itemCapacity);
	FM_FREE_ARRAY(s->colliderFinds, fmColliderFind, s->colliderFindCapacity);
	FM_FREE_ARRAY(s->found, fmPairContact, s->foundCapacity);
	FM_FREE_ARRAY(s->hit, uint8_t, s->foundCapacity);
	FM_FREE_ARRAY(s->bodyLower, fmVec3, s->bodyBoxCapacity);
	FM_FREE_ARRAY(s->bodyUpper, fmVec3, s->bodyBoxCapacity);
	FM_FREE_ARRAY(s->bodyNear, bool, s->bodyBoxCapacity);
	FM_FREE_ARRAY(s->bodySpeed, double, s->bodyBoxCapacity);
	FM_FREE_ARRAY(s->pairContacts, fmPairContact, s->pairContactCapacity);
	FM_FREE_ARRAY(s->edgeContacts, fmEdgeContact, s->edgeContactCapacity);
	FM_FREE_ARRAY(s->points, fmContactPoint, s->pointCapacity);
	FM_FREE_ARRAY(s->pairs, uint64_t, s->pairCapacity);
	FM_FREE_ARRAY(s->lastPairs, uint64_t, s->lastPairCapacity);
	FM_FREE_ARRAY(s->events, fmContactEvent, s->eventCapacity);
	FM_FREE_ARRAY(s->touched, fmTouched, s->touchedCapacity);
	FM_FREE_ARRAY(s->tets, int, s->tetCapacity);
	FM_FREE_ARRAY(s->forces, double, s->forceCapacity);
	FM_FREE_ARRAY(s, fmContactState, 1);
}

static fmContactState* fmGetState(fmWorld* w)
{
	if (w->contactState == NULL)
		w->contactState = FM_ALLOC_ZERO(fmContactState, 1);
	return w->contactState;
}

// ---- settings ----------------------------------------------------------------------------------

fmResult fmContactDef_Validate(const fmContactDef* def, fmDiagnostic* diag)
{
	if (!(def->thickness >= 0.0 && def->thickness < 1e6))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "contact thickness must be >= 0 m and finite (0: automatic, 1%% of the "
		                   "smallest body), got %g",
		                   def->thickness);
	if (!(def->friction >= 0.0 && isfinite(def->friction)))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "contact friction must be finite and >= 0, got %g", def->friction);
	if (!(def->restitution >= 0.0 && def->restitution <= 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "contact restitution must be in [0, 1], got %g", def->restitution);
	if (def->iterations < 1 || def->iterations > 64)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "contact iterations must be in [1, 64] (default 4), got %d",
		                   def->iterations);
	if (!(def->sleepSpeed > 0.0 && def->sleepSpeed < 1e6) ||
	    !(def->sleepTime > 0.0 && def->sleepTime < 1e6))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "contact sleepSpeed (m/s) and sleepTime (s) must be finite and > 0 "
		                   "(defaults 0.05 and 0.5), got %g and %g",
		                   def->sleepSpeed, def->sleepTime);
	return fm_ok;
}

double fmContact_Thickness(const fmWorld* w)
{
	if (w->def.contact.thickness > 0.0)
		return w->def.contact.thickness;
	double smallest = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].x != NULL)
			smallest = fmMin(smallest, w->bodies[i].restSize);
	return isfinite(smallest) ? FM_CONTACT_THICKNESS_FRACTION * smallest : 0.0;
}

static int fmLiveBodies(const fmWorld* w)
{
	int live = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		live += w->bodies[i].x != NULL;
	return live;
}

static bool fmHasColliders(const fmWorld* w)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
		if (w->colliders[k].inUse)
			return true;
	return false;
}

// Whether surfaces of bodies can meet: two or more bodies, or one that collides with itself.
static bool fmBodiesMeet(const fmWorld* w)
{
	if (!w->def.contact.bodies)
		return false;
	if (fmLiveBodies(w) >= 2)
		return true;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].x != NULL && w->bodies[i].selfCollision)
			return true;
	return false;
}

bool fmContact_Active(const fmWorld* w)
{
	return fmHasColliders(w) || fmBodiesMeet(w);
}

// ---- per-body buffers --------------------------------------------------------------------------

// The body's surface vertices (ascending) and its substep-start positions.
// How thick a body is at rest, as 2 V / S (its volume over half its surface area): a plate's
// thickness, a third of a cube's side. What a step may close in on it without passing through.
static double fmRestThinness(const fmBody* b)
{
	double volume = 0.0, area = 0.0;
	for (int t = 0; t < b->tetCount; ++t)
		volume += b->restVolume[t];
	for (int t = 0; t < b->triangleCount; ++t)
	{
		const int* tri = b->surface + 3 * (size_t)t;
		fmVec3 p = fmLoad(b->x0, tri[0]);
		area += 0.5 *
		        fmLength(fmCross(fmSub(fmLoad(b->x0, tri[1]), p), fmSub(fmLoad(b->x0, tri[2]), p)));
	}
	return area > 0.0 ? 2.0 * volume / area : b->restSize;
}

static bool fmBodyContactArrays(fmBody* b)
{
	if (b->contactStart == NULL)
		b->contactStart = FM_ALLOC_ARRAY(double, 3 * (size_t)b->vertexCount);
	if (b->contactMark == NULL)
		b->contactMark = FM_ALLOC_ZERO(int, b->vertexCount);
	if (b->contactPlane == NULL)
		b->contactPlane = FM_ALLOC_ARRAY(double, 4 * (size_t)b->vertexCount);
	if (b->contactFriction == NULL)
		b->contactFriction = FM_ALLOC_ZERO(double, 8 * (size_t)b->vertexCount);
	if (b->contactFrictionNext == NULL)
		b->contactFrictionNext = FM_ALLOC_ZERO(double, 8 * (size_t)b->vertexCount);
	if (b->contactTetMark == NULL)
		b->contactTetMark = FM_ALLOC_ZERO(uint8_t, b->tetCount > 0 ? b->tetCount : 1);
	if (b->embeddedHolder == NULL)
		b->embeddedHolder = FM_ALLOC_ZERO(int, b->vertexCount);
	if (b->surfaceVertex == NULL)
	{
		uint8_t* on = FM_ALLOC_ZERO(uint8_t, b->vertexCount);
		if (on == NULL)
			return false;
		int count = 0;
		for (int k = 0; k < 3 * b->triangleCount; ++k)
			count += on[b->surface[k]]++ == 0;
		b->surfaceVertex = FM_ALLOC_ARRAY(int, count > 0 ? count : 1);
		if (b->surfaceVertex != NULL)
		{
			b->surfaceVertexCount = count;
			count = 0;
			for (int i = 0; i < b->vertexCount; ++i)
				if (on[i])
					b->surfaceVertex[count++] = i;
		}
		FM_FREE_ARRAY(on, uint8_t, b->vertexCount);
		b->contactThinness = fmRestThinness(b);
	}
	return b->contactStart != NULL && b->surfaceVertex != NULL && b->contactMark != NULL &&
	       b->contactTetMark != NULL && b->contactPlane != NULL && b->embeddedHolder != NULL;
}

void fmContact_BeginFrame(fmWorld* w)
{
	w->embeddedSearch = true;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].embeddedHolder != NULL)
			memset(w->bodies[i].embeddedHolder, 0, sizeof(int) * (size_t)w->bodies[i].vertexCount);
	if (w->contactState != NULL)
		w->contactState->pairCount = 0; // what a failed frame left

	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		fmCollider* c = fmWorldCollider(w, k < w->colliderCapacity ? k : FM_FLOOR_SLOT);
		c->impulse = fmMakeVec3(0.0, 0.0, 0.0);
		c->angularImpulse = fmMakeVec3(0.0, 0.0, 0.0);
	}
}

// The largest slip (a share of the thickness) an implicit step's friction takes back from the
// positions as well as the velocities (fmVertexVsCollider, fmRespondPair): a creep's.
#define FM_CREEP_FRACTION 0.1

// Implicit steps: the step's positions follow its velocities (x = x0 + h v), so a velocity
// change @p dv that friction or the stick made along the surface (normal @p n) moves them by
// h dv too, where the slip it takes back is a creep (h |dv| at most FM_CREEP_FRACTION of the
// thickness): the slip is not kept in the positions (it was, and stacks and stick contacts
// crept). A faster slip is an impact's: moving the contact's vertices alone by it would crush
// their tets. Returns the move per unit of @p dv's scale (h, or 0).
static double fmCreepStep(const fmWorld* w, fmVec3 dv, fmVec3 n, double thickness)
{
	if (w->def.integrator != fm_implicit)
		return 0.0;
	double h = w->contactStep;
	fmVec3 along = fmMulAdd(dv, -fmDot(dv, n), n);
	return h * fmLength(along) <= FM_CREEP_FRACTION * thickness ? h : 0.0;
}

// ---- bookkeeping -------------------------------------------------------------------------------

static bool fmRecordPair(fmContactState* s, uint64_t key)
{
	if (s->pairCount > 0 && s->pairs[s->pairCount - 1] == key)
		return true;
	if (!fmGrowArray((void**)&s->pairs, &s->pairCapacity, s->pairCount, s->pairCount + 1,
	                 sizeof(uint64_t)))
		return false;
	s->pairs[s->pairCount++] = key;
	return true;
}

static fmContactPoint* fmNewPoint(fmContactState* s)
{
	if (!fmGrowArray((void**)&s->points, &s->pointCapacity, s->pointCount, s->pointCount + 1,
	                 sizeof(fmContactPoint)))
		return NULL;
	fmContactPoint* p = &s->points[s->pointCount++];
	memset(p, 0, sizeof *p);
	return p;
}

// Note vertex i of body @p slot's state before the stage first changes it.
static bool fmTouch(fmContactState* s, fmBody* b, int slot, int i)
{
	if (b->contactMark[i] != 0)
		return true;
	if (!fmGrowArray((void**)&s->touched, &s->touchedCapacity, s->touchedCount, s->touchedCount + 1,
	                 sizeof(fmTouched)))
		return false;
	fmTouched t = {slot, i, fmLoad(b->x, i), fmLoad(b->v, i)};
	s->touched[s->touchedCount++] = t;
	b->contactMark[i] = s->touchedCount;
	return true;
}

// A push between bodies never moves a vertex below the floor (the floor holds it there).
static void fmKeepAboveFloor(const fmWorld* w, fmBody* b, int i)
{
	const fmFloorDef* floor = &w->def.floor;
	if (fmFloor_Holds(floor, b) && b->x[3 * i + 1] < floor->height && !(b->pinned[i] & FM_PIN_Y))
		b->x[3 * i + 1] = floor->height;
}

// Pinned axes keep their coordinate and have no velocity.
static void fmKeepPins(fmBody* b, int i, fmVec3 x0)
{
	const double before[3] = {x0.x, x0.y, x0.z};
	for (int e = 0; e < 3; ++e)
		if (fmIsDofPinned(b, 3 * i + e))
		{
			b->x[3 * i + e] = before[e];
			b->v[3 * i + e] = 0.0;
		}
}

// The relative velocity @p relative after an impact along @p n with restitution @p e and
// friction @p mu; @p pushed (m/s) is the normal velocity a push during the step already gave
// (the implicit penalty's), which friction's cone counts too. Returns the normal velocity
// change (>= 0).
static double fmImpact(fmVec3* relative, fmVec3 n, double e, double mu, double pushed)
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

// ---- colliders ---------------------------------------------------------------------------------

// Friction for vertex i's next implicit step (penalty.h): the contact normal, the Coulomb
// limit mu lambda (N; a stick collider's: lambda, with next[7] = 1, no limit) and the
// surface's velocity; a stick contact wins over friction, else the strongest of the step.
static void fmKeepFriction(fmBody* b, int i, fmVec3 n, double limit, fmVec3 surface, bool stick)
{
	double* next = b->contactFrictionNext + 8 * (size_t)i;
	bool held = next[7] != 0.0;
	if (held != stick ? held : !(limit > next[3]))
		return;
	next[0] = n.x, next[1] = n.y, next[2] = n.z;
	next[3] = limit;
	next[4] = surface.x, next[5] = surface.y, next[6] = surface.z;
	next[7] = stick ? 1.0 : 0.0;
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
// surface normal and the depth it was in), or nothing (found->hit false) when it is outside
// and did not cross it. Reads only: it runs on the workers (fmCollideWithColliders).
static void fmFindVertexVsCollider(const fmWorld* w, const fmBody* b, int i, const fmCollider* c,
                                   fmColliderFind* found)
{
	fmVec3 x = fmLoad(b->x, i), start = fmLoad(b->contactStart, i), n;
	double d = fmCollider_Distance(c, x, &n), fraction;
	double depth = -d;
	found->hit = true;
	if (fmCollider_CastSegment(c, start, x, 0.0, &fraction, &n))
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
// no gap; @p thickness, the one between bodies, only bounds what an implicit creep takes back):
// its position, the velocity response (restitution, friction), the collider's reaction, the
// contact list. Returns false when the contact list could not grow.
static bool fmVertexVsCollider(fmWorld* w, fmContactState* s, int slot, int i, int k,
                               const fmColliderFind* found, double thickness)
{
	fmBody* b = &w->bodies[slot];
	fmCollider* c = &w->colliders[k];
	fmVec3 x = found->x, n = found->normal, v = fmLoad(b->v, i);
	double depth = found->depth;
	fmVec3 before = fmLoad(b->x, i);
	fmVec3 vc = fmCollider_VelocityAt(c, x), relative = fmSub(v, vc);
	// After an implicit step the penalty pushed the vertex out of the collider during the
	// step: its normal impulse per mass, kappa / h^2 depth h, bounds friction too, unless
	// friction already acted in the solve (lagged from the last step: penalty.h).
	bool implicit = w->def.integrator == fm_implicit;
	double h = w->contactStep;
	double pushed = implicit && depth > 0.0 ? FM_PENALTY_KAPPA * depth / h : 0.0;
	fmVec3 solved = implicit ? fmContactFriction_Force(b, i, b->x, b->contactStart, h)
	                         : fmMakeVec3(0.0, 0.0, 0.0);
	bool inSolve = fmDot(solved, solved) > 0.0 || (implicit && b->contactFriction[8 * i + 3] > 0.0);
	if (c->def.stick)
		fmStickImpact(&relative, n, c->def.restitution);
	else
		fmImpact(&relative, n, c->def.restitution, c->def.friction, inSolve ? 0.0 : pushed);
	double mu = c->def.stick ? 1.0 : c->def.friction;
	if (pushed > 0.0)
		fmKeepFriction(b, i, n, mu * b->mass[i] * pushed / h, vc, c->def.stick);
	if (!fmTouch(s, b, slot, i))
		return false;
	// A creeping slip that friction or the stick takes back leaves the position too.
	fmVec3 taken = fmSub(fmAdd(vc, relative), v);
	double creep = fmCreepStep(w, taken, n, thickness);
	if (creep > 0.0)
		x = fmMulAdd(x, creep, fmMulAdd(taken, -fmDot(taken, n), n));
	fmStore(b->x, i, x);
	fmStore(b->v, i, fmAdd(vc, relative));
	fmKeepPins(b, i, before);
	// The collider's reaction: the velocity change here, and the implicit penalty's push
	// during the step.
	fmVec3 impulse =
	    fmMulAdd(fmScale(b->mass[i], fmSub(fmLoad(b->v, i), v)), b->mass[i] * pushed, n);
	impulse = fmMulAdd(impulse, h, solved);
	c->impulse = fmSub(c->impulse, impulse);
	c->angularImpulse = fmSub(c->angularImpulse, fmCross(fmSub(x, c->position), impulse));
	fmContactPoint* p = fmNewPoint(s);
	if (p == NULL)
		return false;
	p->body = fmWorldBodyId(w, slot);
	p->vertex = b->userVertex[i];
	p->collider = fmWorldColliderId(w, k);
	p->point = fmLoad(b->x, i);
	p->normal = n;
	p->depth = depth;
	p->impulse = fmDot(impulse, n);
	uint64_t key = ((uint64_t)(uint32_t)slot << 32) | (0x80000000u | (uint32_t)k);
	return fmRecordPair(s, key);
}

// The box of a body's surface vertices over the substep (where they started and are now).
static void fmSweptBox(const fmBody* b, fmVec3* lo, fmVec3* hi)
{
	*lo = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	*hi = fmScale(-1.0, *lo);
	for (int p = 0; p < b->surfaceVertexCount; ++p)
	{
		int i = b->surfaceVertex[p];
		fmVec3 x = fmLoad(b->x, i), x0 = fmLoad(b->contactStart, i);
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

// A sleeping body is not moved by colliders; one that moves (kinematic) into it wakes it at
// the end of the frame (island.h).
static void fmWakeIfPushed(fmBody* b, const fmCollider* c)
{
	const fmColliderDef* d = &c->def;
	if (fmDot(d->velocity, d->velocity) == 0.0 &&
	    fmDot(d->angularVelocity, d->angularVelocity) == 0.0)
		return;
	for (int p = 0; p < b->surfaceVertexCount && !b->wakeRequested; ++p)
	{
		fmVec3 n;
		b->wakeRequested = fmCollider_Distance(c, fmLoad(b->x, b->surfaceVertex[p]), &n) < 0.0;
	}
}

typedef struct fmColliderTask
{
	const fmWorld* w;
	const fmBody* b;
	const fmCollider* c;
	fmColliderFind* finds; // per surface vertex of b
} fmColliderTask;

static void fmFindColliderRange(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmColliderTask* t = context;
	for (int p = start; p < end; ++p)
	{
		int i = t->b->surfaceVertex[p];
		if (t->b->pinned[i] == FM_PIN_ALL)
			t->finds[p].hit = false;
		else
			fmFindVertexVsCollider(t->w, t->b, i, t->c, &t->finds[p]);
	}
}

static bool fmCollideWithColliders(fmWorld* w, fmContactState* s, double thickness)
{
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmBody* b = &w->bodies[slot];
		if (b->x == NULL)
			continue;
		fmVec3 lo, hi;
		fmSweptBox(b, &lo, &hi);
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
			                 b->surfaceVertexCount, sizeof(fmColliderFind)))
				return false;
			fmColliderTask task = {w, b, &w->colliders[k], s->colliderFinds};
			fmParallelForBalanced(&w->tasks, b->surfaceVertexCount, FM_CONTACT_MIN_RANGE,
			                      fmFindColliderRange, &task);
			for (int p = 0; p < b->surfaceVertexCount; ++p)
			{
				int i = b->surfaceVertex[p];
				if (s->colliderFinds[p].hit &&
				    !fmVertexVsCollider(w, s, slot, i, k, &s->colliderFinds[p], thickness))
					return false;
			}
		}
	}
	return true;
}

// ---- body against body -------------------------------------------------------------------------

static const int* fmTriangleOf(const fmBody* b, int t)
{
	return b->surface + 3 * t;
}

// The cross product of surface triangle @p tri's edges (its normal times twice its area).
static fmVec3 fmTriangleCross(const fmBody* b, const int* tri)
{
	fmVec3 a = fmLoad(b->x, tri[0]);
	return fmCross(fmSub(fmLoad(b->x, tri[1]), a), fmSub(fmLoad(b->x, tri[2]), a));
}

// How far vertex i may have moved in the substep: since its start, and before an implicit
// step what its velocity will carry it (both bounds of the broad phase's boxes and reaches).
static double fmMotionOf(const fmContactState* s, const fmBody* b, int i)
{
	return fmLength(fmSub(fmLoad(b->x, i), fmLoad(b->contactStart, i))) +
	       s->predict * fmLength(fmLoad(b->v, i));
}

// Whether the box [lo, hi] of something of body @p slot overlaps the box of a body it may touch
// (another one whose filter meets its own, or itself when it collides with itself; with
// @p higher, only the bodies of higher slots, which the edges test against): most vertices of a
// pile of bodies apart from each other skip the spatial hash entirely.
static bool fmNearOtherBody(const fmWorld* w, const fmContactState* s, int slot, fmVec3 lo,
                            fmVec3 hi, bool higher)
{
	const fmBody* b = &w->bodies[slot];
	for (int k = higher ? slot + 1 : 0; k < w->bodyCapacity; ++k)
	{
		const fmBody* o = &w->bodies[k];
		if (o->x == NULL || (k == slot && !b->selfCollision) ||
		    !fmFiltersMeet(b->filter, o->filter))
			continue;
		fmVec3 ol = s->bodyLower[k], oh = s->bodyUpper[k];
		if (!(hi.x < ol.x || lo.x > oh.x || hi.y < ol.y || lo.y > oh.y || hi.z < ol.z ||
		      lo.z > oh.z))
			return true;
	}
	return false;
}

// Room for a box, a flag and a speed per body slot.
static bool fmReserveBodyBoxes(const fmWorld* w, fmContactState* s)
{
	if (w->bodyCapacity <= s->bodyBoxCapacity)
		return true;
	int old = s->bodyBoxCapacity;
	FM_FREE_ARRAY(s->bodyLower, fmVec3, old);
	FM_FREE_ARRAY(s->bodyUpper, fmVec3, old);
	FM_FREE_ARRAY(s->bodyNear, bool, old);
	FM_FREE_ARRAY(s->bodySpeed, double, old);
	s->bodyLower = FM_ALLOC_ARRAY(fmVec3, w->bodyCapacity);
	s->bodyUpper = FM_ALLOC_ARRAY(fmVec3, w->bodyCapacity);
	s->bodyNear = FM_ALLOC_ARRAY(bool, w->bodyCapacity);
	s->bodySpeed = FM_ALLOC_ARRAY(double, w->bodyCapacity);
	s->bodyBoxCapacity = w->bodyCapacity;
	if (s->bodyLower && s->bodyUpper && s->bodyNear && s->bodySpeed)
		return true;
	FM_FREE_ARRAY(s->bodyLower, fmVec3, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodyUpper, fmVec3, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodyNear, bool, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodySpeed, double, w->bodyCapacity);
	s->bodyBoxCapacity = 0;
	return false;
}

// Every body's box: its surface vertices' box grown by the thickness and by the most any of
// them moved in the substep; and whether another body's box (or its own, when it collides with
// itself) overlaps it.
static bool fmBuildBodyBoxes(const fmWorld* w, fmContactState* s, double thickness)
{
	if (!fmReserveBodyBoxes(w, s))
		return false;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		fmVec3 lo = fmMakeVec3(INFINITY, INFINITY, INFINITY), hi = fmScale(-1.0, lo);
		double motion = 0.0;
		for (int p = 0; b->x && p < b->surfaceVertexCount; ++p)
		{
			int i = b->surfaceVertex[p];
			fmVec3 x = fmLoad(b->x, i);
			lo = fmMakeVec3(fmMin(lo.x, x.x), fmMin(lo.y, x.y), fmMin(lo.z, x.z));
			hi = fmMakeVec3(fmMax(hi.x, x.x), fmMax(hi.y, x.y), fmMax(hi.z, x.z));
			motion = fmMax(motion, fmMotionOf(s, b, i));
		}
		double grow = thickness + motion;
		s->bodyLower[slot] = fmSub(lo, fmMakeVec3(grow, grow, grow));
		s->bodyUpper[slot] = fmAdd(hi, fmMakeVec3(grow, grow, grow));
	}
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		s->bodyNear[slot] =
		    w->bodies[slot].x != NULL &&
		    fmNearOtherBody(w, s, slot, s->bodyLower[slot], s->bodyUpper[slot], false);
	return true;
}

// Every body's surface triangles with their boxes (grown by the thickness and by how far their
// vertices moved in the substep) into the broad phase.
static bool fmBuildTriangles(fmWorld* w, fmContactState* s, double thickness)
{
	int total = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		total += w->bodies[slot].x ? w->bodies[slot].triangleCount : 0;
	if (total > s->triangleCapacity)
	{
		int old = s->triangleCapacity;
		FM_FREE_ARRAY(s->lower, fmVec3, old);
		FM_FREE_ARRAY(s->upper, fmVec3, old);
		FM_FREE_ARRAY(s->triangleBody, int, old);
		FM_FREE_ARRAY(s->triangleIndex, int, old);
		s->lower = FM_ALLOC_ARRAY(fmVec3, total);
		s->upper = FM_ALLOC_ARRAY(fmVec3, total);
		s->triangleBody = FM_ALLOC_ARRAY(int, total);
		s->triangleIndex = FM_ALLOC_ARRAY(int, total);
		s->triangleCapacity = total;
		if (!s->lower || !s->upper || !s->triangleBody || !s->triangleIndex)
		{
			s->triangleCapacity = 0; // (the frees above take a count of 0)
			return false;
		}
	}
	if (!fmBuildBodyBoxes(w, s, thickness))
		return false;
	double extent = 0.0;
	int k = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		// Only the triangles of bodies near another one go into the hash.
		for (int t = 0; b->x && s->bodyNear[slot] && t < b->triangleCount; ++t, ++k)
		{
			const int* tri = fmTriangleOf(b, t);
			fmVec3 lo = fmLoad(b->x, tri[0]), hi = lo;
			double motion = 0.0;
			for (int c = 0; c < 3; ++c)
			{
				fmVec3 p = fmLoad(b->x, tri[c]);
				lo = fmMakeVec3(fmMin(lo.x, p.x), fmMin(lo.y, p.y), fmMin(lo.z, p.z));
				hi = fmMakeVec3(fmMax(hi.x, p.x), fmMax(hi.y, p.y), fmMax(hi.z, p.z));
				motion = fmMax(motion, fmMotionOf(s, b, tri[c]));
			}
			if (!(fabs(lo.x) + fabs(lo.y) + fabs(lo.z) + fabs(hi.x) + fabs(hi.y) + fabs(hi.z) +
			          motion <
			      1e30))
			{
				// A body gone non-finite this substep (the frame's checks report it): its
				// triangles sit out of the broad phase's way.
				lo = hi = fmMakeVec3(0.0, 0.0, 0.0);
				motion = 0.0;
			}
			extent += fmMax(hi.x - lo.x, fmMax(hi.y - lo.y, hi.z - lo.z));
			double grow = thickness + motion;
			s->lower[k] = fmSub(lo, fmMakeVec3(grow, grow, grow));
			s->upper[k] = fmAdd(hi, fmMakeVec3(grow, grow, grow));
			s->triangleBody[k] = slot;
			s->triangleIndex[k] = t;
		}
	}
	double cell = fmMax(k > 0 ? extent / k : 0.0, 2.0 * thickness);
	s->triangleCount = k;
	return fmSpatialHash_Build(&s->hash, s->lower, s->upper, k, cell > 0.0 ? cell : 1.0);
}

// Whether vertex i of body b was in front of its own triangle @p tri (normal @p n now) at the
// start of the substep: then it crossed the triangle during it, rather than being inside.
static bool fmInFrontAtStart(const fmBody* b, int i, const int* tri, fmVec3 n, double thickness)
{
	fmVec3 q = fmScale(
	    1.0 / 3.0, fmAdd(fmAdd(fmLoad(b->contactStart, tri[0]), fmLoad(b->contactStart, tri[1])),
	                     fmLoad(b->contactStart, tri[2])));
	return fmDot(n, fmSub(fmLoad(b->contactStart, i), q)) > -thickness;
}

// Self-collision: vertex i of body b may touch its own surface triangle @p tri only when the
// two were apart in the rest shape by more than twice the thickness (so a vertex never touches
// the triangles around it, however coarse or sharp the surface).
static bool fmSelfCandidate(const fmBody* b, int i, const int* tri, double thickness)
{
	if (tri[0] == i || tri[1] == i || tri[2] == i)
		return false;
	fmVec3 p = fmLoad(b->x0, i), a = fmLoad(b->x0, tri[0]), bb = fmLoad(b->x0, tri[1]),
	       c = fmLoad(b->x0, tri[2]);
	double w[3];
	fmClosestOnTriangle(p, a, bb, c, w);
	fmVec3 q = fmAdd(fmAdd(fmScale(w[0], a), fmScale(w[1], bb)), fmScale(w[2], c));
	return fmLength(fmSub(p, q)) > 2.0 * thickness;
}

// The point of surface triangle @p tri of body @p o nearest to @p p (weights @p w, point @p q)
// and the triangle's unit normal @p n; false when the triangle is degenerate.
static bool fmNearestOnTriangle(const fmBody* o, const int* tri, fmVec3 p, double w[3], fmVec3* q,
                                fmVec3* n)
{
	fmVec3 a = fmLoad(o->x, tri[0]), b = fmLoad(o->x, tri[1]), c = fmLoad(o->x, tri[2]);
	fmClosestOnTriangle(p, a, b, c, w);
	*q = fmAdd(fmAdd(fmScale(w[0], a), fmScale(w[1], b)), fmScale(w[2], c));
	*n = fmCross(fmSub(b, a), fmSub(c, a));
	double area = fmLength(*n);
	if (!(area > 0.0))
		return false;
	*n = fmScale(1.0 / area, *n);
	return true;
}

// Whether body slot @p other may hold a vertex of body slot @p slot inside its tets (embedded.h).
static bool fmMayHold(const fmWorld* w, int slot, int other)
{
	const fmBody *b = &w->bodies[slot], *o = &w->bodies[other];
	return other != slot && fmFiltersMeet(b->filter, o->filter) && !(b->asleep && o->asleep);
}

// The surface triangle of body slot @p other nearest to point @p p, from the broad phase's
// triangles in query boxes growing from @p radius until the nearest found lies within the box
// (or the box covers the body's): its index, weights and normal into @p found, the distance
// along the normal into *side. False when none is found or a query ran out of memory.
static bool fmNearestTriangle(const fmContactState* s, const fmWorld* w, fmWorkerFinds* wf,
                              int other, fmVec3 p, double radius, fmPairContact* found,
                              double* side)
{
	double limit = fmLength(fmSub(s->bodyUpper[other], s->bodyLower[other]));
	double best = INFINITY;
	const fmBody* o = &w->bodies[other];
	for (double r = radius; r > 0.0; r *= 2.0)
	{
		int count = fmSpatialHash_Query(&s->hash, &wf->query, fmSub(p, fmMakeVec3(r, r, r)),
		                                fmAdd(p, fmMakeVec3(r, r, r)));
		wf->failed = wf->failed || count < 0;
		for (int c = 0; c < count; ++c)
		{
			int item = wf->query.items[c];
			if (s->triangleBody[item] != other)
				continue;
			double wt[3];
			fmVec3 q, n;
			if (!fmNearestOnTriangle(o, fmTriangleOf(o, s->triangleIndex[item]), p, wt, &q, &n))
				continue;
			double distance = fmLength(fmSub(p, q));
			if (!(distance < best))
				continue;
			best = distance;
			found->other = other;
			found->triangle = s->triangleIndex[item];
			memcpy(found->w, wt, sizeof wt);
			found->normal = n;
			*side = fmDot(n, fmSub(p, q));
		}
		if (best <= r || r >= limit || count < 0)
			break;
	}
	return best < INFINITY && !wf->failed;
}

// A contact of surface vertex i of body @p slot, inside body @p holder, with the holder's
// nearest surface triangle into @p found, pushing it out at most at the depenetration speed.
// With @p behind, only while the vertex is still behind that triangle (in front it is out, or
// within the thickness, where a triangle's reach finds it). False when there is none.
static bool fmEmbeddedContact(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf,
                              int slot, int i, int holder, double thickness, bool behind,
                              fmPairContact* found)
{
	fmVec3 p = fmLoad(w->bodies[slot].x, i);
	double side = 0.0;
	if (!fmNearestTriangle(s, w, wf, holder, p, 2.0 * thickness, found, &side) ||
	    (behind && !(side < 0.0)))
		return false;
	found->depth = thickness - side;
	found->reach = w->def.floor.maxDepenetrationSpeed * w->contactStep;
	found->embedded = true;
	return true;
}

// Surface vertex i of body @p slot, which no triangle's reach found, when a tet of another body
// holds it (it went in deeper than the thickness and the substep's motion, squeezed between
// bodies or the floor): its contact with that body (fmEmbeddedContact). False when no tet holds
// it.
static bool fmFindEmbedded(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                           int i, double thickness, fmPairContact* found)
{
	fmVec3 p = fmLoad(w->bodies[slot].x, i);
	int holder = fmTetHash_Holder(&s->tetHash, w, &wf->tetQuery, slot, p, fmMayHold);
	wf->failed = wf->failed || holder == -2;
	return holder >= 0 && fmEmbeddedContact(w, s, wf, slot, i, holder, thickness, false, found);
}

// The contact of surface vertex i of body @p slot: the nearest triangle of another body (or
// its own, self-colliding) it touches or crossed in the substep, queried with @p wf's buffers
// (safe in parallel with other workers'). False when none, or when memory ran short
// (wf->failed).
static bool fmFindPairContact(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf,
                              int slot, int i, double thickness, fmPairContact* found)
{
	const fmBody* b = &w->bodies[slot];
	fmVec3 p = fmLoad(b->x, i);
	double motion = fmMotionOf(s, b, i), reach = thickness + motion;
	if (!(fabs(p.x) + fabs(p.y) + fabs(p.z) + reach < 1e30))
		return false; // non-finite: the frame's checks report it
	fmVec3 lo = fmSub(p, fmMakeVec3(reach, reach, reach));
	fmVec3 hi = fmAdd(p, fmMakeVec3(reach, reach, reach));
	if (!fmNearOtherBody(w, s, slot, lo, hi, false))
		return false;
	double start = fmSeconds();
	int count = fmSpatialHash_Query(&s->hash, &wf->query, lo, hi);
	wf->broadPhase += fmSeconds() - start;
	wf->failed = wf->failed || count < 0;
	double best = INFINITY;
	int bestItem = -1;
	for (int c = 0; c < count; ++c)
	{
		int item = wf->query.items[c], other = s->triangleBody[item];
		fmVec3 tlo = s->lower[item], thi = s->upper[item];
		if (hi.x < tlo.x || lo.x > thi.x || hi.y < tlo.y || lo.y > thi.y || hi.z < tlo.z ||
		    lo.z > thi.z)
			continue; // the triangle's grown box is out of the vertex's reach
		const fmBody* o = &w->bodies[other];
		if ((other == slot && !b->selfCollision) || !fmFiltersMeet(b->filter, o->filter) ||
		    (b->asleep && o->asleep))
			continue;
		const int* tri = fmTriangleOf(o, s->triangleIndex[item]);
		if (other == slot && !fmSelfCandidate(b, i, tri, thickness))
			continue;
		double wt[3];
		fmVec3 q, n;
		if (!fmNearestOnTriangle(o, tri, p, wt, &q, &n))
			continue;
		double bound = reach + fmMax(fmMotionOf(s, o, tri[0]),
		                             fmMax(fmMotionOf(s, o, tri[1]), fmMotionOf(s, o, tri[2])));
		double distance = fmLength(fmSub(p, q)), side = fmDot(n, fmSub(p, q));
		// (Before a step, a plane within the reach of the step's motion may be met.)
		double near = s->predict > 0.0 ? bound : thickness;
		bool touches = distance <= bound && side < near && side > -bound;
		// A body's own interior lies behind all of its triangles: a vertex of it counts
		// against its own surface only from the front (or just behind, within the thickness),
		// and only within the thickness (with the motion's reach, a vertex would meet the
		// triangles of its own flat face that move with it).
		if (other == slot)
			touches = side > -thickness ? distance <= thickness && side < thickness
			                            : s->predict == 0.0 && distance <= bound &&
			                                  fmInFrontAtStart(b, i, tri, n, thickness);
		// The nearest triangle, preferring one the vertex lies straight above or below (near
		// an edge, the face under the vertex, not the side face that shares the edge).
		double along = distance > 0.0 ? fabs(side) / distance : 1.0;
		double score = distance * (2.0 - along);
		if (touches && (score < best || (score == best && item < bestItem)))
		{
			best = score;
			bestItem = item;
			found->other = other;
			found->triangle = s->triangleIndex[item];
			memcpy(found->w, wt, sizeof wt);
			found->normal = n;
			found->depth = thickness - side;
		}
	}
	found->body = slot;
	found->vertex = i;
	found->impulse = 0.0;
	found->embedded = false;
	if (bestItem < 0 && s->tetHashReady)
		return fmFindEmbedded(w, s, wf, slot, i, thickness, found);
	// Held earlier in the frame (fmFindEmbedded): pushed on in every substep while still inside.
	if (bestItem < 0 && b->embeddedHolder[i] > 0)
		return fmEmbeddedContact(w, s, wf, slot, i, b->embeddedHolder[i] - 1, thickness, true,
		                         found);
	if (bestItem >= 0)
	{
		// Depenetration is limited as against the floor: what the substep's own approach
		// explains goes at once, older penetration at most the depenetration speed (bodies
		// created overlapping come apart gently instead of being catapulted).
		const fmBody* o = &w->bodies[found->other];
		const int* tri = fmTriangleOf(o, found->triangle);
		fmVec3 approach = fmSub(p, fmLoad(b->contactStart, i));
		for (int c = 0; c < 3; ++c)
			approach = fmMulAdd(approach, -found->w[c],
			                    fmSub(fmLoad(o->x, tri[c]), fmLoad(o->contactStart, tri[c])));
		found->reach = fmMax(w->def.floor.maxDepenetrationSpeed * w->contactStep,
		                     fmMax(0.0, -fmDot(approach, found->normal)) + thickness);
	}
	return bestItem >= 0;
}

static double fmInverseMass(const fmBody* b, int i)
{
	return b->pinned[i] == FM_PIN_ALL || b->asleep ? 0.0 : 1.0 / b->mass[i];
}

// Note the state of a contact's vertex and its triangle's before the stage changes them.
static bool fmTouchPair(fmContactState* s, fmBody* b, fmBody* o, const fmPairContact* pc)
{
	const int* tri = fmTriangleOf(o, pc->triangle);
	return fmTouch(s, b, pc->body, pc->vertex) && fmTouch(s, o, pc->other, tri[0]) &&
	       fmTouch(s, o, pc->other, tri[1]) && fmTouch(s, o, pc->other, tri[2]);
}

// One projection of a vertex-triangle contact: the gap along the normal back to the thickness,
// shared by inverse masses. False when memory is short.
static bool fmProjectPair(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness)
{
	fmBody* b = &w->bodies[pc->body];
	fmBody* o = &w->bodies[pc->other];
	const int* tri = fmTriangleOf(o, pc->triangle);
	fmVec3 q = fmMakeVec3(0.0, 0.0, 0.0);
	double weight = fmInverseMass(b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		q = fmMulAdd(q, pc->w[c], fmLoad(o->x, tri[c]));
		weight += pc->w[c] * pc->w[c] * fmInverseMass(o, tri[c]);
	}
	double gap = thickness - fmDot(pc->normal, fmSub(fmLoad(b->x, pc->vertex), q));
	gap = fmMin(gap, pc->reach);
	if (!(gap > 0.0) || !(weight > 0.0))
		return true;
	if (!fmTouchPair(s, b, o, pc))
		return false;
	pc->reach -= gap;
	double lambda = gap / weight;
	fmVec3 x0 = fmLoad(b->x, pc->vertex);
	fmStore(b->x, pc->vertex, fmMulAdd(x0, lambda * fmInverseMass(b, pc->vertex), pc->normal));
	fmKeepPins(b, pc->vertex, x0);
	fmKeepAboveFloor(w, b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		fmVec3 y0 = fmLoad(o->x, tri[c]);
		double share = -lambda * pc->w[c] * fmInverseMass(o, tri[c]);
		fmStore(o->x, tri[c], fmMulAdd(y0, share, pc->normal));
		fmKeepPins(o, tri[c], y0);
		fmKeepAboveFloor(w, o, tri[c]);
	}
	return true;
}

static double fmPairFriction(const fmWorld* w, const fmBody* a, const fmBody* b)
{
	double fa = a->friction >= 0.0 ? a->friction : w->def.contact.friction;
	double fb = b->friction >= 0.0 ? b->friction : w->def.contact.friction;
	return sqrt(fa * fb);
}

// The velocity response of a vertex-triangle contact: the relative velocity of the vertex and
// the triangle's point loses its approach (restitution) and some slip (friction), the impulse
// shared by inverse masses. False when memory is short.
static bool fmRespondPair(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness)
{
	fmBody* b = &w->bodies[pc->body];
	fmBody* o = &w->bodies[pc->other];
	const int* tri = fmTriangleOf(o, pc->triangle);
	fmVec3 vq = fmMakeVec3(0.0, 0.0, 0.0);
	double weight = fmInverseMass(b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		vq = fmMulAdd(vq, pc->w[c], fmLoad(o->v, tri[c]));
		weight += pc->w[c] * pc->w[c] * fmInverseMass(o, tri[c]);
	}
	if (!(weight > 0.0))
		return true;
	if (!fmTouchPair(s, b, o, pc))
		return false;
	fmVec3 vp = fmLoad(b->v, pc->vertex), relative = fmSub(vp, vq), before = relative;
	// After an implicit step the penalty held the pair apart during the step (penalty.h): its
	// impulse per mass bounds friction too. (Friction between bodies inside the solve, as
	// against colliders, made resting stacks jitter and piles of houses blow up: measured,
	// docs/contact.md.)
	double pushed = w->def.integrator == fm_implicit && pc->depth > 0.0
	                    ? FM_PENALTY_KAPPA * pc->depth / w->contactStep
	                    : 0.0;
	fmImpact(&relative, pc->normal, w->def.contact.restitution, fmPairFriction(w, b, o), pushed);
	// Explicit: a vertex caught inside the other body leaves it at the depenetration speed, as
	// one below the floor does: pushed out by the projection alone, it had no velocity to leave
	// with, and the elastic forces pulled it back in every substep (boxes created half inside
	// each other stayed so). The implicit solve carries the push into the velocities itself.
	double separating = fmDot(relative, pc->normal);
	if (pc->embedded && w->def.integrator != fm_implicit &&
	    separating < w->def.floor.maxDepenetrationSpeed)
		relative = fmMulAdd(relative, w->def.floor.maxDepenetrationSpeed - separating, pc->normal);
	fmVec3 impulse = fmScale(1.0 / weight, fmSub(relative, before)); // N s on the vertex
	pc->impulse = fmDot(impulse, pc->normal);
	// A creeping slip that friction takes back leaves the positions too (fmCreepStep).
	double h = fmCreepStep(w, fmSub(relative, before), pc->normal, thickness);
	fmVec3 slip = fmScale(h, fmMulAdd(impulse, -pc->impulse, pc->normal));
	fmVec3 x = fmLoad(b->x, pc->vertex);
	double inverse = fmInverseMass(b, pc->vertex);
	fmStore(b->v, pc->vertex, fmMulAdd(vp, inverse, impulse));
	fmStore(b->x, pc->vertex, fmMulAdd(x, inverse, slip));
	fmKeepPins(b, pc->vertex, x);
	for (int c = 0; c < 3; ++c)
	{
		fmVec3 v0 = fmLoad(o->v, tri[c]), y = fmLoad(o->x, tri[c]);
		double share = -pc->w[c] * fmInverseMass(o, tri[c]);
		fmStore(o->v, tri[c], fmMulAdd(v0, share, impulse));
		fmStore(o->x, tri[c], fmMulAdd(y, share, slip));
		fmKeepPins(o, tri[c], y);
	}
	return true;
}

// ---- edge against edge -------------------------------------------------------------------------

// Parameters s, t in [0, 1] of the closest points of segments p0-p1 and q0-q1 (Ericson 5.1.9).
static void fmClosestSegments(fmVec3 p0, fmVec3 p1, fmVec3 q0, fmVec3 q1, double* s, double* t)
{
	fmVec3 d1 = fmSub(p1, p0), d2 = fmSub(q1, q0), r = fmSub(p0, q0);
	double a = fmDot(d1, d1), e = fmDot(d2, d2), f = fmDot(d2, r), c = fmDot(d1, r);
	double b = fmDot(d1, d2), denominator = a * e - b * b;
	*s = denominator > 1e-12 * a * e ? fmMin(fmMax((b * f - c * e) / denominator, 0.0), 1.0) : 0.0;
	*t = e > 0.0 ? (b * *s + f) / e : 0.0;
	if (*t < 0.0 || *t > 1.0)
	{
		*t = fmMin(fmMax(*t, 0.0), 1.0);
		*s = a > 0.0 ? fmMin(fmMax((b * *t - c) / a, 0.0), 1.0) : 0.0;
	}
}

static fmVec3 fmEdgePoint(const double* x, const int e[2], double s)
{
	return fmMulAdd(fmLoad(x, e[0]), s, fmSub(fmLoad(x, e[1]), fmLoad(x, e[0])));
}

// Edge e of body b (@p side: the normal of a triangle of b's with that edge) against the edges
// of triangle @p tri of body o: a contact when their closest points are inside both edges and
// within the thickness, or when the edges crossed during the substep (the direction between the
// closest points turned over); before an implicit step (s->predict), when they are within
// reach of the step's motion and face each other. Appends to the edge list.
static bool fmEdgeAgainstTriangle(const fmContactState* s, fmWorkerFinds* wf, const fmBody* b,
                                  int slot, const int e[2], fmVec3 side, const fmBody* o, int other,
                                  const int* tri, double thickness, int item)
{
	// (Only the frozen planes before an implicit step ask which way the faces look.)
	fmVec3 face = s->predict > 0.0 ? fmTriangleCross(o, tri) : fmMakeVec3(0.0, 0.0, 0.0);
	for (int k = 0; k < 3; ++k)
	{
		int f[2] = {tri[k], tri[(k + 1) % 3]};
		if (f[0] > f[1])
			continue; // each edge of o once (closed surfaces list it both ways)
		double sa, tb;
		fmClosestSegments(fmLoad(b->x, e[0]), fmLoad(b->x, e[1]), fmLoad(o->x, f[0]),
		                  fmLoad(o->x, f[1]), &sa, &tb);
		if (sa <= 0.0 || sa >= 1.0 || tb <= 0.0 || tb >= 1.0)
			continue;
		fmVec3 d = fmSub(fmEdgePoint(b->x, e, sa), fmEdgePoint(o->x, f, tb));
		fmVec3 d0 = fmSub(fmEdgePoint(b->contactStart, e, sa), fmEdgePoint(o->contactStart, f, tb));
		double distance = fmLength(d), start = fmLength(d0);
		double reach = thickness + fmMotionOf(s, b, e[0]) + fmMotionOf(s, b, e[1]) +
		               fmMotionOf(s, o, f[0]) + fmMotionOf(s, o, f[1]);
		// A crossing: the direction between the closest points turned over within the substep
		// while they were within reach of each other. (Before an implicit step: edges within
		// reach of the step's motion, for its frozen edge planes.)
		bool crossed = s->predict == 0.0 && fmDot(d, d0) < 0.0 && start > 0.0 && start < reach;
		double near = s->predict > 0.0 ? reach : thickness;
		if (!(crossed || (distance < near && distance > 0.0)))
			continue;
		// A frozen plane only between edges that face each other: the direction from o's edge
		// to b's leaves o through the face and enters b against the face of b's edge (@p side).
		// Edges of bodies already inside each other would otherwise be held there.
		if (s->predict > 0.0 && !(fmDot(d, face) > 0.0 && fmDot(d, side) < 0.0))
			continue;
		if (!fmGrowArray((void**)&wf->edges, &wf->edgeCapacity, wf->edgeCount, wf->edgeCount + 1,
		                 sizeof(fmEdgeContact)))
			return false;
		fmEdgeContact* c = &wf->edges[wf->edgeCount++];
		c->body = slot, c->other = other;
		c->a[0] = e[0], c->a[1] = e[1], c->b[0] = f[0], c->b[1] = f[1];
		c->s = sa, c->t = tb;
		c->normal = crossed ? fmScale(1.0 / start, d0) : fmScale(1.0 / distance, d);
		c->reach = reach;
		c->impulse = 0.0;
		c->item = item;
		c->sequence = wf->edgeCount; // increasing within the item
	}
	return true;
}

// Surface edge @p edge (triangle edge / 3, edge % 3) of body @p slot against the surface edges
// of the bodies of higher slots near it (so each pair of bodies once), into @p wf's list.
static void fmFindEdgeContacts(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf,
                               int slot, int edge, double thickness, int item)
{
	const fmBody* b = &w->bodies[slot];
	const int* tri = fmTriangleOf(b, edge / 3);
	int e[2] = {tri[edge % 3], tri[(edge % 3 + 1) % 3]};
	if (e[0] > e[1])
		return;
	fmVec3 side = s->predict > 0.0 ? fmTriangleCross(b, tri) : fmMakeVec3(0.0, 0.0, 0.0);
	fmVec3 p = fmLoad(b->x, e[0]), q = fmLoad(b->x, e[1]);
	double reach = thickness + fmMax(fmMotionOf(s, b, e[0]), fmMotionOf(s, b, e[1]));
	fmVec3 lo =
	    fmMakeVec3(fmMin(p.x, q.x) - reach, fmMin(p.y, q.y) - reach, fmMin(p.z, q.z) - reach);
	fmVec3 hi =
	    fmMakeVec3(fmMax(p.x, q.x) + reach, fmMax(p.y, q.y) + reach, fmMax(p.z, q.z) + reach);
	if (!(fabs(lo.x) + fabs(lo.y) + fabs(lo.z) + fabs(hi.x) + fabs(hi.y) + fabs(hi.z) < 1e30))
		return; // non-finite: the frame's checks report it
	if (!fmNearOtherBody(w, s, slot, lo, hi, true))
		return;
	double start = fmSeconds();
	int count = fmSpatialHash_Query(&s->hash, &wf->query, lo, hi);
	wf->broadPhase += fmSeconds() - start;
	wf->failed = wf->failed || count < 0;
	for (int c = 0; c < count && !wf->failed; ++c)
	{
		int found = wf->query.items[c], other = s->triangleBody[found];
		const fmBody* o = &w->bodies[other];
		fmVec3 ilo = s->lower[found], ihi = s->upper[found];
		if (other <= slot || !fmFiltersMeet(b->filter, o->filter) || (b->asleep && o->asleep) ||
		    hi.x < ilo.x || lo.x > ihi.x || hi.y < ilo.y || lo.y > ihi.y || hi.z < ilo.z ||
		    lo.z > ihi.z)
			continue;
		wf->failed =
		    !fmEdgeAgainstTriangle(s, wf, b, slot, e, side, o, other,
		                           fmTriangleOf(o, s->triangleIndex[found]), thickness, item);
	}
}

// The four weights of an edge contact's vertices in its projection and response.
static void fmEdgeWeights(const fmEdgeContact* c, double weights[4])
{
	weights[0] = 1.0 - c->s, weights[1] = c->s, weights[2] = -(1.0 - c->t), weights[3] = -c->t;
}

static bool fmTouchEdges(fmContactState* s, fmBody* b, fmBody* o, const fmEdgeContact* c)
{
	return fmTouch(s, b, c->body, c->a[0]) && fmTouch(s, b, c->body, c->a[1]) &&
	       fmTouch(s, o, c->other, c->b[0]) && fmTouch(s, o, c->other, c->b[1]);
}

// One projection of an edge contact: the edges apart along the normal to the thickness, shared
// by inverse masses (momentum kept).
static bool fmProjectEdges(fmWorld* w, fmContactState* s, fmEdgeContact* c, double thickness)
{
	fmBody* b = &w->bodies[c->body];
	fmBody* o = &w->bodies[c->other];
	double weights[4], inverse[4] = {fmInverseMass(b, c->a[0]), fmInverseMass(b, c->a[1]),
	                                 fmInverseMass(o, c->b[0]), fmInverseMass(o, c->b[1])};
	fmEdgeWeights(c, weights);
	double sum = 0.0;
	for (int k = 0; k < 4; ++k)
		sum += weights[k] * weights[k] * inverse[k];
	fmVec3 d = fmSub(fmEdgePoint(b->x, c->a, c->s), fmEdgePoint(o->x, c->b, c->t));
	double gap = fmMin(thickness - fmDot(c->normal, d), c->reach);
	if (!(gap > 0.0) || !(sum > 0.0))
		return true;
	if (!fmTouchEdges(s, b, o, c))
		return false;
	c->reach -= gap;
	double lambda = gap / sum;
	fmBody* bodies[4] = {b, b, o, o};
	const int vertices[4] = {c->a[0], c->a[1], c->b[0], c->b[1]};
	for (int k = 0; k < 4; ++k)
	{
		fmVec3 x0 = fmLoad(bodies[k]->x, vertices[k]);
		fmStore(bodies[k]->x, vertices[k],
		        fmMulAdd(x0, lambda * weights[k] * inverse[k], c->normal));
		fmKeepPins(bodies[k], vertices[k], x0);
		fmKeepAboveFloor(w, bodies[k], vertices[k]);
	}
	return true;
}

// Restitution and friction on the edges' relative velocity at the closest points.
static bool fmRespondEdges(fmWorld* w, fmContactState* s, fmEdgeContact* c)
{
	fmBody* b = &w->bodies[c->body];
	fmBody* o = &w->bodies[c->other];
	double weights[4], inverse[4] = {fmInverseMass(b, c->a[0]), fmInverseMass(b, c->a[1]),
	                                 fmInverseMass(o, c->b[0]), fmInverseMass(o, c->b[1])};
	fmEdgeWeights(c, weights);
	fmBody* bodies[4] = {b, b, o, o};
	const int vertices[4] = {c->a[0], c->a[1], c->b[0], c->b[1]};
	double sum = 0.0;
	fmVec3 relative = fmMakeVec3(0.0, 0.0, 0.0);
	for (int k = 0; k < 4; ++k)
	{
		sum += weights[k] * weights[k] * inverse[k];
		relative = fmMulAdd(relative, weights[k], fmLoad(bodies[k]->v, vertices[k]));
	}
	if (!(sum > 0.0))
		return true;
	if (!fmTouchEdges(s, b, o, c))
		return false;
	fmVec3 before = relative;
	fmImpact(&relative, c->normal, w->def.contact.restitution, fmPairFriction(w, b, o), 0.0);
	fmVec3 impulse = fmScale(1.0 / sum, fmSub(relative, before));
	c->impulse = fmDot(impulse, c->normal);
	for (int k = 0; k < 4; ++k)
	{
		fmVec3 x = fmLoad(bodies[k]->x, vertices[k]);
		fmVec3 v = fmLoad(bodies[k]->v, vertices[k]);
		fmStore(bodies[k]->v, vertices[k], fmMulAdd(v, weights[k] * inverse[k], impulse));
		fmKeepPins(bodies[k], vertices[k], x);
	}
	return true;
}

// An edge contact into the contact list (at the nearer end of the first body's edge) and the
// frame's pairs.
static bool fmRecordEdgeContact(fmWorld* w, fmContactState* s, const fmEdgeContact* c)
{
	fmContactPoint* point = fmNewPoint(s);
	if (point == NULL)
		return false;
	const fmBody* b = &w->bodies[c->body];
	point->body = fmWorldBodyId(w, c->body);
	point->vertex = b->userVertex[c->s < 0.5 ? c->a[0] : c->a[1]];
	point->otherBody = fmWorldBodyId(w, c->other);
	point->point = fmEdgePoint(b->x, c->a, c->s);
	point->normal = c->normal;
	point->impulse = c->impulse;
	return fmRecordPair(s, ((uint64_t)(uint32_t)c->body << 32) | (uint32_t)c->other);
}

// ---- parallel detection ------------------------------------------------------------------------

typedef struct fmDetectTask
{
	const fmWorld* w;
	fmContactState* s;
	double thickness;
} fmDetectTask;

// The workers' buffers ready for this detection: stamps for the hash's items, lists emptied.
static bool fmStartWorkers(const fmWorld* w, fmContactState* s)
{
	for (int k = 0; k < w->tasks.workerCount; ++k)
	{
		fmWorkerFinds* wf = &s->workers[k];
		if (!fmHashQuery_Reserve(&wf->query, &s->hash) ||
		    (s->tetHashReady && !fmHashQuery_Reserve(&wf->tetQuery, &s->tetHash.hash)))
			return false;
		wf->edgeCount = 0;
		wf->broadPhase = 0.0;
		wf->failed = false;
	}
	return true;
}

// The workers' broad-phase time into the profile; false when one ran out of memory.
static bool fmEndWorkers(fmWorld* w, const fmContactState* s)
{
	bool ok = true;
	for (int k = 0; k < w->tasks.workerCount; ++k)
	{
		w->profile.broadPhase += 1e3 * s->workers[k].broadPhase;
		ok = ok && !s->workers[k].failed;
	}
	return ok;
}

// Whether body @p slot has detection items: it is near another body (with @p edges, one of a
// higher slot: an edge is tested against those only).
static bool fmHasItems(const fmWorld* w, const fmContactState* s, int slot, bool edges)
{
	return w->bodies[slot].x && s->bodyNear[slot] &&
	       (!edges || fmNearOtherBody(w, s, slot, s->bodyLower[slot], s->bodyUpper[slot], true));
}

// The detection items: (body slot, surface vertex) or, with @p edges, (body slot, triangle
// edge 3 t + k) for every body that has some (fmHasItems). Returns how many, or -1 when memory
// is short.
static int fmListItems(const fmWorld* w, fmContactState* s, bool edges)
{
	int n = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		if (fmHasItems(w, s, slot, edges))
			n += edges ? 3 * w->bodies[slot].triangleCount : w->bodies[slot].surfaceVertexCount;
	if (!fmGrowArray((void**)&s->items, &s->itemCapacity, 0, 2 * n, sizeof(int)))
		return -1;
	n = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		int count = !fmHasItems(w, s, slot, edges) ? 0
		            : edges                        ? 3 * b->triangleCount
		                                           : b->surfaceVertexCount;
		for (int k = 0; k < count; ++k, ++n)
		{
			s->items[2 * n] = slot;
			s->items[2 * n + 1] = edges ? k : b->surfaceVertex[k];
		}
	}
	return n;
}

static void fmDetectVertexRange(int start, int end, int worker, void* context)
{
	fmDetectTask* t = context;
	fmContactState* s = t->s;
	for (int k = start; k < end; ++k)
		s->hit[k] = fmFindPairContact(t->w, s, &s->workers[worker], s->items[2 * k],
		                              s->items[2 * k + 1], t->thickness, &s->found[k]);
}

// Every surface vertex of the bodies near another, in parallel: its contact into s->found[k]
// where s->hit[k], in a fixed order whatever the workers. Returns how many items, or -1 when
// memory is short.
static int fmDetectVertices(fmWorld* w, fmContactState* s, double thickness)
{
	int n = fmListItems(w, s, false);
	if (n < 0 || !fmStartWorkers(w, s))
		return -1;
	if (n > s->foundCapacity)
	{
		FM_FREE_ARRAY(s->found, fmPairContact, s->foundCapacity);
		FM_FREE_ARRAY(s->hit, uint8_t, s->foundCapacity);
		s->found = FM_ALLOC_ARRAY(fmPairContact, n);
		s->hit = FM_ALLOC_ARRAY(uint8_t, n);
		s->foundCapacity = s->found && s->hit ? n : 0;
		if (s->foundCapacity == 0)
		{
			FM_FREE_ARRAY(s->found, fmPairContact, n);
			FM_FREE_ARRAY(s->hit, uint8_t, n);
			return -1;
		}
	}
	fmDetectTask task = {w, s, thickness};
	fmParallelForBalanced(&w->tasks, n, FM_CONTACT_MIN_RANGE, fmDetectVertexRange, &task);
	return fmEndWorkers(w, s) ? n : -1;
}

static void fmDetectEdgeRange(int start, int end, int worker, void* context)
{
	fmDetectTask* t = context;
	fmContactState* s = t->s;
	for (int k = start; k < end; ++k)
		fmFindEdgeContacts(t->w, s, &s->workers[worker], s->items[2 * k], s->items[2 * k + 1],
		                   t->thickness, k);
}

static int fmCompareEdgeContacts(const void* a, const void* b)
{
	const fmEdgeContact *x = a, *y = b;
	if (x->item != y->item)
		return x->item < y->item ? -1 : 1;
	return (x->sequence > y->sequence) - (x->sequence < y->sequence);
}

// Every surface edge of the bodies near another against the other bodies' edges, in parallel:
// the contacts into s->edgeContacts in item order whatever the workers. False when memory is
// short.
static bool fmDetectEdges(fmWorld* w, fmContactState* s, double thickness)
{
	int n = fmListItems(w, s, true);
	if (n < 0 || !fmStartWorkers(w, s))
		return false;
	fmDetectTask task = {w, s, thickness};
	fmParallelForBalanced(&w->tasks, n, FM_CONTACT_MIN_RANGE, fmDetectEdgeRange, &task);
	if (!fmEndWorkers(w, s))
		return false;
	int total = 0;
	s->edgeContactCount = 0;
	for (int k = 0; k < w->tasks.workerCount; ++k)
		total += s->workers[k].edgeCount;
	if (!fmGrowArray((void**)&s->edgeContacts, &s->edgeContactCapacity, 0, total,
	                 sizeof(fmEdgeContact)))
		return false;
	for (int k = 0; k < w->tasks.workerCount && total > 0; ++k)
	{
		if (s->workers[k].edgeCount > 0)
			memcpy(s->edgeContacts + s->edgeContactCount, s->workers[k].edges,
			       sizeof(fmEdgeContact) * (size_t)s->workers[k].edgeCount);
		s->edgeContactCount += s->workers[k].edgeCount;
	}
	if (total > 1)
		qsort(s->edgeContacts, (size_t)s->edgeContactCount, sizeof(fmEdgeContact),
		      fmCompareEdgeContacts);
	return true;
}

// An awake body touches a sleeping one: the sleeper stays still (no inverse mass) and wakes,
// with its island, at the end of the frame (island.h).
static void fmWakeSleeper(fmWorld* w, const fmPairContact* found)
{
	fmBody* b = &w->bodies[found->body];
	fmBody* o = &w->bodies[found->other];
	if (b->asleep || o->asleep)
		(b->asleep ? b : o)->wakeRequested = true;
}

static bool fmCollideBodies(fmWorld* w, fmContactState* s, double thickness)
{
	double start = fmSeconds();
	if (!fmBuildTriangles(w, s, thickness))
		return false;
	// Embedded vertices are looked for once a frame (a tet hash every substep cost a tenth of
	// the frame of ten houses piled, implicit), and pushed out by a frame's depenetration.
	s->tetHashReady = w->embeddedSearch && fmTetHash_Build(&s->tetHash, w, s->bodyNear);
	w->profile.broadPhase += 1e3 * (fmSeconds() - start);
	s->pairContactCount = 0;
	int n = fmDetectVertices(w, s, thickness);
	if (s->tetHashReady)
		w->embeddedSearch = false;
	s->tetHashReady = false;
	if (n < 0 || !fmGrowArray((void**)&s->pairContacts, &s->pairContactCapacity, 0, n,
	                          sizeof(fmPairContact)))
		return false;
	for (int k = 0; k < n; ++k)
		if (s->hit[k])
		{
			const fmPairContact* found = &s->found[k];
			fmWakeSleeper(w, found);
			if (found->embedded)
				w->bodies[found->body].embeddedHolder[found->vertex] = found->other + 1;
			s->pairContacts[s->pairContactCount++] = *found;
		}
	// Edge against edge, explicit substeps only: implicit steps hold edges apart inside the
	// solve (frozen edge planes, fmPredictPlanes). Projecting them after the solve as well made
	// the three-house pile crawl (over 300 s against 49 s; before the edge planes it put 12
	// vertices inside another house against 1; docs/contact.md).
	s->edgeContactCount = 0;
	if (w->def.integrator != fm_implicit && !fmDetectEdges(w, s, thickness))
		return false;
	for (int pass = 0; pass < w->def.contact.iterations; ++pass)
	{
		for (int c = 0; c < s->pairContactCount; ++c)
			if (!fmProjectPair(w, s, &s->pairContacts[c], thickness))
				return false;
		for (int c = 0; c < s->edgeContactCount; ++c)
			if (!fmProjectEdges(w, s, &s->edgeContacts[c], thickness))
				return false;
	}
	for (int c = 0; c < s->edgeContactCount; ++c)
		if (!fmRespondEdges(w, s, &s->edgeContacts[c]) ||
		    !fmRecordEdgeContact(w, s, &s->edgeContacts[c]))
			return false;
	for (int c = 0; c < s->pairContactCount; ++c)
	{
		fmPairContact* pc = &s->pairContacts[c];
		if (!fmRespondPair(w, s, pc, thickness))
			return false;
		fmContactPoint* point = fmNewPoint(s);
		if (point == NULL)
			return false;
		point->body = fmWorldBodyId(w, pc->body);
		point->vertex = w->bodies[pc->body].userVertex[pc->vertex];
		point->otherBody = fmWorldBodyId(w, pc->other);
		point->point = fmLoad(w->bodies[pc->body].x, pc->vertex);
		point->normal = pc->normal;
		point->depth = pc->depth;
		point->impulse = pc->impulse;
		int low = pc->body < pc->other ? pc->body : pc->other;
		int high = pc->body < pc->other ? pc->other : pc->body;
		if (low != high && !fmRecordPair(s, ((uint64_t)(uint32_t)low << 32) | (uint32_t)high))
			return false;
	}
	return true;
}

// ---- the implicit step's planes ----------------------------------------------------------------

static bool fmAddEdgePlane(fmBody* b, const fmEdgePlane* plane)
{
	if (!fmGrowArray((void**)&b->edgePlanes, &b->edgePlaneCapacity, b->edgePlaneCount,
	                 b->edgePlaneCount + 1, sizeof(fmEdgePlane)))
		return false;
	b->edgePlanes[b->edgePlaneCount++] = *plane;
	return true;
}

// Before an implicit step: each surface vertex's nearest triangle of another body that the
// step's motion may reach, frozen as a plane (n, n . q) in b->contactPlane for the step's
// penalty (penalty.h), NaN where there is none; and each pair of surface edges of two bodies
// within that reach, frozen as a plane for each edge (b->edgePlanes).
static bool fmPredictPlanes(fmWorld* w, fmContactState* s, double thickness, double h)
{
	// (fmContact_BeginSubstep has set every plane to none.)
	s->predict = h;
	int n = fmBuildTriangles(w, s, thickness) ? fmDetectVertices(w, s, thickness) : -1;
	for (int k = 0; k < n; ++k)
	{
		if (!s->hit[k])
			continue;
		const fmPairContact* found = &s->found[k];
		fmWakeSleeper(w, found);
		const fmBody* o = &w->bodies[found->other];
		const int* tri = fmTriangleOf(o, found->triangle);
		fmVec3 q = fmMakeVec3(0.0, 0.0, 0.0);
		for (int c = 0; c < 3; ++c)
			q = fmMulAdd(q, found->w[c], fmLoad(o->x, tri[c]));
		double* plane = w->bodies[found->body].contactPlane + 4 * (size_t)found->vertex;
		plane[0] = found->normal.x;
		plane[1] = found->normal.y;
		plane[2] = found->normal.z;
		plane[3] = fmDot(found->normal, q);
	}
	bool ok = n >= 0 && fmDetectEdges(w, s, thickness);
	for (int k = 0; ok && k < s->edgeContactCount; ++k)
	{
		const fmEdgeContact* c = &s->edgeContacts[k];
		fmBody* b = &w->bodies[c->body];
		fmBody* o = &w->bodies[c->other];
		fmVec3 p = fmEdgePoint(b->x, c->a, c->s), q = fmEdgePoint(o->x, c->b, c->t);
		fmEdgePlane mine = {c->a[0], c->a[1], c->s, c->normal, fmDot(c->normal, q)};
		fmVec3 away = fmScale(-1.0, c->normal);
		fmEdgePlane theirs = {c->b[0], c->b[1], c->t, away, fmDot(away, p)};
		ok = fmAddEdgePlane(b, &mine) && fmAddEdgePlane(o, &theirs);
	}
	s->edgeContactCount = 0;
	s->predict = 0.0;
	return ok;
}

// ---- the energy ledger -------------------------------------------------------------------------

// Swap the state (positions and velocities) of body @p slot's touched vertices with their
// state before the stage.
static void fmSwapTouched(fmWorld* w, fmContactState* s, int slot)
{
	fmBody* b = &w->bodies[slot];
	for (int k = 0; k < s->touchedCount; ++k)
	{
		fmTouched* t = &s->touched[k];
		if (t->body != slot)
			continue;
		fmVec3 x = fmLoad(b->x, t->vertex), v = fmLoad(b->v, t->vertex);
		fmStore(b->x, t->vertex, t->x);
		fmStore(b->v, t->vertex, t->v);
		t->x = x;
		t->v = v;
	}
}

// Elastic energy (J) and power sum v . f (W) of the tets in @p tets: the parts of a body's
// energy and of symplectic Euler's shadow term that a change of their vertices changes.
static void fmTetsEnergy(const fmBody* b, const int* tets, int count, double* energy, double* power)
{
	*energy = *power = 0.0;
	for (int k = 0; k < count; ++k)
	{
		int t = tets[k];
		fmMat3 F = fmTetDeformation(b, b->x, t), P;
		double V0 = b->restVolume[t];
		*energy += V0 * fmMaterial_Evaluate(fmTetMaterial(b, t), &F, &P, NULL);
		fmMat3 H = fmMatMulT(&P, &b->DmInv[t]);
		fmVec3 sum = {0.0, 0.0, 0.0};
		for (int a = 1; a < 4; ++a)
		{
			fmVec3 fa = fmScale(-V0, fmColumn(&H, a - 1));
			sum = fmAdd(sum, fa);
			*power += fmDot(fa, fmLoad(b->v, b->tets[4 * t + a]));
		}
		*power -= fmDot(sum, fmLoad(b->v, b->tets[4 * t]));
	}
}

// The same over a whole spring body.
static bool fmSpringEnergyPower(fmContactState* s, const fmBody* b, double* energy, double* power)
{
	int n3 = 3 * b->vertexCount;
	if (!fmGrowArray((void**)&s->forces, &s->forceCapacity, 0, n3, sizeof(double)))
		return false;
	memset(s->forces, 0, sizeof(double) * (size_t)n3);
	*energy = fmAddElasticForces(b, b->x, s->forces);
	*power = 0.0;
	for (int k = 0; k < n3; ++k)
		*power += s->forces[k] * b->v[k];
	return true;
}

// The tets around body @p slot's touched vertices into s->tets; returns how many (-1 when
// memory is short).
static int fmTouchedTets(fmWorld* w, fmContactState* s, int slot)
{
	fmBody* b = &w->bodies[slot];
	int count = 0;
	for (int k = 0; k < s->touchedCount; ++k)
	{
		int i = s->touched[k].vertex;
		if (s->touched[k].body != slot)
			continue;
		for (int e = b->vertexTetStart[i]; e < b->vertexTetStart[i + 1]; ++e)
		{
			int t = b->vertexTets[e] / 4;
			if (b->contactTetMark[t])
				continue;
			if (!fmGrowArray((void**)&s->tets, &s->tetCapacity, count, count + 1, sizeof(int)))
				return -1;
			b->contactTetMark[t] = 1;
			s->tets[count++] = t;
		}
	}
	for (int k = 0; k < count; ++k)
		b->contactTetMark[s->tets[k]] = 0;
	return count;
}

// How the stage changed body @p slot's elastic energy (J) and its power sum v . f (W): over
// the tets around its touched vertices (a spring body: over the whole body), after minus
// before.
static bool fmElasticChange(fmWorld* w, fmContactState* s, int slot, double* energy, double* power)
{
	fmBody* b = &w->bodies[slot];
	double e1 = 0.0, p1 = 0.0, e0 = 0.0, p0 = 0.0;
	if (b->forceModel == fm_massSpring)
	{
		bool ok = fmSpringEnergyPower(s, b, &e1, &p1);
		fmSwapTouched(w, s, slot);
		ok = ok && fmSpringEnergyPower(s, b, &e0, &p0);
		fmSwapTouched(w, s, slot);
		*energy = e1 - e0;
		*power = p1 - p0;
		return ok;
	}
	int count = fmTouchedTets(w, s, slot);
	if (count < 0)
		return false;
	fmTetsEnergy(b, s->tets, count, &e1, &p1);
	fmSwapTouched(w, s, slot);
	fmTetsEnergy(b, s->tets, count, &e0, &p0);
	fmSwapTouched(w, s, slot);
	*energy = e1 - e0;
	*power = p1 - p0;
	return true;
}

// Book the energy the stage gave body @p slot as contact work when it is positive: pushes
// and a kinematic collider's blows add energy, inelastic impacts take it away. The energy is
// the one the ledger measures: kinetic, elastic and gravity's potential, and for explicit
// frames symplectic Euler's shadow term h/2 v . f (energy_ledger.h).
static bool fmBookWork(fmWorld* w, fmContactState* s, int slot)
{
	fmBody* b = &w->bodies[slot];
	if (b->asleep)
		return true; // nothing moved it, and its ledger is closed while it sleeps
	double gained = 0.0, gravityPower = 0.0;
	bool touched = false;
	for (int k = 0; k < s->touchedCount; ++k)
	{
		const fmTouched* t = &s->touched[k];
		if (t->body != slot)
			continue;
		touched = true;
		double m = b->mass[t->vertex];
		fmVec3 x = fmLoad(b->x, t->vertex), v = fmLoad(b->v, t->vertex);
		gained += 0.5 * m * (fmDot(v, v) - fmDot(t->v, t->v));
		gained -= m * fmDot(w->def.gravity, fmSub(x, t->x));
		gravityPower += m * fmDot(w->def.gravity, fmSub(v, t->v));
	}
	if (!touched)
		return true;
	double elastic, power;
	if (!fmElasticChange(w, s, slot, &elastic, &power))
		return false;
	gained += elastic;
	if (w->def.integrator == fm_explicit)
		gained += 0.5 * w->contactStep * (power + gravityPower);
	fmLedger_AddContactWork(b, gained);
	return true;
}

// ---- the stage ---------------------------------------------------------------------------------

// Whether an implicit step of @p h keeps bodies apart with frozen planes in its solve: not in
// the pieces of a cut step, nor at steps no longer than FM_PLANE_STEP_FACTOR times the
// explicit stability limit of a body, where the stage's projection alone holds them (as in
// the explicit integrator) and the planes, which each body sees as immovable, made two plates
// meeting at 20 m/s each cross at 1/12000 s (they held at 1/6000 s and longer).
static bool fmPlanesHold(const fmWorld* w, double h)
{
	if (w->contactPieces > 1)
		return false;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].x && h <= FM_PLANE_STEP_FACTOR * w->bodies[i].explicitLimit)
			return false;
	return true;
}

int fmContact_Pieces(fmWorld* w, double h, int most)
{
	if (!fmBodiesMeet(w))
		return 1;
	fmContactState* s = fmGetState(w);
	if (s == NULL || !fmReserveBodyBoxes(w, s))
		return -1;
	double thickness = fmContact_Thickness(w);
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmBody* b = &w->bodies[slot];
		if (b->x == NULL)
			continue;
		if (!fmBodyContactArrays(b))
			return -1;
		fmVec3 lo = fmMakeVec3(INFINITY, INFINITY, INFINITY), hi = fmScale(-1.0, lo);
		double speed = 0.0;
		for (int p = 0; p < b->surfaceVertexCount; ++p)
		{
			int i = b->surfaceVertex[p];
			fmVec3 x = fmLoad(b->x, i);
			lo = fmMakeVec3(fmMin(lo.x, x.x), fmMin(lo.y, x.y), fmMin(lo.z, x.z));
			hi = fmMakeVec3(fmMax(hi.x, x.x), fmMax(hi.y, x.y), fmMax(hi.z, x.z));
			speed = fmMax(speed, fmLength(fmLoad(b->v, i)));
		}
		double grow = thickness + speed * h;
		s->bodyLower[slot] = fmSub(lo, fmMakeVec3(grow, grow, grow));
		s->bodyUpper[slot] = fmAdd(hi, fmMakeVec3(grow, grow, grow));
		s->bodySpeed[slot] = speed;
	}
	double pieces = 1.0;
	for (int a = 0; a < w->bodyCapacity; ++a)
	{
		const fmBody* A = &w->bodies[a];
		for (int c = a + 1; A->x && c < w->bodyCapacity; ++c)
		{
			const fmBody* C = &w->bodies[c];
			fmVec3 al = s->bodyLower[a], ah = s->bodyUpper[a];
			fmVec3 cl = s->bodyLower[c], ch = s->bodyUpper[c];
			if (C->x == NULL || !fmFiltersMeet(A->filter, C->filter) || ah.x < cl.x ||
			    al.x > ch.x || ah.y < cl.y || al.y > ch.y || ah.z < cl.z || al.z > ch.z)
				continue;
			double allowed =
			    fmMax(FM_PIECE_FRACTION * fmMin(A->contactThinness, C->contactThinness), thickness);
			pieces = fmMax(pieces, ceil((s->bodySpeed[a] + s->bodySpeed[c]) * h / allowed));
		}
	}
	return pieces <= most ? (int)pieces : most + 1;
}

bool fmContact_BeginSubstep(fmWorld* w, double h)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (b->x == NULL)
			continue;
		if (!fmBodyContactArrays(b))
			return false;
		memcpy(b->contactStart, b->x, sizeof(double) * 3 * (size_t)b->vertexCount);
		// Friction found after the last step acts in this one's solve (penalty.h).
		double* found = b->contactFrictionNext;
		b->contactFrictionNext = b->contactFriction;
		b->contactFriction = found;
		memset(b->contactFrictionNext, 0, sizeof(double) * 8 * (size_t)b->vertexCount);
		for (int k = 0; k < b->vertexCount; ++k)
			b->contactPlane[4 * (size_t)k + 3] = NAN;
		b->edgePlaneCount = 0;
	}
	bool bodies = fmBodiesMeet(w);
	if (w->def.integrator != fm_implicit || !bodies)
		return true;
	fmContactState* s = fmGetState(w);
	return s != NULL && (!fmPlanesHold(w, h) || fmPredictPlanes(w, s, fmContact_Thickness(w), h));
}

bool fmContact_Substep(fmWorld* w, double h)
{
	fmContactState* s = fmGetState(w);
	if (s == NULL)
		return false;
	double thickness = fmContact_Thickness(w);
	w->contactStep = h;
	for (int k = 0; k < w->colliderCapacity; ++k)
		if (w->colliders[k].inUse)
			fmCollider_Move(&w->colliders[k], h);
	s->pointCount = 0;
	bool ok = fmCollideWithColliders(w, s, thickness);
	if (ok && fmBodiesMeet(w))
		ok = fmCollideBodies(w, s, thickness);
	for (int slot = 0; ok && slot < w->bodyCapacity; ++slot)
		ok = fmBookWork(w, s, slot);
	for (int k = 0; k < s->touchedCount; ++k)
		w->bodies[s->touched[k].body].contactMark[s->touched[k].vertex] = 0;
	s->touchedCount = 0;
	return ok;
}

static int fmCompareKeys(const void* a, const void* b)
{
	uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

static bool fmAddEvent(fmWorld* w, fmContactState* s, uint64_t key, bool begin)
{
	if (!fmGrowArray((void**)&s->events, &s->eventCapacity, s->eventCount, s->eventCount + 1,
	                 sizeof(fmContactEvent)))
		return false;
	fmContactEvent* e = &s->events[s->eventCount++];
	memset(e, 0, sizeof *e);
	e->begin = begin;
	int a = (int)(key >> 32), b = (int)(uint32_t)key;
	e->body = fmWorldBodyId(w, a);
	if (b & (int)0x80000000u)
		e->collider = fmWorldColliderId(w, b & 0x7fffffff);
	else
		e->otherBody = fmWorldBodyId(w, b);
	return true;
}

bool fmContact_ReportFloor(fmWorld* w, bool listed)
{
	fmContactState* s = w->contactState;
	if (s == NULL && !w->def.floor.enabled)
		return true;
	if (s == NULL && (s = fmGetState(w)) == NULL)
		return false;
	if (!listed)
		s->pointCount = 0;
	fmCollider* floor = &w->floorCollider;
	const fmColliderId floorId = fmWorldColliderId(w, FM_FLOOR_SLOT);
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		fmBody* b = &w->bodies[slot];
		if (!fmIsland_Stepping(b) || b->floorHitCount == 0)
			continue;
		// The body's points at once (a resting body has hundreds a substep, all serial here).
		if (!fmGrowArray((void**)&s->points, &s->pointCapacity, s->pointCount,
		                 s->pointCount + b->floorHitCount, sizeof(fmContactPoint)))
			return false;
		memset(s->points + s->pointCount, 0, (size_t)b->floorHitCount * sizeof(fmContactPoint));
		const fmBodyId id = fmWorldBodyId(w, slot);
		for (int k = 0; k < b->floorHitCount; ++k)
		{
			const fmFloorHit* hit = &b->floorHits[k];
			fmContactPoint* p = &s->points[s->pointCount++];
			p->body = id;
			p->vertex = b->userVertex[hit->vertex];
			p->collider = floorId;
			p->point = fmLoad(b->x, hit->vertex);
			p->normal = floor->def.normal;
			p->depth = hit->depth;
			p->impulse = hit->impulse.y;
			floor->impulse = fmSub(floor->impulse, hit->impulse);
			floor->angularImpulse = fmSub(floor->angularImpulse,
			                              fmCross(fmSub(p->point, floor->position), hit->impulse));
		}
		b->floorHitCount = 0;
		uint64_t key = ((uint64_t)(uint32_t)slot << 32) | (0x80000000u | (uint32_t)FM_FLOOR_SLOT);
		if (!fmRecordPair(s, key))
			return false;
	}
	return true;
}

bool fmContact_EndFrame(fmWorld* w, double frameTime)
{
	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		fmCollider* c = fmWorldCollider(w, k < w->colliderCapacity ? k : FM_FLOOR_SLOT);
		c->force = fmScale(1.0 / frameTime, c->impulse);
		c->torque = fmScale(1.0 / frameTime, c->angularImpulse);
	}
	fmContactState* s = w->contactState;
	if (s == NULL)
		return true;
	// Sleeping bodies keep their pairs (no end events while an island sleeps).
	for (int k = 0; k < s->lastPairCount; ++k)
	{
		int a = (int)(s->lastPairs[k] >> 32), b = (int)(uint32_t)s->lastPairs[k];
		bool collider = (b & (int)0x80000000u) != 0;
		if ((w->bodies[a].asleep || (!collider && w->bodies[b].asleep)) &&
		    !fmRecordPair(s, s->lastPairs[k]))
			return false;
	}
	if (s->pairCount > 1)
		qsort(s->pairs, (size_t)s->pairCount, sizeof(uint64_t), fmCompareKeys);
	int unique = 0;
	for (int k = 0; k < s->pairCount; ++k)
		if (unique == 0 || s->pairs[unique - 1] != s->pairs[k])
			s->pairs[unique++] = s->pairs[k];
	s->pairCount = unique;
	s->eventCount = 0;
	bool ok = true;
	int a = 0, b = 0;
	while (ok && (a < s->pairCount || b < s->lastPairCount))
	{
		bool takeNew = b >= s->lastPairCount || (a < s->pairCount && s->pairs[a] < s->lastPairs[b]);
		bool same = a < s->pairCount && b < s->lastPairCount && s->pairs[a] == s->lastPairs[b];
		if (same)
			a += 1, b += 1;
		else if (takeNew)
			ok = fmAddEvent(w, s, s->pairs[a++], true);
		else
			ok = fmAddEvent(w, s, s->lastPairs[b++], false);
	}
	// This frame's pairs become the last frame's.
	uint64_t* pairs = s->lastPairs;
	int capacity = s->lastPairCapacity;
	s->lastPairs = s->pairs;
	s->lastPairCapacity = s->pairCapacity;
	s->lastPairCount = s->pairCount;
	s->pairs = pairs;
	s->pairCapacity = capacity;
	s->pairCount = 0;
	return ok;
}

// ---- public read-back --------------------------------------------------------------------------

int fmContact_FramePairs(const fmWorld* w, const uint64_t** pairs)
{
	const fmContactState* s = w->contactState;
	*pairs = s ? s->lastPairs : NULL;
	return s ? s->lastPairCount : 0;
}

int fmContact_Points(const fmWorld* w, const fmContactPoint** points)
{
	*points = w->contactState ? w->contactState->points : NULL;
	return w->contactState ? w->contactState->pointCount : 0;
}

int fmWorld_GetContacts(fmWorldId worldId, fmContactPoint* contacts, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && (capacity == 0 || contacts != NULL));
	if (w == NULL || w->contactState == NULL)
		return 0;
	const fmContactState* s = w->contactState;
	int copy = capacity < s->pointCount ? capacity : s->pointCount;
	if (copy > 0 && contacts != NULL)
		memcpy(contacts, s->points, sizeof(fmContactPoint) * (size_t)copy);
	return s->pointCount;
}

int fmWorld_GetContactEvents(fmWorldId worldId, fmContactEvent* events, int capacity)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && (capacity == 0 || events != NULL));
	if (w == NULL || w->contactState == NULL)
		return 0;
	const fmContactState* s = w->contactState;
	int copy = capacity < s->eventCount ? capacity : s->eventCount;
	if (copy > 0 && events != NULL)
		memcpy(events, s->events, sizeof(fmContactEvent) * (size_t)copy);
	return s->eventCount;
}

// ---- snapshots ---------------------------------------------------------------------------------

bool fmContact_SetFramePairs(fmWorld* w, const void* pairs, int count)
{
	if (count == 0 && w->contactState == NULL)
		return true;
	fmContactState* s = fmGetState(w);
	if (s == NULL ||
	    !fmGrowArray((void**)&s->lastPairs, &s->lastPairCapacity, 0, count, sizeof(uint64_t)))
		return false;
	if (count > 0)
		memcpy(s->lastPairs, pairs, sizeof(uint64_t) * (size_t)count);
	s->lastPairCount = count;
	return true;
}
