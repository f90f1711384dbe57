// Triangle-mesh colliders (mesh_collider.h): a median-split bounding-volume hierarchy, a
// best-first closest-point query signed by pseudo-normals, and an exact segment cast.
#include "contact/mesh_collider.h"
#include "contact/mesh_motion.h"

#include "core/core.h"
#include "core/det_math.h"
#include "math/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Triangles a leaf holds at most.
#define FM_MESH_LEAF 4
// Depth of the traversal stacks: a median split halves every level, so 2^48 triangles fit.
#define FM_MESH_STACK 64

// Whether some triangle of a def whose corners are in range has an area above round-off: twice
// its area over 1e-12 times the squared diagonal of the triangles' box.
static bool fmMeshShape_HasArea(const fmColliderDef* d)
{
	fmVec3 lo = d->vertices[d->triangles[0]], hi = lo;
	for (int k = 0; k < 3 * d->triangleCount; ++k)
	{
		lo = fmMinVec(lo, d->vertices[d->triangles[k]]);
		hi = fmMaxVec(hi, d->vertices[d->triangles[k]]);
	}
	// (Corners on a line leave about 1e-16 of the squared diagonal in round-off.)
	fmVec3 size = fmSub(hi, lo);
	double tiny = 1e-12 * fmDot(size, size);
	for (int t = 0; t < d->triangleCount; ++t)
	{
		const int* c = d->triangles + 3 * t;
		fmVec3 n = fmCross(fmSub(d->vertices[c[1]], d->vertices[c[0]]),
		                   fmSub(d->vertices[c[2]], d->vertices[c[0]]));
		if (fmLength(n) > tiny)
			return true;
	}
	return false;
}

const char* fmMeshShape_Problem(const fmColliderDef* d)
{
	if (d->vertices == NULL || d->triangles == NULL)
		return "mesh: vertices and triangles arrays";
	if (d->triangleCount < 1 || d->triangleCount > FM_MAX_COLLIDER_TRIANGLES)
		return "mesh: a triangleCount in [1, FM_MAX_COLLIDER_TRIANGLES]";
	if (d->vertexCount < 3 || d->vertexCount > 3 * FM_MAX_COLLIDER_TRIANGLES)
		return "mesh: a vertexCount in [3, 3 * FM_MAX_COLLIDER_TRIANGLES]";
	for (int i = 0; i < d->vertexCount; ++i)
	{
		fmVec3 v = d->vertices[i];
		if (!(fabs(v.x) <= FM_MAX_COORDINATE && fabs(v.y) <= FM_MAX_COORDINATE &&
		      fabs(v.z) <= FM_MAX_COORDINATE))
			return "mesh: finite vertices within 1e9 m";
	}
	for (int k = 0; k < 3 * d->triangleCount; ++k)
		if (d->triangles[k] < 0 || d->triangles[k] >= d->vertexCount)
			return "mesh: triangle corners in [0, vertexCount)";
	return fmMeshShape_HasArea(d) ? NULL
	                              : "mesh: a triangle of some area (every one is degenerate: "
	                                "its corners on a line or a point)";
}

// ---- preparation -------------------------------------------------------------------------------

static fmVec3 fmCorner(const fmMeshShape* m, int t, int k)
{
	return m->vertices[m->triangles[3 * t + k]];
}

// The angle at corner a of triangle abc (det_math's atan2, the same bits on every target).
static double fmCornerAngle(fmVec3 a, fmVec3 b, fmVec3 c)
{
	fmVec3 u = fmSub(b, a), v = fmSub(c, a);
	return fmDetAtan2(fmLength(fmCross(u, v)), fmDot(u, v));
}

typedef struct fmEdgeKey
{
	uint64_t key; // the lower vertex in the high half
	int slot;     // 3 * triangle + edge
} fmEdgeKey;

static int fmCompareEdges(const void* a, const void* b)
{
	const fmEdgeKey *x = a, *y = b;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return (x->slot > y->slot) - (x->slot < y->slot);
}

static fmVec3 fmUnitOrZero(fmVec3 v)
{
	double length = fmLength(v);
	return length > 0.0 ? fmScale(1.0 / length, v) : fmMakeVec3(0.0, 0.0, 0.0);
}

static uint64_t fmEdgeKeyOf(const fmMeshShape* m, int slot)
{
	uint32_t p = (uint32_t)m->triangles[slot];
	uint32_t q = (uint32_t)m->triangles[slot - slot % 3 + (slot % 3 + 1) % 3];
	return p < q ? ((uint64_t)p << 32 | q) : ((uint64_t)q << 32 | p);
}

bool fmMeshShape_SortEdges(const fmMeshShape* m, int* slots)
{
	int n = 3 * m->triangleCount;
	fmEdgeKey* edges = FM_ALLOC_ARRAY(fmEdgeKey, n);
	if (edges == NULL)
		return false;
	for (int e = 0; e < n; ++e)
	{
		edges[e].key = fmEdgeKeyOf(m, e);
		edges[e].slot = e;
	}
	qsort(edges, (size_t)n, sizeof *edges, fmCompareEdges);
	for (int e = 0; e < n; ++e)
		slots[e] = edges[e].slot;
	FM_FREE_ARRAY(edges, fmEdgeKey, n);
	return true;
}

// Face, edge and vertex pseudo-normals; the slots of one edge are adjacent in @p edgeSlots
// (fmMeshShape_SortEdges), their faces summed in that order.
static void fmPrepareNormals(fmMeshShape* m, const int* edgeSlots)
{
	int n = m->triangleCount;
	memset(m->vertexNormal, 0, sizeof(fmVec3) * (size_t)m->vertexCount);
	for (int t = 0; t < n; ++t)
	{
		fmVec3 a = fmCorner(m, t, 0), b = fmCorner(m, t, 1), c = fmCorner(m, t, 2);
		m->faceNormal[t] = fmUnitOrZero(fmCross(fmSub(b, a), fmSub(c, a)));
		for (int k = 0; k < 3; ++k)
		{
			fmVec3 p = fmCorner(m, t, k), q = fmCorner(m, t, (k + 1) % 3);
			fmVec3 r = fmCorner(m, t, (k + 2) % 3);
			int v = m->triangles[3 * t + k];
			m->vertexNormal[v] =
			    fmMulAdd(m->vertexNormal[v], fmCornerAngle(p, q, r), m->faceNormal[t]);
		}
	}
	for (int v = 0; v < m->vertexCount; ++v)
		m->vertexNormal[v] = fmUnitOrZero(m->vertexNormal[v]);
	for (int first = 0, last; first < 3 * n; first = last)
	{
		uint64_t key = fmEdgeKeyOf(m, edgeSlots[first]);
		fmVec3 sum = fmMakeVec3(0.0, 0.0, 0.0);
		for (last = first; last < 3 * n && fmEdgeKeyOf(m, edgeSlots[last]) == key; ++last)
			sum = fmAdd(sum, m->faceNormal[edgeSlots[last] / 3]);
		for (int e = first; e < last; ++e)
			m->edgeNormal[edgeSlots[e]] = fmUnitOrZero(sum);
	}
}

// The box of triangle @p t grown to hold [*lo, *hi].
static void fmGrowBox(const fmMeshShape* m, int t, fmVec3* lo, fmVec3* hi)
{
	for (int k = 0; k < 3; ++k)
	{
		fmVec3 p = fmCorner(m, t, k);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
}

void fmMeshShape_Reshape(fmMeshShape* m, const int* edgeSlots)
{
	fmPrepareNormals(m, edgeSlots);
	// Children come after their parents (fmBuildNode): backwards, every box is refitted after
	// its children's.
	for (int i = m->nodeCount - 1; i >= 0; --i)
	{
		fmMeshNode* node = &m->nodes[i];
		if (node->left >= 0)
		{
			const fmMeshNode *l = &m->nodes[node->left], *r = l + 1;
			node->lo = fmMakeVec3(fmMin(l->lo.x, r->lo.x), fmMin(l->lo.y, r->lo.y),
			                      fmMin(l->lo.z, r->lo.z));
			node->hi = fmMakeVec3(fmMax(l->hi.x, r->hi.x), fmMax(l->hi.y, r->hi.y),
			                      fmMax(l->hi.z, r->hi.z));
			continue;
		}
		node->lo = node->hi = fmCorner(m, m->order[node->first], 0);
		for (int k = node->first; k < node->first + node->count; ++k)
			fmGrowBox(m, m->order[k], &node->lo, &node->hi);
	}
}

typedef struct fmCentroidKey
{
	double value;
	int triangle;
} fmCentroidKey;

static int fmCompareCentroids(const void* a, const void* b)
{
	const fmCentroidKey *x = a, *y = b;
	if (x->value != y->value)
		return x->value < y->value ? -1 : 1;
	return (x->triangle > y->triangle) - (x->triangle < y->triangle);
}

static double fmAxisOf(fmVec3 v, int axis)
{
	return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

// Node @p index over order[first, first + count): its box, then a split at the median centroid
// along the longest axis of the centroids' box, until leaves of FM_MESH_LEAF triangles.
static void fmBuildNode(fmMeshShape* m, fmCentroidKey* keys, int index, int first, int count)
{
	fmMeshNode* node = &m->nodes[index];
	fmVec3 lo = fmCorner(m, m->order[first], 0), hi = lo;
	fmVec3 clo = fmMakeVec3(INFINITY, INFINITY, INFINITY), chi = fmScale(-1.0, clo);
	for (int i = first; i < first + count; ++i)
	{
		int t = m->order[i];
		fmGrowBox(m, t, &lo, &hi);
		fmVec3 c = fmAdd(fmAdd(fmCorner(m, t, 0), fmCorner(m, t, 1)), fmCorner(m, t, 2));
		clo = fmMakeVec3(fmMin(clo.x, c.x), fmMin(clo.y, c.y), fmMin(clo.z, c.z));
		chi = fmMakeVec3(fmMax(chi.x, c.x), fmMax(chi.y, c.y), fmMax(chi.z, c.z));
	}
	node->lo = lo;
	node->hi = hi;
	node->left = -1;
	node->first = first;
	node->count = count;
	if (count <= FM_MESH_LEAF)
		return;
	fmVec3 extent = fmSub(chi, clo);
	int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
	for (int i = 0; i < count; ++i)
	{
		int t = m->order[first + i];
		fmVec3 c = fmAdd(fmAdd(fmCorner(m, t, 0), fmCorner(m, t, 1)), fmCorner(m, t, 2));
		keys[i].value = fmAxisOf(c, axis);
		keys[i].triangle = t;
	}
	qsort(keys, (size_t)count, sizeof *keys, fmCompareCentroids);
	for (int i = 0; i < count; ++i)
		m->order[first + i] = keys[i].triangle;
	int half = count / 2, left = m->nodeCount;
	m->nodeCount += 2;
	node->left = left;
	node->count = 0;
	fmBuildNode(m, keys, left, first, half);
	fmBuildNode(m, keys, left + 1, first + half, count - half);
}

size_t fmMeshShape_Bytes(int vertexCount, int triangleCount)
{
	size_t v = (size_t)vertexCount, t = (size_t)triangleCount;
	return sizeof(fmMeshShape) + sizeof(fmVec3) * 2 * v + sizeof(int) * 4 * t +
	       sizeof(fmVec3) * 4 * t + sizeof(fmMeshNode) * 2 * t;
}

fmMeshShape* fmMeshShape_Create(const fmColliderDef* def)
{
	fmMeshShape* m = FM_ALLOC_ZERO(fmMeshShape, 1);
	if (m == NULL)
		return NULL;
	int v = def->vertexCount, t = def->triangleCount;
	m->vertexCount = v;
	m->triangleCount = t;
	m->bytes = fmMeshShape_Bytes(v, t);
	m->vertices = FM_ALLOC_ARRAY(fmVec3, v);
	m->vertexNormal = FM_ALLOC_ZERO(fmVec3, v);
	m->triangles = FM_ALLOC_ARRAY(int, 3 * (size_t)t);
	m->order = FM_ALLOC_ARRAY(int, t);
	m->faceNormal = FM_ALLOC_ARRAY(fmVec3, t);
	m->edgeNormal = FM_ALLOC_ARRAY(fmVec3, 3 * (size_t)t);
	m->nodes = FM_ALLOC_ARRAY(fmMeshNode, 2 * (size_t)t);
	fmCentroidKey* keys = FM_ALLOC_ARRAY(fmCentroidKey, t);
	int* edgeSlots = FM_ALLOC_ARRAY(int, 3 * (size_t)t);
	bool ok = m->vertices && m->vertexNormal && m->triangles && m->order && m->faceNormal &&
	          m->edgeNormal && m->nodes && keys && edgeSlots;
	if (ok)
	{
		memcpy(m->vertices, def->vertices, sizeof(fmVec3) * (size_t)v);
		memcpy(m->triangles, def->triangles, sizeof(int) * 3 * (size_t)t);
		for (int i = 0; i < t; ++i)
			m->order[i] = i;
		ok = fmMeshShape_SortEdges(m, edgeSlots);
	}
	if (ok)
		fmPrepareNormals(m, edgeSlots);
	if (ok)
	{
		m->nodeCount = 1;
		fmBuildNode(m, keys, 0, 0, t);
	}
	FM_FREE_ARRAY(keys, fmCentroidKey, t);
	FM_FREE_ARRAY(edgeSlots, int, 3 * (size_t)t);
	if (!ok)
	{
		fmMeshShape_Destroy(m);
		return NULL;
	}
	return m;
}

void fmMeshShape_Destroy(fmMeshShape* m)
{
	if (m == NULL)
		return;
	int v = m->vertexCount, t = m->triangleCount;
	fmMeshMotion_Release(m);
	FM_FREE_ARRAY(m->vertices, fmVec3, v);
	FM_FREE_ARRAY(m->vertexNormal, fmVec3, v);
	FM_FREE_ARRAY(m->triangles, int, 3 * (size_t)t);
	FM_FREE_ARRAY(m->order, int, t);
	FM_FREE_ARRAY(m->faceNormal, fmVec3, t);
	FM_FREE_ARRAY(m->edgeNormal, fmVec3, 3 * (size_t)t);
	FM_FREE_ARRAY(m->nodes, fmMeshNode, 2 * (size_t)t);
	FM_FREE_ARRAY(m, fmMeshShape, 1);
}

void fmMeshShape_Bounds(const fmMeshShape* m, fmVec3* lo, fmVec3* hi)
{
	*lo = m->nodes[0].lo;
	*hi = m->nodes[0].hi;
}

// ---- queries -----------------------------------------------------------------------------------

// Squared distance from p to the box [lo, hi] (0 inside).
static double fmBoxDistance2(fmVec3 p, fmVec3 lo, fmVec3 hi)
{
	double dx = fmMax(fmMax(lo.x - p.x, p.x - hi.x), 0.0);
	double dy = fmMax(fmMax(lo.y - p.y, p.y - hi.y), 0.0);
	double dz = fmMax(fmMax(lo.z - p.z, p.z - hi.z), 0.0);
	return dx * dx + dy * dy + dz * dz;
}

// The pseudo-normal of the feature of triangle t that weights @p w name: the face, an edge
// (one zero weight: the edge opposite it) or a corner (two zeros).
static fmVec3 fmFeatureNormal(const fmMeshShape* m, int t, const double w[3])
{
	int zeros = (w[0] == 0.0) + (w[1] == 0.0) + (w[2] == 0.0);
	if (zeros == 0)
		return m->faceNormal[t];
	if (zeros == 1)
	{
		int opposite = w[0] == 0.0 ? 0 : w[1] == 0.0 ? 1 : 2;
		return m->edgeNormal[3 * t + (opposite + 1) % 3]; // edge k runs from corner k to k + 1
	}
	int corner = w[0] != 0.0 ? 0 : w[1] != 0.0 ? 1 : 2;
	return m->vertexNormal[m->triangles[3 * t + corner]];
}

double fmMeshShape_Nearest(const fmMeshShape* m, fmVec3 p, int* triangle, double weights[3])
{
	double best = INFINITY;
	int stack[FM_MESH_STACK], depth = 0;
	*triangle = 0;
	weights[0] = 1.0;
	weights[1] = weights[2] = 0.0;
	stack[depth++] = 0;
	while (depth > 0)
	{
		const fmMeshNode* node = &m->nodes[stack[--depth]];
		if (fmBoxDistance2(p, node->lo, node->hi) >= best)
			continue;
		if (node->left < 0)
		{
			for (int i = node->first; i < node->first + node->count; ++i)
			{
				int t = m->order[i];
				fmVec3 a = fmCorner(m, t, 0), b = fmCorner(m, t, 1), c = fmCorner(m, t, 2);
				double w[3];
				fmClosestOnTriangle(p, a, b, c, w);
				fmVec3 q = fmAdd(fmAdd(fmScale(w[0], a), fmScale(w[1], b)), fmScale(w[2], c));
				fmVec3 d = fmSub(p, q);
				double d2 = fmDot(d, d);
				if (d2 < best)
				{
					best = d2;
					*triangle = t;
					memcpy(weights, w, sizeof w);
				}
			}
			continue;
		}
		// The nearer child is searched first (pushed last).
		const fmMeshNode* l = &m->nodes[node->left];
		const fmMeshNode* r = l + 1;
		bool leftFirst = fmBoxDistance2(p, l->lo, l->hi) <= fmBoxDistance2(p, r->lo, r->hi);
		stack[depth++] = leftFirst ? node->left + 1 : node->left;
		stack[depth++] = leftFirst ? node->left : node->left + 1;
	}
	return best;
}

double fmMeshShape_Distance(const fmMeshShape* m, fmVec3 p, fmVec3* normal)
{
	int t;
	double bestW[3];
	double best = fmMeshShape_Nearest(m, p, &t, bestW);
	fmVec3 q =
	    fmAdd(fmAdd(fmScale(bestW[0], fmCorner(m, t, 0)), fmScale(bestW[1], fmCorner(m, t, 1))),
	          fmScale(bestW[2], fmCorner(m, t, 2)));
	fmVec3 pseudo = fmFeatureNormal(m, t, bestW), d = fmSub(p, q);
	double distance = sqrt(best);
	double sign = fmDot(d, pseudo) < 0.0 ? -1.0 : 1.0;
	*normal = distance > 1e-12 * (1.0 + fmLength(q)) ? fmScale(sign / distance, d)
	          : fmDot(pseudo, pseudo) > 0.0          ? pseudo
	                                                 : fmMakeVec3(0.0, 1.0, 0.0);
	return sign * distance;
}

bool fmMeshShape_CastSegment(const fmMeshShape* m, fmVec3 p0, fmVec3 p1, double* fraction,
                             fmVec3* normal)
{
	fmVec3 d = fmSub(p1, p0);
	double best = INFINITY;
	int stack[FM_MESH_STACK], depth = 0;
	stack[depth++] = 0;
	while (depth > 0)
	{
		const fmMeshNode* node = &m->nodes[stack[--depth]];
		if (!fmSegmentHitsBox(p0, d, node->lo, node->hi))
			continue;
		if (node->left >= 0)
		{
			stack[depth++] = node->left + 1;
			stack[depth++] = node->left;
			continue;
		}
		for (int i = node->first; i < node->first + node->count; ++i)
		{
			int t = m->order[i];
			if (!(fmDot(d, m->faceNormal[t]) < 0.0))
				continue; // entering through the front only
			double f =
			    fmSegmentTriangle(p0, d, fmCorner(m, t, 0), fmCorner(m, t, 1), fmCorner(m, t, 2));
			if (f >= 0.0 && f < best)
			{
				best = f;
				*normal = m->faceNormal[t];
			}
		}
	}
	if (!(best <= 1.0))
		return false;
	*fraction = best;
	return true;
}
