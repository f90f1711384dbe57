// Mesh utilities: ownership (free, copy), placement, orientation, volumes, statistics,
// boundary extraction and generated box meshes.
#include "core/core.h"
#include "core/det_math.h"
#include "mesh/mesh_internal.h"

#include <float.h>
#include <limits.h>
#include <math.h>
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

// Counts and arrays agree (a mesh built by hand may not): anything else is a programmer error.
static bool fmMeshIsConsistent(const fmTetMesh* m)
{
	return m != NULL && m->nodeCount >= 0 && m->tetCount >= 0 &&
	       (m->nodeCount == 0 || m->positions != NULL) && (m->tetCount == 0 || m->tets != NULL) &&
	       m->nodeAttributeCount >= 0 && m->nodeAttributeCount <= FM_MAX_ATTRIBUTES &&
	       m->tetAttributeCount >= 0 && m->tetAttributeCount <= FM_MAX_ATTRIBUTES &&
	       (m->nodeAttributeCount == 0 || m->nodeCount == 0 || m->nodeAttributes != NULL) &&
	       (m->tetAttributeCount == 0 || m->tetCount == 0 || m->tetAttributes != NULL);
}

fmResult fmCopyTetMesh(const fmTetMesh* source, fmTetMesh* copy)
{
	FM_ASSERT(fmMeshIsConsistent(source) && copy != NULL);
	if (copy != NULL)
		memset(copy, 0, sizeof *copy);
	if (!fmMeshIsConsistent(source) || copy == NULL)
		return fm_errParameter;
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

static bool fmIsFiniteVec3(fmVec3 v)
{
	return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

void fmTetMesh_Transform(fmTetMesh* mesh, const fmMeshTransform* transform)
{
	bool valid = fmMeshIsConsistent(mesh) && transform != NULL && transform->scale > 0.0 &&
	             isfinite(transform->scale) && fmIsFiniteVec3(transform->translate);
	FM_ASSERT(valid);
	if (!valid)
		return;
	fmTransformPoints(mesh->positions, mesh->nodeCount, transform);
}

void fmTransformPoints(double* x, int n, const fmMeshTransform* transform)
{
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

// ---- shape of one tet -------------------------------------------------------------------------

// A tet scaled by a power of two so that its longest edge lies in [0.5, 1). Scaling by a power
// of two is exact, so signs and ratios are those of the coordinates as given, and no product of
// edges can overflow or underflow whatever the mesh's units (1e300 m or 1e-100 m). Lengths in
// metres are the scaled ones times 2^exponent, volumes times 2^(3 exponent).
typedef struct fmTetShape
{
	fmVec3 p[4];      // scaled nodes, translated so that p[0] is the origin
	double longest;   // scaled longest edge: in [0.5, 1), or 0 when the four nodes coincide
	double sixVolume; // scaled 6 V = p1 . (p2 x p3), in [-1, 1]
	int exponent;
	bool finite; // false when a coordinate is inf or NaN (nothing else is set)
} fmTetShape;

static fmVec3 fmLdexpVec3(fmVec3 v, int exponent)
{
	return fmMakeVec3(ldexp(v.x, exponent), ldexp(v.y, exponent), ldexp(v.z, exponent));
}

static fmTetShape fmMakeTetShape(const double* x, const int* tet)
{
	fmTetShape s;
	memset(&s, 0, sizeof s);
	fmVec3 q[4];
	double largest = 0.0;
	for (int k = 0; k < 4; ++k)
	{
		q[k] = fmLoad(x, tet[k]);
		if (!fmIsFiniteVec3(q[k]))
			return s;
		largest = fmMax(largest, fmMax(fabs(q[k].x), fmMax(fabs(q[k].y), fabs(q[k].z))));
	}
	s.finite = true;
	// First bring the coordinates below 1 so the differences cannot overflow ...
	int e1 = 0;
	(void)frexp(largest, &e1);
	double l2 = 0.0;
	for (int k = 0; k < 4; ++k)
		q[k] = fmLdexpVec3(q[k], -e1);
	for (int i = 0; i < 4; ++i)
		for (int j = i + 1; j < 4; ++j)
		{
			fmVec3 e = fmSub(q[j], q[i]);
			l2 = fmMax(l2, fmDot(e, e));
		}
	if (l2 == 0.0)
		return s;
	// ... then bring the longest edge into [0.5, 1).
	int e2 = 0;
	(void)frexp(sqrt(l2), &e2);
	for (int k = 1; k < 4; ++k)
		s.p[k] = fmLdexpVec3(fmSub(q[k], q[0]), -e2);
	s.longest = ldexp(sqrt(l2), -e2);
	s.exponent = e1 + e2;
	s.sixVolume = fmDot(s.p[1], fmCross(s.p[2], s.p[3]));
	return s;
}

// |6 V| <= FM_DEGENERATE_RATIO * (longest edge)^3, decided on the scaled tet: scale-free.
static bool fmShapeIsDegenerate(const fmTetShape* s)
{
	return !(fabs(s->sixVolume) > FM_DEGENERATE_RATIO * s->longest * s->longest * s->longest);
}

// The volume in m^3: +-inf or 0 (or subnormal) when it lies beyond the range of a double.
static double fmShapeVolume(const fmTetShape* s)
{
	return ldexp(s->sixVolume / 6.0, 3 * s->exponent);
}

// A well-shaped tet whose volume in m^3 a double cannot hold (edges beyond about 1e102 m or
// below about 1e-102 m): its mass and stiffness would be inf or 0.
static bool fmShapeVolumeOutOfRange(const fmTetShape* s)
{
	double v = fabs(fmShapeVolume(s));
	return !fmShapeIsDegenerate(s) && !(v >= DBL_MIN && v <= DBL_MAX);
}

// ---- orientation and volume -------------------------------------------------------------------

// Node references in range and distinct (a mesh may be built by hand).
static bool fmTetNodesValid(const fmTetMesh* mesh, const int* v)
{
	for (int k = 0; k < 4; ++k)
	{
		if (v[k] < 0 || v[k] >= mesh->nodeCount)
			return false;
		for (int j = 0; j < k; ++j)
			if (v[j] == v[k])
				return false;
	}
	return true;
}

double fmTetMesh_TetVolume(const fmTetMesh* mesh, const double* positions, int tet)
{
	bool valid = fmMeshIsConsistent(mesh) && tet >= 0 && tet < mesh->tetCount &&
	             fmTetNodesValid(mesh, mesh->tets + 4 * (size_t)tet);
	FM_ASSERT(valid);
	if (!valid)
		return NAN;
	const double* x = positions ? positions : mesh->positions;
	fmTetShape shape = fmMakeTetShape(x, mesh->tets + 4 * (size_t)tet);
	return shape.finite ? fmShapeVolume(&shape) : NAN;
}

// Node references in range and distinct, for every tet.
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

// What is wrong with tet @p t's shape, if anything: a non-finite coordinate, a volume that is
// zero relative to the tet's size, or a volume a double cannot hold.
static fmResult fmCheckTetShape(const fmTetMesh* mesh, int t, fmDiagnostic* diag)
{
	fmTetShape s = fmMakeTetShape(mesh->positions, mesh->tets + 4 * (size_t)t);
	int number = t + mesh->firstIndex;
	if (!s.finite)
		return fmDiagError(diag, fm_errRange, "", 0, 0,
		                   "tet %d (in the file's numbering) has a node with a non-finite "
		                   "coordinate (inf or NaN): expected finite positions",
		                   number);
	double six = ldexp(s.sixVolume, 3 * s.exponent), edge = ldexp(s.longest, s.exponent);
	if (fmShapeIsDegenerate(&s))
		return fmDiagError(diag, fm_errDegenerate, "", 0, 0,
		                   "tet %d (in the file's numbering) has zero volume: 6V = %.3g with "
		                   "longest edge %.3g, expected |6V| > %.0e * edge^3",
		                   number, six, edge, FM_DEGENERATE_RATIO);
	if (fmShapeVolumeOutOfRange(&s))
		return fmDiagError(diag, fm_errRange, "", 0, 0,
		                   "tet %d (in the file's numbering) is well shaped but its volume is out "
		                   "of the range of a double: 6V = %.3g with longest edge %.3g m, expected "
		                   "edges between about 1e-102 and 1e102 m (coordinates in metres)",
		                   number, six, edge);
	return fm_ok;
}

fmResult fmTetMesh_Orient(fmTetMesh* mesh, int* flipped, fmDiagnostic* diag)
{
	if (flipped)
		*flipped = 0;
	FM_ASSERT(fmMeshIsConsistent(mesh));
	if (!fmMeshIsConsistent(mesh))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "expected a mesh whose counts and arrays agree");
	// Check everything first, so a failing mesh is left untouched.
	fmResult result = fmCheckTetNodes(mesh, diag);
	for (int t = 0; t < mesh->tetCount && result == fm_ok; ++t)
		result = fmCheckTetShape(mesh, t, diag);
	if (result != fm_ok)
		return result;
	int count = 0;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		int* v = mesh->tets + 4 * (size_t)t;
		if (fmMakeTetShape(mesh->positions, v).sixVolume > 0.0)
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
	FM_ASSERT(fmMeshIsConsistent(mesh) && triangles != NULL && triangleCount != NULL);
	if (triangles != NULL)
		*triangles = NULL;
	if (triangleCount != NULL)
		*triangleCount = 0;
	if (!fmMeshIsConsistent(mesh) || triangles == NULL || triangleCount == NULL)
		return fm_errParameter;
	// Out-of-range nodes would be read as positions below.
	if (fmCheckTetNodes(mesh, NULL) != fm_ok)
		return fm_errIndex;
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
			bool reverse = fmMakeTetShape(mesh->positions, v).sixVolume < 0.0;
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
			double angle = acos(fmMax(-1.0, fmMin(1.0, c)));
			*minAngle = fmMin(*minAngle, angle);
			*maxAngle = fmMax(*maxAngle, angle);
		}
}

// Measured on the scaled tet (longest edge in [0.5, 1)), so angles and the radius ratio do not
// depend on the units: r_in = 3V / (total face area); r_circ = |a^2 (b x c) + b^2 (c x a) +
// c^2 (a x b)| / (12 V) with a, b, c the edges from node 0 (the circumcentre offset formula).
static fmTetQuality fmMeasureShape(const fmTetShape* s)
{
	fmTetQuality q;
	memset(&q, 0, sizeof q);
	q.volume = fmShapeVolume(s);
	q.longestEdge = ldexp(s->longest, s->exponent);
	q.degenerate = fmShapeIsDegenerate(s);
	q.volumeOutOfRange = fmShapeVolumeOutOfRange(s);
	const fmVec3* p = s->p;
	fmVec3 n[4];
	double area2 = 0.0; // twice the total face area
	for (int f = 0; f < 4; ++f)
	{
		fmVec3 a = p[s_tetFaces[f][0]], b = p[s_tetFaces[f][1]], c = p[s_tetFaces[f][2]];
		n[f] = fmCross(fmSub(b, a), fmSub(c, a));
		area2 += fmLength(n[f]);
	}
	double minAngle, maxAngle;
	fmDihedralRange(n, &minAngle, &maxAngle);
	q.minDihedralDeg = minAngle * (180.0 / FM_PI);
	q.maxDihedralDeg = maxAngle * (180.0 / FM_PI);
	fmVec3 a = p[1], b = p[2], c = p[3];
	fmVec3 r =
	    fmAdd(fmAdd(fmScale(fmDot(a, a), fmCross(b, c)), fmScale(fmDot(b, b), fmCross(c, a))),
	          fmScale(fmDot(c, c), fmCross(a, b)));
	double six = fabs(s->sixVolume);
	if (!q.degenerate && area2 > 0.0)
	{
		double rIn = six / area2;                 // 3V / A with A = area2 / 2 and V = six / 6
		double rCirc = fmLength(r) / (2.0 * six); // |r| / (12 V)
		q.radiusRatio = fmMin(1.0, 3.0 * rIn / rCirc);
	}
	return q;
}

fmResult fmTetMesh_GetTetQuality(const fmTetMesh* mesh, int tet, fmTetQuality* quality)
{
	bool valid = fmMeshIsConsistent(mesh) && tet >= 0 && tet < mesh->tetCount && quality != NULL;
	FM_ASSERT(valid);
	if (quality != NULL)
		memset(quality, 0, sizeof *quality);
	if (!valid)
		return fm_errParameter;
	const int* v = mesh->tets + 4 * (size_t)tet;
	if (!fmTetNodesValid(mesh, v))
		return fm_errIndex;
	fmTetShape shape = fmMakeTetShape(mesh->positions, v);
	if (!shape.finite)
		return fm_errRange;
	*quality = fmMeasureShape(&shape);
	return fm_ok;
}

static void fmInfoAddTet(fmMeshInfo* info, const fmTetQuality* q, bool first)
{
	info->totalVolume += fabs(q->volume);
	info->minVolume = first ? q->volume : fmMin(info->minVolume, q->volume);
	info->maxVolume = first ? q->volume : fmMax(info->maxVolume, q->volume);
	info->minDihedralDeg =
	    first ? q->minDihedralDeg : fmMin(info->minDihedralDeg, q->minDihedralDeg);
	info->maxDihedralDeg =
	    first ? q->maxDihedralDeg : fmMax(info->maxDihedralDeg, q->maxDihedralDeg);
	info->minQuality = first ? q->radiusRatio : fmMin(info->minQuality, q->radiusRatio);
	bool inverted = !q->degenerate && q->volume < 0.0;
	info->degenerateTets += q->degenerate;
	info->invertedTets += inverted;
	info->volumeOutOfRangeTets += q->volumeOutOfRange;
	// Winding is not quality: the loader's Orient fixes it, so an inverted tet is not bad.
	info->badTets += q->degenerate || q->minDihedralDeg < 5.0;
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
		info->boundsMin = fmMakeVec3(fmMin(lo.x, p.x), fmMin(lo.y, p.y), fmMin(lo.z, p.z));
		info->boundsMax = fmMakeVec3(fmMax(hi.x, p.x), fmMax(hi.y, p.y), fmMax(hi.z, p.z));
	}
	FM_FREE_ARRAY(used, unsigned char, n);
	return true;
}

fmResult fmTetMesh_GetInfo(const fmTetMesh* mesh, fmMeshInfo* info)
{
	FM_ASSERT(fmMeshIsConsistent(mesh) && info != NULL);
	if (info != NULL)
		memset(info, 0, sizeof *info);
	if (!fmMeshIsConsistent(mesh) || info == NULL)
		return fm_errParameter;
	if (fmCheckTetNodes(mesh, NULL) != fm_ok)
		return fm_errIndex;
	for (size_t k = 0; k < 3 * (size_t)mesh->nodeCount; ++k)
		if (!isfinite(mesh->positions[k]))
			return fm_errRange;
	info->nodeCount = mesh->nodeCount;
	info->tetCount = mesh->tetCount;
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		fmTetShape shape = fmMakeTetShape(mesh->positions, mesh->tets + 4 * (size_t)t);
		fmTetQuality q = fmMeasureShape(&shape);
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
	// Step by step, each product bounded before the next: nx * ny * nz overflows even a long long
	// and nx + 1 overflows an int for nx = INT_MAX.
	const long long maxCubes = FM_MAX_TETS / 6;
	long long cubes = nx;
	if (cubes > maxCubes || ny > maxCubes / cubes)
		return fm_errLimit;
	cubes *= ny;
	if (nz > maxCubes / cubes)
		return fm_errLimit;
	cubes *= nz;
	// At most 8 nodes per cube, so this product stays far below LLONG_MAX.
	long long nodes = ((long long)nx + 1) * ((long long)ny + 1) * ((long long)nz + 1);
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
	if (mesh == NULL)
		return fm_errParameter;
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
