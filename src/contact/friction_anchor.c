// Anchored friction between bodies (friction_anchor.h).
#include "contact/friction_anchor.h"

#include "core/core.h"
#include "core/det_math.h"
#include "world/world.h"

#include <stdlib.h>
#include <string.h>

int fmBarrierStencil_Compare(const fmBarrierStencil* a, const fmBarrierStencil* b)
{
	for (int k = 0; k < 4; ++k)
	{
		if (a->body[k] != b->body[k])
			return a->body[k] < b->body[k] ? -1 : 1;
		if (a->vertex[k] != b->vertex[k])
			return a->vertex[k] < b->vertex[k] ? -1 : 1;
	}
	return (int)a->edgeEdge - (int)b->edgeEdge;
}

static int fmCompareStretch(const void* a, const void* b)
{
	return fmBarrierStencil_Compare(&((const fmBarrierStretch*)a)->stencil,
	                                &((const fmBarrierStretch*)b)->stencil);
}

// sum_j w[j] x[j] of a stencil's points where the substep began (every body's).
static fmVec3 fmStartRelative(const fmBarrierContact* bc, const fmBarrierStencil* st,
                              const double w[4])
{
	fmVec3 r = fmMakeVec3(0.0, 0.0, 0.0);
	for (int k = 0; k < 4; ++k)
	{
		const fmBody* o = &bc->world->bodies[st->body[k]];
		const double* start = st->body[k] == bc->slot ? bc->xStart : o->contact.start;
		r = fmMulAdd(r, w[k], fmLoad(start, st->vertex[k]));
	}
	return r;
}

fmVec3 fmFrictionAnchor_Carried(const fmBarrierContact* bc, const fmBarrierFriction* f)
{
	const fmBody* b = &bc->world->bodies[bc->slot];
	int lo = 0, hi = b->contact.stretchCount;
	while (lo < hi)
	{
		int mid = lo + (hi - lo) / 2;
		const fmBarrierStretch* r = &b->contact.stretch[mid];
		int order = fmBarrierStencil_Compare(&r->stencil, &f->stencil);
		if (order < 0)
			lo = mid + 1;
		else if (order > 0)
			hi = mid;
		else
		{
			fmVec3 u =
			    fmAdd(r->stretch, fmSub(fmStartRelative(bc, &r->stencil, r->w), r->relative));
			u = fmMulAdd(u, -fmDot(u, f->normal), f->normal);
			double y = fmLength(u);
			return y > f->slip ? fmScale(f->slip / y, u) : u;
		}
	}
	return fmMakeVec3(0.0, 0.0, 0.0);
}

bool fmFrictionAnchor_Keep(const fmBarrierContact* bc, fmBody* b)
{
	b->contact.stretchCount = 0;
	const fmBarrierScratch* s = bc->scratch;
	if (s == NULL || s->frictionCount == 0)
		return true;
	// Grown to the world's shared scratch at once: a body whose pairs grow to what any body's
	// reached before allocates nothing (a settling stack gains pairs long after its first touch).
	if (!fmGrowArray((void**)&b->contact.stretch, &b->contact.stretchCapacity, 0,
	                 s->frictionCount > s->frictionCapacity ? s->frictionCount
	                                                        : s->frictionCapacity,
	                 sizeof *b->contact.stretch))
		return false;
	for (int k = 0; k < s->frictionCount; ++k)
	{
		const fmBarrierFriction* f = &s->friction[k];
		fmBarrierStretch* kept = &b->contact.stretch[k];
		kept->stencil = f->stencil;
		memcpy(kept->w, f->w, sizeof kept->w);
		kept->relative = fmStartRelative(bc, &f->stencil, f->w);
		kept->stretch = f->stretch;
	}
	b->contact.stretchCount = s->frictionCount;
	qsort(b->contact.stretch, (size_t)s->frictionCount, sizeof *b->contact.stretch,
	      fmCompareStretch);
	return true;
}
