// Moving mesh colliders (mesh_motion.h): a linear path from the frame's first vertices to the
// caller's target, reshaped (normals, boxes) at every substep.
#include "contact/mesh_motion.h"

#include "contact/collider.h"
#include "core/core.h"
#include "core/det_math.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

size_t fmMeshMotion_Bytes(const fmMeshShape* m)
{
	return sizeof(fmMeshMotion) + sizeof(fmVec3) * 3 * (size_t)m->vertexCount +
	       sizeof(int) * 3 * (size_t)m->triangleCount;
}

void fmMeshMotion_Release(fmMeshShape* m)
{
	fmMeshMotion* a = m->motion;
	if (a == NULL)
		return;
	int v = m->vertexCount;
	FM_FREE_ARRAY(a->from, fmVec3, v);
	FM_FREE_ARRAY(a->to, fmVec3, v);
	FM_FREE_ARRAY(a->rest, fmVec3, v);
	FM_FREE_ARRAY(a->edgeSlots, int, 3 * (size_t)m->triangleCount);
	FM_FREE_ARRAY(a, fmMeshMotion, 1);
	m->motion = NULL;
	m->bytes -= fmMeshMotion_Bytes(m);
}

bool fmMeshMotion_Reserve(fmMeshShape* m)
{
	if (m->motion != NULL)
		return true;
	fmMeshMotion* a = FM_ALLOC_ZERO(fmMeshMotion, 1);
	if (a == NULL)
		return false;
	int v = m->vertexCount;
	m->motion = a;
	m->bytes += fmMeshMotion_Bytes(m);
	a->from = FM_ALLOC_ARRAY(fmVec3, v);
	a->to = FM_ALLOC_ARRAY(fmVec3, v);
	a->rest = FM_ALLOC_ARRAY(fmVec3, v);
	a->edgeSlots = FM_ALLOC_ARRAY(int, 3 * (size_t)m->triangleCount);
	if (a->from == NULL || a->to == NULL || a->rest == NULL || a->edgeSlots == NULL ||
	    !fmMeshShape_SortEdges(m, a->edgeSlots))
	{
		fmMeshMotion_Release(m);
		return false;
	}
	memcpy(a->from, m->vertices, sizeof(fmVec3) * (size_t)v);
	memcpy(a->rest, m->vertices, sizeof(fmVec3) * (size_t)v);
	return true;
}

const char* fmMeshMotion_Problem(const fmMeshShape* m, const void* bytes, int count)
{
	if (count != m->vertexCount)
		return "as many vertices as the mesh was created with";
	for (int i = 0; i < count; ++i)
	{
		fmVec3 v;
		memcpy(&v, (const unsigned char*)bytes + sizeof v * (size_t)i, sizeof v);
		if (!(fabs(v.x) <= FM_MAX_COORDINATE && fabs(v.y) <= FM_MAX_COORDINATE &&
		      fabs(v.z) <= FM_MAX_COORDINATE))
			return "finite vertices within FM_MAX_COORDINATE (1e9 m)";
	}
	return NULL;
}

// The box of @p count points.
static void fmPointsBox(const fmVec3* p, int count, fmVec3* lo, fmVec3* hi)
{
	*lo = *hi = p[0];
	for (int i = 1; i < count; ++i)
	{
		*lo = fmMakeVec3(fmMin(lo->x, p[i].x), fmMin(lo->y, p[i].y), fmMin(lo->z, p[i].z));
		*hi = fmMakeVec3(fmMax(hi->x, p[i].x), fmMax(hi->y, p[i].y), fmMax(hi->z, p[i].z));
	}
}

void fmMeshMotion_SetTarget(fmMeshShape* m, const fmVec3* vertices)
{
	fmMeshMotion* a = m->motion;
	memcpy(a->to, vertices, sizeof(fmVec3) * (size_t)m->vertexCount);
	fmPointsBox(a->to, m->vertexCount, &a->lo, &a->hi);
	a->pending = true;
}

fmVec3 fmMeshMotion_VelocityAt(const fmMeshShape* m, fmVec3 p)
{
	const fmMeshMotion* a = m->motion;
	fmVec3 v = fmMakeVec3(0.0, 0.0, 0.0);
	if (a == NULL || !(a->rate > 0.0))
		return v;
	int t;
	double w[3];
	fmMeshShape_Nearest(m, p, &t, w);
	for (int k = 0; k < 3; ++k)
	{
		int i = m->triangles[3 * t + k];
		v = fmMulAdd(v, w[k] * a->rate, fmSub(a->to[i], a->from[i]));
	}
	return v;
}

void fmMeshMotion_Bounds(const fmMeshShape* m, fmVec3* lo, fmVec3* hi)
{
	fmMeshShape_Bounds(m, lo, hi);
	const fmMeshMotion* a = m->motion;
	if (a == NULL || !a->pending)
		return;
	*lo = fmMakeVec3(fmMin(lo->x, a->lo.x), fmMin(lo->y, a->lo.y), fmMin(lo->z, a->lo.z));
	*hi = fmMakeVec3(fmMax(hi->x, a->hi.x), fmMax(hi->y, a->hi.y), fmMax(hi->z, a->hi.z));
}

// Place the vertices @p fraction of the way from `from` to `to` and reshape.
static void fmPlace(fmMeshShape* m, double fraction)
{
	const fmMeshMotion* a = m->motion;
	double f = fmMax(0.0, fmMin(1.0, fraction));
	for (int i = 0; i < m->vertexCount; ++i)
		m->vertices[i] = f == 1.0 ? a->to[i] : fmMulAdd(a->from[i], f, fmSub(a->to[i], a->from[i]));
	fmMeshShape_Reshape(m, a->edgeSlots);
}

// The mesh of collider slot @p k whose vertices the frame moves, or NULL.
static fmMeshShape* fmMovingMesh(fmWorld* w, int k)
{
	fmCollider* c = &w->colliders[k];
	fmMeshShape* m = c->inUse ? c->mesh : NULL;
	return m != NULL && m->motion != NULL && m->motion->pending ? m : NULL;
}

void fmMeshMotion_BeginFrame(fmWorld* w, double rate)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshShape* m = w->colliders[k].inUse ? w->colliders[k].mesh : NULL;
		fmMeshMotion* a = m != NULL ? m->motion : NULL;
		if (a != NULL)
			a->moving = a->pending;
		if (a == NULL || !a->pending)
			continue;
		a->rate = rate;
		double far = 0.0;
		for (int i = 0; i < m->vertexCount; ++i)
			far = fmMax(far, fmLength(fmSub(a->to[i], a->from[i])));
		a->speed = far * a->rate;
	}
}

void fmMeshMotion_Substep(fmWorld* w, double fraction)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshShape* m = fmMovingMesh(w, k);
		if (m != NULL)
			fmPlace(m, fraction);
	}
}

void fmMeshMotion_EndFrame(fmWorld* w, bool stepped)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshShape* m = fmMovingMesh(w, k);
		if (m == NULL)
			continue;
		fmMeshMotion* a = m->motion;
		fmPlace(m, stepped ? 1.0 : 0.0);
		a->rate = a->speed = 0.0;
		if (!stepped)
			continue;
		memcpy(a->from, a->to, sizeof(fmVec3) * (size_t)m->vertexCount);
		a->pending = false;
	}
}

int fmMeshMotion_Flags(const fmMeshShape* m)
{
	return m->motion == NULL ? 0 : m->motion->pending ? 3 : 1;
}

void fmMeshMotion_Restore(fmMeshShape* m, int flags, const void* vertices, const void* target)
{
	fmMeshMotion* a = m->motion;
	if (a == NULL)
		return; // never moved, and the snapshot's was not: the vertices are the rest shape
	size_t bytes = sizeof(fmVec3) * (size_t)m->vertexCount;
	memcpy(a->from, (flags & 1) ? vertices : (const void*)a->rest, bytes);
	memcpy(m->vertices, a->from, bytes);
	a->pending = (flags & 2) != 0;
	if (a->pending)
	{
		memcpy(a->to, target, bytes);
		fmPointsBox(a->to, m->vertexCount, &a->lo, &a->hi);
	}
	a->rate = a->speed = 0.0;
	a->moving = false;
	fmMeshShape_Reshape(m, a->edgeSlots);
}
