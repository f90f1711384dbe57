// A torn body's topology (tear_topology.h).
#include "body/tear_topology.h"

#include "body/anchors.h"
#include "body/body.h"
#include "body/fracture.h"
#include "body/loads.h"
#include "body/targets.h"
#include "core/core.h"
#include "fem/nodal_pressure.h"
#include "fem/tet_blocks.h"
#include "solver/solver_cache.h"
#include "world/world.h"

#include <string.h>

// The per-vertex arrays of a topology being made, before they replace the body's.
typedef struct fmVertexArrays
{
	int count;
	double *x0, *x, *v, *f, *xGood, *vGood, *mass, *smoothWeight, *invMass, *userMass;
	uint8_t* pinned;
	int *userVertex, *internalVertex, *origin, *tetStart;
	int* surface; // fmTetMesh_ExtractSurface's (fmFree)
	int triangleCount;
	int* userSurface;
} fmVertexArrays;

static void fmVertexArrays_Free(fmVertexArrays* a)
{
	size_t n = (size_t)a->count;
	double** doubles3[] = {&a->x0, &a->x, &a->v, &a->f, &a->xGood, &a->vGood};
	for (size_t k = 0; k < sizeof doubles3 / sizeof doubles3[0]; ++k)
		FM_FREE_ARRAY(*doubles3[k], double, 3 * n);
	double** doubles[] = {&a->mass, &a->smoothWeight, &a->invMass, &a->userMass};
	for (size_t k = 0; k < sizeof doubles / sizeof doubles[0]; ++k)
		FM_FREE_ARRAY(*doubles[k], double, n);
	int** ints[] = {&a->userVertex, &a->internalVertex, &a->origin};
	for (size_t k = 0; k < sizeof ints / sizeof ints[0]; ++k)
		FM_FREE_ARRAY(*ints[k], int, n);
	FM_FREE_ARRAY(a->tetStart, int, n + 1);
	FM_FREE_ARRAY(a->pinned, uint8_t, n);
	fmFree(a->surface);
	FM_FREE_ARRAY(a->userSurface, int, 3 * (size_t)a->triangleCount);
	memset(a, 0, sizeof *a);
}

static bool fmVertexArrays_Allocate(fmVertexArrays* a, int count)
{
	size_t n = (size_t)count;
	memset(a, 0, sizeof *a);
	a->count = count;
	a->x0 = FM_ALLOC_ARRAY(double, 3 * n);
	a->x = FM_ALLOC_ARRAY(double, 3 * n);
	a->v = FM_ALLOC_ARRAY(double, 3 * n);
	a->f = FM_ALLOC_ZERO(double, 3 * n);
	a->xGood = FM_ALLOC_ARRAY(double, 3 * n);
	a->vGood = FM_ALLOC_ARRAY(double, 3 * n);
	a->mass = FM_ALLOC_ZERO(double, n);
	a->smoothWeight = FM_ALLOC_ARRAY(double, n);
	a->invMass = FM_ALLOC_ARRAY(double, n);
	a->userMass = FM_ALLOC_ARRAY(double, n);
	a->pinned = FM_ALLOC_ARRAY(uint8_t, n);
	a->userVertex = FM_ALLOC_ARRAY(int, n);
	a->internalVertex = FM_ALLOC_ARRAY(int, n);
	a->origin = FM_ALLOC_ARRAY(int, n);
	a->tetStart = FM_ALLOC_ZERO(int, n + 1);
	return a->x0 && a->x && a->v && a->f && a->xGood && a->vGood && a->mass && a->smoothWeight &&
	       a->invMass && a->userMass && a->pinned && a->userVertex && a->internalVertex &&
	       a->origin && a->tetStart;
}

// Positions, velocities, pins from each vertex's source; origins, numbering, the surface.
static bool fmFillCarried(const fmBody* b, const int* tets, const int* from, fmVertexArrays* a)
{
	const fmCracks* c = b->cracks;
	int n0 = c->originalVertexCount, m = b->mesh.tetCount;
	for (int i = 0; i < a->count; ++i)
	{
		int s = from[i];
		memcpy(a->x + 3 * i, b->state.x + 3 * s, 3 * sizeof(double));
		memcpy(a->v + 3 * i, b->state.v + 3 * s, 3 * sizeof(double));
		memcpy(a->xGood + 3 * i, b->xGood + 3 * s, 3 * sizeof(double));
		memcpy(a->vGood + 3 * i, b->vGood + 3 * s, 3 * sizeof(double));
		a->pinned[i] = b->state.pinned[s];
		a->origin[i] = i < n0 ? i : -1;
		a->userVertex[i] = i < n0 ? b->userVertex[i] : i;
		a->internalVertex[a->userVertex[i]] = i;
	}
	for (int e = 0; e < 4 * m; ++e)
	{
		a->origin[tets[e]] = c->originalTets[e];
		a->tetStart[tets[e]] += 1; // (counts for now)
	}
	for (int i = 0; i < a->count; ++i)
		memcpy(a->x0 + 3 * i, b->mesh.x0 + 3 * a->origin[i], 3 * sizeof(double));
	fmTetMesh view;
	memset(&view, 0, sizeof view);
	view.nodeCount = a->count;
	view.positions = a->x0;
	view.tetCount = m;
	view.tets = (int*)tets;
	if (fmTetMesh_ExtractSurface(&view, &a->surface, &a->triangleCount) != fm_ok)
		return false;
	size_t corners = 3 * (size_t)a->triangleCount;
	a->userSurface = FM_ALLOC_ARRAY(int, corners > 0 ? corners : 1);
	for (size_t k = 0; a->userSurface != NULL && k < corners; ++k)
		a->userSurface[k] = a->userVertex[a->surface[k]];
	return a->userSurface != NULL;
}

// Each vertex's mass: its original's times the vertex's share of the original's tets, by
// volume (a mass from density: what the pieces' own lumping gives) or by count (a mass per
// particle, which never came from volumes: a sliver's corner keeps a tet's share, not its tiny
// volume's, and the explicit step limit with it), the original's own number taking what the
// copies leave (the sum is the original's).
static void fmShareMasses(const fmBody* b, const int* tets, fmVertexArrays* a, double* whole)
{
	const fmCracks* c = b->cracks;
	int n0 = c->originalVertexCount, m = b->mesh.tetCount;
	memset(whole, 0, sizeof(double) * (size_t)n0);
	for (int e = 0; e < 4 * m; ++e)
	{
		double weight = b->massPerParticle ? 1.0 : b->mesh.restVolume[e / 4];
		whole[c->originalTets[e]] += weight;
		a->mass[tets[e]] += weight; // (weights for now)
	}
	for (int i = n0; i < a->count; ++i)
		a->mass[i] = c->originalMass[a->origin[i]] * (a->mass[i] / whole[a->origin[i]]);
	for (int i = 0; i < n0; ++i)
		a->mass[i] = c->originalMass[i];
	for (int i = n0; i < a->count; ++i)
		a->mass[a->origin[i]] -= a->mass[i];
	for (int i = 0; i < a->count; ++i)
	{
		a->invMass[i] = a->pinned[i] == FM_PIN_ALL ? 0.0 : 1.0 / a->mass[i];
		a->userMass[a->userVertex[i]] = a->mass[i];
		int around = a->tetStart[i];
		a->smoothWeight[i] = around > 0 ? 1.0 / (4.0 * around) : 0.0;
	}
}

// The arrays replace the body's (the old ones go to @p a, to be freed).
static void fmSwapIn(fmBody* b, const int* tets, fmVertexArrays* a)
{
	int n = b->mesh.vertexCount;
	fmVertexArrays old = {.count = n,
	                      .x0 = b->mesh.x0,
	                      .x = b->state.x,
	                      .v = b->state.v,
	                      .f = b->state.f,
	                      .xGood = b->xGood,
	                      .vGood = b->vGood,
	                      .mass = b->mesh.mass,
	                      .smoothWeight = b->mesh.smoothWeight,
	                      .invMass = b->state.invMass,
	                      .userMass = b->userMass,
	                      .pinned = b->state.pinned,
	                      .userVertex = b->userVertex,
	                      .internalVertex = b->internalVertex,
	                      .origin = b->cracks->origin,
	                      .tetStart = b->mesh.vertexTetStart,
	                      .surface = b->mesh.surface,
	                      .triangleCount = b->mesh.triangleCount,
	                      .userSurface = b->userSurface};
	b->mesh.vertexCount = a->count;
	b->mesh.x0 = a->x0;
	b->state.x = a->x;
	b->state.v = a->v;
	b->state.f = a->f;
	b->xGood = a->xGood;
	b->vGood = a->vGood;
	b->mesh.mass = a->mass;
	b->mesh.smoothWeight = a->smoothWeight;
	b->state.invMass = a->invMass;
	b->userMass = a->userMass;
	b->state.pinned = a->pinned;
	b->userVertex = a->userVertex;
	b->internalVertex = a->internalVertex;
	b->cracks->origin = a->origin;
	b->mesh.vertexTetStart = a->tetStart;
	b->mesh.surface = a->surface;
	b->mesh.triangleCount = a->triangleCount;
	b->userSurface = a->userSurface;
	*a = old;
	memcpy(b->mesh.tets, tets, sizeof(int) * 4 * (size_t)b->mesh.tetCount);
}

// The tets around each vertex again (vertexTetStart holds the counts on entry): filled from the
// back with the corners in descending order, each list ends up ascending.
static void fmRebuildIncidence(fmElasticMesh* mesh)
{
	int total = 0;
	for (int i = 0; i < mesh->vertexCount; ++i)
	{
		total += mesh->vertexTetStart[i];
		mesh->vertexTetStart[i] = total; // (the end of i's list for now)
	}
	mesh->vertexTetStart[mesh->vertexCount] = total;
	for (int e = 4 * mesh->tetCount - 1; e >= 0; --e)
		mesh->vertexTets[--mesh->vertexTetStart[mesh->tets[e]]] = e;
}

// What the body keeps that a new topology makes stale: the stages' scratch, made again when next
// needed.
static void fmDropDerived(fmBody* b, int oldCount)
{
	fmBodyContact_Free(&b->contact, oldCount, b->mesh.tetCount);
	fmSolverCache_Free(b->solverCache);
	b->solverCache = NULL;
	fmTetBlocks_Destroy(b->mesh.tetBlocks);
	b->mesh.tetBlocks = NULL;
	fmAttachment_Release(&b->drawCache);
	FM_FREE_ARRAY(b->previousX, double, 3 * (size_t)oldCount);
	b->previousX = NULL;
	b->previousValid = false;
	b->energyStale = true;
}

bool fmTearTopology_Set(fmWorld* w, fmBody* b, const int* tets, int vertexCount, const int* from)
{
	int n = b->mesh.vertexCount;
	fmVertexArrays a;
	memset(&a, 0, sizeof a);
	double* whole = FM_ALLOC_ARRAY(double, b->cracks->originalVertexCount);
	bool ok = whole != NULL && fmVertexArrays_Allocate(&a, vertexCount) &&
	          fmFillCarried(b, tets, from, &a) && fmLoads_Renumber(b, vertexCount, from);
	if (ok) // (nothing below fails but the nodal patches and the arena: those say so)
	{
		fmShareMasses(b, tets, &a, whole);
		fmNodalPressure_Free(&b->mesh); // (sized by the vertex count it was made for)
		fmSwapIn(b, tets, &a);
		fmRebuildIncidence(&b->mesh);
		for (int t = 0; t < b->mesh.tetCount; ++t)
			for (int k = 0; k < 4; ++k)
				b->userTets[4 * b->userTet[t] + k] = b->userVertex[b->mesh.tets[4 * t + k]];
		b->mesh.totalMass = 0.0;
		for (int i = 0; i < b->mesh.vertexCount; ++i)
			b->mesh.totalMass += b->mesh.mass[i];
		fmDropDerived(b, n);
		if (fmNodalPressure_Prepare(&b->mesh, NULL) != fm_ok)
			fmDiagWarn(&w->lastError, "", 0,
			           "out of memory for the nodal pressure of torn body %d: its tets keep "
			           "their own volume terms",
			           b->slot);
		if (!fmWorldReserveArenaFor(w, b))
			fmDiagWarn(&w->lastError, "", 0,
			           "out of memory for the step buffers of torn body %d (%d vertices)", b->slot,
			           vertexCount);
		b->explicitLimit = fmWorldBodyStepLimit(w, b);
	}
	fmVertexArrays_Free(&a);
	FM_FREE_ARRAY(whole, double, b->cracks->originalVertexCount);
	return ok;
}

// Vertex i's original from the corners, checked (NULL, or what is wrong).
static const char* fmOrigins(const fmCracks* c, const int* tets, int m, int vertexCount,
                             int* origin)
{
	int n0 = c->originalVertexCount;
	for (int i = 0; i < vertexCount; ++i)
		origin[i] = i < n0 ? i : -1;
	for (int e = 0; e < 4 * m; ++e)
	{
		int v = tets[e];
		if (v < 0 || v >= vertexCount)
			return "a corner out of range";
		if (origin[v] < 0)
			origin[v] = c->originalTets[e];
		else if (origin[v] != c->originalTets[e])
			return "a vertex standing for two original vertices";
	}
	for (int i = n0; i < vertexCount; ++i)
		if (origin[i] < 0)
			return "a copy no tet uses";
	return NULL;
}

const char* fmTearTopology_Problem(const fmBody* b, const int* tets, int vertexCount)
{
	const fmCracks* c = b->cracks;
	int n0 = c->originalVertexCount, m = b->mesh.tetCount;
	if (vertexCount < n0 || (int64_t)vertexCount > (int64_t)n0 + 4 * (int64_t)m)
		return "a vertex count outside [the original count, that plus 4 per tet]";
	int* origin = FM_ALLOC_ARRAY(int, vertexCount);
	uint8_t* used = FM_ALLOC_ZERO(uint8_t, 2 * (size_t)n0);
	if (origin == NULL || used == NULL)
	{
		FM_FREE_ARRAY(origin, int, origin != NULL ? vertexCount : 0);
		FM_FREE_ARRAY(used, uint8_t, used != NULL ? 2 * (size_t)n0 : 0);
		return FM_TEAR_NO_MEMORY;
	}
	const char* problem = fmOrigins(c, tets, m, vertexCount, origin);
	// An original vertex with tets keeps its number on one of them (its mass stays finite).
	for (int e = 0; problem == NULL && e < 4 * m; ++e)
	{
		used[c->originalTets[e]] = 1;
		if (tets[e] < n0)
			used[n0 + tets[e]] = 1;
	}
	for (int i = 0; problem == NULL && i < n0; ++i)
		if (used[i] && !used[n0 + i])
			problem = "an original vertex whose every tet went to its copies";
	FM_FREE_ARRAY(origin, int, vertexCount);
	FM_FREE_ARRAY(used, uint8_t, 2 * (size_t)n0);
	return problem;
}

int fmTearTopology_HighestHeld(const fmWorld* w, const fmBody* b)
{
	int highest = -1;
	for (int k = 0; k < b->targetCount; ++k)
		highest = b->targets[k].vertex > highest ? b->targets[k].vertex : highest;
	for (int k = 0; b->anchorTargets != NULL && k < b->anchorCount; ++k)
		highest = b->anchorTargets[k].vertex > highest ? b->anchorTargets[k].vertex : highest;
	const fmLoadSet* s = b->loads;
	for (int k = 0; s != NULL && k < s->prescribedCount; ++k)
		highest = s->prescribed[k].vertex > highest ? s->prescribed[k].vertex : highest;
	for (int k = 0; s != NULL && k < 3 * s->followerCount; ++k)
		highest = s->followerTriangle[k] > highest ? s->followerTriangle[k] : highest;
	for (int i = 0; i < w->bodyCapacity; ++i) // other bodies welded to this one's vertices
	{
		const fmBody* o = &w->bodies[i];
		for (int k = 0; fmBody_IsLive(o) && k < o->anchorCount; ++k)
			if (o->anchors[k].collider < 0 && o->anchors[k].body == b->slot)
				highest = o->anchors[k].otherVertex > highest ? o->anchors[k].otherVertex : highest;
	}
	return highest;
}
