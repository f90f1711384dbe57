// Mesh utilities: orientation, volumes, surfaces (closed, outward, divergence theorem), box
// meshes (conforming, positive), statistics against geometry, transform order, memory.
#include "support.h"
#include "test.h"

#include <femto/femto.h>
#include <limits.h>
#include <stdlib.h>

static const double s_pi = 3.14159265358979323846;

// A mesh from literal arrays (copied, so fmFreeTetMesh can free it).
static fmTetMesh makeMesh(const double* x, int nodeCount, const int* tets, int tetCount)
{
	fmTetMesh source;
	memset(&source, 0, sizeof source);
	source.nodeCount = nodeCount;
	source.positions = (double*)x;
	source.tetCount = tetCount;
	source.tets = (int*)tets;
	fmTetMesh copy;
	fmCopyTetMesh(&source, &copy);
	return copy;
}

static fmTetMesh loadHouse(void)
{
	fmTetMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	fmLoadTetGen(FEMTO_MESH_DIR "/house2.node", FEMTO_MESH_DIR "/house2.ele", &mesh, NULL);
	return mesh;
}

static double volumeSum(const fmTetMesh* mesh)
{
	double sum = 0.0;
	for (int t = 0; t < mesh->tetCount; ++t)
		sum += fmTetMesh_TetVolume(mesh, NULL, t);
	return sum;
}

// Divergence theorem: V = (1/3) sum over faces of (centroid . area vector) = sum p0.(p1 x p2)/6.
static double enclosedVolume(const fmTetMesh* mesh, const int* tri, int count)
{
	double sum = 0.0;
	for (int k = 0; k < count; ++k)
	{
		fmVec3 a = fmLoad(mesh->positions, tri[3 * k]), b = fmLoad(mesh->positions, tri[3 * k + 1]);
		fmVec3 c = fmLoad(mesh->positions, tri[3 * k + 2]);
		sum += fmDot(a, fmCross(b, c)) / 6.0;
	}
	return sum;
}

typedef struct Edge
{
	int a, b;
} Edge;

static int compareEdges(const void* p, const void* q)
{
	const Edge* e = p;
	const Edge* f = q;
	return e->a != f->a ? (e->a < f->a ? -1 : 1) : (e->b < f->b ? -1 : (e->b > f->b));
}

// Closed and consistently wound: every directed edge appears once and its reverse once.
static bool surfaceIsClosedAndConsistent(const int* tri, int count)
{
	Edge* edges = malloc(sizeof(Edge) * 3 * (size_t)count);
	for (int k = 0; k < count; ++k)
		for (int e = 0; e < 3; ++e)
			edges[3 * k + e] = (Edge){tri[3 * k + e], tri[3 * k + (e + 1) % 3]};
	qsort(edges, 3 * (size_t)count, sizeof *edges, compareEdges);
	bool ok = count > 0;
	for (int k = 0; k < 3 * count && ok; ++k)
	{
		Edge reverse = {edges[k].b, edges[k].a};
		ok = (k == 0 || compareEdges(&edges[k - 1], &edges[k]) != 0) &&
		     bsearch(&reverse, edges, 3 * (size_t)count, sizeof *edges, compareEdges) != NULL;
	}
	free(edges);
	return ok;
}

// ---- orientation and volume -------------------------------------------------------------------

TEST(orient_flips_negative_tets_only)
{
	// The unit corner tet twice: once positive, once with two nodes exchanged.
	const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	const int tets[] = {0, 1, 2, 3, 0, 2, 1, 3};
	fmTetMesh mesh = makeMesh(x, 4, tets, 2);
	CHECK(fmTetMesh_TetVolume(&mesh, NULL, 1) < 0.0);
	int flipped = -1;
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, NULL), fm_ok);
	CHECK_INT(flipped, 1);
	CHECK_INT(mesh.tets[0], 0); // the positive tet is unchanged
	CHECK_INT(mesh.tets[3], 3);
	CHECK_NEAR(fmTetMesh_TetVolume(&mesh, NULL, 1), 1.0 / 6.0, 1e-15);
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, NULL), fm_ok); // idempotent
	CHECK_INT(flipped, 0);
	fmFreeTetMesh(&mesh);
}

TEST(orient_errors_leave_the_mesh_untouched)
{
	const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0};
	const int negativeThenRepeated[] = {0, 2, 1, 3, 0, 1, 1, 3};
	fmTetMesh mesh = makeMesh(x, 5, negativeThenRepeated, 2);
	fmDiagnostic diag;
	CHECK_INT(fmTetMesh_Orient(&mesh, NULL, &diag), fm_errIndex);
	CHECK_STR_CONTAINS(diag.message, "tet 1 repeats node 1");
	CHECK_INT(mesh.tets[1], 2);
	mesh.tets[6] = 7;
	CHECK_INT(fmTetMesh_Orient(&mesh, NULL, &diag), fm_errIndex);
	CHECK_STR_CONTAINS(diag.message, "tet 1 refers to node 7: expected 0 to 4");
	fmFreeTetMesh(&mesh);
}

TEST(degenerate_is_relative_to_size)
{
	// A tiny well-shaped tet (1e-6 m edges) is fine; a sliver 1e-13 of its edge thick is not.
	const double tiny[] = {0, 0, 0, 1e-6, 0, 0, 0, 1e-6, 0, 0, 0, 1e-6};
	const double sliver[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1e-13};
	const int tet[] = {0, 1, 2, 3};
	fmTetMesh a = makeMesh(tiny, 4, tet, 1), b = makeMesh(sliver, 4, tet, 1);
	CHECK_INT(fmTetMesh_Orient(&a, NULL, NULL), fm_ok);
	fmDiagnostic diag;
	CHECK_INT(fmTetMesh_Orient(&b, NULL, &diag), fm_errDegenerate);
	CHECK_STR_CONTAINS(diag.message, "tet 0 (in the file's numbering) has zero volume");
	fmFreeTetMesh(&a);
	fmFreeTetMesh(&b);
}

TEST(tet_volume_invariances)
{
	// Volume is translation invariant, scales with s^3 and changes sign with a node swap.
	double x[12];
	for (int k = 0; k < 12; ++k)
		x[k] = fmTestRandom(-1.0, 1.0);
	const int tet[] = {0, 1, 2, 3};
	fmTetMesh mesh = makeMesh(x, 4, tet, 1);
	double v = fmTetMesh_TetVolume(&mesh, NULL, 0);
	double moved[12];
	for (int k = 0; k < 12; ++k)
		moved[k] = 2.5 * x[k] + (k % 3 == 1 ? 7.0 : -3.0);
	CHECK_REL(fmTetMesh_TetVolume(&mesh, moved, 0), 2.5 * 2.5 * 2.5 * v, 1e-12, 1e-12);
	mesh.tets[0] = 1;
	mesh.tets[1] = 0;
	CHECK_REL(fmTetMesh_TetVolume(&mesh, NULL, 0), -v, 1e-14, 1e-14);
	fmFreeTetMesh(&mesh);
}

// ---- surfaces ---------------------------------------------------------------------------------

TEST(box_surface_closed_outward_divergence)
{
	int nx = 3, ny = 2, nz = 4;
	fmVec3 lo = fmMakeVec3(-1.0, 0.5, 2.0), hi = fmMakeVec3(2.0, 1.5, 6.0);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(nx, ny, nz, lo, hi, &mesh), fm_ok);
	int* tri = NULL;
	int count = 0;
	CHECK_INT(fmTetMesh_ExtractSurface(&mesh, &tri, &count), fm_ok);
	// Each boundary square is two triangles; more would mean non-conforming cubes.
	CHECK_INT(count, 4 * (nx * ny + ny * nz + nz * nx));
	CHECK(surfaceIsClosedAndConsistent(tri, count));
	double boxVolume = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
	CHECK_REL(volumeSum(&mesh), boxVolume, 1e-12, 1.0);
	CHECK_REL(enclosedVolume(&mesh, tri, count), boxVolume, 1e-12, 1.0);
	// Convex box: every normal points away from the centre.
	fmVec3 centre = fmScale(0.5, fmAdd(lo, hi));
	int outward = 0;
	for (int k = 0; k < count; ++k)
	{
		fmVec3 a = fmLoad(mesh.positions, tri[3 * k]), b = fmLoad(mesh.positions, tri[3 * k + 1]);
		fmVec3 c = fmLoad(mesh.positions, tri[3 * k + 2]);
		fmVec3 n = fmCross(fmSub(b, a), fmSub(c, a));
		outward += fmDot(n, fmSub(a, centre)) > 0.0;
	}
	CHECK_INT(outward, count);
	fmFree(tri);
	fmFreeTetMesh(&mesh);
}

TEST(house_surface_closed_and_outward)
{
	fmTetMesh mesh = loadHouse();
	CHECK_INT(fmTetMesh_Orient(&mesh, NULL, NULL), fm_ok);
	int* tri = NULL;
	int count = 0;
	CHECK_INT(fmTetMesh_ExtractSurface(&mesh, &tri, &count), fm_ok);
	CHECK(surfaceIsClosedAndConsistent(tri, count));
	CHECK_REL(enclosedVolume(&mesh, tri, count), volumeSum(&mesh), 1e-12, 1.0);
	fmFree(tri);
	// Without orienting, inverted tets' faces are reversed: the surface still faces out.
	fmMeshTransform swap = fmDefaultMeshTransform();
	swap.swapYZ = true;
	fmTetMesh_Transform(&mesh, &swap);
	CHECK(volumeSum(&mesh) < 0.0);
	CHECK_INT(fmTetMesh_ExtractSurface(&mesh, &tri, &count), fm_ok);
	CHECK_REL(enclosedVolume(&mesh, tri, count), -volumeSum(&mesh), 1e-12, 1.0);
	fmFree(tri);
	fmFreeTetMesh(&mesh);
}

// ---- box meshes -------------------------------------------------------------------------------

TEST(box_mesh_conforming_and_positive)
{
	int nx = 2, ny = 3, nz = 2;
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(nx, ny, nz, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	CHECK_INT(mesh.nodeCount, (nx + 1) * (ny + 1) * (nz + 1));
	CHECK_INT(mesh.tetCount, 6 * nx * ny * nz);
	double cell = 1.0 / (nx * ny * nz);
	int positive = 0;
	for (int t = 0; t < mesh.tetCount; ++t)
		positive += fabs(fmTetMesh_TetVolume(&mesh, NULL, t) - cell / 6.0) < 1e-15;
	CHECK_INT(positive, mesh.tetCount); // every tet positive, a sixth of its cube
	int flipped = -1;
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, NULL), fm_ok);
	CHECK_INT(flipped, 0);
	// Conforming: the faces inside pair up exactly, so the boundary is only the box's skin.
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&mesh, &info), fm_ok);
	CHECK_INT(info.surfaceTriangleCount, 4 * (nx * ny + ny * nz + nz * nx));
	CHECK_INT(info.unreferencedNodes, 0);
	fmFreeTetMesh(&mesh);
}

TEST(box_mesh_parameters)
{
	fmTetMesh mesh;
	fmVec3 lo = fmMakeVec3(0, 0, 0), hi = fmMakeVec3(1, 1, 1);
	CHECK_INT(fmMakeBoxMesh(0, 1, 1, lo, hi, &mesh), fm_errParameter);
	CHECK_INT(fmMakeBoxMesh(1, -2, 1, lo, hi, &mesh), fm_errParameter);
	CHECK_INT(fmMakeBoxMesh(1, 1, 1, hi, lo, &mesh), fm_errParameter);
	CHECK_INT(fmMakeBoxMesh(1, 1, 1, lo, fmMakeVec3(1, 0, 1), &mesh), fm_errParameter);
	CHECK_INT(fmMakeBoxMesh(1, 1, 1, lo, fmMakeVec3(1, NAN, 1), &mesh), fm_errParameter);
	CHECK_INT(fmMakeBoxMesh(1000, 1000, 1000, lo, hi, &mesh), fm_errLimit);
	CHECK_INT(fmMakeBoxMesh(65536, 65536, 65536, lo, hi, &mesh),
	          fm_errLimit); // product overflows int
	CHECK(mesh.positions == NULL && mesh.nodeCount == 0);
}

// ---- statistics -------------------------------------------------------------------------------

TEST(info_regular_tet)
{
	// Alternate corners of a cube: a regular tet of edge sqrt(2), volume 1/3.
	const double x[] = {0, 0, 0, 1, 1, 0, 1, 0, 1, 0, 1, 1};
	const int tet[] = {0, 1, 2, 3};
	fmTetMesh mesh = makeMesh(x, 4, tet, 1);
	if (fmTetMesh_TetVolume(&mesh, NULL, 0) < 0.0)
		fmTetMesh_Orient(&mesh, NULL, NULL);
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&mesh, &info), fm_ok);
	double dihedral = acos(1.0 / 3.0) * 180.0 / s_pi;
	CHECK_NEAR(info.minDihedralDeg, dihedral, 1e-9);
	CHECK_NEAR(info.maxDihedralDeg, dihedral, 1e-9);
	CHECK_NEAR(info.minQuality, 1.0, 1e-12);
	CHECK_NEAR(info.totalVolume, 1.0 / 3.0, 1e-15);
	CHECK_NEAR(info.minVolume, 1.0 / 3.0, 1e-15);
	CHECK_INT(info.surfaceTriangleCount, 4);
	CHECK_INT(info.badTets + info.invertedTets + info.degenerateTets + info.unreferencedNodes, 0);
	CHECK(info.boundsMin.x == 0.0 && info.boundsMax.z == 1.0);
	fmFreeTetMesh(&mesh);
}

TEST(info_box_kuhn_tets)
{
	// Every Kuhn tet has dihedral angles of 45, 60 and 90 degrees; its circumsphere is the
	// cube's (R = sqrt(3)/2 h) and r_in = 3V/A with A = (1 + sqrt 2) h^2: 3r/R = sqrt3/(1+sqrt2).
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(-1, -1, -1), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&mesh, &info), fm_ok);
	CHECK_NEAR(info.minDihedralDeg, 45.0, 1e-9);
	CHECK_NEAR(info.maxDihedralDeg, 90.0, 1e-9);
	CHECK_NEAR(info.minQuality, sqrt(3.0) / (1.0 + sqrt(2.0)), 1e-12);
	CHECK_NEAR(info.totalVolume, 8.0, 1e-12);
	CHECK_NEAR(info.minVolume, 1.0 / 6.0, 1e-15);
	CHECK_NEAR(info.maxVolume, 1.0 / 6.0, 1e-15);
	CHECK(info.boundsMin.x == -1.0 && info.boundsMax.y == 1.0);
	CHECK_INT(info.nodeCount, 27);
	CHECK_INT(info.tetCount, 48);
	fmFreeTetMesh(&mesh);
}

TEST(info_counts_bad_tets)
{
	// One good tet, one inverted copy, one flat tet, one sliver of 2 degrees, an unused node.
	double sliverHeight = tan(2.0 * s_pi / 180.0) * 0.5;
	const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0, 0.5, 0.5, sliverHeight,
	                    9, 9, 9};
	const int tets[] = {0, 1, 2, 3, 0, 2, 1, 3, 0, 1, 4, 2, 0, 1, 4, 5};
	fmTetMesh mesh = makeMesh(x, 7, tets, 4);
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&mesh, &info), fm_ok);
	CHECK_INT(info.invertedTets, 1);
	CHECK_INT(info.degenerateTets, 1);
	CHECK_INT(info.badTets, 2); // the flat tet and the sliver; winding is not quality
	CHECK_INT(info.unreferencedNodes, 1);
	CHECK_NEAR(info.minVolume, -1.0 / 6.0, 1e-15);
	CHECK_NEAR(info.minQuality, 0.0, 0.0);
	CHECK(info.minDihedralDeg < 5.0);
	fmFreeTetMesh(&mesh);
}

// ---- placement --------------------------------------------------------------------------------

TEST(transform_order_scale_center_swap_translate)
{
	double x[15];
	for (int k = 0; k < 15; ++k)
		x[k] = fmTestRandom(-2.0, 3.0);
	const int tet[] = {0, 1, 2, 3};
	fmTetMesh mesh = makeMesh(x, 5, tet, 1);
	fmMeshTransform t = fmDefaultMeshTransform();
	t.scale = 0.4;
	t.center = true;
	t.swapYZ = true;
	t.translate = fmMakeVec3(1.0, -2.0, 3.0);
	double before = fmTetMesh_TetVolume(&mesh, NULL, 0);
	fmTetMesh_Transform(&mesh, &t);
	// The centroid lands on the translation: it is added after centring, and not scaled.
	fmVec3 centroid = fmMakeVec3(0, 0, 0);
	for (int i = 0; i < 5; ++i)
		centroid = fmAdd(centroid, fmLoad(mesh.positions, i));
	centroid = fmScale(0.2, centroid);
	CHECK_NEAR(centroid.x, 1.0, 1e-14);
	CHECK_NEAR(centroid.y, -2.0, 1e-14);
	CHECK_NEAR(centroid.z, 3.0, 1e-14);
	// Edges are scaled and y/z exchanged; the swap is a reflection, so volumes change sign.
	fmVec3 e0 = fmSub(fmLoad(x, 1), fmLoad(x, 0));
	fmVec3 e1 = fmSub(fmLoad(mesh.positions, 1), fmLoad(mesh.positions, 0));
	CHECK_NEAR(e1.x, 0.4 * e0.x, 1e-14);
	CHECK_NEAR(e1.y, 0.4 * e0.z, 1e-14);
	CHECK_NEAR(e1.z, 0.4 * e0.y, 1e-14);
	CHECK_REL(fmTetMesh_TetVolume(&mesh, NULL, 0), -0.064 * before, 1e-12, 1e-12);
	fmFreeTetMesh(&mesh);
}

TEST(default_transform_is_identity)
{
	fmTetMesh mesh = loadHouse();
	fmTetMesh copy;
	CHECK_INT(fmCopyTetMesh(&mesh, &copy), fm_ok);
	fmMeshTransform t = fmDefaultMeshTransform();
	fmTetMesh_Transform(&copy, &t);
	CHECK(memcmp(copy.positions, mesh.positions, sizeof(double) * 3 * (size_t)mesh.nodeCount) == 0);
	fmFreeTetMesh(&copy);
	fmFreeTetMesh(&mesh);
}

// ---- memory -----------------------------------------------------------------------------------

// An allocator that checks every free gets the size that was allocated (fmFree's header).
#define MAX_LIVE 64
static void* s_live[MAX_LIVE];
static size_t s_liveSize[MAX_LIVE];
static int s_sizeMismatches;

static void* checkingAlloc(size_t size, size_t alignment)
{
	void* p = aligned_alloc(alignment, size);
	for (int k = 0; k < MAX_LIVE && p; ++k)
		if (s_live[k] == NULL)
		{
			s_live[k] = p;
			s_liveSize[k] = size;
			break;
		}
	return p;
}

static void checkingFree(void* memory, size_t size)
{
	for (int k = 0; k < MAX_LIVE; ++k)
		if (s_live[k] == memory)
		{
			s_sizeMismatches += s_liveSize[k] != size;
			s_live[k] = NULL;
		}
	free(memory);
}

TEST(copy_free_and_sized_deallocation)
{
	fmSetAllocator(checkingAlloc, checkingFree);
	s_sizeMismatches = 0;
	size_t before = fmGetAllocatedBytes();
	fmTetMesh mesh;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/cube_full.ele",
	                       &mesh, NULL),
	          fm_ok);
	fmTetMesh copy;
	CHECK_INT(fmCopyTetMesh(&mesh, &copy), fm_ok);
	CHECK(copy.positions != mesh.positions && copy.nodeMarkers != mesh.nodeMarkers);
	CHECK(memcmp(copy.nodeAttributes, mesh.nodeAttributes, sizeof(double) * 16) == 0);
	copy.positions[0] = 42.0; // deep: the original does not change
	CHECK_NEAR(mesh.positions[0], 0.0, 0.0);
	int* tri = NULL;
	int count = 0;
	CHECK_INT(fmTetMesh_ExtractSurface(&copy, &tri, &count), fm_ok);
	CHECK_INT((int)((uintptr_t)tri % 64), 0);
	fmFree(tri);
	fmFree(NULL);
	fmFreeTetMesh(&copy);
	fmFreeTetMesh(&mesh);
	fmFreeTetMesh(&mesh); // safe on a zeroed mesh
	fmSetAllocator(NULL, NULL);
	CHECK_INT(s_sizeMismatches, 0);
	CHECK_INT(fmGetAllocatedBytes(), before);
}

// ---- scale-free measures ----------------------------------------------------------------------

// The regular tet of info_regular_tet (alternate cube corners, positive) scaled by @p scale.
static fmTetMesh regularTet(double scale)
{
	const double x[] = {0, 0, 0, 1, 1, 0, 1, 0, 1, 0, 1, 1};
	const int tet[] = {0, 1, 3, 2};
	double scaled[12];
	for (int k = 0; k < 12; ++k)
		scaled[k] = scale * x[k];
	return makeMesh(scaled, 4, tet, 1);
}

TEST(measures_do_not_depend_on_scale)
{
	double dihedral = acos(1.0 / 3.0) * 180.0 / s_pi;
	const double scales[] = {1e-150, 1e-100, 1e-30, 1.0, 1e30, 1e100, 1e300};
	for (int i = 0; i < 7; ++i)
	{
		fmTetMesh mesh = regularTet(scales[i]);
		fmMeshInfo info;
		CHECK_INT(fmTetMesh_GetInfo(&mesh, &info), fm_ok);
		CHECK_NEAR(info.minQuality, 1.0, 1e-12);
		CHECK_NEAR(info.minDihedralDeg, dihedral, 1e-9);
		CHECK_NEAR(info.maxDihedralDeg, dihedral, 1e-9);
		CHECK_INT(info.badTets + info.degenerateTets + info.invertedTets, 0);
		fmTetQuality q;
		CHECK_INT(fmTetMesh_GetTetQuality(&mesh, 0, &q), fm_ok);
		CHECK_NEAR(q.radiusRatio, 1.0, 1e-12);
		CHECK(!q.degenerate);
		CHECK_REL(q.longestEdge, sqrt(2.0) * scales[i], 1e-15, 0.0);
		fmFreeTetMesh(&mesh);
	}
	// Volumes a double holds are exact to rounding, the others are out of range (not NaN).
	fmTetMesh small = regularTet(1e-100), huge = regularTet(1e300), tiny = regularTet(1e-150);
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&small, &info), fm_ok);
	CHECK_REL(info.totalVolume, 1e-300 / 3.0, 1e-14, 0.0);
	CHECK_INT(info.volumeOutOfRangeTets, 0);
	CHECK_INT(fmTetMesh_GetInfo(&huge, &info), fm_ok);
	CHECK_INT(info.volumeOutOfRangeTets, 1);
	CHECK(isinf(info.totalVolume) && info.maxVolume > 0.0);
	CHECK(isinf(fmTetMesh_TetVolume(&huge, NULL, 0)));
	CHECK_INT(fmTetMesh_GetInfo(&tiny, &info), fm_ok);
	CHECK_INT(info.volumeOutOfRangeTets, 1);
	CHECK_INT(info.degenerateTets, 0);
	fmFreeTetMesh(&small);
	fmFreeTetMesh(&huge);
	fmFreeTetMesh(&tiny);
}

TEST(orient_names_overflow_not_zero_volume)
{
	fmTetMesh huge = regularTet(1e300), far = regularTet(1.0);
	fmDiagnostic diag;
	CHECK_INT(fmTetMesh_Orient(&huge, NULL, &diag), fm_errRange);
	CHECK_STR_CONTAINS(diag.message, "tet 0 (in the file's numbering) is well shaped but its "
	                                 "volume is out of the range of a double: 6V = inf");
	// A unit tet far from the origin is fine: only differences matter.
	for (int k = 0; k < 12; ++k)
		far.positions[k] += 1e15;
	CHECK_INT(fmTetMesh_Orient(&far, NULL, &diag), fm_ok);
	far.positions[5] = NAN;
	CHECK_INT(fmTetMesh_Orient(&far, NULL, &diag), fm_errRange);
	CHECK_STR_CONTAINS(diag.message, "non-finite coordinate");
	fmMeshInfo info;
	CHECK_INT(fmTetMesh_GetInfo(&far, &info), fm_errRange);
	fmFreeTetMesh(&huge);
	fmFreeTetMesh(&far);
}

// ---- arguments --------------------------------------------------------------------------------

TEST(null_and_out_of_range_arguments)
{
	fmTestRecordAssertsBegin();
	fmTetMesh mesh = regularTet(1.0);
	fmMeshTransform transform = fmDefaultMeshTransform();
	fmMeshInfo info;
	int* triangles = (int*)&mesh;
	int count = 7;
	fmTetQuality quality;
	int before = fmTestAssertCount();
	fmTetMesh_Transform(NULL, &transform);
	fmTetMesh_Transform(&mesh, NULL);
	transform.scale = NAN;
	fmTetMesh_Transform(&mesh, &transform);
	CHECK_NEAR(mesh.positions[3], 1.0, 0.0); // unchanged
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmTetMesh_Orient(NULL, &count, NULL), fm_errParameter);
	CHECK_INT(count, 0);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmTetMesh_GetInfo(NULL, &info), fm_errParameter);
	CHECK_INT(fmTetMesh_GetInfo(&mesh, NULL), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmTetMesh_ExtractSurface(NULL, &triangles, &count), fm_errParameter);
	CHECK(triangles == NULL && count == 0);
	CHECK_INT(fmTetMesh_ExtractSurface(&mesh, NULL, &count), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmCopyTetMesh(NULL, NULL), fm_errParameter);
	CHECK_INT(fmCopyTetMesh(&mesh, NULL), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK(isnan(fmTetMesh_TetVolume(&mesh, NULL, -1)));
	CHECK(isnan(fmTetMesh_TetVolume(&mesh, NULL, 1)));
	CHECK(isnan(fmTetMesh_TetVolume(NULL, NULL, 0)));
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmTetMesh_GetTetQuality(&mesh, -1, &quality), fm_errParameter);
	CHECK_INT(fmTetMesh_GetTetQuality(&mesh, 0, NULL), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmMakeBoxMesh(1, 1, 1, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), NULL),
	          fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	// An inconsistent mesh built by hand (a count without its array).
	fmTetMesh broken = mesh;
	broken.tets = NULL;
	before = fmTestAssertCount();
	CHECK_INT(fmTetMesh_Orient(&broken, NULL, NULL), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	// Node references out of range are bad data, not a crash: an error code, no assert.
	before = fmTestAssertCount();
	mesh.tets[2] = 99;
	CHECK_INT(fmTetMesh_ExtractSurface(&mesh, &triangles, &count), fm_errIndex);
	CHECK_INT(fmTetMesh_GetTetQuality(&mesh, 0, &quality), fm_errIndex);
	CHECK_INT(fmTestAssertCount(), before);
	// The test runner's counting hook is not reachable from here: restore the default.
	fmTestRecordAssertsEnd();
	fmFreeTetMesh(&mesh);
}

TEST(box_mesh_limits_without_overflow)
{
	fmTetMesh mesh;
	fmVec3 lo = fmMakeVec3(0, 0, 0), hi = fmMakeVec3(1, 1, 1);
	CHECK_INT(fmMakeBoxMesh(INT_MAX, 1, 1, lo, hi, &mesh), fm_errLimit);
	CHECK_INT(fmMakeBoxMesh(1, INT_MAX, 1, lo, hi, &mesh), fm_errLimit);
	CHECK_INT(fmMakeBoxMesh(1, 1, INT_MAX, lo, hi, &mesh), fm_errLimit);
	CHECK_INT(fmMakeBoxMesh(INT_MAX, INT_MAX, INT_MAX, lo, hi, &mesh), fm_errLimit);
	// 2^21 * 2^21 * 4 wraps a long long product of three ints to 0 when computed as one.
	CHECK_INT(fmMakeBoxMesh(1 << 21, 1 << 21, 1 << 22, lo, hi, &mesh), fm_errLimit);
	CHECK(mesh.positions == NULL && mesh.nodeCount == 0);
}
