// Vertex against triangle between bodies (contact_pair.h).
#include "contact/contact_pair.h"
#include "contact/barrier_contact.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "contact/contact_detect.h"
#include "contact/contact_response.h"
#include "contact/penalty.h"
#include "core/det_math.h"
#include "core/timer.h"
#include "math/geometry.h"

#include <math.h>
#include <string.h>

// Whether vertex i of body b was in front of its own triangle @p tri (normal @p n now) at the
// start of the substep: then it crossed the triangle during it, rather than being inside.
static bool fmInFrontAtStart(const fmBody* b, int i, const int* tri, fmVec3 n, double thickness)
{
	fmVec3 q = fmScale(
	    1.0 / 3.0, fmAdd(fmAdd(fmLoad(b->contact.start, tri[0]), fmLoad(b->contact.start, tri[1])),
	                     fmLoad(b->contact.start, tri[2])));
	return fmDot(n, fmSub(fmLoad(b->contact.start, i), q)) > -thickness;
}

// Self-collision: vertex i of body b may touch its own surface triangle @p tri only when the
// two were apart in the rest shape by more than twice the thickness (so a vertex never touches
// the triangles around it, however coarse or sharp the surface), or lie on two pieces a tear made
// (fracture.h).
static bool fmSelfCandidate(const fmBody* b, int i, const int* tri, double thickness)
{
	if (tri[0] == i || tri[1] == i || tri[2] == i)
		return false;
	const int stencil[4] = {i, tri[0], tri[1], tri[2]};
	if (fmFracture_AcrossPieces(b, stencil, 1, 4))
		return true;
	if (!b->selfCollision)
		return false; // (a torn body meets only its other pieces)
	fmVec3 p = fmLoad(b->mesh.x0, i), a = fmLoad(b->mesh.x0, tri[0]),
	       bb = fmLoad(b->mesh.x0, tri[1]), c = fmLoad(b->mesh.x0, tri[2]);
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
	fmVec3 a = fmLoad(o->state.x, tri[0]), b = fmLoad(o->state.x, tri[1]),
	       c = fmLoad(o->state.x, tri[2]);
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
static bool fmMayContain(const fmWorld* w, int slot, int other)
{
	const fmBody *b = &w->bodies[slot], *o = &w->bodies[other];
	return other != slot && fmFiltersMeet(b->filter, o->filter) && !(b->asleep && o->asleep) &&
	       !fmAnchors_Welded(b, o);
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
			if (!fmNearestOnTriangle(o, fmContactDetect_Triangle(o, s->triangleIndex[item]), p, wt,
			                         &q, &n))
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
	fmVec3 p = fmLoad(w->bodies[slot].state.x, i);
	double side = 0.0;
	if (!fmNearestTriangle(s, w, wf, holder, p, 2.0 * thickness, found, &side) ||
	    (behind && !(side < 0.0)))
		return false;
	found->depth = thickness - side;
	found->reach = w->def.floor.maxDepenetrationSpeed * w->contactStep;
	found->embedded = true;
	return true;
}

// How well triangle @p item of the hash fits vertex @p i of body @p slot at @p p (its box
// [lo, hi] grown by @p reach): its score (the distance, weighted towards triangles the vertex
// lies straight above or below), or INFINITY when the triangle is out of reach, filtered out,
// or not touching. On a finite score @p wt, @p n and @p side describe the nearest point.
static double fmCandidateScore(const fmWorld* w, const fmContactState* s, int slot, int i, fmVec3 p,
                               fmVec3 lo, fmVec3 hi, double reach, double thickness, int item,
                               double wt[3], fmVec3* n, double* side)
{
	const fmBody* b = &w->bodies[slot];
	int other = s->triangleBody[item];
	fmVec3 tlo = s->lower[item], thi = s->upper[item];
	if (hi.x < tlo.x || lo.x > thi.x || hi.y < tlo.y || lo.y > thi.y || hi.z < tlo.z ||
	    lo.z > thi.z)
		return INFINITY; // the triangle's grown box is out of the vertex's reach
	const fmBody* o = &w->bodies[other];
	if ((other == slot && !fmFracture_MeetsItself(b)) || !fmFiltersMeet(b->filter, o->filter) ||
	    (b->asleep && o->asleep) || fmAnchors_Welded(b, o))
		return INFINITY;
	const int* tri = fmContactDetect_Triangle(o, s->triangleIndex[item]);
	if (other == slot && !fmSelfCandidate(b, i, tri, thickness))
		return INFINITY;
	fmVec3 q;
	if (!fmNearestOnTriangle(o, tri, p, wt, &q, n))
		return INFINITY;
	double bound = reach + fmMax(fmContactDetect_Motion(s, o, tri[0]),
	                             fmMax(fmContactDetect_Motion(s, o, tri[1]),
	                                   fmContactDetect_Motion(s, o, tri[2])));
	double distance = fmLength(fmSub(p, q));
	*side = fmDot(*n, fmSub(p, q));
	// (Before a step, a plane within the reach of the step's motion may be met.)
	double near = s->predicting ? bound : thickness;
	bool touches = distance <= bound && *side<near&& * side> - bound;
	// A body's own interior lies behind all of its triangles: a vertex of it counts against its
	// own surface only from the front (or just behind, within the thickness), and only within
	// the thickness (with the motion's reach, a vertex would meet the triangles of its own flat
	// face that move with it).
	if (other == slot)
		touches = *side > -thickness ? distance <= thickness && *side < thickness
		                             : !s->predicting && distance <= bound &&
		                                   fmInFrontAtStart(b, i, tri, *n, thickness);
	if (!touches)
		return INFINITY;
	// The nearest triangle, preferring one the vertex lies straight above or below (near an
	// edge, the face under the vertex, not the side face that shares the edge).
	double along = distance > 0.0 ? fabs(*side) / distance : 1.0;
	return distance * (2.0 - along);
}

// Surface vertex i of body @p slot, which no triangle's reach found, when a tet of another body
// holds it (it went in deeper than the thickness and the substep's motion, squeezed between
// bodies or the floor): its contact with that body (fmEmbeddedContact). False when no tet holds
// it.
static bool fmFindEmbedded(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                           int i, double thickness, fmPairContact* found)
{
	fmVec3 p = fmLoad(w->bodies[slot].state.x, i);
	int holder = fmTetHash_Container(&s->tetHash, w, &wf->tetQuery, slot, p, fmMayContain);
	wf->failed = wf->failed || holder == -2;
	return holder >= 0 && fmEmbeddedContact(w, s, wf, slot, i, holder, thickness, false, found);
}

bool fmContactPair_Find(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                        int i, double thickness, fmPairContact* found)
{
	const fmBody* b = &w->bodies[slot];
	fmVec3 p = fmLoad(b->state.x, i);
	double motion = fmContactDetect_Motion(s, b, i), reach = thickness + motion;
	if (!(fabs(p.x) + fabs(p.y) + fabs(p.z) + reach < 1e30))
		return false; // non-finite: the frame's checks report it
	fmVec3 lo = fmSub(p, fmMakeVec3(reach, reach, reach));
	fmVec3 hi = fmAdd(p, fmMakeVec3(reach, reach, reach));
	if (!fmContactDetect_NearOtherBody(w, s, slot, lo, hi, false))
		return false;
	double start = fmSeconds();
	int count = fmSpatialHash_Query(&s->hash, &wf->query, lo, hi);
	wf->broadPhase += fmSeconds() - start;
	wf->failed = wf->failed || count < 0;
	double best = INFINITY;
	int bestItem = -1;
	for (int c = 0; c < count; ++c)
	{
		int item = wf->query.items[c];
		double wt[3], side = 0.0;
		fmVec3 n;
		double score =
		    fmCandidateScore(w, s, slot, i, p, lo, hi, reach, thickness, item, wt, &n, &side);
		if (score < best || (score == best && item < bestItem))
		{
			best = score;
			bestItem = item;
			found->other = s->triangleBody[item];
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
	if (bestItem < 0 && b->contact.embeddedHolder[i] > 0)
		return fmEmbeddedContact(w, s, wf, slot, i, b->contact.embeddedHolder[i] - 1, thickness,
		                         true, found);
	if (bestItem >= 0)
	{
		// Depenetration is limited as against the floor: what the substep's own approach
		// explains goes at once, older penetration at most the depenetration speed (bodies
		// created overlapping come apart gently instead of being catapulted), and a vertex that
		// started within the thickness is only kept from coming closer (fmContactResponse_Reach).
		const fmBody* o = &w->bodies[found->other];
		const int* tri = fmContactDetect_Triangle(o, found->triangle);
		fmVec3 approach = fmSub(p, fmLoad(b->contact.start, i));
		for (int c = 0; c < 3; ++c)
			approach =
			    fmMulAdd(approach, -found->w[c],
			             fmSub(fmLoad(o->state.x, tri[c]), fmLoad(o->contact.start, tri[c])));
		// A body's own surface is kept from coming closer, not pushed back out to the thickness
		// at once: in a fold the projection's jump crushed the tets between the two sides, and
		// an explicit bar folding onto itself blew up at its first self contact (docs/contact.md,
		// "Self-collision").
		double closing = -fmDot(approach, found->normal);
		double depen = fmContactResponse_DepenetrationStep(w);
		double before = thickness - found->depth + closing; // the distance at the step's start
		// A pair that touched (FM_BARRIER_TOUCHING) between bodies off the barrier for it parts
		// at the depenetration speed, so that the barrier can hold it again.
		bool parting = found->other != slot && before >= 0.0 &&
		               before <= FM_BARRIER_TOUCHING * thickness && fmBarrierContact_Active(w) &&
		               fmBarrierContact_Overlapping(w, slot, found->other);
		found->reach = found->other == slot ? fmMax(depen, fmMax(0.0, closing))
		               : parting            ? fmMax(0.0, closing) + fmMin(thickness - before, depen)
		                         : fmContactResponse_Reach(before, closing, thickness, depen);
	}
	return bestItem >= 0;
}

// Note the state of a contact's vertex and its triangle's before the stage changes them.
static bool fmLogPairVertices(fmContactState* s, fmBody* b, fmBody* o, const fmPairContact* pc)
{
	const int* tri = fmContactDetect_Triangle(o, pc->triangle);
	return fmContactState_LogVertex(s, b, pc->body, pc->vertex) &&
	       fmContactState_LogVertex(s, o, pc->other, tri[0]) &&
	       fmContactState_LogVertex(s, o, pc->other, tri[1]) &&
	       fmContactState_LogVertex(s, o, pc->other, tri[2]);
}

bool fmContactPair_Project(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness)
{
	fmBody* b = &w->bodies[pc->body];
	fmBody* o = &w->bodies[pc->other];
	const int* tri = fmContactDetect_Triangle(o, pc->triangle);
	fmVec3 q = fmMakeVec3(0.0, 0.0, 0.0);
	double weight = fmContactResponse_InverseMass(b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		q = fmMulAdd(q, pc->w[c], fmLoad(o->state.x, tri[c]));
		weight += pc->w[c] * pc->w[c] * fmContactResponse_InverseMass(o, tri[c]);
	}
	double gap = thickness - fmDot(pc->normal, fmSub(fmLoad(b->state.x, pc->vertex), q));
	gap = fmMin(gap, pc->reach);
	if (!(gap > 0.0) || !(weight > 0.0))
		return true;
	if (!fmLogPairVertices(s, b, o, pc))
		return false;
	pc->reach -= gap;
	double lambda = gap / weight;
	fmVec3 x0 = fmLoad(b->state.x, pc->vertex);
	fmStore(b->state.x, pc->vertex,
	        fmMulAdd(x0, lambda * fmContactResponse_InverseMass(b, pc->vertex), pc->normal));
	fmContactResponse_KeepPins(b, pc->vertex, x0);
	fmContactResponse_KeepAboveFloor(w, b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		fmVec3 y0 = fmLoad(o->state.x, tri[c]);
		double share = -lambda * pc->w[c] * fmContactResponse_InverseMass(o, tri[c]);
		fmStore(o->state.x, tri[c], fmMulAdd(y0, share, pc->normal));
		fmContactResponse_KeepPins(o, tri[c], y0);
		fmContactResponse_KeepAboveFloor(w, o, tri[c]);
	}
	return true;
}

bool fmContactPair_Respond(fmWorld* w, fmContactState* s, fmPairContact* pc, double thickness)
{
	fmBody* b = &w->bodies[pc->body];
	fmBody* o = &w->bodies[pc->other];
	const int* tri = fmContactDetect_Triangle(o, pc->triangle);
	fmVec3 vq = fmMakeVec3(0.0, 0.0, 0.0);
	double weight = fmContactResponse_InverseMass(b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		vq = fmMulAdd(vq, pc->w[c], fmLoad(o->state.v, tri[c]));
		weight += pc->w[c] * pc->w[c] * fmContactResponse_InverseMass(o, tri[c]);
	}
	if (!(weight > 0.0))
		return true;
	if (!fmLogPairVertices(s, b, o, pc))
		return false;
	fmVec3 vp = fmLoad(b->state.v, pc->vertex), relative = fmSub(vp, vq), before = relative;
	// After an implicit step the penalty held the pair apart during the step (penalty.h): its
	// impulse per mass bounds friction too. Friction between bodies acts here, after the solve,
	// not inside it as against colliders (docs/contact.md, Measurements).
	double pushed = w->def.integrator == fm_implicit && pc->depth > 0.0
	                    ? FM_PENALTY_KAPPA * pc->depth / w->contactStep
	                    : 0.0;
	fmContactResponse_Impact(&relative, pc->normal, w->def.contact.restitution,
	                         fmContactResponse_PairFriction(w, b, o), pushed);
	// Explicit: a vertex caught inside the other body leaves it at the depenetration speed, as
	// one below the floor does: the projection alone gives it no velocity to leave with, and the
	// elastic forces would pull it back in every substep. The implicit solve carries the push
	// into the velocities itself where it held bodies with frozen planes; with barriers (which
	// leave bodies known to overlap to this stage) it leaves as explicit ones do.
	double separating = fmDot(relative, pc->normal);
	if (pc->embedded && (w->def.integrator != fm_implicit || fmBarrierContact_Active(w)) &&
	    separating < w->def.floor.maxDepenetrationSpeed)
		relative = fmMulAdd(relative, w->def.floor.maxDepenetrationSpeed - separating, pc->normal);
	fmVec3 impulse = fmScale(1.0 / weight, fmSub(relative, before)); // N s on the vertex
	pc->impulse = fmDot(impulse, pc->normal);
	// A creeping slip that friction takes back leaves the positions too
	// (fmContactResponse_CreepStep), as against colliders.
	double h = fmContactResponse_CreepStep(w, fmSub(relative, before), pc->normal,
	                                       fmContactResponse_PairCreep(w, thickness));
	fmVec3 slip = fmScale(h, fmMulAdd(impulse, -pc->impulse, pc->normal));
	fmVec3 x = fmLoad(b->state.x, pc->vertex);
	double inverse = fmContactResponse_InverseMass(b, pc->vertex);
	fmStore(b->state.v, pc->vertex, fmMulAdd(vp, inverse, impulse));
	fmStore(b->state.x, pc->vertex, fmMulAdd(x, inverse, slip));
	fmContactResponse_KeepPins(b, pc->vertex, x);
	fmContactResponse_KeepAboveFloor(w, b, pc->vertex);
	for (int c = 0; c < 3; ++c)
	{
		fmVec3 v0 = fmLoad(o->state.v, tri[c]), y = fmLoad(o->state.x, tri[c]);
		double share = -pc->w[c] * fmContactResponse_InverseMass(o, tri[c]);
		fmStore(o->state.v, tri[c], fmMulAdd(v0, share, impulse));
		fmStore(o->state.x, tri[c], fmMulAdd(y, share, slip));
		fmContactResponse_KeepPins(o, tri[c], y);
		fmContactResponse_KeepAboveFloor(w, o, tri[c]);
	}
	return true;
}

void fmContactPair_WakeSleeper(fmWorld* w, const fmPairContact* found)
{
	fmBody* b = &w->bodies[found->body];
	fmBody* o = &w->bodies[found->other];
	if (b->asleep || o->asleep)
		(b->asleep ? b : o)->wakeRequested = true;
}
