// TetGen reading and writing: the bouncy house, files with every optional field, one malformed
// input per error class (result, file, line, column and message checked, nothing leaked, the
// mesh left zeroed), and a bit-exact write/read round trip.
// POSIX for mkfifo: a FIFO must be refused, not waited on.
#define _POSIX_C_SOURCE 200809L

#include "support.h"
#include "test.h"

#include <femto/femto.h>
#include <stdlib.h>
#include <sys/stat.h>

#define TEXT(s) (s), sizeof(s) - 1

static const char s_node4[] = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
static const char s_ele1[] = "1 4 0\n1 1 2 3 4\n";

static fmResult loadTexts(const char* node, size_t nodeSize, const char* ele, size_t eleSize,
                          fmTetMesh* mesh, fmDiagnostic* diag)
{
	return fmLoadTetGenFromMemory(node, nodeSize, "t.node", ele, eleSize, "t.ele", mesh, diag);
}

static bool meshIsZero(const fmTetMesh* m)
{
	return m->nodeCount == 0 && m->tetCount == 0 && m->positions == NULL && m->tets == NULL &&
	       m->nodeAttributes == NULL && m->nodeMarkers == NULL && m->tetAttributes == NULL;
}

// Load the texts, expect @p expected at file:line[:column] with @p message in the text; the mesh
// must be left zeroed and nothing leaked.
static void expectLoadError(int* failures_, int callerLine, const char* node, size_t nodeSize,
                            const char* ele, size_t eleSize, fmResult expected, const char* file,
                            int line, int column, const char* message)
{
	size_t before = fmGetAllocatedBytes();
	fmTetMesh mesh;
	fmDiagnostic diag;
	fmResult r = loadTexts(node, nodeSize, ele, eleSize, &mesh, &diag);
	char text[1024];
	fmDiagnostic_Format(&diag, text, sizeof text);
	bool ok = r == expected && diag.result == expected && strcmp(diag.file, file) == 0 &&
	          diag.line == line && (column == 0 || diag.column == column) &&
	          strstr(diag.message, message) != NULL && meshIsZero(&mesh) &&
	          fmGetAllocatedBytes() == before;
	if (!ok)
		FAIL_AT("case at line %d: got %s \"%s\" (line %d, column %d); expected %s at %s:%d:%d "
		        "containing \"%s\"",
		        callerLine, fmResultName(r), text, diag.line, diag.column, fmResultName(expected),
		        file, line, column, message);
}

#define EXPECT_NODE_ERROR(nodeText, result, line, column, message)                                 \
	expectLoadError(failures_, __LINE__, TEXT(nodeText), TEXT(s_ele1), result, "t.node", line,     \
	                column, message)
#define EXPECT_ELE_ERROR(eleText, result, line, column, message)                                   \
	expectLoadError(failures_, __LINE__, TEXT(s_node4), TEXT(eleText), result, "t.ele", line,      \
	                column, message)

// ---- good input -------------------------------------------------------------------------------

TEST(house2)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	fmResult r =
	    fmLoadTetGen(FEMTO_MESH_DIR "/house2.node", FEMTO_MESH_DIR "/house2.ele", &mesh, &diag);
	CHECK_INT(r, fm_ok);
	CHECK_INT(mesh.nodeCount, 400);
	CHECK_INT(mesh.tetCount, 1389);
	CHECK_INT(mesh.firstIndex, 1);
	CHECK(mesh.nodeMarkers != NULL);
	// Stellar writes 0/1 flags in the element index column: one warning, nothing else.
	CHECK_INT(diag.warningCount, 1);
	CHECK_STR_CONTAINS(diag.warning, "house2.ele:2: warning: tet number 0 where 1 was expected");
	// The first record "1 1 75 175 52" of house2.ele, 0-based.
	CHECK_INT(mesh.tets[0], 0);
	CHECK_INT(mesh.tets[1], 74);
	CHECK_INT(mesh.tets[3], 51);
	int flipped = -1;
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, &diag), fm_ok);
	CHECK(flipped > 0); // loading does not reorient: the file's tets are negative in its frame
	int positive = 0;
	for (int t = 0; t < mesh.tetCount; ++t)
		positive += fmTetMesh_TetVolume(&mesh, NULL, t) > 0.0;
	CHECK_INT(positive, mesh.tetCount);
	fmFreeTetMesh(&mesh);
	CHECK(meshIsZero(&mesh));
}

TEST(every_optional_field)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/cube_full.ele",
	                       &mesh, &diag),
	          fm_ok);
	CHECK_INT(diag.warningCount, 0);
	CHECK_INT(mesh.nodeCount, 8);
	CHECK_INT(mesh.tetCount, 6);
	CHECK_INT(mesh.firstIndex, 1);
	CHECK_INT(mesh.nodeAttributeCount, 2);
	CHECK_INT(mesh.tetAttributeCount, 1);
	CHECK(mesh.nodeAttributes && mesh.nodeMarkers && mesh.tetAttributes);
	if (!mesh.nodeAttributes || !mesh.nodeMarkers || !mesh.tetAttributes)
		return;
	// Point 3 is tab-separated; point 8 is the cube's far corner with marker -3.
	CHECK(mesh.positions[6] == 0.0 && mesh.positions[7] == 1.0 && mesh.positions[8] == 0.0);
	CHECK_NEAR(mesh.nodeAttributes[2 * 2], 1.5, 0.0);
	CHECK_NEAR(mesh.nodeAttributes[2 * 4], 1e-300, 0.0);
	CHECK(signbit(mesh.nodeAttributes[2 * 5]));
	CHECK_INT(mesh.nodeMarkers[3], 2);
	CHECK_INT(mesh.nodeMarkers[7], -3);
	CHECK_NEAR(mesh.tetAttributes[4], 30.0, 0.0);
	// Tets 2 and 5 are written inverted; loading keeps them so, Orient fixes exactly those.
	CHECK(fmTetMesh_TetVolume(&mesh, NULL, 1) < 0.0 && fmTetMesh_TetVolume(&mesh, NULL, 4) < 0.0);
	int flipped = 0;
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, NULL), fm_ok);
	CHECK_INT(flipped, 2);
	fmFreeTetMesh(&mesh);
}

TEST(quadratic_tets_zero_based)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(
	    fmLoadTetGen(FEMTO_TEST_DATA "/tet10.node", FEMTO_TEST_DATA "/tet10.ele", &mesh, &diag),
	    fm_ok);
	CHECK_INT(mesh.firstIndex, 0);
	CHECK_INT(mesh.tetCount, 1);
	CHECK(mesh.nodeMarkers == NULL && mesh.nodeAttributes == NULL && mesh.tetAttributes == NULL);
	for (int k = 0; k < 4; ++k)
		CHECK_INT(mesh.tets[k], k); // the corners are kept
	// Two warnings: the 10-node tets, then the six midpoints no linear tet uses.
	CHECK_INT(diag.warningCount, 2);
	CHECK_STR_CONTAINS(diag.warning, "tet10.ele:1: warning: 10-node (quadratic) tets");
	CHECK_NEAR(fmTetMesh_TetVolume(&mesh, NULL, 0), 1.0 / 6.0, 1e-15);
	fmFreeTetMesh(&mesh);
}

TEST(comments_blank_lines_crlf)
{
	const char node[] = "# header follows\r\n\r\n4 3 0 0 # trailing comment\r\n"
	                    "1 0 0 0\r\n   \t\r\n2 1 0 0#glued comment\r\n3 0 1 0\r\n4 0 0 1";
	const char ele[] = "1 4 0\r\n#\r\n1 1 2 3 4\r\n# end\r\n\r\n";
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(loadTexts(TEXT(node), TEXT(ele), &mesh, &diag), fm_ok);
	CHECK_INT(diag.warningCount, 0);
	CHECK_INT(mesh.nodeCount, 4);
	CHECK_NEAR(mesh.positions[3], 1.0, 0.0);
	CHECK_NEAR(fmTetMesh_TetVolume(&mesh, NULL, 0), 1.0 / 6.0, 1e-15);
	fmFreeTetMesh(&mesh);
}

TEST(longest_line_and_underflow_accepted)
{
	// A line of exactly FM_MAX_LINE bytes is accepted; 1e-400 underflows to a tiny number.
	static char node[FM_MAX_LINE + 64];
	int n = snprintf(node, sizeof node, "4 3 0 0\n#");
	memset(node + n, 'x', FM_MAX_LINE - 1);
	n += FM_MAX_LINE - 1;
	n += snprintf(node + n, sizeof node - (size_t)n, "\n1 1e-400 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
	fmTetMesh mesh;
	CHECK_INT(loadTexts(node, (size_t)n, TEXT(s_ele1), &mesh, NULL), fm_ok);
	CHECK(mesh.positions && fabs(mesh.positions[0]) < 1e-300);
	fmFreeTetMesh(&mesh);
}

TEST(unreferenced_nodes_warn)
{
	const char node[] = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 9 9 9\n";
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(loadTexts(TEXT(node), TEXT(s_ele1), &mesh, &diag), fm_ok);
	CHECK_INT(mesh.nodeCount, 5);
	CHECK_INT(diag.warningCount, 1);
	CHECK_STR_CONTAINS(diag.warning, "t.node: warning: 1 of 5 points are used by no tet (the first "
	                                 "is point 5)");
	fmFreeTetMesh(&mesh);
}

// ---- one test per error class -----------------------------------------------------------------

TEST(error_missing_or_unreadable_file)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	const char* missing = FEMTO_TEST_DATA "/no_such_mesh.node";
	CHECK_INT(fmLoadTetGen(missing, FEMTO_TEST_DATA "/cube_full.ele", &mesh, &diag), fm_errIo);
	CHECK_STR_CONTAINS(diag.file, "no_such_mesh.node");
	CHECK_STR_CONTAINS(diag.message, "cannot open: No such file or directory");
	CHECK(meshIsZero(&mesh));
	// The .ele is named when it is the one missing.
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/no_such.ele", &mesh,
	                       &diag),
	          fm_errIo);
	CHECK_STR_CONTAINS(diag.file, "no_such.ele");
	// A directory opens but is not a file.
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA, FEMTO_TEST_DATA "/cube_full.ele", &mesh, &diag),
	          fm_errIo);
	CHECK_STR_CONTAINS(diag.message, "is a directory, not a regular file");
	CHECK_INT(fmGetAllocatedBytes(), 0);
}

TEST(error_truncated)
{
	EXPECT_NODE_ERROR(
	    "4 3 0 0\n1 0.000 0.000 0.000\n2 1.000 0.000 0.000\n3 0.000 1.000 0.000\n", fm_errCount, 5,
	    0, "unexpected end of file: expected point 4 of the 4 the header on line 1 declares");
	// On disk: the file is named with its path and the line after the last.
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/bad_truncated.ele",
	                       &mesh, &diag),
	          fm_errCount);
	CHECK_STR_CONTAINS(diag.file, "bad_truncated.ele");
	CHECK_INT(diag.line, 5);
	CHECK_STR_CONTAINS(diag.message, "expected tet 3 of the 3 the header on line 2 declares");
}

TEST(error_nul_byte)
{
	const char node[] = "4 3 0 0\n1 0\0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
	expectLoadError(failures_, __LINE__, node, sizeof node - 1, TEXT(s_ele1), fm_errSyntax,
	                "t.node", 2, 4, "NUL byte");
}

TEST(error_overlong_line)
{
	static char node[FM_MAX_LINE + 64];
	int n = snprintf(node, sizeof node, "4 3 0 0\n1 0 0 0\n#");
	memset(node + n, 'x', FM_MAX_LINE);
	n += FM_MAX_LINE;
	n += snprintf(node + n, sizeof node - (size_t)n, "\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
	expectLoadError(failures_, __LINE__, node, (size_t)n, TEXT(s_ele1), fm_errLimit, "t.node", 3,
	                FM_MAX_LINE + 1, "line is 4097 bytes long: expected at most 4096");
}

TEST(error_number_overflow)
{
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 1e999 0\n3 0 1 0\n4 0 0 1\n", fm_errRange, 3, 5,
	                  "y coordinate \"1e999\" overflows a double");
	EXPECT_NODE_ERROR("99999999999 3 0 0\n1 0 0 0\n", fm_errRange, 1, 1,
	                  "point count \"99999999999\" overflows an int");
	EXPECT_ELE_ERROR("1 4 0\n1 1 2 3 -4294967297\n", fm_errRange, 2, 9,
	                 "node number \"-4294967297\" overflows an int");
	char longNumber[200] = "4 3 0 0\n1 0 0 ";
	size_t n = strlen(longNumber);
	memset(longNumber + n, '1', 130);
	snprintf(longNumber + n + 130, sizeof longNumber - n - 130, "\n");
	expectLoadError(failures_, __LINE__, longNumber, strlen(longNumber), TEXT(s_ele1), fm_errSyntax,
	                "t.node", 2, 7, "z coordinate is 130 characters long");
}

TEST(error_nan_inf)
{
	EXPECT_NODE_ERROR("4 3 0 0\n1 nan 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", fm_errRange, 2, 3,
	                  "x coordinate is \"nan\": expected a finite number");
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 -Infinity\n", fm_errRange, 5, 7,
	                  "z coordinate is \"-Infinity\": expected a finite number");
	EXPECT_NODE_ERROR("4 3 1 0\n1 0 0 0 inf\n2 1 0 0 0\n3 0 1 0 0\n4 0 0 1 0\n", fm_errRange, 2, 9,
	                  "point attribute is \"inf\"");
}

TEST(error_negative_counts)
{
	EXPECT_NODE_ERROR("-4 3 0 0\n1 0 0 0\n", fm_errRange, 1, 1, "negative point count -4");
	EXPECT_ELE_ERROR("-1 4 0\n1 1 2 3 4\n", fm_errRange, 1, 1, "negative tet count -1");
	EXPECT_NODE_ERROR("4 3 -1 0\n1 0 0 0\n", fm_errRange, 1, 5,
	                  "attribute count -1 is out of range: expected 0 to 64");
}

// Records the largest request, to prove oversized headers are rejected before allocating.
static size_t s_largestRequest;
static void* recordingAlloc(size_t size, size_t alignment)
{
	if (size > s_largestRequest)
		s_largestRequest = size;
	return aligned_alloc(alignment, size);
}
static void recordingFree(void* memory, size_t size)
{
	(void)size;
	free(memory);
}

TEST(error_counts_larger_than_the_file)
{
	fmSetAllocator(recordingAlloc, recordingFree);
	s_largestRequest = 0;
	EXPECT_NODE_ERROR("100000000 3 0 0\n1 0 0 0\n", fm_errLimit, 1, 1,
	                  "100000000 points exceed the limit of 67108864");
	EXPECT_NODE_ERROR("1000000 3 0 0\n1 0 0 0\n2 1 0 0\n", fm_errCount, 1, 1,
	                  "the header declares 1000000 points but only 16 bytes follow");
	EXPECT_ELE_ERROR("200000000 4 0\n1 1 2 3 4\n", fm_errLimit, 1, 1,
	                 "200000000 tets exceed the limit of 134217728");
	EXPECT_ELE_ERROR("50000000 10 64\n1 1 2 3 4\n", fm_errCount, 1, 1,
	                 "expected at least 7499999999 bytes (75 fields per tet)");
	EXPECT_NODE_ERROR("4 3 65 0\n1 0 0 0\n", fm_errRange, 1, 5,
	                  "attribute count 65 is out of range");
	fmSetAllocator(NULL, NULL);
	CHECK(s_largestRequest < 100000); // only the small node arrays of s_node4 were allocated
}

// ---- files: only regular files, size checked first, read once -------------------------------

TEST(error_not_a_regular_file)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	// A device never ends: it was read until memory ran out.
	FILE* zero = fopen("/dev/zero", "rb");
	if (zero != NULL)
	{
		fclose(zero);
		CHECK_INT(fmLoadTetGen("/dev/zero", FEMTO_TEST_DATA "/cube_full.ele", &mesh, &diag),
		          fm_errIo);
		CHECK_STR_CONTAINS(diag.file, "/dev/zero");
		CHECK_STR_CONTAINS(diag.message,
		                   "is a character device, not a regular file: expected a mesh file");
		CHECK(meshIsZero(&mesh));
	}
	// A FIFO without a writer: opening it used to block forever.
	const char* fifo = "mesh_io_fifo.node";
	remove(fifo);
	if (mkfifo(fifo, 0600) == 0)
	{
		CHECK_INT(fmLoadTetGen(fifo, FEMTO_TEST_DATA "/cube_full.ele", &mesh, &diag), fm_errIo);
		CHECK_STR_CONTAINS(diag.message, "is a FIFO (named pipe), not a regular file");
		CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", fifo, &mesh, &diag), fm_errIo);
		CHECK_STR_CONTAINS(diag.file, fifo);
		remove(fifo);
	}
	CHECK_INT(fmGetAllocatedBytes(), 0);
}

// Live and peak bytes through the allocator hook, and the largest single request.
static size_t s_liveBytes, s_peakBytes, s_largestAlloc;
static void* trackingAlloc(size_t size, size_t alignment)
{
	s_liveBytes += size;
	s_peakBytes = s_liveBytes > s_peakBytes ? s_liveBytes : s_peakBytes;
	s_largestAlloc = size > s_largestAlloc ? size : s_largestAlloc;
	return aligned_alloc(alignment, size);
}
static void trackingFree(void* memory, size_t size)
{
	s_liveBytes -= size;
	free(memory);
}
static void startTracking(void)
{
	s_liveBytes = s_peakBytes = s_largestAlloc = 0;
	fmSetAllocator(trackingAlloc, trackingFree);
}

static long fileSize(const char* path)
{
	FILE* f = fopen(path, "rb");
	long size = -1;
	if (f != NULL && fseek(f, 0, SEEK_END) == 0)
		size = ftell(f);
	if (f != NULL)
		fclose(f);
	return size;
}

TEST(error_file_over_the_size_limit)
{
	const char* node = FEMTO_TEST_DATA "/cube_full.node";
	const char* ele = FEMTO_TEST_DATA "/cube_full.ele";
	long nodeSize = fileSize(node);
	CHECK(nodeSize > 100);
	fmMeshLoadDef def = fmDefaultMeshLoadDef();
	CHECK(def.maxFileBytes == FM_DEFAULT_MESH_FILE_LIMIT);
	CHECK(FM_DEFAULT_MESH_FILE_LIMIT == (size_t)1 << 30);
	fmTetMesh mesh;
	fmDiagnostic diag;
	// One byte over the limit: refused before anything is allocated.
	def.maxFileBytes = (size_t)nodeSize - 1;
	startTracking();
	CHECK_INT(fmLoadTetGenWithDef(node, ele, &def, &mesh, &diag), fm_errLimit);
	fmSetAllocator(NULL, NULL);
	CHECK_INT(s_largestAlloc, 0);
	char expected[200];
	snprintf(expected, sizeof expected,
	         "file is %ld bytes, more than the limit of %ld bytes (fmMeshLoadDef.maxFileBytes)",
	         nodeSize, nodeSize - 1);
	CHECK_STR_CONTAINS(diag.message, expected);
	CHECK_STR_CONTAINS(diag.file, "cube_full.node");
	CHECK(meshIsZero(&mesh));
	// Exactly at the limit: loaded.
	def.maxFileBytes = (size_t)nodeSize;
	if (fileSize(ele) <= nodeSize)
	{
		CHECK_INT(fmLoadTetGenWithDef(node, ele, &def, &mesh, &diag), fm_ok);
		fmFreeTetMesh(&mesh);
	}
	// The default refuses a 2 GiB file at once (sparse: no disk used) instead of reading it.
	const char* sparse = "mesh_io_sparse.node";
	FILE* f = fopen(sparse, "wb");
	if (f != NULL && fseek(f, 2147483647L, SEEK_SET) == 0 && fputc('\n', f) != EOF)
	{
		fclose(f);
		startTracking();
		CHECK_INT(fmLoadTetGen(sparse, ele, &mesh, &diag), fm_errLimit);
		fmSetAllocator(NULL, NULL);
		CHECK_INT(s_largestAlloc, 0);
		CHECK_STR_CONTAINS(diag.message, "file is 2147483648 bytes, more than the limit of "
		                                 "1073741824 bytes");
	}
	else if (f != NULL)
		fclose(f);
	remove(sparse);
	CHECK_INT(fmGetAllocatedBytes(), 0);
}

TEST(file_read_into_one_buffer_of_its_size)
{
	// About 1.3 MB of .node text for 20000 points and a one-tet .ele.
	const char* nodePath = "mesh_io_many_points.node";
	const char* elePath = "mesh_io_one_tet.ele";
	FILE* f = fopen(nodePath, "w");
	CHECK(f != NULL);
	if (f == NULL)
		return;
	const int n = 20000;
	fprintf(f, "%d 3 0 0\n", n);
	for (int i = 0; i < n; ++i)
		fprintf(f, "%d %.17g %.17g %.17g\n", i, fmTestRandom(-1, 1), fmTestRandom(-1, 1),
		        fmTestRandom(-1, 1));
	fclose(f);
	f = fopen(elePath, "w");
	CHECK(f != NULL);
	if (f == NULL)
		return;
	fprintf(f, "1 4 0\n0 0 1 2 3\n");
	fclose(f);
	size_t text = (size_t)fileSize(nodePath);
	fmTetMesh mesh;
	startTracking();
	CHECK_INT(fmLoadTetGen(nodePath, elePath, &mesh, NULL), fm_ok);
	size_t kept = s_liveBytes; // the mesh's arrays
	fmFreeTetMesh(&mesh);
	fmSetAllocator(NULL, NULL);
	// One buffer of the file's size (rounded to the 64-byte alignment), never a grown copy ...
	CHECK_INT(s_largestAlloc, (text + 63) / 64 * 64);
	// ... and at the peak only that text, the mesh's arrays and a few small temporaries.
	size_t bound = text + kept + 4096 + (size_t)n;
	if (s_peakBytes > bound)
		FAIL_AT("peak %zu bytes for a %zu-byte file and %zu bytes of mesh: expected at most %zu",
		        s_peakBytes, text, kept, bound);
	remove(nodePath);
	remove(elePath);
}

// ---- located messages, byte-order mark, line ends ---------------------------------------------

TEST(short_file_reported_at_the_line_not_the_header)
{
	// One missing coordinate in a small file: the line that lacks it, not "the header declares".
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 0\n3 0 1 0\n4 0 0 1\n", fm_errSyntax, 3, 6,
	                  "missing field: expected 4 fields (<point #> <x> <y> <z>), found 3");
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n", fm_errCount, 5, 0,
	                  "unexpected end of file: expected point 4 of the 4");
	EXPECT_ELE_ERROR("2 4 0\n1 1 2 3 4\n", fm_errCount, 3, 0,
	                 "unexpected end of file: expected tet 2 of the 2");
	// A count that would allocate much is still checked against the file before allocating.
	EXPECT_NODE_ERROR("100000 3 0 0\n1 0 0 0\n", fm_errCount, 1, 1,
	                  "the header declares 100000 points but only 8 bytes follow");
}

TEST(byte_order_mark_accepted)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	const char node[] = "\xEF\xBB\xBF# written by a Windows editor\n4 3 0 0\n1 0 0 0\n2 1 0 0\n"
	                    "3 0 1 0\n4 0 0 1\n";
	const char ele[] = "\xEF\xBB\xBF"
	                   "1 4 0\n1 1 2 3 4\n";
	CHECK_INT(loadTexts(TEXT(node), TEXT(ele), &mesh, &diag), fm_ok);
	CHECK_INT(mesh.nodeCount, 4);
	CHECK_INT(mesh.tetCount, 1);
	fmFreeTetMesh(&mesh);
	// Columns count from after the mark.
	EXPECT_NODE_ERROR("\xEF\xBB\xBF"
	                  "4 3 0 x\n",
	                  fm_errSyntax, 1, 7, "expected boundary marker flag (an integer)");
	const char face[] = "\xEF\xBB\xBF"
	                    "1 0\n1 1 2 3\n";
	int* triangles = NULL;
	int count = 0;
	CHECK_INT(fmLoadTetGenFaceFromMemory(TEXT(face), "t.face", 4, 1, &triangles, &count, &diag),
	          fm_ok);
	CHECK_INT(count, 1);
	fmFree(triangles);
}

TEST(error_cr_only_line_ends)
{
	EXPECT_NODE_ERROR("4 3 0 0\r1 0 0 0\r2 1 0 0\r3 0 1 0\r4 0 0 1\r", fm_errSyntax, 1, 8,
	                  "carriage return inside a line: the file has CR-only (old Mac) line ends; "
	                  "expected LF or CRLF line ends");
	EXPECT_ELE_ERROR("1 4 0\n1 1 2\r3 4\n", fm_errSyntax, 2, 6, "carriage return inside a line");
	// Without a diagnostic the code is still the reader's, not a stand-in.
	fmTetMesh mesh;
	const char cr[] = "4 3 0 0\r1 0 0 0\r";
	CHECK_INT(loadTexts(TEXT(cr), TEXT(s_ele1), &mesh, NULL), fm_errSyntax);
	CHECK(meshIsZero(&mesh));
}

// ---- arguments --------------------------------------------------------------------------------

TEST(null_arguments_are_errors)
{
	fmTestRecordAssertsBegin();
	fmDiagnostic diag;
	int before = fmTestAssertCount();
	CHECK_INT(loadTexts(TEXT(s_node4), TEXT(s_ele1), NULL, &diag), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	fmTetMesh mesh;
	fmMeshLoadDef def;
	memset(&def, 0, sizeof def);
	before = fmTestAssertCount();
	CHECK_INT(fmLoadTetGenWithDef(FEMTO_TEST_DATA "/cube_full.node",
	                              FEMTO_TEST_DATA "/cube_full.ele", &def, &mesh, &diag),
	          fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "start from fmDefaultMeshLoadDef()");
	CHECK(meshIsZero(&mesh));
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmLoadTetGenWithDef(FEMTO_TEST_DATA "/cube_full.node",
	                              FEMTO_TEST_DATA "/cube_full.ele", NULL, &mesh, &diag),
	          fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	int count = 7;
	before = fmTestAssertCount();
	CHECK_INT(
	    fmLoadTetGenFaceFromMemory(TEXT("1 0\n1 1 2 3\n"), "t.face", 4, 1, NULL, &count, &diag),
	    fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	before = fmTestAssertCount();
	CHECK_INT(fmWriteTetGenNode(NULL, &mesh, NULL, &diag), fm_errParameter);
	CHECK_INT(fmWriteTetGenNode("mesh_io_never_written.node", NULL, NULL, &diag), fm_errParameter);
	CHECK_ASSERTED_SINCE(before);
	// The test runner's counting hook is not reachable from here: restore the default.
	fmTestRecordAssertsEnd();
	CHECK_INT(fmGetAllocatedBytes(), 0);
}

TEST(error_extra_or_missing_fields)
{
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 0 0 7\n3 0 1 0\n4 0 0 1\n", fm_errSyntax, 3, 9,
	                  "extra field \"7\": expected 4 fields (<point #> <x> <y> <z>), found 5");
	EXPECT_NODE_ERROR("4 3 0 1\n1 0 0 0 1\n2 1 0 0  # no marker\n3 0 1 0 1\n4 0 0 1 1\n",
	                  fm_errSyntax, 3, 8,
	                  "missing field: expected 5 fields (<point #> <x> <y> <z> <boundary marker>), "
	                  "found 4");
	EXPECT_NODE_ERROR("4 3 0 0 9\n1 0 0 0\n", fm_errSyntax, 1, 9, "extra field \"9\"");
	EXPECT_ELE_ERROR("1 4 1\n1 1 2 3 4   # no attribute\n", fm_errSyntax, 2, 10,
	                 "expected 6 fields (<tet #> <4 node numbers> <1 attributes>), found 5");
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 abc 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", fm_errSyntax, 2, 5,
	                  "expected y coordinate (a number), found \"abc\"");
	EXPECT_ELE_ERROR("1 4 0\n1 1 2 3 4.0\n", fm_errSyntax, 2, 9,
	                 "expected node number (an integer), found \"4.0\"");
}

TEST(error_node_reference_out_of_range)
{
	EXPECT_ELE_ERROR("1 4 0\n1 1 2 3 5\n", fm_errIndex, 2, 9,
	                 "node number 5 is out of range: expected 1 to 4");
	EXPECT_ELE_ERROR("1 4 0\n1 0 1 2 3\n", fm_errIndex, 2, 3,
	                 "node number 0 is out of range: expected 1 to 4 (4 points numbered from 1)");
	// On disk, with the full formatted diagnostic.
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGen(FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/bad_range.ele",
	                       &mesh, &diag),
	          fm_errIndex);
	char text[1024];
	CHECK_STR_CONTAINS(fmDiagnostic_Format(&diag, text, sizeof text),
	                   "bad_range.ele:3:10: node number 9 is out of range: expected 1 to 8");
}

TEST(error_repeated_nodes)
{
	EXPECT_ELE_ERROR("1 4 0\n1 1 2 2 4\n", fm_errIndex, 2, 7,
	                 "tet 1 repeats node 2: expected 4 distinct nodes");
}

TEST(error_duplicate_tets)
{
	const char node[] = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n";
	const char ele[] = "3 4 0\n1 1 2 3 4\n2 2 3 4 5\n3 4 3 2 1\n";
	expectLoadError(failures_, __LINE__, TEXT(node), TEXT(ele), fm_errIndex, "t.ele", 4, 0,
	                "tet 3 has the same nodes as tet 1 on line 2");
}

TEST(error_zero_volume_from_orient)
{
	// Loads (volume is geometry, not syntax), then Orient names the flat tet and changes nothing.
	const char node[] = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 0\n";
	const char ele[] = "2 4 0\n1 1 3 2 4\n2 1 2 3 5\n";
	fmTetMesh mesh;
	fmDiagnostic diag;
	CHECK_INT(loadTexts(TEXT(node), TEXT(ele), &mesh, &diag), fm_ok);
	int flipped = -1;
	CHECK_INT(fmTetMesh_Orient(&mesh, &flipped, &diag), fm_errDegenerate);
	CHECK_STR_CONTAINS(diag.message, "tet 2 (in the file's numbering) has zero volume");
	CHECK_INT(flipped, 0);
	CHECK_INT(mesh.tets[2], 1); // tet 1 (negative) was not flipped: the call changed nothing
	fmFreeTetMesh(&mesh);
}

TEST(error_empty_mesh)
{
	EXPECT_NODE_ERROR("", fm_errEmpty, 1, 0, "no header");
	EXPECT_NODE_ERROR("# only a comment\n\n", fm_errEmpty, 3, 0, "no header");
	EXPECT_NODE_ERROR("0 3 0 0\n", fm_errEmpty, 1, 1, "the header declares 0 points");
	EXPECT_ELE_ERROR("0 4 0\n", fm_errEmpty, 1, 1, "the header declares 0 tets");
}

TEST(error_wrong_dimension)
{
	EXPECT_NODE_ERROR("4 2 0 0\n1 0 0\n", fm_errRange, 1, 3, "dimension is 2: expected 3");
}

TEST(error_marker_flag)
{
	EXPECT_NODE_ERROR("4 3 0 2\n1 0 0 0 1\n", fm_errRange, 1, 7,
	                  "boundary marker flag 2 is out of range: expected 0 to 1");
}

TEST(error_trailing_data)
{
	EXPECT_NODE_ERROR("4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n# ok\n5 1 1 1\n", fm_errCount,
	                  7, 0, "data after the last of the 4 points the header on line 1 declares");
	EXPECT_ELE_ERROR("1 4 0\n1 1 2 3 4\nend\n", fm_errCount, 3, 0, "expected the end of the file");
}

TEST(error_other_header_values)
{
	EXPECT_NODE_ERROR("4 3 0 0\n2 0 0 0\n3 1 0 0\n4 0 1 0\n5 0 0 1\n", fm_errRange, 2, 1,
	                  "first point number is 2: expected 0 or 1");
	EXPECT_ELE_ERROR("1 6 0\n1 1 2 3 4 1 2\n", fm_errRange, 1, 3,
	                 "6 nodes per tet: expected 4 or 10");
}

// ---- the .face reader -------------------------------------------------------------------------

TEST(face_file)
{
	size_t before = fmGetAllocatedBytes();
	const char text[] = "# the four faces of a tet\n4 1\n1 1 3 2 -1\n2 1 2 4 -1\n3 1 4 3 -1\n"
	                    "4 2 3 4 -1 # last\n";
	int* triangles = NULL;
	int count = 0;
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGenFaceFromMemory(TEXT(text), "t.face", 4, 1, &triangles, &count, &diag),
	          fm_ok);
	CHECK_INT(count, 4);
	if (triangles)
	{
		CHECK_INT(triangles[0], 0);
		CHECK_INT(triangles[1], 2);
		CHECK_INT(triangles[11], 3);
	}
	fmFree(triangles);
	CHECK_INT(fmGetAllocatedBytes(), before);
	const char bad[] = "2 0\n1 1 2 3\n2 1 2 7\n";
	CHECK_INT(fmLoadTetGenFaceFromMemory(TEXT(bad), "t.face", 4, 1, &triangles, &count, &diag),
	          fm_errIndex);
	CHECK_INT(diag.line, 3);
	CHECK_STR_CONTAINS(diag.message, "node number 7 is out of range: expected 1 to 4");
	CHECK(triangles == NULL && count == 0);
	CHECK_INT(fmGetAllocatedBytes(), before);
}

// ---- writing ----------------------------------------------------------------------------------

static bool sameBits(const void* a, const void* b, size_t bytes)
{
	return (a == NULL && b == NULL) || (a && b && memcmp(a, b, bytes) == 0);
}

// Write moved positions (random doubles that need all 17 digits), read back, compare bits.
static void roundTrip(int* failures_, const char* nodePath, const char* elePath)
{
	fmTetMesh mesh, back;
	CHECK_INT(fmLoadTetGen(nodePath, elePath, &mesh, NULL), fm_ok);
	size_t n3 = 3 * (size_t)mesh.nodeCount;
	double* moved = malloc(sizeof(double) * n3);
	for (size_t k = 0; k < n3; ++k)
		moved[k] = mesh.positions[k] + fmTestRandom(-1.0, 1.0) * 1e-3;
	moved[0] = -0.0;
	moved[1] = 5e-324; // the smallest subnormal
	const char* out = "mesh_io_roundtrip.node";
	fmDiagnostic diag;
	CHECK_INT(fmWriteTetGenNode(out, &mesh, moved, &diag), fm_ok);
	CHECK_INT(fmLoadTetGen(out, elePath, &back, &diag), fm_ok);
	CHECK_INT(back.nodeCount, mesh.nodeCount);
	CHECK_INT(back.firstIndex, mesh.firstIndex);
	CHECK_INT(back.nodeAttributeCount, mesh.nodeAttributeCount);
	CHECK(sameBits(back.positions, moved, sizeof(double) * n3));
	CHECK(sameBits(back.nodeAttributes, mesh.nodeAttributes,
	               sizeof(double) * (size_t)mesh.nodeCount * (size_t)mesh.nodeAttributeCount));
	CHECK(sameBits(back.nodeMarkers, mesh.nodeMarkers, sizeof(int) * (size_t)mesh.nodeCount));
	remove(out);
	free(moved);
	fmFreeTetMesh(&mesh);
	fmFreeTetMesh(&back);
}

TEST(write_read_round_trip_bit_exact)
{
	roundTrip(failures_, FEMTO_TEST_DATA "/cube_full.node", FEMTO_TEST_DATA "/cube_full.ele");
	roundTrip(failures_, FEMTO_TEST_DATA "/tet10.node", FEMTO_TEST_DATA "/tet10.ele");
	roundTrip(failures_, FEMTO_MESH_DIR "/house2.node", FEMTO_MESH_DIR "/house2.ele");
}

TEST(write_errors)
{
	fmTetMesh mesh;
	CHECK_INT(loadTexts(TEXT(s_node4), TEXT(s_ele1), &mesh, NULL), fm_ok);
	fmDiagnostic diag;
	const char* path = "/nonexistent-femto-dir/out.node";
	CHECK_INT(fmWriteTetGenNode(path, &mesh, NULL, &diag), fm_errIo);
	CHECK_STR_CONTAINS(diag.file, path);
	CHECK_STR_CONTAINS(diag.message, "cannot open for writing");
	FILE* full = fopen("/dev/full", "w");
	if (full)
	{
		fclose(full);
		CHECK_INT(fmWriteTetGenNode("/dev/full", &mesh, NULL, &diag), fm_errIo);
		CHECK_STR_CONTAINS(diag.message, "cannot write: No space left on device");
	}
	mesh.positions[4] = NAN;
	CHECK_INT(fmWriteTetGenNode("mesh_io_never_written.node", &mesh, NULL, &diag), fm_errRange);
	CHECK_STR_CONTAINS(diag.message, "point 2 has a non-finite coordinate");
	CHECK(fopen("mesh_io_never_written.node", "r") == NULL);
	fmFreeTetMesh(&mesh);
}

TEST(large_generated_mesh_round_trip)
{
	// Large enough (about 1 MB) that the file reader grows its buffer several times.
	fmTetMesh box, back;
	CHECK_INT(fmMakeBoxMesh(20, 20, 20, fmMakeVec3(-1, -2, -3), fmMakeVec3(1, 0.5, 3), &box),
	          fm_ok);
	box.firstIndex = 1;
	const char* nodePath = "mesh_io_box.node";
	const char* elePath = "mesh_io_box.ele";
	CHECK_INT(fmWriteTetGenNode(nodePath, &box, NULL, NULL), fm_ok);
	FILE* f = fopen(elePath, "w");
	CHECK(f != NULL);
	if (f == NULL)
		return;
	fprintf(f, "%d 4 0\n", box.tetCount);
	for (int t = 0; t < box.tetCount; ++t)
		fprintf(f, "%d %d %d %d %d\n", t + 1, box.tets[4 * t] + 1, box.tets[4 * t + 1] + 1,
		        box.tets[4 * t + 2] + 1, box.tets[4 * t + 3] + 1);
	fclose(f);
	fmDiagnostic diag;
	CHECK_INT(fmLoadTetGen(nodePath, elePath, &back, &diag), fm_ok);
	CHECK_INT(diag.warningCount, 0);
	CHECK_INT(back.nodeCount, box.nodeCount);
	CHECK_INT(back.tetCount, box.tetCount);
	CHECK(sameBits(back.positions, box.positions, sizeof(double) * 3 * (size_t)box.nodeCount));
	CHECK(sameBits(back.tets, box.tets, sizeof(int) * 4 * (size_t)box.tetCount));
	remove(nodePath);
	remove(elePath);
	fmFreeTetMesh(&box);
	fmFreeTetMesh(&back);
}
