// Bodies: creation from a mesh (rest-shape preprocessing), state access, pins, statistics; the
// definition's defaults, checks and memory estimate are body_def.c's.
#include "body/body.h"

#include "body/anchors.h"
#include "body/body_def.h"
#include "body/fracture.h"
#include "body/grab.h"
#include "body/loads.h"
#include "body/plasticity.h"
#include "body/targets.h"
#include "contact/floor.h"
#include "contact/penalty.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"
#include "fem/force_fvm.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/nodal_pressure.h"
#include "fem/tet_blocks.h"
#include "material/material_aniso.h"
#include "material/material_plastic.h"
#include "mesh/mesh_internal.h"
#include "mesh/reorder.h"
#include "solver/solver_cache.h"
#include "world/audit.h"
#include "world/island.h"
#include "world/world.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static bool fmIsFiniteVec3(fmVec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// Free every array of a body; safe on a partially built body.
void fmBodyRelease(fmBody* b)
{
	int vertexCount = b->mesh.vertexCount, tetCount = b->mesh.tetCount;
	size_t n = (size_t)vertexCount, m = (size_t)tetCount;
	fmBodyState_Free(&b->state, vertexCount);
	FM_FREE_ARRAY(b->xGood, double, 3 * n);
	FM_FREE_ARRAY(b->vGood, double, 3 * n);
	FM_FREE_ARRAY(b->previousX, double, 3 * n);
	FM_FREE_ARRAY(b->userVertex, int, n);
	FM_FREE_ARRAY(b->internalVertex, int, n);
	FM_FREE_ARRAY(b->userTet, int, m);
	FM_FREE_ARRAY(b->userTets, int, 4 * m);
	FM_FREE_ARRAY(b->userSurface, int, 3 * (size_t)b->mesh.triangleCount);
	FM_FREE_ARRAY(b->userMass, double, n);
	fmAttachment_Release(&b->drawCache);
	fmAttachment_Release(&b->renderMesh);
	fmBodyContact_Free(&b->contact, vertexCount, tetCount);
	fmGrab_Free(b);
	fmTargets_Free(b);
	fmAnchors_Free(b);
	fmLoads_Free(b->loads);
	fmFracture_Free(b);
	fmSolverCache_Free(b->solverCache);
	fmTetBlocks_Destroy(b->mesh.tetBlocks);
	fmElasticMesh_Free(&b->mesh);
	uint32_t generation = b->generation;
	memset(b, 0, sizeof *b);
	b->generation = generation;
}

static bool fmBodyAllocate(fmBody* b, int n, int m)
{
	bool made = fmElasticMesh_Allocate(&b->mesh, n, m) && fmBodyState_Allocate(&b->state, n);
	b->xGood = FM_ALLOC_ARRAY(double, 3 * (size_t)n);
	b->vGood = FM_ALLOC_ZERO(double, 3 * (size_t)n);
	b->userVertex = FM_ALLOC_ARRAY(int, n);
	b->internalVertex = FM_ALLOC_ARRAY(int, n);
	b->userTet = FM_ALLOC_ARRAY(int, m);
	b->userTets = FM_ALLOC_ARRAY(int, 4 * (size_t)m);
	b->userMass = FM_ALLOC_ARRAY(double, n);
	return made && b->xGood && b->vGood && b->userVertex && b->internalVertex && b->userTet &&
	       b->userTets && b->userMass;
}

// Reference edge matrices, volumes, masses and smoothing weights from the oriented mesh.
static fmResult fmBodyPrecomputeWith(fmBody* b, const fmBodyDef* def, const fmTetMesh* mesh,
                                     fmDiagnostic* diag, int* tetsAround)
{
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		const int* n = b->mesh.tets + 4 * t;
		fmVec3 X0 = fmLoad(b->mesh.x0, n[0]);
		fmMat3 Dm = fmMat3FromColumns(fmSub(fmLoad(b->mesh.x0, n[1]), X0),
		                              fmSub(fmLoad(b->mesh.x0, n[2]), X0),
		                              fmSub(fmLoad(b->mesh.x0, n[3]), X0));
		double volume = fmDet(&Dm) / 6.0;
		if (!(volume > 0.0) || !fmInverse(&Dm, &b->mesh.DmInv[t]))
			return fmDiagError(diag, fm_errDegenerate, "", 0, 0,
			                   "tet %d (in the mesh's numbering) has zero volume",
			                   b->userTet[t] + mesh->firstIndex);
		b->mesh.restVolume[t] = volume;
		for (int a = 0; a < 4; ++a)
		{
			tetsAround[n[a]] += 1;
			if (def->massMode == fm_massFromDensity)
				b->mesh.mass[n[a]] += def->density * volume / 4.0;
		}
	}
	b->mesh.totalMass = 0.0;
	fmVec3 lo = fmLoad(b->mesh.x0, 0), hi = lo;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->mesh.x0, i);
		lo = fmMakeVec3(fmMin(lo.x, p.x), fmMin(lo.y, p.y), fmMin(lo.z, p.z));
		hi = fmMakeVec3(fmMax(hi.x, p.x), fmMax(hi.y, p.y), fmMax(hi.z, p.z));
		if (def->massMode == fm_massPerParticle)
			b->mesh.mass[i] = def->particleMass;
		b->mesh.smoothWeight[i] = tetsAround[i] > 0 ? 1.0 / (4.0 * tetsAround[i]) : 0.0;
		// A node no tet uses has no elastic tie to the body: keep it where it is.
		if (tetsAround[i] == 0)
			b->state.pinned[i] = FM_PIN_ALL;
		b->state.invMass[i] = b->state.pinned[i] == FM_PIN_ALL ? 0.0 : 1.0 / b->mesh.mass[i];
		b->mesh.totalMass += b->mesh.mass[i];
	}
	b->mesh.restSize = fmLength(fmSub(hi, lo));
	// Density times a tiny volume can underflow to a zero mass (an infinite inverse), a huge
	// one overflow: the integrators divide by these.
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		if (b->state.pinned[i] != FM_PIN_ALL &&
		    !(isfinite(b->state.invMass[i]) && b->state.invMass[i] > 0.0))
			return fmDiagError(diag, fm_errRange, "", 0, 0,
			                   "node %d gets mass %g kg: expected a finite mass > 0 (density %g "
			                   "kg/m^3 times its tets' volume, or the particle mass)",
			                   b->userVertex[i] + mesh->firstIndex, b->mesh.mass[i], def->density);
	if (!isfinite(b->mesh.totalMass))
		return fmDiagError(diag, fm_errRange, "", 0, 0, "the body's total mass overflows (%g kg)",
		                   b->mesh.totalMass);
	return fm_ok;
}

// The tets around each vertex in ascending order (vertexTetStart, vertexTets) from the counts
// @p tetsAround (consumed).
static void fmBodyBuildIncidence(fmBody* b, int* tetsAround)
{
	b->mesh.vertexTetStart[0] = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		b->mesh.vertexTetStart[i + 1] = b->mesh.vertexTetStart[i] + tetsAround[i];
		tetsAround[i] = b->mesh.vertexTetStart[i]; // the next free place of vertex i
	}
	for (int t = 0; t < b->mesh.tetCount; ++t) // tets in order: each list ends up ascending
		for (int a = 0; a < 4; ++a)
			b->mesh.vertexTets[tetsAround[b->mesh.tets[4 * t + a]]++] = 4 * t + a;
}

// The same with a counter of the tets around each vertex, allocated for the call.
static fmResult fmBodyPrecompute(fmBody* b, const fmBodyDef* def, const fmTetMesh* mesh,
                                 fmDiagnostic* diag)
{
	int* tetsAround = FM_ALLOC_ZERO(int, (size_t)b->mesh.vertexCount);
	if (tetsAround == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                   "out of memory preparing a body of %d vertices", b->mesh.vertexCount);
	fmResult r = fmBodyPrecomputeWith(b, def, mesh, diag, tetsAround);
	if (r == fm_ok)
		fmBodyBuildIncidence(b, tetsAround);
	FM_FREE_ARRAY(tetsAround, int, (size_t)b->mesh.vertexCount);
	return r;
}

// Put the body's vertices and tets (user's order, oriented) in the body's own order
// (reorder.h), keeping the maps between the two numberings and the user's tets.
static bool fmBodyReorder(fmBody* b)
{
	const int n = b->mesh.vertexCount, m = b->mesh.tetCount;
	double* userX = FM_ALLOC_ARRAY(double, 3 * (size_t)n);
	bool ok = userX != NULL &&
	          fmReorder_Compute(b->mesh.x0, n, b->mesh.tets, m, b->userTet, b->userVertex);
	if (ok)
	{
		memcpy(userX, b->mesh.x0, sizeof(double) * 3 * (size_t)n);
		memcpy(b->userTets, b->mesh.tets, sizeof(int) * 4 * (size_t)m);
		for (int i = 0; i < n; ++i)
		{
			b->internalVertex[b->userVertex[i]] = i;
			fmStore(b->mesh.x0, i, fmLoad(userX, b->userVertex[i]));
		}
		for (int t = 0; t < m; ++t)
			for (int a = 0; a < 4; ++a)
				b->mesh.tets[4 * t + a] = b->internalVertex[b->userTets[4 * b->userTet[t] + a]];
	}
	FM_FREE_ARRAY(userX, double, 3 * (size_t)n);
	return ok;
}

// The surface in the user's numbering (what fmBody_GetSurface returns).
static bool fmBodyUserSurface(fmBody* b)
{
	size_t count = 3 * (size_t)b->mesh.triangleCount;
	b->userSurface = FM_ALLOC_ARRAY(int, count);
	if (b->userSurface == NULL && count > 0)
		return false;
	for (size_t k = 0; k < count; ++k)
		b->userSurface[k] = b->userVertex[b->mesh.surface[k]];
	return true;
}

// The body takes only positions and tets from the (validated) def mesh: no copy of the mesh,
// its attributes or markers is made, and the caller's mesh is not modified.
// Per-region materials: each tet's material from its region (the mesh's first tet attribute,
// read through the body's tet order), the default material for regions not listed; per-tet
// fibres in the body's tet order.
static bool fmBodyAssignRegions(fmBody* b, const fmBodyDef* def)
{
	if (def->tetFibres != NULL)
	{
		b->mesh.fibres = FM_ALLOC_ARRAY(fmVec3, b->mesh.tetCount);
		if (b->mesh.fibres == NULL)
			return false;
		for (int t = 0; t < b->mesh.tetCount; ++t)
			b->mesh.fibres[t] = def->tetFibres[b->userTet[t]];
	}
	if (def->regionCount <= 0)
		return true;
	b->mesh.materialCount = def->regionCount + 1;
	b->mesh.materials = FM_ALLOC_ARRAY(fmMaterial, b->mesh.materialCount);
	b->mesh.tetMaterial = FM_ALLOC_ZERO(uint16_t, b->mesh.tetCount);
	if (b->mesh.materials == NULL || b->mesh.tetMaterial == NULL)
		return false;
	b->mesh.materials[0] = def->material;
	memcpy(b->mesh.materials + 1, def->regionMaterials,
	       sizeof(fmMaterial) * (size_t)def->regionCount);
	for (int k = 0; k < b->mesh.materialCount; ++k)
		fmMaterial_SetScale(&b->mesh.materials[k]);
	const fmTetMesh* mesh = def->mesh;
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		double region =
		    mesh->tetAttributes[(size_t)b->userTet[t] * (size_t)mesh->tetAttributeCount];
		for (int k = 0; k < def->regionCount; ++k)
			if (region == (double)def->regionIds[k])
				b->mesh.tetMaterial[t] = (uint16_t)(k + 1);
	}
	return true;
}

static fmResult fmBodyInit(fmBody* b, const fmBodyDef* def, fmDiagnostic* diag)
{
	const fmTetMesh* source = def->mesh;
	fmResult r = fm_ok;
	if (!fmBodyAllocate(b, source->nodeCount, source->tetCount))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                "out of memory creating a body of %d tets", source->tetCount);
	// A view of the body's own arrays: orientation swaps nodes in the body's copy of the tets.
	fmTetMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	mesh.nodeCount = source->nodeCount;
	mesh.positions = b->mesh.x0;
	mesh.tetCount = source->tetCount;
	mesh.tets = b->mesh.tets;
	mesh.firstIndex = source->firstIndex;
	if (r == fm_ok)
	{
		size_t n3 = sizeof(double) * 3 * (size_t)mesh.nodeCount;
		memcpy(b->mesh.x0, source->positions, n3);
		memcpy(b->mesh.tets, source->tets, sizeof(int) * 4 * (size_t)mesh.tetCount);
		r = fmTetMesh_Orient(&mesh, NULL, diag);
	}
	if (r == fm_ok && !fmBodyReorder(b))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                "out of memory ordering a body of %d tets", source->tetCount);
	if (r == fm_ok)
	{
		b->firstIndex = mesh.firstIndex;
		b->mesh.material = def->material;
		fmMaterial_SetScale(&b->mesh.material);
		b->mesh.forceModel = def->forceModel;
		b->damping = def->damping;
		b->smoothing = def->smoothing;
		b->rayleighMass = def->rayleighMass;
		b->rayleighStiffness = def->rayleighStiffness;
		b->mesh.springDamping = def->springDamping;
		b->friction = def->friction;
		b->filter = def->filter;
		b->selfCollision = def->selfCollision;
		b->canSleep = def->enableSleep;
		b->massPerParticle = def->massMode == fm_massPerParticle;
		size_t n3 = sizeof(double) * 3 * (size_t)mesh.nodeCount;
		memcpy(b->state.x, b->mesh.x0, n3);
		memcpy(b->xGood, b->mesh.x0, n3);
		r = fmBodyPrecompute(b, def, &mesh, diag);
	}
	if (r == fm_ok &&
	    (fmTetMesh_ExtractSurface(&mesh, &b->mesh.surface, &b->mesh.triangleCount) != fm_ok ||
	     !fmBodyUserSurface(b)))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory extracting the surface");
	if (r == fm_ok)
		for (int i = 0; i < b->mesh.vertexCount; ++i)
			b->userMass[b->userVertex[i]] = b->mesh.mass[i];
	if (r == fm_ok && !fmBodyAssignRegions(b, def))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for region materials");
	if (r == fm_ok && b->mesh.forceModel == fm_massSpring && fmBuildSprings(&b->mesh) != 0)
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory building springs");
	if (r == fm_ok && b->mesh.forceModel == fm_fvm && fmBuildFvmNormals(&b->mesh) != 0)
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory building FVM normals");
	if (r == fm_ok && !fmPlasticity_Prepare(b))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for plastic state");
	if (r == fm_ok)
		r = fmNodalPressure_Prepare(&b->mesh, diag);
	if (r == fm_ok)
		r = fmFracture_Prepare(b, diag);
	if (r == fm_ok)
		b->energyStale = true;
	return r;
}

// ---- the memory budget
// ---------------------------------------------------------------------------

// Refuse a body the world's memory budget cannot hold, before anything is allocated.
static fmResult fmCheckBudget(const fmWorld* world, const fmBodyDef* def, size_t* estimate,
                              fmDiagnostic* diag)
{
	*estimate = fmEstimateBodyMemory(def);
	size_t used = fmWorldMemoryInUse(world), budget = world->def.memoryBudget;
	if (used <= budget && *estimate <= budget - used)
		return fm_ok;
	const double mib = 1024.0 * 1024.0;
	return fmDiagError(
	    diag, fm_errLimit, "", 0, 0,
	    "a body of %d nodes and %d tets needs about %.1f MiB (%zu bytes: its arrays and the "
	    "implicit solver's matrix, fmEstimateBodyMemory); the world already uses %.1f MiB of its "
	    "memory budget of %.1f MiB (fmWorldDef.memoryBudget): use a coarser mesh or raise the "
	    "budget",
	    def->mesh->nodeCount, def->mesh->tetCount, (double)*estimate / mib, *estimate,
	    (double)used / mib, (double)budget / mib);
}

// ---- creation and ids --------------------------------------------------------------------------

// A new body starting across or inside another it collides with, or across itself when it meets
// itself, is refused: contact cannot separate surfaces that already cross (docs/contact.md).
static fmResult fmRefuseOverlap(fmWorld* w, int slot, fmDiagnostic* diag)
{
	fmAuditOverlap o;
	fmResult r = fmAudit_Overlap(w, slot, &o);
	if (r != fm_ok)
		return fmDiagError(diag, r, "", 0, 0,
		                   "cannot check that the new body starts apart from the others (%s)",
		                   fmResultMessage(r));
	if (o.selfCrossings > 0)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "the body's surface crosses itself at rest (%d surface edges cross "
		                   "its own triangles; the first, edge %d-%d, crosses triangle %d): "
		                   "self-collision holds a surface apart from itself, it cannot "
		                   "separate one that already crosses; fix the mesh (overlapping tets?) "
		                   "or turn selfCollision off",
		                   o.selfCrossings, o.firstSelfCrossing.vertex[0],
		                   o.firstSelfCrossing.vertex[1], o.firstSelfCrossing.index);
	if (o.other < 0)
		return fm_ok;
	return fmDiagError(diag, fm_errParameter, "", 0, 0,
	                   "the body would start overlapping body %d (%d surface edges crossing "
	                   "surface triangles, %d surface vertices and %d tet centres inside, up to "
	                   "%.3g m deep): bodies that collide must start apart, contact cannot "
	                   "separate surfaces that already cross; move it, or give the two bodies "
	                   "filters that do not meet",
	                   o.other, o.crossings, o.verticesInside, o.tetsInside, o.deepest);
}

static fmResult fmCreateBodyIn(fmWorldId worldId, const fmBodyDef* def, fmBodyId* bodyId,
                               fmDiagnostic* diag)
{
	fmDiagClear(diag);
	if (bodyId)
		memset(bodyId, 0, sizeof *bodyId);
	fmWorld* world = fmGetWorld(worldId);
	FM_ASSERT(world != NULL);
	if (world == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid or destroyed world id");
	fmResult r = fmBodyDef_Validate(def, diag);
	if (r != fm_ok)
		return r;
	size_t estimate;
	r = fmCheckBudget(world, def, &estimate, diag);
	if (r != fm_ok)
		return r;
	// A slot whose generation would wrap is retired: its old ids must never come back.
	int slot = -1;
	for (int i = world->freeSlotHint; i < world->bodyCapacity && slot < 0; ++i)
		if (!fmBody_IsLive(&world->bodies[i]) && world->bodies[i].generation != UINT32_MAX)
			slot = i;
	if (slot < 0)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "the world holds %d bodies already (maxBodies)", world->bodyCapacity);
	fmBody* b = &world->bodies[slot];
	b->generation += 1;
	r = fmBodyInit(b, def, diag);
	b->slot = slot;
	if (r == fm_ok && !fmWorldReserveArenaFor(world, b))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                "out of memory for the step buffers of a body of %d vertices",
		                b->mesh.vertexCount);
	if (r == fm_ok)
		b->explicitLimit = fmWorldBodyStepLimit(world, b);
	if (r == fm_ok && world->def.contact.bodies)
		r = fmRefuseOverlap(world, slot, diag);
	if (r != fm_ok)
	{
		fmBodyRelease(b);
		return r;
	}
	b->memoryEstimate = estimate;
	world->bodyMemory += estimate; // (within the budget: fmCheckBudget)
	world->freeSlotHint = slot + 1;
	if (bodyId)
	{
		bodyId->index1 = slot + 1;
		bodyId->generation = b->generation;
		bodyId->world0 = worldId.index1 - 1;
		bodyId->worldGeneration = worldId.generation;
	}
	return fm_ok;
}

fmBody* fmGetBody(fmBodyId id)
{
	fmWorld* world = fmGetWorldOfBody(id);
	if (world == NULL || id.index1 < 1 || id.index1 > world->bodyCapacity)
		return NULL;
	fmBody* b = &world->bodies[id.index1 - 1];
	if (!fmBody_IsLive(b) || b->generation != id.generation)
		return NULL;
	return b;
}

// Resolve an id for a public call: a stale id is a programmer error.
static fmBody* fmBodyOrAssert(fmBodyId id)
{
	fmBody* b = fmGetBody(id);
	FM_ASSERT(b != NULL);
	return b;
}

void fmDestroyBody(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	fmIsland_WakeBody(bodyId); // what rested on it must fall
	if (b == NULL)
		return;
	fmWorld* world = fmGetWorldOfBody(bodyId);
	world->bodyMemory -= b->memoryEstimate;
	world->freeSlotHint = b->slot < world->freeSlotHint ? b->slot : world->freeSlotHint;
	fmBodyRelease(b);
}

bool fmBody_IsValid(fmBodyId bodyId)
{
	return fmGetBody(bodyId) != NULL;
}

int fmBody_GetVertexCount(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->mesh.vertexCount : 0;
}

int fmBody_GetTetCount(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->mesh.tetCount : 0;
}

// ---- copy-out read-back ------------------------------------------------------------------------

// Check a copy-out call (@p what names it): a live body, a buffer, room for every vertex. On
// failure the world's last error, when the world is live, says why.
static fmResult fmCheckCopyOut(fmBodyId bodyId, const void* out, int vertexCapacity,
                               const char* what, fmBody** body)
{
	fmWorld* world = fmGetWorldOfBody(bodyId);
	fmDiagnostic* diag = world ? &world->lastError : NULL;
	*body = fmBodyOrAssert(bodyId);
	FM_ASSERT(out != NULL);
	if (*body == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "%s: invalid or destroyed body id",
		                   what);
	if (out == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "%s: the buffer is NULL (expected 3 values a vertex)", what);
	if (vertexCapacity < (*body)->mesh.vertexCount)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "%s: a buffer of %d vertices is too small for body %d's %d vertices "
		                   "(fmBody_GetVertexCount; 3 values a vertex)",
		                   what, vertexCapacity, bodyId.index1 - 1, (*body)->mesh.vertexCount);
	return fm_ok;
}

// The one place internal state leaves the library: vertex i of the user's numbering (the mesh's
// node order) goes to out[3 i .. 3 i + 2], whatever order femto keeps its own arrays in.
static void fmCopyOut(const fmBody* b, const double* state, double* out)
{
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		fmStore(out, b->userVertex[i], fmLoad(state, i));
}

// The same into floats, rounded in femto's floating-point environment (to nearest, whatever the
// host's rounding mode).
static void fmCopyOutFloat(const fmBody* b, const double* state, float* out)
{
	fmFpEnv env = fmFpEnv_Enter(fmDetMath_Enabled());
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		for (int k = 0; k < 3; ++k)
			out[3 * b->userVertex[i] + k] = (float)state[3 * i + k];
	fmFpEnv_Leave(&env);
}

// A copy-out of the positions (or @p velocities) as doubles (@p out) or floats (@p outFloat).
static fmResult fmCopyState(fmBodyId bodyId, bool velocities, double* out, float* outFloat,
                            int vertexCapacity, const char* what)
{
	fmBody* b;
	const void* buffer = out ? (const void*)out : (const void*)outFloat;
	fmResult r = fmCheckCopyOut(bodyId, buffer, vertexCapacity, what, &b);
	if (r != fm_ok)
		return r;
	if (out)
		fmCopyOut(b, velocities ? b->state.v : b->state.x, out);
	else
		fmCopyOutFloat(b, velocities ? b->state.v : b->state.x, outFloat);
	return fm_ok;
}

fmResult fmBody_CopyPositions(fmBodyId bodyId, double* positions, int vertexCapacity)
{
	return fmCopyState(bodyId, false, positions, NULL, vertexCapacity, "fmBody_CopyPositions");
}

fmResult fmBody_CopyPositionsFloat(fmBodyId bodyId, float* positions, int vertexCapacity)
{
	return fmCopyState(bodyId, false, NULL, positions, vertexCapacity, "fmBody_CopyPositionsFloat");
}

fmResult fmBody_CopyInterpolatedPositionsFloat(fmBodyId bodyId, double alpha, float* positions,
                                               int vertexCapacity)
{
	fmBody* b;
	const char* what = "fmBody_CopyInterpolatedPositionsFloat";
	fmResult r = fmCheckCopyOut(bodyId, positions, vertexCapacity, what, &b);
	if (r != fm_ok)
		return r;
	if (!(alpha >= 0.0 && alpha <= 1.0))
		return fmDiagError(&fmGetWorldOfBody(bodyId)->lastError, fm_errParameter, "", 0, 0,
		                   "%s: alpha %g is outside [0, 1] (fmFixedStep.alpha)", what, alpha);
	if (!b->previousValid || alpha == 1.0) // now, bit for bit
	{
		fmCopyOutFloat(b, b->state.x, positions);
		return fm_ok;
	}
	fmFpEnv env = fmFpEnv_Enter(fmDetMath_Enabled());
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		for (int k = 0; k < 3; ++k)
		{
			double from = b->previousX[3 * i + k], to = b->state.x[3 * i + k];
			positions[3 * b->userVertex[i] + k] = (float)(from + alpha * (to - from));
		}
	fmFpEnv_Leave(&env);
	return fm_ok;
}

fmResult fmBody_CopyVelocities(fmBodyId bodyId, double* velocities, int vertexCapacity)
{
	return fmCopyState(bodyId, true, velocities, NULL, vertexCapacity, "fmBody_CopyVelocities");
}

fmResult fmBody_CopyVelocitiesFloat(fmBodyId bodyId, float* velocities, int vertexCapacity)
{
	return fmCopyState(bodyId, true, NULL, velocities, vertexCapacity,
	                   "fmBody_CopyVelocitiesFloat");
}

const double* fmBody_GetMasses(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->userMass : NULL;
}

const int* fmBody_GetTets(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->userTets : NULL;
}

const int* fmBody_GetSurface(fmBodyId bodyId, int* triangleCount)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (triangleCount)
		*triangleCount = b ? b->mesh.triangleCount : 0;
	return b ? b->userSurface : NULL;
}

// A state array the caller hands in must be there. Non-finite values are accepted on purpose:
// the next step's health check reports them and restores the last good state (test_robust.c).
static bool fmHasState(const fmBody* b, const double* values)
{
	FM_ASSERT(values != NULL);
	return b != NULL && values != NULL;
}

void fmBody_SetPositions(fmBodyId bodyId, const double* positions)
{
	fmIsland_WakeBody(bodyId);
	fmBody* b = fmBodyOrAssert(bodyId);
	if (!fmHasState(b, positions))
		return;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		fmStore(b->state.x, i, fmLoad(positions, b->userVertex[i]));
	b->positionsSet = true;
	b->previousValid = false; // a teleport: nothing to interpolate from
	fmWorld_MovedVertices(fmGetWorldOfBody(bodyId));
}

void fmBody_SetVelocities(fmBodyId bodyId, const double* velocities)
{
	fmIsland_WakeBody(bodyId);
	fmBody* b = fmBodyOrAssert(bodyId);
	if (!fmHasState(b, velocities))
		return;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmStore(b->state.v, i, fmLoad(velocities, b->userVertex[i]));
		fmZeroPinnedAxes(&b->state, i, b->state.v + 3 * i);
	}
}

static void fmBodyApplyImpulseIn(fmBodyId bodyId, fmVec3 deltaVelocity)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(fmIsFiniteVec3(deltaVelocity));
	if (b == NULL || !fmIsFiniteVec3(deltaVelocity))
		return;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmStore(b->state.v, i, fmAdd(fmLoad(b->state.v, i), deltaVelocity));
		fmZeroPinnedAxes(&b->state, i, b->state.v + 3 * i);
	}
}

static void fmBodyApplyVertexImpulseIn(fmBodyId bodyId, int vertex, fmVec3 deltaVelocity)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->mesh.vertexCount));
	FM_ASSERT(fmIsFiniteVec3(deltaVelocity));
	if (b && vertex >= 0 && vertex < b->mesh.vertexCount && fmIsFiniteVec3(deltaVelocity))
	{
		vertex = b->internalVertex[vertex];
		fmStore(b->state.v, vertex, fmAdd(fmLoad(b->state.v, vertex), deltaVelocity));
		fmZeroPinnedAxes(&b->state, vertex, b->state.v + 3 * vertex);
	}
}

void fmBody_SetPinned(fmBodyId bodyId, int vertex, bool pinned)
{
	fmIsland_WakeBody(bodyId);
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->mesh.vertexCount));
	if (b == NULL || vertex < 0 || vertex >= b->mesh.vertexCount)
		return;
	fmBody_SetPinnedAxes(bodyId, vertex, pinned ? FM_PIN_ALL : 0u);
}

static void fmBodySetPinnedAxesIn(fmBodyId bodyId, int vertex, unsigned axes)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->mesh.vertexCount));
	FM_ASSERT(axes <= FM_PIN_ALL);
	if (b == NULL || vertex < 0 || vertex >= b->mesh.vertexCount)
		return;
	vertex = b->internalVertex[vertex];
	b->state.pinned[vertex] = (uint8_t)(axes & FM_PIN_ALL);
	b->state.invMass[vertex] =
	    b->state.pinned[vertex] == FM_PIN_ALL ? 0.0 : 1.0 / b->mesh.mass[vertex];
	fmZeroPinnedAxes(&b->state, vertex, b->state.v + 3 * vertex);
}

bool fmBody_IsPinned(fmBodyId bodyId, int vertex)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->mesh.vertexCount));
	return b && vertex >= 0 && vertex < b->mesh.vertexCount &&
	       b->state.pinned[b->internalVertex[vertex]] == FM_PIN_ALL;
}

int fmBody_PinBox(fmBodyId bodyId, fmVec3 min, fmVec3 max)
{
	fmIsland_WakeBody(bodyId);
	fmBody* b = fmBodyOrAssert(bodyId);
	// Infinite bounds are fine (a half-space); NaN ones catch nothing and are a mistake.
	bool ordered = !isnan(min.x) && !isnan(min.y) && !isnan(min.z) && !isnan(max.x) &&
	               !isnan(max.y) && !isnan(max.z);
	FM_ASSERT(ordered);
	if (b == NULL || !ordered)
		return 0;
	int count = 0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i);
		if (p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
		    p.z <= max.z)
		{
			fmBody_SetPinned(bodyId, b->userVertex[i], true);
			++count;
		}
	}
	return count;
}

// The springs of a body built again as if every tet had @p material (the same edges); on
// failure the old ones are kept.
static bool fmBodyRebuildSprings(fmBody* b, const fmMaterial* material)
{
	fmBody old = *b;
	uint16_t* tetMaterial = b->mesh.tetMaterial;
	fmMaterial saved = b->mesh.material;
	b->mesh.tetMaterial = NULL;
	b->mesh.material = *material;
	bool ok = fmBuildSprings(&b->mesh) == 0;
	b->mesh.tetMaterial = tetMaterial;
	b->mesh.material = saved;
	if (!ok)
	{
		FM_FREE_ARRAY(b->mesh.edges, int, 2 * (size_t)b->mesh.edgeCount);
		FM_FREE_ARRAY(b->mesh.restLength, double, b->mesh.edgeCount);
		FM_FREE_ARRAY(b->mesh.springK, double, b->mesh.edgeCount);
		b->mesh.edges = old.mesh.edges;
		b->mesh.restLength = old.mesh.restLength;
		b->mesh.springK = old.mesh.springK;
		b->mesh.edgeCount = old.mesh.edgeCount;
		return false;
	}
	FM_FREE_ARRAY(old.mesh.edges, int, 2 * (size_t)old.mesh.edgeCount);
	FM_FREE_ARRAY(old.mesh.restLength, double, old.mesh.edgeCount);
	FM_FREE_ARRAY(old.mesh.springK, double, old.mesh.edgeCount);
	return true;
}

static fmResult fmBodySetMaterialIn(fmBodyId bodyId, const fmMaterial* material, fmDiagnostic* diag)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(material != NULL);
	if (b == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid or destroyed body id");
	fmResult r = fmMaterial_Validate(material, diag);
	if (r != fm_ok)
		return r;
	if (b->mesh.forceModel == fm_massSpring && fmMaterialModel_IsAnisotropic(material->model))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "anisotropic materials need the fem or fvm force model: this body's "
		                   "springs carry one stiffness each");
	if (b->mesh.forceModel != fm_fem && fmPlasticity_Flows(material))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "plasticity needs the fem force model (a tet's plastic part lives in "
		                   "its rest data), not %s",
		                   fmForceModelName(b->mesh.forceModel));
	if (b->mesh.forceModel != fm_fem && fmFracture_Tears(material))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "fracture needs the fem force model, not %s",
		                   fmForceModelName(b->mesh.forceModel));
	if (b->mesh.forceModel != fm_fem && material->nodalPressure)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "nodalPressure needs the fem force model, not %s",
		                   fmForceModelName(b->mesh.forceModel));
	if (fmPlasticity_Flows(material) && !fmPlasticity_Allocate(b)) // before anything changes
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for plastic state");
	bool wasNodal = fmNodalPressure_On(&b->mesh);
	fmNodalPressure_Free(&b->mesh); // (sized by the materials it was made from)
	if (b->mesh.tetMaterial != NULL)
	{
		// Per-region materials give way to the one material for every tet; springs, whose
		// stiffness summed each tet's own modulus, are rebuilt.
		if (b->mesh.forceModel == fm_massSpring && !fmBodyRebuildSprings(b, material))
			return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
			                   "out of memory rebuilding the springs");
		FM_FREE_ARRAY(b->mesh.materials, fmMaterial, b->mesh.materialCount);
		FM_FREE_ARRAY(b->mesh.tetMaterial, uint16_t, b->mesh.tetCount);
		b->mesh.materials = NULL;
		b->mesh.tetMaterial = NULL;
		b->mesh.materialCount = 0;
	}
	else
	{
		// Spring stiffness is proportional to Young's modulus (force_spring.c).
		double ratio = fmYoungsModulus(material) / fmYoungsModulus(&b->mesh.material);
		for (int e = 0; e < b->mesh.edgeCount; ++e)
			b->mesh.springK[e] *= ratio;
	}
	b->mesh.material = *material;
	fmMaterial_SetScale(&b->mesh.material);
	// One material now: its patches cannot fail on laws, only on memory (then the body is left
	// with the material's per-tet volume term, and says so).
	r = fmNodalPressure_Prepare(&b->mesh, diag);
	if (wasNodal != fmNodalPressure_On(&b->mesh)) // the Newton matrix's pattern changes
	{
		fmSolverCache_Free(b->solverCache);
		b->solverCache = NULL;
	}
	if (r == fm_ok)
		r = fmFracture_Prepare(b, diag); // (the averages follow the fracture lengths)
	b->explicitLimit = fmWorldBodyStepLimit(fmGetWorldOfBody(bodyId), b);
	b->energyStale = true;
	return r;
}

static double fmBodyComputeElasticForcesIn(fmBodyId bodyId, double* forces)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(forces != NULL);
	if (b == NULL || forces == NULL)
		return 0.0;
	size_t n3 = 3 * (size_t)b->mesh.vertexCount;
	double* internal = FM_ALLOC_ZERO(double, n3);
	if (internal == NULL)
	{
		fmLog(fm_logError, "fmBody_ComputeElasticForces: out of memory for %zu doubles", n3);
		memset(forces, 0, sizeof(double) * n3);
		return 0.0;
	}
	double energy = fmAddElasticForces(&b->mesh, b->state.x, internal);
	fmCopyOut(b, internal, forces);
	FM_FREE_ARRAY(internal, double, n3);
	return energy;
}

int fmBodyCountInvertedAt(const fmBody* b, const double* x)
{
	int inverted = 0;
	unsigned char flags[256];
	for (int first = 0; first < b->mesh.tetCount; first += 256)
	{
		int end = b->mesh.tetCount - first < 256 ? b->mesh.tetCount : first + 256;
		fmInvertedTets(&b->mesh, x, first, end, flags);
		for (int t = 0; t < end - first; ++t)
			inverted += flags[t];
	}
	return inverted;
}

double fmBodyKineticEnergy(const fmBody* b)
{
	double sum = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 v = fmLoad(b->state.v, i);
		sum += 0.5 * b->mesh.mass[i] * fmDot(v, v);
	}
	return sum;
}

int fmBodyCountInverted(const fmBody* b)
{
	return fmBodyCountInvertedAt(b, b->state.x);
}

typedef struct fmInvertedTask
{
	const fmBody* body;
	unsigned char* inverted; // a flag a tet
} fmInvertedTask;

static void fmInvertedRange(int start, int end, int worker, void* context)
{
	(void)worker;
	const fmInvertedTask* c = context;
	fmInvertedTets(&c->body->mesh, c->body->state.x, start, end, c->inverted + start);
}

int fmBodyCountInvertedOn(const fmBody* b, const fmTaskSystem* tasks, fmArena* arena)
{
	if (tasks == NULL || tasks->workerCount < 2 || b->mesh.tetCount < 2 * FM_PARALLEL_MIN_RANGE)
		return fmBodyCountInverted(b);
	size_t mark = fmArena_Mark(arena);
	double* room = fmArena_DoublesUninit(arena, ((size_t)b->mesh.tetCount + 7) / 8);
	int inverted = 0;
	if (room == NULL)
		inverted = fmBodyCountInverted(b);
	else
	{
		fmInvertedTask c = {b, (unsigned char*)room};
		fmParallelFor(tasks, b->mesh.tetCount, FM_PARALLEL_MIN_RANGE, fmInvertedRange, &c);
		for (int t = 0; t < b->mesh.tetCount; ++t)
			inverted += c.inverted[t];
	}
	fmArena_Release(arena, mark);
	return inverted;
}

static fmBodyStats fmBodyGetStatsIn(fmBodyId bodyId)
{
	fmBodyStats s;
	memset(&s, 0, sizeof s);
	fmBody* b = fmBodyOrAssert(bodyId);
	fmWorld* world = fmGetWorldOfBody(bodyId);
	if (b == NULL || world == NULL)
		return s;
	fmVec3 g = world->def.gravity;
	s.lowestY = INFINITY;
	fmVec3 moment = {0, 0, 0};
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i), v = fmLoad(b->state.v, i);
		s.kineticEnergy += 0.5 * b->mesh.mass[i] * fmDot(v, v);
		s.gravityEnergy -= b->mesh.mass[i] * fmDot(g, p);
		moment = fmMulAdd(moment, b->mesh.mass[i], p);
		s.lowestY = fmMin(s.lowestY, p.y);
	}
	s.centerOfMass = fmScale(1.0 / b->mesh.totalMass, moment);
	s.elasticEnergy = fmSolverCache_Energy(&b->mesh, b->solverCache, b->state.x, NULL, NULL);
	s.invertedTets = fmBodyCountInverted(b);
	s.work = b->ledger.work;
	s.initialEnergy = b->ledger.initialEnergy;
	s.plasticWork = b->plasticWork;
	s.plasticStrain = fmPlasticity_LargestStrain(b);
	return s;
}

// ---- public calls that compute, in femto's floating-point environment (fp_env.h) ---------------

// Save the host's floating-point state and set femto's, with the det_math mode of the body's
// world (a stale id gets the default mode; the call itself then reports the id).
static fmFpEnv fmBodyFpEnter(fmBodyId bodyId)
{
	fmWorld* world = fmGetWorldOfBody(bodyId);
	return fmFpEnv_Enter(world != NULL && world->def.crossPlatformDeterminism);
}

fmResult fmBodyDef_Validate(const fmBodyDef* def, fmDiagnostic* diag)
{
	fmFpEnv env = fmFpEnv_Enter(false);
	fmResult result = fmBodyDef_Check(def, diag);
	fmFpEnv_Leave(&env);
	return result;
}

fmResult fmCreateBody(fmWorldId worldId, const fmBodyDef* def, fmBodyId* bodyId, fmDiagnostic* diag)
{
	fmWorld* world = fmGetWorld(worldId);
	fmFpEnv env = fmFpEnv_Enter(world != NULL && world->def.crossPlatformDeterminism);
	fmResult result = fmCreateBodyIn(worldId, def, bodyId, diag);
	fmFpEnv_Leave(&env);
	return result;
}

void fmBody_ApplyImpulse(fmBodyId bodyId, fmVec3 deltaVelocity)
{
	fmIsland_WakeBody(bodyId);
	fmFpEnv env = fmBodyFpEnter(bodyId);
	fmBodyApplyImpulseIn(bodyId, deltaVelocity);
	fmFpEnv_Leave(&env);
}

void fmBody_ApplyVertexImpulse(fmBodyId bodyId, int vertex, fmVec3 deltaVelocity)
{
	fmIsland_WakeBody(bodyId);
	fmFpEnv env = fmBodyFpEnter(bodyId);
	fmBodyApplyVertexImpulseIn(bodyId, vertex, deltaVelocity);
	fmFpEnv_Leave(&env);
}

void fmBody_SetPinnedAxes(fmBodyId bodyId, int vertex, unsigned axes)
{
	fmIsland_WakeBody(bodyId);
	fmFpEnv env = fmBodyFpEnter(bodyId);
	fmBodySetPinnedAxesIn(bodyId, vertex, axes);
	fmFpEnv_Leave(&env);
}

fmResult fmBody_SetMaterial(fmBodyId bodyId, const fmMaterial* material, fmDiagnostic* diag)
{
	fmIsland_WakeBody(bodyId);
	fmFpEnv env = fmBodyFpEnter(bodyId);
	fmResult result = fmBodySetMaterialIn(bodyId, material, diag);
	fmFpEnv_Leave(&env);
	return result;
}

double fmBody_ComputeElasticForces(fmBodyId bodyId, double* forces)
{
	fmFpEnv env = fmBodyFpEnter(bodyId);
	double result = fmBodyComputeElasticForcesIn(bodyId, forces);
	fmFpEnv_Leave(&env);
	return result;
}

fmBodyStats fmBody_GetStats(fmBodyId bodyId)
{
	fmFpEnv env = fmBodyFpEnter(bodyId);
	fmBodyStats result = fmBodyGetStatsIn(bodyId);
	fmFpEnv_Leave(&env);
	return result;
}
