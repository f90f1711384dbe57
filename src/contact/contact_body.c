// A body's contact arrays (see contact_body.h).
#include "contact/contact_body.h"

#include "contact/floor.h"
#include "contact/friction_anchor.h"
#include "contact/penalty.h"
#include "core/core.h"

#include <string.h>

void fmBodyContact_Free(fmBodyContact* c, int vertexCount, int tetCount)
{
	size_t n = (size_t)vertexCount, m = (size_t)tetCount;
	FM_FREE_ARRAY(c->surfaceVertex, int, c->surfaceVertexCount);
	FM_FREE_ARRAY(c->surfaceEdge, int,
	              2 * (size_t)(c->surfaceEdgeCount > 0 ? c->surfaceEdgeCount : 1));
	FM_FREE_ARRAY(c->start, double, 3 * n);
	FM_FREE_ARRAY(c->mark, int, n);
	FM_FREE_ARRAY(c->embeddedHolder, int, n);
	FM_FREE_ARRAY(c->plane, double, 4 * n);
	FM_FREE_ARRAY(c->colliderGap, double, 2 * n);
	FM_FREE_ARRAY(c->friction, double, FM_FRICTION_STRIDE* n);
	FM_FREE_ARRAY(c->frictionNext, double, FM_FRICTION_STRIDE* n);
	FM_FREE_ARRAY(c->tetMark, uint8_t, m > 0 ? m : 1);
	FM_FREE_ARRAY(c->edgePlanes, fmEdgePlane, c->edgePlaneCapacity);
	FM_FREE_ARRAY(c->floorHits, fmFloorHit, c->floorHitCapacity);
	FM_FREE_ARRAY(c->stretch, fmBarrierStretch, c->stretchCapacity);
	memset(c, 0, sizeof *c);
}
