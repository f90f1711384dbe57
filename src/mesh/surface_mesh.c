// Wavefront OBJ reading into a triangle surface (fmSurfaceMesh), for mesh colliders.
// Written to the OBJ specification (Wavefront's "Object Files (.obj)", Appendix B1 of the
// Advanced Visualizer manual): `v x y z [w]`; `f v1 v2 v3 ...` where each reference is `v`,
// `v/vt`, `v//vn` or `v/vt/vn`, a negative number counting back from the last element of its
// kind read so far; the grouping and display statements do not change the geometry.
// Two passes over the text: the first counts vertices, texture and normal vertices and
// triangles (checked against the limits), so the arrays are allocated once at their exact size
// and never grow; the second parses. Every failure names the file, line, column and what was
// expected (the TetGen readers' text_reader.c and its limits).
// POSIX for open, fstat and read: the file is checked through its descriptor before reading.
#define _POSIX_C_SOURCE 200809L

#include "core/core.h"
#include "mesh/mesh_file.h"
#include "mesh/mesh_internal.h"
#include "mesh/text_reader.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Most vertices of one face: every field of a record but the keyword.
#define FM_OBJ_MAX_FACE_VERTICES (FM_READER_MAX_FIELDS - 1)

// Statements that do not change the polygonal geometry: texture and normal vertices (counted
// for the references' checks), parameter-space vertices, grouping, display and rendering
// attributes, and lines and points (not surfaces).
static const char* const s_ignored[] = {"vt",     "vn",     "vp",         "o",         "g",
                                        "s",      "mg",     "usemtl",     "mtllib",    "l",
                                        "p",      "lod",    "bevel",      "c_interp",  "d_interp",
                                        "maplib", "usemap", "shadow_obj", "trace_obj", NULL};

// Free-form geometry: curves and surfaces femto does not tessellate.
static const char* const s_freeForm[] = {"cstype", "deg",  "bmat",  "step",  "curv", "curv2",
                                         "surf",   "parm", "trim",  "hole",  "scrv", "sp",
                                         "end",    "con",  "ctech", "stech", NULL};

// What the first pass found.
typedef struct fmObjCounts
{
	int vertices;
	int texCoords;
	int normals;
	int triangles;
} fmObjCounts;

// References read so far in the second pass (negative references count back from these).
typedef struct fmObjCursor
{
	int vertices;
	int texCoords;
	int normals;
} fmObjCursor;

static bool fmObjKeywordIs(const fmTextReader* r, const char* word)
{
	size_t length = strlen(word);
	return (size_t)r->fieldLength[0] == length && memcmp(r->field[0], word, length) == 0;
}

static bool fmObjKeywordIn(const fmTextReader* r, const char* const* words)
{
	for (int i = 0; words[i] != NULL; ++i)
		if (fmObjKeywordIs(r, words[i]))
			return true;
	return false;
}

// A '\' ending the line continues it on the next (optional in the specification): refused, with
// the fix, rather than reading half a statement.
static fmResult fmObjCheckContinuation(const fmTextReader* r)
{
	int last = (r->fieldCount < FM_READER_MAX_FIELDS ? r->fieldCount : FM_READER_MAX_FIELDS) - 1;
	const char* field = r->field[last];
	int length = r->fieldLength[last];
	if (length > 0 && field[length - 1] == '\\')
		return fmReader_Error(r, fm_errSyntax, last,
		                      "line continuation ('\\' at the end of the line) is not supported: "
		                      "expected the statement on one line");
	return fm_ok;
}

// Keywords other than v and f: ignored, or refused with what was expected.
static fmResult fmObjCheckOther(const fmTextReader* r)
{
	if (fmObjKeywordIn(r, s_ignored))
		return fm_ok;
	int shown = r->fieldLength[0] < 40 ? r->fieldLength[0] : 40;
	if (fmObjKeywordIn(r, s_freeForm))
		return fmReader_Error(r, fm_errSyntax, 0,
		                      "free-form geometry (\"%.*s\") is not supported: expected polygons "
		                      "(f) over vertices (v)",
		                      shown, r->field[0]);
	return fmReader_Error(r, fm_errSyntax, 0,
	                      "unknown statement \"%.*s\": expected v, f, vt, vn, o, g, s, usemtl, "
	                      "mtllib or another OBJ statement",
	                      shown, r->field[0]);
}

// One more of something, within @p limit.
static fmResult fmObjCount(const fmTextReader* r, int* count, int add, int limit, const char* what)
{
	if (*count > limit - add)
		return fmReader_Error(r, fm_errLimit, 0, "more than %d %s: the limit of an OBJ file", limit,
		                      what);
	*count += add;
	return fm_ok;
}

// `v x y z [w]`, or `v x y z r g b` (vertex colours, a common extension).
static fmResult fmObjReadVertex(const fmTextReader* r, double* xyz)
{
	const char* layout = "v <x> <y> <z> [<w>], or v <x> <y> <z> <r> <g> <b>";
	int n = r->fieldCount;
	if (n < 4)
		return fmReader_ExpectFields(r, 4, 5, layout);
	if (n == 6 || n > 7)
		return fmReader_Error(r, fm_errSyntax, n == 6 ? 6 : 7, "%d numbers: expected %s", n - 1,
		                      layout);
	static const char* const names[] = {"x", "y", "z", "w", "r", "g", "b"};
	for (int k = 1; k < r->fieldCount; ++k)
	{
		double value = 0.0;
		fmResult result = fmReader_Double(r, k, names[k - 1], &value);
		if (result != fm_ok)
			return result;
		if (k <= 3)
			xyz[k - 1] = value;
	}
	return fm_ok;
}

// First pass: count every kind of record, check the vertices, the limits and the face sizes.
static fmResult fmObjCountRecords(fmTextReader* r, fmObjCounts* counts)
{
	memset(counts, 0, sizeof *counts);
	for (;;)
	{
		fmReadStatus status = fmReader_Next(r);
		if (status == fm_readError)
			return r->error;
		if (status == fm_readEnd)
			return fm_ok;
		fmResult result = fmObjCheckContinuation(r);
		if (result != fm_ok)
			return result;
		double xyz[3];
		if (fmObjKeywordIs(r, "v")) // checked here so that errors come in the file's order
		{
			result = fmObjReadVertex(r, xyz);
			if (result == fm_ok)
				result = fmObjCount(r, &counts->vertices, 1, FM_MAX_SURFACE_VERTICES, "vertices");
		}
		else if (fmObjKeywordIs(r, "vt"))
			result = fmObjCount(r, &counts->texCoords, 1, INT_MAX, "texture vertices");
		else if (fmObjKeywordIs(r, "vn"))
			result = fmObjCount(r, &counts->normals, 1, INT_MAX, "normals");
		else if (fmObjKeywordIs(r, "f"))
		{
			if (r->fieldCount > FM_READER_MAX_FIELDS)
				return fmReader_Error(r, fm_errLimit, FM_READER_MAX_FIELDS - 1,
				                      "a face of %d vertices: expected at most %d",
				                      r->fieldCount - 1, FM_OBJ_MAX_FACE_VERTICES);
			result =
			    fmReader_ExpectFields(r, 4, FM_READER_MAX_FIELDS, "f <v1> <v2> <v3> [<v4> ...]");
			if (result == fm_ok)
				result = fmObjCount(r, &counts->triangles, r->fieldCount - 3,
				                    FM_MAX_SURFACE_TRIANGLES, "triangles");
		}
		else
			result = fmObjCheckOther(r);
		if (result != fm_ok)
			return result;
	}
}

// Parse the decimal integer @p text[0..length) (sign allowed) into *value; false if it is not
// one or if its magnitude exceeds INT_MAX.
static bool fmObjParseIndex(const char* text, int length, long long* value)
{
	if (length <= 0)
		return false; // an empty reference ("3/1/" at the end of the file): nothing to read
	int i = text[0] == '-' || text[0] == '+' ? 1 : 0;
	if (i >= length)
		return false;
	long long v = 0;
	for (; i < length; ++i)
	{
		if (text[i] < '0' || text[i] > '9')
			return false;
		v = 10 * v + (text[i] - '0');
		if (v > INT_MAX)
			return false;
	}
	*value = text[0] == '-' ? -v : v;
	return true;
}

// Resolve one reference of kind @p what ("vertex", ...): 1..total, or -1..-soFar counting back
// from the last one read. 0-based result in *out.
static fmResult fmObjResolve(const fmTextReader* r, int field, const char* text, int length,
                             int soFar, int total, const char* what, int* out)
{
	long long value = 0;
	int shown = length < 40 ? length : 40;
	if (!fmObjParseIndex(text, length, &value))
		return fmReader_Error(r, fm_errSyntax, field,
		                      "%s reference \"%.*s\" is not an integer: expected v, v/vt, v//vn "
		                      "or v/vt/vn with nonzero integers",
		                      what, shown, text);
	if (value > 0 && value <= total)
	{
		*out = (int)value - 1;
		return fm_ok;
	}
	if (value < 0 && -value <= soFar)
	{
		*out = soFar + (int)value;
		return fm_ok;
	}
	if (value == 0)
		return fmReader_Error(r, fm_errIndex, field,
		                      "%s reference 0: OBJ numbers from 1 (or from -1 backwards)", what);
	if (value > 0)
		return fmReader_Error(r, fm_errIndex, field,
		                      "%s reference %lld: expected 1 to %d (the file has %d)", what, value,
		                      total, total);
	return fmReader_Error(r, fm_errIndex, field,
	                      "%s reference %lld: expected -1 to -%d (%d read before this line)", what,
	                      value, soFar, soFar);
}

// One face reference: `v`, `v/vt`, `v//vn` or `v/vt/vn`; the vertex in *vertex (0-based).
static fmResult fmObjReadReference(const fmTextReader* r, int field, const fmObjCounts* counts,
                                   const fmObjCursor* cursor, int* vertex)
{
	const char* text = r->field[field];
	int length = r->fieldLength[field];
	int start[3] = {0, 0, 0}, end[3] = {length, 0, 0}, parts = 1;
	for (int i = 0; i < length; ++i)
	{
		if (text[i] != '/')
			continue;
		if (parts == 3)
			return fmReader_Error(r, fm_errSyntax, field,
			                      "too many '/' in \"%.*s\": expected v, v/vt, v//vn or v/vt/vn",
			                      length < 40 ? length : 40, text);
		end[parts - 1] = i;
		start[parts] = i + 1;
		end[parts] = length;
		parts += 1;
	}
	fmResult result =
	    fmObjResolve(r, field, text, end[0], cursor->vertices, counts->vertices, "vertex", vertex);
	int ignored = 0;
	bool hasTex = parts >= 2 && end[1] > start[1];
	if (result == fm_ok && parts == 2 && !hasTex)
		return fmReader_Error(r, fm_errSyntax, field,
		                      "empty texture reference in \"%.*s\": expected v, v/vt, v//vn or "
		                      "v/vt/vn",
		                      length < 40 ? length : 40, text);
	if (result == fm_ok && hasTex)
		result = fmObjResolve(r, field, text + start[1], end[1] - start[1], cursor->texCoords,
		                      counts->texCoords, "texture vertex", &ignored);
	if (result == fm_ok && parts == 3)
		result = fmObjResolve(r, field, text + start[2], end[2] - start[2], cursor->normals,
		                      counts->normals, "normal", &ignored);
	return result;
}

// `f v1 v2 v3 ...`: a polygon, fan-triangulated from its first vertex into @p triangles.
static fmResult fmObjReadFace(const fmTextReader* r, const fmObjCounts* counts,
                              const fmObjCursor* cursor, int* triangles)
{
	int corners[FM_OBJ_MAX_FACE_VERTICES];
	int n = r->fieldCount - 1;
	for (int k = 0; k < n; ++k)
	{
		fmResult result = fmObjReadReference(r, k + 1, counts, cursor, &corners[k]);
		if (result != fm_ok)
			return result;
	}
	for (int k = 1; k + 1 < n; ++k)
	{
		int* t = triangles + 3 * (k - 1);
		t[0] = corners[0];
		t[1] = corners[k];
		t[2] = corners[k + 1];
	}
	return fm_ok;
}

// Second pass: the records, into arrays sized by the first.
static fmResult fmObjReadRecords(fmTextReader* r, const fmObjCounts* counts, fmSurfaceMesh* s)
{
	fmObjCursor cursor = {0, 0, 0};
	int triangles = 0;
	for (;;)
	{
		fmReadStatus status = fmReader_Next(r);
		if (status != fm_readRecord)
			return status == fm_readError ? r->error : fm_ok;
		fmResult result = fm_ok;
		if (fmObjKeywordIs(r, "v"))
			result = fmObjReadVertex(r, s->positions + 3 * (size_t)cursor.vertices++);
		else if (fmObjKeywordIs(r, "vt"))
			cursor.texCoords += 1;
		else if (fmObjKeywordIs(r, "vn"))
			cursor.normals += 1;
		else if (fmObjKeywordIs(r, "f"))
		{
			FM_ASSERT(triangles + r->fieldCount - 3 <= counts->triangles);
			result = fmObjReadFace(r, counts, &cursor, s->triangles + 3 * (size_t)triangles);
			triangles += r->fieldCount - 3;
		}
		if (result != fm_ok)
			return result;
	}
}

static fmResult fmObjAllocate(const fmObjCounts* counts, const char* name, fmSurfaceMesh* s,
                              fmDiagnostic* diag)
{
	s->positions = FM_ALLOC_ARRAY(double, 3 * (size_t)counts->vertices);
	s->triangles = FM_ALLOC_ARRAY(int, 3 * (size_t)counts->triangles);
	s->vertexCount = counts->vertices;
	s->triangleCount = counts->triangles;
	if (s->positions == NULL || s->triangles == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, name, 0, 0,
		                   "out of memory for %d vertices and %d triangles", counts->vertices,
		                   counts->triangles);
	return fm_ok;
}

static fmResult fmObjParse(const char* text, size_t size, const char* name, fmSurfaceMesh* s,
                           fmDiagnostic* diag)
{
	fmTextReader r;
	fmResult result = fmReader_Init(&r, text, size, name, diag);
	if (result != fm_ok)
	{
		// The reader names TetGen in its message: say OBJ, at the same line and column.
		if (diag != NULL)
			snprintf(diag->message, sizeof diag->message,
			         "NUL byte in the text: expected an OBJ text file, not binary data");
		return result;
	}
	fmObjCounts counts;
	result = fmObjCountRecords(&r, &counts);
	if (result == fm_ok && counts.vertices == 0)
		return fmDiagError(diag, fm_errEmpty, name, 0, 0, "no vertices: expected v <x> <y> <z>");
	if (result == fm_ok && counts.triangles == 0)
		return fmDiagError(diag, fm_errEmpty, name, 0, 0,
		                   "no faces: expected f <v1> <v2> <v3> (a surface of triangles or "
		                   "polygons)");
	if (result == fm_ok)
		result = fmObjAllocate(&counts, name, s, diag);
	if (result == fm_ok)
		result = fmReader_Init(&r, text, size, name, diag);
	if (result == fm_ok)
		result = fmObjReadRecords(&r, &counts, s);
	return result;
}

fmResult fmLoadObjFromMemory(const char* text, size_t size, const char* name,
                             fmSurfaceMesh* surface, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(surface != NULL);
	if (surface == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "no surface to load into");
	memset(surface, 0, sizeof *surface);
	name = name ? name : "<obj text>";
	if (text == NULL && size > 0)
		return fmDiagError(diag, fm_errParameter, name, 0, 0, "no text for %zu bytes", size);
	fmSurfaceMesh s;
	memset(&s, 0, sizeof s);
	fmResult result = fmObjParse(text, size, name, &s, diag);
	if (result != fm_ok)
	{
		fmFreeSurfaceMesh(&s);
		return result;
	}
	*surface = s;
	return fm_ok;
}

// ---- files ------------------------------------------------------------------------------------

fmResult fmLoadObjWithDef(const char* path, const fmMeshLoadDef* def, fmSurfaceMesh* surface,
                          fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(surface != NULL && def != NULL && def->internalValue == FM_DEF_MAGIC);
	if (surface == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "no surface to load into");
	memset(surface, 0, sizeof *surface);
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "mesh load def not initialised: start from fmDefaultMeshLoadDef()");
	if (path == NULL)
		return fmDiagError(diag, fm_errIo, "", 0, 0, "cannot open: no path given");
	fmFileText text;
	fmResult result = fmReadWholeFile(path, def->maxFileBytes, &text, diag);
	if (result == fm_ok)
		result = fmLoadObjFromMemory(text.data, text.size, path, surface, diag);
	fmFileText_Free(&text);
	return result;
}

fmResult fmLoadObj(const char* path, fmSurfaceMesh* surface, fmDiagnostic* diag)
{
	fmMeshLoadDef def = fmDefaultMeshLoadDef();
	return fmLoadObjWithDef(path, &def, surface, diag);
}

// ---- placement and ownership ------------------------------------------------------------------

// Counts and arrays agree and every triangle names a vertex.
static bool fmSurfaceMesh_IsConsistent(const fmSurfaceMesh* s)
{
	if (s == NULL || s->vertexCount < 0 || s->triangleCount < 0)
		return false;
	if ((s->vertexCount > 0) != (s->positions != NULL) ||
	    (s->triangleCount > 0) != (s->triangles != NULL))
		return false;
	for (size_t k = 0; k < 3 * (size_t)s->triangleCount; ++k)
		if (s->triangles[k] < 0 || s->triangles[k] >= s->vertexCount)
			return false;
	return true;
}

void fmSurfaceMesh_Transform(fmSurfaceMesh* surface, const fmMeshTransform* transform)
{
	bool valid = fmSurfaceMesh_IsConsistent(surface) && transform != NULL &&
	             transform->scale > 0.0 && isfinite(transform->scale) &&
	             isfinite(transform->translate.x) && isfinite(transform->translate.y) &&
	             isfinite(transform->translate.z);
	FM_ASSERT(valid);
	if (!valid)
		return;
	fmTransformPoints(surface->positions, surface->vertexCount, transform);
	// A mirror turns counter-clockwise into clockwise: swap two corners to keep the fronts.
	for (int t = 0; transform->swapYZ && t < surface->triangleCount; ++t)
	{
		int* tri = surface->triangles + 3 * (size_t)t;
		int keep = tri[1];
		tri[1] = tri[2];
		tri[2] = keep;
	}
}

void fmFreeSurfaceMesh(fmSurfaceMesh* surface)
{
	if (surface == NULL)
		return;
	size_t n = (size_t)(surface->vertexCount > 0 ? surface->vertexCount : 0);
	size_t m = (size_t)(surface->triangleCount > 0 ? surface->triangleCount : 0);
	FM_FREE_ARRAY(surface->positions, double, 3 * n);
	FM_FREE_ARRAY(surface->triangles, int, 3 * m);
	memset(surface, 0, sizeof *surface);
}
