// TetGen .node / .ele / .face reading and .node writing (docs/mesh-format.md).
// Every count in a header is checked against the limits and against the bytes left in the text
// before anything is allocated; every field is parsed with overflow checks; every failure names
// the file, line, column and what was expected. Loading never reorients: fmTetMesh_Orient does.
#include "core/core.h"
#include "mesh/mesh_file.h"
#include "mesh/mesh_internal.h"
#include "mesh/text_reader.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// What a section header (first record of a .node, .ele or .face file) declares.
typedef struct fmSectionHeader
{
	const char* kind;      // "point", "tet", "face": used in messages
	const char* countName; // "point count", ...
	int count;             // records declared
	int line;              // line of the header
	int nodes;             // node references per record (tets: 4 or 10, faces: 3; points: 0)
	int attributes;        // attributes per record
	int markers;           // 1 if each record ends with a boundary marker
	int fields;            // fields per record, index column included
	char layout[128];      // the record layout, for messages
	bool warnedIndex;      // the index-column warning was given
} fmSectionHeader;

// ---- headers ----------------------------------------------------------------------------------

// The first record must exist and have @p minFields to @p maxFields fields.
static fmResult fmReadHeaderRecord(fmTextReader* r, int minFields, int maxFields,
                                   const char* layout)
{
	fmReadStatus status = fmReader_Next(r);
	if (status == fm_readError)
		return r->error;
	if (status == fm_readEnd)
		return fmDiagError(r->diag, fm_errEmpty, r->name, r->line, 0, "no header: expected \"%s\"",
		                   layout);
	return fmReader_ExpectFields(r, minFields, maxFields, layout);
}

// A header count is compared with the bytes that follow only when the arrays it asks for would
// exceed this: the comparison exists to refuse a huge allocation for a small file, and below this
// size the records are simply read, so a short file is reported where it ends (at the line with
// the missing field or record) instead of at the header.
#define FM_TRUSTED_HEADER_BYTES ((unsigned long long)1 << 20)

// A record count: >= 1, within @p limit, and, when it asks for much memory, small enough that the
// rest of the text can hold that many records of h->fields fields.
static fmResult fmReadCount(fmTextReader* r, fmSectionHeader* h, int limit)
{
	int n;
	fmResult result = fmReader_Int(r, 0, INT_MIN, INT_MAX, h->countName, &n);
	if (result != fm_ok)
		return result;
	if (n < 0)
		return fmReader_Error(r, fm_errRange, 0, "negative %s count %d: expected a count >= 1",
		                      h->kind, n);
	if (n == 0)
		return fmReader_Error(r, fm_errEmpty, 0, "the header declares 0 %ss: expected at least 1",
		                      h->kind);
	if (n > limit)
		return fmReader_Error(r, fm_errLimit, 0, "%d %ss exceed the limit of %d", n, h->kind,
		                      limit);
	// At most 8 bytes of arrays per field and a few more per record (line numbers, sort keys).
	unsigned long long memory = (unsigned long long)n * (8u * (unsigned long long)h->fields + 32u);
	// Each record is at least its fields, one byte each, and a separator after each field.
	unsigned long long need = (unsigned long long)n * 2u * (unsigned long long)h->fields - 1u;
	unsigned long long left = fmReader_Remaining(r);
	if (memory > FM_TRUSTED_HEADER_BYTES && need > left)
		return fmReader_Error(r, fm_errCount, 0,
		                      "the header declares %d %ss but only %llu bytes follow: expected at "
		                      "least %llu bytes (%d fields per %s)",
		                      n, h->kind, left, need, h->fields, h->kind);
	h->count = n;
	return fm_ok;
}

// Attribute count (field @p field) and the optional boundary-marker flag (field @p field + 1).
static fmResult fmReadHeaderTail(fmTextReader* r, fmSectionHeader* h, int field, bool hasMarkers)
{
	fmResult result = fm_ok;
	if (field >= 0 && r->fieldCount > field)
		result = fmReader_Int(r, field, 0, FM_MAX_ATTRIBUTES, "attribute count", &h->attributes);
	int markerField = hasMarkers ? (field >= 0 ? field + 1 : 1) : -1;
	if (result == fm_ok && markerField >= 0 && r->fieldCount > markerField)
		result = fmReader_Int(r, markerField, 0, 1, "boundary marker flag", &h->markers);
	h->fields = 1 + (h->nodes > 0 ? h->nodes : 3) + h->attributes + h->markers;
	int n = snprintf(h->layout, sizeof h->layout, "<%s #>", h->kind);
	if (h->nodes > 0)
		n += snprintf(h->layout + n, sizeof h->layout - (size_t)n, " <%d node numbers>", h->nodes);
	else
		n += snprintf(h->layout + n, sizeof h->layout - (size_t)n, " <x> <y> <z>");
	if (h->attributes > 0)
		n += snprintf(h->layout + n, sizeof h->layout - (size_t)n, " <%d attributes>",
		              h->attributes);
	if (h->markers)
		snprintf(h->layout + n, sizeof h->layout - (size_t)n, " <boundary marker>");
	return result;
}

// .node: <#points> <dimension (3)> [<#attributes> [<boundary markers (0 or 1)>]]
static fmResult fmReadNodeHeader(fmTextReader* r, fmSectionHeader* h)
{
	memset(h, 0, sizeof *h);
	h->kind = "point";
	h->countName = "point count";
	const char* layout = "<#points> <dimension (3)> <#attributes> <boundary markers (0 or 1)>";
	fmResult result = fmReadHeaderRecord(r, 2, 4, layout);
	h->line = r->line;
	int dimension = 0;
	if (result == fm_ok)
		result = fmReader_Int(r, 1, INT_MIN, INT_MAX, "dimension", &dimension);
	if (result == fm_ok && dimension != 3)
		result =
		    fmReader_Error(r, fm_errRange, 1,
		                   "dimension is %d: expected 3 (femto reads 3D meshes only)", dimension);
	if (result == fm_ok)
		result = fmReadHeaderTail(r, h, 2, true);
	if (result == fm_ok)
		result = fmReadCount(r, h, FM_MAX_NODES);
	return result;
}

// .ele: <#tetrahedra> [<nodes per tet (4 or 10)> [<#attributes>]]
static fmResult fmReadTetHeader(fmTextReader* r, fmSectionHeader* h)
{
	memset(h, 0, sizeof *h);
	h->kind = "tet";
	h->countName = "tet count";
	h->nodes = 4;
	fmResult result =
	    fmReadHeaderRecord(r, 1, 3, "<#tetrahedra> <nodes per tet (4 or 10)> <#attributes>");
	h->line = r->line;
	if (result == fm_ok && r->fieldCount > 1)
		result = fmReader_Int(r, 1, 4, 10, "nodes per tet", &h->nodes);
	if (result == fm_ok && h->nodes != 4 && h->nodes != 10)
		result = fmReader_Error(r, fm_errRange, 1, "%d nodes per tet: expected 4 or 10", h->nodes);
	if (result == fm_ok)
		result = fmReadHeaderTail(r, h, 2, false);
	if (result == fm_ok)
		result = fmReadCount(r, h, FM_MAX_TETS);
	if (result == fm_ok && h->nodes == 10)
		fmDiagWarn(r->diag, r->name, h->line,
		           "10-node (quadratic) tets: only the 4 corner nodes are used");
	return result;
}

// .face: <#faces> [<boundary marker (0 or 1)>]
static fmResult fmReadFaceHeader(fmTextReader* r, fmSectionHeader* h)
{
	memset(h, 0, sizeof *h);
	h->kind = "face";
	h->countName = "face count";
	h->nodes = 3;
	fmResult result = fmReadHeaderRecord(r, 1, 2, "<#faces> <boundary marker (0 or 1)>");
	h->line = r->line;
	if (result == fm_ok)
		result = fmReadHeaderTail(r, h, -1, true);
	if (result == fm_ok)
		result = fmReadCount(r, h, FM_MAX_TETS);
	return result;
}

// ---- records ----------------------------------------------------------------------------------

// Next record @p index (0-based) of the section, with exactly h->fields fields.
static fmResult fmReadRecord(fmTextReader* r, const fmSectionHeader* h, int index)
{
	fmReadStatus status = fmReader_Next(r);
	if (status == fm_readError)
		return r->error;
	if (status == fm_readEnd)
		return fmDiagError(r->diag, fm_errCount, r->name, r->line, 0,
		                   "unexpected end of file: expected %s %d of the %d the header on line %d "
		                   "declares",
		                   h->kind, index + 1, h->count, h->line);
	return fmReader_ExpectFields(r, h->fields, h->fields, h->layout);
}

// The index column is not trusted (Stellar's house2.ele has 0/1 flags there): records are
// numbered by their order. A mismatch is reported once as a warning.
static fmResult fmCheckIndexColumn(fmTextReader* r, fmSectionHeader* h, int expected)
{
	int index;
	fmResult result = fmReader_Int(r, 0, INT_MIN, INT_MAX, "index column", &index);
	if (result == fm_ok && index != expected && !h->warnedIndex)
	{
		h->warnedIndex = true;
		fmDiagWarn(r->diag, r->name, r->line,
		           "%s number %d where %d was expected: the index column is ignored, %ss are "
		           "numbered by their order in the file",
		           h->kind, index, expected, h->kind);
	}
	return result;
}

static fmResult fmReadDoubles(fmTextReader* r, int first, int count, const char* what, double* out)
{
	for (int k = 0; k < count; ++k)
	{
		fmResult result = fmReader_Double(r, first + k, what, out + k);
		if (result != fm_ok)
			return result;
	}
	return fm_ok;
}

// Point @p i: the first point's number sets the numbering base (0 or 1).
static fmResult fmReadPoint(fmTextReader* r, fmSectionHeader* h, int i, fmTetMesh* m)
{
	fmResult result = fmReadRecord(r, h, i);
	if (result == fm_ok && i == 0)
	{
		result = fmReader_Int(r, 0, INT_MIN, INT_MAX, "first point number", &m->firstIndex);
		if (result == fm_ok && m->firstIndex != 0 && m->firstIndex != 1)
			result = fmReader_Error(
			    r, fm_errRange, 0, "first point number is %d: expected 0 or 1 (the numbering base)",
			    m->firstIndex);
	}
	else if (result == fm_ok)
		result = fmCheckIndexColumn(r, h, m->firstIndex + i);
	static const char* const axes[3] = {"x coordinate", "y coordinate", "z coordinate"};
	for (int k = 0; k < 3 && result == fm_ok; ++k)
		result = fmReader_Double(r, 1 + k, axes[k], m->positions + 3 * (size_t)i + k);
	// Pointer arithmetic on a NULL array is undefined even with a zero offset.
	if (result == fm_ok && h->attributes > 0)
		result = fmReadDoubles(r, 4, h->attributes, "point attribute",
		                       m->nodeAttributes + (size_t)i * (size_t)h->attributes);
	if (result == fm_ok && h->markers)
		result = fmReader_Int(r, 4 + h->attributes, INT_MIN, INT_MAX, "boundary marker",
		                      m->nodeMarkers + i);
	return result;
}

// Node references of the current record, 0-based into @p out (the first @p keep of them),
// checked against the node count and for repeats among the kept ones.
static fmResult fmReadNodeRefs(fmTextReader* r, const fmSectionHeader* h, int record, int nodeCount,
                               int firstIndex, int keep, int* out)
{
	for (int k = 0; k < h->nodes; ++k)
	{
		int v;
		fmResult result = fmReader_Int(r, 1 + k, INT_MIN, INT_MAX, "node number", &v);
		if (result != fm_ok)
			return result;
		if (v < firstIndex || v - firstIndex >= nodeCount)
			return fmReader_Error(r, fm_errIndex, 1 + k,
			                      "node number %d is out of range: expected %d to %d (%d points "
			                      "numbered from %d)",
			                      v, firstIndex, firstIndex + nodeCount - 1, nodeCount, firstIndex);
		if (k >= keep)
			continue;
		out[k] = v - firstIndex;
		for (int j = 0; j < k; ++j)
			if (out[j] == out[k])
				return fmReader_Error(r, fm_errIndex, 1 + k,
				                      "%s %d repeats node %d: expected %d distinct nodes", h->kind,
				                      record + firstIndex, v, keep);
	}
	return fm_ok;
}

static fmResult fmReadTet(fmTextReader* r, fmSectionHeader* h, int t, fmTetMesh* m, int* lines)
{
	fmResult result = fmReadRecord(r, h, t);
	if (result == fm_ok)
		result = fmCheckIndexColumn(r, h, m->firstIndex + t);
	if (result == fm_ok)
		result = fmReadNodeRefs(r, h, t, m->nodeCount, m->firstIndex, 4, m->tets + 4 * (size_t)t);
	if (result == fm_ok && h->attributes > 0)
		result = fmReadDoubles(r, 1 + h->nodes, h->attributes, "tet attribute",
		                       m->tetAttributes + (size_t)t * (size_t)h->attributes);
	lines[t] = r->line;
	return result;
}

// After the last record only blank and comment lines may follow: data there means the header's
// count is wrong (or two files were concatenated), and silently dropping it would lose tets.
static fmResult fmExpectEnd(fmTextReader* r, const fmSectionHeader* h)
{
	fmReadStatus status = fmReader_Next(r);
	if (status == fm_readError)
		return r->error;
	if (status == fm_readEnd)
		return fm_ok;
	return fmReader_Error(r, fm_errCount, 0,
	                      "data after the last of the %d %ss the header on line %d declares: "
	                      "expected the end of the file (or only comments)",
	                      h->count, h->kind, h->line);
}

// ---- sections ---------------------------------------------------------------------------------

static fmResult fmParseNodes(const char* text, size_t size, const char* name, fmTetMesh* m,
                             fmDiagnostic* diag)
{
	fmTextReader r;
	fmSectionHeader h;
	fmResult result = fmReader_Init(&r, text, size, name, diag);
	if (result == fm_ok)
		result = fmReadNodeHeader(&r, &h);
	if (result != fm_ok)
		return result;
	m->nodeCount = h.count;
	m->nodeAttributeCount = h.attributes;
	m->positions = FM_ALLOC_ARRAY(double, 3 * (size_t)h.count);
	if (h.attributes > 0)
		m->nodeAttributes = FM_ALLOC_ARRAY(double, (size_t)h.count*(size_t)h.attributes);
	if (h.markers)
		m->nodeMarkers = FM_ALLOC_ARRAY(int, h.count);
	if (!m->positions || (h.attributes > 0 && !m->nodeAttributes) || (h.markers && !m->nodeMarkers))
		return fmDiagError(diag, fm_errOutOfMemory, name, h.line, 0, "out of memory for %d points",
		                   h.count);
	for (int i = 0; i < h.count && result == fm_ok; ++i)
		result = fmReadPoint(&r, &h, i, m);
	return result == fm_ok ? fmExpectEnd(&r, &h) : result;
}

// Sorted node quadruple of a tet, to find duplicates by sorting (O(m log m)).
typedef struct fmTetKey
{
	int v[4];
	int tet;
} fmTetKey;

static int fmCompareTetKeys(const void* a, const void* b)
{
	const fmTetKey* p = a;
	const fmTetKey* q = b;
	for (int k = 0; k < 4; ++k)
		if (p->v[k] != q->v[k])
			return p->v[k] < q->v[k] ? -1 : 1;
	return p->tet < q->tet ? -1 : (p->tet > q->tet);
}

static void fmSort4(int* v)
{
	for (int i = 1; i < 4; ++i)
		for (int j = i; j > 0 && v[j - 1] > v[j]; --j)
		{
			int s = v[j];
			v[j] = v[j - 1];
			v[j - 1] = s;
		}
}

// Two tets on the same four nodes would double that element's mass and stiffness and hide
// their faces from the surface: an error naming both lines.
fmResult fmCheckDuplicateTets(const fmTetMesh* m, const int* lines, const char* name,
                              fmDiagnostic* diag)
{
	fmTetKey* keys = FM_ALLOC_ARRAY(fmTetKey, m->tetCount);
	if (keys == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, name, 0, 0, "out of memory checking %d tets",
		                   m->tetCount);
	for (int t = 0; t < m->tetCount; ++t)
	{
		memcpy(keys[t].v, m->tets + 4 * (size_t)t, sizeof keys[t].v);
		fmSort4(keys[t].v);
		keys[t].tet = t;
	}
	qsort(keys, (size_t)m->tetCount, sizeof *keys, fmCompareTetKeys);
	fmResult result = fm_ok;
	for (int k = 1; k < m->tetCount && result == fm_ok; ++k)
	{
		if (memcmp(keys[k].v, keys[k - 1].v, sizeof keys[k].v) != 0)
			continue;
		int first = keys[k - 1].tet, second = keys[k].tet;
		result =
		    fmDiagError(diag, fm_errIndex, name, lines ? lines[second] : 0, 0,
		                "tet %d has the same nodes as tet %d on line %d: expected each tet "
		                "once",
		                second + m->firstIndex, first + m->firstIndex, lines ? lines[first] : 0);
	}
	FM_FREE_ARRAY(keys, fmTetKey, m->tetCount);
	return result;
}

static fmResult fmAllocTets(fmTetMesh* m, const fmSectionHeader* h, const char* name,
                            fmDiagnostic* diag)
{
	m->tetCount = h->count;
	m->tetAttributeCount = h->attributes;
	m->tets = FM_ALLOC_ARRAY(int, 4 * (size_t)h->count);
	if (h->attributes > 0)
		m->tetAttributes = FM_ALLOC_ARRAY(double, (size_t)h->count*(size_t)h->attributes);
	if (m->tets && (h->attributes == 0 || m->tetAttributes))
		return fm_ok;
	return fmDiagError(diag, fm_errOutOfMemory, name, h->line, 0, "out of memory for %d tets",
	                   h->count);
}

static fmResult fmParseTets(const char* text, size_t size, const char* name, fmTetMesh* m,
                            fmDiagnostic* diag)
{
	fmTextReader r;
	fmSectionHeader h;
	fmResult result = fmReader_Init(&r, text, size, name, diag);
	if (result == fm_ok)
		result = fmReadTetHeader(&r, &h);
	if (result == fm_ok)
		result = fmAllocTets(m, &h, name, diag);
	if (result != fm_ok)
		return result;
	int* lines = FM_ALLOC_ARRAY(int, h.count);
	if (lines == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, name, h.line, 0, "out of memory for %d tets",
		                   h.count);
	for (int t = 0; t < h.count && result == fm_ok; ++t)
		result = fmReadTet(&r, &h, t, m, lines);
	if (result == fm_ok)
		result = fmExpectEnd(&r, &h);
	if (result == fm_ok)
		result = fmCheckDuplicateTets(m, lines, name, diag);
	FM_FREE_ARRAY(lines, int, h.count);
	return result;
}

// Nodes no tet uses are accepted (the body keeps them fixed) with one warning.
void fmWarnUnreferenced(const fmTetMesh* m, const char* name, fmDiagnostic* diag)
{
	unsigned char* used = FM_ALLOC_ZERO(unsigned char, m->nodeCount);
	if (used == NULL)
		return;
	for (size_t k = 0; k < 4 * (size_t)m->tetCount; ++k)
		used[m->tets[k]] = 1;
	int unused = 0, first = -1;
	for (int i = 0; i < m->nodeCount; ++i)
		if (!used[i] && unused++ == 0)
			first = i;
	if (unused > 0)
		fmDiagWarn(diag, name, 0,
		           "%d of %d points are used by no tet (the first is point %d); they are kept and "
		           "will not move",
		           unused, m->nodeCount, first + m->firstIndex);
	FM_FREE_ARRAY(used, unsigned char, m->nodeCount);
}

fmResult fmLoadTetGenFromMemory(const char* nodeText, size_t nodeSize, const char* nodeName,
                                const char* eleText, size_t eleSize, const char* eleName,
                                fmTetMesh* mesh, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(mesh != NULL);
	if (mesh == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "no mesh to load into");
	memset(mesh, 0, sizeof *mesh);
	nodeName = nodeName ? nodeName : "<node text>";
	eleName = eleName ? eleName : "<ele text>";
	fmTetMesh m;
	memset(&m, 0, sizeof m);
	fmResult result = fmParseNodes(nodeText, nodeSize, nodeName, &m, diag);
	if (result == fm_ok)
		result = fmParseTets(eleText, eleSize, eleName, &m, diag);
	if (result != fm_ok)
	{
		fmFreeTetMesh(&m);
		return result;
	}
	fmWarnUnreferenced(&m, nodeName, diag);
	*mesh = m;
	return fm_ok;
}

// ---- files ------------------------------------------------------------------------------------

fmMeshLoadDef fmDefaultMeshLoadDef(void)
{
	fmMeshLoadDef def;
	memset(&def, 0, sizeof def);
	def.maxFileBytes = FM_DEFAULT_MESH_FILE_LIMIT;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

// Read and parse one file with @p parse, then release its text before the next file is read.
static fmResult fmLoadFile(const char* path, size_t limit,
                           fmResult (*parse)(const char*, size_t, const char*, fmTetMesh*,
                                             fmDiagnostic*),
                           fmTetMesh* m, fmDiagnostic* diag)
{
	fmFileText text;
	fmResult result = fmReadWholeFile(path, limit, &text, diag);
	if (result == fm_ok)
		result = parse(text.data, text.size, path, m, diag);
	fmFileText_Free(&text);
	return result;
}

fmResult fmStartLoad(fmTetMesh* mesh, const fmMeshLoadDef* def, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(mesh != NULL && def != NULL && def->internalValue == FM_DEF_MAGIC);
	if (mesh == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "no mesh to load into");
	memset(mesh, 0, sizeof *mesh);
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "mesh load def not initialised: start from fmDefaultMeshLoadDef()");
	return fm_ok;
}

fmResult fmLoadTetGenWithDef(const char* nodePath, const char* elePath, const fmMeshLoadDef* def,
                             fmTetMesh* mesh, fmDiagnostic* diag)
{
	fmResult started = fmStartLoad(mesh, def, diag);
	if (started != fm_ok)
		return started;
	if (nodePath == NULL || elePath == NULL)
		return fmDiagError(diag, fm_errIo, nodePath ? nodePath : "", 0, 0,
		                   "cannot open: no path given for the %s file",
		                   nodePath ? ".ele" : ".node");
	fmTetMesh m;
	memset(&m, 0, sizeof m);
	// One file in memory at a time: the .node text is gone before the .ele is read.
	fmResult result = fmLoadFile(nodePath, def->maxFileBytes, fmParseNodes, &m, diag);
	if (result == fm_ok)
		result = fmLoadFile(elePath, def->maxFileBytes, fmParseTets, &m, diag);
	if (result != fm_ok)
	{
		fmFreeTetMesh(&m);
		return result;
	}
	fmWarnUnreferenced(&m, nodePath, diag);
	*mesh = m;
	return fm_ok;
}

fmResult fmLoadTetGen(const char* nodePath, const char* elePath, fmTetMesh* mesh,
                      fmDiagnostic* diag)
{
	fmMeshLoadDef def = fmDefaultMeshLoadDef();
	return fmLoadTetGenWithDef(nodePath, elePath, &def, mesh, diag);
}

// ---- .face ------------------------------------------------------------------------------------

static fmResult fmParseFaces(fmTextReader* r, fmSectionHeader* h, int nodeCount, int firstIndex,
                             int* out)
{
	fmResult result = fm_ok;
	for (int f = 0; f < h->count && result == fm_ok; ++f)
	{
		result = fmReadRecord(r, h, f);
		if (result == fm_ok)
			result = fmCheckIndexColumn(r, h, firstIndex + f);
		if (result == fm_ok)
			result = fmReadNodeRefs(r, h, f, nodeCount, firstIndex, 3, out + 3 * (size_t)f);
		int marker;
		if (result == fm_ok && h->markers)
			result = fmReader_Int(r, 4, INT_MIN, INT_MAX, "boundary marker", &marker);
	}
	return result == fm_ok ? fmExpectEnd(r, h) : result;
}

fmResult fmLoadTetGenFaceFromMemory(const char* text, size_t size, const char* name, int nodeCount,
                                    int firstIndex, int** triangles, int* triangleCount,
                                    fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(triangles != NULL && triangleCount != NULL && nodeCount > 0 &&
	          (firstIndex == 0 || firstIndex == 1));
	if (triangles == NULL || triangleCount == NULL || nodeCount <= 0 ||
	    (firstIndex != 0 && firstIndex != 1))
		return fmDiagError(diag, fm_errParameter, name ? name : "", 0, 0,
		                   "expected output pointers, nodeCount >= 1 and firstIndex 0 or 1");
	*triangles = NULL;
	*triangleCount = 0;
	name = name ? name : "<face text>";
	fmTextReader r;
	fmSectionHeader h;
	fmResult result = fmReader_Init(&r, text, size, name, diag);
	if (result == fm_ok)
		result = fmReadFaceHeader(&r, &h);
	if (result != fm_ok)
		return result;
	int* out = fmAllocUser(fmMulSize(3 * sizeof(int), (size_t)h.count));
	if (out == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, name, h.line, 0, "out of memory for %d faces",
		                   h.count);
	result = fmParseFaces(&r, &h, nodeCount, firstIndex, out);
	if (result != fm_ok)
	{
		fmFree(out);
		return result;
	}
	*triangles = out;
	*triangleCount = h.count;
	return fm_ok;
}

// ---- writing ----------------------------------------------------------------------------------

static bool fmWriteNodeLines(FILE* f, const fmTetMesh* m, const double* x)
{
	bool ok =
	    fprintf(f, "%d 3 %d %d\n", m->nodeCount, m->nodeAttributeCount, m->nodeMarkers ? 1 : 0) > 0;
	for (int i = 0; i < m->nodeCount && ok; ++i)
	{
		ok = fprintf(f, "%d %.17g %.17g %.17g", i + m->firstIndex, x[3 * (size_t)i],
		             x[3 * (size_t)i + 1], x[3 * (size_t)i + 2]) > 0;
		for (int a = 0; a < m->nodeAttributeCount && ok; ++a)
			ok = fprintf(f, " %.17g",
			             m->nodeAttributes[(size_t)i * (size_t)m->nodeAttributeCount + (size_t)a]) >
			     0;
		if (ok && m->nodeMarkers)
			ok = fprintf(f, " %d", m->nodeMarkers[i]) > 0;
		ok = ok && fputc('\n', f) != EOF;
	}
	return ok;
}

// A file the reader would reject is not written: coordinates and attributes must be finite.
static fmResult fmCheckWritable(const char* path, const fmTetMesh* m, const double* x,
                                fmDiagnostic* diag)
{
	fmResult result = fmCheckFinitePoints(path, m, x, diag);
	size_t attributes = (size_t)m->nodeCount * (size_t)m->nodeAttributeCount;
	for (size_t k = 0; result == fm_ok && k < attributes; ++k)
		if (!isfinite(m->nodeAttributes[k]))
			return fmDiagError(diag, fm_errRange, path, 0, 0,
			                   "point %d has a non-finite attribute: expected finite values",
			                   (int)(k / (size_t)m->nodeAttributeCount) + m->firstIndex);
	return result;
}

fmResult fmWriteTetGenNodeFile(const char* path, const fmTetMesh* mesh, const double* positions,
                               bool commit, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	bool valid = path != NULL && mesh != NULL && mesh->nodeCount > 0 &&
	             (positions != NULL || mesh->positions != NULL) && mesh->nodeAttributeCount >= 0 &&
	             mesh->nodeAttributeCount <= FM_MAX_ATTRIBUTES &&
	             (mesh->nodeAttributeCount == 0 || mesh->nodeAttributes != NULL);
	FM_ASSERT(valid);
	if (!valid)
		return fmDiagError(diag, fm_errParameter, path ? path : "", 0, 0,
		                   "expected a path and a mesh with points");
	const double* x = positions ? positions : mesh->positions;
	fmResult result = fmCheckWritable(path, mesh, x, diag);
	if (result != fm_ok)
		return result;
	FILE* f = fmOpenForWriting(path, diag, &result);
	if (f == NULL)
		return result;
	bool ok = fmWriteNodeLines(f, mesh, x);
	return commit ? fmFinishFile(f, ok, path, diag) : fmFinishFileStaged(f, ok, path, diag);
}

fmResult fmWriteTetGenNode(const char* path, const fmTetMesh* mesh, const double* positions,
                           fmDiagnostic* diag)
{
	return fmWriteTetGenNodeFile(path, mesh, positions, true, diag);
}
