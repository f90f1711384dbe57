// VTK XML mesh reading (docs/mesh-format.md), written to "The VTK User's Guide", chapter "VTK
// File Formats": .vtu UnstructuredGrid, one Piece; DataArrays in ascii, binary (base64) or
// appended (raw or base64) form, with a UInt32 or UInt64 header, either byte order,
// zlib-compressed where femto was built with zlib. Tets as the legacy reader's (mesh_vtk.h); a
// CellData array named "region" or "gmsh:physical" becomes the tets' region attribute.
#include "mesh/mesh_vtu.h"

#include "core/core.h"
#include "mesh/mesh_vtk.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#ifdef FEMTO_HAVE_ZLIB
#include <zlib.h>
#endif

bool fmVtuHasZlib(void)
{
#ifdef FEMTO_HAVE_ZLIB
	return true;
#else
	return false;
#endif
}

// The largest factor by which deflate can shrink data (about 1032:1): a compressed array that
// claims to expand more than this is refused before its memory is allocated.
#define FM_DEFLATE_MAX_RATIO 1032u

// ---- XML .vtu ---------------------------------------------------------------------------------

#define FM_XML_MAX_ATTRIBUTES 16

typedef struct fmXmlTag
{
	const unsigned char* name;
	size_t nameLength;
	bool closing;     // </name>
	bool selfClosing; // <name ... />
	int attributeCount;
	const unsigned char* key[FM_XML_MAX_ATTRIBUTES];
	size_t keyLength[FM_XML_MAX_ATTRIBUTES];
	const unsigned char* value[FM_XML_MAX_ATTRIBUTES];
	size_t valueLength[FM_XML_MAX_ATTRIBUTES];
	int line;
	int column;
} fmXmlTag;

typedef enum fmVtuType
{
	fm_vtuNone,
	fm_vtuInt8,
	fm_vtuUInt8,
	fm_vtuInt16,
	fm_vtuUInt16,
	fm_vtuInt32,
	fm_vtuUInt32,
	fm_vtuInt64,
	fm_vtuUInt64,
	fm_vtuFloat32,
	fm_vtuFloat64,
} fmVtuType;

typedef enum fmVtuFormat
{
	fm_vtuAscii,
	fm_vtuBinary,
	fm_vtuAppended,
} fmVtuFormat;

// A DataArray: where its values are and how they are written.
typedef struct fmVtuArray
{
	bool present;
	fmVtuType type;
	int components;
	fmVtuFormat format;
	unsigned long long offset; // appended: from the byte after '_'
	size_t contentStart;       // ascii, binary: the text between the tags
	size_t contentEnd;
	int line; // of the DataArray tag
	int column;
} fmVtuArray;

typedef struct fmVtu
{
	fmScan s;
	bool bigEndian;
	int headerSize; // 4 (UInt32) or 8 (UInt64)
	bool compressed;
	bool appendedBase64;
	size_t appendedStart; // the byte after '_'
	bool haveAppended;
	long long pointCount;
	long long cellCount;
	bool havePiece;
	int pieceLine; // where the Piece is, for arrays it lacks
	int pieceColumn;
	fmVtuArray points, connectivity, offsets, types, regions;
} fmVtu;

static bool fmXmlNameIs(const unsigned char* name, size_t length, const char* word)
{
	return strlen(word) == length && memcmp(name, word, length) == 0;
}

static bool fmXmlAttribute(const fmXmlTag* tag, const char* key, const unsigned char** value,
                           size_t* length)
{
	for (int k = 0; k < tag->attributeCount; ++k)
		if (fmXmlNameIs(tag->key[k], tag->keyLength[k], key))
		{
			*value = tag->value[k];
			*length = tag->valueLength[k];
			return true;
		}
	return false;
}

static bool fmXmlAttributeIs(const fmXmlTag* tag, const char* key, const char* word)
{
	const unsigned char* v;
	size_t n;
	return fmXmlAttribute(tag, key, &v, &n) && fmXmlNameIs(v, n, word);
}

static fmResult fmXmlError(const fmVtu* x, const fmXmlTag* tag, fmResult result, const char* text)
{
	return fmDiagError(x->s.diag, result, x->s.name, tag->line, tag->column, "%s", text);
}

static bool fmXmlIsNameChar(unsigned char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
	       c == ':' || c == '-' || c == '.';
}

// Skip past @p end (e.g. "-->"); false when the data ends first.
static bool fmXmlSkipPast(fmScan* s, const char* end)
{
	size_t n = strlen(end);
	while (s->size - s->pos >= n)
	{
		if (memcmp(s->data + s->pos, end, n) == 0)
		{
			fmScan_Advance(s, n);
			return true;
		}
		fmScan_Advance(s, 1);
	}
	fmScan_Advance(s, s->size - s->pos);
	return false;
}

// The attributes of a start tag up to '>' or "/>".
static fmResult fmXmlAttributes(fmVtu* x, fmXmlTag* tag)
{
	fmScan* s = &x->s;
	while (true)
	{
		fmScan_SkipSpace(s);
		if (s->pos >= s->size)
			return fmXmlError(x, tag, fm_errSyntax, "the file ends inside a tag: expected '>'");
		unsigned char c = s->data[s->pos];
		if (c == '>' || (c == '/' && s->pos + 1 < s->size && s->data[s->pos + 1] == '>'))
		{
			tag->selfClosing = c == '/';
			fmScan_Advance(s, c == '/' ? 2 : 1);
			return fm_ok;
		}
		size_t start = s->pos;
		while (s->pos < s->size && fmXmlIsNameChar(s->data[s->pos]))
			fmScan_Advance(s, 1);
		size_t keyLength = s->pos - start;
		fmScan_SkipSpace(s);
		if (keyLength == 0 || s->pos >= s->size || s->data[s->pos] != '=')
			return fmScan_ErrorHere(s, fm_errSyntax,
			                        "expected an attribute name=\"value\" in <%.*s>",
			                        (int)(tag->nameLength < 30 ? tag->nameLength : 30), tag->name);
		fmScan_Advance(s, 1);
		fmScan_SkipSpace(s);
		unsigned char quote = s->pos < s->size ? s->data[s->pos] : 0;
		if (quote != '"' && quote != '\'')
			return fmScan_ErrorHere(s, fm_errSyntax, "expected a quoted attribute value");
		fmScan_Advance(s, 1);
		size_t valueStart = s->pos;
		const unsigned char* close = memchr(s->data + s->pos, quote, s->size - s->pos);
		if (close == NULL)
			return fmScan_ErrorHere(s, fm_errSyntax, "the attribute value has no closing quote");
		fmScan_Advance(s, (size_t)(close - (s->data + s->pos)) + 1);
		if (tag->attributeCount < FM_XML_MAX_ATTRIBUTES)
		{
			int k = tag->attributeCount++;
			tag->key[k] = s->data + start;
			tag->keyLength[k] = keyLength;
			tag->value[k] = s->data + valueStart;
			tag->valueLength[k] = (size_t)(close - (s->data + valueStart));
		}
	}
}

// The next element tag (declarations, comments and processing instructions are skipped); false
// at the end of the data.
static fmResult fmXmlNext(fmVtu* x, fmXmlTag* tag, bool* found)
{
	fmScan* s = &x->s;
	memset(tag, 0, sizeof *tag);
	*found = false;
	while (true)
	{
		const unsigned char* lt = memchr(s->data + s->pos, '<', s->size - s->pos);
		if (lt == NULL)
			return fm_ok;
		fmScan_Advance(s, (size_t)(lt - (s->data + s->pos)));
		tag->line = s->line;
		tag->column = (int)(s->pos - s->lineStart) + 1;
		size_t left = s->size - s->pos;
		if (left >= 4 && memcmp(lt, "<!--", 4) == 0)
		{
			if (!fmXmlSkipPast(s, "-->"))
				return fmXmlError(x, tag, fm_errSyntax, "the comment has no end: expected \"-->\"");
			continue;
		}
		if (left >= 2 && (lt[1] == '?' || lt[1] == '!'))
		{
			if (!fmXmlSkipPast(s, ">"))
				return fmXmlError(x, tag, fm_errSyntax, "the declaration has no end: expected '>'");
			continue;
		}
		fmScan_Advance(s, 1);
		tag->closing = s->pos < s->size && s->data[s->pos] == '/';
		fmScan_Advance(s, tag->closing ? 1 : 0);
		tag->name = s->data + s->pos;
		while (s->pos < s->size && fmXmlIsNameChar(s->data[s->pos]))
			fmScan_Advance(s, 1);
		tag->nameLength = (size_t)(s->data + s->pos - tag->name);
		if (tag->nameLength == 0)
			return fmXmlError(x, tag, fm_errSyntax, "'<' without a tag name: expected an element");
		*found = true;
		if (!tag->closing)
			return fmXmlAttributes(x, tag);
		if (!fmXmlSkipPast(s, ">"))
			return fmXmlError(x, tag, fm_errSyntax, "the closing tag has no '>'");
		return fm_ok;
	}
}

static fmVtuType fmVtuTypeFromName(const unsigned char* v, size_t n)
{
	static const char* const names[] = {"",       "Int8",  "UInt8",  "Int16",   "UInt16", "Int32",
	                                    "UInt32", "Int64", "UInt64", "Float32", "Float64"};
	for (int k = 1; k < (int)(sizeof names / sizeof names[0]); ++k)
		if (fmXmlNameIs(v, n, names[k]))
			return (fmVtuType)k;
	return fm_vtuNone;
}

static int fmVtuTypeSize(fmVtuType type)
{
	static const int sizes[] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
	return sizes[type];
}

// Parse an unsigned decimal attribute value.
static bool fmXmlUnsigned(const unsigned char* v, size_t n, unsigned long long* out)
{
	unsigned long long value = 0;
	if (n == 0 || n > 19)
		return false;
	for (size_t k = 0; k < n; ++k)
	{
		if (v[k] < '0' || v[k] > '9')
			return false;
		value = 10 * value + (unsigned long long)(v[k] - '0');
	}
	*out = value;
	return true;
}

static fmResult fmVtuFileTag(fmVtu* x, const fmXmlTag* tag)
{
	if (!fmXmlAttributeIs(tag, "type", "UnstructuredGrid"))
		return fmXmlError(x, tag, fm_errSyntax,
		                  "VTKFile type is not \"UnstructuredGrid\": expected a .vtu tet mesh");
	x->bigEndian = fmXmlAttributeIs(tag, "byte_order", "BigEndian");
	x->headerSize = fmXmlAttributeIs(tag, "header_type", "UInt64") ? 8 : 4;
	const unsigned char* v;
	size_t n;
	if (fmXmlAttribute(tag, "header_type", &v, &n) && !fmXmlNameIs(v, n, "UInt64") &&
	    !fmXmlNameIs(v, n, "UInt32"))
		return fmXmlError(x, tag, fm_errSyntax, "header_type: expected UInt32 or UInt64");
	if (fmXmlAttribute(tag, "compressor", &v, &n) && n > 0)
	{
		if (!fmXmlNameIs(v, n, "vtkZLibDataCompressor"))
			return fmDiagError(x->s.diag, fm_errSyntax, x->s.name, tag->line, tag->column,
			                   "compressor \"%.*s\" is not read: expected vtkZLibDataCompressor "
			                   "or uncompressed data",
			                   (int)(n < 40 ? n : 40), (const char*)v);
		x->compressed = true;
	}
	return fm_ok;
}

static fmResult fmVtuPieceTag(fmVtu* x, const fmXmlTag* tag)
{
	if (x->havePiece)
		return fmXmlError(x, tag, fm_errSyntax,
		                  "a second Piece: femto reads files of one piece (merge them first)");
	x->havePiece = true;
	x->pieceLine = tag->line;
	x->pieceColumn = tag->column;
	const unsigned char* v;
	size_t n;
	unsigned long long points, cells;
	if (!fmXmlAttribute(tag, "NumberOfPoints", &v, &n) || !fmXmlUnsigned(v, n, &points) ||
	    !fmXmlAttribute(tag, "NumberOfCells", &v, &n) || !fmXmlUnsigned(v, n, &cells))
		return fmXmlError(x, tag, fm_errSyntax,
		                  "Piece: expected NumberOfPoints and NumberOfCells (unsigned integers)");
	if (points == 0)
		return fmXmlError(x, tag, fm_errEmpty, "Piece has 0 points: expected a mesh");
	if (points > FM_MAX_NODES)
		return fmDiagError(x->s.diag, fm_errLimit, x->s.name, tag->line, tag->column,
		                   "%llu points exceed the limit of %d", points, FM_MAX_NODES);
	if (cells > (unsigned long long)FM_MAX_TETS + FM_MAX_NODES)
		return fmDiagError(x->s.diag, fm_errLimit, x->s.name, tag->line, tag->column,
		                   "%llu cells exceed the limit of %d", cells, FM_MAX_TETS + FM_MAX_NODES);
	x->pointCount = (long long)points;
	x->cellCount = (long long)cells;
	return fm_ok;
}

static fmResult fmVtuArrayTag(fmVtu* x, const fmXmlTag* tag, fmVtuArray* a)
{
	memset(a, 0, sizeof *a);
	a->present = true;
	a->line = tag->line;
	a->column = tag->column;
	const unsigned char* v;
	size_t n;
	if (!fmXmlAttribute(tag, "type", &v, &n) || (a->type = fmVtuTypeFromName(v, n)) == fm_vtuNone)
		return fmXmlError(x, tag, fm_errSyntax,
		                  "DataArray type: expected Int8 to UInt64, Float32 or Float64");
	unsigned long long components = 1;
	if (fmXmlAttribute(tag, "NumberOfComponents", &v, &n) &&
	    (!fmXmlUnsigned(v, n, &components) || components < 1 || components > 64))
		return fmXmlError(x, tag, fm_errSyntax, "NumberOfComponents: expected 1 to 64");
	a->components = (int)components;
	if (!fmXmlAttribute(tag, "format", &v, &n))
		return fmXmlError(x, tag, fm_errSyntax,
		                  "DataArray has no format: expected ascii, binary or appended");
	if (fmXmlNameIs(v, n, "ascii"))
		a->format = fm_vtuAscii;
	else if (fmXmlNameIs(v, n, "binary"))
		a->format = fm_vtuBinary;
	else if (fmXmlNameIs(v, n, "appended"))
	{
		a->format = fm_vtuAppended;
		if (!fmXmlAttribute(tag, "offset", &v, &n) || !fmXmlUnsigned(v, n, &a->offset))
			return fmXmlError(x, tag, fm_errSyntax,
			                  "appended DataArray: expected an offset (an unsigned integer)");
	}
	else
		return fmXmlError(x, tag, fm_errSyntax,
		                  "DataArray format: expected ascii, binary or appended");
	a->contentStart = x->s.pos;
	if (!tag->selfClosing)
	{
		const unsigned char* lt = memchr(x->s.data + x->s.pos, '<', x->s.size - x->s.pos);
		a->contentEnd = lt ? (size_t)(lt - x->s.data) : x->s.size;
	}
	else
		a->contentEnd = a->contentStart;
	return fm_ok;
}

// Walk the elements up to <AppendedData> (whose raw bytes are never tokenized) or the end.
// The section of the Piece the walk is in.
typedef enum fmVtuSection
{
	fm_vtuInNone,
	fm_vtuInPoints,
	fm_vtuInCells,
	fm_vtuInCellData,
	fm_vtuInOther
} fmVtuSection;

// The array a DataArray tag fills: the first one of Points, Cells' connectivity, offsets and
// types, a CellData "region" or "gmsh:physical"; NULL for any other (read and ignored).
static fmVtuArray* fmVtuArrayFor(fmVtu* x, const fmXmlTag* tag, fmVtuSection where)
{
	if (where == fm_vtuInPoints && !x->points.present)
		return &x->points;
	if (where == fm_vtuInCells && fmXmlAttributeIs(tag, "Name", "connectivity"))
		return &x->connectivity;
	if (where == fm_vtuInCells && fmXmlAttributeIs(tag, "Name", "offsets"))
		return &x->offsets;
	if (where == fm_vtuInCells && fmXmlAttributeIs(tag, "Name", "types"))
		return &x->types;
	if (where == fm_vtuInCellData &&
	    (fmXmlAttributeIs(tag, "Name", "region") || fmXmlAttributeIs(tag, "Name", "gmsh:physical")))
		return &x->regions;
	return NULL;
}

// <AppendedData encoding="raw|base64">: where its data start (after the '_').
static fmResult fmVtuAppendedTag(fmVtu* x, const fmXmlTag* tag)
{
	x->appendedBase64 = fmXmlAttributeIs(tag, "encoding", "base64");
	if (!x->appendedBase64 && !fmXmlAttributeIs(tag, "encoding", "raw"))
		return fmXmlError(x, tag, fm_errSyntax, "AppendedData encoding: expected raw or base64");
	const unsigned char* mark = memchr(x->s.data + x->s.pos, '_', x->s.size - x->s.pos);
	if (mark == NULL)
		return fmXmlError(x, tag, fm_errSyntax, "AppendedData has no '_' before its data");
	x->appendedStart = (size_t)(mark - x->s.data) + 1;
	x->haveAppended = true;
	return fm_ok;
}

static fmResult fmVtuWalk(fmVtu* x)
{
	fmVtuSection where = fm_vtuInNone;
	bool haveFile = false;
	fmXmlTag tag;
	bool found = true;
	fmResult result = fm_ok;
	while (result == fm_ok)
	{
		result = fmXmlNext(x, &tag, &found);
		if (result != fm_ok || !found)
			break;
		const unsigned char* nm = tag.name;
		size_t nl = tag.nameLength;
		bool section = fmXmlNameIs(nm, nl, "Points") || fmXmlNameIs(nm, nl, "Cells") ||
		               fmXmlNameIs(nm, nl, "CellData") || fmXmlNameIs(nm, nl, "PointData");
		if (tag.closing)
		{
			if (section)
				where = fm_vtuInNone;
			continue;
		}
		if (!haveFile && !fmXmlNameIs(nm, nl, "VTKFile"))
			return fmXmlError(x, &tag, fm_errSyntax, "expected the <VTKFile> element first");
		if (fmXmlNameIs(nm, nl, "VTKFile"))
		{
			haveFile = true;
			result = fmVtuFileTag(x, &tag);
		}
		else if (fmXmlNameIs(nm, nl, "Piece"))
			result = fmVtuPieceTag(x, &tag);
		else if (section && !tag.selfClosing)
			where = fmXmlNameIs(nm, nl, "Points")     ? fm_vtuInPoints
			        : fmXmlNameIs(nm, nl, "Cells")    ? fm_vtuInCells
			        : fmXmlNameIs(nm, nl, "CellData") ? fm_vtuInCellData
			                                          : fm_vtuInOther;
		else if (fmXmlNameIs(nm, nl, "DataArray"))
		{
			fmVtuArray* a = fmVtuArrayFor(x, &tag, where);
			fmVtuArray ignored;
			result = fmVtuArrayTag(x, &tag, a ? a : &ignored);
		}
		else if (fmXmlNameIs(nm, nl, "AppendedData"))
		{
			result = fmVtuAppendedTag(x, &tag);
			if (result != fm_ok)
				return result;
			break;
		}
	}
	if (result != fm_ok)
		return result;
	if (!haveFile)
		return fmScan_ErrorHere(&x->s, x->s.size == 0 ? fm_errEmpty : fm_errSyntax,
		                        "no <VTKFile> element: expected a .vtu file");
	if (!x->havePiece)
		return fmScan_ErrorHere(&x->s, fm_errEmpty, "no <Piece>: expected a mesh");
	return fm_ok;
}

// ---- .vtu data --------------------------------------------------------------------------------

// A byte stream over raw bytes or base64 text (padding may appear mid-stream: VTK and meshio
// encode a header and its data separately).
typedef struct fmVtuStream
{
	const unsigned char* p;
	const unsigned char* end;
	bool base64;
	unsigned char carry[3];
	int carryCount;
	int carryAt;
} fmVtuStream;

static int fmBase64Value(unsigned char c)
{
	if (c >= 'A' && c <= 'Z')
		return c - 'A';
	if (c >= 'a' && c <= 'z')
		return c - 'a' + 26;
	if (c >= '0' && c <= '9')
		return c - '0' + 52;
	if (c == '+')
		return 62;
	if (c == '/')
		return 63;
	return -1;
}

// Decode the next group of 4 base64 characters into the carry; false at the end or on a bad
// character.
static bool fmVtuDecodeGroup(fmVtuStream* st)
{
	int v[4], got = 0, pad = 0;
	while (got < 4 && st->p < st->end)
	{
		unsigned char c = *st->p++;
		if (c == ' ' || c == '\n' || c == '\r' || c == '\t')
			continue;
		if (c == '=')
		{
			v[got++] = 0;
			++pad;
			continue;
		}
		int value = fmBase64Value(c);
		if (value < 0 || pad > 0)
			return false;
		v[got++] = value;
	}
	if (got < 4 || pad > 2)
		return false;
	unsigned long bits = ((unsigned long)v[0] << 18) | ((unsigned long)v[1] << 12) |
	                     ((unsigned long)v[2] << 6) | (unsigned long)v[3];
	st->carry[0] = (unsigned char)(bits >> 16);
	st->carry[1] = (unsigned char)(bits >> 8);
	st->carry[2] = (unsigned char)bits;
	st->carryCount = 3 - pad;
	st->carryAt = 0;
	return true;
}

// Read @p count bytes; false when the stream ends first (or holds a character outside base64).
static bool fmVtuRead(fmVtuStream* st, unsigned char* out, size_t count)
{
	if (!st->base64)
	{
		if ((size_t)(st->end - st->p) < count)
			return false;
		memcpy(out, st->p, count);
		st->p += count;
		return true;
	}
	for (size_t k = 0; k < count; ++k)
	{
		if (st->carryAt == st->carryCount && !fmVtuDecodeGroup(st))
			return false;
		out[k] = st->carry[st->carryAt++];
	}
	return true;
}

// Most bytes the stream can still give (to check a size before allocating it).
static size_t fmVtuStreamBound(const fmVtuStream* st)
{
	size_t left = (size_t)(st->end - st->p);
	return st->base64 ? left / 4 * 3 + 3 : left;
}

static fmResult fmVtuArrayError(const fmVtu* x, const fmVtuArray* a, fmResult result,
                                const char* what, const char* problem)
{
	return fmDiagError(x->s.diag, result, x->s.name, a->line, a->column, "DataArray %s: %s", what,
	                   problem);
}

static unsigned long long fmVtuHeaderValue(const fmVtu* x, const unsigned char* b)
{
	bool swap = x->bigEndian == fmHostIsLittleEndian();
	return x->headerSize == 8 ? fmLoadU64(b, swap) : fmLoadU32(b, swap);
}

// Inflate the compressed blocks of one array into @p out (@p bytes long).
static fmResult fmVtuInflate(const fmVtu* x, const fmVtuArray* a, const char* what, fmVtuStream* st,
                             unsigned char* out, size_t bytes)
{
	unsigned char h[24];
	if (!fmVtuRead(st, h, 3 * (size_t)x->headerSize))
		return fmVtuArrayError(x, a, fm_errCount, what, "the data ends in the compression header");
	unsigned long long blocks = fmVtuHeaderValue(x, h);
	unsigned long long blockSize = fmVtuHeaderValue(x, h + x->headerSize);
	unsigned long long lastSize = fmVtuHeaderValue(x, h + 2 * x->headerSize);
	// (blocks - 1) * blockSize is computed only once it is known not to overflow.
	bool sane = blocks <= bytes + 1 && blockSize <= ((unsigned long long)1 << 40) &&
	            lastSize <= blockSize && (blocks <= 1 || blockSize > 0) &&
	            (blocks <= 1 || blocks - 1 <= bytes / blockSize);
	unsigned long long total =
	    !sane || blocks == 0 ? 0 : (blocks - 1) * blockSize + (lastSize ? lastSize : blockSize);
	if (!sane || total != bytes)
	{
		char text[160];
		snprintf(text, sizeof text,
		         "the compression header describes %llu bytes in %llu blocks: expected %zu bytes",
		         total, blocks, bytes);
		return fmVtuArrayError(x, a, fm_errCount, what, text);
	}
#ifndef FEMTO_HAVE_ZLIB
	(void)out;
	return fmVtuArrayError(x, a, fm_errSyntax, what,
	                       "the data is zlib-compressed (compressor=\"vtkZLibDataCompressor\") and "
	                       "this femto was built without zlib: rebuild it where zlib is found "
	                       "(Debian: zlib1g-dev), or write the file uncompressed");
#else
	// The compressed sizes follow the three header values; they are read one at a time.
	// st reads the sizes; data starts after them.
	fmVtuStream data = *st;
	unsigned long long compressedTotal = 0;
	for (unsigned long long k = 0; k < blocks; ++k)
	{
		if (!fmVtuRead(&data, h, (size_t)x->headerSize))
			return fmVtuArrayError(x, a, fm_errCount, what,
			                       "the data ends in the compressed block sizes");
		compressedTotal += fmVtuHeaderValue(x, h);
	}
	if (compressedTotal > fmVtuStreamBound(&data) ||
	    bytes / FM_DEFLATE_MAX_RATIO > compressedTotal + 1)
		return fmVtuArrayError(x, a, fm_errCount, what,
		                       "the compressed block sizes exceed the data that follows");
	size_t done = 0;
	fmResult result = fm_ok;
	for (unsigned long long k = 0; k < blocks && result == fm_ok; ++k)
	{
		fmVtuRead(st, h, (size_t)x->headerSize);
		size_t csize = (size_t)fmVtuHeaderValue(x, h);
		size_t usize = (size_t)(k + 1 == blocks && lastSize ? lastSize : blockSize);
		if (usize > bytes - done)
			return fmVtuArrayError(x, a, fm_errCount, what,
			                       "the compressed blocks hold more than the array's bytes");
		unsigned char* packed = fmAlloc(csize > 0 ? csize : 1);
		if (packed == NULL)
			return fmVtuArrayError(x, a, fm_errOutOfMemory, what, "out of memory");
		bool read = fmVtuRead(&data, packed, csize);
		uLongf got = (uLongf)usize;
		int z = read ? uncompress(out + done, &got, packed, (uLong)csize) : Z_DATA_ERROR;
		fmDealloc(packed, csize > 0 ? csize : 1);
		if (z != Z_OK || got != usize)
			result = fmVtuArrayError(x, a, fm_errSyntax, what,
			                         "a compressed block does not inflate to its size (corrupt "
			                         "zlib data)");
		done += usize;
	}
	*st = data;
	return result;
#endif
}

// The decoded bytes of a binary or appended array: exactly @p bytes (count * value size).
static fmResult fmVtuPayload(const fmVtu* x, const fmVtuArray* a, const char* what, size_t bytes,
                             unsigned char** out)
{
	fmVtuStream st;
	memset(&st, 0, sizeof st);
	if (a->format == fm_vtuAppended)
	{
		if (!x->haveAppended)
			return fmVtuArrayError(x, a, fm_errSyntax, what,
			                       "format=\"appended\" but the file has no <AppendedData>");
		if (a->offset > x->s.size - x->appendedStart)
			return fmVtuArrayError(x, a, fm_errCount, what,
			                       "its offset lies beyond the end of the appended data");
		st.p = x->s.data + x->appendedStart + a->offset;
		st.end = x->s.data + x->s.size;
		st.base64 = x->appendedBase64;
	}
	else
	{
		st.p = x->s.data + a->contentStart;
		st.end = x->s.data + a->contentEnd;
		st.base64 = true;
	}
	if (!x->compressed)
	{
		unsigned char h[8];
		if (!fmVtuRead(&st, h, (size_t)x->headerSize))
			return fmVtuArrayError(x, a, fm_errCount, what, "the data ends in its size header");
		unsigned long long declared = fmVtuHeaderValue(x, h);
		if (declared != bytes)
		{
			char text[160];
			snprintf(text, sizeof text, "its header says %llu bytes: expected %zu", declared,
			         bytes);
			return fmVtuArrayError(x, a, fm_errCount, what, text);
		}
		if (bytes > fmVtuStreamBound(&st))
			return fmVtuArrayError(x, a, fm_errCount, what,
			                       "the file ends before the bytes its header declares");
	}
	*out = fmAlloc(bytes > 0 ? bytes : 1);
	if (*out == NULL)
		return fmVtuArrayError(x, a, fm_errOutOfMemory, what, "out of memory");
	fmResult result = fm_ok;
	if (x->compressed)
		result = fmVtuInflate(x, a, what, &st, *out, bytes);
	else if (!fmVtuRead(&st, *out, bytes))
		result = fmVtuArrayError(x, a, fm_errSyntax, what,
		                         "the data ends early or holds a character outside base64");
	if (result != fm_ok)
	{
		fmDealloc(*out, bytes > 0 ? bytes : 1);
		*out = NULL;
	}
	return result;
}

// One value of a binary array as a double (integers exactly up to 2^53).
static double fmVtuValue(const fmVtu* x, fmVtuType type, const unsigned char* b, bool* tooLarge)
{
	bool swap = x->bigEndian == fmHostIsLittleEndian();
	switch (type)
	{
	case fm_vtuInt8:
		return (double)(int8_t)b[0];
	case fm_vtuUInt8:
		return (double)b[0];
	case fm_vtuInt16:
		return (double)(int16_t)(x->bigEndian ? (b[0] << 8) | b[1] : (b[1] << 8) | b[0]);
	case fm_vtuUInt16:
		return (double)(uint16_t)(x->bigEndian ? (b[0] << 8) | b[1] : (b[1] << 8) | b[0]);
	case fm_vtuInt32:
		return (double)(int32_t)fmLoadU32(b, swap);
	case fm_vtuUInt32:
		return (double)fmLoadU32(b, swap);
	case fm_vtuInt64:
	{
		int64_t v = (int64_t)fmLoadU64(b, swap);
		*tooLarge = v > ((int64_t)1 << 53) || v < -((int64_t)1 << 53);
		return (double)v;
	}
	case fm_vtuUInt64:
	{
		uint64_t v = fmLoadU64(b, swap);
		*tooLarge = v > ((uint64_t)1 << 53);
		return (double)v;
	}
	case fm_vtuFloat32:
		return (double)fmLoadF32(b, swap);
	case fm_vtuFloat64:
		return fmLoadF64(b, swap);
	default:
		return 0.0;
	}
}

// The @p count values of an array as doubles into @p out (integers are checked by the caller).
static fmResult fmVtuValues(fmVtu* x, const fmVtuArray* a, const char* what, size_t count,
                            double* out)
{
	if (a->format == fm_vtuAscii)
	{
		// A scanner over the content, its line numbers counted from the start of the file.
		fmScan sub = x->s;
		sub.pos = 0;
		sub.line = 1;
		sub.lineStart = 0;
		fmScan_Advance(&sub, a->contentStart);
		sub.size = a->contentEnd;
		fmResult result = fm_ok;
		for (size_t k = 0; k < count && result == fm_ok; ++k)
			result = fmScan_Double(&sub, what, &out[k]);
		if (result == fm_ok && fmScan_Next(&sub))
			result = fmScan_Error(&sub, fm_errCount, "more values than the %zu of %s", count, what);
		return result;
	}
	size_t size = (size_t)fmVtuTypeSize(a->type);
	unsigned char* bytes = NULL;
	fmResult result = fmVtuPayload(x, a, what, count * size, &bytes);
	for (size_t k = 0; k < count && result == fm_ok; ++k)
	{
		bool tooLarge = false;
		out[k] = fmVtuValue(x, a->type, bytes + k * size, &tooLarge);
		if (tooLarge || !(out[k] - out[k] == 0.0))
			result = fmVtuArrayError(x, a, fm_errRange, what, "a value is not finite or too large");
	}
	if (bytes)
		fmDealloc(bytes, count * size > 0 ? count * size : 1);
	return result;
}

// Integers of an array, each in [lo, hi].
static fmResult fmVtuIntegers(fmVtu* x, const fmVtuArray* a, const char* what, size_t count,
                              long long lo, long long hi, long long* out)
{
	double* values = FM_ALLOC_ARRAY(double, count > 0 ? count : 1);
	if (values == NULL)
		return fmVtuArrayError(x, a, fm_errOutOfMemory, what, "out of memory");
	fmResult result = fmVtuValues(x, a, what, count, values);
	for (size_t k = 0; k < count && result == fm_ok; ++k)
	{
		double v = values[k];
		// The range first: converting a double beyond long long's range is undefined.
		if (!(v >= (double)lo && v <= (double)hi) || v != (double)(long long)v)
		{
			char text[160];
			snprintf(text, sizeof text, "value %zu is %.17g: expected an integer from %lld to %lld",
			         k, v, lo, hi);
			result = fmVtuArrayError(x, a, fm_errRange, what, text);
		}
		else
			out[k] = (long long)v;
	}
	FM_FREE_ARRAY(values, double, count > 0 ? count : 1);
	return result;
}

static fmResult fmVtuRequire(fmVtu* x, const fmVtuArray* a, const char* what, fmVtuType minType)
{
	if (!a->present)
		return fmDiagError(x->s.diag, fm_errSyntax, x->s.name, x->pieceLine, x->pieceColumn,
		                   "the Piece has no %s DataArray", what);
	bool isFloat = a->type == fm_vtuFloat32 || a->type == fm_vtuFloat64;
	if ((minType == fm_vtuFloat32) != isFloat)
		return fmVtuArrayError(x, a, fm_errSyntax, what,
		                       minType == fm_vtuFloat32 ? "expected Float32 or Float64"
		                                                : "expected an integer type");
	return fm_ok;
}

// Points, offsets, connectivity, types (and regions) into positions and cells.
static fmResult fmVtuLoadArrays(fmVtu* x, double** positions, fmVtkCells* c)
{
	fmResult result = fmVtuRequire(x, &x->points, "Points", fm_vtuFloat32);
	if (result == fm_ok && x->points.components != 3)
		result = fmVtuArrayError(x, &x->points, fm_errSyntax, "Points",
		                         "expected NumberOfComponents=\"3\"");
	if (result == fm_ok)
		result = fmVtuRequire(x, &x->offsets, "offsets", fm_vtuInt8);
	if (result == fm_ok)
		result = fmVtuRequire(x, &x->connectivity, "connectivity", fm_vtuInt8);
	if (result == fm_ok)
		result = fmVtuRequire(x, &x->types, "types", fm_vtuInt8);
	if (result != fm_ok)
		return result;
	size_t n = (size_t)x->pointCount;
	*positions = FM_ALLOC_ARRAY(double, 3 * n);
	c->count = x->cellCount;
	c->start = FM_ALLOC_ARRAY(long long, c->count + 1);
	c->types = FM_ALLOC_ARRAY(unsigned char, c->count + 1);
	long long* types = FM_ALLOC_ARRAY(long long, c->count + 1);
	if (*positions == NULL || c->start == NULL || c->types == NULL || types == NULL)
		result = fmScan_ErrorHere(&x->s, fm_errOutOfMemory, "out of memory for %lld points",
		                          x->pointCount);
	if (result == fm_ok)
		result = fmVtuValues(x, &x->points, "Points", 3 * n, *positions);
	if (c->start != NULL)
		c->start[0] = 0;
	if (result == fm_ok)
		result =
		    fmVtuIntegers(x, &x->offsets, "offsets", (size_t)c->count, 0, INT_MAX, c->start + 1);
	for (long long k = 0; k < c->count && result == fm_ok; ++k)
		if (c->start[k + 1] < c->start[k])
			result = fmVtuArrayError(x, &x->offsets, fm_errRange, "offsets",
			                         "the offsets decrease: expected each cell's end, in order");
	// (Read only when the offsets were: after a failure the array holds no values.)
	c->connCount = result == fm_ok && c->count > 0 ? c->start[c->count] : 0;
	// Each connectivity value takes at least a byte of the file (or of its inflated data).
	unsigned long long bound = (x->compressed ? FM_DEFLATE_MAX_RATIO : 1u) * x->s.size + 64u;
	if (result == fm_ok && (unsigned long long)c->connCount > bound)
		result = fmVtuArrayError(x, &x->offsets, fm_errCount, "offsets",
		                         "the last offset asks for more connectivity values than the "
		                         "file can hold");
	long long* conn = NULL;
	if (result == fm_ok)
	{
		conn = FM_ALLOC_ARRAY(long long, c->connCount + 1);
		c->conn = FM_ALLOC_ARRAY(int, c->connCount + 1);
		if (conn == NULL || c->conn == NULL)
			result = fmScan_ErrorHere(&x->s, fm_errOutOfMemory, "out of memory for the cells");
	}
	if (result == fm_ok)
		result = fmVtuIntegers(x, &x->connectivity, "connectivity", (size_t)c->connCount, 0,
		                       x->pointCount - 1, conn);
	for (long long k = 0; k < c->connCount && result == fm_ok; ++k)
		c->conn[k] = (int)conn[k];
	FM_FREE_ARRAY(conn, long long, c->connCount + 1);
	if (result == fm_ok)
		result = fmVtuIntegers(x, &x->types, "types", (size_t)c->count, 0, 255, types);
	for (long long k = 0; k < c->count && result == fm_ok; ++k)
		c->types[k] = (unsigned char)types[k];
	FM_FREE_ARRAY(types, long long, c->count + 1);
	if (result == fm_ok && x->regions.present && x->regions.components == 1)
	{
		c->regions = FM_ALLOC_ARRAY(double, c->count + 1);
		result = c->regions ? fmVtuValues(x, &x->regions, "region", (size_t)c->count, c->regions)
		                    : fmScan_ErrorHere(&x->s, fm_errOutOfMemory, "out of memory");
	}
	return result;
}

fmResult fmParseVtu(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                    fmDiagnostic* diag)
{
	fmVtu x;
	memset(&x, 0, sizeof x);
	fmScan_Init(&x.s, data, size, name, diag);
	fmResult result = fmVtuWalk(&x);
	// Uncompressed arrays are bounded by the file's bytes; the counts must fit them too (an ascii
	// value takes 2 bytes, a binary one its size): checked before the arrays are allocated.
	unsigned long long values =
	    3ull * (unsigned long long)x.pointCount + 3ull * (unsigned long long)x.cellCount;
	unsigned long long bound =
	    (x.compressed ? FM_DEFLATE_MAX_RATIO : 2u) * (unsigned long long)size + 64;
	if (result == fm_ok && values > bound)
		result = fmScan_ErrorHere(&x.s, fm_errCount,
		                          "the Piece declares %lld points and %lld cells but the file has "
		                          "only %zu bytes",
		                          x.pointCount, x.cellCount, size);
	double* positions = NULL;
	fmVtkCells cells;
	memset(&cells, 0, sizeof cells);
	if (result == fm_ok)
		result = fmVtuLoadArrays(&x, &positions, &cells);
	fmTetList list;
	memset(&list, 0, sizeof list);
	fmScan at = x.s;
	at.tokenLine = x.types.line;
	at.tokenColumn = x.types.column;
	at.token = at.data + at.pos; // errors point at the types, not at a byte
	at.tokenLength = 0;
	if (result == fm_ok)
		result = fmVtkCells_ToTets(&cells, &list, &at);
	// The arrays were allocated with one spare element each.
	FM_FREE_ARRAY(cells.start, long long, cells.count + 1);
	FM_FREE_ARRAY(cells.conn, int, cells.connCount + 1);
	FM_FREE_ARRAY(cells.types, unsigned char, cells.count + 1);
	FM_FREE_ARRAY(cells.regions, double, cells.count + 1);
	if (result != fm_ok)
	{
		fmTetList_Free(&list);
		FM_FREE_ARRAY(positions, double, 3 * (size_t)x.pointCount);
		return result;
	}
	return fmTetList_Finish(&list, positions, (int)x.pointCount, 0, name, mesh, diag);
}
