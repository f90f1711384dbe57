// The frozen planes of an implicit step (contact_planes.h).
#include "contact/contact_planes.h"

#include "contact/penalty.h"

#include "contact/contact_detect.h"
#include "contact/contact_edge.h"
#include "contact/contact_pair.h"
#include "core/core.h"
#include "core/det_math.h"

static bool fmAddEdgePlane(fmBody* b, const fmEdgePlane* plane)
{
	if (!fmGrowArray((void**)&b->contact.edgePlanes, &b->contact.edgePlaneCapacity, b->contact.edgePlaneCount,
	                 b->contact.edgePlaneCount + 1, sizeof(fmEdgePlane)))
		return false;
	b->contact.edgePlanes[b->contact.edgePlaneCount++] = *plane;
	return true;
}

bool fmContactPlanes_Predict(fmWorld* w, fmContactState* s, double thickness)
{
	// (fmContact_BeginSubstep has set every plane to none, and the motion's horizon.)
	int n = fmContactDetect_BuildTriangles(w, s, thickness)
	            ? fmContactDetect_Vertices(w, s, thickness)
	            : -1;
	for (int k = 0; k < n; ++k)
	{
		if (!s->hit[k])
			continue;
		const fmPairContact* found = &s->found[k];
		fmContactPair_WakeSleeper(w, found);
		const fmBody* o = &w->bodies[found->other];
		const int* tri = fmContactDetect_Triangle(o, found->triangle);
		fmVec3 q = fmMakeVec3(0.0, 0.0, 0.0);
		for (int c = 0; c < 3; ++c)
			q = fmMulAdd(q, found->w[c], fmLoad(o->state.x, tri[c]));
		double* plane = w->bodies[found->body].contact.plane + 4 * (size_t)found->vertex;
		plane[0] = found->normal.x;
		plane[1] = found->normal.y;
		plane[2] = found->normal.z;
		plane[3] = fmDot(found->normal, q);
	}
	bool ok = n >= 0 && fmContactDetect_Edges(w, s, thickness);
	for (int k = 0; ok && k < s->edgeContactCount; ++k)
	{
		const fmEdgeContact* c = &s->edgeContacts[k];
		fmBody* b = &w->bodies[c->body];
		fmBody* o = &w->bodies[c->other];
		fmVec3 p = fmContactEdge_Point(b->state.x, c->a, c->s), q = fmContactEdge_Point(o->state.x, c->b, c->t);
		fmEdgePlane mine = {c->a[0], c->a[1], c->s, c->normal, fmDot(c->normal, q)};
		fmVec3 away = fmScale(-1.0, c->normal);
		fmEdgePlane theirs = {c->b[0], c->b[1], c->t, away, fmDot(away, p)};
		ok = fmAddEdgePlane(b, &mine) && fmAddEdgePlane(o, &theirs);
	}
	s->edgeContactCount = 0;
	return ok;
}
