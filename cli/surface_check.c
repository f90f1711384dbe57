// The surface checks before meshing (surface_check.h): coordinates, triangles, edges (closed
// and manifold), and crossings between triangles found through a uniform grid over their boxes.
#include "surface_check.h"

#include "cli.h"

#include <femto/femto.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

// Cells along the grid's longest side at most, and grid entries (a triangle in a cell) at most
// before the crossing test is given up as too costly (it is said so).
#define CLI_CHECK_CELLS 128
#define CLI_CHECK_ENTRIES 50000000

static fmVec3 cliVertex(const cliSurface* s, int v)
{
	return fmMakeVec3(s->x[3 * v], s->x[3 * v + 1], s->x[3 * v + 2]);
}

static bool cliCheckCoordinates(const char* path, const cliSurface* s, fmVec3* lo, fmVec3* hi)
{
	for (int k = 0; k < 3 * s->vertexCount; ++k)
		if (!(fabs(s->x[k]) <= FM_MAX_COORDINATE))
		{
			cliError("%s: vertex %d has coordinate %g: expected finite, |x| <= %g m", path, k / 3,
			         s->x[k], FM_MAX_COORDINATE);
			return false;
		}
	*lo = *hi = cliVertex(s, 0);
	for (int v = 1; v < s->vertexCount; ++v)
	{
		fmVec3 p = cliVertex(s, v);
		*lo = fmMakeVec3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
		*hi = fmMakeVec3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
	}
	fmVec3 e = fmSub(*hi, *lo);
	if (e.x > 0.0 && e.y > 0.0 && e.z > 0.0)
		return true;
	cliError("%s: the surface is flat (its box is %g x %g x %g m): it encloses no volume", path,
	         e.x, e.y, e.z);
	return false;
}

static bool cliCheckTriangles(const char* path, const cliSurface* s, double extent)
{
	int bad = 0, first = -1;
	for (int t = 0; t < s->triangleCount; ++t)
	{
		const int* v = s->triangles + 3 * t;
		fmVec3 a = cliVertex(s, v[0]);
		double area =
		    0.5 * fmLength(fmCross(fmSub(cliVertex(s, v[1]), a), fmSub(cliVertex(s, v[2]), a)));
		if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(area > 1e-12 * extent * extent))
			first = bad++ == 0 ? t : first;
	}
	if (bad == 0)
		return true;
	const int* v = s->triangles + 3 * first;
	cliError("%s: %d triangles have no area (the first: triangle %d, vertices %d %d %d): remove "
	         "them or merge their vertices",
	         path, bad, first, v[0], v[1], v[2]);
	return false;
}

typedef struct cliEdge
{
	int a, b; // the vertices, a < b
	int triangle;
} cliEdge;

static int cliCompareEdges(const void* x, const void* y)
{
	const cliEdge* e = x;
	const cliEdge* f = y;
	if (e->a != f->a)
		return e->a < f->a ? -1 : 1;
	if (e->b != f->b)
		return e->b < f->b ? -1 : 1;
	return (e->triangle > f->triangle) - (e->triangle < f->triangle);
}

// Every edge in exactly two triangles: a closed, manifold surface.
static bool cliCheckEdges(const char* path, const cliSurface* s)
{
	size_t count = 3 * (size_t)s->triangleCount;
	cliEdge* edges = malloc(sizeof *edges * count);
	if (edges == NULL)
	{
		cliError("%s: out of memory for %zu edges", path, count);
		return false;
	}
	for (int t = 0; t < s->triangleCount; ++t)
		for (int k = 0; k < 3; ++k)
		{
			int u = s->triangles[3 * t + k], w = s->triangles[3 * t + (k + 1) % 3];
			edges[3 * (size_t)t + (size_t)k] = (cliEdge){u < w ? u : w, u < w ? w : u, t};
		}
	qsort(edges, count, sizeof *edges, cliCompareEdges);
	int open = 0, crowded = 0;
	cliEdge firstOpen = {0, 0, 0}, firstCrowded = {0, 0, 0};
	for (size_t i = 0, j; i < count; i = j)
	{
		for (j = i + 1; j < count && edges[j].a == edges[i].a && edges[j].b == edges[i].b; ++j)
			;
		if (j - i == 1 && open++ == 0)
			firstOpen = edges[i];
		if (j - i > 2 && crowded++ == 0)
			firstCrowded = edges[i];
	}
	free(edges);
	if (open > 0)
		cliError("%s: the surface is not closed: %d edges belong to one triangle only (the "
		         "first: vertices %d-%d, of triangle %d); TetGen and Gmsh mesh the inside of a "
		         "closed surface: close its holes",
		         path, open, firstOpen.a, firstOpen.b, firstOpen.triangle);
	else if (crowded > 0)
		cliError("%s: the surface is not a manifold: %d edges belong to more than two triangles "
		         "(the first: vertices %d-%d); split it into closed surfaces that do not touch",
		         path, crowded, firstCrowded.a, firstCrowded.b);
	return open == 0 && crowded == 0;
}

// ---- crossings ----------------------------------------------------------------------------------

static double cliOrient(fmVec3 a, fmVec3 b, fmVec3 c, fmVec3 d)
{
	return fmDot(fmCross(fmSub(b, a), fmSub(c, a)), fmSub(d, a));
}

// Whether segment pq passes through the inside of triangle abc (strictly: touching is not).
static bool cliSegmentCrosses(fmVec3 p, fmVec3 q, fmVec3 a, fmVec3 b, fmVec3 c)
{
	double sp = cliOrient(a, b, c, p), sq = cliOrient(a, b, c, q);
	if (!((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)))
		return false;
	double u = cliOrient(p, q, a, b), v = cliOrient(p, q, b, c), w = cliOrient(p, q, c, a);
	return (u > 0.0 && v > 0.0 && w > 0.0) || (u < 0.0 && v < 0.0 && w < 0.0);
}

// Whether triangles @p t and @p u, which share no vertex, cross: an edge of one through the other.
static bool cliTrianglesCross(const cliSurface* s, int t, int u)
{
	const int* a = s->triangles + 3 * t;
	const int* b = s->triangles + 3 * u;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			if (a[i] == b[j])
				return false;
	for (int pass = 0; pass < 2; ++pass, a = s->triangles + 3 * u, b = s->triangles + 3 * t)
		for (int k = 0; k < 3; ++k)
			if (cliSegmentCrosses(cliVertex(s, a[k]), cliVertex(s, a[(k + 1) % 3]),
			                      cliVertex(s, b[0]), cliVertex(s, b[1]), cliVertex(s, b[2])))
				return true;
	return false;
}

typedef struct cliGrid
{
	fmVec3 lo;
	double h[3];
	int n[3];
} cliGrid;

typedef struct cliEntry
{
	int64_t cell;
	int triangle;
} cliEntry;

static int cliCompareEntries(const void* x, const void* y)
{
	const cliEntry* e = x;
	const cliEntry* f = y;
	if (e->cell != f->cell)
		return e->cell < f->cell ? -1 : 1;
	return (e->triangle > f->triangle) - (e->triangle < f->triangle);
}

// The cells [c0, c1] of triangle @p t's box.
static void cliTriangleCells(const cliSurface* s, const cliGrid* g, int t, int c0[3], int c1[3])
{
	fmVec3 p[3];
	for (int k = 0; k < 3; ++k)
		p[k] = cliVertex(s, s->triangles[3 * t + k]);
	double lo[3] = {fmin(p[0].x, fmin(p[1].x, p[2].x)), fmin(p[0].y, fmin(p[1].y, p[2].y)),
	                fmin(p[0].z, fmin(p[1].z, p[2].z))};
	double hi[3] = {fmax(p[0].x, fmax(p[1].x, p[2].x)), fmax(p[0].y, fmax(p[1].y, p[2].y)),
	                fmax(p[0].z, fmax(p[1].z, p[2].z))};
	double o[3] = {g->lo.x, g->lo.y, g->lo.z};
	for (int a = 0; a < 3; ++a)
	{
		c0[a] = (int)fmin(fmax(floor((lo[a] - o[a]) / g->h[a]), 0.0), g->n[a] - 1);
		c1[a] = (int)fmin(fmax(floor((hi[a] - o[a]) / g->h[a]), 0.0), g->n[a] - 1);
	}
}

static int64_t cliCellKey(const cliGrid* g, int i, int j, int k)
{
	return ((int64_t)k * g->n[1] + j) * g->n[0] + i;
}

static cliGrid cliMakeGrid(const cliSurface* s, fmVec3 lo, fmVec3 hi)
{
	double size = 0.0;
	for (int t = 0; t < s->triangleCount; ++t)
	{
		fmVec3 a = cliVertex(s, s->triangles[3 * t]);
		size += fmLength(fmSub(cliVertex(s, s->triangles[3 * t + 1]), a)) +
		        fmLength(fmSub(cliVertex(s, s->triangles[3 * t + 2]), a));
	}
	size = size / s->triangleCount; // about twice a triangle's side: a cell holds a few
	fmVec3 e = fmSub(hi, lo);
	double ext[3] = {e.x, e.y, e.z};
	cliGrid g = {lo, {0, 0, 0}, {1, 1, 1}};
	for (int a = 0; a < 3; ++a)
	{
		g.n[a] = (int)fmin(fmax(ceil(ext[a] / size), 1.0), CLI_CHECK_CELLS);
		g.h[a] = ext[a] / g.n[a];
	}
	return g;
}

// Whether the pair (t, u) is tested in cell @p cell: the lowest cell their boxes share.
static bool cliFirstSharedCell(const cliSurface* s, const cliGrid* g, int t, int u, int64_t cell)
{
	int a0[3], a1[3], b0[3], b1[3];
	cliTriangleCells(s, g, t, a0, a1);
	cliTriangleCells(s, g, u, b0, b1);
	int lo[3];
	for (int a = 0; a < 3; ++a)
		lo[a] = a0[a] > b0[a] ? a0[a] : b0[a];
	return cliCellKey(g, lo[0], lo[1], lo[2]) == cell;
}

static cliEntry* cliFillGrid(const cliSurface* s, const cliGrid* g, size_t* count)
{
	size_t n = 0;
	for (int t = 0; t < s->triangleCount; ++t)
	{
		int c0[3], c1[3];
		cliTriangleCells(s, g, t, c0, c1);
		n +=
		    (size_t)(c1[0] - c0[0] + 1) * (size_t)(c1[1] - c0[1] + 1) * (size_t)(c1[2] - c0[2] + 1);
	}
	*count = n;
	cliEntry* entries = n <= CLI_CHECK_ENTRIES ? malloc(sizeof *entries * (n > 0 ? n : 1)) : NULL;
	for (int t = 0, e = 0; entries != NULL && t < s->triangleCount; ++t)
	{
		int c0[3], c1[3];
		cliTriangleCells(s, g, t, c0, c1);
		for (int k = c0[2]; k <= c1[2]; ++k)
			for (int j = c0[1]; j <= c1[1]; ++j)
				for (int i = c0[0]; i <= c1[0]; ++i)
					entries[e++] = (cliEntry){cliCellKey(g, i, j, k), t};
	}
	if (entries != NULL)
		qsort(entries, n, sizeof *entries, cliCompareEntries);
	return entries;
}

static bool cliCheckCrossings(const char* path, const cliSurface* s, fmVec3 lo, fmVec3 hi)
{
	cliGrid g = cliMakeGrid(s, lo, hi);
	size_t count;
	cliEntry* entries = cliFillGrid(s, &g, &count);
	if (entries == NULL)
	{
		cliWarn("%s: the self-intersection check was skipped (%zu grid entries)", path, count);
		return true;
	}
	int crossings = 0, first[2] = {-1, -1};
	for (size_t i = 0, j; i < count; i = j)
	{
		for (j = i + 1; j < count && entries[j].cell == entries[i].cell; ++j)
			;
		for (size_t x = i; x < j; ++x)
			for (size_t y = x + 1; y < j; ++y)
			{
				int t = entries[x].triangle, u = entries[y].triangle;
				if (!cliFirstSharedCell(s, &g, t, u, entries[i].cell) ||
				    !cliTrianglesCross(s, t, u))
					continue;
				if (crossings++ == 0)
					first[0] = t, first[1] = u;
			}
	}
	free(entries);
	if (crossings == 0)
		return true;
	fmVec3 at = cliVertex(s, s->triangles[3 * first[0]]);
	cliError("%s: the surface intersects itself: %d pairs of triangles cross (the first: "
	         "triangles %d and %d, near (%g, %g, %g)); TetGen and Gmsh need a surface that does "
	         "not: mend it (MeshLab, or Blender's 3D-Print toolbox)",
	         path, crossings, first[0], first[1], at.x, at.y, at.z);
	return false;
}

bool cliSurface_Check(const char* path, const cliSurface* s)
{
	fmVec3 lo, hi;
	if (!cliCheckCoordinates(path, s, &lo, &hi))
		return false;
	fmVec3 e = fmSub(hi, lo);
	double extent = fmax(e.x, fmax(e.y, e.z));
	return cliCheckTriangles(path, s, extent) && cliCheckEdges(path, s) &&
	       cliCheckCrossings(path, s, lo, hi);
}
