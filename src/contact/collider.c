// Rigid colliders (collider.h): exact signed distances of the four shapes, a segment cast by
// sphere tracing on them (exact distances make every step safe), kinematic motion.
#include "contact/collider.h"
#include "contact/contact_collider.h"
#include "contact/mesh_motion.h"

#include "core/core.h"
#include "core/det_math.h"
#include "world/world.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

// Most sphere-tracing steps of a segment cast; a grazing segment that needs more is reported
// as missing (the distance query of the end point still catches what it leaves inside).
#define FM_CAST_STEPS 64

fmMat3 fmRotationFromAxisAngle(fmVec3 w)
{
	double angle = fmLength(w);
	if (!(angle > 0.0))
		return fmIdentity3();
	fmVec3 k = fmScale(1.0 / angle, w);
	double c, s;
	fmDetSinCos(angle, &s, &c); // the same bits on every target (det_math.h)
	double t = 1.0 - c;
	fmMat3 R;
	R.m[0] = c + t * k.x * k.x;
	R.m[1] = t * k.x * k.y - s * k.z;
	R.m[2] = t * k.x * k.z + s * k.y;
	R.m[3] = t * k.x * k.y + s * k.z;
	R.m[4] = c + t * k.y * k.y;
	R.m[5] = t * k.y * k.z - s * k.x;
	R.m[6] = t * k.x * k.z - s * k.y;
	R.m[7] = t * k.y * k.z + s * k.x;
	R.m[8] = c + t * k.z * k.z;
	return R;
}

bool fmCollider_Init(fmCollider* c, const fmColliderDef* def)
{
	c->def = *def;
	// The caller's mesh arrays are copied into the shape, never kept.
	c->def.vertices = NULL;
	c->def.triangles = NULL;
	c->rotation = fmIdentity3();
	c->impulse = c->angularImpulse = c->force = c->torque = fmMakeVec3(0.0, 0.0, 0.0);
	switch (def->shape)
	{
	case fm_shapePlane:
	{
		double length = fmLength(def->normal);
		c->localNormal = fmScale(1.0 / length, def->normal);
		c->def.normal = c->localNormal;
		c->def.offset = def->offset / length;
		c->position = fmScale(c->def.offset, c->localNormal);
		break;
	}
	case fm_shapeBox:
		c->position = def->center;
		c->rotation = fmRotationFromAxisAngle(def->rotation);
		break;
	case fm_shapeMesh:
		c->position = def->center;
		c->rotation = fmRotationFromAxisAngle(def->rotation);
		c->mesh = fmMeshShape_Create(def);
		return c->mesh != NULL;
	case fm_shapeCapsule:
		c->position = fmScale(0.5, fmAdd(def->a, def->b));
		c->halfSegment = fmScale(0.5, fmSub(def->b, def->a));
		break;
	default:
		c->position = def->center;
		break;
	}
	return true;
}

// Box: distance from the local point q to a box of half extents h (exact outside and inside).
static double fmBoxDistance(fmVec3 q, fmVec3 h, fmVec3* localNormal)
{
	double d[3] = {fabs(q.x) - h.x, fabs(q.y) - h.y, fabs(q.z) - h.z};
	double s[3] = {q.x < 0.0 ? -1.0 : 1.0, q.y < 0.0 ? -1.0 : 1.0, q.z < 0.0 ? -1.0 : 1.0};
	if (d[0] > 0.0 || d[1] > 0.0 || d[2] > 0.0)
	{
		fmVec3 out =
		    fmMakeVec3(s[0] * fmMax(d[0], 0.0), s[1] * fmMax(d[1], 0.0), s[2] * fmMax(d[2], 0.0));
		double length = fmLength(out);
		*localNormal = fmScale(1.0 / length, out);
		return length;
	}
	int axis = d[0] >= d[1] && d[0] >= d[2] ? 0 : d[1] >= d[2] ? 1 : 2;
	double n[3] = {0.0, 0.0, 0.0};
	n[axis] = s[axis];
	*localNormal = fmMakeVec3(n[0], n[1], n[2]);
	return d[axis];
}

// Distance to a point (or a segment's closest point) at @p center, less @p radius; the normal
// points away from the centre (any unit vector when on it).
static double fmRoundDistance(fmVec3 p, fmVec3 center, double radius, fmVec3* normal)
{
	fmVec3 d = fmSub(p, center);
	double length = fmLength(d);
	*normal = length > 0.0 ? fmScale(1.0 / length, d) : fmMakeVec3(0.0, 1.0, 0.0);
	return length - radius;
}

// @p p in the collider's own frame (its rotation undone about its position).
static fmVec3 fmToLocal(const fmCollider* c, fmVec3 p)
{
	fmVec3 d = fmSub(p, c->position);
	const double* m = c->rotation.m;
	return fmMakeVec3(m[0] * d.x + m[3] * d.y + m[6] * d.z, m[1] * d.x + m[4] * d.y + m[7] * d.z,
	                  m[2] * d.x + m[5] * d.y + m[8] * d.z);
}

double fmCollider_Distance(const fmCollider* c, fmVec3 p, fmVec3* normal)
{
	switch (c->def.shape)
	{
	case fm_shapePlane:
		*normal = fmMatVec(&c->rotation, c->localNormal);
		return fmDot(*normal, fmSub(p, c->position));
	case fm_shapeSphere:
		return fmRoundDistance(p, c->position, c->def.radius, normal);
	case fm_shapeBox:
	{
		fmVec3 n;
		double d = fmBoxDistance(fmToLocal(c, p), c->def.halfExtents, &n);
		*normal = fmMatVec(&c->rotation, n);
		return d;
	}
	case fm_shapeMesh:
	{
		fmVec3 n;
		double d = fmMeshShape_Distance(c->mesh, fmToLocal(c, p), &n);
		*normal = fmMatVec(&c->rotation, n);
		return d;
	}
	case fm_shapeCapsule:
	{
		fmVec3 half = fmMatVec(&c->rotation, c->halfSegment);
		fmVec3 a = fmSub(c->position, half), ab = fmScale(2.0, half);
		double length2 = fmDot(ab, ab);
		double t = length2 > 0.0 ? fmDot(fmSub(p, a), ab) / length2 : 0.0;
		t = fmMin(fmMax(t, 0.0), 1.0);
		return fmRoundDistance(p, fmMulAdd(a, t, ab), c->def.radius, normal);
	}
	default:
		*normal = fmMakeVec3(0.0, 1.0, 0.0);
		return INFINITY;
	}
}

bool fmCollider_CastSegment(const fmCollider* c, fmVec3 p0, fmVec3 p1, double margin,
                            double* fraction, fmVec3* normal)
{
	fmVec3 d = fmSub(p1, p0);
	double length = fmLength(d), touching = 1e-9 * (1.0 + length);
	// A start inside is the distance query's; a start on the surface is a crossing only when
	// the segment heads inside (a vertex resting on the surface must be free to leave it, and
	// one pushed from it must not pass through a thin collider in one step).
	if (!(length > 0.0))
		return false;
	double start = fmCollider_Distance(c, p0, normal) - margin;
	if (start <= touching)
	{
		*fraction = 0.0;
		return start >= -touching && fmDot(d, *normal) < 0.0;
	}
	if (c->def.shape == fm_shapeMesh && margin == 0.0)
	{
		// Exact: the first front face the segment enters through.
		fmVec3 n;
		if (!fmMeshShape_CastSegment(c->mesh, fmToLocal(c, p0), fmToLocal(c, p1), fraction, &n))
			return false;
		*normal = fmMatVec(&c->rotation, n);
		return true;
	}
	fmVec3 u = fmScale(1.0 / length, d);
	double t = 0.0;
	for (int step = 0; step < FM_CAST_STEPS; ++step)
	{
		double gap = fmCollider_Distance(c, fmMulAdd(p0, t, u), normal) - margin;
		if (gap <= touching)
		{
			*fraction = t / length;
			return true;
		}
		t += gap;
		if (t > length)
			return false;
	}
	return false;
}

bool fmCollider_IsMoving(const fmCollider* c)
{
	const fmColliderDef* d = &c->def;
	return fmDot(d->velocity, d->velocity) > 0.0 ||
	       fmDot(d->angularVelocity, d->angularVelocity) > 0.0 ||
	       (c->mesh != NULL && c->mesh->motion != NULL && c->mesh->motion->moving);
}

fmVec3 fmCollider_VelocityAt(const fmCollider* c, fmVec3 p)
{
	fmVec3 v = fmAdd(c->def.velocity, fmCross(c->def.angularVelocity, fmSub(p, c->position)));
	if (c->mesh != NULL && c->mesh->motion != NULL && c->mesh->motion->rate > 0.0)
		v = fmAdd(v, c->mesh->motion->velocityAt(c, p));
	return v;
}

// ---- the public collider calls -----------------------------------------------------------------

fmFilter fmDefaultFilter(void)
{
	fmFilter filter = {1u, 0xffffffffu};
	return filter;
}

bool fmFiltersMeet(fmFilter a, fmFilter b)
{
	return (a.categoryBits & b.maskBits) != 0 && (b.categoryBits & a.maskBits) != 0;
}

fmColliderDef fmDefaultColliderDef(void)
{
	fmColliderDef def;
	memset(&def, 0, sizeof def);
	def.shape = fm_shapePlane;
	def.normal = fmMakeVec3(0.0, 1.0, 0.0);
	def.radius = 0.5;
	def.halfExtents = fmMakeVec3(0.5, 0.5, 0.5);
	def.b = fmMakeVec3(0.0, 1.0, 0.0);
	def.friction = 0.5;
	def.filter = fmDefaultFilter();
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

static bool fmFiniteVec(fmVec3 v, double limit)
{
	return fabs(v.x) <= limit && fabs(v.y) <= limit && fabs(v.z) <= limit;
}

// What is wrong with a def's shape, or NULL.
static const char* fmShapeProblem(const fmColliderDef* d)
{
	const double far = FM_MAX_COORDINATE;
	switch (d->shape)
	{
	case fm_shapePlane:
		return !fmFiniteVec(d->normal, far) || !(fmLength(d->normal) > 0.0)
		           ? "plane: a finite, non-zero normal"
		       : !(fabs(d->offset) <= far) ? "plane: a finite offset within 1e9 m"
		                                   : NULL;
	case fm_shapeSphere:
		return !fmFiniteVec(d->center, far)             ? "sphere: a finite center within 1e9 m"
		       : !(d->radius > 0.0 && d->radius <= far) ? "sphere: a radius in (0, 1e9] m"
		                                                : NULL;
	case fm_shapeBox:
		return !fmFiniteVec(d->center, far) ? "box: a finite center within 1e9 m"
		       : !(d->halfExtents.x > 0.0 && d->halfExtents.y > 0.0 && d->halfExtents.z > 0.0 &&
		           fmFiniteVec(d->halfExtents, far))
		           ? "box: half extents in (0, 1e9] m"
		       : !fmFiniteVec(d->rotation, 1e3) ? "box: a finite rotation (axis-angle, rad)"
		                                        : NULL;
	case fm_shapeCapsule:
		return !fmFiniteVec(d->a, far) || !fmFiniteVec(d->b, far)
		           ? "capsule: finite ends a and b within 1e9 m"
		       : !(d->radius > 0.0 && d->radius <= far) ? "capsule: a radius in (0, 1e9] m"
		                                                : NULL;
	case fm_shapeMesh:
		return !fmFiniteVec(d->center, far)     ? "mesh: a finite center within 1e9 m"
		       : !fmFiniteVec(d->rotation, 1e3) ? "mesh: a finite rotation (axis-angle, rad)"
		                                        : fmMeshShape_Problem(d);
	default:
		return "a shape of fm_shapePlane, fm_shapeSphere, fm_shapeBox, fm_shapeCapsule or "
		       "fm_shapeMesh";
	}
}

fmResult fmColliderDef_Validate(const fmColliderDef* def, fmDiagnostic* diag)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "collider def not initialised: start from fmDefaultColliderDef()");
	const char* problem = fmShapeProblem(def);
	if (problem == NULL && !(def->friction >= 0.0 && isfinite(def->friction)))
		problem = "a friction coefficient >= 0";
	if (problem == NULL && !(def->restitution >= 0.0 && def->restitution <= 1.0))
		problem = "a restitution in [0, 1]";
	if (problem == NULL &&
	    (!fmFiniteVec(def->velocity, 1e6) || !fmFiniteVec(def->angularVelocity, 1e6)))
		problem = "finite velocity and angular velocity (at most 1e6 m/s and rad/s)";
	if (problem != NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "collider: expected %s", problem);
	return fm_ok;
}

// Refuse a collider the world's memory budget cannot hold (its mesh's shape, and the table's
// growth when @p slot is past its end), before anything is allocated.
static fmResult fmColliderBudget(const fmWorld* w, const fmColliderDef* def, int slot,
                                 fmDiagnostic* diag)
{
	size_t need =
	    def->shape == fm_shapeMesh ? fmMeshShape_Bytes(def->vertexCount, def->triangleCount) : 0;
	if (slot == w->colliderCapacity)
		need += sizeof(fmCollider) * (size_t)(w->colliderCapacity > 0 ? w->colliderCapacity : 8);
	size_t used = fmWorldMemoryInUse(w), budget = w->def.memoryBudget;
	if (used <= budget && need <= budget - used)
		return fm_ok;
	const double mib = 1024.0 * 1024.0;
	char what[64] = "a collider (the collider table's growth)";
	if (def->shape == fm_shapeMesh)
		snprintf(what, sizeof what, "a mesh collider of %d triangles", def->triangleCount);
	return fmDiagError(diag, fm_errLimit, "", 0, 0,
	                   "%s needs about %.2f MiB; the world already uses %.1f MiB of its memory "
	                   "budget of %.1f MiB (fmWorldDef.memoryBudget): use fewer or coarser mesh "
	                   "colliders, or raise the budget",
	                   what, (double)need / mib, (double)used / mib, (double)budget / mib);
}

fmResult fmCreateCollider(fmWorldId worldId, const fmColliderDef* def, fmColliderId* colliderId,
                          fmDiagnostic* diag)
{
	fmWorld* w = fmGetWorld(worldId);
	FM_ASSERT(w != NULL && colliderId != NULL);
	if (colliderId != NULL)
		memset(colliderId, 0, sizeof *colliderId);
	if (w == NULL || colliderId == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid world id or NULL id");
	fmResult r = fmColliderDef_Validate(def, diag);
	if (r != fm_ok)
		return r;
	int slot = 0;
	while (slot < w->colliderCapacity &&
	       (w->colliders[slot].inUse || w->colliders[slot].generation == UINT32_MAX))
		++slot;
	r = fmColliderBudget(w, def, slot, diag);
	if (r != fm_ok)
		return r;
	if (slot == w->colliderCapacity)
	{
		int grown = w->colliderCapacity == 0 ? 8 : 2 * w->colliderCapacity;
		if (grown > FM_MAX_COLLIDERS)
			grown = FM_MAX_COLLIDERS;
		if (slot >= grown)
			return fmDiagError(diag, fm_errLimit, "", 0, 0,
			                   "a world holds at most %d colliders (FM_MAX_COLLIDERS)",
			                   FM_MAX_COLLIDERS);
		fmCollider* fresh = FM_ALLOC_ZERO(fmCollider, grown);
		if (fresh == NULL)
			return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for colliders");
		if (w->colliderCapacity > 0)
			memcpy(fresh, w->colliders, sizeof(fmCollider) * (size_t)w->colliderCapacity);
		FM_FREE_ARRAY(w->colliders, fmCollider, w->colliderCapacity);
		w->colliders = fresh;
		w->colliderCapacity = grown;
	}
	fmCollider* c = &w->colliders[slot];
	uint32_t generation = c->generation + 1;
	memset(c, 0, sizeof *c);
	if (!fmCollider_Init(c, def))
	{
		c->generation = generation - 1;
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory for a mesh collider of %d triangles", def->triangleCount);
	}
	c->generation = generation;
	c->inUse = true;
	colliderId->index1 = slot + 1;
	colliderId->generation = generation;
	colliderId->world0 = worldId.index1 - 1;
	colliderId->worldGeneration = worldId.generation;
	return fm_ok;
}

fmCollider* fmGetCollider(fmColliderId id, fmWorld** world)
{
	fmWorldId worldId = {id.world0 + 1, id.worldGeneration};
	fmWorld* w = id.index1 > 0 ? fmGetWorld(worldId) : NULL;
	bool floor = id.index1 == FM_FLOOR_SLOT + 1;
	if (w == NULL || (id.index1 > w->colliderCapacity && !floor))
		return NULL;
	fmCollider* c = fmWorldCollider(w, id.index1 - 1);
	if (world != NULL)
		*world = w;
	return c->inUse && c->generation == id.generation ? c : NULL;
}

static fmCollider* fmColliderOrAssert(fmColliderId id)
{
	fmCollider* c = fmGetCollider(id, NULL);
	FM_ASSERT(c != NULL);
	return c;
}

// A collider that may be moved: not the floor (fmWorld_SetFloor moves that one).
static fmCollider* fmMovableCollider(fmColliderId id)
{
	fmCollider* c = fmColliderOrAssert(id);
	bool floor = id.index1 == FM_FLOOR_SLOT + 1;
	FM_ASSERT(!floor);
	return floor ? NULL : c;
}

void fmDestroyCollider(fmColliderId colliderId)
{
	fmWorld* w = NULL;
	fmCollider* c = fmGetCollider(colliderId, &w);
	FM_ASSERT(c != NULL);
	if (c == NULL)
		return;
	if (c == &w->floorCollider)
		w->def.floor.enabled = false;
	fmContactCollider_ForgetFriction(w, c == &w->floorCollider ? FM_FLOOR_SLOT
	                                                           : (int)(c - w->colliders));
	fmCollider_Release(c);
}

void fmCollider_Release(fmCollider* c)
{
	fmMeshShape_Destroy(c->mesh);
	c->mesh = NULL;
	c->inUse = false;
}

bool fmCollider_Bounds(const fmCollider* c, fmVec3* lo, fmVec3* hi)
{
	fmVec3 center = c->position, half;
	switch (c->def.shape)
	{
	case fm_shapeSphere:
		half = fmMakeVec3(c->def.radius, c->def.radius, c->def.radius);
		break;
	case fm_shapeCapsule:
	{
		fmVec3 s = fmMatVec(&c->rotation, c->halfSegment);
		half = fmMakeVec3(fabs(s.x) + c->def.radius, fabs(s.y) + c->def.radius,
		                  fabs(s.z) + c->def.radius);
		break;
	}
	case fm_shapeBox:
	case fm_shapeMesh:
	{
		fmVec3 a = c->def.halfExtents, b = fmScale(-1.0, a);
		if (c->def.shape == fm_shapeMesh)
			fmMeshShape_Bounds(c->mesh, &b, &a);
		fmVec3 mid = fmScale(0.5, fmAdd(a, b)), h = fmScale(0.5, fmSub(a, b));
		const double* m = c->rotation.m;
		center = fmAdd(center, fmMatVec(&c->rotation, mid));
		half = fmMakeVec3(fabs(m[0]) * h.x + fabs(m[1]) * h.y + fabs(m[2]) * h.z,
		                  fabs(m[3]) * h.x + fabs(m[4]) * h.y + fabs(m[5]) * h.z,
		                  fabs(m[6]) * h.x + fabs(m[7]) * h.y + fabs(m[8]) * h.z);
		break;
	}
	default:
		return false;
	}
	*lo = fmSub(center, half);
	*hi = fmAdd(center, half);
	return true;
}

double fmCollider_Thickness(const fmCollider* c)
{
	switch (c->def.shape)
	{
	case fm_shapeSphere:
	case fm_shapeCapsule:
		return 2.0 * c->def.radius;
	case fm_shapeBox:
		return 2.0 * fmMin(c->def.halfExtents.x, fmMin(c->def.halfExtents.y, c->def.halfExtents.z));
	case fm_shapeMesh:
	{
		fmVec3 lo, hi;
		fmMeshShape_Bounds(c->mesh, &lo, &hi);
		return fmMin(hi.x - lo.x, fmMin(hi.y - lo.y, hi.z - lo.z));
	}
	default:
		return INFINITY;
	}
}

double fmCollider_SweepSpeed(const fmCollider* c)
{
	fmVec3 lo, hi;
	double radius = fmCollider_Bounds(c, &lo, &hi) ? 0.5 * fmLength(fmSub(hi, lo)) : 0.0;
	const fmMeshMotion* a = c->mesh != NULL ? c->mesh->motion : NULL;
	double morph = a != NULL ? a->far * a->rate : 0.0; // the fastest vertex in a moving frame
	return fmLength(c->def.velocity) + fmLength(c->def.angularVelocity) * radius + morph;
}

bool fmCollider_IsValid(fmColliderId colliderId)
{
	return fmGetCollider(colliderId, NULL) != NULL;
}

void fmCollider_SetTransform(fmColliderId colliderId, fmVec3 position, fmVec3 rotation)
{
	fmCollider* c = fmMovableCollider(colliderId);
	bool finite = fmFiniteVec(position, FM_MAX_COORDINATE) && fmFiniteVec(rotation, 1e3);
	FM_ASSERT(finite);
	if (c == NULL || !finite)
		return;
	c->position = position;
	fmMat3 turn = fmRotationFromAxisAngle(rotation);
	bool turned = c->def.shape == fm_shapeBox || c->def.shape == fm_shapeMesh;
	fmMat3 shape = turned ? fmRotationFromAxisAngle(c->def.rotation) : fmIdentity3();
	c->rotation = fmMatMul(&turn, &shape);
}

void fmCollider_SetVelocity(fmColliderId colliderId, fmVec3 velocity, fmVec3 angularVelocity)
{
	fmCollider* c = fmMovableCollider(colliderId);
	bool finite = fmFiniteVec(velocity, 1e6) && fmFiniteVec(angularVelocity, 1e6);
	FM_ASSERT(finite);
	if (c == NULL || !finite)
		return;
	c->def.velocity = velocity;
	c->def.angularVelocity = angularVelocity;
}

fmVec3 fmCollider_GetPosition(fmColliderId colliderId)
{
	fmCollider* c = fmColliderOrAssert(colliderId);
	return c ? c->position : fmMakeVec3(0.0, 0.0, 0.0);
}

void fmCollider_GetContactForce(fmColliderId colliderId, fmVec3* force, fmVec3* torque)
{
	fmCollider* c = fmColliderOrAssert(colliderId);
	if (force)
		*force = c ? c->force : fmMakeVec3(0.0, 0.0, 0.0);
	if (torque)
		*torque = c ? c->torque : fmMakeVec3(0.0, 0.0, 0.0);
}
