// Mesh utilities: ownership (free, copy), placement, orientation, volumes, statistics,
// boundary extraction and generated box meshes.
#include "core.h"
#include "mesh_internal.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#define FM_PI 3.14159265358979323846

// ---- memory -----------------------------------------------------------------------------------

enum
{
	fm_userHeader = 64 // keeps the array 64-byte aligned, as fmAlloc returns it
};

void* fmAllocUser(size_t size)
{
	if (size > SIZE_MAX - fm_userHeader)
		return NULL;
	unsigned char* block = fmAlloc(size + fm_userHeader);
	if (block == NULL)
		return NULL;
	memcpy(block, &size, sizeof size);
	return block + fm_userHeader;
}

void fmFree(void* memory)
{
	if (memory == NULL)
		return;
	unsigned char* block = (unsigned char*)memory - fm_userHeader;
	size_t size;
	memcpy(&size, block, sizeof size);
	fmDealloc(block, size + fm_userHeader);
}

void fmFreeTetMesh(fmTetMesh* mesh)
{
	if (mesh == NULL)
		return;
	size_t n = (size_t)(mesh->nodeCount > 0 ? mesh->nodeCount : 0);
	size_t m = (size_t)(mesh->tetCount > 0 ? mesh->tetCount : 0);
	FM_FREE_ARRAY(mesh->positions, double, 3 * n);
	FM_FREE_ARRAY(mesh->tets, int, 4 * m);
	FM_FREE_ARRAY(mesh->nodeAttributes, double, n*(size_t)mesh->nodeAttributeCount);
	FM_FREE_ARRAY(mesh->nodeMarkers, int, n);
	FM_FREE_ARRAY(mesh->tetAttributes, double, m*(size_t)mesh->tetAttributeCount);
	memset(mesh, 0, sizeof *mesh);
}

// Copy @p count bytes into a new allocation; NULL source gives NULL (and counts as success).
static bool fmDuplicate(const void* source, size_t count, void** copy)
{
	*copy = NULL;
	if (source == NULL || count == 0)
		return true;
	*copy = fmAlloc(count);
	if (*copy)
		memcpy(*copy, source, count);
	return *copy != NULL;
}

fmResult fmCopyTetMesh(const fmTetMesh* source, fmTetMesh* copy)
{
	FM_ASSERT(source != NULL && copy != NULL);
	fmTetMesh c = *source;
	size_t n = (size_t)source->nodeCount, m = (size_t)source->tetCount;
	bool ok = fmDuplicate(source->positions, sizeof(double) * 3 * n, (void**)&c.positions);
	ok = fmDuplicate(source->tets, sizeof(int) * 4 * m, (void**)&c.tets) && ok;
	ok =
	    fmDuplicate(source->nodeAttributes, sizeof(double) * n * (size_t)source->nodeAttributeCount,
	                (void**)&c.nodeAttributes) &&
	    ok;
	ok = fmDuplicate(source->nodeMarkers, sizeof(int) * n, (void**)&c.nodeMarkers) && ok;
	ok = fmDuplicate(source->tetAttributes, sizeof(double) * m * (size_t)source->tetAttributeCount,
	                 (void**)&c.tetAttributes) &&
	     ok;
	if (!ok)
	{
		fmFreeTetMesh(&c);
		memset(copy, 0, sizeof *copy);
		return fm_errOutOfMemory;
	}
	*copy = c;
	return fm_ok;
}

// ---- placement --------------------------------------------------------------------------------

fmMeshTransform fmDefaultMeshTransform(void)
{
	fmMeshTransform t;
	t.scale = 1.0;
	t.center = false;
	t.swapYZ = false;
	t.translate = fmMakeVec3(0.0, 0.0, 0.0);
	return t;
}

void fmTetMesh_Transform(fmTetMesh* mesh, const fmMeshTransform* transform)
{
	FM_ASSERT(mesh != NULL && transform != NULL && transform->scale > 0.0);
	int n = mesh->nodeCount;
	double* x = mesh->positions;
	for (size_t k = 0; k < 3 * (size_t)n; ++k)
		x[k] *= transform->scale;
	fmVec3 centroid = fmMakeVec3(0.0, 0.0, 0.0);
	if (transform->center && n > 0)
	{
		for (int i = 0; i < n; ++i)
			centroid = fmAdd(centroid, fmLoad(x, i));
		centroid = fmScale(1.0 / n, centroid);
	}
	for (int i = 0; i < n; ++i)
	{
		fmVec3 p = fmSub(fmLoad(x, i), centroid);
		if (transform->swapYZ)
			p = fmMakeVec3(p.x, p.z, p.y);
		fmStore(x, i, fmAdd(p, transform->translate));
	}
}

// ---- orientation and volume -------------------------------------------------------------------

double fmTetSixVolume(const double* positions, const int* tet, double* longestEdge)
{
	fmVec3 p[4];
	for (int k = 0; k < 4; ++k)
		p[k] = fmLoad(positions, tet[k]);
	fmVec3 a = fmSub(p[1], p[0]), b = fmSub(p[2], p[0]), c = fmSub(p[3], p[0]);
	if (longestEdge)
	{
		double l2 = 0.0;
		for (int i = 0; i < 4; ++i)
			for (int j = i + 1; j < 4; ++j)
			{
				fmVec3 e = fmSub(p[j], p[i]);
				l2 = fmax(l2, fmDot(e, e));
			}
		*longestEdge = sqrt(l2);
	}
	return fmDot(a, fmCross(b, c));
}

double fmTetMesh_TetVolume(const fmTetMesh* mesh, const double* positions, int tet)
{
	FM_ASSERT(mesh != NULL && tet >= 0 && tet < mesh->tetCount);
	const double* x = positions ? positions : mesh->positions;
	return fmTetSixVolume(x, mesh->tets + 4 * (size_t)tet, NULL) / 6.0;
}

static bool fmIsDegenerate(double sixVolume, double longestEdge)
{
	return !(fabs(sixVolume) > FM_DEGENERATE_RATIO * longestEdge * longestEdge * longestEdge);
}

// Node references in range and distinct, for every tet (a mesh may be built by hand).
static fmResult fmCheckTetNodes(const fmTetMesh* mesh, fmDiagnostic* diag)
{
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		const int* v = mesh->tets + 4 * (size_t)t;
		for (int k = 0; k < 4; ++k)
		{
			if (v[k] < 0 || v[k] >= mesh->nodeCount)
				return fmDiagError(diag, fm_errIndex, "", 0, 0,
				                   "tet %d refers to node %d: expected 0 to %d (0-based)",
				                   t + mesh->firstIndex, v[k], mesh->nodeCount - 1);
			for (int j = 0; j < k; ++j)
				if (v[j] == v[k])
					return fmDiagError(diag, fm_errIndex, "", 0, 0,
					                   "tet %d repeats node %d: expected 4 distinct nodes",
					                   t + mesh->firstIndex, v[k] + mesh->firstIndex);
		}
	}
	return fm_ok;
}

// Every tet must have a volume that is not zero relative to its size.
static fmResult fmCheckTetVolumes(const fmTetMesh* mesh, fmDiagnostic* diag)
{
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		double edge;
		double six = fmTetSixVolume(mesh->positions, mesh->tets + 4 * (size_t)t, &edge);
		if (fmIsDegenerate(six, edge))
			return fmDiagError(diag, fm_errDegenerate, "", 0, 0,
			                   "tet %d (in the file's numbering) has zero volume: 6V = %.3g with "
			                   "longest edge %.3g, expected |6V| > %.0e * edge^3",
			                   t + mesh->firstIndex, six, edge, FM_DEGENERATE_RATIO);
	}
	return fm_ok;
}

fmResult fmTetMesh_Orient(fmTetMesh* mesh, int* flipped, fmDiagnostic* diag)
{
	FM_ASSERT(mesh != NULL);
	if (flipped)
		*flipped = 0;
	// Check everything first, so a failing mesh is left untouched.
	fmResult result = fmCheckTetNodes(mesh, diag);
	if (result == fm_ok)
		result = fmCheckTetVolumes(mesh, diag);
	if (result != fm_ok)
		return result;
	int count = 0;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		int* v = mesh->tets + 4 * (size_t)t;
		if (fmTetSixVolume(mesh->positions, v, NULL) > 0.0)
			continue;
		// Exchanging two nodes negates the determinant.
		int s = v[2];
		v[2] = v[3];
		v[3] = s;
		++count;
	}
	if (flipped)
		*flipped = count;
	return fm_ok;
}

// ---- surface ----------------------------------------------------------------------------------

// The faces of tet (a, b, c, d), wound counter-clockwise seen from outside when the tet is
// positively oriented, i.e. (b - a) . ((c - a) x (d - a)) > 0: face k is opposite node k.
static const int s_tetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

typedef struct fmFaceKey
{
	int v[3]; // sorted node indices
	int face; // 4 * tet + local face
} fmFaceKey;

static int fmCompareFaceKeys(const void* a, const void* b)
{
	const fmFaceKey* p = a;
	const fmFaceKey* q = b;
	for (int k = 0; k < 3; ++k)
		if (p->v[k] != q->v[k])
			return p->v[k] < q->v[k] ? -1 : 1;
	return p->face < q->face ? -1 : (p->face > q->face);
}

static fmFaceKey fmMakeFaceKey(const int* tet, int t, int f)
{
	fmFaceKey key;
	int a = tet[s_tetFaces[f][0]], b = tet[s_tetFaces[f][1]], c = tet[s_tetFaces[f][2]];
	int lo = a < b ? (a < c ? a : c) : (b < c ? b : c);
	int hi = a > b ? (a > c ? a : c) : (b > c ? b : c);
	key.v[0] = lo;
	key.v[1] = a + b + c - lo - hi;
	key.v[2] = hi;
	key.face = 4 * t + f;
	return key;
}

static int fmCompareInts(const void* a, const void* b)
{
	int p = *(const int*)a, q = *(const int*)b;
	return p < q ? -1 : (p > q);
}

// Boundary faces (used by exactly one tet), sorted by tet and local face for a stable order.
// Sorting the 4m face keys makes this O(m log m).
static int fmFindBoundaryFaces(const fmTetMesh* mesh, int** faces)
{
	size_t total = 4 * (size_t)mesh->tetCount;
	*faces = NULL;
	if (total == 0)
		return 0;
	fmFaceKey* keys = FM_ALLOC_ARRAY(fmFaceKey, total);
	if (keys == NULL)
		return -1;
	for (int t = 0; t < mesh->tetCount; ++t)
		for (int f = 0; f < 4; ++f)
			keys[4 * (size_t)t + (size_t)f] = fmMakeFaceKey(mesh->tets + 4 * (size_t)t, t, f);
	qsort(keys, total, sizeof *keys, fmCompareFaceKeys);
	int count = 0;
	int* out = (int*)keys; // compacted in place: entry k is read before slot count <= k is written
	for (size_t k = 0; k < total;)
	{
		size_t run = 1;
		while (k + run < total && memcmp(keys[k].v, keys[k + run].v, sizeof keys[k].v) == 0)
			++run;
		if (run == 1)
			out[count++] = keys[k].face;
		k += run;
	}
	qsort(out, (size_t)count, sizeof *out, fmCompareInts);
	*faces = out;
	return count;
}

fmResult fmTetMesh_ExtractSurface(const fmTetMesh* mesh, int** triangles, int* triangleCount)
{
	FM_ASSERT(mesh != NULL && triangles != NULL && triangleCount != NULL);
	*triangles = NULL;
	*triangleCount = 0;
	int* faces = NULL;
	int count = fmFindBoundaryFaces(mesh, &faces);
	if (count < 0)
		return fm_errOutOfMemory;
	int* out = fmAllocUser(fmMulSize(3 * sizeof(int), (size_t)count));
	if (out != NULL)
	{
		for (int k = 0; k < count; ++k)
		{
			int t = faces[k] / 4, f = faces[k] % 4;
			const int* v = mesh->tets + 4 * (size_t)t;
			// An inverted tet's faces point inwards: reverse them so the surface faces out.
			bool reverse = fmTetSixVolume(mesh->positions, v, NULL) < 0.0;
			out[3 * k] = v[s_tetFaces[f][0]];
			out[3 * k + 1] = v[s_tetFaces[f][reverse ? 2 : 1]];
			out[3 * k + 2] = v[s_tetFaces[f][reverse ? 1 : 2]];
		}
	}
	FM_FREE_ARRAY(faces, fmFaceKey, 4 * (size_t)mesh->tetCount);
	if (out == NULL)
		return fm_errOutOfMemory;
	*triangles = out;
	*triangleCount = count;
	return fm_ok;
}

// ---- statistics -------------------------------------------------------------------------------

// Quality measures of one tet.
typedef struct fmTetQuality
{
	double sixVolume;
	double longestEdge;
	double minDihedral; // radians
	double maxDihedral;
	double radiusRatio; // 3 r_in / r_circ, 1 for the regular tet, 0 when degenerate
} fmTetQuality;

// Dihedral angles from the face normals n_k (face opposite node k, all outward or all inward):
// the angle at the edge shared by faces k and l is pi - angle(n_k, n_l).
static void fmDihedralRange(const fmVec3* n, double* minAngle, double* maxAngle)
{
	*minAngle = FM_PI;
	*maxAngle = 0.0;
	for (int k = 0; k < 4; ++k)
		for (int l = k + 1; l < 4; ++l)
		{
			double denominator = fmLength(n[k]) * fmLength(n[l]);
			double c = denominator > 0.0 ? -fmDot(n[k], n[l]) / denominator : 1.0;
			double angle = acos(fmax(-1.0, fmin(1.0, c)));
			*minAngle = fmin(*minAngle, angle);
			*maxAngle = fmax(*maxAngle, angle);
		}
}

// r_in = 3V / (total face area); r_circ = |a^2 (b x c) + b^2 (c x a) + c^2 (a x b)| / (12 V)
// with a, b, c the edges from node 0 (the circumcentre offset formula).
static fmTetQuality fmMeasureTet(const double* x, const int* tet)
{
	fmTetQuality q;
	q.sixVolume = fmTetSixVolume(x, tet, &q.longestEdge);
	fmVec3 p[4];
	for (int k = 0; k < 4; ++k)
		p[k] = fmLoad(x, tet[k]);
	fmVec3 n[4];
	double area2 = 0.0; // twice the total face area
	for (int f = 0; f < 4; ++f)
	{
		fmVec3 a = p[s_tetFaces[f][0]], b = p[s_tetFaces[f][1]], c = p[s_tetFaces[f][2]];
		n[f] = fmCross(fmSub(b, a), fmSub(c, a));
		area2 += fmLength(n[f]);
	}
	fmDihedralRange(n, &q.minDihedral, &q.maxDihedral);
	fmVec3 a = fmSub(p[1], p[0]), b = fmSub(p[2], p[0]), c = fmSub(p[3], p[0]);
	fmVec3 r =
	    fmAdd(fmAdd(fmScale(fmDot(a, a), fmCross(b, c)), fmScale(fmDot(b, b), fmCross(c, a))),
	          fmScale(fmDot(c, c), fmCross(a, b)));
	double six = fabs(q.sixVolume);
	q.radiusRatio = 0.0;
	if (!fmIsDegenerate(q.sixVolume, q.longestEdge) && area2 > 0.0)
	{
		double rIn = six / area2;                 // 3V / A with A = area2 / 2 and V = six / 6
		double rCirc = fmLength(r) / (2.0 * six); // |r| / (12 V)
		q.radiusRatio = fmin(1.0, 3.0 * rIn / rCirc);
	}
	return q;
}

static void fmInfoAddTet(fmMeshInfo* info, const fmTetQuality* q, bool first)
{
	double volume = q->sixVolume / 6.0;
	double minDeg = q->minDihedral * (180.0 / FM_PI), maxDeg = q->maxDihedral * (180.0 / FM_PI);
	info->totalVolume += fabs(volume);
	info->minVolume = first ? volume : fmin(info->minVolume, volume);
	info->maxVolume = first ? volume : fmax(info->maxVolume, volume);
	info->minDihedralDeg = first ? minDeg : fmin(info->minDihedralDeg, minDeg);
	info->maxDihedralDeg = first ? maxDeg : fmax(info->maxDihedralDeg, maxDeg);
	info->minQuality = first ? q->radiusRatio : fmin(info->minQuality, q->radiusRatio);
	bool degenerate = fmIsDegenerate(q->sixVolume, q->longestEdge);
	bool inverted = !degenerate && q->sixVolume < 0.0;
	info->degenerateTets += degenerate;
	info->invertedTets += inverted;
	// Winding is not quality: the loader's Orient fixes it, so an inverted tet is not bad.
	info->badTets += degenerate || minDeg < 5.0;
}

// Unreferenced nodes and bounds; false when out of memory.
static bool fmInfoNodes(const fmTetMesh* mesh, fmMeshInfo* info)
{
	size_t n = (size_t)mesh->nodeCount;
	unsigned char* used = FM_ALLOC_ZERO(unsigned char, n);
	if (used == NULL && n > 0)
		return false;
	for (size_t k = 0; k < 4 * (size_t)mesh->tetCount; ++k)
		used[mesh->tets[k]] = 1;
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		fmVec3 p = fmLoad(mesh->positions, i);
		fmVec3 lo = i == 0 ? p : info->boundsMin, hi = i == 0 ? p : info->boundsMax;
		info->unreferencedNodes += !used[i];
		info->boundsMin = fmMakeVec3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
		info->boundsMax = fmMakeVec3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
	}
	FM_FREE_ARRAY(used, unsigned char, n);
	return true;
}

fmResult fmTetMesh_GetInfo(const fmTetMesh* mesh, fmMeshInfo* info)
{
	FM_ASSERT(mesh != NULL && info != NULL);
	memset(info, 0, sizeof *info);
	if (fmCheckTetNodes(mesh, NULL) != fm_ok)
		return fm_errIndex;
	info->nodeCount = mesh->nodeCount;
	info->tetCount = mesh->tetCount;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmTetQuality q = fmMeasureTet(mesh->positions, mesh->tets + 4 * (size_t)t);
		fmInfoAddTet(info, &q, t == 0);
	}
	int* triangles = NULL;
	if (fmTetMesh_ExtractSurface(mesh, &triangles, &info->surfaceTriangleCount) != fm_ok)
		return fm_errOutOfMemory;
	fmFree(triangles);
	return fmInfoNodes(mesh, info) ? fm_ok : fm_errOutOfMemory;
}

// ---- box meshes -------------------------------------------------------------------------------

// Kuhn (Freudenthal) split of a cube into the 6 tets around its main diagonal, one per
// permutation of the axes: corner 0 -> +e_a -> +e_b -> corner 7. Every cube is split the same
// way, so each shared face is cut along the same diagonal and neighbours conform. The corner
// bits are x = 1, y = 2, z = 4; node order is chosen so each tet is positively oriented (odd
// permutations have their middle nodes exchanged).
static const int s_kuhnTets[6][4] = {
    {0, 1, 3, 7}, // x, y, z
    {0, 3, 2, 7}, // y, x, z (odd)
    {0, 2, 6, 7}, // y, z, x
    {0, 6, 4, 7}, // z, y, x (odd)
    {0, 4, 5, 7}, // z, x, y
    {0, 5, 1, 7}, // x, z, y (odd)
};

static fmResult fmCheckBoxParameters(int nx, int ny, int nz, fmVec3 min, fmVec3 max)
{
	if (nx < 1 || ny < 1 || nz < 1)
		return fm_errParameter;
	if (!(min.x < max.x && min.y < max.y && min.z < max.z))
		return fm_errParameter; // also rejects NaN
	if (!isfinite(min.x) || !isfinite(min.y) || !isfinite(min.z) || !isfinite(max.x) ||
	    !isfinite(max.y) || !isfinite(max.z))
		return fm_errParameter;
	long long cubes = (long long)nx * ny * nz;
	if (cubes > FM_MAX_TETS / 6)
		return fm_errLimit;
	long long nodes = (long long)(nx + 1) * (ny + 1) * (nz + 1);
	if (nodes > FM_MAX_NODES)
		return fm_errLimit;
	return fm_ok;
}

static void fmFillBoxNodes(fmTetMesh* mesh, int nx, int ny, int nz, fmVec3 min, fmVec3 max)
{
	int n = 0;
	for (int k = 0; k <= nz; ++k)
		for (int j = 0; j <= ny; ++j)
			for (int i = 0; i <= nx; ++i)
			{
				// Exact ends: the last node lands on max, not on min + n * h.
				fmVec3 p =
				    fmMakeVec3(min.x + (max.x - min.x) * i / nx, min.y + (max.y - min.y) * j / ny,
				               min.z + (max.z - min.z) * k / nz);
				fmStore(mesh->positions, n++, p);
			}
}

static void fmFillBoxTets(fmTetMesh* mesh, int nx, int ny, int nz)
{
	int t = 0;
	for (int k = 0; k < nz; ++k)
		for (int j = 0; j < ny; ++j)
			for (int i = 0; i < nx; ++i)
			{
				int corner[8];
				for (int c = 0; c < 8; ++c)
					corner[c] = (i + (c & 1)) +
					            (nx + 1) * ((j + ((c >> 1) & 1)) + (ny + 1) * (k + ((c >> 2) & 1)));
				for (int s = 0; s < 6; ++s, ++t)
					for (int a = 0; a < 4; ++a)
						mesh->tets[4 * (size_t)t + (size_t)a] = corner[s_kuhnTets[s][a]];
			}
}

fmResult fmMakeBoxMesh(int nx, int ny, int nz, fmVec3 min, fmVec3 max, fmTetMesh* mesh)
{
	FM_ASSERT(mesh != NULL);
	memset(mesh, 0, sizeof *mesh);
	fmResult result = fmCheckBoxParameters(nx, ny, nz, min, max);
	if (result != fm_ok)
		return result;
	fmTetMesh m;
	memset(&m, 0, sizeof m);
	m.nodeCount = (nx + 1) * (ny + 1) * (nz + 1);
	m.tetCount = 6 * nx * ny * nz;
	m.positions = FM_ALLOC_ARRAY(double, 3 * (size_t)m.nodeCount);
	m.tets = FM_ALLOC_ARRAY(int, 4 * (size_t)m.tetCount);
	if (m.positions == NULL || m.tets == NULL)
	{
		fmFreeTetMesh(&m);
		return fm_errOutOfMemory;
	}
	fmFillBoxNodes(&m, nx, ny, nz, min, max);
	fmFillBoxTets(&m, nx, ny, nz);
	*mesh = m;
	return fm_ok;
}
