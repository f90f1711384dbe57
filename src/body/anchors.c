// Attachments (anchors.h): fmBody_AttachToCollider, fmBody_Weld, fmBody_ClearAttachments and
// the anchors' placement every substep.
#include "body/anchors.h"
#include "core/det_math.h"

#include "body/targets.h"
#include "contact/collider.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

// The defaults' scale of the body's weight (m/s^2): the world's gravity, or Earth's when weaker.
#define FM_ANCHOR_GRAVITY 9.81
// Default stretch (m) at which a body's glued vertices together carry its weight.
#define FM_ANCHOR_SAG 0.001

fmAttachDef fmDefaultAttachDef(void)
{
	fmAttachDef def;
	memset(&def, 0, sizeof def);
	def.dampingRatio = 1.0;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

void fmAnchors_Free(fmBody* b)
{
	FM_FREE_ARRAY(b->anchors, fmAnchor, b->anchorCapacity);
	FM_FREE_ARRAY(b->anchorTargets, fmTarget, b->anchorCapacity);
	b->anchors = NULL;
	b->anchorTargets = NULL;
	b->anchorCapacity = 0;
	b->anchorCount = 0;
}

bool fmAnchors_Reserve(fmBody* b, int count)
{
	if (count <= b->anchorCapacity)
		return true;
	int capacity = count > 2 * b->anchorCapacity ? count : 2 * b->anchorCapacity;
	fmAnchor* anchors = FM_ALLOC_ARRAY(fmAnchor, capacity);
	fmTarget* targets = FM_ALLOC_ARRAY(fmTarget, capacity);
	if (anchors == NULL || targets == NULL)
	{
		FM_FREE_ARRAY(anchors, fmAnchor, capacity);
		FM_FREE_ARRAY(targets, fmTarget, capacity);
		return false;
	}
	if (b->anchorCount > 0)
	{
		memcpy(anchors, b->anchors, sizeof(fmAnchor) * (size_t)b->anchorCount);
		memcpy(targets, b->anchorTargets, sizeof(fmTarget) * (size_t)b->anchorCount);
	}
	int count0 = b->anchorCount;
	fmAnchors_Free(b);
	b->anchors = anchors;
	b->anchorTargets = targets;
	b->anchorCapacity = capacity;
	b->anchorCount = count0;
	return true;
}

// The collider anchor @p a is glued to, or NULL when it is welded or the collider is gone.
static fmCollider* fmAnchorCollider(struct fmWorld* w, const fmAnchor* a)
{
	if (a->collider < 0)
		return NULL;
	fmCollider* c = fmWorldCollider(w, a->collider);
	return c->inUse && c->generation == a->generation ? c : NULL;
}

bool fmAnchors_WeldedTo(const fmBody* b, const fmBody* o)
{
	for (int a = 0; a < b->anchorCount; ++a)
		if (b->anchors[a].collider < 0 && b->anchors[a].body == o->slot &&
		    b->anchors[a].generation == o->generation && o != b)
			return true;
	return false;
}

// The slot of anchor @p a's live weld partner, or -1 (glued, or the partner gone).
static int fmAnchorPartner(const struct fmWorld* w, const fmBody* b, int a)
{
	const fmAnchor* anchor = &b->anchors[a];
	if (anchor->collider >= 0)
		return -1;
	const fmBody* o = &w->bodies[anchor->body];
	return fmBody_IsLive(o) && o->generation == anchor->generation ? anchor->body : -1;
}

// Drop the anchors of @p b whose source is gone, keeping the others' order.
static void fmDropStale(struct fmWorld* w, fmBody* b)
{
	int kept = 0;
	for (int a = 0; a < b->anchorCount; ++a)
	{
		if (fmAnchorCollider(w, &b->anchors[a]) == NULL && fmAnchorPartner(w, b, a) < 0)
			continue;
		b->anchors[kept] = b->anchors[a];
		b->anchorTargets[kept++] = b->anchorTargets[a];
	}
	b->anchorCount = kept;
}

// A glued anchor where collider @p c leaves it after @p h more seconds of its motion.
static void fmPlaceGlued(fmAnchor* a, fmTarget* t, const fmCollider* c, double h, double frameTime)
{
	fmMat3 rotation = c->rotation;
	if (fmDot(c->def.angularVelocity, c->def.angularVelocity) > 0.0)
	{
		fmMat3 turn = fmRotationFromAxisAngle(fmScale(h, c->def.angularVelocity));
		rotation = fmMatMul(&turn, &c->rotation);
	}
	fmVec3 centre = fmMulAdd(c->position, h, c->def.velocity);
	a->lever = fmMatVec(&rotation, a->local);
	fmVec3 q = fmAdd(centre, a->lever);
	fmVec3 v = fmAdd(c->def.velocity, fmCross(c->def.angularVelocity, a->lever));
	fmStore(t->position, 0, q);
	fmStore(t->motion, 0, fmScale(frameTime, v));
}

// A welded end at the midpoint of the two vertices @p ahead seconds on (the implicit step's
// predicted ends x + h v + h^2 a; 0: where they are now), moving at their mean velocity then.
static void fmPlaceWelded(const fmBody* b, const fmAnchor* a, fmTarget* t, const fmBody* o,
                          double ahead, double frameTime)
{
	fmVec3 v = fmMulAdd(fmAdd(fmLoad(b->state.v, t->vertex), fmLoad(o->state.v, a->otherVertex)),
	                    2.0 * ahead, a->acceleration);
	fmVec3 p = fmMulAdd(fmAdd(fmLoad(b->state.x, t->vertex), fmLoad(o->state.x, a->otherVertex)),
	                    ahead, v);
	fmStore(t->position, 0, fmScale(0.5, p));
	fmStore(t->motion, 0, fmScale(0.5 * frameTime, v));
}

// Place @p b's anchors @p ahead seconds on (the implicit step's end; 0: now, the explicit
// step's forces act at the substep's start); true when one of them is welded.
static bool fmPlaceBody(struct fmWorld* w, fmBody* b, double ahead, double frameTime)
{
	fmDropStale(w, b);
	bool welded = false;
	for (int a = 0; a < b->anchorCount; ++a)
	{
		fmAnchor* anchor = &b->anchors[a];
		const fmCollider* c = fmAnchorCollider(w, anchor);
		if (c != NULL)
			fmPlaceGlued(anchor, &b->anchorTargets[a], c, ahead, frameTime);
		else
			fmPlaceWelded(b, anchor, &b->anchorTargets[a], &w->bodies[anchor->body], ahead,
			              frameTime);
		welded = welded || c == NULL;
	}
	return welded;
}

// The body's momentum (kg m/s).
static fmVec3 fmMomentum(const fmBody* b)
{
	fmVec3 p = fmMakeVec3(0.0, 0.0, 0.0);
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		p = fmMulAdd(p, b->mesh.mass[i], fmLoad(b->state.v, i));
	return p;
}

static void fmAnchorsPlace(struct fmWorld* w, double h, double frameTime)
{
	bool implicit = w->def.integrator == fm_implicit;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b) || b->anchorCount == 0)
			continue;
		// Welded, implicit: the momentum the pair's acceleration is measured from.
		if (fmPlaceBody(w, b, implicit ? h : 0.0, frameTime) && implicit)
			b->weldMomentum = fmMomentum(b);
	}
}

void fmAnchors_PlaceStatic(struct fmWorld* w, fmBody* b)
{
	(void)fmPlaceBody(w, b, 0.0, 0.0);
}

// Glued anchor @p a of @p b: its force, reversed, into collider @p c's impulse over @p h.
static void fmBookReaction(const fmBody* b, int a, fmCollider* c, double h)
{
	fmVec3 impulse = fmScale(-h, fmLoad(b->anchorTargets[a].applied, 0));
	c->impulse = fmAdd(c->impulse, impulse);
	c->angularImpulse = fmAdd(c->angularImpulse, fmCross(b->anchors[a].lever, impulse));
}

// The acceleration of @p b over the substep of @p h it stepped from everything but its welds:
// its momentum's change less the welds' impulses, over its mass.
static void fmNoteAcceleration(const struct fmWorld* w, fmBody* b, double h)
{
	fmVec3 change = fmSub(fmMomentum(b), b->weldMomentum);
	for (int a = 0; a < b->anchorCount; ++a)
		if (fmAnchorPartner(w, b, a) >= 0)
			change = fmMulAdd(change, -h, fmLoad(b->anchorTargets[a].applied, 0));
	b->weldAcceleration = fmScale(1.0 / (h * b->mesh.totalMass), change);
}

// The pair's acceleration, from the two bodies' (mass-weighted), for each welded anchor of @p b.
static void fmShareAcceleration(const struct fmWorld* w, fmBody* b)
{
	for (int a = 0; a < b->anchorCount; ++a)
	{
		int o = fmAnchorPartner(w, b, a);
		if (o < 0)
			continue;
		const fmBody* other = &w->bodies[o];
		double mb = b->mesh.totalMass, mo = other->mesh.totalMass;
		b->anchors[a].acceleration =
		    fmScale(1.0 / (mb + mo),
		            fmAdd(fmScale(mb, b->weldAcceleration), fmScale(mo, other->weldAcceleration)));
	}
}

static void fmAnchorsAfterSubstep(struct fmWorld* w, double h)
{
	bool implicit = w->def.integrator == fm_implicit;
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		bool welded = false;
		for (int a = 0; fmIsland_Stepping(b) && a < b->anchorCount; ++a)
		{
			fmCollider* c = fmAnchorCollider(w, &b->anchors[a]);
			if (c != NULL)
				fmBookReaction(b, a, c, h);
			welded = welded || c == NULL;
		}
		if (implicit && welded)
			fmNoteAcceleration(w, b, h);
	}
	for (int i = 0; implicit && i < w->bodyCapacity; ++i)
		if (fmIsland_Stepping(&w->bodies[i]) && w->bodies[i].anchorCount > 0)
			fmShareAcceleration(w, &w->bodies[i]);
}

// Whether @p b hangs on a collider that moves.
static bool fmOnMovingCollider(const struct fmWorld* w, const fmBody* b)
{
	for (int a = 0; a < b->anchorCount; ++a)
	{
		const fmCollider* c = fmAnchorCollider((struct fmWorld*)w, &b->anchors[a]);
		if (c != NULL && fmCollider_IsMoving(c))
			return true;
	}
	return false;
}

static void fmAnchorsWake(struct fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmBody* b = &w->bodies[i];
		if (!fmBody_IsLive(b) || !b->asleep)
			continue;
		bool wake = fmOnMovingCollider(w, b);
		for (int a = 0; !wake && a < b->anchorCount; ++a)
		{
			int o = fmAnchorPartner(w, b, a);
			wake = o >= 0 && !w->bodies[o].asleep;
		}
		if (wake)
			fmIsland_Wake(w, i);
	}
}

static const fmAnchorStages fmStages = {fmAnchorsPlace, fmAnchorsAfterSubstep, fmAnchorsWake,
                                        fmOnMovingCollider, fmAnchorPartner};

void fmAnchors_Enable(struct fmWorld* w)
{
	w->anchorStages = &fmStages;
}

// ---- the public calls ------------------------------------------------------------------------

// What is wrong with @p def or @p vertices of @p b (count given), or NULL; @p at gets the entry
// at fault (-1: none), @p code the result (fm_errLimit: too many).
static const char* fmAttachProblem(const fmBody* b, const int* vertices, int count,
                                   const fmAttachDef* def, int* at, fmResult* code)
{
	*at = -1;
	*code = fm_errParameter;
	if (def != NULL && def->internalValue != FM_DEF_MAGIC)
		return "a def started from fmDefaultAttachDef() (or NULL)";
	if (def != NULL && !(def->stiffness >= 0.0 && isfinite(def->stiffness)))
		return "a finite stiffness >= 0 N/m (0: the default)";
	if (def != NULL && !(def->dampingRatio >= 0.0 && def->dampingRatio <= 1e6))
		return "a damping ratio in [0, 1e6]";
	if (def != NULL && !(def->maxForce >= 0.0 && !isnan(def->maxForce)))
		return "a maxForce >= 0 N (0: no bound)";
	if (count < 1 || vertices == NULL)
		return "count >= 1 and non-NULL vertices";
	if (count > FM_MAX_ANCHORS_PER_VERTEX * b->mesh.vertexCount - b->anchorCount)
		*code = fm_errLimit;
	if (*code == fm_errLimit)
		return "at most FM_MAX_ANCHORS_PER_VERTEX attachments a vertex on the body";
	for (int k = 0; k < count; ++k)
		if (vertices[k] < 0 || vertices[k] >= b->mesh.vertexCount)
		{
			*at = k;
			return "a vertex index in [0, vertexCount)";
		}
	return NULL;
}

// Refuse with the world's last error: @p call's @p what at entry @p at (-1: the call's).
static fmResult fmRefuse(struct fmWorld* w, fmResult code, const char* call, const char* what,
                         int at, const int* vertices)
{
	if (at >= 0)
		return fmDiagError(&w->lastError, code, "", 0, 0, "%s: entry %d (vertex %d): expected %s",
		                   call, at, vertices[at], what);
	return fmDiagError(&w->lastError, code, "", 0, 0, "%s: expected %s", call, what);
}

// The spring of a vertex of @p b among @p count held by @p def (NULL: the default), sharing
// @p mass (kg) between them.
static fmTarget fmAnchorSpring(const fmWorld* w, const fmAttachDef* def, double mass, int count)
{
	fmAttachDef d = def != NULL ? *def : fmDefaultAttachDef();
	double share = mass / count;
	double g = fmMax(FM_ANCHOR_GRAVITY, fmLength(w->def.gravity));
	double k = d.stiffness > 0.0 ? d.stiffness : share * g / FM_ANCHOR_SAG;
	return (fmTarget){.stiffness = k,
	                  .damping = 2.0 * d.dampingRatio * sqrt(k * share),
	                  .maxForce = d.maxForce > 0.0 ? d.maxForce : INFINITY};
}

// The live collider @p id names in world @p w (its slot in @p slot), or NULL.
static fmCollider* fmColliderOfWorld(fmWorld* w, fmColliderId id, int* slot)
{
	fmWorld* of = NULL;
	fmCollider* c = fmGetCollider(id, &of);
	*slot = id.index1 - 1;
	return of == w ? c : NULL;
}

static fmResult fmAttachIn(fmBody* b, fmWorld* w, const int* vertices, int count,
                           fmColliderId colliderId, const fmAttachDef* def)
{
	const char* call = "fmBody_AttachToCollider";
	int at, slot;
	fmResult code;
	const char* what = fmAttachProblem(b, vertices, count, def, &at, &code);
	if (what != NULL)
		return fmRefuse(w, code, call, what, at, vertices);
	const fmCollider* c = fmColliderOfWorld(w, colliderId, &slot);
	if (c == NULL)
		return fmRefuse(w, fm_errParameter, call, "a live collider of the body's world", -1, NULL);
	if (!fmAnchors_Reserve(b, b->anchorCount + count))
		return fmRefuse(w, fm_errOutOfMemory, call, "memory for the attachments", -1, NULL);
	fmTarget spring = fmAnchorSpring(w, def, b->mesh.totalMass, count);
	fmMat3 inverse = fmTranspose(&c->rotation);
	for (int k = 0; k < count; ++k)
	{
		int i = b->internalVertex[vertices[k]];
		fmVec3 x = fmLoad(b->state.x, i);
		b->anchors[b->anchorCount] = (fmAnchor){
		    .collider = slot,
		    .generation = c->generation,
		    .local = fmMatVec(&inverse, fmSub(x, c->position)),
		};
		fmTarget* t = &b->anchorTargets[b->anchorCount++];
		*t = spring;
		t->vertex = i;
		fmStore(t->position, 0, x);
	}
	return fm_ok;
}

// Weld ends on @p b's vertices to @p o's (both validated, room reserved), with @p spring; until
// the pair has stepped, it is predicted to fly freely under @p gravity (as a step's first guess).
static void fmAddWeldEnds(fmBody* b, const int* vertices, const fmBody* o, const int* others,
                          int count, fmTarget spring, fmVec3 gravity)
{
	for (int k = 0; k < count; ++k)
	{
		int i = b->internalVertex[vertices[k]];
		b->anchors[b->anchorCount] = (fmAnchor){.collider = -1,
		                                        .body = o->slot,
		                                        .generation = o->generation,
		                                        .otherVertex = o->internalVertex[others[k]],
		                                        .acceleration = gravity};
		fmTarget* t = &b->anchorTargets[b->anchorCount++];
		*t = spring;
		t->vertex = i;
		fmStore(t->position, 0, fmLoad(b->state.x, i));
	}
}

static fmResult fmWeldIn(fmBody* b, fmBody* o, fmWorld* w, const int* vertices, const int* others,
                         int count, const fmAttachDef* def)
{
	const char* call = "fmBody_Weld";
	int at;
	fmResult code;
	const char* what = fmAttachProblem(b, vertices, count, def, &at, &code);
	if (what != NULL)
		return fmRefuse(w, code, call, what, at, vertices);
	what = fmAttachProblem(o, others, count, def, &at, &code);
	if (what != NULL)
		return fmRefuse(w, code, "fmBody_Weld (the other body)", what, at, others);
	for (int k = 0; k < count && o == b; ++k)
		if (vertices[k] == others[k])
			return fmRefuse(w, fm_errParameter, call, "two different vertices of the body", k,
			                vertices);
	if (!fmAnchors_Reserve(b, b->anchorCount + count + (o == b ? count : 0)) ||
	    !fmAnchors_Reserve(o, o->anchorCount + count))
		return fmRefuse(w, fm_errOutOfMemory, call, "memory for the welds", -1, NULL);
	double mass = fmMin(b->mesh.totalMass, o->mesh.totalMass);
	fmTarget spring = fmAnchorSpring(w, def, mass, count);
	fmAddWeldEnds(b, vertices, o, others, count, spring, w->def.gravity);
	fmAddWeldEnds(o, others, b, vertices, count, spring, w->def.gravity);
	return fm_ok;
}

// The body of @p id and its world, or false (asserted: a stale id is the caller's bug).
static bool fmBodyAndWorld(fmBodyId id, fmBody** b, fmWorld** w)
{
	*b = fmGetBody(id);
	*w = fmGetWorldOfBody(id);
	FM_ASSERT(*b != NULL && *w != NULL);
	return *b != NULL && *w != NULL;
}

fmResult fmBody_AttachToCollider(fmBodyId bodyId, const int* vertices, int count,
                                 fmColliderId colliderId, const fmAttachDef* def)
{
	fmBody* b;
	fmWorld* w;
	if (!fmBodyAndWorld(bodyId, &b, &w))
		return fm_errInvalidId;
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	fmResult r = fmAttachIn(b, w, vertices, count, colliderId, def);
	fmFpEnv_Leave(&env);
	if (r == fm_ok)
	{
		fmAnchors_Enable(w);
		fmIsland_WakeBody(bodyId);
	}
	return r;
}

fmResult fmBody_Weld(fmBodyId bodyId, const int* vertices, fmBodyId otherId, const int* others,
                     int count, const fmAttachDef* def)
{
	fmBody *b, *o;
	fmWorld *w, *wo;
	if (!fmBodyAndWorld(bodyId, &b, &w) || !fmBodyAndWorld(otherId, &o, &wo))
		return fm_errInvalidId;
	if (w != wo)
		return fmRefuse(w, fm_errParameter, "fmBody_Weld", "two bodies of one world", -1, NULL);
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	fmResult r = fmWeldIn(b, o, w, vertices, others, count, def);
	fmFpEnv_Leave(&env);
	if (r == fm_ok)
	{
		fmAnchors_Enable(w);
		fmIsland_WakeBody(bodyId);
		fmIsland_WakeBody(otherId);
	}
	return r;
}

int fmBody_GetAttachmentCount(fmBodyId bodyId)
{
	const fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	return b != NULL ? b->anchorCount : 0;
}

// Drop @p b's weld ends whose partner is slot @p slot.
static void fmDropWeldsTo(fmBody* b, int slot)
{
	int kept = 0;
	for (int a = 0; a < b->anchorCount; ++a)
	{
		if (b->anchors[a].collider < 0 && b->anchors[a].body == slot)
			continue;
		b->anchors[kept] = b->anchors[a];
		b->anchorTargets[kept++] = b->anchorTargets[a];
	}
	b->anchorCount = kept;
}

void fmBody_ClearAttachments(fmBodyId bodyId)
{
	fmBody* b;
	fmWorld* w;
	if (!fmBodyAndWorld(bodyId, &b, &w))
		return;
	for (int a = 0; a < b->anchorCount; ++a)
	{
		int o = fmAnchorPartner(w, b, a);
		if (o >= 0 && o != b->slot)
			fmDropWeldsTo(&w->bodies[o], b->slot);
	}
	b->anchorCount = 0;
	fmIsland_WakeBody(bodyId);
}

// ---- snapshots --------------------------------------------------------------------------------

fmAnchorRecord fmAnchors_Record(const fmBody* b, int a)
{
	const fmAnchor* anchor = &b->anchors[a];
	const fmTarget* t = &b->anchorTargets[a];
	fmAnchorRecord r;
	memset(&r, 0, sizeof r);
	r.vertex = t->vertex;
	r.collider = anchor->collider;
	r.body = anchor->body;
	r.otherVertex = anchor->otherVertex;
	r.generation = anchor->generation;
	fmStore(r.local, 0, anchor->local);
	r.stiffness = t->stiffness;
	r.damping = t->damping;
	r.maxForce = t->maxForce;
	fmStore(r.acceleration, 0, anchor->acceleration);
	return r;
}

const char* fmAnchors_RecordProblem(const struct fmWorld* w, const fmBody* b,
                                    const fmAnchorRecord* r)
{
	if (r->vertex < 0 || r->vertex >= b->mesh.vertexCount || r->zero != 0)
		return "a vertex of the body";
	if (r->collider >= 0 && r->collider >= w->colliderCapacity && r->collider != FM_FLOOR_SLOT)
		return "a collider slot of the world";
	if (r->collider < -1 || (r->collider == -1 && (r->body < 0 || r->body >= w->bodyCapacity)))
		return "a body slot of the world";
	const fmBody* o = r->collider == -1 ? &w->bodies[r->body] : NULL;
	if (o != NULL && fmBody_IsLive(o) && o->generation == r->generation &&
	    (r->otherVertex < 0 || r->otherVertex >= o->mesh.vertexCount))
		return "a vertex of the welded body";
	bool finite = fabs(r->local[0]) <= FM_MAX_COORDINATE &&
	              fabs(r->local[1]) <= FM_MAX_COORDINATE && fabs(r->local[2]) <= FM_MAX_COORDINATE;
	for (int e = 0; e < 3; ++e)
		finite = finite && fabs(r->acceleration[e]) <= FM_MAX_COORDINATE;
	if (!finite || !(r->stiffness >= 0.0 && isfinite(r->stiffness)) ||
	    !(r->damping >= 0.0 && isfinite(r->damping)) || !(r->maxForce > 0.0))
		return "a finite point and spring";
	return NULL;
}

void fmAnchors_Restore(fmBody* b, int a, const fmAnchorRecord* r)
{
	b->anchors[a] = (fmAnchor){.collider = r->collider,
	                           .body = r->body,
	                           .generation = r->generation,
	                           .otherVertex = r->otherVertex,
	                           .local = fmLoad(r->local, 0),
	                           .acceleration = fmLoad(r->acceleration, 0)};
	b->anchorTargets[a] = (fmTarget){.vertex = r->vertex,
	                                 .stiffness = r->stiffness,
	                                 .damping = r->damping,
	                                 .maxForce = r->maxForce};
}
