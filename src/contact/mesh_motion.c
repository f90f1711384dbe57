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

static const fmMeshMotionStages fmStages = {fmMeshMotion_BeginFrame, fmMeshMotion_Substep,
                                            fmMeshMotion_EndFrame};

bool fmMeshMotion_Reserve(fmWorld* w, fmMeshShape* m)
{
	w->meshMotion = &fmStages;
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
	a->velocityAt = fmMeshMotion_VelocityAt;
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

// A target set in `to`: pending, and its farthest vertex's path.
static void fmAim(fmMeshMotion* a, int count)
{
	a->far = 0.0;
	for (int i = 0; i < count; ++i)
		a->far = fmMax(a->far, fmLength(fmSub(a->to[i], a->from[i])));
	a->pending = true;
}

void fmMeshMotion_SetTarget(fmMeshShape* m, const fmVec3* vertices)
{
	fmMeshMotion* a = m->motion;
	memcpy(a->to, vertices, sizeof(fmVec3) * (size_t)m->vertexCount);
	fmAim(a, m->vertexCount);
}

fmVec3 fmMeshMotion_VelocityAt(const fmCollider* c, fmVec3 p)
{
	const fmMeshShape* m = c->mesh;
	const fmMeshMotion* a = m->motion;
	fmVec3 v = fmMakeVec3(0.0, 0.0, 0.0);
	if (a == NULL || !(a->rate > 0.0))
		return v;
	fmMat3 back = fmTranspose(&c->rotation); // into the mesh's frame
	int t;
	double w[3];
	fmMeshShape_Nearest(m, fmMatVec(&back, fmSub(p, c->position)), &t, w);
	for (int k = 0; k < 3; ++k)
	{
		int i = m->triangles[3 * t + k];
		v = fmMulAdd(v, w[k] * a->rate, fmSub(a->to[i], a->from[i]));
	}
	return fmMatVec(&c->rotation, v);
}

fmResult fmCollider_SetMeshVertices(fmColliderId colliderId, const fmVec3* vertices,
                                    int vertexCount)
{
	fmWorld* w = NULL;
	fmCollider* c = fmGetCollider(colliderId, &w);
	FM_ASSERT(c != NULL);
	if (c == NULL)
		return fm_errInvalidId;
	if (atomic_load(&w->stepping) != 0) // (from the substep callback) the frame's path is fixed
		return fm_errBusy;
	const char* problem = c->mesh == NULL    ? "a mesh collider (fm_shapeMesh)"
	                      : vertices == NULL ? "a vertices array"
	                                         : fmMeshMotion_Problem(c->mesh, vertices, vertexCount);
	if (problem != NULL)
		return fmDiagError(&w->lastError, fm_errParameter, "", 0, 0,
		                   "fmCollider_SetMeshVertices: expected %s (the mesh is unchanged)",
		                   problem);
	size_t need = c->mesh->motion == NULL ? fmMeshMotion_Bytes(c->mesh) : 0;
	size_t used = fmWorldMemoryInUse(w), budget = w->def.memoryBudget;
	if (used > budget || need > budget - used)
		return fmDiagError(&w->lastError, fm_errLimit, "", 0, 0,
		                   "a moving mesh collider needs %zu more bytes than the memory budget "
		                   "(fmWorldDef.memoryBudget) leaves",
		                   need - (used > budget ? 0 : budget - used));
	if (!fmMeshMotion_Reserve(w, c->mesh))
		return fmDiagError(&w->lastError, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for a moving mesh collider");
	fmMeshMotion_SetTarget(c->mesh, vertices);
	return fm_ok;
}

// The motion of collider slot @p k's mesh, or NULL.
static fmMeshMotion* fmMotionOf(fmWorld* w, int k)
{
	const fmCollider* c = &w->colliders[k];
	return c->inUse && c->mesh != NULL ? c->mesh->motion : NULL;
}

void fmMeshMotion_BeginFrame(fmWorld* w, double rate)
{
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshMotion* a = fmMotionOf(w, k);
		if (a == NULL)
			continue;
		a->moving = a->pending;
		a->rate = a->pending ? rate : 0.0;
	}
}

void fmMeshMotion_Substep(fmWorld* w, double fraction)
{
	double f = fmMax(0.0, fmMin(1.0, fraction));
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshMotion* a = fmMotionOf(w, k);
		if (a == NULL || !a->pending)
			continue;
		fmMeshShape* m = w->colliders[k].mesh;
		for (int i = 0; i < m->vertexCount; ++i)
			m->vertices[i] =
			    f == 1.0 ? a->to[i] : fmMulAdd(a->from[i], f, fmSub(a->to[i], a->from[i]));
		fmMeshShape_Reshape(m, a->edgeSlots);
	}
}

void fmMeshMotion_EndFrame(fmWorld* w, bool stepped)
{
	fmMeshMotion_Substep(w, stepped ? 1.0 : 0.0);
	for (int k = 0; k < w->colliderCapacity; ++k)
	{
		fmMeshMotion* a = fmMotionOf(w, k);
		if (a == NULL || !a->pending)
			continue;
		a->rate = 0.0;
		if (stepped)
			memcpy(a->from, a->to, sizeof(fmVec3) * (size_t)w->colliders[k].mesh->vertexCount);
		a->pending = !stepped;
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
	a->pending = false;
	if (flags & 2)
	{
		memcpy(a->to, target, bytes);
		fmAim(a, m->vertexCount);
	}
	a->rate = 0.0;
	a->moving = false;
	fmMeshShape_Reshape(m, a->edgeSlots);
}
