// The scene's welds (welds.h): the other body's vertices sorted by x, each vertex of the body
// paired with the nearest of those within the distance found in the x window around it, so the
// search is n log n plus the vertices in the windows, not n^2.
#include "welds.h"

#include "cli.h"

#include <stdlib.h>

typedef struct cliSortedVertex
{
	double x;
	int vertex;
} cliSortedVertex;

static int cliCompareX(const void* a, const void* b)
{
	const cliSortedVertex *p = a, *q = b;
	if (p->x != q->x)
		return p->x < q->x ? -1 : 1;
	return (p->vertex > q->vertex) - (p->vertex < q->vertex);
}

// The first of @p count sorted entries with x >= @p x.
static int cliLowerBound(const cliSortedVertex* sorted, int count, double x)
{
	int lo = 0, hi = count;
	while (lo < hi)
	{
		int mid = lo + (hi - lo) / 2;
		if (sorted[mid].x < x)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

// The vertex of the sorted @p other nearest to @p p within @p distance, other than @p skip, or -1.
static int cliNearest(const fmTetMesh* other, const cliSortedVertex* sorted, fmVec3 p,
                      double distance, int skip)
{
	int best = -1;
	double bestDistance = distance;
	int n = other->nodeCount;
	for (int k = cliLowerBound(sorted, n, p.x - distance); k < n && sorted[k].x <= p.x + distance;
	     ++k)
	{
		double d = fmLength(fmSub(fmLoad(other->positions, sorted[k].vertex), p));
		if (d <= bestDistance && sorted[k].vertex != skip)
		{
			bestDistance = d;
			best = sorted[k].vertex;
		}
	}
	return best;
}

// Pair body @p b's vertices with body @p o's (weld @p w); their count, the pairs in @p mine and
// @p theirs.
static int cliPair(const cliSimulation* sim, int b, int o, const cliWeld* w,
                   cliSortedVertex* sorted, int* mine, int* theirs)
{
	const fmTetMesh* other = &sim->meshes[o];
	for (int k = 0; k < other->nodeCount; ++k)
		sorted[k] = (cliSortedVertex){other->positions[3 * k], k};
	qsort(sorted, (size_t)other->nodeCount, sizeof *sorted, cliCompareX);
	int count = 0;
	for (int i = 0; i < sim->meshes[b].nodeCount; ++i)
	{
		// A seam (the body itself) pairs each vertex with another, each pair once.
		int j = cliNearest(other, sorted, fmLoad(sim->meshes[b].positions, i), w->distance,
		                   o == b ? i : -1);
		if (j < 0 || (o == b && j < i))
			continue;
		mine[count] = i;
		theirs[count++] = j;
	}
	return count;
}

// Make weld @p k of body @p b.
static bool cliWeldBodies(const cliScene* scene, cliSimulation* sim, int b, int k)
{
	const cliWeld* w = &scene->bodies[b].welds[k];
	if (w->body >= sim->bodyCount)
	{
		cliError("%s: bodies[%d].welds[%d].body: %d, but the scene has %d bodies", scene->name, b,
		         k, w->body, sim->bodyCount);
		return false;
	}
	int n = sim->meshes[b].nodeCount, m = sim->meshes[w->body].nodeCount;
	int* mine = malloc(sizeof(int) * (size_t)n);
	int* theirs = malloc(sizeof(int) * (size_t)n);
	cliSortedVertex* sorted = malloc(sizeof *sorted * (size_t)m);
	bool ok = mine != NULL && theirs != NULL && sorted != NULL;
	int count = ok ? cliPair(sim, b, w->body, w, sorted, mine, theirs) : 0;
	fmAttachDef def = fmDefaultAttachDef();
	def.stiffness = w->stiffness;
	def.dampingRatio = w->dampingRatio;
	if (!ok)
		cliError("%s: out of memory for bodies[%d].welds[%d]", scene->name, b, k);
	else if (count == 0)
		cliError("%s: bodies[%d].welds[%d]: no vertex of the body is within %g m of a vertex of "
		         "body %d (scene coordinates, after the transforms): raise \"distance\"",
		         scene->name, b, k, w->distance, w->body);
	else if (fmBody_Weld(sim->bodies[b], mine, sim->bodies[w->body], theirs, count, &def) != fm_ok)
		cliError("%s: bodies[%d].welds[%d]: %s", scene->name, b, k,
		         fmWorld_GetLastError(sim->world)->message);
	else
		count = -count; // welded
	free(mine);
	free(theirs);
	free(sorted);
	return ok && count < 0;
}

bool cliWelds_Create(const cliScene* scene, cliSimulation* sim)
{
	for (int b = 0; b < scene->bodyCount; ++b)
		for (int k = 0; k < scene->bodies[b].weldCount; ++k)
			if (!cliWeldBodies(scene, sim, b, k))
				return false;
	return true;
}
