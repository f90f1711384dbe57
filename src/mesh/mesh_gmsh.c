// Gmsh .msh reading, versions 2.2 and 4.1, ASCII and binary (docs/mesh-format.md), written to the
// format's description in the Gmsh reference manual ("MSH file format"). Tets (type 4) are read;
// 10-node tets (type 11) by their four corners; every other element type is counted and skipped.
// A tet's physical tag (msh 2: its first tag; msh 4: the first physical tag of its volume entity)
// becomes its region attribute. Node tags may be sparse and in any order.
#include "mesh/mesh_gmsh.h"

#include "core/core.h"
#include "mesh/mesh_reader.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

// Nodes of each element type, from the manual's list (0: unknown to this reader).
static int fmGmshNodeCount(long long type)
{
	static const int counts[] = {0, 2,  3,  4,  4, 8,  6,  5,  3,  6,  9, 10, 27, 18, 14, 1,
	                             8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5,  6,  20, 35, 56};
	if (type >= 1 && type < (long long)(sizeof counts / sizeof counts[0]))
		return counts[type];
	if (type == 92)
		return 64;
	if (type == 93)
		return 125;
	return 0;
}

// What a skipped element type is, for the note.
static const char* fmGmshKind(long long type)
{
	switch (type)
	{
	case 15:
		return "points";
	case 1:
	case 8:
	case 26:
	case 27:
	case 28:
		return "lines";
	case 2:
	case 9:
	case 20:
	case 21:
	case 22:
	case 23:
	case 24:
	case 25:
		return "triangles";
	case 3:
	case 10:
	case 16:
		return "quadrangles";
	case 5:
	case 12:
	case 17:
	case 92:
	case 93:
		return "hexahedra";
	case 6:
	case 13:
	case 18:
		return "prisms";
	case 7:
	case 14:
	case 19:
		return "pyramids";
	case 29:
	case 30:
	case 31:
		return "tets of order 3 and more";
	default:
		return "elements of unknown types";
	}
}

typedef struct fmGmsh
{
	fmScan s;
	int version; // 2 or 4
	bool binary;
	bool swap; // binary data in the other byte order
	// Nodes.
	int nodeCount;
	double* positions;
	fmTagMap tags;
	bool haveNodes;
	// msh 4: volume entity tag -> first physical tag.
	int volumeCount;
	int* volumeTags;
	int* volumePhysical;
	fmTetList tets;
	bool haveElements;
} fmGmsh;

// ---- binary helpers ---------------------------------------------------------------------------

// In a binary file the data starts after the line end that follows the section's header line.
static fmResult fmGmshToBinary(fmGmsh* g)
{
	fmScan* s = &g->s;
	while (s->pos < s->size &&
	       (s->data[s->pos] == ' ' || s->data[s->pos] == '\t' || s->data[s->pos] == '\r'))
		fmScan_Advance(s, 1);
	if (s->pos >= s->size || s->data[s->pos] != '\n')
		return fmScan_ErrorHere(s, fm_errSyntax, "expected a line end before the binary data");
	fmScan_Advance(s, 1);
	return fm_ok;
}

static fmResult fmGmshInt(fmGmsh* g, const char* what, int* out)
{
	const unsigned char* b;
	fmResult result = fmScan_Bytes(&g->s, 4, what, &b);
	if (result == fm_ok)
		*out = (int)fmLoadU32(b, g->swap);
	return result;
}

// A size_t of msh 4 binary (8 bytes: the data size of the header) within [0, hi].
static fmResult fmGmshSize(fmGmsh* g, const char* what, long long hi, long long* out)
{
	const unsigned char* b;
	size_t at = g->s.pos;
	fmResult result = fmScan_Bytes(&g->s, 8, what, &b);
	if (result != fm_ok)
		return result;
	uint64_t v = fmLoadU64(b, g->swap);
	if (v > (uint64_t)hi)
		return fmScan_ErrorHere(&g->s, fm_errRange,
		                        "%s %llu at byte %zu is out of range: expected 0 to %lld", what,
		                        (unsigned long long)v, at, hi);
	*out = (long long)v;
	return fm_ok;
}

// An integer of the current representation: text, or binary int (4 bytes) / size_t (8 bytes).
static fmResult fmGmshValue(fmGmsh* g, bool isSize, const char* what, long long lo, long long hi,
                            long long* out)
{
	if (!g->binary)
		return fmScan_Int64(&g->s, what, lo, hi, out);
	long long v = 0;
	if (isSize)
	{
		fmResult result = fmGmshSize(g, what, LLONG_MAX, &v);
		if (result != fm_ok)
			return result;
	}
	else
	{
		int i;
		fmResult result = fmGmshInt(g, what, &i);
		if (result != fm_ok)
			return result;
		v = i;
	}
	if (v < lo || v > hi)
		return fmScan_ErrorHere(&g->s, fm_errRange,
		                        "%s %lld before byte %zu is out of range: expected %lld to %lld",
		                        what, v, g->s.pos, lo, hi);
	*out = v;
	return fm_ok;
}

static fmResult fmGmshDouble(fmGmsh* g, const char* what, double* out)
{
	if (!g->binary)
		return fmScan_Double(&g->s, what, out);
	const unsigned char* b;
	size_t at = g->s.pos;
	fmResult result = fmScan_Bytes(&g->s, 8, what, &b);
	if (result != fm_ok)
		return result;
	double v = fmLoadF64(b, g->swap);
	if (!(v - v == 0.0))
		return fmScan_ErrorHere(&g->s, fm_errRange,
		                        "%s at byte %zu is not finite: expected a finite number", what, at);
	*out = v;
	return fm_ok;
}

// ---- sections ---------------------------------------------------------------------------------

// "$MeshFormat" then "version file-type data-size" [binary one] "$EndMeshFormat".
static fmResult fmGmshFormat(fmGmsh* g)
{
	fmScan* s = &g->s;
	fmResult result = fmScan_Word(s, "$MeshFormat", false);
	if (result != fm_ok)
		return s->tokenLength == 0 ? fmScan_Error(s, fm_errEmpty,
		                                          "empty file: expected "
		                                          "\"$MeshFormat\"")
		                           : result;
	result = fmScan_Expect(s, "the version (2.2 or 4.1)");
	if (result != fm_ok)
		return result;
	if (fmScan_Is(s, "2.2") || fmScan_Is(s, "2.1") || fmScan_Is(s, "2") || fmScan_Is(s, "2.0"))
		g->version = 2;
	else if (fmScan_Is(s, "4.1"))
		g->version = 4;
	else
		return fmScan_Error(s, fm_errSyntax,
		                    "msh version \"%.*s\" is not read: expected 2.2 or 4.1 (Gmsh writes "
		                    "them with -format msh22 or msh41)",
		                    (int)(s->tokenLength < 20 ? s->tokenLength : 20), s->token);
	long long fileType = 0, dataSize = 0;
	result = fmScan_Int64(s, "file type (0 ASCII, 1 binary)", 0, 1, &fileType);
	if (result == fm_ok)
		result = fmScan_Int64(s, "data size", 8, 8, &dataSize);
	if (result != fm_ok)
		return result;
	g->binary = fileType == 1;
	if (g->binary)
	{
		result = fmGmshToBinary(g);
		const unsigned char* b;
		if (result == fm_ok)
			result = fmScan_Bytes(s, 4, "the binary one (endianness check)", &b);
		if (result != fm_ok)
			return result;
		if (fmLoadU32(b, false) == 1)
			g->swap = false;
		else if (fmLoadU32(b, true) == 1)
			g->swap = true;
		else
			return fmScan_ErrorHere(s, fm_errSyntax,
			                        "the binary one after the format line reads 0x%08x: expected "
			                        "the integer 1 in either byte order",
			                        (unsigned)fmLoadU32(b, false));
	}
	return fmScan_Word(s, "$EndMeshFormat", false);
}

// Skip a section this reader does not need: to its "$End..." line.
static fmResult fmGmshSkipSection(fmGmsh* g)
{
	fmScan* s = &g->s;
	char end[80];
	int n = snprintf(end, sizeof end, "$End%.*s",
	                 (int)(s->tokenLength - 1 < 60 ? s->tokenLength - 1 : 60),
	                 (const char*)s->token + 1);
	int startLine = s->tokenLine;
	while (fmScan_Next(s))
		if (s->tokenLength == (size_t)n && memcmp(s->token, end, (size_t)n) == 0)
			return fm_ok;
	return fmDiagError(s->diag, fm_errSyntax, s->name, startLine, 1,
	                   "the section has no \"%s\": expected the section to end", end);
}

static fmResult fmGmshEnd(fmGmsh* g, const char* word)
{
	return fmScan_Word(&g->s, word, false);
}

// msh 4 $Entities: the first physical tag of each volume (the regions of its tets).
static fmResult fmGmshEntities(fmGmsh* g)
{
	if (g->version != 4)
		return fmGmshSkipSection(g);
	if (g->volumeTags != NULL)
		return fmScan_Error(&g->s, fm_errSyntax, "a second $Entities section: expected one");
	if (g->binary)
	{
		fmResult result = fmGmshToBinary(g);
		if (result != fm_ok)
			return result;
	}
	long long counts[4];
	static const char* const names[4] = {"point entity count", "curve entity count",
	                                     "surface entity count", "volume entity count"};
	for (int d = 0; d < 4; ++d)
	{
		fmResult result = fmGmshValue(g, true, names[d], 0, INT_MAX, &counts[d]);
		if (result == fm_ok)
			result = fmScan_CheckCount(&g->s, counts[d], INT_MAX, g->binary ? 12 : 8, "entities");
		if (result != fm_ok)
			return result;
	}
	g->volumeCount = (int)counts[3];
	g->volumeTags = FM_ALLOC_ZERO(int, counts[3] + 1);
	g->volumePhysical = FM_ALLOC_ZERO(int, counts[3] + 1);
	if (g->volumeTags == NULL || g->volumePhysical == NULL)
		return fmScan_Error(&g->s, fm_errOutOfMemory, "out of memory for %d volumes",
		                    g->volumeCount);
	for (int d = 0; d < 4; ++d)
		for (long long e = 0; e < counts[d]; ++e)
		{
			long long tag = 0, n = 0, value = 0;
			double x;
			fmResult result = fmGmshValue(g, false, "entity tag", INT_MIN, INT_MAX, &tag);
			for (int k = 0; k < (d == 0 ? 3 : 6) && result == fm_ok; ++k)
				result = fmGmshDouble(g, "entity bounding box", &x);
			if (result == fm_ok)
				result = fmGmshValue(g, true, "physical tag count", 0, INT_MAX, &n);
			if (result == fm_ok)
				result = fmScan_CheckCount(&g->s, n, INT_MAX, g->binary ? 4 : 2, "physical tags");
			for (long long k = 0; k < n && result == fm_ok; ++k)
			{
				result = fmGmshValue(g, false, "physical tag", INT_MIN, INT_MAX, &value);
				if (result == fm_ok && d == 3 && k == 0)
					g->volumePhysical[e] = (int)value;
			}
			if (d == 3)
				g->volumeTags[e] = (int)tag;
			if (result == fm_ok && d > 0)
				result = fmGmshValue(g, true, "bounding entity count", 0, INT_MAX, &n);
			if (result == fm_ok && d > 0)
				result =
				    fmScan_CheckCount(&g->s, n, INT_MAX, g->binary ? 4 : 2, "bounding entities");
			for (long long k = 0; k < n && d > 0 && result == fm_ok; ++k)
				result = fmGmshValue(g, false, "bounding entity tag", INT_MIN, INT_MAX, &value);
			if (result != fm_ok)
				return result;
		}
	return fmGmshEnd(g, "$EndEntities");
}

static fmResult fmGmshAllocNodes(fmGmsh* g, long long count, long long** tags)
{
	fmResult result = fmScan_CheckCount(&g->s, count, FM_MAX_NODES, g->binary ? 28 : 8, "nodes");
	if (result == fm_ok && count == 0)
		result = fmScan_Error(&g->s, fm_errEmpty, "the file declares 0 nodes: expected at least 4");
	if (result != fm_ok)
		return result;
	g->nodeCount = (int)count;
	g->positions = FM_ALLOC_ARRAY(double, 3 * (size_t)count);
	*tags = FM_ALLOC_ARRAY(long long, count);
	if (g->positions == NULL || *tags == NULL)
		return fmScan_Error(&g->s, fm_errOutOfMemory, "out of memory for %lld nodes", count);
	return fm_ok;
}

// msh 2 nodes: "tag x y z" records (binary: int tag, 3 doubles).
static fmResult fmGmshNodes2(fmGmsh* g, long long* tags)
{
	fmResult result = fm_ok;
	for (int i = 0; i < g->nodeCount && result == fm_ok; ++i)
	{
		result = fmGmshValue(g, false, "node tag", 1, LLONG_MAX, &tags[i]);
		for (int k = 0; k < 3 && result == fm_ok; ++k)
			result = fmGmshDouble(g, "node coordinate", &g->positions[3 * (size_t)i + (size_t)k]);
	}
	return result;
}

// msh 4 nodes: entity blocks, each its tags then its coordinates (and parametric ones).
static fmResult fmGmshNodes4(fmGmsh* g, long long blocks, long long* tags)
{
	long long done = 0;
	fmResult result = fm_ok;
	for (long long b = 0; b < blocks && result == fm_ok; ++b)
	{
		long long dim = 0, tag = 0, parametric = 0, n = 0;
		result = fmGmshValue(g, false, "entity dimension", 0, 3, &dim);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "entity tag", INT_MIN, INT_MAX, &tag);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "parametric flag", 0, 1, &parametric);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "nodes in the block", 0, g->nodeCount - done, &n);
		for (long long i = 0; i < n && result == fm_ok; ++i)
			result = fmGmshValue(g, true, "node tag", 1, LLONG_MAX, &tags[done + i]);
		int extra = parametric ? (int)dim : 0;
		for (long long i = 0; i < n && result == fm_ok; ++i)
		{
			double* x = g->positions + 3 * (size_t)(done + i);
			double u;
			for (int k = 0; k < 3 && result == fm_ok; ++k)
				result = fmGmshDouble(g, "node coordinate", &x[k]);
			for (int k = 0; k < extra && result == fm_ok; ++k)
				result = fmGmshDouble(g, "parametric coordinate", &u);
		}
		done += n;
	}
	if (result == fm_ok && done != g->nodeCount)
		result = fmScan_ErrorHere(&g->s, fm_errCount,
		                          "the node blocks hold %lld nodes: the $Nodes header declares %d",
		                          done, g->nodeCount);
	return result;
}

static fmResult fmGmshNodes(fmGmsh* g)
{
	if (g->haveNodes)
		return fmScan_Error(&g->s, fm_errSyntax, "a second $Nodes section: expected one");
	g->haveNodes = true;
	long long count = 0, blocks = 0, minTag = 0, maxTag = 0;
	fmResult result = fm_ok;
	if (g->version == 4 && g->binary)
		result = fmGmshToBinary(g);
	if (g->version == 4)
	{
		result = result == fm_ok ? fmGmshValue(g, true, "entity block count", 0, INT_MAX, &blocks)
		                         : result;
		if (result == fm_ok)
			result = fmGmshValue(g, true, "node count", 0, LLONG_MAX, &count);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "smallest node tag", 0, LLONG_MAX, &minTag);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "largest node tag", 0, LLONG_MAX, &maxTag);
	}
	else
	{
		result = fmScan_Int64(&g->s, "node count", 0, LLONG_MAX, &count);
		if (result == fm_ok && g->binary)
			result = fmGmshToBinary(g);
	}
	long long* tags = NULL;
	if (result == fm_ok)
		result = fmGmshAllocNodes(g, count, &tags);
	if (result == fm_ok)
		result = g->version == 4 ? fmGmshNodes4(g, blocks, tags) : fmGmshNodes2(g, tags);
	if (result == fm_ok)
		result = fmTagMap_Build(&g->tags, tags, g->nodeCount, g->s.name, g->s.diag);
	FM_FREE_ARRAY(tags, long long, count);
	return result == fm_ok ? fmGmshEnd(g, "$EndNodes") : result;
}

// The region of the tets of volume entity @p tag (msh 4): its first physical tag, or 0.
static double fmGmshRegion(const fmGmsh* g, long long tag)
{
	for (int v = 0; v < g->volumeCount; ++v)
		if (g->volumeTags[v] == tag)
			return g->volumePhysical[v];
	return 0.0;
}

// The nodes of one element: tets are kept (their first 4 nodes), others read and dropped.
static fmResult fmGmshElementNodes(fmGmsh* g, long long type, int nodeCount, double region,
                                   int line)
{
	int corners[4];
	fmResult result = fm_ok;
	for (int k = 0; k < nodeCount && result == fm_ok; ++k)
	{
		long long tag = 0;
		result = fmGmshValue(g, g->version == 4, "node tag", 1, LLONG_MAX, &tag);
		if (result != fm_ok || k >= 4 || (type != 4 && type != 11))
			continue;
		corners[k] = fmTagMap_Find(&g->tags, tag);
		if (corners[k] < 0)
			result = g->binary ? fmScan_ErrorHere(&g->s, fm_errIndex,
			                                      "node tag %lld before byte %zu is not in "
			                                      "$Nodes: expected a node of the file",
			                                      tag, g->s.pos)
			                   : fmScan_Error(&g->s, fm_errIndex,
			                                  "node tag %lld is not in $Nodes: expected a node "
			                                  "of the file",
			                                  tag);
	}
	if (result != fm_ok)
		return result;
	if (type == 4 || type == 11)
	{
		g->tets.reducedQuadratic += type == 11;
		return fmTetList_Add(&g->tets, corners, line, region, &g->s);
	}
	fmSkipped_Add(&g->tets.skipped, fmGmshKind(type), 1);
	return fm_ok;
}

// msh 2 ASCII: "tag type tagCount tags... nodes..." per line; unknown types are skipped by line.
static fmResult fmGmshElement2(fmGmsh* g)
{
	long long tag = 0, type = 0, tagCount = 0, value = 0;
	fmResult result = fmScan_Int64(&g->s, "element tag", 1, LLONG_MAX, &tag);
	if (result == fm_ok)
		result = fmScan_Int64(&g->s, "element type", 1, INT_MAX, &type);
	int line = g->s.tokenLine;
	int nodes = fmGmshNodeCount(type);
	if (result == fm_ok && nodes == 0)
	{
		fmSkipped_Add(&g->tets.skipped, fmGmshKind(type), 1);
		fmScan_SkipLine(&g->s);
		return fm_ok;
	}
	if (result == fm_ok)
		result = fmScan_Int64(&g->s, "number of tags", 0, 64, &tagCount);
	double region = 0.0;
	for (long long k = 0; k < tagCount && result == fm_ok; ++k)
	{
		result = fmScan_Int64(&g->s, "element tag value", LLONG_MIN, LLONG_MAX, &value);
		if (k == 0)
			region = (double)value;
	}
	return result == fm_ok ? fmGmshElementNodes(g, type, nodes, region, line) : result;
}

// msh 2 binary: blocks of "type count tagCount" then count x (tag, tags..., nodes...) ints.
static fmResult fmGmshElements2Binary(fmGmsh* g, long long count)
{
	long long done = 0;
	fmResult result = fm_ok;
	while (done < count && result == fm_ok)
	{
		long long type = 0, n = 0, tagCount = 0, value = 0;
		result = fmGmshValue(g, false, "element type", 1, INT_MAX, &type);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "elements in the block", 1, count - done, &n);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "number of tags", 0, 64, &tagCount);
		int nodes = fmGmshNodeCount(type);
		if (result == fm_ok && nodes == 0)
			return fmScan_ErrorHere(&g->s, fm_errSyntax,
			                        "element type %lld before byte %zu is unknown: its node count "
			                        "is needed to skip it in a binary file",
			                        type, g->s.pos);
		if (result == fm_ok)
			result =
			    fmScan_CheckCount(&g->s, n, count, 4 * (size_t)(1 + tagCount + nodes), "elements");
		for (long long e = 0; e < n && result == fm_ok; ++e)
		{
			double region = 0.0;
			result = fmGmshValue(g, false, "element tag", INT_MIN, INT_MAX, &value);
			for (long long k = 0; k < tagCount && result == fm_ok; ++k)
			{
				result = fmGmshValue(g, false, "element tag value", INT_MIN, INT_MAX, &value);
				if (k == 0)
					region = (double)value;
			}
			if (result == fm_ok)
				result = fmGmshElementNodes(g, type, nodes, region, 0);
		}
		done += n;
	}
	return result;
}

// msh 4: entity blocks "dim entity type count", then count x (tag, nodes...).
static fmResult fmGmshElements4(fmGmsh* g, long long blocks, long long count)
{
	long long done = 0;
	fmResult result = fm_ok;
	for (long long b = 0; b < blocks && result == fm_ok; ++b)
	{
		long long dim = 0, entity = 0, type = 0, n = 0, tag = 0;
		result = fmGmshValue(g, false, "entity dimension", 0, 3, &dim);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "entity tag", INT_MIN, INT_MAX, &entity);
		if (result == fm_ok)
			result = fmGmshValue(g, false, "element type", 1, INT_MAX, &type);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "elements in the block", 0, count - done, &n);
		int nodes = fmGmshNodeCount(type);
		if (result == fm_ok && nodes == 0 && g->binary)
			return fmScan_ErrorHere(&g->s, fm_errSyntax,
			                        "element type %lld before byte %zu is unknown: its node count "
			                        "is needed to skip it in a binary file",
			                        type, g->s.pos);
		if (result == fm_ok && nodes == 0)
		{
			// An unknown type in ASCII: the rest of the block's line, then one line per element.
			fmSkipped_Add(&g->tets.skipped, fmGmshKind(type), n);
			fmScan_SkipLine(&g->s);
			for (long long e = 0; e < n; ++e)
				fmScan_SkipLine(&g->s);
			done += n;
			continue;
		}
		if (result == fm_ok)
			result = fmScan_CheckCount(&g->s, n, count, g->binary ? 8 * (size_t)(1 + nodes) : 2,
			                           "elements");
		double region = fmGmshRegion(g, entity);
		for (long long e = 0; e < n && result == fm_ok; ++e)
		{
			result = fmGmshValue(g, true, "element tag", 1, LLONG_MAX, &tag);
			if (result == fm_ok)
				result = fmGmshElementNodes(g, type, nodes, region, g->s.tokenLine);
		}
		done += n;
	}
	if (result == fm_ok && done != count)
		result = fmScan_ErrorHere(&g->s, fm_errCount,
		                          "the element blocks hold %lld elements: the $Elements header "
		                          "declares %lld",
		                          done, count);
	return result;
}

static fmResult fmGmshElements(fmGmsh* g)
{
	if (!g->haveNodes)
		return fmScan_Error(&g->s, fm_errSyntax,
		                    "$Elements before $Nodes: expected the nodes first");
	if (g->haveElements)
		return fmScan_Error(&g->s, fm_errSyntax, "a second $Elements section: expected one");
	g->haveElements = true;
	long long count = 0, blocks = 0, value = 0;
	fmResult result = fm_ok;
	if (g->version == 4)
	{
		if (g->binary)
			result = fmGmshToBinary(g);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "entity block count", 0, INT_MAX, &blocks);
		if (result == fm_ok)
			result = fmGmshValue(g, true, "element count", 0, LLONG_MAX, &count);
		for (int k = 0; k < 2 && result == fm_ok; ++k)
			result = fmGmshValue(g, true, "element tag bound", 0, LLONG_MAX, &value);
	}
	else
	{
		result = fmScan_Int64(&g->s, "element count", 0, LLONG_MAX, &count);
		if (result == fm_ok && g->binary)
			result = fmGmshToBinary(g);
	}
	// An element is at least 2 tokens of 2 bytes (ASCII) or 8 bytes (binary).
	if (result == fm_ok)
		result = fmScan_CheckCount(&g->s, count, (long long)FM_MAX_TETS + FM_MAX_NODES,
		                           g->binary ? 8 : 4, "elements");
	if (result != fm_ok)
		return result;
	fmTetList_Init(&g->tets, count, true);
	if (g->version == 4)
		result = fmGmshElements4(g, blocks, count);
	else if (g->binary)
		result = fmGmshElements2Binary(g, count);
	else
		for (long long e = 0; e < count && result == fm_ok; ++e)
			result = fmGmshElement2(g);
	return result == fm_ok ? fmGmshEnd(g, "$EndElements") : result;
}

static fmResult fmGmshSections(fmGmsh* g)
{
	fmScan* s = &g->s;
	fmResult result = fmGmshFormat(g);
	while (result == fm_ok && fmScan_Next(s))
	{
		if (s->token[0] != '$')
		{
			result = fmScan_Error(s, fm_errSyntax,
			                      "\"%.*s\" between sections: expected a section such as $Nodes",
			                      (int)(s->tokenLength < 40 ? s->tokenLength : 40), s->token);
		}
		else if (fmScan_Is(s, "$Nodes"))
			result = fmGmshNodes(g);
		else if (fmScan_Is(s, "$Elements"))
			result = fmGmshElements(g);
		else if (fmScan_Is(s, "$Entities"))
			result = fmGmshEntities(g);
		else if (fmScan_Is(s, "$MeshFormat"))
			result = fmScan_Error(s, fm_errSyntax, "a second $MeshFormat: expected one");
		else
			result = fmGmshSkipSection(g);
	}
	if (result == fm_ok && !g->haveNodes)
		result = fmScan_Error(s, fm_errEmpty, "the file has no $Nodes section: expected a mesh");
	if (result == fm_ok && !g->haveElements)
		result = fmScan_Error(s, fm_errEmpty, "the file has no $Elements section: expected a mesh");
	return result;
}

fmResult fmParseGmsh(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                     fmDiagnostic* diag)
{
	fmGmsh g;
	memset(&g, 0, sizeof g);
	fmScan_Init(&g.s, data, size, name, diag);
	fmResult result = fmGmshSections(&g);
	fmTagMap_Free(&g.tags);
	FM_FREE_ARRAY(g.volumeTags, int, g.volumeCount + 1);
	FM_FREE_ARRAY(g.volumePhysical, int, g.volumeCount + 1);
	if (result != fm_ok)
	{
		fmTetList_Free(&g.tets);
		FM_FREE_ARRAY(g.positions, double, 3 * (size_t)g.nodeCount);
		return result;
	}
	return fmTetList_Finish(&g.tets, g.positions, g.nodeCount, 1, name, mesh, diag);
}
