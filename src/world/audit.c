// The contact audit (fmWorld_AuditContact): an intersection checker that shares no code with the
// contact stage (src/contact/), so that it can judge it. Three counts:
//  - crossings: a surface edge pq of body A and a surface triangle abc of body B cross properly
//    when p and q lie strictly on opposite sides of abc's plane and pq passes strictly inside
//    abc (the three orientations of pq against abc's edges strictly of one sign): five
//    orientation determinants;
//  - vertices inside: a surface vertex of A is strictly inside B when a ray along +x from it
//    crosses B's surface an odd number of times (symbolic perturbation for the ties) and it is
//    farther than 1e-12 of B's size from B's surface;
//  - inverted tets: det [x1-x0, x2-x0, x3-x0] <= 0 (the sign of det F: the rest shape's is > 0).
// Orientation signs are certified by Shewchuk's static error bound ("Adaptive precision
// floating-point arithmetic and fast robust geometric predicates", 1997, orient3d's errboundA);
// a sign it cannot certify counts as zero, so touching or grazing is never a crossing. Each
// orientation of an edge against a triangle's edge is evaluated in one order of the vertices
// (the lower index first), so two triangles sharing an edge see the same sign.
// Broad phase: a uniform grid over each body's surface triangles (a dense array of cells over
// the body's box, a triangle in every cell its box, slightly enlarged, overlaps), queried by each
// other body's edges and vertices within the body's box; a stamp per triangle visits each once
// per query.
#include "world/audit.h"

#include "contact/collider.h"
#include "core/det_math.h"

#include "body/anchors.h"
#include "body/fracture.h"
#include "core/core.h"
#include "core/fp_env.h"
#include "math/geometry.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Cells per axis at most: 64^3 cells at most per body.
#define FM_AUDIT_MAX_CELLS 64

// A body's surface as the audit sees it: its edges, its surface vertices and a grid.
typedef struct fmAuditBody
{
	const fmBody* body;
	int slot;
	int* edges; // 2 per edge, the lower vertex first, sorted
	int edgeCount;
	int* vertices; // the surface vertices, ascending
	int vertexCount;
	fmVec3 lo, hi;    // the surface's box
	fmVec3 cell;      // m, a cell's size on each axis
	int n[3];         // cells on each axis
	double margin;    // m, added around a triangle's box when it is put in the grid
	int* cellStart;   // n0 n1 n2 + 1: cell c holds cellTris[cellStart[c] .. cellStart[c + 1])
	int* cellTris;    // the triangles of every cell
	int* stamp;       // triangleCount: the last query that visited each triangle
	size_t itemCount; // cellTris's length
} fmAuditBody;

// ---- predicates -------------------------------------------------------------------------------

// The sign of det [a-d, b-d, c-d] (orient3d), or 0 when the double result is within the static
// error bound (7 + 56 eps) eps * permanent, eps = 2^-53, and so cannot be certified.
static int fmAuditOrient(fmVec3 a, fmVec3 b, fmVec3 c, fmVec3 d)
{
	const double eps = 1.1102230246251565e-16;
	double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
	double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
	double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
	double bc = bdx * cdy, cb = cdx * bdy, ca = cdx * ady, ac = adx * cdy, ab = adx * bdy,
	       ba = bdx * ady;
	double det = adz * (bc - cb) + bdz * (ca - ac) + cdz * (ab - ba);
	double permanent = (fabs(bc) + fabs(cb)) * fabs(adz) + (fabs(ca) + fabs(ac)) * fabs(bdz) +
	                   (fabs(ab) + fabs(ba)) * fabs(cdz);
	double bound = (7.0 + 56.0 * eps) * eps * permanent;
	return det > bound ? 1 : det < -bound ? -1 : 0;
}

// orient3d(p, q, u, v) for the triangle edge (u, v) of vertex indices iu, iv, evaluated with the
// lower index first so that both triangles of the edge get the same sign.
static int fmAuditEdgeSign(fmVec3 p, fmVec3 q, const double* x, int iu, int iv)
{
	if (iu < iv)
		return fmAuditOrient(p, q, fmLoad(x, iu), fmLoad(x, iv));
	return -fmAuditOrient(p, q, fmLoad(x, iv), fmLoad(x, iu));
}

// Whether segment pq crosses triangle @p tri (of positions @p x) properly.
static bool fmAuditCrosses(fmVec3 p, fmVec3 q, const double* x, const int* tri)
{
	fmVec3 a = fmLoad(x, tri[0]), b = fmLoad(x, tri[1]), c = fmLoad(x, tri[2]);
	int sp = fmAuditOrient(a, b, c, p), sq = fmAuditOrient(a, b, c, q);
	if (sp == 0 || sp != -sq)
		return false;
	int s0 = fmAuditEdgeSign(p, q, x, tri[0], tri[1]);
	if (s0 == 0)
		return false;
	return fmAuditEdgeSign(p, q, x, tri[1], tri[2]) == s0 &&
	       fmAuditEdgeSign(p, q, x, tri[2], tri[0]) == s0;
}

// The sign of det2 [a-p, b-p] in the (y, z) plane with p moved to (py + e, pz + e^2), e -> 0
// (simulation of simplicity): the double value, else az - bz, else by - ay. Swapping a and b
// negates every term exactly, so the two triangles of an edge see opposite signs.
static int fmAuditSide2(fmVec3 p, fmVec3 a, fmVec3 b)
{
	double f = (a.y - p.y) * (b.z - p.z) - (a.z - p.z) * (b.y - p.y);
	if (f != 0.0)
		return f > 0.0 ? 1 : -1;
	if (a.z != b.z)
		return a.z > b.z ? 1 : -1;
	if (a.y != b.y)
		return b.y > a.y ? 1 : -1;
	return 0;
}

// The ray from p along +x against triangle @p tri: 1 when it crosses it ahead of p, 0 when not,
// -1 when p lies on it (in its plane, within its perturbed projection).
static int fmAuditRayHit(fmVec3 p, const double* x, const int* tri)
{
	fmVec3 a = fmLoad(x, tri[0]), b = fmLoad(x, tri[1]), c = fmLoad(x, tri[2]);
	if (p.y < fmMin(a.y, fmMin(b.y, c.y)) || p.y > fmMax(a.y, fmMax(b.y, c.y)) ||
	    p.z < fmMin(a.z, fmMin(b.z, c.z)) || p.z > fmMax(a.z, fmMax(b.z, c.z)) ||
	    p.x > fmMax(a.x, fmMax(b.x, c.x)))
		return 0;
	int s = fmAuditSide2(p, a, b);
	if (s == 0 || fmAuditSide2(p, b, c) != s || fmAuditSide2(p, c, a) != s)
		return 0;
	// det [a-p, b-p, c-p] = n . (a - p), and sign(n.x) = s: the crossing's x is beyond p's
	// exactly when the two signs agree.
	int d = fmAuditOrient(a, b, c, p);
	return d == 0 ? -1 : d == s ? 1 : 0;
}

// ---- a body's surface and grid ----------------------------------------------------------------

static int fmAuditCompareEdges(const void* a, const void* b)
{
	const int* u = a;
	const int* v = b;
	return u[0] != v[0] ? (u[0] > v[0]) - (u[0] < v[0]) : (u[1] > v[1]) - (u[1] < v[1]);
}

static int fmAuditCompareInts(const void* a, const void* b)
{
	int u = *(const int*)a, v = *(const int*)b;
	return (u > v) - (u < v);
}

// The body's surface edges (each once, the lower vertex first, sorted) and surface vertices
// (each once, ascending).
static bool fmAuditSurface(fmAuditBody* ab)
{
	const fmElasticMesh* m = &ab->body->mesh;
	int t3 = 3 * m->triangleCount;
	ab->edges = FM_ALLOC_ARRAY(int, 2 * (size_t)t3);
	ab->vertices = FM_ALLOC_ARRAY(int, t3);
	ab->edgeCount = ab->vertexCount = 0;
	if (t3 == 0) // no surface (nothing to sort: qsort takes no NULL array)
		return true;
	if (ab->edges == NULL || ab->vertices == NULL)
		return false;
	for (int k = 0; k < t3; ++k)
	{
		int u = m->surface[k], v = m->surface[k % 3 == 2 ? k - 2 : k + 1];
		ab->edges[2 * k] = u < v ? u : v;
		ab->edges[2 * k + 1] = u < v ? v : u;
		ab->vertices[k] = u;
	}
	qsort(ab->edges, (size_t)t3, 2 * sizeof(int), fmAuditCompareEdges);
	qsort(ab->vertices, (size_t)t3, sizeof(int), fmAuditCompareInts);
	for (int k = 0; k < t3; ++k)
	{
		int e = ab->edgeCount;
		if (e == 0 || ab->edges[2 * k] != ab->edges[2 * e - 2] ||
		    ab->edges[2 * k + 1] != ab->edges[2 * e - 1])
		{
			ab->edges[2 * e] = ab->edges[2 * k];
			ab->edges[2 * e + 1] = ab->edges[2 * k + 1];
			ab->edgeCount += 1;
		}
		if (ab->vertexCount == 0 || ab->vertices[k] != ab->vertices[ab->vertexCount - 1])
			ab->vertices[ab->vertexCount++] = ab->vertices[k];
	}
	return true;
}

// The box of triangle @p t, or of the points @p a, @p b.
static void fmAuditTriangleBox(const fmAuditBody* ab, int t, fmVec3* lo, fmVec3* hi)
{
	const double* x = ab->body->state.x;
	const int* tri = ab->body->mesh.surface + 3 * t;
	*lo = *hi = fmLoad(x, tri[0]);
	for (int k = 1; k < 3; ++k)
	{
		fmVec3 p = fmLoad(x, tri[k]);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
}

// The cell of coordinate @p v on axis @p k, clamped into the grid (what lies outside goes to the
// border cells, for the triangles and the queries alike).
static int fmAuditCellOf(const fmAuditBody* ab, int k, double v)
{
	double lo = k == 0 ? ab->lo.x : k == 1 ? ab->lo.y : ab->lo.z;
	double size = k == 0 ? ab->cell.x : k == 1 ? ab->cell.y : ab->cell.z;
	double c = floor((v - lo) / size);
	// (NaN, from a non-finite position, goes to cell 0: never a conversion of NaN to int.)
	return !(c >= 0.0) ? 0 : c >= ab->n[k] ? ab->n[k] - 1 : (int)c;
}

// The cell range [c0, c1] of the box [lo, hi] grown by the grid's margin.
static void fmAuditRange(const fmAuditBody* ab, fmVec3 lo, fmVec3 hi, int c0[3], int c1[3])
{
	double g = ab->margin;
	double l[3] = {lo.x - g, lo.y - g, lo.z - g}, h[3] = {hi.x + g, hi.y + g, hi.z + g};
	for (int k = 0; k < 3; ++k)
	{
		c0[k] = fmAuditCellOf(ab, k, l[k]);
		c1[k] = fmAuditCellOf(ab, k, h[k]);
	}
}

// The grid's shape: the surface's box, cells about the mean triangle's size (at least 1/64 of
// the box's longest side).
static void fmAuditShape(fmAuditBody* ab)
{
	const fmElasticMesh* m = &ab->body->mesh;
	double mean = 0.0;
	for (int t = 0; t < m->triangleCount; ++t)
	{
		fmVec3 lo, hi;
		fmAuditTriangleBox(ab, t, &lo, &hi);
		ab->lo = t == 0 ? lo
		                : fmMakeVec3(fmMin(ab->lo.x, lo.x), fmMin(ab->lo.y, lo.y),
		                             fmMin(ab->lo.z, lo.z));
		ab->hi = t == 0 ? hi
		                : fmMakeVec3(fmMax(ab->hi.x, hi.x), fmMax(ab->hi.y, hi.y),
		                             fmMax(ab->hi.z, hi.z));
		mean += fmMax(hi.x - lo.x, fmMax(hi.y - lo.y, hi.z - lo.z));
	}
	fmVec3 e = fmSub(ab->hi, ab->lo);
	double longest = fmMax(e.x, fmMax(e.y, e.z));
	double size = fmMax(mean / fmMax(m->triangleCount, 1), longest / FM_AUDIT_MAX_CELLS);
	size = size > 0.0 ? size : 1.0;
	double ext[3] = {e.x, e.y, e.z}, cell[3];
	for (int k = 0; k < 3; ++k)
	{
		double n = fmMin(fmMax(floor(ext[k] / size), 1.0), FM_AUDIT_MAX_CELLS);
		ab->n[k] = (int)n;
		cell[k] = ext[k] > 0.0 ? ext[k] / n : size;
	}
	ab->cell = fmMakeVec3(cell[0], cell[1], cell[2]);
	ab->margin = 1e-9 * fmMax(longest, 1e-300) + 1e-6 * size;
}

// Visit the cells of triangle @p t: count its place in each (fill false) or put it there.
static void fmAuditPlace(fmAuditBody* ab, int t, bool fill)
{
	fmVec3 lo, hi;
	fmAuditTriangleBox(ab, t, &lo, &hi);
	int c0[3], c1[3];
	fmAuditRange(ab, lo, hi, c0, c1);
	for (int i = c0[0]; i <= c1[0]; ++i)
		for (int j = c0[1]; j <= c1[1]; ++j)
			for (int k = c0[2]; k <= c1[2]; ++k)
			{
				int c = (i * ab->n[1] + j) * ab->n[2] + k;
				if (fill)
					ab->cellTris[ab->cellStart[c]++] = t;
				else
					ab->cellStart[c + 1] += 1;
			}
}

// The grid of the body's surface triangles (counting sort into the cells).
static bool fmAuditGrid(fmAuditBody* ab)
{
	const fmElasticMesh* m = &ab->body->mesh;
	fmAuditShape(ab);
	int cells = ab->n[0] * ab->n[1] * ab->n[2];
	ab->cellStart = FM_ALLOC_ZERO(int, (size_t)cells + 1);
	ab->stamp = FM_ALLOC_ZERO(int, m->triangleCount);
	if (ab->cellStart == NULL || (ab->stamp == NULL && m->triangleCount > 0))
		return false;
	for (int t = 0; t < m->triangleCount; ++t)
		fmAuditPlace(ab, t, false);
	for (int c = 0; c < cells; ++c)
		ab->cellStart[c + 1] += ab->cellStart[c];
	ab->itemCount = (size_t)ab->cellStart[cells];
	ab->cellTris = FM_ALLOC_ARRAY(int, ab->itemCount);
	if (ab->cellTris == NULL && ab->itemCount > 0)
		return false;
	for (int t = 0; t < m->triangleCount; ++t)
		fmAuditPlace(ab, t, true); // each cell's start moves to the next cell's
	for (int c = cells; c > 0; --c)
		ab->cellStart[c] = ab->cellStart[c - 1];
	ab->cellStart[0] = 0;
	return true;
}

static void fmAuditFree(fmAuditBody* ab)
{
	int t = ab->body->mesh.triangleCount;
	FM_FREE_ARRAY(ab->edges, int, 6 * (size_t)t);
	FM_FREE_ARRAY(ab->vertices, int, 3 * (size_t)t);
	FM_FREE_ARRAY(ab->cellStart, int, (size_t)ab->n[0] * ab->n[1] * ab->n[2] + 1);
	FM_FREE_ARRAY(ab->cellTris, int, ab->itemCount);
	FM_FREE_ARRAY(ab->stamp, int, t);
}

// ---- the audit --------------------------------------------------------------------------------

typedef struct fmAuditRun
{
	const fmWorld* world;
	fmAuditBody* bodies;
	int count;
	int query; // the stamp of the current query
	fmContactAudit* out;
	int focus;      // a slot: only the pairs with that body whose filters meet, no tets; -1: all
	int tetsInside; // with a focus: tets of one body of a pair whose centroid is inside the other
	fmAuditFinding firstTetInside;
} fmAuditRun;

// Whether the boxes [alo, ahi] and [blo, bhi] overlap (closed).
static bool fmAuditBoxesMeet(fmVec3 alo, fmVec3 ahi, fmVec3 blo, fmVec3 bhi)
{
	return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y && alo.z <= bhi.z &&
	       blo.z <= ahi.z;
}

static void fmAuditFind(fmAuditFinding* f, const fmAuditRun* run, const fmAuditBody* a,
                        const fmAuditBody* b, int v0, int v1, int index, double depth)
{
	if (f->body.index1 != 0)
		return;
	f->body = fmWorldBodyId(run->world, a->slot);
	f->otherBody = b != NULL ? fmWorldBodyId(run->world, b->slot) : (fmBodyId){0, 0, 0, 0};
	f->vertex[0] = v0 >= 0 ? a->body->userVertex[v0] : -1;
	f->vertex[1] = v1 >= 0 ? a->body->userVertex[v1] : -1;
	f->index = index;
	f->depth = depth;
}

// Edge @p e of body @p a against the triangles of body @p b (itself: those sharing no vertex
// with the edge).
// Whether a body's own triangle @p tri holds vertex u or v, or a copy of one a tear made (the
// two sides of a crack start on each other).
static bool fmAuditShares(const fmCracks* c, const int* tri, int u, int v)
{
	for (int k = 0; k < 3; ++k)
		if (fmFracture_Siblings(c, tri[k], u) || fmFracture_Siblings(c, tri[k], v))
			return true;
	return false;
}

static void fmAuditEdge(fmAuditRun* run, const fmAuditBody* a, fmAuditBody* b, int e)
{
	const double* xa = a->body->state.x;
	const double* xb = b->body->state.x;
	int u = a->edges[2 * e], v = a->edges[2 * e + 1];
	fmVec3 p = fmLoad(xa, u), q = fmLoad(xa, v);
	fmVec3 lo = fmMakeVec3(fmMin(p.x, q.x), fmMin(p.y, q.y), fmMin(p.z, q.z));
	fmVec3 hi = fmMakeVec3(fmMax(p.x, q.x), fmMax(p.y, q.y), fmMax(p.z, q.z));
	if (!fmAuditBoxesMeet(lo, hi, b->lo, b->hi))
		return;
	bool self = a == b;
	int stamp = ++run->query;
	int c0[3], c1[3];
	fmAuditRange(b, lo, hi, c0, c1);
	for (int i = c0[0]; i <= c1[0]; ++i)
		for (int j = c0[1]; j <= c1[1]; ++j)
			for (int k = c0[2]; k <= c1[2]; ++k)
			{
				int c = (i * b->n[1] + j) * b->n[2] + k;
				for (int s = b->cellStart[c]; s < b->cellStart[c + 1]; ++s)
				{
					int t = b->cellTris[s];
					const int* tri = b->body->mesh.surface + 3 * t;
					if (b->stamp[t] == stamp)
						continue;
					b->stamp[t] = stamp;
					if (self && fmAuditShares(a->body->cracks, tri, u, v))
						continue;
					if (!fmAuditCrosses(p, q, xb, tri))
						continue;
					fmContactAudit* o = run->out;
					*(self ? &o->selfCrossings : &o->crossings) += 1;
					fmAuditFind(self ? &o->firstSelfCrossing : &o->firstCrossing, run, a, b, u, v,
					            t, 0.0);
				}
			}
}

// The distance from @p p to body @p b's surface.
static double fmAuditDistance(const fmAuditBody* b, fmVec3 p)
{
	const double* x = b->body->state.x;
	double best = INFINITY;
	for (int t = 0; t < b->body->mesh.triangleCount; ++t)
	{
		const int* tri = b->body->mesh.surface + 3 * t;
		fmVec3 pa = fmLoad(x, tri[0]), pb = fmLoad(x, tri[1]), pc = fmLoad(x, tri[2]);
		double w[3];
		fmClosestOnTriangle(p, pa, pb, pc, w);
		fmVec3 c = fmAdd(fmAdd(fmScale(w[0], pa), fmScale(w[1], pb)), fmScale(w[2], pc));
		best = fmMin(best, fmLength(fmSub(p, c)));
	}
	return best;
}

// The parity of the ray from @p p along +x against body @p b's surface: 1 odd, 0 even, -1 when
// p lies on a triangle it meets.
static int fmAuditParity(fmAuditRun* run, fmAuditBody* b, fmVec3 p)
{
	int stamp = ++run->query;
	int j = fmAuditCellOf(b, 1, p.y), k = fmAuditCellOf(b, 2, p.z);
	int parity = 0;
	for (int i = fmAuditCellOf(b, 0, p.x); i < b->n[0]; ++i)
	{
		int c = (i * b->n[1] + j) * b->n[2] + k;
		for (int s = b->cellStart[c]; s < b->cellStart[c + 1]; ++s)
		{
			int t = b->cellTris[s];
			if (b->stamp[t] == stamp)
				continue;
			b->stamp[t] = stamp;
			int hit = fmAuditRayHit(p, b->body->state.x, b->body->mesh.surface + 3 * t);
			if (hit < 0)
				return -1;
			parity ^= hit;
		}
	}
	return parity;
}

// How deep point @p p lies inside body @p b (its distance to b's surface), or 0 when it is
// outside or on the surface within round-off of b's size.
static double fmAuditDepthInside(fmAuditRun* run, fmAuditBody* b, fmVec3 p)
{
	if (!fmAuditBoxesMeet(p, p, b->lo, b->hi) || fmAuditParity(run, b, p) != 1)
		return 0.0;
	fmVec3 e = fmSub(b->hi, b->lo);
	double depth = fmAuditDistance(b, p);
	return depth > 1e-12 * fmMax(fmMax(e.x, e.y), fmMax(e.z, 1e-300)) ? depth : 0.0;
}

// Surface vertex @p v of body @p a inside body @p b?
static void fmAuditVertex(fmAuditRun* run, const fmAuditBody* a, fmAuditBody* b, int v)
{
	double depth = fmAuditDepthInside(run, b, fmLoad(a->body->state.x, v));
	if (!(depth > 0.0))
		return;
	fmContactAudit* o = run->out;
	o->verticesInside += 1;
	o->deepest = fmMax(o->deepest, depth);
	fmAuditFind(&o->firstInside, run, a, b, v, -1, -1, depth);
}

// Whether the centroid of tet @p t of body @p a lies inside body @p b: two bodies whose surfaces
// lie on each other (the same box made twice at one place) have no vertex strictly inside the
// other, but their interiors overlap.
static void fmAuditTetInside(fmAuditRun* run, const fmAuditBody* a, fmAuditBody* b, int t)
{
	const int* tet = a->body->mesh.tets + 4 * t;
	const double* x = a->body->state.x;
	fmVec3 p = fmScale(0.25, fmAdd(fmAdd(fmLoad(x, tet[0]), fmLoad(x, tet[1])),
	                               fmAdd(fmLoad(x, tet[2]), fmLoad(x, tet[3]))));
	double depth = fmAuditDepthInside(run, b, p);
	if (!(depth > 0.0))
		return;
	if (run->tetsInside++ == 0)
		run->firstTetInside = (fmAuditFinding){fmWorldBodyId(run->world, a->slot),
		                                       fmWorldBodyId(run->world, b->slot),
		                                       {-1, -1},
		                                       a->body->userTet[t],
		                                       depth};
}

// Body @p a's inverted tets: det [x1-x0, x2-x0, x3-x0] <= 0.
static void fmAuditTets(fmAuditRun* run, const fmAuditBody* a)
{
	const fmElasticMesh* m = &a->body->mesh;
	const double* x = a->body->state.x;
	for (int t = 0; t < m->tetCount; ++t)
	{
		const int* tet = m->tets + 4 * t;
		fmVec3 x0 = fmLoad(x, tet[0]);
		fmVec3 e1 = fmSub(fmLoad(x, tet[1]), x0), e2 = fmSub(fmLoad(x, tet[2]), x0),
		       e3 = fmSub(fmLoad(x, tet[3]), x0);
		if (fmDot(e1, fmCross(e2, e3)) > 0.0)
			continue;
		run->out->invertedTets += 1;
		fmAuditFind(&run->out->firstInverted, run, a, NULL, -1, -1, a->body->userTet[t], 0.0);
	}
}

// Whether the run looks at the pair of @p a and @p b: every pair, or with a focus the pairs of
// the focus and another body whose filters meet.
static bool fmAuditLooksAt(const fmAuditRun* run, const fmAuditBody* a, const fmAuditBody* b)
{
	if (run->focus < 0)
		return true;
	if (a == b)
		return a->slot == run->focus; // the focus's own surface (when it meets itself)
	fmFilter fa = a->body->filter, fb = b->body->filter;
	return a != b && (a->slot == run->focus || b->slot == run->focus) &&
	       (fa.categoryBits & fb.maskBits) != 0 && (fb.categoryBits & fa.maskBits) != 0;
}

// Every ordered pair of bodies whose boxes meet: a's edges against b's triangles and a's
// vertices against b's inside; a's own edges when it collides with itself.
static void fmAuditPairs(fmAuditRun* run)
{
	for (int ia = 0; ia < run->count; ++ia)
	{
		fmAuditBody* a = &run->bodies[ia];
		if (run->focus < 0)
			fmAuditTets(run, a);
		for (int ib = 0; ib < run->count; ++ib)
		{
			fmAuditBody* b = &run->bodies[ib];
			bool self = ia == ib;
			if ((self && !fmFracture_MeetsItself(a->body)) ||
			    !fmAuditBoxesMeet(a->lo, a->hi, b->lo, b->hi) || !fmAuditLooksAt(run, a, b))
				continue;
			for (int e = 0; e < a->edgeCount; ++e)
				fmAuditEdge(run, a, b, e);
			for (int v = 0; !self && v < a->vertexCount; ++v)
				fmAuditVertex(run, a, b, a->vertices[v]);
			for (int t = 0; run->focus >= 0 && !self && t < a->body->mesh.tetCount; ++t)
				fmAuditTetInside(run, a, b, t);
		}
	}
}

// Whether body @p b's positions are finite (a non-finite body has no surface to audit).
static bool fmAuditFinite(const fmBody* b)
{
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
		if (!isfinite(b->state.x[k]))
			return false;
	return true;
}

// The box of body @p b's vertices.
static void fmAuditVertexBox(const fmBody* b, fmVec3* lo, fmVec3* hi)
{
	*lo = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	*hi = fmScale(-1.0, *lo);
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->state.x, i);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
}

// fmAuditVertexBox, found once while no vertex moves (the world's verticesEpoch). Builds with
// assertions check every cached box against its vertices.
static void fmAuditCachedBox(const fmWorld* w, fmBody* b, fmVec3* lo, fmVec3* hi)
{
	if (b->boxEpoch != w->verticesEpoch)
	{
		fmAuditVertexBox(b, &b->boxLower, &b->boxUpper);
		b->boxEpoch = w->verticesEpoch;
	}
#ifndef NDEBUG
	fmVec3 l, h;
	fmAuditVertexBox(b, &l, &h);
	FM_ASSERT(memcmp(&l, &b->boxLower, sizeof l) == 0 && memcmp(&h, &b->boxUpper, sizeof h) == 0);
#endif
	*lo = b->boxLower, *hi = b->boxUpper;
}

// Whether the audit takes the body in @p slot: every live body, or with a focus the focus and
// the bodies whose boxes meet its box and whose filters meet its filters (a new body among
// thousands costs the few near it, not all of them: their boxes are cached).
static bool fmAuditTakes(fmWorld* w, int focus, const fmVec3 focusBox[2], int slot)
{
	fmBody* b = &w->bodies[slot];
	if (!fmBody_IsLive(b))
		return false;
	if (focus < 0 || slot == focus)
		return true;
	if (!fmFiltersMeet(w->bodies[focus].filter, b->filter) ||
	    fmAnchors_Welded(&w->bodies[focus], b))
		return false;
	fmVec3 blo, bhi;
	fmAuditCachedBox(w, b, &blo, &bhi);
	return fmAuditBoxesMeet(focusBox[0], focusBox[1], blo, bhi);
}

static fmResult fmAuditIn(fmWorld* w, fmContactAudit* audit, int focus, int* tetsInside,
                          fmAuditFinding* firstTetInside)
{
	fmAuditRun run = {w, NULL, 0, 0, audit, focus, 0, audit->firstInside};
	fmVec3 focusBox[2] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
	if (focus >= 0)
		fmAuditCachedBox(w, &w->bodies[focus], &focusBox[0], &focusBox[1]);
	int* taken = FM_ALLOC_ARRAY(int, w->bodyCapacity);
	if (taken == NULL && w->bodyCapacity > 0)
		return fm_errOutOfMemory;
	for (int slot = 0; slot < w->bodyCapacity; ++slot)
		if (fmAuditTakes(w, focus, focusBox, slot))
			taken[run.count++] = slot;
	bool finite = true;
	for (int k = 0; k < run.count && finite; ++k)
		finite = fmAuditFinite(&w->bodies[taken[k]]);
	run.bodies = finite ? FM_ALLOC_ZERO(fmAuditBody, run.count) : NULL;
	bool ok = finite && (run.bodies != NULL || run.count == 0);
	for (int k = 0; ok && k < run.count; ++k)
	{
		fmAuditBody* ab = &run.bodies[k];
		ab->body = &w->bodies[taken[k]];
		ab->slot = taken[k];
		ok = fmAuditSurface(ab) && fmAuditGrid(ab);
	}
	FM_FREE_ARRAY(taken, int, w->bodyCapacity);
	if (!finite)
		return fm_errNumerical;
	audit->bodies = run.count;
	if (ok)
		fmAuditPairs(&run);
	if (tetsInside != NULL)
		*tetsInside = run.tetsInside;
	if (firstTetInside != NULL)
		*firstTetInside = run.firstTetInside;
	for (int k = 0; run.bodies != NULL && k < run.count; ++k)
		if (run.bodies[k].body != NULL)
			fmAuditFree(&run.bodies[k]);
	FM_FREE_ARRAY(run.bodies, fmAuditBody, run.count);
	return ok ? fm_ok : fm_errOutOfMemory;
}

// The audit's findings, none yet.
static fmContactAudit fmAuditNothing(void)
{
	fmContactAudit found;
	memset(&found, 0, sizeof found);
	fmAuditFinding none = {{0, 0, 0, 0}, {0, 0, 0, 0}, {-1, -1}, -1, 0.0};
	found.firstCrossing = found.firstSelfCrossing = found.firstInside = found.firstInverted = none;
	return found;
}

fmResult fmAudit_Overlap(fmWorld* w, int slot, fmAuditOverlap* overlap)
{
	fmContactAudit audit = fmAuditNothing();
	fmAuditFinding tet;
	memset(overlap, 0, sizeof *overlap);
	overlap->other = -1;
	fmResult r = fmAuditIn(w, &audit, slot, &overlap->tetsInside, &tet);
	overlap->crossings = audit.crossings;
	overlap->verticesInside = audit.verticesInside;
	overlap->selfCrossings = audit.selfCrossings;
	overlap->firstSelfCrossing = audit.firstSelfCrossing;
	overlap->deepest = fmMax(audit.deepest, tet.depth);
	if (r != fm_ok ||
	    (audit.crossings == 0 && audit.verticesInside == 0 && overlap->tetsInside == 0))
		return r;
	const fmAuditFinding* f = audit.crossings > 0        ? &audit.firstCrossing
	                          : audit.verticesInside > 0 ? &audit.firstInside
	                                                     : &tet;
	fmBodyId other = f->body.index1 == slot + 1 ? f->otherBody : f->body;
	overlap->other = (int)other.index1 - 1;
	return fm_ok;
}

fmResult fmWorld_AuditContact(fmWorldId worldId, fmContactAudit* audit)
{
	fmWorld* w = fmWorldOrAssert(worldId);
	FM_ASSERT(audit != NULL);
	if (w == NULL)
		return fm_errInvalidId;
	if (audit == NULL)
		return fm_errParameter;
	fmContactAudit found = fmAuditNothing();
	fmFpEnv env = fmFpEnv_Enter(w->def.crossPlatformDeterminism);
	fmResult result = fmAuditIn(w, &found, -1, NULL, NULL);
	fmFpEnv_Leave(&env);
	if (result == fm_ok)
		*audit = found;
	return result;
}
