// OBJ reading (fmLoadObj*): every statement of the format femto reads or ignores, every
// reference form, relative references, fan triangulation, and one malformed input per error
// (result, line, column and message checked, nothing leaked, the surface left zeroed); files
// (size limit, directories); the surface transform and its winding.
#define _POSIX_C_SOURCE 200809L

#include "test.h"

#include <femto/femto.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#define TEXT(s) (s), sizeof(s) - 1

static bool surfaceIsZero(const fmSurfaceMesh* s)
{
	return s->vertexCount == 0 && s->triangleCount == 0 && s->positions == NULL &&
	       s->triangles == NULL;
}

// Load @p text, expect success with @p vertices and the triangles @p expected (3 per triangle).
static void expectSurface(int* failures_, int callerLine, const char* text, size_t size,
                          int vertices, const int* expected, int triangles)
{
	fmSurfaceMesh s;
	fmDiagnostic diag;
	fmResult r = fmLoadObjFromMemory(text, size, "t.obj", &s, &diag);
	if (r != fm_ok)
	{
		char message[1024];
		FAIL_AT("case at line %d: %s", callerLine,
		        fmDiagnostic_Format(&diag, message, sizeof message));
		return;
	}
	if (s.vertexCount != vertices || s.triangleCount != triangles)
		FAIL_AT("case at line %d: %d vertices and %d triangles, expected %d and %d", callerLine,
		        s.vertexCount, s.triangleCount, vertices, triangles);
	for (int k = 0; k < 3 * triangles && s.triangleCount == triangles; ++k)
		if (s.triangles[k] != expected[k])
			FAIL_AT("case at line %d: triangle %d corner %d is %d, expected %d", callerLine, k / 3,
			        k % 3, s.triangles[k], expected[k]);
	fmFreeSurfaceMesh(&s);
}

// Load @p text, expect @p expected at t.obj:line[:column] with @p message; the surface must be
// left zeroed and nothing leaked.
static void expectError(int* failures_, int callerLine, const char* text, size_t size,
                        fmResult expected, int line, int column, const char* message)
{
	size_t before = fmGetAllocatedBytes();
	fmSurfaceMesh s;
	fmDiagnostic diag;
	fmResult r = fmLoadObjFromMemory(text, size, "t.obj", &s, &diag);
	char formatted[1024];
	fmDiagnostic_Format(&diag, formatted, sizeof formatted);
	bool ok = r == expected && diag.result == expected && strcmp(diag.file, "t.obj") == 0 &&
	          diag.line == line && (column == 0 || diag.column == column) &&
	          strstr(diag.message, message) != NULL && surfaceIsZero(&s) &&
	          fmGetAllocatedBytes() == before;
	if (!ok)
		FAIL_AT("case at line %d: got %s \"%s\" (line %d, column %d); expected %s at t.obj:%d:%d "
		        "containing \"%s\"",
		        callerLine, fmResultName(r), formatted, diag.line, diag.column,
		        fmResultName(expected), line, column, message);
	if (r == fm_ok)
		fmFreeSurfaceMesh(&s);
}

#define EXPECT_SURFACE(text, vertices, ...)                                                        \
	do                                                                                             \
	{                                                                                              \
		static const int expected_[] = {__VA_ARGS__};                                              \
		expectSurface(failures_, __LINE__, TEXT(text), vertices, expected_,                        \
		              (int)(sizeof expected_ / sizeof expected_[0]) / 3);                          \
	} while (0)

#define EXPECT_ERROR(text, result, line, column, message)                                          \
	expectError(failures_, __LINE__, TEXT(text), result, line, column, message)

TEST(reads_triangles_with_their_coordinates)
{
	fmSurfaceMesh s;
	fmDiagnostic diag;
	static const char text[] = "v 0.5 -2 3e2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
	CHECK_INT(fmLoadObjFromMemory(TEXT(text), "t.obj", &s, &diag), fm_ok);
	CHECK_INT(s.vertexCount, 3);
	CHECK_INT(s.triangleCount, 1);
	if (s.vertexCount == 3)
	{
		CHECK_NEAR(s.positions[0], 0.5, 0.0);
		CHECK_NEAR(s.positions[1], -2.0, 0.0);
		CHECK_NEAR(s.positions[2], 300.0, 0.0);
		CHECK_NEAR(s.positions[7], 1.0, 0.0);
	}
	fmFreeSurfaceMesh(&s);
	CHECK(surfaceIsZero(&s));
}

TEST(polygons_are_fan_triangulated_in_their_winding)
{
	EXPECT_SURFACE("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", 4, 0, 1, 2, 0, 2, 3);
	EXPECT_SURFACE("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n", 5, 0, 1, 2, 0, 2,
	               3, 0, 3, 4);
	EXPECT_SURFACE("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 4 3 2\nf 1 2 4\n", 4, 3, 2, 1, 0, 1, 3);
}

TEST(every_reference_form_is_read)
{
	static const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
	                           "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
	                           "f 1 2 3\n"
	                           "f 1/1 2/2 3/3\n"
	                           "f 1//1 3//1 4//1\n"
	                           "f 1/1/1 3/3/1 4/2/1\n";
	EXPECT_SURFACE(text, 4, 0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 2, 3);
}

TEST(negative_references_count_back_from_the_last_read)
{
	// -1 is the last vertex read before the face, whatever comes after it.
	EXPECT_SURFACE("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\n", 4, 0, 1, 2, 0, 2,
	               3);
	EXPECT_SURFACE("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\nf -3/-1/-1 -2/-1/-1 -1//-1\n", 3,
	               0, 1, 2);
	// Absolute references may name a vertex defined later in the file.
	EXPECT_SURFACE("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 1 1 0\n", 3, 0, 1, 2);
}

TEST(optional_weight_colours_comments_and_ignored_statements)
{
	static const char text[] = "\xEF\xBB\xBF# exported by a modeller\r\n"
	                           "mtllib ground.mtl\r\n"
	                           "o ground\r\n"
	                           "g part one\r\n"
	                           "v 0 0 0 1\r\n"
	                           "v 1 0 0 0.5 0.5 0.5\r\n"
	                           "v 1 1 0   # trailing comment\r\n"
	                           "vp 0.5\r\n"
	                           "usemtl grass\r\n"
	                           "s off\r\n"
	                           "s 1\r\n"
	                           "mg 1 0.5\r\n"
	                           "l 1 2\r\n"
	                           "p 3\r\n"
	                           "\r\n"
	                           "\tf 1 2 3\r\n";
	EXPECT_SURFACE(text, 3, 0, 1, 2);
}

TEST(every_malformed_input_is_located)
{
	EXPECT_ERROR("v 0 0 0\nv 1 0\x00 0\n", fm_errSyntax, 2, 6, "NUL byte");
	EXPECT_ERROR("# nothing\n", fm_errEmpty, 0, 0, "no vertices");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\n", fm_errEmpty, 0, 0, "no faces");
	EXPECT_ERROR("v 0 0 0\nvertex 1 0 0\n", fm_errSyntax, 2, 1, "unknown statement \"vertex\"");
	EXPECT_ERROR("v 0 0 0\ncstype bspline\n", fm_errSyntax, 2, 1, "free-form geometry");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 \\\n3\n", fm_errSyntax, 4, 7,
	             "line continuation");
	EXPECT_ERROR("v 0 0 0\nv 1 0\n", fm_errSyntax, 2, 6, "missing field");
	EXPECT_ERROR("v 0 0 0 1 2\n", fm_errSyntax, 1, 12, "5 numbers");
	EXPECT_ERROR("v 0 0 0 1 2 3 4\n", fm_errSyntax, 1, 15, "7 numbers");
	EXPECT_ERROR("v 0 0 0\nv 1 abc 0\n", fm_errSyntax, 2, 5, "expected y (a number)");
	EXPECT_ERROR("v 0 0 nan\n", fm_errRange, 1, 7, "expected a finite number");
	EXPECT_ERROR("v 0 0 1e999\n", fm_errRange, 1, 7, "overflows a double");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nf 1 2\n", fm_errSyntax, 3, 6, "missing field");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 0 3\n", fm_errIndex, 4, 5, "vertex reference 0");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n", fm_errIndex, 4, 7,
	             "vertex reference 4: expected 1 to 3");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 1 1 0\n", fm_errIndex, 3, 9,
	             "vertex reference -3: expected -1 to -2");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2.5 3\n", fm_errSyntax, 4, 5, "not an integer");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 99999999999\n", fm_errSyntax, 4, 7,
	             "not an integer");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1/1/1/1 2 3\n", fm_errSyntax, 4, 3, "too many '/'");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1/ 2 3\n", fm_errSyntax, 4, 3,
	             "empty texture reference");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", fm_errIndex, 5, 3,
	             "texture vertex reference 2: expected 1 to 1");
	EXPECT_ERROR("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1//1 2//1 3//1\n", fm_errIndex, 4, 3,
	             "normal reference 1: expected 1 to 0");
	EXPECT_ERROR("v 0 0 0\rv 1 0 0\r", fm_errSyntax, 1, 8, "carriage return");
}

TEST(limits_are_enforced_before_allocation)
{
	// A face of 80 vertices: more than a record holds.
	char text[2048];
	int n = snprintf(text, sizeof text, "v 0 0 0\nv 1 0 0\nv 1 1 0\nf");
	for (int k = 0; k < 80; ++k)
		n += snprintf(text + n, sizeof text - (size_t)n, " %d", 1 + k % 3);
	n += snprintf(text + n, sizeof text - (size_t)n, "\n");
	expectError(failures_, __LINE__, text, (size_t)n, fm_errLimit, 4, 0, "a face of 80 vertices");
	// A line longer than FM_MAX_LINE.
	char* line = malloc(FM_MAX_LINE + 64);
	memset(line, ' ', FM_MAX_LINE + 63);
	memcpy(line, "v 0 0 0\nv", 9);
	line[FM_MAX_LINE + 62] = '\n';
	expectError(failures_, __LINE__, line, FM_MAX_LINE + 63, fm_errLimit, 2, FM_MAX_LINE + 1,
	            "bytes long");
	free(line);
}

static void writeFile(const char* path, const char* text)
{
	FILE* f = fopen(path, "wb");
	if (f != NULL)
	{
		fputs(text, f);
		fclose(f);
	}
}

TEST(files_are_read_within_the_limit)
{
	char path[] = "/tmp/femto_obj_XXXXXX";
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	if (fd < 0)
		return;
	close(fd);
	writeFile(path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
	fmSurfaceMesh s;
	fmDiagnostic diag;
	CHECK_INT(fmLoadObj(path, &s, &diag), fm_ok);
	CHECK_INT(s.triangleCount, 1);
	fmFreeSurfaceMesh(&s);
	fmMeshLoadDef def = fmDefaultMeshLoadDef();
	def.maxFileBytes = 16;
	CHECK_INT(fmLoadObjWithDef(path, &def, &s, &diag), fm_errLimit);
	CHECK_STR_CONTAINS(diag.message, "more than the limit of 16 bytes");
	CHECK(surfaceIsZero(&s));
	writeFile(path, "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
	CHECK_INT(fmLoadObj(path, &s, &diag), fm_errIndex);
	CHECK_STR_CONTAINS(diag.file, path);
	CHECK_INT(diag.line, 3);
	unlink(path);
	CHECK_INT(fmLoadObj(path, &s, &diag), fm_errIo);
	CHECK_STR_CONTAINS(diag.message, "cannot open");
	CHECK_INT(fmLoadObj("/tmp", &s, &diag), fm_errIo);
	CHECK_STR_CONTAINS(diag.message, "not a regular file");
}

TEST(transform_places_vertices_and_keeps_fronts)
{
	fmSurfaceMesh s;
	static const char text[] = "v 0 0 0\nv 2 0 0\nv 0 0 -2\nf 1 2 3\n";
	CHECK_INT(fmLoadObjFromMemory(TEXT(text), "t.obj", &s, NULL), fm_ok);
	if (s.vertexCount != 3)
		return;
	// The triangle faces +y (counter-clockwise seen from above).
	fmMeshTransform t = fmDefaultMeshTransform();
	t.scale = 0.5;
	t.center = true;
	t.swapYZ = true;
	t.translate = fmMakeVec3(1, 2, 3);
	fmSurfaceMesh_Transform(&s, &t);
	// Scaled: (0,0,0), (1,0,0), (0,0,-1); centroid (1/3, 0, -1/3); swapped and moved.
	CHECK_NEAR(s.positions[0], 1.0 - 1.0 / 3.0, 1e-15);
	CHECK_NEAR(s.positions[1], 2.0 + 1.0 / 3.0, 1e-15);
	CHECK_NEAR(s.positions[2], 3.0, 1e-15);
	CHECK_NEAR(s.positions[8], 3.0, 1e-15);
	CHECK_NEAR(s.positions[7], 2.0 - 2.0 / 3.0, 1e-15);
	// The mirror takes the front +y to +z: the winding was reversed so that the front follows.
	fmVec3 p[3];
	for (int k = 0; k < 3; ++k)
		p[k] = fmLoad(s.positions, s.triangles[k]);
	fmVec3 normal = fmCross(fmSub(p[1], p[0]), fmSub(p[2], p[0]));
	CHECK(normal.z > 0.0);
	CHECK_NEAR(normal.x, 0.0, 1e-15);
	fmFreeSurfaceMesh(&s);
}
