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
//    Explicit substeps also push surface edges of two bodies apart (contact_edge.h);
// 4. the energy ledger books what the stage gave each body (contact_ledger.h).
// The body-body detection (contact_detect.h) and the body-collider queries run on the workers,
// each writing only its own items; the responses run on one thread, in a fixed order (bodies,
// vertices, colliders, triangles ascending): the same bits for any number of workers.
#include "contact/contact.h"
#include "core/det_math.h"

#include "body/fracture.h"
#include "body/loads.h"
#include "contact/barrier_contact.h"
#include "contact/collider.h"
#include "contact/contact_collider.h"
#include "contact/contact_detect.h"
#include "contact/contact_edge.h"
#include "contact/contact_ledger.h"
#include "contact/contact_pair.h"
#include "contact/contact_state.h"
#include "contact/embedded.h"
#include "core/core.h"
#include "core/timer.h"

#include <math.h>
#include <string.h>

// The automatic thickness: this fraction of the smallest body's bounding-box diagonal.
#define FM_CONTACT_THICKNESS_FRACTION 0.01

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
	if (w->stepKnown)
		return w->stepThickness;
	if (w->def.contact.thickness > 0.0)
		return w->def.contact.thickness;
	double smallest = INFINITY;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]))
			smallest = fmMin(smallest, w->bodies[i].mesh.restSize);
	return isfinite(smallest) ? FM_CONTACT_THICKNESS_FRACTION * smallest : 0.0;
}

static int fmLiveBodies(const fmWorld* w)
{
	int live = 0;
	for (int i = 0; i < w->bodyCapacity; ++i)
		live += fmBody_IsLive(&w->bodies[i]);
	return live;
}

bool fmContact_HasColliders(const fmWorld* w)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
		if (w->colliders[k].inUse)
			return true;
	return false;
}

// Whether surfaces of bodies can meet: two or more bodies, or one that collides with itself.
bool fmContact_BodiesMeet(const fmWorld* w)
{
	if (w->stepKnown)
		return w->stepBodiesMeet;
	if (!w->def.contact.bodies)
		return false;
	if (fmLiveBodies(w) >= 2)
		return true;
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (fmBody_IsLive(&w->bodies[i]) && fmFracture_MeetsItself(&w->bodies[i]))
			return true;
	return false;
}

bool fmContact_FloorFriction(const fmWorld* w)
{
	const fmFloorDef* floor = &w->def.floor;
	return w->def.integrator == fm_implicit && w->def.implicitSolver != fm_solverVbd &&
	       floor->enabled && floor->friction == fm_floorCoulomb && floor->frictionCoefficient > 0.0;
}

bool fmContact_ColliderBarrier(const fmWorld* w)
{
	return w->def.integrator == fm_implicit && w->def.implicitSolver != fm_solverVbd;
}

bool fmContact_Active(const fmWorld* w)
{
	return fmContact_HasColliders(w) || fmContact_BodiesMeet(w);
}

// How thick a body is at rest, as 2 V / S (its volume over half its surface area): a plate's
// thickness, a third of a cube's side. What a step may close in on it without passing through.
static double fmRestThinness(const fmBody* b)
{
	double volume = 0.0, area = 0.0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
		volume += b->mesh.restVolume[t];
	for (int t = 0; t < b->mesh.triangleCount; ++t)
	{
		const int* tri = b->mesh.surface + 3 * (size_t)t;
		fmVec3 p = fmLoad(b->mesh.x0, tri[0]);
		area += 0.5 * fmLength(fmCross(fmSub(fmLoad(b->mesh.x0, tri[1]), p),
		                               fmSub(fmLoad(b->mesh.x0, tri[2]), p)));
	}
	return area > 0.0 ? 2.0 * volume / area : b->mesh.restSize;
}

// The body's contact arrays, made on first use: its surface vertices (ascending), its
// substep-start positions, marks, planes, friction and embedded holders, and its rest
// thickness. False when memory is short.
static bool fmBodyContactArrays(fmBody* b)
{
	if (b->contact.start == NULL)
		b->contact.start = FM_ALLOC_ARRAY(double, 3 * (size_t)b->mesh.vertexCount);
	if (b->contact.mark == NULL)
		b->contact.mark = FM_ALLOC_ZERO(int, b->mesh.vertexCount);
	if (b->contact.plane == NULL)
		b->contact.plane = FM_ALLOC_ARRAY(double, 4 * (size_t)b->mesh.vertexCount);
	if (b->contact.colliderGap == NULL)
		b->contact.colliderGap = FM_ALLOC_ZERO(double, 2 * (size_t)b->mesh.vertexCount);
	if (b->contact.friction == NULL)
		b->contact.friction =
		    FM_ALLOC_ZERO(double, (size_t)FM_FRICTION_STRIDE * b->mesh.vertexCount);
	if (b->contact.frictionNext == NULL)
		b->contact.frictionNext =
		    FM_ALLOC_ZERO(double, (size_t)FM_FRICTION_STRIDE * b->mesh.vertexCount);
	if (b->contact.tetMark == NULL)
		b->contact.tetMark = FM_ALLOC_ZERO(uint8_t, b->mesh.tetCount > 0 ? b->mesh.tetCount : 1);
	if (b->contact.embeddedHolder == NULL)
		b->contact.embeddedHolder = FM_ALLOC_ZERO(int, b->mesh.vertexCount);
	if (b->contact.surfaceVertex == NULL)
	{
		uint8_t* on = FM_ALLOC_ZERO(uint8_t, b->mesh.vertexCount);
		if (on == NULL)
			return false;
		int count = 0;
		for (int k = 0; k < 3 * b->mesh.triangleCount; ++k)
			count += on[b->mesh.surface[k]]++ == 0;
		b->contact.surfaceVertex = FM_ALLOC_ARRAY(int, count > 0 ? count : 1);
		if (b->contact.surfaceVertex != NULL)
		{
			b->contact.surfaceVertexCount = count;
			count = 0;
			for (int i = 0; i < b->mesh.vertexCount; ++i)
				if (on[i])
					b->contact.surfaceVertex[count++] = i;
		}
		FM_FREE_ARRAY(on, uint8_t, b->mesh.vertexCount);
		b->contact.thinness = fmRestThinness(b);
	}
	return b->contact.start != NULL && b->contact.surfaceVertex != NULL &&
	       b->contact.mark != NULL && b->contact.tetMark != NULL && b->contact.plane != NULL &&
	       b->contact.colliderGap != NULL && b->contact.embeddedHolder != NULL &&
	       b->contact.friction != NULL && b->contact.frictionNext != NULL;
}

// A fingerprint of every live body's positions with its slot and vertex count (FNV-1a on
// 64-bit words, four lanes): a single changed word always changes it.
static uint64_t fmPositionsPrint(const fmWorld* w)
{
	const uint64_t prime = 1099511628211ull;
	uint64_t lane[4] = {1469598103934665603ull, 1, 2, 3};
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		const fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		lane[0] = (lane[0] ^ ((uint64_t)i << 32 | (uint32_t)b->mesh.vertexCount)) * prime;
		const int n3 = 3 * b->mesh.vertexCount;
		for (int k = 0; k < n3; ++k)
		{
			uint64_t bits;
			memcpy(&bits, &b->state.x[k], sizeof bits);
			lane[k & 3] = (lane[k & 3] ^ bits) * prime;
		}
		for (int j = 1; j < 4; ++j)
			lane[0] = (lane[0] ^ lane[j]) * prime;
	}
	return lane[0];
}

// Whether a barrier world's frame must look for embedded vertices (fmContact_BeginFrame). A
// prescribed displacement moving now keeps the next frame's search due too (it may move its
// vertices in this frame's later substeps, after the search).
static bool fmEmbeddedSearchDue(fmWorld* w)
{
	bool due = w->embeddedDue || fmPositionsPrint(w) != w->positionsPrint, moving = false;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		const fmBody* b = &w->bodies[i];
		due = due || (fmBody_IsLive(b) && b->contact.overlapWith[0] != 0);
		moving = moving || (fmBody_IsLive(b) && fmLoads_Moving(b));
	}
	w->embeddedDue = moving;
	return due || moving;
}

void fmContact_BeginFrame(fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
		if (w->bodies[i].contact.embeddedHolder != NULL)
		{
			fmBarrierContact_NoteOverlaps(&w->bodies[i]);
			memset(w->bodies[i].contact.embeddedHolder, 0,
			       sizeof(int) * (size_t)w->bodies[i].mesh.vertexCount);
		}
	w->embeddedSearch = !fmBarrierContact_Active(w) || fmEmbeddedSearchDue(w);
	if (w->contactState != NULL)
		w->contactState->pairCount = 0; // what a failed frame left

	for (int k = 0; k <= w->colliderCapacity; ++k)
	{
		fmCollider* c = fmWorldCollider(w, k < w->colliderCapacity ? k : FM_FLOOR_SLOT);
		c->impulse = fmMakeVec3(0.0, 0.0, 0.0);
		c->angularImpulse = fmMakeVec3(0.0, 0.0, 0.0);
	}
}

// Whether the stage moves a body-body contact: every one without barrier contact; with it, only
// a vertex found inside the other body's tets, and any between two bodies known to overlap.
static bool fmMovesPair(const fmWorld* w, bool barrier, const fmPairContact* pc)
{
	return !barrier || pc->embedded || fmBarrierContact_Overlapping(w, pc->body, pc->other);
}

// The distance from a pair contact's vertex to the nearest point of its triangle.
static double fmPairDistance(const fmWorld* w, const fmPairContact* pc)
{
	const fmBody* o = &w->bodies[pc->other];
	const int* tri = fmContactDetect_Triangle(o, pc->triangle);
	fmVec3 q = fmMakeVec3(0.0, 0.0, 0.0);
	for (int c = 0; c < 3; ++c)
		q = fmMulAdd(q, pc->w[c], fmLoad(o->state.x, tri[c]));
	return fmLength(fmSub(fmLoad(w->bodies[pc->body].state.x, pc->vertex), q));
}

// A vertex-triangle contact the detection found, into the stage's list: it wakes a sleeper,
// and notes what the next frame's contact must look for.
static void fmTakePairContact(fmWorld* w, fmContactState* s, const fmPairContact* found,
                              double thickness)
{
	fmContactPair_WakeSleeper(w, found);
	// Behind the face it found, over its inside (crossing, or inside but within reach): the next
	// frame looks for embedded vertices too, which the solves' moves may make deeper. (Behind an
	// edge or a corner is not telling: a concave corner.)
	w->embeddedDue = w->embeddedDue || (found->depth > thickness && found->w[0] > 0.0 &&
	                                    found->w[1] > 0.0 && found->w[2] > 0.0);
	// Inside the other body, or touching another under the barrier (FM_BARRIER_TOUCHING): from
	// the next frame the two bodies overlap, off the barrier, and the projection parts them.
	bool touching = fmBarrierContact_Active(w) && found->other != found->body &&
	                fmPairDistance(w, found) <= FM_BARRIER_TOUCHING * thickness;
	if (found->embedded || touching)
		w->bodies[found->body].contact.embeddedHolder[found->vertex] = found->other + 1;
	s->pairContacts[s->pairContactCount++] = *found;
}

// Body against body (step 3): the broad phase, the parallel detection of vertex-triangle
// contacts (and, explicit, edge-edge ones), the projections in Gauss-Seidel passes, then the
// velocity responses and the contact list, in item order. False when memory is short.
static bool fmCollideBodies(fmWorld* w, fmContactState* s, double thickness)
{
	double start = fmSeconds();
	if (!fmContactDetect_BuildTriangles(w, s, thickness))
		return false;
	// Embedded vertices are looked for once a frame (the frame's first detection: a tet hash is
	// too dear for every substep; docs/contact.md, Measurements), and pushed out by a frame's
	// depenetration.
	s->tetHashReady = w->embeddedSearch && fmTetHash_Build(&s->tetHash, w, s->bodyNear);
	w->profile.broadPhase += 1e3 * (fmSeconds() - start);
	s->pairContactCount = 0;
	int n = fmContactDetect_Vertices(w, s, thickness);
	if (s->tetHashReady)
		w->embeddedSearch = false;
	s->tetHashReady = false;
	if (n < 0 || !fmGrowArray((void**)&s->pairContacts, &s->pairContactCapacity, 0, n,
	                          sizeof(fmPairContact)))
		return false;
	for (int k = 0; k < n; ++k)
		if (s->hit[k])
			fmTakePairContact(w, s, &s->found[k], thickness);
	// Edge against edge, explicit substeps only: implicit steps hold edges apart inside the
	// solve (frozen edge planes, fmContactPlanes_Predict) and do not project them again after
	// it (docs/contact.md, Measurements).
	s->edgeContactCount = 0;
	if (w->def.integrator != fm_implicit && !fmContactDetect_Edges(w, s, thickness))
		return false;
	// Implicit steps: the barrier held the bodies apart and their friction acted in the solve;
	// the contacts are listed, not moved, except a vertex already inside the other body (bodies
	// made overlapping, or pushed in by pins, targets or the floor: what the barrier cannot
	// undo), pushed out as before (barrier_contact.h).
	const bool barrier = fmBarrierContact_Active(w);
	for (int pass = 0; pass < w->def.contact.iterations; ++pass)
	{
		for (int c = 0; c < s->pairContactCount; ++c)
			if (fmMovesPair(w, barrier, &s->pairContacts[c]) &&
			    !fmContactPair_Project(w, s, &s->pairContacts[c], thickness))
				return false;
		for (int c = 0; c < s->edgeContactCount; ++c)
			if (!fmContactEdge_Project(w, s, &s->edgeContacts[c], thickness))
				return false;
	}
	for (int c = 0; c < s->edgeContactCount; ++c)
		if (!fmContactEdge_Respond(w, s, &s->edgeContacts[c]) ||
		    !fmContactEdge_Record(w, s, &s->edgeContacts[c]))
			return false;
	for (int c = 0; c < s->pairContactCount; ++c)
	{
		fmPairContact* pc = &s->pairContacts[c];
		if (fmMovesPair(w, barrier, pc) && !fmContactPair_Respond(w, s, pc, thickness))
			return false;
		fmContactPoint* point = fmContactState_NewPoint(s);
		if (point == NULL)
			return false;
		point->body = fmWorldBodyId(w, pc->body);
		point->vertex = w->bodies[pc->body].userVertex[pc->vertex];
		point->otherBody = fmWorldBodyId(w, pc->other);
		point->point = fmLoad(w->bodies[pc->body].state.x, pc->vertex);
		point->normal = pc->normal;
		point->depth = pc->depth;
		point->impulse = pc->impulse;
		int low = pc->body < pc->other ? pc->body : pc->other;
		int high = pc->body < pc->other ? pc->other : pc->body;
		if (low != high &&
		    !fmContactState_RecordPair(s, ((uint64_t)(uint32_t)low << 32) | (uint32_t)high))
			return false;
	}
	return true;
}

// Advance a kinematic collider by @p h seconds of its velocity and angular velocity.
static void fmMoveCollider(fmCollider* c, double h)
{
	c->position = fmMulAdd(c->position, h, c->def.velocity);
	if (fmDot(c->def.angularVelocity, c->def.angularVelocity) > 0.0)
	{
		fmMat3 turn = fmRotationFromAxisAngle(fmScale(h, c->def.angularVelocity));
		c->rotation = fmMatMul(&turn, &c->rotation);
	}
}

bool fmContact_BeginSubstep(fmWorld* w, double h)
{
	// Under the colliders' barrier the solve meets each kinematic collider where the substep
	// leaves it; the contact stage otherwise moves them after the bodies' steps.
	for (int k = 0; k < w->colliderCapacity && fmContact_ColliderBarrier(w); ++k)
		if (w->colliders[k].inUse)
			fmMoveCollider(&w->colliders[k], h);
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b))
			continue;
		if (!fmBodyContactArrays(b))
			return false;
		memcpy(b->contact.start, b->state.x, sizeof(double) * 3 * (size_t)b->mesh.vertexCount);
		// Friction found after the last step acts in this one's solve (penalty.h).
		double* found = b->contact.frictionNext;
		b->contact.frictionNext = b->contact.friction;
		b->contact.friction = found;
		memset(b->contact.frictionNext, 0,
		       sizeof(double) * (size_t)FM_FRICTION_STRIDE * b->mesh.vertexCount);
		for (int k = 0; k < b->mesh.vertexCount; ++k)
			b->contact.plane[4 * (size_t)k + 3] = NAN;
		b->contact.edgePlaneCount = 0;
	}
	// Implicit steps hold bodies apart with the barrier inside the solve (barrier_contact.h): it
	// needs every body's surface edges.
	if (!fmBarrierContact_Active(w))
		return true;
	fmContactState* s = fmContactState_Get(w);
	if (s == NULL)
		return false;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		if (!fmBody_IsLive(&w->bodies[i]))
			continue;
		if (!fmBarrierContact_Edges(&w->bodies[i]))
			return false;
		fmBarrierContact_NoteSurface(&w->bodies[i]);
	}
	return true;
}

bool fmContact_Substep(fmWorld* w, const fmStepContext* ctx)
{
	fmContactState* s = fmContactState_Get(w);
	if (s == NULL)
		return false;
	double thickness = fmContact_Thickness(w);
	w->contactStep = ctx->substep;
	// Symplectic Euler's shadow term h/2 v . f, which the contact ledger books the change of.
	const double shadowWeight = w->def.integrator == fm_explicit ? 0.5 * ctx->substep : 0.0;
	for (int k = 0; k < w->colliderCapacity && !fmContact_ColliderBarrier(w); ++k)
		if (w->colliders[k].inUse)
			fmMoveCollider(&w->colliders[k], ctx->substep);
	s->pointCount = 0;
	s->colliderMoved = false;
	bool ok = fmContactCollider_Collide(w, s, thickness);
	// A barrier world's collider stage moved a vertex outside the solves' CCD: this substep's
	// detection looks (explicit worlds look once a frame whatever moved).
	w->embeddedSearch = w->embeddedSearch || (s->colliderMoved && fmBarrierContact_Active(w));
	if (ok && fmContact_BodiesMeet(w))
		ok = fmCollideBodies(w, s, thickness);
	for (int slot = 0; ok && slot < w->bodyCapacity; ++slot)
		ok = fmContactLedger_AddStageWork(w, s, ctx, shadowWeight, slot);
	for (int k = 0; k < s->loggedCount; ++k)
		w->bodies[s->logged[k].body].contact.mark[s->logged[k].vertex] = 0;
	s->loggedCount = 0;
	return ok;
}

int fmContact_EndFrame(fmWorld* w)
{
	if (fmBarrierContact_Active(w))
		w->positionsPrint = fmPositionsPrint(w);
	return w->contactState != NULL ? w->contactState->pointCount : 0;
}
