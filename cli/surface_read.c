// Surface readers of `femto mesh` (surface_read.h): STL, OFF and ASCII PLY, written to their
// descriptions (the StereoLithography Interface Specification of 3D Systems, Geomview's OFF
// manual page, Greg Turk's PLY description). Every count is checked against the limits and the
// data; errors say the file and line.
#include "surface_read.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void cliSurface_Free(cliSurface* s)
{
	free(s->x);
	free(s->triangles);
	memset(s, 0, sizeof *s);
}

bool cliSurface_AddVertex(cliSurface* s, double x, double y, double z)
{
	if (s->vertexCount == FM_MAX_SURFACE_VERTICES)
		return false;
	if (s->vertexCount == s->vertexCapacity)
	{
		int capacity = s->vertexCapacity > 0 ? 2 * s->vertexCapacity : 1024;
		capacity = capacity < FM_MAX_SURFACE_VERTICES ? capacity : FM_MAX_SURFACE_VERTICES;
		double* grown = realloc(s->x, sizeof(double) * 3 * (size_t)capacity);
		if (grown == NULL)
			return false;
		s->x = grown;
		s->vertexCapacity = capacity;
	}
	double* p = s->x + 3 * (size_t)s->vertexCount++;
	p[0] = x;
	p[1] = y;
	p[2] = z;
	return true;
}

bool cliSurface_AddTriangle(cliSurface* s, int a, int b, int c)
{
	if (s->triangleCount == FM_MAX_SURFACE_TRIANGLES)
		return false;
	if (s->triangleCount == s->triangleCapacity)
	{
		int capacity = s->triangleCapacity > 0 ? 2 * s->triangleCapacity : 1024;
		capacity = capacity < FM_MAX_SURFACE_TRIANGLES ? capacity : FM_MAX_SURFACE_TRIANGLES;
		int* grown = realloc(s->triangles, sizeof(int) * 3 * (size_t)capacity);
		if (grown == NULL)
			return false;
		s->triangles = grown;
		s->triangleCapacity = capacity;
	}
	int* t = s->triangles + 3 * (size_t)s->triangleCount++;
	t[0] = a;
	t[1] = b;
	t[2] = c;
	return true;
}

// A text being read line by line, with the line number for messages.
typedef struct cliText
{
	const char* name;
	char* at;
	int line;
	FILE* messages;
} cliText;

// The next line that is not empty or a '#' comment, NUL-terminated in place; NULL at the end.
static char* cliText_Line(cliText* t)
{
	while (*t->at != 0)
	{
		char* line = t->at;
		char* end = strchr(line, '\n');
		t->at = end != NULL ? end + 1 : line + strlen(line);
		if (end != NULL)
			*end = 0;
		t->line += 1;
		char* hash = strchr(line, '#');
		if (hash != NULL)
			*hash = 0;
		while (isspace((unsigned char)*line))
			++line;
		if (*line != 0)
			return line;
	}
	return NULL;
}

static bool cliTextFail(const cliText* t, const char* format, ...)
    __attribute__((format(printf, 2, 3)));

static bool cliTextFail(const cliText* t, const char* format, ...)
{
	if (t->messages == NULL)
		return false;
	fprintf(t->messages, "%s:%d: ", t->name, t->line);
	va_list args;
	va_start(args, format);
	vfprintf(t->messages, format, args);
	va_end(args);
	fputc('\n', t->messages);
	return false;
}

// Read @p count finite numbers from @p line.
static bool cliReadNumbers(char** line, double* out, int count)
{
	for (int k = 0; k < count; ++k)
	{
		char* end = NULL;
		out[k] = strtod(*line, &end);
		if (end == *line || !(out[k] - out[k] == 0.0))
			return false;
		*line = end;
	}
	return true;
}

// Read a whole number in [0, limit].
static bool cliReadCount(char** line, long* out, long limit)
{
	char* end = NULL;
	errno = 0;
	*out = strtol(*line, &end, 10);
	if (end == *line || errno != 0 || *out < 0 || *out > limit)
		return false;
	*line = end;
	return true;
}

// A polygon of @p count vertex indices from @p line, fan-triangulated.
static bool cliReadPolygon(cliText* t, char* line, long count, cliSurface* s)
{
	long first = 0, previous = 0;
	for (long k = 0; k < count; ++k)
	{
		long index;
		if (!cliReadCount(&line, &index, (long)s->vertexCount - 1))
			return cliTextFail(t, "expected %ld vertex indices in [0, %d]", count,
			                   s->vertexCount - 1);
		if (k == 0)
			first = index;
		else if (k >= 2 && !cliSurface_AddTriangle(s, (int)first, (int)previous, (int)index))
			return cliTextFail(t, "more than %d triangles, or out of memory",
			                   FM_MAX_SURFACE_TRIANGLES);
		previous = index;
	}
	return true;
}

// Polygons have at most this many vertices (a face line of a million indices is an error).
#define CLI_MAX_POLYGON 1000

// OFF: "OFF", the counts "V F E", V lines "x y z", F lines "n i0 .. in-1" (0-based).
static bool cliReadOff(cliText* t, cliSurface* s)
{
	char* line = cliText_Line(t);
	if (line == NULL || strncmp(line, "OFF", 3) != 0)
		return cliTextFail(t, "expected the OFF header");
	line += 3;
	while (isspace((unsigned char)*line))
		++line;
	if (*line == 0 && (line = cliText_Line(t)) == NULL)
		return cliTextFail(t, "expected the counts V F E");
	long vertices, faces;
	if (!cliReadCount(&line, &vertices, FM_MAX_SURFACE_VERTICES) ||
	    !cliReadCount(&line, &faces, FM_MAX_SURFACE_TRIANGLES))
		return cliTextFail(t, "expected the counts V F E (at most %d and %d)",
		                   FM_MAX_SURFACE_VERTICES, FM_MAX_SURFACE_TRIANGLES);
	for (long i = 0; i < vertices; ++i)
	{
		double p[3];
		if ((line = cliText_Line(t)) == NULL || !cliReadNumbers(&line, p, 3))
			return cliTextFail(t, "expected a vertex x y z (vertex %ld of %ld)", i, vertices);
		if (!cliSurface_AddVertex(s, p[0], p[1], p[2]))
			return cliTextFail(t, "out of memory");
	}
	for (long f = 0; f < faces; ++f)
	{
		long count;
		if ((line = cliText_Line(t)) == NULL || !cliReadCount(&line, &count, CLI_MAX_POLYGON) ||
		    count < 3)
			return cliTextFail(t, "expected a face: a vertex count in [3, %d], then the indices",
			                   CLI_MAX_POLYGON);
		if (!cliReadPolygon(t, line, count, s))
			return false;
	}
	return true;
}

// Most elements and properties a PLY header may declare.
#define CLI_PLY_ELEMENTS 16
#define CLI_PLY_PROPERTIES 64

typedef struct cliPlyElement
{
	char name[32];
	long count;
	int properties;
	int xyz[3]; // the positions of x, y, z among the properties, -1 if absent
} cliPlyElement;

// The header up to "end_header". False (with a message) on a binary format or too many parts.
static bool cliReadPlyHeader(cliText* t, cliPlyElement* elements, int* elementCount)
{
	char* line = cliText_Line(t);
	if (line == NULL || strcmp(line, "ply") != 0)
		return cliTextFail(t, "expected the ply header");
	*elementCount = 0;
	while ((line = cliText_Line(t)) != NULL && strcmp(line, "end_header") != 0)
	{
		char word[32], type[32], name[64];
		long count = 0;
		if (strncmp(line, "format", 6) == 0 && strstr(line, "ascii") == NULL)
			return cliTextFail(t, "binary PLY is not read: save it as ASCII PLY (or STL, OBJ)");
		if (sscanf(line, "element %31s %ld", word, &count) == 2)
		{
			if (*elementCount == CLI_PLY_ELEMENTS || count < 0)
				return cliTextFail(t, "more than %d elements, or a negative count",
				                   CLI_PLY_ELEMENTS);
			cliPlyElement* e = &elements[(*elementCount)++];
			snprintf(e->name, sizeof e->name, "%s", word);
			e->count = count;
			e->properties = 0;
			e->xyz[0] = e->xyz[1] = e->xyz[2] = -1;
		}
		else if (sscanf(line, "property %31s %63s", type, name) == 2 && *elementCount > 0)
		{
			cliPlyElement* e = &elements[*elementCount - 1];
			if (e->properties == CLI_PLY_PROPERTIES)
				return cliTextFail(t, "more than %d properties in element %s", CLI_PLY_PROPERTIES,
				                   e->name);
			for (int k = 0; k < 3 && strcmp(type, "list") != 0; ++k)
				if (name[0] == "xyz"[k] && name[1] == 0)
					e->xyz[k] = e->properties;
			e->properties += 1;
		}
	}
	if (line == NULL)
		return cliTextFail(t, "the header has no end_header");
	return true;
}

// PLY in ASCII: the vertex element's x, y, z and the face element's "vertex_indices" lists;
// other elements are skipped line by line.
static bool cliReadPly(cliText* t, cliSurface* s)
{
	cliPlyElement elements[CLI_PLY_ELEMENTS];
	int elementCount = 0;
	if (!cliReadPlyHeader(t, elements, &elementCount))
		return false;
	for (int e = 0; e < elementCount; ++e)
	{
		const cliPlyElement* el = &elements[e];
		bool isVertex = strcmp(el->name, "vertex") == 0, isFace = strcmp(el->name, "face") == 0;
		if (isVertex && (el->xyz[0] < 0 || el->xyz[1] < 0 || el->xyz[2] < 0))
			return cliTextFail(t, "the vertex element lacks the properties x, y, z");
		if ((isVertex && el->count > FM_MAX_SURFACE_VERTICES) ||
		    (isFace && el->count > FM_MAX_SURFACE_TRIANGLES))
			return cliTextFail(t, "element %s: %ld entries, more than femto takes", el->name,
			                   el->count);
		for (long i = 0; i < el->count; ++i)
		{
			char* line = cliText_Line(t);
			if (line == NULL)
				return cliTextFail(t, "the file ends inside element %s (%ld of %ld)", el->name, i,
				                   el->count);
			if (isVertex)
			{
				double values[CLI_PLY_PROPERTIES];
				if (!cliReadNumbers(&line, values, el->properties))
					return cliTextFail(t, "expected %d numbers a vertex", el->properties);
				if (!cliSurface_AddVertex(s, values[el->xyz[0]], values[el->xyz[1]],
				                          values[el->xyz[2]]))
					return cliTextFail(t, "out of memory");
			}
			else if (isFace)
			{
				long count;
				if (!cliReadCount(&line, &count, CLI_MAX_POLYGON) || count < 3)
					return cliTextFail(t,
					                   "expected a face: a vertex count in [3, %d], then the "
					                   "indices",
					                   CLI_MAX_POLYGON);
				if (!cliReadPolygon(t, line, count, s))
					return false;
			}
		}
	}
	return true;
}

// An STL corner and where it came from, sorted by coordinates to weld equal ones.
typedef struct cliCorner
{
	double x[3];
	int index;
} cliCorner;

static int cliCompareCorners(const void* a, const void* b)
{
	const cliCorner* p = a;
	const cliCorner* q = b;
	for (int k = 0; k < 3; ++k)
		if (p->x[k] != q->x[k])
			return p->x[k] < q->x[k] ? -1 : 1;
	return p->index < q->index ? -1 : (p->index > q->index);
}

// STL repeats each corner in every facet: corners with the same coordinates become one vertex.
static bool cliWeldCorners(cliCorner* corners, int cornerCount, cliSurface* s)
{
	int* vertex = malloc(sizeof(int) * (size_t)(cornerCount > 0 ? cornerCount : 1));
	bool ok = vertex != NULL;
	if (ok && cornerCount > 0) // (an STL with no facets has no array to sort)
		qsort(corners, (size_t)cornerCount, sizeof *corners, cliCompareCorners);
	for (int i = 0; ok && i < cornerCount; ++i)
	{
		const double* p = corners[i].x;
		const double* q = i > 0 ? corners[i - 1].x : NULL;
		if (q == NULL || p[0] != q[0] || p[1] != q[1] || p[2] != q[2])
			ok = cliSurface_AddVertex(s, p[0], p[1], p[2]);
		vertex[corners[i].index] = s->vertexCount - 1;
	}
	for (int t = 0; ok && t < cornerCount / 3; ++t)
		ok = cliSurface_AddTriangle(s, vertex[3 * t], vertex[3 * t + 1], vertex[3 * t + 2]);
	free(vertex);
	return ok;
}

static float cliFloatLE(const unsigned char* p)
{
	uint32_t bits =
	    (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
	float value;
	memcpy(&value, &bits, sizeof value);
	return value;
}

// Binary STL: an 80-byte header, a little-endian facet count, 50 bytes a facet (normal, three
// corners as little-endian floats, two attribute bytes).
static bool cliReadStlBinary(cliText* t, const unsigned char* bytes, uint32_t facets,
                             cliCorner* corners)
{
	for (uint32_t f = 0; f < facets; ++f)
		for (int k = 0; k < 9; ++k)
		{
			size_t at = 84 + 50 * (size_t)f + 12 + 4 * (size_t)k;
			double v = cliFloatLE(bytes + at);
			if (!(v - v == 0.0))
			{
				if (t->messages != NULL)
					fprintf(t->messages,
					        "%s: byte %zu: facet %u has a coordinate that is not "
					        "finite\n",
					        t->name, at, f);
				return false;
			}
			corners[3 * (size_t)f + (size_t)(k / 3)].x[k % 3] = v;
			corners[3 * (size_t)f + (size_t)(k / 3)].index = (int)(3 * f + (uint32_t)(k / 3));
		}
	return true;
}

// ASCII STL: "solid", facets of "outer loop" and three "vertex x y z". Only the vertex lines
// carry data; their count must be a multiple of 3.
static bool cliReadStlAscii(cliText* t, cliCorner** corners, int* cornerCount)
{
	char* line = cliText_Line(t);
	if (line == NULL || strncmp(line, "solid", 5) != 0)
		return cliTextFail(t, "neither binary STL (the size does not match the facet count) nor "
		                      "ASCII STL (\"solid\" expected)");
	int capacity = 0;
	while ((line = cliText_Line(t)) != NULL)
	{
		if (strncmp(line, "vertex", 6) != 0)
			continue;
		line += 6;
		double p[3];
		if (!cliReadNumbers(&line, p, 3))
			return cliTextFail(t, "expected vertex x y z");
		if (*cornerCount == capacity)
		{
			if (capacity >= FM_MAX_SURFACE_TRIANGLES)
				return cliTextFail(t, "more than %d facets", FM_MAX_SURFACE_TRIANGLES / 3);
			capacity = capacity > 0 ? 2 * capacity : 3072;
			cliCorner* grown = realloc(*corners, sizeof(cliCorner) * (size_t)capacity);
			if (grown == NULL)
				return cliTextFail(t, "out of memory");
			*corners = grown;
		}
		cliCorner* c = &(*corners)[(*cornerCount)++];
		memcpy(c->x, p, sizeof p);
		c->index = *cornerCount - 1;
	}
	if (*cornerCount % 3 != 0)
		return cliTextFail(t, "%d vertex lines: not a whole number of triangles", *cornerCount);
	return true;
}

static bool cliReadStl(cliText* t, const unsigned char* bytes, size_t size, cliSurface* s)
{
	uint32_t facets = size >= 84 ? (uint32_t)bytes[80] | (uint32_t)bytes[81] << 8 |
	                                   (uint32_t)bytes[82] << 16 | (uint32_t)bytes[83] << 24
	                             : 0;
	bool binary = size >= 84 && (size - 84) % 50 == 0 && (size - 84) / 50 == facets;
	cliCorner* corners = NULL;
	int cornerCount = 0;
	bool ok;
	if (binary)
	{
		if (facets > (uint32_t)(FM_MAX_SURFACE_TRIANGLES / 3))
		{
			if (t->messages != NULL)
				fprintf(t->messages, "%s: %u facets, more than femto takes\n", t->name, facets);
			return false;
		}
		corners = malloc(sizeof(cliCorner) * 3 * (size_t)(facets > 0 ? facets : 1));
		ok = corners != NULL && cliReadStlBinary(t, bytes, facets, corners);
		cornerCount = 3 * (int)facets;
	}
	else
		ok = cliReadStlAscii(t, &corners, &cornerCount);
	if (ok && !cliWeldCorners(corners, cornerCount, s))
	{
		if (t->messages != NULL)
			fprintf(t->messages, "%s: more vertices than femto takes, or out of memory\n", t->name);
		ok = false;
	}
	free(corners);
	return ok;
}

bool cliReadSurface(const char* name, const char* data, size_t size, cliSurfaceFormat format,
                    FILE* messages, cliSurface* surface)
{
	memset(surface, 0, sizeof *surface);
	char* copy = malloc(size + 1);
	if (copy == NULL)
	{
		if (messages != NULL)
			fprintf(messages, "%s: out of memory\n", name);
		return false;
	}
	memcpy(copy, data, size);
	copy[size] = 0;
	cliText t = {name, copy, 0, messages};
	bool ok;
	if (format == cli_surfaceStl)
		ok = cliReadStl(&t, (const unsigned char*)copy, size, surface);
	else if (memchr(copy, 0, size) != NULL)
		ok = cliTextFail(&t, "a NUL byte in a text file (binary %s is not read)",
		                 format == cli_surfacePly ? "PLY" : "data");
	else
		ok = format == cli_surfaceOff ? cliReadOff(&t, surface) : cliReadPly(&t, surface);
	free(copy);
	if (!ok)
		cliSurface_Free(surface);
	return ok;
}
