// The barrier's pairs (barrier_pairs.h): the surfaces' primitives, the candidates around a
// point or a segment, the pairs within dHat.
#include "contact/barrier_pairs.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "contact/contact.h"
#include "core/det_math.h"
#include "math/distance.h"
#include "math/geometry.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// The candidates' box reaches this many dHat past the segment they were gathered for: the
// Newton steps after the first are short, and their segments stay inside it.
#define FM_BARRIER_SLACK 0.25

// ---- the bodies' surfaces ----------------------------------------------------------------------

// The vertices of primitive @p p (1, 2 or 3 of them); returns how many.
static int fmPrimitiveVertices(const fmBody* b, const fmBarrierPrimitive* p, int v[3])
{
	if (p->kind == 0)
	{
		v[0] = b->contact.surfaceVertex[p->index];
		return 1;
	}
	if (p->kind == 1)
	{
		v[0] = b->contact.surfaceEdge[2 * p->index];
		v[1] = b->contact.surfaceEdge[2 * p->index + 1];
		return 2;
	}
	for (int k = 0; k < 3; ++k)
		v[k] = b->mesh.surface[3 * p->index + k];
	return 3;
}

static int fmPrimitiveCount(const fmBody* b, int kind)
{
	return kind == 0   ? b->contact.surfaceVertexCount
	       : kind == 1 ? b->contact.surfaceEdgeCount
	                   : b->mesh.triangleCount;
}

// The box of a primitive at @p x, swept along @p dx (NULL: none), grown by @p grow.
static void fmPrimitiveBox(const fmBody* b, const fmBarrierPrimitive* p, const double* x,
                           const double* dx, double grow, fmVec3* lo, fmVec3* hi)
{
	int v[3], n = fmPrimitiveVertices(b, p, v);
	fmVec3 l = fmMakeVec3(INFINITY, INFINITY, INFINITY), u = fmScale(-1.0, l);
	for (int k = 0; k < n; ++k)
		for (int end = 0; end < (dx != NULL ? 2 : 1); ++end)
		{
			fmVec3 q = fmLoad(x, v[k]);
			if (end)
				q = fmAdd(q, fmLoad(dx, v[k]));
			l = fmMakeVec3(fmMin(l.x, q.x), fmMin(l.y, q.y), fmMin(l.z, q.z));
			u = fmMakeVec3(fmMax(u.x, q.x), fmMax(u.y, q.y), fmMax(u.z, q.z));
		}
	*lo = fmSub(l, fmMakeVec3(grow, grow, grow));
	*hi = fmAdd(u, fmMakeVec3(grow, grow, grow));
}

// ---- gathering primitives ----------------------------------------------------------------------

static bool fmAddPrimitive(fmBarrierPrimitive** list, fmVec3** lower, fmVec3** upper, int* count,
                           int* capacity, fmBarrierPrimitive p, fmVec3 lo, fmVec3 hi)
{
	if (*count == *capacity)
	{
		int old = *capacity, grown = old > 0 ? 2 * old : 256;
		int c1 = old, c2 = old;
		if (!fmGrowArray((void**)list, capacity, old, grown, sizeof **list) ||
		    !fmGrowArray((void**)lower, &c1, old, grown, sizeof **lower) ||
		    !fmGrowArray((void**)upper, &c2, old, grown, sizeof **upper))
			return false;
	}
	(*list)[*count] = p;
	(*lower)[*count] = lo;
	(*upper)[*count] = hi;
	*count += 1;
	return true;
}

// Whether body @p b's surface (its box as noted, fmBarrierContact_NoteSurface), grown by
// @p grow, reaches into [lo, hi].
static bool fmSurfaceMeets(const fmBody* b, double grow, fmVec3 lo, fmVec3 hi)
{
	fmVec3 g = fmMakeVec3(grow, grow, grow);
	return fmBoxesMeet(fmSub(b->contact.surfaceLower, g), fmAdd(b->contact.surfaceUpper, g), lo,
	                   hi);
}

// Whether the solved body meets body @p o's surface in [lo, hi].
static bool fmMayMeet(const fmBarrierContact* bc, int o, fmVec3 lo, fmVec3 hi)
{
	const fmWorld* w = bc->world;
	const fmBody* other = &w->bodies[o];
	return o != bc->slot && fmBody_IsLive(other) &&
	       fmFiltersMeet(w->bodies[bc->slot].filter, other->filter) &&
	       !fmAnchors_Welded(&w->bodies[bc->slot], other) &&
	       !fmBarrierContact_Overlapping(w, bc->slot, o) && other->contact.surfaceEdge != NULL &&
	       other->contact.start != NULL && fmSurfaceMeets(other, bc->dHat, lo, hi);
}

// The sides of [lo, hi] that point @p q, grown by @p grow, lies wholly past (6 bits: below and
// above in x, y, z), computed as fmPrimitiveBox grows a box and compared as fmBoxesMeet does.
static uint32_t fmSidesPast(fmVec3 q, double grow, fmVec3 lo, fmVec3 hi)
{
	return (uint32_t)(q.x + grow < lo.x) | (uint32_t)(q.x - grow > hi.x) << 1 |
	       (uint32_t)(q.y + grow < lo.y) << 2 | (uint32_t)(q.y - grow > hi.y) << 3 |
	       (uint32_t)(q.z + grow < lo.z) << 4 | (uint32_t)(q.z - grow > hi.z) << 5;
}

// For each surface vertex of body @p b at @p x, into the scratch's sides: the sides it lies past
// (fmSidesPast, grown by @p grow) of each of the @p count boxes [lo[j], hi[j]], 6 bits a box (an
// empty box, lo above hi, is past on every side); false when memory is short.
static bool fmNoteSides(fmBarrierScratch* s, const fmBody* b, const double* x, double grow,
                        const fmVec3* lo, const fmVec3* hi, int count)
{
	if (!fmGrowArray((void**)&s->sides, &s->sidesCapacity, 0, b->mesh.vertexCount,
	                 sizeof *s->sides))
		return false;
	for (int k = 0; k < b->contact.surfaceVertexCount; ++k)
	{
		int v = b->contact.surfaceVertex[k];
		fmVec3 q = fmLoad(x, v);
		uint32_t sides = 0;
		for (int j = 0; j < count; ++j)
			sides |= fmSidesPast(q, grow, lo[j], hi[j]) << (6 * j);
		s->sides[v] = sides;
	}
	return true;
}

// Whether primitive @p p of body @p b surely misses box @p box of those fmNoteSides noted: all
// its vertices lie past one same side of it. Then so does its grown box (rounding is monotone:
// the box's grown corner is its vertices' extreme grown one), as fmBoxesMeet would find.
static bool fmPrimitivePast(const fmBarrierScratch* s, const fmBody* b, const fmBarrierPrimitive* p,
                            int box)
{
	int v[3], n = fmPrimitiveVertices(b, p, v);
	uint32_t common = ~0u;
	for (int k = 0; k < n; ++k)
		common &= s->sides[v[k]];
	return ((common >> (6 * box)) & 63u) != 0;
}

// The other bodies' primitives of one kind whose boxes (grown by dHat) meet [lo, hi], after the
// scratch's others, hashed, with the box around each body's ones.
static bool fmGatherKind(fmBarrierContact* bc, int kind, fmVec3 lo, fmVec3 hi)
{
	const fmWorld* w = bc->world;
	fmBarrierScratch* s = bc->scratch;
	const int start = s->otherCount;
	s->kindStart[kind] = start;
	for (int m = 0; m < s->meetCount; ++m)
	{
		const int o = s->meets[m];
		const fmBody* other = &w->bodies[o];
		if (!fmNoteSides(s, other, other->state.x, bc->dHat, &lo, &hi, 1))
			return false;
		for (int k = 0; k < fmPrimitiveCount(other, kind); ++k)
		{
			fmBarrierPrimitive p = {o, k, kind};
			if (fmPrimitivePast(s, other, &p, 0))
				continue;
			fmVec3 pl, ph;
			fmPrimitiveBox(other, &p, other->state.x, NULL, bc->dHat, &pl, &ph);
			if (fmBoxesMeet(pl, ph, lo, hi) &&
			    !fmAddPrimitive(&s->others, &s->otherLower, &s->otherUpper, &s->otherCount,
			                    &s->otherCapacity, p, pl, ph))
				return false;
		}
	}
	// The box around each other body's primitives of the kind (up to FM_BARRIER_NEAR_BOXES).
	int boxes = 0;
	for (int k = start; k < s->otherCount; ++k)
	{
		bool first = k == start || s->others[k].body != s->others[k - 1].body;
		boxes += first;
		if (boxes > FM_BARRIER_NEAR_BOXES)
			break;
		fmVec3* l = &s->othersLower[kind][boxes - 1];
		fmVec3* u = &s->othersUpper[kind][boxes - 1];
		*l = first ? s->otherLower[k] : fmMinVec(*l, s->otherLower[k]);
		*u = first ? s->otherUpper[k] : fmMaxVec(*u, s->otherUpper[k]);
	}
	s->othersBoxes[kind] = boxes;
	const bool any = s->otherCount > start; // (the arrays are NULL until something is gathered)
	return fmSpatialHash_Build(&s->otherHash[kind], any ? s->otherLower + start : NULL,
	                           any ? s->otherUpper + start : NULL, s->otherCount - start,
	                           bc->cell) &&
	       fmHashQuery_Reserve(&s->query, &s->otherHash[kind]);
}

// The other bodies' primitives whose boxes (grown by dHat) meet [lo, hi], into the scratch: by
// kind, each kind hashed on its own (a vertex meets triangles, an edge edges, a triangle
// vertices).
bool fmBarrierPairs_GatherOthers(fmBarrierContact* bc, fmVec3 lo, fmVec3 hi)
{
	const fmWorld* w = bc->world;
	fmBarrierScratch* s = bc->scratch;
	if (!fmGrowArray((void**)&s->meets, &s->meetsCapacity, 0, w->bodyCapacity, sizeof(int)))
		return false;
	// The schedule's list of the bodies the gather can meet (schedule.h), else every body.
	const fmSchedule* schedule = &w->schedule;
	const fmBodySweep* near = &schedule->gather;
	const bool listed = schedule->gatherKnown;
	const int count =
	    listed ? near->listStart[bc->slot + 1] - near->listStart[bc->slot] : w->bodyCapacity;
	s->meetCount = 0;
	for (int n = 0; n < count; ++n)
	{
		int o = listed ? near->list[near->listStart[bc->slot] + n] : n;
		if (fmMayMeet(bc, o, lo, hi))
			s->meets[s->meetCount++] = o;
	}
	s->otherCount = 0;
	for (int kind = 0; kind < 3; ++kind)
		if (!fmGatherKind(bc, kind, lo, hi))
			return false;
	s->kindStart[3] = s->otherCount;
	return true;
}

// The body's own primitives at @p x (swept along @p dx when not NULL), their boxes grown by
// @p grow, hashed for self-contact.
static bool fmGatherOwn(const fmBarrierContact* bc, const double* x, const double* dx, double grow)
{
	const fmBody* b = &bc->world->bodies[bc->slot];
	fmBarrierScratch* s = bc->scratch;
	s->ownCount = 0;
	for (int kind = 0; kind < 3; ++kind)
		for (int k = 0; k < fmPrimitiveCount(b, kind); ++k)
		{
			fmBarrierPrimitive p = {bc->slot, k, kind};
			fmVec3 lo, hi;
			fmPrimitiveBox(b, &p, x, dx, grow, &lo, &hi);
			if (!fmAddPrimitive(&s->own, &s->ownLower, &s->ownUpper, &s->ownCount, &s->ownCapacity,
			                    p, lo, hi))
				return false;
		}
	return fmSpatialHash_Build(&s->ownHash, s->ownLower, s->ownUpper, s->ownCount, bc->cell) &&
	       fmHashQuery_Reserve(&s->query, &s->ownHash);
}

// ---- pairs -------------------------------------------------------------------------------------

// Position of stencil point k: the solved body's from @p x, any other body's where it stands.
static fmVec3 fmStencilPoint(const fmBarrierContact* bc, const fmBarrierStencil* st, int k,
                             const double* x)
{
	const fmBody* o = &bc->world->bodies[st->body[k]];
	return fmLoad(st->body[k] == bc->slot ? x : o->state.x, st->vertex[k]);
}

void fmBarrierPairs_Points(const fmBarrierContact* bc, const fmBarrierStencil* st, const double* x,
                           fmVec3 p[4])
{
	for (int k = 0; k < 4; ++k)
		p[k] = fmStencilPoint(bc, st, k, x);
}

// A stencil's squared distance from its closest points (no derivatives: the broad filter's).
static double fmStencilDistance2(const fmBarrierStencil* st, const fmVec3 p[4])
{
	fmVec3 r;
	if (st->edgeEdge)
	{
		double a, c;
		fmDistance_EdgeEdgeClosest(p, &a, &c);
		r = fmSub(fmMulAdd(p[0], a, fmSub(p[1], p[0])), fmMulAdd(p[2], c, fmSub(p[3], p[2])));
	}
	else
	{
		double t[3];
		fmClosestOnTriangle(p[0], p[1], p[2], p[3], t);
		r = fmSub(p[0],
		          fmAdd(fmAdd(fmScale(t[0], p[1]), fmScale(t[1], p[2])), fmScale(t[2], p[3])));
	}
	return fmDot(r, r);
}

// The stencil of primitive @p a (of the solved body or another) against @p b: a vertex against
// a triangle or two edges; false for other kinds, or pairs that share a vertex.
static bool fmMakeStencil(const fmWorld* w, const fmBarrierPrimitive* a,
                          const fmBarrierPrimitive* b, fmBarrierStencil* st)
{
	const fmBarrierPrimitive* first = a->kind == 2 ? b : a;
	const fmBarrierPrimitive* second = a->kind == 2 ? a : b;
	if (!((first->kind == 0 && second->kind == 2) || (first->kind == 1 && second->kind == 1)))
		return false;
	int u[3], v[3];
	int nu = fmPrimitiveVertices(&w->bodies[first->body], first, u);
	int nv = fmPrimitiveVertices(&w->bodies[second->body], second, v);
	for (int i = 0; first->body == second->body && i < nu; ++i)
		for (int j = 0; j < nv; ++j)
			if (u[i] == v[j])
				return false;
	st->edgeEdge = first->kind == 1;
	for (int k = 0; k < 4; ++k)
	{
		st->body[k] = k < nu ? first->body : second->body;
		st->vertex[k] = k < nu ? u[k] : v[k - nu];
	}
	return true;
}

// A self pair counts only when its primitives are further than dHat apart at rest (pairs of a
// body's own rest shape closer than that are its shape, not a contact), or lie on two pieces a
// tear made (fracture.h).
static bool fmApartAtRest(const fmBarrierContact* bc, const fmBarrierStencil* st)
{
	const fmBody* b = &bc->world->bodies[bc->slot];
	if (fmFracture_AcrossPieces(b, st->vertex, st->edgeEdge ? 2 : 1, 4))
		return true;
	if (!b->selfCollision)
		return false; // (a torn body meets only its other pieces)
	fmVec3 p[4];
	for (int k = 0; k < 4; ++k)
		p[k] = fmLoad(b->mesh.x0, st->vertex[k]);
	return fmStencilDistance2(st, p) >= bc->sHat;
}

static bool fmPushPair(fmBarrierScratch* s, const fmBarrierPair* st)
{
	if (!fmGrowArray((void**)&s->pairs, &s->pairCapacity, s->pairCount, s->pairCount + 1,
	                 sizeof *s->pairs))
		return false;
	s->pairs[s->pairCount++] = *st;
	return true;
}

// What to do with each stencil fmVisitStencils finds; false stops the visit (out of memory).
typedef bool fmStencilVisit(const fmBarrierContact* bc, const fmBarrierStencil* st, void* context);

// Whether [lo, hi] meets the box around some other body's primitives of @p kind (or there are
// more such bodies than boxes kept).
static bool fmNearOthers(const fmBarrierScratch* s, int kind, fmVec3 lo, fmVec3 hi)
{
	if (s->othersBoxes[kind] > FM_BARRIER_NEAR_BOXES)
		return true;
	for (int k = 0; k < s->othersBoxes[kind]; ++k)
		if (fmBoxesMeet(lo, hi, s->othersLower[kind][k], s->othersUpper[kind][k]))
			return true;
	return false;
}

// Every stencil of the solved body's primitive @p p with the other bodies' primitives (or, with
// @p self, its own) whose stored boxes meet [lo, hi], handed to @p visit. Self pairs: a vertex
// against triangles and each pair of edges once, only those apart at rest.
static bool fmVisitStencils(const fmBarrierContact* bc, const fmBarrierPrimitive* p, fmVec3 lo,
                            fmVec3 hi, bool self, fmStencilVisit* visit, void* context)
{
	fmBarrierScratch* s = bc->scratch;
	const int kind = 2 - p->kind; // the kind of the others' primitives p meets
	if (!self && !fmNearOthers(s, kind, lo, hi))
		return true;
	int n = fmSpatialHash_Query(self ? &s->ownHash : &s->otherHash[kind], &s->query, lo, hi);
	if (n < 0)
		return false;
	const int offset = self ? 0 : s->kindStart[kind];
	const fmBarrierPrimitive* list = self ? s->own : s->others;
	const fmVec3* lower = self ? s->ownLower : s->otherLower;
	const fmVec3* upper = self ? s->ownUpper : s->otherUpper;
	for (int k = 0; k < n; ++k)
	{
		int item = s->query.items[k] + offset;
		const fmBarrierPrimitive* q = &list[item];
		if (!fmBoxesMeet(lo, hi, lower[item], upper[item]) ||
		    (self && (p->kind == 2 || (p->kind == 1 && q->index <= p->index))))
			continue;
		fmBarrierStencil st;
		if (fmMakeStencil(bc->world, p, q, &st) && (!self || fmApartAtRest(bc, &st)) &&
		    !visit(bc, &st, context))
			return false;
	}
	return true;
}

// Each of the solved body's primitives, its box at @p x (swept along @p dx when not NULL) grown
// by @p grow against the others and by @p selfGrow against its own, visited. Against the others,
// a primitive whose vertices all lie past one side of the others' boxes is skipped unboxed (the
// same primitives are visited: fmPrimitivePast).
static bool fmVisitBody(const fmBarrierContact* bc, const double* x, const double* dx, double grow,
                        double selfGrow, fmStencilVisit* visit, void* context)
{
	const fmBody* b = &bc->world->bodies[bc->slot];
	fmBarrierScratch* s = bc->scratch;
	const bool others = s->otherCount > 0;
	// The box around the others' primitives of each kind (when their boxes are kept).
	fmVec3 near[3], far[3]; // lower and upper corners
	bool sides = others && dx == NULL;
	for (int kind = 0; sides && kind < 3; ++kind)
	{
		sides = s->othersBoxes[kind] <= FM_BARRIER_NEAR_BOXES;
		near[kind] = fmMakeVec3(INFINITY, INFINITY, INFINITY);
		far[kind] = fmScale(-1.0, near[kind]);
		for (int j = 0; sides && j < s->othersBoxes[kind]; ++j)
		{
			near[kind] = fmMinVec(near[kind], s->othersLower[kind][j]);
			far[kind] = fmMaxVec(far[kind], s->othersUpper[kind][j]);
		}
	}
	if (sides && !fmNoteSides(s, b, x, grow, near, far, 3))
		return false;
	for (int kind = 0; kind < 3; ++kind)
		for (int k = 0; k < fmPrimitiveCount(b, kind); ++k)
		{
			fmBarrierPrimitive p = {bc->slot, k, kind};
			fmVec3 lo, hi;
			if (others && !(sides && fmPrimitivePast(s, b, &p, 2 - kind)))
			{
				fmPrimitiveBox(b, &p, x, dx, grow, &lo, &hi);
				if (!fmVisitStencils(bc, &p, lo, hi, false, visit, context))
					return false;
			}
			if (bc->self)
			{
				fmPrimitiveBox(b, &p, x, dx, selfGrow, &lo, &hi);
				if (!fmVisitStencils(bc, &p, lo, hi, true, visit, context))
					return false;
			}
		}
	return true;
}

// Whether the boxes of a stencil's two sides (its points @p p, swept by @p motion when not NULL)
// are more than dHat apart on some axis: then no point of the sweep brings the pair within dHat.
bool fmBarrierPairs_SidesApart(const fmBarrierContact* bc, const fmBarrierStencil* st,
                               const fmVec3 p[4], const fmVec3* motion)
{
	fmVec3 end[4];
	for (int k = 0; k < 4; ++k)
		end[k] = motion != NULL ? fmAdd(p[k], motion[k]) : p[k];
	int split = st->edgeEdge ? 2 : 1;
	fmVec3 lo[2] = {fmMinVec(p[0], end[0]), fmMinVec(p[split], end[split])};
	fmVec3 hi[2] = {fmMaxVec(p[0], end[0]), fmMaxVec(p[split], end[split])};
	for (int k = 1; k < 4; ++k)
	{
		if (k == split)
			continue;
		int side = k < split ? 0 : 1;
		lo[side] = fmMinVec(lo[side], fmMinVec(p[k], end[k]));
		hi[side] = fmMaxVec(hi[side], fmMaxVec(p[k], end[k]));
	}
	double d = bc->dHat;
	return lo[0].x > hi[1].x + d || lo[1].x > hi[0].x + d || lo[0].y > hi[1].y + d ||
	       lo[1].y > hi[0].y + d || lo[0].z > hi[1].z + d || lo[1].z > hi[0].z + d;
}

// The closest points' weights of a stencil at @p p: sum_j w[j] p[j] is the vector between them.
static void fmClosestWeights(const fmBarrierStencil* st, const fmVec3 p[4], double w[4])
{
	if (st->edgeEdge)
	{
		double a, c;
		fmDistance_EdgeEdgeClosest(p, &a, &c);
		w[0] = 1.0 - a, w[1] = a, w[2] = -(1.0 - c), w[3] = -c;
		return;
	}
	double t[3];
	fmClosestOnTriangle(p[0], p[1], p[2], p[3], t);
	w[0] = 1.0, w[1] = -t[0], w[2] = -t[1], w[3] = -t[2];
}

// Stencil @p st at @p x as a pair: its closest points' weights, the vector between them and its
// squared length.
static fmBarrierPair fmPairAt(const fmBarrierContact* bc, const fmBarrierStencil* st,
                              const double* x)
{
	fmBarrierPair pair;
	fmVec3 p[4];
	fmBarrierPairs_Points(bc, st, x, p);
	pair.stencil = *st;
	fmClosestWeights(st, p, pair.w);
	pair.r = fmMakeVec3(0.0, 0.0, 0.0);
	for (int j = 0; j < 4; ++j)
		pair.r = fmMulAdd(pair.r, pair.w[j], p[j]);
	pair.d2 = fmDot(pair.r, pair.r);
	return pair;
}

// A candidate gathered around @p context (the candidates' centre) is kept unless it is so far
// there that no point of the box brings it within dHat: each vertex of the body moves at most
// sqrt(3) radius from the centre, so a distance changes by at most twice that.
static bool fmKeepCandidate(const fmBarrierContact* bc, const fmBarrierStencil* st, void* context)
{
	fmBarrierScratch* s = bc->scratch;
	fmVec3 pts[4];
	fmBarrierPairs_Points(bc, st, context, pts);
	double slack = sqrt(fmStencilDistance2(st, pts)) - bc->dHat;
	if (slack > 2.0 * sqrt(3.0) * s->candidateRadius * (1.0 + 1e-9))
		return true;
	if (!fmGrowArray((void**)&s->candidates, &s->candidateCapacity, s->candidateCount,
	                 s->candidateCount + 1, sizeof *s->candidates) ||
	    !fmGrowArray((void**)&s->candidateSlack, &s->slackCapacity, s->candidateCount,
	                 s->candidateCount + 1, sizeof *s->candidateSlack))
		return false;
	s->candidateSlack[s->candidateCount] = slack;
	s->candidates[s->candidateCount++] = *st;
	return true;
}

// Whether candidate @p k surely stays beyond dHat at @p x: none of the solved body's vertices in
// it moved half its slack from the candidates' centre.
bool fmBarrierPairs_SurelyFar(const fmBarrierContact* bc, int k, const double* x)
{
	const fmBarrierScratch* s = bc->scratch;
	const fmBarrierStencil* st = &s->candidates[k];
	double slack = s->candidateSlack[k], moved = 0.0;
	if (!(slack > 0.0))
		return false;
	for (int j = 0; j < 4; ++j)
		if (st->body[j] == bc->slot)
		{
			fmVec3 d = fmSub(fmLoad(x, st->vertex[j]), fmLoad(s->candidateCentre, st->vertex[j]));
			moved = fmMax(moved, fmDot(d, d));
		}
	return 4.0 * moved < slack * slack * (1.0 - 1e-9);
}

// Whether the candidates cover @p x and, when @p dx is not NULL, x + dx (and so the segment
// between: the box is convex).
static bool fmCandidatesCover(const fmBarrierContact* bc, const double* x, const double* dx)
{
	const fmBarrierScratch* s = bc->scratch;
	const int n3 = 3 * bc->world->bodies[bc->slot].mesh.vertexCount;
	if (s->candidateCount < 0)
		return false;
	for (int k = 0; k < n3; ++k)
		if (!(fabs(x[k] - s->candidateCentre[k]) <= s->candidateRadius &&
		      (dx == NULL || fabs(x[k] + dx[k] - s->candidateCentre[k]) <= s->candidateRadius)))
			return false;
	return true;
}

// Candidates covering the segment from @p x along @p dx (NULL: the point): kept when they do,
// else gathered again for the box around the segment's middle reaching FM_BARRIER_SLACK dHat
// past it: every pair that can come within dHat while each coordinate of the body stays in the
// box (the others standing still), its own primitives' boxes grown by the radius too.
bool fmBarrierPairs_Cover(const fmBarrierContact* bc, const double* x, const double* dx)
{
	fmBarrierScratch* s = bc->scratch;
	if (fmCandidatesCover(bc, x, dx))
		return true;
	const int n3 = 3 * bc->world->bodies[bc->slot].mesh.vertexCount;
	int capacity = s->centreCapacity;
	if (!fmGrowArray((void**)&s->candidateCentre, &capacity, 0, n3, sizeof(double)))
		return false;
	s->centreCapacity = capacity;
	double half = 0.0;
	for (int k = 0; k < n3; ++k)
	{
		double d = dx != NULL ? 0.5 * dx[k] : 0.0;
		s->candidateCentre[k] = x[k] + d;
		half = fmMax(half, fabs(d));
	}
	const double r = half + FM_BARRIER_SLACK * bc->dHat;
	s->candidateRadius = r;
	s->candidateCount = 0;
	s->pairsKnown = false;
	const double grow = r * (1.0 + 1e-9);
	if ((bc->self && !fmGatherOwn(bc, s->candidateCentre, NULL, grow + 0.5 * bc->dHat)) ||
	    !fmVisitBody(bc, s->candidateCentre, NULL, grow, grow + 0.5 * bc->dHat, fmKeepCandidate,
	                 s->candidateCentre))
	{
		s->candidateCount = -1;
		return false;
	}
	return true;
}

// The pairs within dHat at @p x, into the scratch (in the candidates' order: deterministic);
// kept from the last call at the same positions (a solve evaluates each point up to three times:
// the line search's energy, the gradient, the Hessian).
bool fmBarrierPairs_Find(const fmBarrierContact* bc, const double* x)
{
	fmBarrierScratch* s = bc->scratch;
	const int n3 = 3 * bc->world->bodies[bc->slot].mesh.vertexCount;
	if (s->pairsKnown && memcmp(s->pairsAt, x, sizeof(double) * (size_t)n3) == 0)
		return true;
	s->pairCount = 0;
	s->pairsKnown = false;
	if (!fmBarrierPairs_Cover(bc, x, NULL))
		return false;
	for (int k = 0; k < s->candidateCount; ++k)
	{
		if (fmBarrierPairs_SurelyFar(bc, k, x))
			continue;
		fmBarrierPair pair = fmPairAt(bc, &s->candidates[k], x);
		if (pair.d2 < bc->sHat && !fmPushPair(s, &pair))
			return false;
	}
	if (!fmGrowArray((void**)&s->pairsAt, &s->pairsAtCapacity, 0, n3, sizeof(double)))
		return false;
	memcpy(s->pairsAt, x, sizeof(double) * (size_t)n3);
	s->pairsKnown = true;
	return true;
}
