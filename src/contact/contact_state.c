// The contact stage's buffers (contact_state.h).
#include "contact/contact_state.h"

#include "core/core.h"

#include <string.h>

fmContactState* fmContactState_Get(fmWorld* w)
{
	if (w->contactState == NULL)
		w->contactState = FM_ALLOC_ZERO(fmContactState, 1);
	return w->contactState;
}

void fmContactState_Free(fmContactState* s)
{
	if (s == NULL)
		return;
	fmSpatialHash_Free(&s->hash);
	fmTetHash_Free(&s->tetHash);
	for (int k = 0; k < FM_MAX_WORKERS; ++k)
		fmBarrierScratch_Free(&s->barrier[k]);
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
	FM_FREE_ARRAY(s->neighbourStart, int, s->bodyBoxCapacity + 1);
	FM_FREE_ARRAY(s->neighbour, int, s->neighbourCapacity);
	fmBodySweep_Free(&s->sweep);
	FM_FREE_ARRAY(s->live, int, s->bodyBoxCapacity);
	FM_FREE_ARRAY(s->pairContacts, fmPairContact, s->pairContactCapacity);
	FM_FREE_ARRAY(s->edgeContacts, fmEdgeContact, s->edgeContactCapacity);
	FM_FREE_ARRAY(s->points, fmContactPoint, s->pointCapacity);
	FM_FREE_ARRAY(s->pairs, uint64_t, s->pairCapacity);
	FM_FREE_ARRAY(s->lastPairs, uint64_t, s->lastPairCapacity);
	FM_FREE_ARRAY(s->events, fmContactEvent, s->eventCapacity);
	FM_FREE_ARRAY(s->logged, fmLoggedVertex, s->loggedCapacity);
	FM_FREE_ARRAY(s->tets, int, s->tetCapacity);
	FM_FREE_ARRAY(s->forces, double, s->forceCapacity);
	FM_FREE_ARRAY(s, fmContactState, 1);
}

bool fmContactState_ReserveBodyBoxes(const fmWorld* w, fmContactState* s)
{
	if (w->bodyCapacity <= s->bodyBoxCapacity)
		return true;
	int old = s->bodyBoxCapacity;
	FM_FREE_ARRAY(s->bodyLower, fmVec3, old);
	FM_FREE_ARRAY(s->bodyUpper, fmVec3, old);
	FM_FREE_ARRAY(s->bodyNear, bool, old);
	FM_FREE_ARRAY(s->bodySpeed, double, old);
	FM_FREE_ARRAY(s->neighbourStart, int, old + 1);
	FM_FREE_ARRAY(s->live, int, old);
	s->bodyLower = FM_ALLOC_ARRAY(fmVec3, w->bodyCapacity);
	s->bodyUpper = FM_ALLOC_ARRAY(fmVec3, w->bodyCapacity);
	s->bodyNear = FM_ALLOC_ARRAY(bool, w->bodyCapacity);
	s->bodySpeed = FM_ALLOC_ARRAY(double, w->bodyCapacity);
	s->neighbourStart = FM_ALLOC_ARRAY(int, w->bodyCapacity + 1);
	s->live = FM_ALLOC_ARRAY(int, w->bodyCapacity);
	s->bodyBoxCapacity = w->bodyCapacity;
	if (s->bodyLower && s->bodyUpper && s->bodyNear && s->bodySpeed && s->neighbourStart && s->live)
		return true;
	FM_FREE_ARRAY(s->bodyLower, fmVec3, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodyUpper, fmVec3, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodyNear, bool, w->bodyCapacity);
	FM_FREE_ARRAY(s->bodySpeed, double, w->bodyCapacity);
	FM_FREE_ARRAY(s->neighbourStart, int, w->bodyCapacity + 1);
	FM_FREE_ARRAY(s->live, int, w->bodyCapacity);
	s->bodyBoxCapacity = 0;
	return false;
}

bool fmContactState_RecordPair(fmContactState* s, uint64_t key)
{
	if (s->pairCount > 0 && s->pairs[s->pairCount - 1] == key)
		return true;
	if (!fmGrowArray((void**)&s->pairs, &s->pairCapacity, s->pairCount, s->pairCount + 1,
	                 sizeof(uint64_t)))
		return false;
	s->pairs[s->pairCount++] = key;
	return true;
}

fmContactPoint* fmContactState_NewPoint(fmContactState* s)
{
	if (!fmGrowArray((void**)&s->points, &s->pointCapacity, s->pointCount, s->pointCount + 1,
	                 sizeof(fmContactPoint)))
		return NULL;
	fmContactPoint* p = &s->points[s->pointCount++];
	memset(p, 0, sizeof *p);
	return p;
}

bool fmContactState_LogVertex(fmContactState* s, fmBody* b, int slot, int i)
{
	if (b->contact.mark[i] != 0)
		return true;
	if (!fmGrowArray((void**)&s->logged, &s->loggedCapacity, s->loggedCount, s->loggedCount + 1,
	                 sizeof(fmLoggedVertex)))
		return false;
	fmLoggedVertex t = {slot, i, fmLoad(b->state.x, i), fmLoad(b->state.v, i)};
	s->logged[s->loggedCount++] = t;
	b->contact.mark[i] = s->loggedCount;
	return true;
}
