// Edge against edge between bodies (contact_edge.h).
#include "contact/contact_edge.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "contact/contact.h"
#include "contact/contact_detect.h"
#include "contact/contact_response.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/timer.h"

#include <math.h>

// The cross product of surface triangle @p tri's edges (its normal times twice its area).
static fmVec3 fmTriangleCross(const fmBody* b, const int* tri)
{
	fmVec3 a = fmLoad(b->state.x, tri[0]);
	return fmCross(fmSub(fmLoad(b->state.x, tri[1]), a), fmSub(fmLoad(b->state.x, tri[2]), a));
}

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

fmVec3 fmContactEdge_Point(const double* x, const int e[2], double s)
{
	return fmMulAdd(fmLoad(x, e[0]), s, fmSub(fmLoad(x, e[1]), fmLoad(x, e[0])));
}

// Whether edges @p e and @p f of one body may touch each other (self-collision): each pair once,
// and only when they share no vertex and were apart in the rest shape by more than twice the
// thickness (as a vertex and its own triangles, contact_pair.c), or lie on two pieces a tear made.
static bool fmSelfEdges(const fmBody* b, const int e[2], const int f[2], double thickness)
{
	if (e[0] > f[0] || (e[0] == f[0] && e[1] >= f[1]) || e[0] == f[1] || e[1] == f[0] ||
	    e[1] == f[1])
		return false;
	const int stencil[4] = {e[0], e[1], f[0], f[1]};
	if (fmFracture_AcrossPieces(b, stencil, 2, 4))
		return true;
	if (!b->selfCollision)
		return false; // (a torn body meets only its other pieces)
	fmVec3 p = fmLoad(b->mesh.x0, e[0]), q = fmLoad(b->mesh.x0, e[1]);
	fmVec3 r = fmLoad(b->mesh.x0, f[0]), t = fmLoad(b->mesh.x0, f[1]);
	double sa, tb;
	fmClosestSegments(p, q, r, t, &sa, &tb);
	fmVec3 d = fmSub(fmMulAdd(p, sa, fmSub(q, p)), fmMulAdd(r, tb, fmSub(t, r)));
	return fmLength(d) > 2.0 * thickness;
}

// Edge e of body b (@p side: the normal of a triangle of b's with that edge) against the edges
// of triangle @p tri of body o: a contact when their closest points are inside both edges and
// within the thickness, or when the edges crossed during the substep (the direction between the
// closest points turned over); before an implicit step (s->predicting), when they are within
// reach of the step's motion and face each other. Appends to the edge list.
static bool fmEdgeAgainstTriangle(const fmContactState* s, fmWorkerFinds* wf, const fmBody* b,
                                  int slot, const int e[2], fmVec3 side, const fmBody* o, int other,
                                  const int* tri, double thickness, double depen, int item)
{
	// (Only the frozen planes before an implicit step ask which way the faces look.)
	fmVec3 face = s->predicting ? fmTriangleCross(o, tri) : fmMakeVec3(0.0, 0.0, 0.0);
	for (int k = 0; k < 3; ++k)
	{
		int f[2] = {tri[k], tri[(k + 1) % 3]};
		if (f[0] > f[1])
			continue; // each edge of o once (closed surfaces list it both ways)
		if (other == slot && !fmSelfEdges(b, e, f, thickness))
			continue;
		double sa, tb;
		fmClosestSegments(fmLoad(b->state.x, e[0]), fmLoad(b->state.x, e[1]),
		                  fmLoad(o->state.x, f[0]), fmLoad(o->state.x, f[1]), &sa, &tb);
		if (sa <= 0.0 || sa >= 1.0 || tb <= 0.0 || tb >= 1.0)
			continue;
		fmVec3 d =
		    fmSub(fmContactEdge_Point(b->state.x, e, sa), fmContactEdge_Point(o->state.x, f, tb));
		fmVec3 d0 = fmSub(fmContactEdge_Point(b->contact.start, e, sa),
		                  fmContactEdge_Point(o->contact.start, f, tb));
		double distance = fmLength(d), start = fmLength(d0);
		double reach = thickness + fmContactDetect_Motion(s, b, e[0]) +
		               fmContactDetect_Motion(s, b, e[1]) + fmContactDetect_Motion(s, o, f[0]) +
		               fmContactDetect_Motion(s, o, f[1]);
		// A crossing: the direction between the closest points turned over within the substep
		// while they were within reach of each other. (Before an implicit step: edges within
		// reach of the step's motion, for its frozen edge planes.)
		bool crossed = !s->predicting && fmDot(d, d0) < 0.0 && start > 0.0 && start < reach;
		double near = s->predicting ? reach : thickness;
		if (!(crossed || (distance < near && distance > 0.0)))
			continue;
		// A frozen plane only between edges that face each other: the direction from o's edge
		// to b's leaves o through the face and enters b against the face of b's edge (@p side).
		// Edges of bodies already inside each other would otherwise be held there.
		if (s->predicting && !(fmDot(d, face) > 0.0 && fmDot(d, side) < 0.0))
			continue;
		if (!fmGrowArray((void**)&wf->edges, &wf->edgeCapacity, wf->edgeCount, wf->edgeCount + 1,
		                 sizeof(fmEdgeContact)))
			return false;
		fmEdgeContact* c = &wf->edges[wf->edgeCount++];
		c->body = slot, c->other = other;
		c->a[0] = e[0], c->a[1] = e[1], c->b[0] = f[0], c->b[1] = f[1];
		c->s = sa, c->t = tb;
		c->normal = crossed ? fmScale(1.0 / start, d0) : fmScale(1.0 / distance, d);
		double from = fmDot(d0, c->normal);
		double closing = from - fmDot(d, c->normal);
		// A body's own edges are kept from coming closer, as its vertices are (contact_pair.c).
		c->reach = s->predicting   ? reach
		           : other == slot ? fmMax(depen, fmMax(0.0, closing))
		                           : fmContactResponse_Reach(from, closing, thickness, depen);
		c->impulse = 0.0;
		c->item = item;
		c->sequence = wf->edgeCount; // increasing within the item
	}
	return true;
}

void fmContactEdge_Find(const fmWorld* w, const fmContactState* s, fmWorkerFinds* wf, int slot,
                        int edge, double thickness, int item)
{
	const fmBody* b = &w->bodies[slot];
	const int* tri = fmContactDetect_Triangle(b, edge / 3);
	int e[2] = {tri[edge % 3], tri[(edge % 3 + 1) % 3]};
	if (e[0] > e[1])
		return;
	fmVec3 side = s->predicting ? fmTriangleCross(b, tri) : fmMakeVec3(0.0, 0.0, 0.0);
	fmVec3 p = fmLoad(b->state.x, e[0]), q = fmLoad(b->state.x, e[1]);
	double reach =
	    thickness + fmMax(fmContactDetect_Motion(s, b, e[0]), fmContactDetect_Motion(s, b, e[1]));
	fmVec3 lo =
	    fmMakeVec3(fmMin(p.x, q.x) - reach, fmMin(p.y, q.y) - reach, fmMin(p.z, q.z) - reach);
	fmVec3 hi =
	    fmMakeVec3(fmMax(p.x, q.x) + reach, fmMax(p.y, q.y) + reach, fmMax(p.z, q.z) + reach);
	if (!(fabs(lo.x) + fabs(lo.y) + fabs(lo.z) + fabs(hi.x) + fabs(hi.y) + fabs(hi.z) < 1e30))
		return; // non-finite: the frame's checks report it
	if (!fmContactDetect_NearOtherBody(w, s, slot, lo, hi, true))
		return;
	const double depen = fmContactResponse_DepenetrationStep(w);
	double start = fmSeconds();
	int count = fmSpatialHash_Query(&s->hash, &wf->query, lo, hi);
	wf->broadPhase += fmSeconds() - start;
	wf->failed = wf->failed || count < 0;
	for (int c = 0; c < count && !wf->failed; ++c)
	{
		int found = wf->query.items[c], other = s->triangleBody[found];
		const fmBody* o = &w->bodies[other];
		fmVec3 ilo = s->lower[found], ihi = s->upper[found];
		if (other < slot || (other == slot && !fmFracture_MeetsItself(b)) ||
		    !fmFiltersMeet(b->filter, o->filter) || (b->asleep && o->asleep) ||
		    fmAnchors_Welded(b, o) || hi.x < ilo.x || lo.x > ihi.x || hi.y < ilo.y ||
		    lo.y > ihi.y || hi.z < ilo.z || lo.z > ihi.z)
			continue;
		wf->failed = !fmEdgeAgainstTriangle(s, wf, b, slot, e, side, o, other,
		                                    fmContactDetect_Triangle(o, s->triangleIndex[found]),
		                                    thickness, depen, item);
	}
}

// The four weights of an edge contact's vertices in its projection and response.
static void fmEdgeWeights(const fmEdgeContact* c, double weights[4])
{
	weights[0] = 1.0 - c->s, weights[1] = c->s, weights[2] = -(1.0 - c->t), weights[3] = -c->t;
}

static bool fmLogEdgeVertices(fmContactState* s, fmBody* b, fmBody* o, const fmEdgeContact* c)
{
	return fmContactState_LogVertex(s, b, c->body, c->a[0]) &&
	       fmContactState_LogVertex(s, b, c->body, c->a[1]) &&
	       fmContactState_LogVertex(s, o, c->other, c->b[0]) &&
	       fmContactState_LogVertex(s, o, c->other, c->b[1]);
}

bool fmContactEdge_Project(fmWorld* w, fmContactState* s, fmEdgeContact* c, double thickness)
{
	fmBody* b = &w->bodies[c->body];
	fmBody* o = &w->bodies[c->other];
	double weights[4], inverse[4] = {fmContactResponse_InverseMass(b, c->a[0]),
	                                 fmContactResponse_InverseMass(b, c->a[1]),
	                                 fmContactResponse_InverseMass(o, c->b[0]),
	                                 fmContactResponse_InverseMass(o, c->b[1])};
	fmEdgeWeights(c, weights);
	double sum = 0.0;
	for (int k = 0; k < 4; ++k)
		sum += weights[k] * weights[k] * inverse[k];
	fmVec3 d = fmSub(fmContactEdge_Point(b->state.x, c->a, c->s),
	                 fmContactEdge_Point(o->state.x, c->b, c->t));
	double gap = fmMin(thickness - fmDot(c->normal, d), c->reach);
	if (!(gap > 0.0) || !(sum > 0.0))
		return true;
	if (!fmLogEdgeVertices(s, b, o, c))
		return false;
	c->reach -= gap;
	double lambda = gap / sum;
	fmBody* bodies[4] = {b, b, o, o};
	const int vertices[4] = {c->a[0], c->a[1], c->b[0], c->b[1]};
	for (int k = 0; k < 4; ++k)
	{
		fmVec3 x0 = fmLoad(bodies[k]->state.x, vertices[k]);
		fmStore(bodies[k]->state.x, vertices[k],
		        fmMulAdd(x0, lambda * weights[k] * inverse[k], c->normal));
		fmContactResponse_KeepPins(bodies[k], vertices[k], x0);
		fmContactResponse_KeepAboveFloor(w, bodies[k], vertices[k]);
	}
	return true;
}

bool fmContactEdge_Respond(fmWorld* w, fmContactState* s, fmEdgeContact* c)
{
	fmBody* b = &w->bodies[c->body];
	fmBody* o = &w->bodies[c->other];
	double weights[4], inverse[4] = {fmContactResponse_InverseMass(b, c->a[0]),
	                                 fmContactResponse_InverseMass(b, c->a[1]),
	                                 fmContactResponse_InverseMass(o, c->b[0]),
	                                 fmContactResponse_InverseMass(o, c->b[1])};
	fmEdgeWeights(c, weights);
	fmBody* bodies[4] = {b, b, o, o};
	const int vertices[4] = {c->a[0], c->a[1], c->b[0], c->b[1]};
	double sum = 0.0;
	fmVec3 relative = fmMakeVec3(0.0, 0.0, 0.0);
	for (int k = 0; k < 4; ++k)
	{
		sum += weights[k] * weights[k] * inverse[k];
		relative = fmMulAdd(relative, weights[k], fmLoad(bodies[k]->state.v, vertices[k]));
	}
	if (!(sum > 0.0))
		return true;
	if (!fmLogEdgeVertices(s, b, o, c))
		return false;
	fmVec3 before = relative;
	fmContactResponse_Impact(&relative, c->normal, w->def.contact.restitution,
	                         fmContactResponse_PairFriction(w, b, o), 0.0);
	fmVec3 impulse = fmScale(1.0 / sum, fmSub(relative, before));
	c->impulse = fmDot(impulse, c->normal);
	// A creeping slip that friction takes back leaves the positions too, as for a vertex.
	double h = fmContactResponse_CreepStep(w, fmSub(relative, before), c->normal,
	                                       fmContactResponse_PairCreep(w, fmContact_Thickness(w)));
	fmVec3 slip = fmScale(h, fmMulAdd(impulse, -c->impulse, c->normal));
	for (int k = 0; k < 4; ++k)
	{
		fmVec3 x = fmLoad(bodies[k]->state.x, vertices[k]);
		fmVec3 v = fmLoad(bodies[k]->state.v, vertices[k]);
		fmStore(bodies[k]->state.v, vertices[k], fmMulAdd(v, weights[k] * inverse[k], impulse));
		fmStore(bodies[k]->state.x, vertices[k], fmMulAdd(x, weights[k] * inverse[k], slip));
		fmContactResponse_KeepPins(bodies[k], vertices[k], x);
		fmContactResponse_KeepAboveFloor(w, bodies[k], vertices[k]);
	}
	return true;
}

bool fmContactEdge_Record(fmWorld* w, fmContactState* s, const fmEdgeContact* c)
{
	fmContactPoint* point = fmContactState_NewPoint(s);
	if (point == NULL)
		return false;
	const fmBody* b = &w->bodies[c->body];
	point->body = fmWorldBodyId(w, c->body);
	point->vertex = b->userVertex[c->s < 0.5 ? c->a[0] : c->a[1]];
	point->otherBody = fmWorldBodyId(w, c->other);
	point->point = fmContactEdge_Point(b->state.x, c->a, c->s);
	point->normal = c->normal;
	point->impulse = c->impulse;
	return fmContactState_RecordPair(s, ((uint64_t)(uint32_t)c->body << 32) | (uint32_t)c->other);
}
