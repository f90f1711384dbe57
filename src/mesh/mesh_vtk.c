// VTK legacy mesh reading (docs/mesh-format.md), written to "The VTK User's Guide", chapter
// "VTK File Formats": .vtk in ASCII or BINARY (big-endian), DATASET UNSTRUCTURED_GRID, with the
// CELLS layout of versions before 5 and the OFFSETS/CONNECTIVITY layout of 5.1. Tets (cell type
// 10) are read, quadratic tets (type 24) by their four corners; other cells are counted and
// skipped. The cells-to-tets step is shared with the XML reader (mesh_vtu.c).
#include "mesh/mesh_vtk.h"

#include "core/core.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

// ---- cells to tets (the .vtk and .vtu readers)
// -------------------------------------------------------------

static const char* fmVtkKind(long long type)
{
	switch (type)
	{
	case 1:
	case 2:
		return "vertices";
	case 3:
	case 4:
	case 21:
		return "lines";
	case 5:
	case 6:
	case 22:
		return "triangles";
	case 7:
		return "polygons";
	case 8:
	case 9:
	case 23:
		return "quadrangles";
	case 11:
	case 12:
	case 25:
		return "hexahedra";
	case 13:
		return "wedges";
	case 14:
		return "pyramids";
	default:
		return "cells of other types";
	}
}

void fmVtkCells_Free(fmVtkCells* c)
{
	FM_FREE_ARRAY(c->start, long long, c->count + 1);
	FM_FREE_ARRAY(c->conn, int, c->connCount);
	FM_FREE_ARRAY(c->types, unsigned char, c->count);
	FM_FREE_ARRAY(c->regions, double, c->count);
	memset(c, 0, sizeof *c);
}

fmResult fmVtkCells_ToTets(const fmVtkCells* c, fmTetList* list, const fmScan* s)
{
	fmTetList_Init(list, c->count, c->regions != NULL);
	fmResult result = fm_ok;
	for (long long k = 0; k < c->count && result == fm_ok; ++k)
	{
		int type = c->types[k];
		long long n = c->start[k + 1] - c->start[k];
		if (type != 10 && type != 24)
		{
			fmSkipped_Add(&list->skipped, fmVtkKind(type), 1);
			continue;
		}
		if (n != (type == 10 ? 4 : 10))
			return fmScan_Error(s, fm_errCount,
			                    "cell %lld is a %stetra (type %d) with %lld points: expected %d", k,
			                    type == 24 ? "quadratic " : "", type, n, type == 10 ? 4 : 10);
		list->reducedQuadratic += type == 24;
		result = fmTetList_Add(list, c->conn + c->start[k], s->tokenLine,
		                       c->regions ? c->regions[k] : 0.0, s);
	}
	return result;
}

// ---- legacy .vtk ------------------------------------------------------------------------------

typedef struct fmVtkLegacy
{
	fmScan s;
	bool binary;
	int version; // major version of the header (5: OFFSETS/CONNECTIVITY)
	int nodeCount;
	double* positions;
	fmVtkCells cells;
	bool haveCells;
	bool haveTypes;
	int typesLine; // where CELL_TYPES is, for errors found when the cells become tets
	int typesColumn;
} fmVtkLegacy;

// Binary data starts after the line end that ends the keyword's line.
static fmResult fmVtkToBinary(fmScan* s)
{
	while (s->pos < s->size && s->data[s->pos] != '\n' &&
	       (s->data[s->pos] == ' ' || s->data[s->pos] == '\t' || s->data[s->pos] == '\r'))
		fmScan_Advance(s, 1);
	if (s->pos >= s->size || s->data[s->pos] != '\n')
		return fmScan_ErrorHere(s, fm_errSyntax, "expected a line end before the binary data");
	fmScan_Advance(s, 1);
	return fm_ok;
}

// The bytes per value of a legacy data type name (0: not a number type read here).
static int fmVtkLegacyTypeSize(const fmScan* s, bool* isFloat)
{
	static const struct
	{
		const char* name;
		int size;
		bool isFloat;
	} types[] = {{"float", 4, true},         {"double", 8, true},
	             {"int", 4, false},          {"unsigned_int", 4, false},
	             {"long", 8, false},         {"unsigned_long", 8, false},
	             {"vtktypeint64", 8, false}, {"vtktypeint32", 4, false},
	             {"short", 2, false},        {"unsigned_short", 2, false}};
	for (size_t k = 0; k < sizeof types / sizeof types[0]; ++k)
		if (fmScan_IsNoCase(s, types[k].name))
		{
			*isFloat = types[k].isFloat;
			return types[k].size;
		}
	return 0;
}

// One value of a legacy array: text, or big-endian binary of @p size bytes.
static fmResult fmVtkLegacyInt(fmVtkLegacy* v, int size, const char* what, long long lo,
                               long long hi, long long* out)
{
	if (!v->binary)
		return fmScan_Int64(&v->s, what, lo, hi, out);
	const unsigned char* b;
	fmResult result = fmScan_Bytes(&v->s, (size_t)size, what, &b);
	if (result != fm_ok)
		return result;
	bool swap = fmHostIsLittleEndian();
	long long value = size == 8   ? (long long)fmLoadU64(b, swap)
	                  : size == 4 ? (long long)(int32_t)fmLoadU32(b, swap)
	                              : (long long)(int16_t)((b[0] << 8) | b[1]);
	if (value < lo || value > hi)
		return fmScan_ErrorHere(&v->s, fm_errRange,
		                        "%s %lld before byte %zu is out of range: expected %lld to %lld",
		                        what, value, v->s.pos, lo, hi);
	*out = value;
	return fm_ok;
}

static fmResult fmVtkLegacyPoints(fmVtkLegacy* v)
{
	if (v->positions != NULL)
		return fmScan_Error(&v->s, fm_errSyntax, "a second POINTS: expected one");
	long long count = 0;
	fmResult result = fmScan_Int64(&v->s, "point count", 1, LLONG_MAX, &count);
	bool isFloat = false;
	int size = 0;
	if (result == fm_ok)
		result = fmScan_Expect(&v->s, "the data type (float or double)");
	if (result == fm_ok)
	{
		size = fmVtkLegacyTypeSize(&v->s, &isFloat);
		if (!isFloat)
			result = fmScan_Error(&v->s, fm_errSyntax,
			                      "point data type \"%.*s\": expected float or double",
			                      (int)(v->s.tokenLength < 20 ? v->s.tokenLength : 20), v->s.token);
	}
	if (result == fm_ok)
		result = fmScan_CheckCount(&v->s, count, FM_MAX_NODES, v->binary ? 3 * (size_t)size : 6,
		                           "points");
	if (result == fm_ok && v->binary)
		result = fmVtkToBinary(&v->s);
	if (result != fm_ok)
		return result;
	v->nodeCount = (int)count;
	v->positions = FM_ALLOC_ARRAY(double, 3 * (size_t)count);
	if (v->positions == NULL)
		return fmScan_Error(&v->s, fm_errOutOfMemory, "out of memory for %lld points", count);
	bool swap = fmHostIsLittleEndian();
	for (size_t k = 0; k < 3 * (size_t)count && result == fm_ok; ++k)
	{
		if (!v->binary)
		{
			result = fmScan_Double(&v->s, "point coordinate", &v->positions[k]);
			continue;
		}
		const unsigned char* b;
		result = fmScan_Bytes(&v->s, (size_t)size, "the points", &b);
		double x = result != fm_ok ? 0.0
		           : size == 8     ? fmLoadF64(b, swap)
		                           : (double)fmLoadF32(b, swap);
		if (result == fm_ok && !(x - x == 0.0))
			result = fmScan_ErrorHere(&v->s, fm_errRange,
			                          "point %zu has a coordinate that is not finite: expected "
			                          "finite numbers",
			                          k / 3);
		v->positions[k] = x;
	}
	return result;
}

// Allocate the cells: @p count cells of @p connCount node numbers in all.
static fmResult fmVtkAllocCells(fmVtkLegacy* v, long long count, long long connCount)
{
	fmVtkCells* c = &v->cells;
	c->count = count;
	c->connCount = connCount;
	c->start = FM_ALLOC_ARRAY(long long, count + 1);
	c->conn = FM_ALLOC_ARRAY(int, connCount > 0 ? connCount : 1);
	if (connCount == 0)
	{
		FM_FREE_ARRAY(c->conn, int, 1);
		c->conn = NULL;
	}
	if (c->start == NULL || (connCount > 0 && c->conn == NULL))
		return fmScan_Error(&v->s, fm_errOutOfMemory, "out of memory for %lld cells", count);
	c->start[0] = 0;
	return fm_ok;
}

// A node number of a cell, checked against the points read (POINTS comes first).
static fmResult fmVtkLegacyNode(fmVtkLegacy* v, int size, int* out)
{
	long long id = 0;
	char what[64];
	snprintf(what, sizeof what, "point number (0 to %d)", v->nodeCount - 1);
	fmResult result = fmVtkLegacyInt(v, size, what, 0, v->nodeCount - 1, &id);
	*out = (int)id;
	return result;
}

// Before version 5: "CELLS n size", then per cell "npts id...".
static fmResult fmVtkLegacyCells4(fmVtkLegacy* v, long long count, long long size)
{
	fmResult result = fmScan_CheckCount(&v->s, size, INT_MAX, v->binary ? 4 : 2, "cell values");
	if (result == fm_ok && size < count)
		result = fmScan_Error(&v->s, fm_errCount,
		                      "CELLS size %lld is less than its %lld cells: expected the count of "
		                      "every number in the list",
		                      size, count);
	if (result == fm_ok && v->binary)
		result = fmVtkToBinary(&v->s);
	if (result == fm_ok)
		result = fmVtkAllocCells(v, count, size - count);
	fmVtkCells* c = &v->cells;
	for (long long k = 0; k < count && result == fm_ok; ++k)
	{
		long long n = 0;
		result =
		    fmVtkLegacyInt(v, 4, "number of points of the cell", 0, c->connCount - c->start[k], &n);
		for (long long i = 0; i < n && result == fm_ok; ++i)
			result = fmVtkLegacyNode(v, 4, &c->conn[c->start[k] + i]);
		c->start[k + 1] = c->start[k] + n;
	}
	if (result == fm_ok && c->start[count] != c->connCount)
		result = fmScan_ErrorHere(&v->s, fm_errCount,
		                          "the cells hold %lld point numbers: CELLS declares %lld values "
		                          "(%lld with the counts)",
		                          c->start[count], c->connCount, size);
	return result;
}

// Version 5: "CELLS offsets connectivity", "OFFSETS type" values, "CONNECTIVITY type" values.
static fmResult fmVtkLegacyCells5(fmVtkLegacy* v, long long offsetCount, long long connCount)
{
	fmResult result = offsetCount < 1 ? fmScan_Error(&v->s, fm_errCount,
	                                                 "CELLS declares %lld offsets: expected at "
	                                                 "least 1 (cells + 1)",
	                                                 offsetCount)
	                                  : fm_ok;
	bool isFloat;
	int size = 0;
	if (result == fm_ok)
		result = fmScan_Word(&v->s, "OFFSETS", true);
	if (result == fm_ok)
		result = fmScan_Expect(&v->s, "the offsets' type");
	if (result == fm_ok && ((size = fmVtkLegacyTypeSize(&v->s, &isFloat)) == 0 || isFloat))
		result = fmScan_Error(&v->s, fm_errSyntax, "expected an integer type for OFFSETS");
	if (result == fm_ok)
		result = fmScan_CheckCount(&v->s, offsetCount + connCount, INT_MAX,
		                           v->binary ? (size_t)size : 2, "cell values");
	if (result == fm_ok && v->binary)
		result = fmVtkToBinary(&v->s);
	if (result == fm_ok)
		result = fmVtkAllocCells(v, offsetCount - 1, connCount);
	fmVtkCells* c = &v->cells;
	for (long long k = 0; k < offsetCount && result == fm_ok; ++k)
		result = fmVtkLegacyInt(v, size, "offset", k == 0 ? 0 : c->start[k - 1],
		                        k == 0 ? 0 : connCount, &c->start[k]);
	if (result == fm_ok && c->start[offsetCount - 1] != connCount)
		result = fmScan_Error(&v->s, fm_errCount,
		                      "the last offset is %lld: expected the connectivity size %lld",
		                      c->start[offsetCount - 1], connCount);
	if (result == fm_ok)
		result = fmScan_Word(&v->s, "CONNECTIVITY", true);
	if (result == fm_ok)
		result = fmScan_Expect(&v->s, "the connectivity's type");
	if (result == fm_ok && ((size = fmVtkLegacyTypeSize(&v->s, &isFloat)) == 0 || isFloat))
		result = fmScan_Error(&v->s, fm_errSyntax, "expected an integer type for CONNECTIVITY");
	if (result == fm_ok && v->binary)
		result = fmVtkToBinary(&v->s);
	for (long long k = 0; k < connCount && result == fm_ok; ++k)
		result = fmVtkLegacyNode(v, size, &c->conn[k]);
	return result;
}

static fmResult fmVtkLegacyCells(fmVtkLegacy* v)
{
	if (v->positions == NULL)
		return fmScan_Error(&v->s, fm_errSyntax, "CELLS before POINTS: expected the points first");
	if (v->haveCells)
		return fmScan_Error(&v->s, fm_errSyntax, "a second CELLS: expected one");
	v->haveCells = true;
	long long a = 0, b = 0;
	fmResult result =
	    fmScan_Int64(&v->s, v->version >= 5 ? "offset count" : "cell count", 0, LLONG_MAX, &a);
	if (result == fm_ok)
		result = fmScan_Int64(&v->s, v->version >= 5 ? "connectivity size" : "cell list size", 0,
		                      LLONG_MAX, &b);
	if (result == fm_ok)
		result = fmScan_CheckCount(&v->s, a, (long long)FM_MAX_TETS + FM_MAX_NODES,
		                           v->binary ? 4 : 2, "cells");
	if (result != fm_ok)
		return result;
	return v->version >= 5 ? fmVtkLegacyCells5(v, a, b) : fmVtkLegacyCells4(v, a, b);
}

static fmResult fmVtkLegacyTypes(fmVtkLegacy* v)
{
	if (!v->haveCells)
		return fmScan_Error(&v->s, fm_errSyntax,
		                    "CELL_TYPES before CELLS: expected the cells first");
	if (v->haveTypes)
		return fmScan_Error(&v->s, fm_errSyntax, "a second CELL_TYPES: expected one");
	v->haveTypes = true;
	v->typesLine = v->s.tokenLine;
	v->typesColumn = v->s.tokenColumn;
	long long count = 0;
	fmResult result = fmScan_Int64(&v->s, "cell type count", 0, LLONG_MAX, &count);
	if (result == fm_ok && count != v->cells.count)
		result = fmScan_Error(&v->s, fm_errCount, "CELL_TYPES declares %lld cells: CELLS has %lld",
		                      count, v->cells.count);
	if (result == fm_ok && v->binary)
		result = fmVtkToBinary(&v->s);
	if (result != fm_ok || count == 0)
		return result; // the count is only trusted once it matches the cells already read
	v->cells.types = FM_ALLOC_ARRAY(unsigned char, count);
	if (v->cells.types == NULL)
		result = fmScan_Error(&v->s, fm_errOutOfMemory, "out of memory for %lld cells", count);
	for (long long k = 0; k < count && result == fm_ok; ++k)
	{
		long long type = 0;
		result = fmVtkLegacyInt(v, 4, "cell type", 1, 255, &type);
		if (result == fm_ok)
			v->cells.types[k] = (unsigned char)type;
	}
	return result;
}

// Line 1 "# vtk DataFile Version x.y", line 2 a title, line 3 ASCII or BINARY, then DATASET.
static fmResult fmVtkLegacyHeader(fmVtkLegacy* v)
{
	fmScan* s = &v->s;
	static const char magic[] = "# vtk DataFile Version";
	size_t n = sizeof magic - 1;
	if (s->size == 0)
		return fmScan_ErrorHere(s, fm_errEmpty, "empty file: expected \"%s\"", magic);
	if (s->size < n || memcmp(s->data, magic, n) != 0)
		return fmScan_ErrorHere(s, fm_errSyntax, "expected the first line \"%s x.y\"", magic);
	fmScan_Advance(s, n);
	long long major = 0;
	fmResult result = fmScan_Expect(s, "the version");
	for (size_t k = 0; result == fm_ok && k < s->tokenLength && s->token[k] != '.'; ++k)
		major = s->token[k] >= '0' && s->token[k] <= '9' && major < 100
		            ? 10 * major + (s->token[k] - '0')
		            : 100;
	if (result == fm_ok && (major < 1 || major > 5))
		result = fmScan_Error(s, fm_errSyntax, "version \"%.*s\": expected 1.0 to 5.1",
		                      (int)(s->tokenLength < 20 ? s->tokenLength : 20), s->token);
	if (result != fm_ok)
		return result;
	v->version = (int)major;
	fmScan_SkipLine(s); // the rest of line 1
	fmScan_SkipLine(s); // the title
	result = fmScan_Expect(s, "ASCII or BINARY");
	if (result != fm_ok)
		return result;
	if (fmScan_IsNoCase(s, "BINARY"))
		v->binary = true;
	else if (!fmScan_IsNoCase(s, "ASCII"))
		return fmScan_Error(s, fm_errSyntax, "\"%.*s\" on line 3: expected ASCII or BINARY",
		                    (int)(s->tokenLength < 20 ? s->tokenLength : 20), s->token);
	result = fmScan_Word(s, "DATASET", true);
	if (result == fm_ok)
		result = fmScan_Expect(s, "the dataset type");
	if (result == fm_ok && !fmScan_IsNoCase(s, "UNSTRUCTURED_GRID"))
		result = fmScan_Error(s, fm_errSyntax,
		                      "DATASET %.*s is not read: expected UNSTRUCTURED_GRID (a tet mesh)",
		                      (int)(s->tokenLength < 30 ? s->tokenLength : 30), s->token);
	return result;
}

static fmResult fmVtkLegacySections(fmVtkLegacy* v)
{
	fmScan* s = &v->s;
	fmResult result = fmVtkLegacyHeader(v);
	bool attributes = false;
	while (result == fm_ok && !attributes && fmScan_Next(s))
	{
		if (fmScan_IsNoCase(s, "POINTS"))
			result = fmVtkLegacyPoints(v);
		else if (fmScan_IsNoCase(s, "CELLS"))
			result = fmVtkLegacyCells(v);
		else if (fmScan_IsNoCase(s, "CELL_TYPES"))
			result = fmVtkLegacyTypes(v);
		else if (fmScan_IsNoCase(s, "METADATA"))
		{
			// Text up to the next blank line (VTK 9 writes it after POINTS and CELLS).
			fmScan_SkipLine(s);
			while (
			    s->pos < s->size && s->data[s->pos] != '\n' &&
			    !(s->data[s->pos] == '\r' && s->pos + 1 < s->size && s->data[s->pos + 1] == '\n'))
				fmScan_SkipLine(s);
		}
		else if (fmScan_IsNoCase(s, "POINT_DATA") || fmScan_IsNoCase(s, "CELL_DATA") ||
		         fmScan_IsNoCase(s, "FIELD"))
			attributes = true; // the geometry is complete; data arrays are not read
		else
			result = fmScan_Error(s, fm_errSyntax,
			                      "\"%.*s\": expected POINTS, CELLS, CELL_TYPES or the data "
			                      "sections",
			                      (int)(s->tokenLength < 30 ? s->tokenLength : 30), s->token);
	}
	if (result == fm_ok && v->positions == NULL)
		result = fmScan_Error(s, fm_errEmpty, "the file has no POINTS: expected a mesh");
	if (result == fm_ok && !v->haveTypes)
		result = fmScan_Error(s, fm_errEmpty,
		                      "the file has no CELLS and CELL_TYPES: expected tetrahedra");
	return result;
}

fmResult fmParseVtkLegacy(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                          fmDiagnostic* diag)
{
	fmVtkLegacy v;
	memset(&v, 0, sizeof v);
	fmScan_Init(&v.s, data, size, name, diag);
	fmTetList list;
	memset(&list, 0, sizeof list);
	fmResult result = fmVtkLegacySections(&v);
	fmScan at = v.s;
	at.tokenLine = v.typesLine;
	at.tokenColumn = v.typesColumn;
	at.token = at.data + at.pos; // errors point at the types, not at a byte
	at.tokenLength = 0;
	if (result == fm_ok)
		result = fmVtkCells_ToTets(&v.cells, &list, &at);
	fmVtkCells_Free(&v.cells);
	if (result != fm_ok)
	{
		fmTetList_Free(&list);
		FM_FREE_ARRAY(v.positions, double, 3 * (size_t)v.nodeCount);
		return result;
	}
	return fmTetList_Finish(&list, v.positions, v.nodeCount, 0, name, mesh, diag);
}
