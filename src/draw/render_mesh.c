// Render meshes: a triangle surface of any resolution carried by a body. Each render vertex is
// bound once, at its rest position, to one tet (the one containing it, or the nearest one for a
// vertex just outside) by its barycentric coordinates w; afterwards its position is the same
// affine combination of the tet's four deformed nodes, x = sum_i w_i x_i. A vertex outside its
// tet has a negative coordinate and follows the tet's affine map extrapolated, so rigid motions
// are reproduced exactly and smooth deformations to first order everywhere.
//
// The embedding looks tets up in a uniform grid over their rest bounding boxes (each tet listed
// in every cell its box overlaps), so binding n vertices to m tets costs about n + m, not n m.
#include "draw/render_mesh.h"

#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"
#include "world/world.h"

#include <math.h>
#include <string.h>

typedef struct fmRenderMesh
{
	int vertexCount;
	int triangleCount;
	int* tet;          // vertexCount: the body's (internal) tet each vertex is bound to
	double* weight;    // 4 per vertex: barycentric coordinates in that tet (sum 1)
	int* triangles;    // 3 per triangle, 0-based, the caller's winding
	double* positions; // 3 per vertex: the last deformed positions (scratch of the copy calls)
	double* normals;   // 3 per vertex: their smooth normals
} fmRenderMesh;

// Release a render mesh; NULL is fine.
static void fmRenderMesh_Free(fmRenderMesh* mesh)
{
	if (mesh == NULL)
		return;
	size_t n = (size_t)mesh->vertexCount;
	FM_FREE_ARRAY(mesh->tet, int, n);
	FM_FREE_ARRAY(mesh->weight, double, 4 * n);
	FM_FREE_ARRAY(mesh->triangles, int, 3 * (size_t)mesh->triangleCount);
	FM_FREE_ARRAY(mesh->positions, double, 3 * n);
	FM_FREE_ARRAY(mesh->normals, double, 3 * n);
	fmDealloc(mesh, sizeof *mesh);
}

static void fmReleaseRenderMesh(void* mesh)
{
	fmRenderMesh_Free(mesh);
}

static const fmRenderMesh* fmBodyRenderMesh(const fmBody* b)
{
	return b->renderMesh.data;
}

// ---- the grid over the tets ---------------------------------------------------------------

// Most cells the grid has per tet: enough that a cell holds a few tets, few enough that an empty
// grid costs little memory.
#define FM_RENDER_CELLS_PER_TET 2.0

typedef struct fmTetGrid
{
	fmVec3 lo;    // m, the rest shape's bounding box corner
	double h;     // m, the cell size
	int n[3];     // cells along each axis
	int* start;   // cellCount + 1: the tets of cell c are list[start[c] .. start[c + 1])
	int* list;    // tets, listed once per cell their box overlaps
	size_t count; // entries in list
} fmTetGrid;

static void fmTetBounds(const fmBody* b, int t, fmVec3* lo, fmVec3* hi)
{
	*lo = *hi = fmLoad(b->mesh.x0, b->mesh.tets[4 * t]);
	for (int k = 1; k < 4; ++k)
	{
		fmVec3 p = fmLoad(b->mesh.x0, b->mesh.tets[4 * t + k]);
		*lo = fmMakeVec3(fmMin(lo->x, p.x), fmMin(lo->y, p.y), fmMin(lo->z, p.z));
		*hi = fmMakeVec3(fmMax(hi->x, p.x), fmMax(hi->y, p.y), fmMax(hi->z, p.z));
	}
}

// The cell of coordinate @p x along @p axis, clamped into the grid.
static int fmGridCell(const fmTetGrid* g, double x, double origin, int axis)
{
	double c = floor((x - origin) / g->h);
	if (!(c >= 0.0))
		return 0;
	return c >= g->n[axis] ? g->n[axis] - 1 : (int)c;
}

// Whether @p p lies in the grid's box.
static bool fmGridContains(const fmTetGrid* g, fmVec3 p)
{
	fmVec3 hi = fmAdd(g->lo, fmMakeVec3(g->n[0] * g->h, g->n[1] * g->h, g->n[2] * g->h));
	return p.x >= g->lo.x && p.y >= g->lo.y && p.z >= g->lo.z && p.x <= hi.x && p.y <= hi.y &&
	       p.z <= hi.z;
}

static void fmCellRange(const fmTetGrid* g, fmVec3 lo, fmVec3 hi, int a[3], int z[3])
{
	double l[3] = {lo.x, lo.y, lo.z}, u[3] = {hi.x, hi.y, hi.z}, o[3] = {g->lo.x, g->lo.y, g->lo.z};
	for (int k = 0; k < 3; ++k)
	{
		a[k] = fmGridCell(g, l[k], o[k], k);
		z[k] = fmGridCell(g, u[k], o[k], k);
	}
}

static void fmTetGrid_Free(fmTetGrid* g)
{
	size_t cells = (size_t)g->n[0] * (size_t)g->n[1] * (size_t)g->n[2];
	FM_FREE_ARRAY(g->start, int, cells + 1);
	FM_FREE_ARRAY(g->list, int, g->count);
}

// Fill the grid (two passes: count, then list). fm_errOutOfMemory or fm_errLimit (more than
// INT_MAX entries: tets far longer than the cells) on failure.
static fmResult fmTetGrid_Build(fmTetGrid* g, const fmBody* b)
{
	memset(g, 0, sizeof *g);
	fmVec3 lo, hi;
	fmTetBounds(b, 0, &lo, &hi);
	for (int t = 1; t < b->mesh.tetCount; ++t)
	{
		fmVec3 l, u;
		fmTetBounds(b, t, &l, &u);
		lo = fmMakeVec3(fmMin(lo.x, l.x), fmMin(lo.y, l.y), fmMin(lo.z, l.z));
		hi = fmMakeVec3(fmMax(hi.x, u.x), fmMax(hi.y, u.y), fmMax(hi.z, u.z));
	}
	fmVec3 size = fmSub(hi, lo);
	double extent = fmMax(size.x, fmMax(size.y, size.z));
	// Cells of about a tet's size: the box's volume shared among the tets (a flat box counts
	// its longest side squared so the cell size stays positive).
	double volume =
	    fmMax(size.x, 1e-3 * extent) * fmMax(size.y, 1e-3 * extent) * fmMax(size.z, 1e-3 * extent);
	// (No cbrt, whose last bits differ between C libraries: halving finds the cell size
	// within a factor of 2, all the grid needs.)
	double target = volume / (FM_RENDER_CELLS_PER_TET * b->mesh.tetCount);
	g->h = fmMax(extent, 1e-300);
	while (g->h * g->h * g->h > target && g->h > 1e-150)
		g->h *= 0.5;
	double ext[3] = {size.x, size.y, size.z};
	for (;;)
	{
		double cells = 1.0;
		for (int k = 0; k < 3; ++k)
		{
			g->n[k] = (int)fmMin(fmMax(ceil(ext[k] / g->h), 1.0), 4096.0);
			cells *= g->n[k];
		}
		if (cells <= FM_RENDER_CELLS_PER_TET * b->mesh.tetCount + 8.0)
			break;
		g->h *= 1.25;
	}
	g->lo = lo;
	size_t cellCount = (size_t)g->n[0] * (size_t)g->n[1] * (size_t)g->n[2];
	g->start = FM_ALLOC_ZERO(int, cellCount + 1);
	if (g->start == NULL)
		return fm_errOutOfMemory;
	size_t total = 0;
	for (int pass = 0; pass < 2; ++pass)
	{
		for (int t = 0; t < b->mesh.tetCount; ++t)
		{
			fmVec3 l, u;
			int a[3], z[3];
			fmTetBounds(b, t, &l, &u);
			fmCellRange(g, l, u, a, z);
			for (int k = a[2]; k <= z[2]; ++k)
				for (int j = a[1]; j <= z[1]; ++j)
					for (int i = a[0]; i <= z[0]; ++i)
					{
						size_t c = ((size_t)k * g->n[1] + (size_t)j) * g->n[0] + (size_t)i;
						if (pass == 0)
							g->start[c + 1] += 1, total += 1;
						else
							g->list[g->start[c]++] = t;
					}
		}
		if (pass == 0)
		{
			if (total > INT32_MAX)
				return fm_errLimit;
			for (size_t c = 0; c < cellCount; ++c)
				g->start[c + 1] += g->start[c];
			g->count = total;
			g->list = FM_ALLOC_ARRAY(int, total);
			if (g->list == NULL)
				return fm_errOutOfMemory;
		}
	}
	// The fill pass advanced each start to its cell's end: shift back.
	for (size_t c = cellCount; c > 0; --c)
		g->start[c] = g->start[c - 1];
	g->start[0] = 0;
	return fm_ok;
}

// ---- binding a vertex ---------------------------------------------------------------------

// Barycentric coordinates of @p p in rest tet @p t: (w1, w2, w3) = Dm^-1 (p - X0), with the rest
// positions' own Dm^-1 (a plastic body's DmInv also holds its plastic part).
static void fmBarycentric(const fmBody* b, int t, fmVec3 p, double w[4])
{
	const fmMat3* DmInv = b->mesh.restDmInv != NULL ? &b->mesh.restDmInv[t] : &b->mesh.DmInv[t];
	fmVec3 r = fmMatVec(DmInv, fmSub(p, fmLoad(b->mesh.x0, b->mesh.tets[4 * t])));
	w[1] = r.x;
	w[2] = r.y;
	w[3] = r.z;
	w[0] = 1.0 - r.x - r.y - r.z;
}

// How far @p p lies outside tet @p t (0 inside): its distance to the point whose coordinates are
// w with the negative ones set to 0 and the rest rescaled to sum 1. That point lies on the face
// or edge facing p; the distance is the true one for a point beyond a face and close to it
// otherwise, which is all the choice of the nearest tet needs.
static double fmOutsideDistance(const fmBody* b, int t, fmVec3 p, const double w[4])
{
	double sum = 0.0, c[4];
	bool inside = true;
	for (int k = 0; k < 4; ++k)
	{
		c[k] = fmMax(w[k], 0.0);
		sum += c[k];
		inside = inside && w[k] >= 0.0;
	}
	if (inside)
		return 0.0;
	fmVec3 q = fmMakeVec3(0, 0, 0);
	for (int k = 0; k < 4; ++k)
		q = fmMulAdd(q, c[k] / sum, fmLoad(b->mesh.x0, b->mesh.tets[4 * t + k]));
	return fmLength(fmSub(p, q));
}

typedef struct fmBinding
{
	int tet;
	double w[4];
	double distance; // m outside the tet, 0 inside
} fmBinding;

// Test the tets of cell (i, j, k) against the best binding so far. True when p lies inside one.
static bool fmTestCell(const fmBody* b, const fmTetGrid* g, int i, int j, int k, fmVec3 p,
                       fmBinding* best)
{
	size_t c = ((size_t)k * g->n[1] + (size_t)j) * g->n[0] + (size_t)i;
	for (int e = g->start[c]; e < g->start[c + 1]; ++e)
	{
		int t = g->list[e];
		double w[4];
		fmBarycentric(b, t, p, w);
		double d = fmOutsideDistance(b, t, p, w);
		if (best->tet < 0 || d < best->distance)
		{
			best->tet = t;
			best->distance = d;
			memcpy(best->w, w, sizeof w);
			if (d == 0.0)
				return true;
		}
	}
	return false;
}

// The cells of ring @p r around cell @p c (Chebyshev distance r) that lie in the grid, each
// tested; true when p lies inside a tet. Only the ring's cells are visited: its two faces in k,
// then in j, then the two columns in i between them (a cube's shell, not the whole cube).
static bool fmTestRing(const fmBody* b, const fmTetGrid* g, const int c[3], int r, fmVec3 p,
                       fmBinding* best)
{
	int lo[3], hi[3];
	for (int a = 0; a < 3; ++a)
	{
		lo[a] = c[a] - r < 0 ? 0 : c[a] - r;
		hi[a] = c[a] + r >= g->n[a] ? g->n[a] - 1 : c[a] + r;
	}
	for (int k = lo[2]; k <= hi[2]; ++k)
	{
		bool kFace = k == c[2] - r || k == c[2] + r;
		for (int j = lo[1]; j <= hi[1]; ++j)
		{
			bool face = kFace || j == c[1] - r || j == c[1] + r;
			for (int i = lo[0]; i <= hi[0]; i = face || i >= c[0] + r ? i + 1 : c[0] + r)
			{
				if (!face && i != c[0] - r && i != c[0] + r)
					continue;
				if (fmTestCell(b, g, i, j, k, p, best))
					return true;
			}
		}
	}
	return false;
}

// The tet of @p p: cells in rings of growing Chebyshev radius around p's (clamped) cell, until
// p is inside a tet or the next ring lies farther than the nearest tet found.
static fmBinding fmBindVertex(const fmBody* b, const fmTetGrid* g, fmVec3 p)
{
	fmBinding best = {-1, {0, 0, 0, 0}, 0.0};
	int c[3];
	c[0] = fmGridCell(g, p.x, g->lo.x, 0);
	c[1] = fmGridCell(g, p.y, g->lo.y, 1);
	c[2] = fmGridCell(g, p.z, g->lo.z, 2);
	int maxRing = g->n[0] > g->n[1] ? g->n[0] : g->n[1];
	maxRing = maxRing > g->n[2] ? maxRing : g->n[2];
	// How far p lies outside the grid: rings are counted from its clamped cell.
	fmVec3 hi = fmAdd(g->lo, fmMakeVec3(g->n[0] * g->h, g->n[1] * g->h, g->n[2] * g->h));
	fmVec3 clamped = fmMakeVec3(fmMin(fmMax(p.x, g->lo.x), hi.x), fmMin(fmMax(p.y, g->lo.y), hi.y),
	                            fmMin(fmMax(p.z, g->lo.z), hi.z));
	double away = fmLength(fmSub(p, clamped));
	for (int r = 0; r <= maxRing; ++r)
	{
		// Every cell of ring r + 1 and beyond is at least r - 1 cells from p's clamped cell,
		// and p is `away` outside the grid's box: since the clamp is the projection onto a
		// convex box, |p - q|^2 >= away^2 + |clamp - q|^2 for every q in it.
		double reach = fmMax(0.0, (r - 1) * g->h);
		if (best.tet >= 0 && best.distance * best.distance <= away * away + reach * reach)
			break;
		if (fmTestRing(b, g, c, r, p, &best))
			return best;
	}
	return best;
}

// ---- a tree over the tets, for vertices outside the grid's box ------------------------------
// A vertex far outside the body would have the grid's rings sweep every cell (its nearest tet is
// as far as the body is); the tree's boxes prune all but the nearest branches.

#define FM_TREE_LEAF 4

typedef struct fmTetNode
{
	fmVec3 lo, hi;    // the box of the node's tets
	int left;         // inner: the first child (the second is left + 1); leaf: -1
	int first, count; // leaf: tets order[first .. first + count)
} fmTetNode;

typedef struct fmTetTree
{
	fmTetNode* nodes;
	int nodeCount;
	int* order;
	fmVec3* centre; // per tet, its rest centroid
} fmTetTree;

static double fmAxis(fmVec3 v, int axis)
{
	return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

// Put the tets of order[first, first + count) whose centre along @p axis is below the k-th
// smallest before it (quickselect; k counted from first).
static void fmTreeSelect(fmTetTree* t, int first, int count, int k, int axis)
{
	int lo = first, hi = first + count - 1, target = first + k;
	while (lo < hi)
	{
		double pivot = fmAxis(t->centre[t->order[(lo + hi) / 2]], axis);
		int i = lo, j = hi;
		while (i <= j)
		{
			while (fmAxis(t->centre[t->order[i]], axis) < pivot)
				++i;
			while (fmAxis(t->centre[t->order[j]], axis) > pivot)
				--j;
			if (i <= j)
			{
				int swap = t->order[i];
				t->order[i++] = t->order[j];
				t->order[j--] = swap;
			}
		}
		if (target <= j)
			hi = j;
		else if (target >= i)
			lo = i;
		else
			return;
	}
}

static void fmTreeBuild(fmTetTree* t, const fmBody* b, int node, int first, int count)
{
	fmTetNode* n = &t->nodes[node];
	fmVec3 clo = t->centre[t->order[first]], chi = clo;
	for (int k = 0; k < count; ++k)
	{
		fmVec3 lo, hi, c = t->centre[t->order[first + k]];
		fmTetBounds(b, t->order[first + k], &lo, &hi);
		n->lo = k == 0
		            ? lo
		            : fmMakeVec3(fmMin(n->lo.x, lo.x), fmMin(n->lo.y, lo.y), fmMin(n->lo.z, lo.z));
		n->hi = k == 0
		            ? hi
		            : fmMakeVec3(fmMax(n->hi.x, hi.x), fmMax(n->hi.y, hi.y), fmMax(n->hi.z, hi.z));
		clo = fmMakeVec3(fmMin(clo.x, c.x), fmMin(clo.y, c.y), fmMin(clo.z, c.z));
		chi = fmMakeVec3(fmMax(chi.x, c.x), fmMax(chi.y, c.y), fmMax(chi.z, c.z));
	}
	n->first = first;
	n->count = count;
	n->left = -1;
	if (count <= FM_TREE_LEAF)
		return;
	fmVec3 e = fmSub(chi, clo);
	int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
	int half = count / 2;
	fmTreeSelect(t, first, count, half, axis);
	n->left = t->nodeCount;
	t->nodeCount += 2;
	fmTreeBuild(t, b, n->left, first, half);
	fmTreeBuild(t, b, n->left + 1, first + half, count - half);
}

static void fmTetTree_Free(fmTetTree* t, int tetCount)
{
	FM_FREE_ARRAY(t->nodes, fmTetNode, 2 * (size_t)tetCount);
	FM_FREE_ARRAY(t->order, int, tetCount);
	FM_FREE_ARRAY(t->centre, fmVec3, tetCount);
}

static fmResult fmTetTree_Build(fmTetTree* t, const fmBody* b)
{
	int n = b->mesh.tetCount;
	t->nodes = FM_ALLOC_ARRAY(fmTetNode, 2 * (size_t)n);
	t->order = FM_ALLOC_ARRAY(int, n);
	t->centre = FM_ALLOC_ARRAY(fmVec3, n);
	t->nodeCount = 1;
	if (t->nodes == NULL || t->order == NULL || t->centre == NULL)
		return fm_errOutOfMemory;
	for (int k = 0; k < n; ++k)
	{
		const int* tet = b->mesh.tets + 4 * k;
		t->order[k] = k;
		t->centre[k] =
		    fmScale(0.25, fmAdd(fmAdd(fmLoad(b->mesh.x0, tet[0]), fmLoad(b->mesh.x0, tet[1])),
		                        fmAdd(fmLoad(b->mesh.x0, tet[2]), fmLoad(b->mesh.x0, tet[3]))));
	}
	fmTreeBuild(t, b, 0, 0, n);
	return fm_ok;
}

// Squared distance from @p p to the box [lo, hi] (0 inside).
static double fmBoxDistance2(fmVec3 p, fmVec3 lo, fmVec3 hi)
{
	fmVec3 q = fmMakeVec3(fmMin(fmMax(p.x, lo.x), hi.x), fmMin(fmMax(p.y, lo.y), hi.y),
	                      fmMin(fmMax(p.z, lo.z), hi.z));
	return fmDot(fmSub(p, q), fmSub(p, q));
}

// The nearest tet to @p p by the tree: branches whose box lies farther than the best found are
// skipped (a tet's outside distance is at least its box's), the nearer child first.
static fmBinding fmBindByTree(const fmBody* b, const fmTetTree* t, fmVec3 p)
{
	fmBinding best = {-1, {0, 0, 0, 0}, INFINITY};
	int stack[128], top = 0;
	stack[top++] = 0;
	while (top > 0)
	{
		const fmTetNode* n = &t->nodes[stack[--top]];
		if (fmBoxDistance2(p, n->lo, n->hi) >= best.distance * best.distance)
			continue;
		if (n->left < 0)
		{
			for (int k = 0; k < n->count; ++k)
			{
				int tet = t->order[n->first + k];
				double w[4];
				fmBarycentric(b, tet, p, w);
				double d = fmOutsideDistance(b, tet, p, w);
				if (d < best.distance)
					best = (fmBinding){tet, {w[0], w[1], w[2], w[3]}, d};
			}
			continue;
		}
		const fmTetNode* l = &t->nodes[n->left];
		const fmTetNode* r = &t->nodes[n->left + 1];
		bool leftNearer = fmBoxDistance2(p, l->lo, l->hi) <= fmBoxDistance2(p, r->lo, r->hi);
		stack[top++] = leftNearer ? n->left + 1 : n->left; // the farther, visited last
		stack[top++] = leftNearer ? n->left : n->left + 1;
	}
	return best;
}

int fmRenderMesh_Binding(const fmBody* body, int vertex, double w[4])
{
	const fmRenderMesh* m = body->renderMesh.data;
	if (m == NULL || vertex < 0 || vertex >= m->vertexCount)
		return -1;
	memcpy(w, m->weight + 4 * vertex, sizeof(double) * 4);
	return m->tet[vertex];
}

double fmRenderMesh_TetDistance(const fmBody* body, int tet, fmVec3 p)
{
	double w[4];
	fmBarycentric(body, tet, p, w);
	return fmOutsideDistance(body, tet, p, w);
}

// ---- the public calls ---------------------------------------------------------------------

static fmResult fmCheckRenderInput(const double* vertices, int vertexCount, const int* triangles,
                                   int triangleCount, fmDiagnostic* diag)
{
	if (vertexCount < 1 || vertexCount > FM_MAX_SURFACE_VERTICES || vertices == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "fmBody_SetRenderMesh: expected 1 to %d vertices and their array, got "
		                   "%d%s",
		                   FM_MAX_SURFACE_VERTICES, vertexCount,
		                   vertices == NULL ? " and NULL" : "");
	if (triangleCount < 0 || triangleCount > FM_MAX_SURFACE_TRIANGLES ||
	    (triangleCount > 0 && triangles == NULL))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "fmBody_SetRenderMesh: expected 0 to %d triangles and their array, "
		                   "got %d",
		                   FM_MAX_SURFACE_TRIANGLES, triangleCount);
	for (int i = 0; i < 3 * vertexCount; ++i)
		if (!isfinite(vertices[i]) || fabs(vertices[i]) > FM_MAX_COORDINATE)
			return fmDiagError(diag, fm_errRange, "", 0, 0,
			                   "fmBody_SetRenderMesh: vertex %d has coordinate %g (expected "
			                   "finite, within %g m)",
			                   i / 3, vertices[i], FM_MAX_COORDINATE);
	for (int i = 0; i < 3 * triangleCount; ++i)
		if (triangles[i] < 0 || triangles[i] >= vertexCount)
			return fmDiagError(diag, fm_errIndex, "", 0, 0,
			                   "fmBody_SetRenderMesh: triangle %d refers to vertex %d (expected 0 "
			                   "to %d)",
			                   i / 3, triangles[i], vertexCount - 1);
	return fm_ok;
}

static fmRenderMesh* fmRenderMesh_Alloc(int vertexCount, int triangleCount)
{
	fmRenderMesh* m = fmAllocZero(sizeof *m);
	if (m == NULL)
		return NULL;
	m->vertexCount = vertexCount;
	m->triangleCount = triangleCount;
	size_t n = (size_t)vertexCount;
	m->tet = FM_ALLOC_ARRAY(int, n);
	m->weight = FM_ALLOC_ARRAY(double, 4 * n);
	m->triangles = FM_ALLOC_ARRAY(int, 3 * (size_t)(triangleCount > 0 ? triangleCount : 0));
	m->positions = FM_ALLOC_ARRAY(double, 3 * n);
	m->normals = FM_ALLOC_ARRAY(double, 3 * n);
	if (m->tet == NULL || m->weight == NULL || (triangleCount > 0 && m->triangles == NULL) ||
	    m->positions == NULL || m->normals == NULL)
	{
		fmRenderMesh_Free(m);
		return NULL;
	}
	return m;
}

fmResult fmBody_SetRenderMesh(fmBodyId bodyId, const double* vertices, int vertexCount,
                              const int* triangles, int triangleCount, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0,
		                   "fmBody_SetRenderMesh: invalid or destroyed body id");
	fmResult r = fmCheckRenderInput(vertices, vertexCount, triangles, triangleCount, diag);
	if (r != fm_ok)
		return r;
	fmFpEnv env = fmFpEnv_Enter(fmDetMath_Enabled());
	fmRenderMesh* m = fmRenderMesh_Alloc(vertexCount, triangleCount);
	fmTetGrid grid;
	fmTetTree tree;
	memset(&tree, 0, sizeof tree);
	r = m == NULL ? fm_errOutOfMemory : fmTetGrid_Build(&grid, b);
	if (r == fm_ok)
		r = fmTetTree_Build(&tree, b);
	int outside = 0;
	double farthest = 0.0;
	for (int i = 0; r == fm_ok && i < vertexCount; ++i)
	{
		fmVec3 p = fmLoad(vertices, i);
		fmBinding bind =
		    fmGridContains(&grid, p) ? fmBindVertex(b, &grid, p) : fmBindByTree(b, &tree, p);
		m->tet[i] = bind.tet;
		memcpy(m->weight + 4 * i, bind.w, sizeof bind.w);
		// Outside by more than round-off of the tet's own size: reported.
		if (bind.distance > 1e-9 * b->mesh.restSize)
		{
			outside += 1;
			farthest = fmMax(farthest, bind.distance);
		}
	}
	if (m != NULL)
		fmTetGrid_Free(&grid);
	fmTetTree_Free(&tree, b->mesh.tetCount);
	fmFpEnv_Leave(&env);
	if (r != fm_ok)
	{
		fmRenderMesh_Free(m);
		return fmDiagError(diag, r, "", 0, 0,
		                   "fmBody_SetRenderMesh: %s binding %d vertices to %d tets",
		                   fmResultMessage(r), vertexCount, b->mesh.tetCount);
	}
	if (triangleCount > 0)
		memcpy(m->triangles, triangles, sizeof(int) * 3 * (size_t)triangleCount);
	if (outside > 0)
		fmDiagWarn(diag, "", 0,
		           "fmBody_SetRenderMesh: %d of %d render vertices lie outside the body's tets "
		           "(the farthest %.3g m, %.3g of the body's size): each follows its nearest "
		           "tet's map, extrapolated",
		           outside, vertexCount, farthest, farthest / b->mesh.restSize);
	fmAttachment_Set(&b->renderMesh, m, fmReleaseRenderMesh);
	return fm_ok;
}

void fmBody_ClearRenderMesh(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL)
		return;
	fmAttachment_Release(&b->renderMesh);
}

int fmBody_GetRenderVertexCount(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	return b != NULL && b->renderMesh.data != NULL ? fmBodyRenderMesh(b)->vertexCount : 0;
}

const int* fmBody_GetRenderTriangles(fmBodyId bodyId, int* triangleCount)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	bool has = b != NULL && b->renderMesh.data != NULL;
	if (triangleCount != NULL)
		*triangleCount = has ? fmBodyRenderMesh(b)->triangleCount : 0;
	return has ? fmBodyRenderMesh(b)->triangles : NULL;
}

// Deform the render mesh with the body's current positions into its scratch arrays: positions
// from the bindings, normals as the normalised sum of the cross products of the triangles
// around each vertex (twice their areas: area-weighted), in triangle order (deterministic).
// A tet node's position: now, or (@p previous not NULL) @p alpha of the way from @p previous.
static fmVec3 fmNodeAt(const fmBody* b, const double* previous, double alpha, int node)
{
	fmVec3 now = fmLoad(b->state.x, node);
	if (previous == NULL)
		return now;
	fmVec3 from = fmLoad(previous, node);
	return fmMulAdd(from, alpha, fmSub(now, from));
}

// The render mesh of the body's positions now, or (@p previous not NULL) of the positions
// @p alpha of the way from @p previous to now; with @p normals, its smooth normals.
static void fmRenderMesh_Update(const fmBody* b, fmRenderMesh* m, bool normals,
                                const double* previous, double alpha)
{
	for (int i = 0; i < m->vertexCount; ++i)
	{
		const int* tet = b->mesh.tets + 4 * m->tet[i];
		const double* w = m->weight + 4 * i;
		fmVec3 x = fmMakeVec3(0, 0, 0);
		for (int k = 0; k < 4; ++k)
			x = fmMulAdd(x, w[k], fmNodeAt(b, previous, alpha, tet[k]));
		fmStore(m->positions, i, x);
	}
	if (!normals)
		return;
	memset(m->normals, 0, sizeof(double) * 3 * (size_t)m->vertexCount);
	for (int t = 0; t < m->triangleCount; ++t)
	{
		const int* v = m->triangles + 3 * t;
		fmVec3 a = fmLoad(m->positions, v[0]);
		fmVec3 n =
		    fmCross(fmSub(fmLoad(m->positions, v[1]), a), fmSub(fmLoad(m->positions, v[2]), a));
		for (int k = 0; k < 3; ++k)
			fmStore(m->normals, v[k], fmAdd(fmLoad(m->normals, v[k]), n));
	}
	for (int i = 0; i < m->vertexCount; ++i)
	{
		fmVec3 n = fmLoad(m->normals, i);
		double length = fmLength(n);
		fmStore(m->normals, i, length > 0.0 ? fmScale(1.0 / length, n) : fmMakeVec3(0, 0, 0));
	}
}

// Check a render copy-out, deform, then copy into doubles or floats.
static fmResult fmCopyRender(fmBodyId bodyId, double* positions, double* normals,
                             float* positionsFloat, float* normalsFloat, int vertexCapacity,
                             double alpha, const char* what)
{
	fmBody* b = fmGetBody(bodyId);
	fmWorld* world = fmGetWorldOfBody(bodyId);
	fmDiagnostic* diag = world ? &world->lastError : NULL;
	FM_ASSERT(b != NULL);
	FM_ASSERT(positions != NULL || positionsFloat != NULL);
	if (b == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "%s: invalid or destroyed body id",
		                   what);
	if (positions == NULL && positionsFloat == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "%s: the positions buffer is NULL (expected 3 values a vertex)", what);
	fmRenderMesh* m = b->renderMesh.data;
	if (m == NULL)
		return fmDiagError(diag, fm_errEmpty, "", 0, 0,
		                   "%s: body %d has no render mesh (fmBody_SetRenderMesh)", what,
		                   bodyId.index1 - 1);
	if (vertexCapacity < m->vertexCount)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "%s: a buffer of %d vertices is too small for the render mesh's %d "
		                   "(fmBody_GetRenderVertexCount; 3 values a vertex)",
		                   what, vertexCapacity, m->vertexCount);
	if (!(alpha >= 0.0 && alpha <= 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "%s: alpha %g is outside [0, 1] (fmFixedStep.alpha)", what, alpha);
	fmFpEnv env = fmFpEnv_Enter(fmDetMath_Enabled());
	bool wantNormals = normals != NULL || normalsFloat != NULL;
	// alpha 1 (the copies of now) reads the positions as they are, bit for bit.
	const double* previous = alpha < 1.0 && b->previousValid ? b->previousX : NULL;
	fmRenderMesh_Update(b, m, wantNormals, previous, alpha);
	size_t values = 3 * (size_t)m->vertexCount;
	if (positions != NULL)
		memcpy(positions, m->positions, sizeof(double) * values);
	if (normals != NULL)
		memcpy(normals, m->normals, sizeof(double) * values);
	for (size_t i = 0; positionsFloat != NULL && i < values; ++i)
		positionsFloat[i] = (float)m->positions[i];
	for (size_t i = 0; normalsFloat != NULL && i < values; ++i)
		normalsFloat[i] = (float)m->normals[i];
	fmFpEnv_Leave(&env);
	return fm_ok;
}

fmResult fmBody_CopyRenderPositions(fmBodyId bodyId, double* positions, double* normals,
                                    int vertexCapacity)
{
	return fmCopyRender(bodyId, positions, normals, NULL, NULL, vertexCapacity, 1.0,
	                    "fmBody_CopyRenderPositions");
}

fmResult fmBody_CopyRenderPositionsFloat(fmBodyId bodyId, float* positions, float* normals,
                                         int vertexCapacity)
{
	return fmCopyRender(bodyId, NULL, NULL, positions, normals, vertexCapacity, 1.0,
	                    "fmBody_CopyRenderPositionsFloat");
}

fmResult fmBody_CopyInterpolatedRenderPositionsFloat(fmBodyId bodyId, double alpha,
                                                     float* positions, float* normals,
                                                     int vertexCapacity)
{
	return fmCopyRender(bodyId, NULL, NULL, positions, normals, vertexCapacity, alpha,
	                    "fmBody_CopyInterpolatedRenderPositionsFloat");
}
