// Body-body detection (contact_detect.h).
#include "contact/contact_detect.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "contact/contact_edge.h"
#include "contact/contact_pair.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/timer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const int* fmContactDetect_Triangle(const fmBody* b, int t)
{
	return b->mesh.surface + 3 * t;
}

double fmContactDetect_Motion(const fmContactState* s, const fmBody* b, int i)
{
	return fmLength(fmSub(fmLoad(b->state.x, i), fmLoad(b->contact.start, i))) +
	       s->predict * fmLength(fmLoad(b->state.v, i));
}

static bool fmBoxMeetsBody(const fmContactState* s, int k, fmVec3 lo, fmVec3 hi)
{
	fmVec3 ol = s->bodyLower[k], oh = s->bodyUpper[k];
	return !(hi.x < ol.x || lo.x > oh.x || hi.y < ol.y || lo.y > oh.y || hi.z < ol.z ||
	         lo.z > oh.z);
}

bool fmContactDetect_NearOtherBody(const fmWorld* w, const fmContactState* s, int slot, fmVec3 lo,
                                   fmVec3 hi, bool higher)
{
	(void)w;
	for (int n = s->neighbourStart[slot]; n < s->neighbourStart[slot + 1]; ++n)
		if ((!higher || s->neighbour[n] >= slot) && fmBoxMeetsBody(s, s->neighbour[n], lo, hi))
			return true;
	return false;
}

// Whether body @p k is a neighbour of body @p slot (their boxes meeting): live, itself only when
// it collides with itself, and with filters that meet.
static bool fmIsNeighbour(const fmWorld* w, int slot, int k)
{
	const fmBody* b = &w->bodies[slot];
	const fmBody* o = &w->bodies[k];
	return fmBody_IsLive(o) && (k != slot || fmFracture_MeetsItself(b)) &&
	       fmFiltersMeet(b->filter, o->filter) && !fmAnchors_Welded(b, o);
}

// Append neighbour @p k to the list being made; false when memory is short.
static bool fmAddNeighbour(fmContactState* s, int* count, int k)
{
	if (!fmGrowArray((void**)&s->neighbour, &s->neighbourCapacity, *count, *count + 1, sizeof(int)))
		return false;
	s->neighbour[(*count)++] = k;
	return true;
}

// Each body's neighbours (fmContactState.neighbour), and whether it has any (bodyNear): the
// pairs of boxes that meet by a sweep (body_sweep.h), then each body's list in slot order, its
// own slot among them when it collides with itself. The same lists as testing every pair, but
// that a body gone non-finite (the frame's checks refuse it) has none and is no one's. False
// when memory is short.
static bool fmFindNeighbours(const fmWorld* w, fmContactState* s)
{
	int live = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		if (!fmBody_IsLive(&w->bodies[slot]))
			continue;
		if (!fmBodySweep_Sweepable(s->bodyLower[slot], s->bodyUpper[slot]))
		{
			s->bodyLower[slot] = fmMakeVec3(INFINITY, INFINITY, INFINITY); // (empty: meets none)
			s->bodyUpper[slot] = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
		}
		s->live[live++] = slot;
	}
	fmBodySweep* sweep = &s->sweep;
	if (!fmBodySweep_Pairs(sweep, s->live, live, s->bodyLower, s->bodyUpper) ||
	    !fmBodySweep_Lists(sweep, w->bodyCapacity))
		return false;
	int count = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		s->neighbourStart[slot] = count;
		bool self = fmBody_IsLive(&w->bodies[slot]) && fmFracture_MeetsItself(&w->bodies[slot]) &&
		            fmBoxMeetsBody(s, slot, s->bodyLower[slot], s->bodyUpper[slot]);
		for (int n = sweep->listStart[slot]; n <= sweep->listStart[slot + 1]; ++n)
		{
			// The own slot goes where slot order puts it, before the first higher one.
			int k = n < sweep->listStart[slot + 1] ? sweep->list[n] : w->bodyCapacity;
			if (self && k > slot && !fmAddNeighbour(s, &count, slot))
				return false;
			self = self && k < slot;
			if (k < w->bodyCapacity && fmIsNeighbour(w, slot, k) && !fmAddNeighbour(s, &count, k))
				return false;
		}
		s->bodyNear[slot] = count > s->neighbourStart[slot];
	}
	s->neighbourStart[w->bodyCapacity] = count;
	return true;
}

// Every body's box: its surface vertices' box grown by the thickness and by the most any of
// them moved in the substep; and whether another body's box (or its own, when it collides with
// itself) overlaps it.
static bool fmBuildBodyBoxes(const fmWorld* w, fmContactState* s, double thickness)
{
	if (!fmContactState_ReserveBodyBoxes(w, s))
		return false;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		fmVec3 lo = fmMakeVec3(INFINITY, INFINITY, INFINITY), hi = fmScale(-1.0, lo);
		double motion = 0.0;
		for (int p = 0; fmBody_IsLive(b) && p < b->contact.surfaceVertexCount; ++p)
		{
			int i = b->contact.surfaceVertex[p];
			fmVec3 x = fmLoad(b->state.x, i);
			lo = fmMakeVec3(fmMin(lo.x, x.x), fmMin(lo.y, x.y), fmMin(lo.z, x.z));
			hi = fmMakeVec3(fmMax(hi.x, x.x), fmMax(hi.y, x.y), fmMax(hi.z, x.z));
			motion = fmMax(motion, fmContactDetect_Motion(s, b, i));
		}
		double grow = thickness + motion;
		s->bodyLower[slot] = fmSub(lo, fmMakeVec3(grow, grow, grow));
		s->bodyUpper[slot] = fmAdd(hi, fmMakeVec3(grow, grow, grow));
	}
	return fmFindNeighbours(w, s);
}

bool fmContactDetect_BuildTriangles(fmWorld* w, fmContactState* s, double thickness)
{
	int total = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		total += fmBody_IsLive(&w->bodies[slot]) ? w->bodies[slot].mesh.triangleCount : 0;
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
		for (int t = 0; fmBody_IsLive(b) && s->bodyNear[slot] && t < b->mesh.triangleCount;
		     ++t, ++k)
		{
			const int* tri = fmContactDetect_Triangle(b, t);
			fmVec3 lo = fmLoad(b->state.x, tri[0]), hi = lo;
			double motion = 0.0;
			for (int c = 0; c < 3; ++c)
			{
				fmVec3 p = fmLoad(b->state.x, tri[c]);
				lo = fmMakeVec3(fmMin(lo.x, p.x), fmMin(lo.y, p.y), fmMin(lo.z, p.z));
				hi = fmMakeVec3(fmMax(hi.x, p.x), fmMax(hi.y, p.y), fmMax(hi.z, p.z));
				motion = fmMax(motion, fmContactDetect_Motion(s, b, tri[c]));
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
// higher slot, or itself when it collides with itself: an edge is tested against those only).
static bool fmHasItems(const fmWorld* w, const fmContactState* s, int slot, bool edges)
{
	return fmBody_IsLive(&w->bodies[slot]) && s->bodyNear[slot] &&
	       (!edges || fmContactDetect_NearOtherBody(w, s, slot, s->bodyLower[slot],
	                                                s->bodyUpper[slot], true));
}

// The detection items: (body slot, surface vertex) or, with @p edges, (body slot, triangle
// edge 3 t + k) for every body that has some (fmHasItems). Returns how many, or -1 when memory
// is short.
static int fmListItems(const fmWorld* w, fmContactState* s, bool edges)
{
	int n = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		if (fmHasItems(w, s, slot, edges))
			n += edges ? 3 * w->bodies[slot].mesh.triangleCount
			           : w->bodies[slot].contact.surfaceVertexCount;
	if (!fmGrowArray((void**)&s->items, &s->itemCapacity, 0, 2 * n, sizeof(int)))
		return -1;
	n = 0;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
	{
		const fmBody* b = &w->bodies[slot];
		int count = !fmHasItems(w, s, slot, edges) ? 0
		            : edges                        ? 3 * b->mesh.triangleCount
		                                           : b->contact.surfaceVertexCount;
		for (int k = 0; k < count; ++k, ++n)
		{
			s->items[2 * n] = slot;
			s->items[2 * n + 1] = edges ? k : b->contact.surfaceVertex[k];
		}
	}
	return n;
}

static void fmDetectVertexRange(int start, int end, int worker, void* context)
{
	fmDetectTask* t = context;
	fmContactState* s = t->s;
	for (int k = start; k < end; ++k)
		s->hit[k] = fmContactPair_Find(t->w, s, &s->workers[worker], s->items[2 * k],
		                               s->items[2 * k + 1], t->thickness, &s->found[k]);
}

int fmContactDetect_Vertices(fmWorld* w, fmContactState* s, double thickness)
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
		fmContactEdge_Find(t->w, s, &s->workers[worker], s->items[2 * k], s->items[2 * k + 1],
		                   t->thickness, k);
}

static int fmCompareEdgeContacts(const void* a, const void* b)
{
	const fmEdgeContact *x = a, *y = b;
	if (x->item != y->item)
		return x->item < y->item ? -1 : 1;
	return (x->sequence > y->sequence) - (x->sequence < y->sequence);
}

bool fmContactDetect_Edges(fmWorld* w, fmContactState* s, double thickness)
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
