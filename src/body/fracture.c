// Fracture of a body along its tet faces (fracture.h): the crack state, the criterion and the
// tear that splits vertices.
#include "body/fracture.h"

#include "body/body.h"
#include "body/tear_topology.h"
#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"
#include "fem/nodal_pressure.h"
#include "fem/tet_blocks.h"
#include "solver/solver_cache.h"
#include "world/island.h"
#include "world/world.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

// The most tets one stress average may take (a fracture length of a few tets is what it is for).
#define FM_TEAR_MAX_NEAR 512

// Node slots of face k of a tet (the face opposite node k).
static const int s_face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// ---- pieces ------------------------------------------------------------------------------------

static int fmFindRoot(int* parent, int t)
{
	while (parent[t] != t)
	{
		parent[t] = parent[parent[t]];
		t = parent[t];
	}
	return t;
}

static void fmUnite(int* parent, int a, int b)
{
	a = fmFindRoot(parent, a);
	b = fmFindRoot(parent, b);
	if (a != b) // the smaller tet roots: labels follow the body's tet order
		parent[a > b ? a : b] = a > b ? b : a;
}

// Each tet's piece (tets joined by unbroken faces), numbered by their first tet; returns the
// count. @p parent: tetCount scratch.
static int fmLabelPieces(const fmCracks* c, int m, int* parent, int* piece)
{
	for (int t = 0; t < m; ++t)
		parent[t] = t;
	for (int f = 0; f < 4 * m; ++f)
		if (c->neighbour[f] >= 0 && !c->broken[f])
			fmUnite(parent, f / 4, c->neighbour[f] / 4);
	int count = 0;
	for (int t = 0; t < m; ++t)
	{
		int root = fmFindRoot(parent, t);
		piece[t] = root == t ? count++ : piece[root];
	}
	return count;
}

// ---- preparation -------------------------------------------------------------------------------

typedef struct fmFaceKey
{
	int v[3]; // sorted
	int face; // 4 t + k
} fmFaceKey;

static int fmCompareFaceKeys(const void* a, const void* b)
{
	const fmFaceKey *p = a, *q = b;
	for (int k = 0; k < 3; ++k)
		if (p->v[k] != q->v[k])
			return p->v[k] < q->v[k] ? -1 : 1;
	return (p->face > q->face) - (p->face < q->face);
}

static void fmSort3(int v[3])
{
	for (int i = 0; i < 2; ++i)
		for (int j = 0; j < 2 - i; ++j)
			if (v[j] > v[j + 1])
			{
				int s = v[j];
				v[j] = v[j + 1];
				v[j + 1] = s;
			}
}

// Each face's neighbour across it from the tets before any tear; false when out of memory.
static bool fmFindNeighbours(fmCracks* c, int tetCount)
{
	size_t faces = 4 * (size_t)tetCount;
	fmFaceKey* keys = FM_ALLOC_ARRAY(fmFaceKey, faces);
	if (keys == NULL)
		return false;
	for (size_t f = 0; f < faces; ++f)
	{
		for (int j = 0; j < 3; ++j)
			keys[f].v[j] = c->originalTets[4 * (f / 4) + (size_t)s_face[f % 4][j]];
		fmSort3(keys[f].v);
		keys[f].face = (int)f;
		c->neighbour[f] = -1;
	}
	qsort(keys, faces, sizeof *keys, fmCompareFaceKeys);
	for (size_t f = 0; f < faces;)
	{
		size_t run = 1; // (a face of three or more tets, a non-manifold mesh, never breaks)
		while (f + run < faces && memcmp(keys[f].v, keys[f + run].v, sizeof keys[f].v) == 0)
			run += 1;
		if (run == 2)
		{
			c->neighbour[keys[f].face] = keys[f + 1].face;
			c->neighbour[keys[f + 1].face] = keys[f].face;
		}
		f += run;
	}
	FM_FREE_ARRAY(keys, fmFaceKey, faces);
	return true;
}

static fmVec3 fmRestCentre(const fmBody* b, int t)
{
	const int* n = b->mesh.tets + 4 * t;
	fmVec3 s = fmMakeVec3(0.0, 0.0, 0.0);
	for (int a = 0; a < 4; ++a)
		s = fmAdd(s, fmLoad(b->mesh.x0, n[a]));
	return fmScale(0.25, s);
}

typedef struct fmCellTet
{
	int64_t cell;
	int tet;
} fmCellTet;

static int fmCompareCells(const void* a, const void* b)
{
	const fmCellTet *p = a, *q = b;
	if (p->cell != q->cell)
		return p->cell < q->cell ? -1 : 1;
	return (p->tet > q->tet) - (p->tet < q->tet);
}

// The tets whose rest centres lie within tet t's fracture length of its own, ascending,
// appended to @p out (at most FM_TEAR_MAX_NEAR); returns how many, or -1 when over.
static int fmGatherNear(const fmBody* b, const fmCellTet* cells, int m, const fmVec3* centre,
                        double size, const int64_t dims[3], fmVec3 lo, int t, int* out)
{
	double length = fmTetUserMaterial(&b->mesh, t)->fracture.length;
	if (!(length > 0.0))
	{
		out[0] = t;
		return 1;
	}
	int count = 0;
	double along[3] = {(centre[t].x - lo.x) / size, (centre[t].y - lo.y) / size,
	                   (centre[t].z - lo.z) / size};
	int64_t at[3]; // (clamped as the binning clamps)
	for (int a = 0; a < 3; ++a)
		at[a] = (int64_t)fmMin(along[a], (double)(dims[a] - 1));
	for (int64_t dz = -1; dz <= 1; ++dz)
		for (int64_t dy = -1; dy <= 1; ++dy)
			for (int64_t dx = -1; dx <= 1; ++dx)
			{
				int64_t i = at[0] + dx, j = at[1] + dy, k = at[2] + dz;
				if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2])
					continue;
				int64_t cell = (k * dims[1] + j) * dims[0] + i;
				int lo2 = 0, hi2 = m; // first entry of the cell
				while (lo2 < hi2)
				{
					int mid = lo2 + (hi2 - lo2) / 2;
					if (cells[mid].cell < cell)
						lo2 = mid + 1;
					else
						hi2 = mid;
				}
				for (int e = lo2; e < m && cells[e].cell == cell; ++e)
					if (fmLength(fmSub(centre[cells[e].tet], centre[t])) <= length)
					{
						if (count == FM_TEAR_MAX_NEAR)
							return -1;
						out[count++] = cells[e].tet;
					}
			}
	// ascending, for a sum in one order whatever the grid
	for (int i = 1; i < count; ++i)
		for (int j = i; j > 0 && out[j - 1] > out[j]; --j)
		{
			int s = out[j];
			out[j] = out[j - 1];
			out[j - 1] = s;
		}
	return count;
}

// The largest fracture length of the body's materials (0: every average is one tet).
static double fmLongestLength(const fmBody* b)
{
	double longest = b->mesh.material.fracture.length;
	for (int k = 0; k < b->mesh.materialCount; ++k)
		longest = fmMax(longest, b->mesh.materials[k].fracture.length);
	return longest;
}

// The rest centres binned on a grid of the longest length's cells, sorted by cell.
static fmCellTet* fmBinCentres(const fmBody* b, const fmVec3* centre, double size, int64_t dims[3],
                               fmVec3* lo)
{
	int m = b->mesh.tetCount;
	fmVec3 hi = centre[0];
	*lo = centre[0];
	for (int t = 1; t < m; ++t)
	{
		*lo = fmMakeVec3(fmMin(lo->x, centre[t].x), fmMin(lo->y, centre[t].y),
		                 fmMin(lo->z, centre[t].z));
		hi = fmMakeVec3(fmMax(hi.x, centre[t].x), fmMax(hi.y, centre[t].y),
		                fmMax(hi.z, centre[t].z));
	}
	double extent[3] = {hi.x - lo->x, hi.y - lo->y, hi.z - lo->z};
	for (int a = 0; a < 3; ++a) // (cells beyond 2^20 a side share: a bound, not a limit)
		dims[a] = (int64_t)fmMin(extent[a] / size, 1048575.0) + 1;
	fmCellTet* cells = FM_ALLOC_ARRAY(fmCellTet, m);
	for (int t = 0; cells != NULL && t < m; ++t)
	{
		int64_t i = (int64_t)fmMin((centre[t].x - lo->x) / size, (double)(dims[0] - 1));
		int64_t j = (int64_t)fmMin((centre[t].y - lo->y) / size, (double)(dims[1] - 1));
		int64_t k = (int64_t)fmMin((centre[t].z - lo->z) / size, (double)(dims[2] - 1));
		cells[t].cell = (k * dims[1] + j) * dims[0] + i;
		cells[t].tet = t;
	}
	if (cells != NULL)
		qsort(cells, (size_t)m, sizeof *cells, fmCompareCells);
	return cells;
}

// The averages' tets: nearStart / near. fm_errLimit when one takes too many.
static fmResult fmFindNear(fmBody* b, fmCracks* c, fmDiagnostic* diag)
{
	int m = b->mesh.tetCount;
	double size = fmLongestLength(b);
	fmVec3* centre = FM_ALLOC_ARRAY(fmVec3, m);
	int* list = FM_ALLOC_ARRAY(int, FM_TEAR_MAX_NEAR);
	int64_t dims[3] = {1, 1, 1};
	fmVec3 lo = fmMakeVec3(0.0, 0.0, 0.0);
	for (int t = 0; centre != NULL && t < m; ++t)
		centre[t] = fmRestCentre(b, t);
	fmCellTet* cells =
	    centre != NULL && size > 0.0 ? fmBinCentres(b, centre, size, dims, &lo) : NULL;
	fmResult r =
	    centre == NULL || list == NULL || (size > 0.0 && cells == NULL) ? fm_errOutOfMemory : fm_ok;
	size_t total = 0, capacity = 0;
	for (int t = 0; r == fm_ok && t < m; ++t)
	{
		int count = fmGatherNear(b, cells, m, centre, size, dims, lo, t, list);
		if (count < 0)
		{
			r = fmDiagError(diag, fm_errLimit, "", 0, 0,
			                "fracture.length = %g m takes more than %d tets into the stress "
			                "average of tet %d: shorten it (a few tets across is enough) or use a "
			                "coarser mesh",
			                fmTetUserMaterial(&b->mesh, t)->fracture.length, FM_TEAR_MAX_NEAR,
			                b->userTet[t]);
			break;
		}
		if (total + (size_t)count > (size_t)INT_MAX)
		{
			r = fmDiagError(diag, fm_errLimit, "", 0, 0,
			                "fracture.length = %g m: the stress averages would take more than %d "
			                "entries: shorten it",
			                fmTetUserMaterial(&b->mesh, t)->fracture.length, INT_MAX);
			break;
		}
		if (total + (size_t)count > capacity)
		{
			size_t grown = fmMax((double)(2 * capacity), (double)(total + (size_t)count + 64));
			int* more = FM_ALLOC_ARRAY(int, grown);
			if (more == NULL)
			{
				r = fm_errOutOfMemory;
				break;
			}
			if (c->near != NULL)
				memcpy(more, c->near, sizeof(int) * total);
			FM_FREE_ARRAY(c->near, int, capacity);
			c->near = more;
			capacity = grown;
		}
		c->nearStart[t] = (int)total;
		memcpy(c->near + total, list, sizeof(int) * (size_t)count);
		total += (size_t)count;
	}
	if (r == fm_ok)
	{
		c->nearStart[m] = (int)total;
		int* exact =
		    FM_ALLOC_ARRAY(int, total); // the list at its size: Free knows it from nearStart
		if (exact == NULL)
			r = fm_errOutOfMemory;
		else
		{
			memcpy(exact, c->near, sizeof(int) * total);
			FM_FREE_ARRAY(c->near, int, capacity);
			c->near = exact;
		}
	}
	else
	{
		FM_FREE_ARRAY(c->near, int, capacity);
		c->near = NULL;
	}
	FM_FREE_ARRAY(centre, fmVec3, m);
	FM_FREE_ARRAY(list, int, FM_TEAR_MAX_NEAR);
	FM_FREE_ARRAY(cells, fmCellTet, cells != NULL ? m : 0);
	return r;
}

static bool fmAnyTears(const fmBody* b)
{
	bool tears = fmFracture_Tears(&b->mesh.material);
	for (int k = 0; k < b->mesh.materialCount; ++k)
		tears = tears || fmFracture_Tears(&b->mesh.materials[k]);
	return tears;
}

static double fmMinPieceVolume(const fmBody* b)
{
	if (b->mesh.material.fracture.minVolume > 0.0)
		return b->mesh.material.fracture.minVolume;
	double total = 0.0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
		total += b->mesh.restVolume[t];
	return 8.0 * total / b->mesh.tetCount;
}

fmResult fmFracture_Prepare(fmBody* b, fmDiagnostic* diag)
{
	if (!fmAnyTears(b))
		return fm_ok;
	fmCracks* c = b->cracks;
	int n = b->mesh.vertexCount, m = b->mesh.tetCount;
	if (c == NULL)
	{
		c = b->cracks = FM_ALLOC_ZERO(fmCracks, 1);
		if (c == NULL)
			return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for fracture");
		c->originalVertexCount = n;
		c->originalMass = FM_ALLOC_ARRAY(double, n);
		c->originalTets = FM_ALLOC_ARRAY(int, 4 * (size_t)m);
		c->origin = FM_ALLOC_ARRAY(int, n);
		c->neighbour = FM_ALLOC_ARRAY(int, 4 * (size_t)m);
		c->broken = FM_ALLOC_ZERO(uint8_t, 4 * (size_t)m);
		c->piece = FM_ALLOC_ZERO(int, m);
		c->frame = FM_ALLOC_ARRAY(double, 16 * (size_t)m);
		c->pieceCount = 1;
		bool made = c->originalMass && c->originalTets && c->origin && c->neighbour && c->broken &&
		            c->piece && c->frame;
		if (made)
		{
			memcpy(c->originalMass, b->mesh.mass, sizeof(double) * (size_t)n);
			memcpy(c->originalTets, b->mesh.tets, sizeof(int) * 4 * (size_t)m);
			for (int i = 0; i < n; ++i)
				c->origin[i] = i;
		}
		int* parent = made ? FM_ALLOC_ARRAY(int, m) : NULL;
		made = parent != NULL && fmFindNeighbours(c, m);
		if (made) // (a mesh of several parts is several pieces from the start)
			c->pieceCount = fmLabelPieces(c, m, parent, c->piece);
		FM_FREE_ARRAY(parent, int, parent != NULL ? m : 0);
		if (!made)
		{
			fmFracture_Free(b);
			return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory for fracture");
		}
	}
	// The averages follow the materials (fmBody_SetMaterial may change the lengths).
	if (c->nearStart != NULL)
		FM_FREE_ARRAY(c->near, int, c->nearStart[m]);
	FM_FREE_ARRAY(c->nearStart, int, (size_t)m + 1);
	c->near = NULL;
	c->nearStart = FM_ALLOC_ARRAY(int, (size_t)m + 1);
	fmResult r = c->nearStart != NULL ? fmFindNear(b, c, diag) : fm_errOutOfMemory;
	if (r == fm_errOutOfMemory)
		fmDiagError(diag, r, "", 0, 0, "out of memory for fracture");
	if (r != fm_ok) // (a torn body keeps its cracks; it only stops tearing)
	{
		FM_FREE_ARRAY(c->nearStart, int, (size_t)m + 1);
		c->nearStart = NULL;
		return r;
	}
	c->minVolume = fmMinPieceVolume(b);
	return fm_ok;
}

void fmFracture_Free(fmBody* b)
{
	fmCracks* c = b->cracks;
	if (c == NULL)
		return;
	size_t n0 = (size_t)c->originalVertexCount, m = (size_t)b->mesh.tetCount;
	FM_FREE_ARRAY(c->originalMass, double, n0);
	FM_FREE_ARRAY(c->originalTets, int, 4 * m);
	FM_FREE_ARRAY(c->origin, int, b->mesh.vertexCount);
	FM_FREE_ARRAY(c->neighbour, int, 4 * m);
	FM_FREE_ARRAY(c->broken, uint8_t, 4 * m);
	if (c->nearStart != NULL)
		FM_FREE_ARRAY(c->near, int, c->nearStart[m]);
	FM_FREE_ARRAY(c->nearStart, int, m + 1);
	FM_FREE_ARRAY(c->piece, int, m);
	FM_FREE_ARRAY(c->frame, double, 16 * m);
	FM_FREE_ARRAY(c, fmCracks, 1);
	b->cracks = NULL;
}

// ---- the criterion -----------------------------------------------------------------------------

// Tet t's Cauchy stress sigma = P F^T / J (6: xx yy zz xy yz zx); zero for an inverted tet
// (crushed, not pulled).
static void fmTetCauchy(const fmBody* b, int t, double s[6])
{
	fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t), P;
	double J = fmDet(&F);
	memset(s, 0, 6 * sizeof(double));
	if (!(J > 0.0))
		return;
	fmTetEvaluate(&b->mesh, t, &F, &P, NULL, false);
	fmMat3 tau = fmMatMulT(&P, &F); // P F^T (symmetric for the frame-indifferent laws)
	const double* a = tau.m;
	s[0] = a[0] / J;
	s[1] = a[4] / J;
	s[2] = a[8] / J;
	s[3] = 0.5 * (a[1] + a[3]) / J;
	s[4] = 0.5 * (a[5] + a[7]) / J;
	s[5] = 0.5 * (a[2] + a[6]) / J;
}

// The volume term a nodal material keeps on its vertices (fem/nodal_pressure.h) is a pressure:
// each nodal tet's Cauchy stress gets its nodes' mean pressure on the diagonal (the tet's own
// evaluation left the term out), read into the mesh's scratch (a pressure that is not finite
// adds nothing, as an inverted tet's stress is zero).
static void fmAddNodalPressure(const fmBody* b, double* stress)
{
	const fmElasticMesh* mesh = &b->mesh;
	fmNodalPressure_State(mesh, b->state.x, mesh->nodalPressure, NULL);
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		double p = fmNodalPressure_TetMean(mesh, mesh->nodalPressure, t);
		for (int k = 0; k < 3 && fmNodalPressure_TetIsNodal(mesh, t) && isfinite(p); ++k)
			stress[6 * t + k] += p;
	}
}

// The volume-weighted averages of the tets' stresses over each tet's near list (6 per tet).
static void fmAverageStress(const fmBody* b, const double* stress, double* average)
{
	const fmCracks* c = b->cracks;
	for (int t = 0; t < b->mesh.tetCount; ++t)
	{
		double sum[6] = {0}, volume = 0.0;
		for (int e = c->nearStart[t]; e < c->nearStart[t + 1]; ++e)
		{
			int s = c->near[e];
			double v = b->mesh.restVolume[s];
			volume += v;
			for (int k = 0; k < 6; ++k)
				sum[k] += v * stress[6 * s + k];
		}
		for (int k = 0; k < 6; ++k)
			average[6 * t + k] = sum[k] / volume;
	}
}

// The strength of the face between tets t and u: the weaker tearing material's; 0 when neither
// tears.
static double fmFaceStrength(const fmBody* b, int t, int u)
{
	double a = fmTetUserMaterial(&b->mesh, t)->fracture.strength;
	double c = fmTetUserMaterial(&b->mesh, u)->fracture.strength;
	if (a > 0.0 && c > 0.0)
		return fmMin(a, c);
	return a > 0.0 ? a : c;
}

// n . sigma n for the face of tet t opposite node k at the current positions, sigma the mean
// of the two sides' averages.
static double fmFaceTraction(const fmBody* b, const double* average, int t, int k, int u)
{
	const int* n = b->mesh.tets + 4 * t;
	fmVec3 p0 = fmLoad(b->state.x, n[s_face[k][0]]), p1 = fmLoad(b->state.x, n[s_face[k][1]]),
	       p2 = fmLoad(b->state.x, n[s_face[k][2]]);
	fmVec3 normal = fmCross(fmSub(p1, p0), fmSub(p2, p0));
	double area = fmLength(normal);
	if (!(area > 0.0))
		return 0.0;
	normal = fmScale(1.0 / area, normal);
	double s[6];
	for (int e = 0; e < 6; ++e)
		s[e] = 0.5 * (average[6 * t + e] + average[6 * u + e]);
	fmVec3 sn = fmMakeVec3(s[0] * normal.x + s[3] * normal.y + s[5] * normal.z,
	                       s[3] * normal.x + s[1] * normal.y + s[4] * normal.z,
	                       s[5] * normal.x + s[4] * normal.y + s[2] * normal.z);
	return fmDot(normal, sn);
}

double fmFracture_Damage(const fmBody* b, double* tetDamage, double* faceRatio)
{
	const fmCracks* c = b->cracks;
	int m = b->mesh.tetCount;
	if (tetDamage != NULL)
		memset(tetDamage, 0, sizeof(double) * (size_t)m);
	if (faceRatio != NULL)
		memset(faceRatio, 0, sizeof(double) * 4 * (size_t)m);
	if (c == NULL || c->nearStart == NULL || !fmAnyTears(b))
		return 0.0;
	double *stress = c->frame, largest = 0.0;
	double* average = stress + 6 * (size_t)m;
	for (int t = 0; t < m; ++t)
		fmTetCauchy(b, t, stress + 6 * t);
	if (fmNodalPressure_On(&b->mesh))
		fmAddNodalPressure(b, stress);
	fmAverageStress(b, stress, average);
	for (int f = 0; f < 4 * m; ++f)
	{
		int g = c->neighbour[f];
		if (g < 0 || c->broken[f])
			continue;
		double strength = fmFaceStrength(b, f / 4, g / 4);
		if (!(strength > 0.0))
			continue;
		double ratio = fmFaceTraction(b, average, f / 4, f % 4, g / 4) / strength;
		ratio = isfinite(ratio) ? fmMax(ratio, 0.0) : 0.0;
		largest = fmMax(largest, ratio);
		if (faceRatio != NULL)
			faceRatio[f] = ratio;
		if (tetDamage != NULL)
			tetDamage[f / 4] = fmMax(tetDamage[f / 4], ratio);
	}
	return largest;
}

void fmFracture_SetBroken(fmBody* b, const uint8_t* broken, int* parent)
{
	fmCracks* c = b->cracks;
	int m = b->mesh.tetCount;
	memcpy(c->broken, broken, 4 * (size_t)m);
	c->brokenCount = 0;
	for (int f = 0; f < 4 * m; ++f)
		c->brokenCount += c->broken[f] && c->neighbour[f] > f;
	c->pieceCount = fmLabelPieces(c, m, parent, c->piece);
}

// Unbreak this call's faces (@p fresh) around every piece smaller than the minimum; returns
// whether any was. @p parent, @p piece: tetCount scratch; @p volume: tetCount scratch.
static bool fmKeepSlivers(const fmBody* b, fmCracks* c, uint8_t* fresh, int* parent, int* piece,
                          double* volume)
{
	int m = b->mesh.tetCount;
	int count = fmLabelPieces(c, m, parent, piece);
	memset(volume, 0, sizeof(double) * (size_t)count);
	for (int t = 0; t < m; ++t)
		volume[piece[t]] += b->mesh.restVolume[t];
	bool any = false;
	for (int f = 0; f < 4 * m; ++f)
	{
		int g = c->neighbour[f];
		if (!fresh[f] ||
		    (volume[piece[f / 4]] >= c->minVolume && volume[piece[g / 4]] >= c->minVolume))
			continue;
		fresh[f] = fresh[g] = 0;
		c->broken[f] = c->broken[g] = 0;
		any = true;
	}
	return any;
}

// ---- splitting ---------------------------------------------------------------------------------

// The groups of vertex v's tets (around[0 .. count)) that hold together across unbroken faces
// through the vertex: each tet's root in @p parent (indexed by the tet's place in `around`).
static void fmGroupAround(const fmBody* b, const int* around, int count, int* parent)
{
	const fmCracks* c = b->cracks;
	for (int i = 0; i < count; ++i)
		parent[i] = i;
	for (int i = 0; i < count; ++i)
	{
		int t = around[i] / 4, a = around[i] % 4;
		for (int k = 0; k < 4; ++k)
		{
			int f = 4 * t + k, g = c->neighbour[f];
			if (k == a || g < 0 || c->broken[f])
				continue; // (face k holds v unless k is v's own slot)
			for (int j = 0; j < count; ++j)
				if (around[j] / 4 == g / 4)
					fmUnite(parent, i, j);
		}
	}
}

// The new corners: every vertex that a broken face touches is split into its groups, the group
// of its first tet keeping it, the others' copies numbered in vertex order, then by their first
// tet. Returns the new vertex count (tets and from filled). @p parent, @p label: tetCount each.
static int fmSplitVertices(const fmBody* b, const uint8_t* touched, int* tets, int* from,
                           int* parent, int* label)
{
	const fmElasticMesh* mesh = &b->mesh;
	int n = mesh->vertexCount;
	memcpy(tets, mesh->tets, sizeof(int) * 4 * (size_t)mesh->tetCount);
	for (int i = 0; i < n; ++i)
		from[i] = i;
	int next = n;
	for (int v = 0; v < n; ++v)
	{
		if (!touched[v])
			continue;
		const int* around = mesh->vertexTets + mesh->vertexTetStart[v];
		int count = mesh->vertexTetStart[v + 1] - mesh->vertexTetStart[v];
		fmGroupAround(b, around, count, parent);
		for (int i = 0; i < count; ++i)
		{
			int root = fmFindRoot(parent, i); // (the group's first place: root <= i)
			if (root == i)
			{
				label[i] = i == 0 ? v : next;
				if (i > 0)
					from[next++] = v;
			}
			tets[around[i]] = label[root];
		}
	}
	return next;
}

// Mark the faces this frame breaks (@p ratio: each face's traction over strength) in @p fresh
// and in the crack state, none that would cut off a piece below the minimum; mark their
// vertices in @p touched. Returns how many (each shared face once). @p scratch: 2 ints a tet;
// @p volume: a double a tet.
static int fmBreakFaces(const fmBody* b, fmCracks* c, const double* ratio, uint8_t* fresh,
                        int* scratch, double* volume, uint8_t* touched)
{
	int m = b->mesh.tetCount;
	size_t faces = 4 * (size_t)m;
	for (size_t f = 0; f < faces; ++f)
		if (ratio[f] >= 1.0 && c->neighbour[f] > (int)f)
		{
			fresh[f] = fresh[c->neighbour[f]] = 1;
			c->broken[f] = c->broken[c->neighbour[f]] = 1;
		}
	while (fmKeepSlivers(b, c, fresh, scratch, scratch + m, volume))
		;
	int broke = 0;
	for (size_t f = 0; f < faces; ++f)
		if (fresh[f] && c->neighbour[f] > (int)f)
		{
			broke += 1;
			for (int j = 0; j < 3; ++j)
				touched[b->mesh.tets[4 * (f / 4) + (size_t)s_face[f % 4][j]]] = 1;
		}
	return broke;
}

int fmFracture_Tear(fmWorld* w, fmBody* b, fmDiagnostic* diag)
{
	fmCracks* c = b->cracks;
	if (c == NULL || c->nearStart == NULL || !fmAnyTears(b))
		return 0;
	int n = b->mesh.vertexCount, m = b->mesh.tetCount;
	size_t faces = 4 * (size_t)m;
	double* ratio = c->frame + 12 * (size_t)m;
	double largest = fmFracture_Damage(b, NULL, ratio);
	if (largest < 1.0)
		return 0; // (nothing breaks: nothing allocated)
	uint8_t* fresh = FM_ALLOC_ZERO(uint8_t, faces);
	int* scratch = FM_ALLOC_ARRAY(int, 2 * (size_t)m);
	double* volume = FM_ALLOC_ARRAY(double, m);
	uint8_t* touched = FM_ALLOC_ZERO(uint8_t, n);
	int* tets = FM_ALLOC_ARRAY(int, faces);
	int* from = FM_ALLOC_ARRAY(int, n + faces); // (at most a vertex a corner)
	int* label = FM_ALLOC_ARRAY(int, m);
	int broke = -1;
	if (fresh && scratch && volume && touched && tets && from && label)
		broke = fmBreakFaces(b, c, ratio, fresh, scratch, volume, touched);
	if (broke > 0)
	{
		int count = fmSplitVertices(b, touched, tets, from, scratch, label);
		if (!fmTearTopology_Set(w, b, tets, count, from))
			broke = -1;
	}
	if (broke < 0)
	{
		for (size_t f = 0; fresh != NULL && f < faces; ++f)
			if (fresh[f])
				c->broken[f] = 0; // the body unchanged
		fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		            "out of memory tearing a body of %d tets: it stays whole this frame", m);
	}
	else if (broke > 0)
	{
		c->brokenCount += broke;
		c->pieceCount = fmLabelPieces(c, m, scratch, c->piece);
	}
	FM_FREE_ARRAY(fresh, uint8_t, faces);
	FM_FREE_ARRAY(scratch, int, 2 * (size_t)m);
	FM_FREE_ARRAY(volume, double, m);
	FM_FREE_ARRAY(touched, uint8_t, n);
	FM_FREE_ARRAY(tets, int, faces);
	FM_FREE_ARRAY(from, int, n + faces);
	FM_FREE_ARRAY(label, int, m);
	return broke;
}

static int fmVertexPiece(const fmBody* b, int v)
{
	int start = b->mesh.vertexTetStart[v];
	return start < b->mesh.vertexTetStart[v + 1] ? b->cracks->piece[b->mesh.vertexTets[start] / 4]
	                                             : -1;
}

bool fmFracture_MeetsItself(const fmBody* b)
{
	return b->selfCollision || (b->cracks != NULL && b->cracks->pieceCount > 1);
}

bool fmFracture_AcrossPieces(const fmBody* b, const int* v, int split, int count)
{
	const fmCracks* c = b->cracks;
	if (c == NULL || c->pieceCount < 2)
		return false;
	int first = fmVertexPiece(b, v[0]), second = fmVertexPiece(b, v[split]);
	if (first < 0 || second < 0 || first == second)
		return false;
	for (int i = 0; i < count; ++i)
		if (fmVertexPiece(b, v[i]) != (i < split ? first : second))
			return false;
	for (int i = 0; i < split; ++i)
		for (int j = split; j < count; ++j)
			if (c->origin[v[i]] == c->origin[v[j]])
				return false;
	return true;
}

void fmFracture_EndFrame(fmWorld* w)
{
	for (int i = 0; i < w->bodyCapacity; ++i)
	{
		fmDiagnostic diag;
		memset(&diag, 0, sizeof diag);
		if (fmIsland_Stepping(&w->bodies[i]) && w->bodies[i].cracks != NULL &&
		    fmFracture_Tear(w, &w->bodies[i], &diag) < 0) // (the frame stands: a warning)
			fmDiagWarn(&w->lastError, "", 0, "body %d: %s", i, diag.message);
	}
}

// ---- public calls ------------------------------------------------------------------------------

static int fmBodyFractureIn(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL || w == NULL)
		return -1;
	return fmFracture_Tear(w, b, &w->lastError);
}

int fmBody_Fracture(fmBodyId bodyId)
{
	fmIsland_WakeBody(bodyId);
	fmWorld* w = fmGetWorldOfBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	int result = fmBodyFractureIn(bodyId);
	fmFpEnv_Leave(&env);
	return result;
}

// The tets' values in the user's numbering, from the body's order.
static void fmToUserTets(const fmBody* b, const double* values, double* out)
{
	for (int t = 0; t < b->mesh.tetCount; ++t)
		out[b->userTet[t]] = values[t];
}

double fmBody_ComputeDamage(fmBodyId bodyId, double* tetDamage)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL)
		return 0.0;
	fmWorld* w = fmGetWorldOfBody(bodyId);
	fmFpEnv env = fmFpEnv_Enter(w != NULL && w->def.crossPlatformDeterminism);
	double* damage = tetDamage != NULL ? FM_ALLOC_ARRAY(double, b->mesh.tetCount) : NULL;
	double largest = fmFracture_Damage(b, damage, NULL);
	if (damage != NULL)
		fmToUserTets(b, damage, tetDamage);
	else if (tetDamage != NULL) // (no room: NaN says so, as the largest does)
		for (int t = 0; t < b->mesh.tetCount; ++t)
			tetDamage[t] = NAN;
	FM_FREE_ARRAY(damage, double, damage != NULL ? b->mesh.tetCount : 0);
	fmFpEnv_Leave(&env);
	return tetDamage != NULL && damage == NULL ? NAN : largest;
}

int fmBody_GetPieces(fmBodyId bodyId, int* tetPiece)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	if (b == NULL)
		return 0;
	const fmCracks* c = b->cracks;
	if (tetPiece == NULL)
		return c != NULL ? c->pieceCount : 1;
	for (int t = 0; t < b->mesh.tetCount; ++t)
		tetPiece[t] = -1;
	// numbered again by first appearance in the user's tet order
	int* label = FM_ALLOC_ARRAY(int, c != NULL ? c->pieceCount : 1);
	int* internalTet = FM_ALLOC_ARRAY(int, b->mesh.tetCount);
	if (label == NULL || internalTet == NULL)
	{
		FM_FREE_ARRAY(label, int, c != NULL ? c->pieceCount : 1);
		FM_FREE_ARRAY(internalTet, int, b->mesh.tetCount);
		return -1;
	}
	for (int t = 0; t < b->mesh.tetCount; ++t)
		internalTet[b->userTet[t]] = t;
	int count = c != NULL ? c->pieceCount : 1, next = 0;
	for (int k = 0; k < count; ++k)
		label[k] = -1;
	for (int u = 0; u < b->mesh.tetCount; ++u)
	{
		int p = c != NULL ? c->piece[internalTet[u]] : 0;
		if (label[p] < 0)
			label[p] = next++;
		tetPiece[u] = label[p];
	}
	FM_FREE_ARRAY(label, int, count);
	FM_FREE_ARRAY(internalTet, int, b->mesh.tetCount);
	return count;
}

int fmBody_GetBrokenFaceCount(fmBodyId bodyId)
{
	fmBody* b = fmGetBody(bodyId);
	FM_ASSERT(b != NULL);
	return b != NULL && b->cracks != NULL ? b->cracks->brokenCount : 0;
}
