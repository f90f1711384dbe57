// Output writers: VTK XML (binary appended, zlib-compressed where the build has zlib; ASCII on
// request), PVD collections, OBJ surfaces and .node positions, each written whole to a temporary
// file and renamed.
#include "output.h"

#include "whole_file.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifdef FEMTO_CLI_HAVE_ZLIB
#include <zlib.h>
#endif

// VTK cell type of a linear tetrahedron (vtkCellType.h).
#define CLI_VTK_TETRA 10

// ---- .vtu: ASCII, or binary arrays appended raw (zlib-compressed where the build has zlib) --

// The arrays of one body as the .vtu holds them.
typedef struct cliVtuPiece
{
	int vertexCount;
	int tetCount;
	double* x;        // 3 per vertex, positions (m)
	double* v;        // 3 per vertex, velocities (m/s)
	int32_t* tets;    // 4 per tet
	int32_t* offsets; // tetCount: 4 (t + 1)
	uint8_t* types;   // tetCount: VTK_TETRA
} cliVtuPiece;

static void cliVtuPiece_Free(cliVtuPiece* p)
{
	free(p->x);
	free(p->v);
	free(p->tets);
	free(p->offsets);
	free(p->types);
	memset(p, 0, sizeof *p);
}

static bool cliVtuPiece_Make(cliVtuPiece* p, fmBodyId body)
{
	memset(p, 0, sizeof *p);
	p->vertexCount = fmBody_GetVertexCount(body);
	p->tetCount = fmBody_GetTetCount(body);
	size_t m = (size_t)p->tetCount;
	p->x = cliCopyState(body, false);
	p->v = cliCopyState(body, true);
	p->tets = malloc(sizeof(int32_t) * 4 * m);
	p->offsets = malloc(sizeof(int32_t) * m);
	p->types = malloc(m);
	if (p->x == NULL || p->v == NULL || p->tets == NULL || p->offsets == NULL || p->types == NULL)
	{
		cliError("out of memory writing a .vtu piece of %d vertices", p->vertexCount);
		cliVtuPiece_Free(p);
		return false;
	}
	const int* tets = fmBody_GetTets(body);
	for (size_t t = 0; t < m; ++t)
	{
		for (int k = 0; k < 4; ++k)
			p->tets[4 * t + k] = tets[4 * t + k];
		p->offsets[t] = (int32_t)(4 * (t + 1));
		p->types[t] = CLI_VTK_TETRA;
	}
	return true;
}

static void cliWriteVtuPieceAscii(FILE* file, const cliVtuPiece* p)
{
	fprintf(file, "<Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", p->vertexCount,
	        p->tetCount);
	fprintf(file, "<PointData Vectors=\"velocity\">\n"
	              "<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
	              "format=\"ascii\">\n");
	for (int i = 0; i < p->vertexCount; ++i)
		fprintf(file, "%.9g %.9g %.9g\n", p->v[3 * i], p->v[3 * i + 1], p->v[3 * i + 2]);
	fprintf(file, "</DataArray>\n</PointData>\n<Points>\n"
	              "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
	// 17 significant digits: the positions round-trip exactly.
	for (int i = 0; i < p->vertexCount; ++i)
		fprintf(file, "%.17g %.17g %.17g\n", p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
	fprintf(file, "</DataArray>\n</Points>\n<Cells>\n"
	              "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
	for (int t = 0; t < p->tetCount; ++t)
		fprintf(file, "%d %d %d %d\n", p->tets[4 * t], p->tets[4 * t + 1], p->tets[4 * t + 2],
		        p->tets[4 * t + 3]);
	fprintf(file, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
	for (int t = 0; t < p->tetCount; ++t)
		fprintf(file, "%d\n", p->offsets[t]);
	fprintf(file, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
	for (int t = 0; t < p->tetCount; ++t)
		fprintf(file, "%d\n", p->types[t]);
	fprintf(file, "</DataArray>\n</Cells>\n</Piece>\n");
}

// The appended data of a file being built in memory: each array's block (its header and bytes)
// one after the other; a DataArray's offset is where its block starts.
typedef struct cliBlob
{
	unsigned char* data;
	size_t length;
	size_t capacity;
	bool failed;
} cliBlob;

static void cliBlob_Append(cliBlob* b, const void* bytes, size_t size)
{
	if (b->failed)
		return;
	if (b->length + size > b->capacity)
	{
		size_t capacity = b->capacity > 0 ? b->capacity : 65536;
		while (capacity < b->length + size)
			capacity *= 2;
		unsigned char* grown = realloc(b->data, capacity);
		if (grown == NULL)
		{
			b->failed = true;
			return;
		}
		b->data = grown;
		b->capacity = capacity;
	}
	memcpy(b->data + b->length, bytes, size);
	b->length += size;
}

// The .vtu's byte order is declared LittleEndian: numbers are written in it whatever the host.
static void cliBlob_AppendU64(cliBlob* b, uint64_t value)
{
	unsigned char bytes[8];
	for (int k = 0; k < 8; ++k)
		bytes[k] = (unsigned char)(value >> (8 * k));
	cliBlob_Append(b, bytes, 8);
}

static bool cliHostIsLittleEndian(void)
{
	const uint16_t one = 1;
	unsigned char first;
	memcpy(&first, &one, 1);
	return first == 1;
}

// @p count values of @p size bytes, little-endian (byte-swapped on a big-endian host).
static unsigned char* cliLittleEndian(const void* values, size_t count, size_t size)
{
	unsigned char* out = malloc(count * size > 0 ? count * size : 1);
	if (out == NULL)
		return NULL;
	memcpy(out, values, count * size);
	if (!cliHostIsLittleEndian())
		for (size_t i = 0; i < count; ++i)
			for (size_t k = 0; k < size / 2; ++k)
			{
				unsigned char t = out[i * size + k];
				out[i * size + k] = out[i * size + size - 1 - k];
				out[i * size + size - 1 - k] = t;
			}
	return out;
}

// Blocks of this many bytes are compressed one by one (VTK's own default block size).
#define CLI_VTU_BLOCK 32768u

// One array's block, as the VTK XML format's appended data holds it with header_type UInt64:
// uncompressed, the byte count then the bytes; zlib-compressed (vtkZLibDataCompressor), the
// number of blocks, the block size, the size of the last block, each block's compressed size,
// then the compressed blocks.
static void cliBlob_AppendArray(cliBlob* b, const void* values, size_t count, size_t size,
                                bool compress)
{
	unsigned char* bytes = cliLittleEndian(values, count, size);
	size_t total = count * size;
	if (bytes == NULL)
	{
		b->failed = true;
		return;
	}
#ifdef FEMTO_CLI_HAVE_ZLIB
	if (compress && total > 0)
	{
		size_t blocks = (total + CLI_VTU_BLOCK - 1) / CLI_VTU_BLOCK;
		uLong bound = compressBound(CLI_VTU_BLOCK);
		unsigned char* packed = malloc(blocks * bound);
		uint64_t* sizes = malloc(sizeof *sizes * blocks);
		for (size_t k = 0; packed != NULL && sizes != NULL && k < blocks; ++k)
		{
			size_t length = k + 1 < blocks ? CLI_VTU_BLOCK : total - k * CLI_VTU_BLOCK;
			uLongf packedLength = bound;
			if (compress2(packed + k * bound, &packedLength, bytes + k * CLI_VTU_BLOCK,
			              (uLong)length, Z_DEFAULT_COMPRESSION) != Z_OK)
				b->failed = true;
			sizes[k] = packedLength;
		}
		if (packed == NULL || sizes == NULL)
			b->failed = true;
		cliBlob_AppendU64(b, blocks);
		cliBlob_AppendU64(b, CLI_VTU_BLOCK);
		cliBlob_AppendU64(b, total - (blocks - 1) * CLI_VTU_BLOCK);
		for (size_t k = 0; !b->failed && k < blocks; ++k)
			cliBlob_AppendU64(b, sizes[k]);
		for (size_t k = 0; !b->failed && k < blocks; ++k)
			cliBlob_Append(b, packed + k * bound, (size_t)sizes[k]);
		free(packed);
		free(sizes);
		free(bytes);
		return;
	}
#else
	(void)compress;
#endif
	cliBlob_AppendU64(b, total);
	cliBlob_Append(b, bytes, total);
	free(bytes);
}

// A DataArray element pointing into the appended data at its current end, and the array's block.
static void cliWriteAppendedArray(FILE* file, cliBlob* blob, const char* type, const char* name,
                                  int components, const void* values, size_t count, size_t size,
                                  bool compress)
{
	fprintf(file, "<DataArray type=\"%s\"", type);
	if (name != NULL)
		fprintf(file, " Name=\"%s\"", name);
	if (components > 1)
		fprintf(file, " NumberOfComponents=\"%d\"", components);
	fprintf(file, " format=\"appended\" offset=\"%zu\"/>\n", blob->length);
	cliBlob_AppendArray(blob, values, count, size, compress);
}

static void cliWriteVtuPieceAppended(FILE* file, cliBlob* blob, const cliVtuPiece* p, bool compress)
{
	size_t n = (size_t)p->vertexCount, m = (size_t)p->tetCount;
	fprintf(file, "<Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", p->vertexCount,
	        p->tetCount);
	fprintf(file, "<PointData Vectors=\"velocity\">\n");
	cliWriteAppendedArray(file, blob, "Float64", "velocity", 3, p->v, 3 * n, 8, compress);
	fprintf(file, "</PointData>\n<Points>\n");
	cliWriteAppendedArray(file, blob, "Float64", NULL, 3, p->x, 3 * n, 8, compress);
	fprintf(file, "</Points>\n<Cells>\n");
	cliWriteAppendedArray(file, blob, "Int32", "connectivity", 1, p->tets, 4 * m, 4, compress);
	cliWriteAppendedArray(file, blob, "Int32", "offsets", 1, p->offsets, m, 4, compress);
	cliWriteAppendedArray(file, blob, "UInt8", "types", 1, p->types, m, 1, compress);
	fprintf(file, "</Cells>\n</Piece>\n");
}

bool cliVtuCompressed(void)
{
#ifdef FEMTO_CLI_HAVE_ZLIB
	return true;
#else
	return false;
#endif
}

bool cliWriteVtu(const char* path, const cliSimulation* sim, bool ascii)
{
	cliOutput out;
	if (!cliOutput_Open(&out, path))
		return false;
	FILE* file = out.file;
	bool compress = !ascii && cliVtuCompressed();
	fprintf(file,
	        "<?xml version=\"1.0\"?>\n"
	        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"%s%s>\n"
	        "<UnstructuredGrid>\n",
	        ascii ? "" : " header_type=\"UInt64\"",
	        compress ? " compressor=\"vtkZLibDataCompressor\"" : "");
	cliBlob blob = {NULL, 0, 0, false};
	bool ok = true;
	for (int b = 0; b < sim->bodyCount && ok; ++b)
	{
		cliVtuPiece piece;
		ok = cliVtuPiece_Make(&piece, sim->bodies[b]);
		if (ok && ascii)
			cliWriteVtuPieceAscii(file, &piece);
		else if (ok)
			cliWriteVtuPieceAppended(file, &blob, &piece, compress);
		cliVtuPiece_Free(&piece);
	}
	if (blob.failed)
		cliError("%s: out of memory (or a compression failure) writing the appended data", path);
	if (!ok || blob.failed)
	{
		free(blob.data);
		return cliOutput_Abort(&out);
	}
	fprintf(file, "</UnstructuredGrid>\n");
	if (!ascii)
	{
		// Raw bytes after the underscore, up to the closing tag (the VTK XML format's appended
		// data: offsets count from the byte after '_').
		fprintf(file, "<AppendedData encoding=\"raw\">\n_");
		if (blob.length > 0)
			fwrite(blob.data, 1, blob.length, file);
		fprintf(file, "\n</AppendedData>\n");
	}
	fprintf(file, "</VTKFile>\n");
	free(blob.data);
	return cliOutput_Commit(&out);
}

// ---- .obj: the tet surface (its vertices only) or the render mesh, with smooth normals -------

// Area-weighted vertex normals of @p triangles over @p x (3 per vertex), normalised, into
// @p normals (3 per vertex, zeroed first).
static void cliSmoothNormals(const double* x, int vertexCount, const int* triangles,
                             int triangleCount, double* normals)
{
	memset(normals, 0, sizeof(double) * 3 * (size_t)vertexCount);
	for (int t = 0; t < triangleCount; ++t)
	{
		const int* v = triangles + 3 * t;
		fmVec3 a = fmLoad(x, v[0]);
		fmVec3 n = fmCross(fmSub(fmLoad(x, v[1]), a), fmSub(fmLoad(x, v[2]), a));
		for (int k = 0; k < 3; ++k)
			fmStore(normals, v[k], fmAdd(fmLoad(normals, v[k]), n));
	}
	for (int i = 0; i < vertexCount; ++i)
	{
		fmVec3 n = fmLoad(normals, i);
		double length = fmLength(n);
		fmStore(normals, i, length > 0.0 ? fmScale(1.0 / length, n) : n);
	}
}

// One object: @p vertexCount vertices with normals, triangles indexing them (0-based).
static void cliWriteObjObject(FILE* file, const char* name, const double* x, const double* normals,
                              int vertexCount, const int* triangles, int triangleCount,
                              int vertexBase)
{
	fprintf(file, "o %s\n", name);
	for (int i = 0; i < vertexCount; ++i)
		fprintf(file, "v %.9g %.9g %.9g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
	for (int i = 0; i < vertexCount; ++i)
		fprintf(file, "vn %.6f %.6f %.6f\n", normals[3 * i], normals[3 * i + 1],
		        normals[3 * i + 2]);
	for (int t = 0; t < triangleCount; ++t)
	{
		int a = triangles[3 * t] + vertexBase, b = triangles[3 * t + 1] + vertexBase,
		    c = triangles[3 * t + 2] + vertexBase;
		fprintf(file, "f %d//%d %d//%d %d//%d\n", a, a, b, b, c, c);
	}
}

// A body's render mesh, deformed now. Returns the vertices written, or -1.
static int cliWriteRenderObject(FILE* file, fmBodyId body, const char* name, int vertexBase)
{
	int n = fmBody_GetRenderVertexCount(body), triangleCount = 0;
	const int* triangles = fmBody_GetRenderTriangles(body, &triangleCount);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	double* normals = malloc(sizeof(double) * 3 * (size_t)n);
	bool ok =
	    x != NULL && normals != NULL && fmBody_CopyRenderPositions(body, x, normals, n) == fm_ok;
	if (ok)
		cliWriteObjObject(file, name, x, normals, n, triangles, triangleCount, vertexBase);
	else
		cliError("out of memory writing a render mesh of %d vertices", n);
	free(x);
	free(normals);
	return ok ? n : -1;
}

// A body's tet surface: only the vertices on it, renumbered in ascending order. Returns the
// vertices written, or -1.
static int cliWriteSurfaceObject(FILE* file, fmBodyId body, const char* name, int vertexBase)
{
	int vertexCount = fmBody_GetVertexCount(body), triangleCount = 0;
	const int* surface = fmBody_GetSurface(body, &triangleCount);
	double* all = cliCopyState(body, false);
	int* local = malloc(sizeof(int) * (size_t)vertexCount);
	int* triangles = malloc(sizeof(int) * 3 * (size_t)(triangleCount > 0 ? triangleCount : 1));
	double* x = malloc(sizeof(double) * 3 * (size_t)vertexCount);
	double* normals = malloc(sizeof(double) * 3 * (size_t)vertexCount);
	int n = -1;
	if (all != NULL && local != NULL && triangles != NULL && x != NULL && normals != NULL)
	{
		for (int i = 0; i < vertexCount; ++i)
			local[i] = -1;
		for (int k = 0; k < 3 * triangleCount; ++k)
			local[surface[k]] = 0;
		n = 0;
		for (int i = 0; i < vertexCount; ++i)
			if (local[i] == 0)
			{
				local[i] = n;
				fmStore(x, n++, fmLoad(all, i));
			}
		for (int k = 0; k < 3 * triangleCount; ++k)
			triangles[k] = local[surface[k]];
		cliSmoothNormals(x, n, triangles, triangleCount, normals);
		cliWriteObjObject(file, name, x, normals, n, triangles, triangleCount, vertexBase);
	}
	else
		cliError("out of memory writing the surface of a body of %d vertices", vertexCount);
	free(all);
	free(local);
	free(triangles);
	free(x);
	free(normals);
	return n;
}

bool cliWriteObj(const char* path, const cliSimulation* sim)
{
	cliOutput out;
	if (!cliOutput_Open(&out, path))
		return false;
	FILE* file = out.file;
	fprintf(file, "# femto surface: the render mesh of bodies that have one, else the tet "
	              "surface's vertices\n");
	int vertexBase = 1; // OBJ indices are 1-based and global over the file
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		fmBodyId body = sim->bodies[b];
		char name[32];
		bool render = fmBody_GetRenderVertexCount(body) > 0;
		snprintf(name, sizeof name, render ? "body%d_render" : "body%d", b);
		int written = render ? cliWriteRenderObject(file, body, name, vertexBase)
		                     : cliWriteSurfaceObject(file, body, name, vertexBase);
		if (written < 0)
			return cliOutput_Abort(&out);
		vertexBase += written;
	}
	return cliOutput_Commit(&out);
}

bool cliWriteNodes(const char* path, const cliSimulation* sim, bool announce)
{
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		char bodyPath[CLI_MAX_PATH], temp[CLI_MAX_PATH];
		if (sim->bodyCount == 1)
			snprintf(bodyPath, sizeof bodyPath, "%s", path);
		else
		{
			// "out.node" -> "out_1.node" for body 1.
			size_t length = strlen(path);
			size_t stem =
			    length >= 5 && strcmp(path + length - 5, ".node") == 0 ? length - 5 : length;
			snprintf(bodyPath, sizeof bodyPath, "%.*s_%d.node", (int)stem, path, b);
		}
		if (!cliTempPath(bodyPath, temp, sizeof temp))
			return false;
		fmDiagnostic diag;
		memset(&diag, 0, sizeof diag);
		double* x = cliCopyState(sim->bodies[b], false);
		bool ok = x != NULL && fmWriteTetGenNode(temp, &sim->meshes[b], x, &diag) == fm_ok;
		if (x == NULL)
			cliError("out of memory exporting a body's positions");
		else if (!ok)
			cliPrintDiagnostic(NULL, &diag);
		free(x);
		if (!cliReplace(temp, bodyPath, ok))
			return false;
		if (announce)
			printf("wrote            %s\n", bodyPath);
	}
	return true;
}

// ---- series --------------------------------------------------------------------------------

// Whether the first @p length bytes of @p file are "NAME.pvd", "NAME_NNNNNN.vtu" or
// "NAME_NNNNNN.obj" with the frame number as %06d prints it.
static bool cliIsSeriesName(const char* name, const char* file, size_t length)
{
	size_t n = strlen(name);
	if (length < n + 4 || strncmp(file, name, n) != 0)
		return false;
	if (length == n + 4)
		return memcmp(file + n, ".pvd", 4) == 0;
	if (file[n] != '_' || length < n + 1 + 6 + 4)
		return false;
	const char* digits = file + n + 1;
	size_t count = length - n - 1 - 4;
	if (count > 10 || (count > 6 && digits[0] == '0'))
		return false;
	for (size_t i = 0; i < count; ++i)
		if (!isdigit((unsigned char)digits[i]))
			return false;
	return memcmp(digits + count, ".vtu", 4) == 0 || memcmp(digits + count, ".obj", 4) == 0;
}

bool cliSeries_IsOwnFile(const char* name, const char* fileName)
{
	size_t length = strlen(fileName);
	if (cliIsSeriesName(name, fileName, length))
		return true;
	// A temporary file left by a killed run: ".FILE.PID.tmp" (cliTempPath).
	if (fileName[0] != '.' || length < 7 || strcmp(fileName + length - 4, ".tmp") != 0)
		return false;
	const char* pidEnd = fileName + length - 4;
	const char* pid = pidEnd;
	while (pid > fileName + 1 && isdigit((unsigned char)pid[-1]))
		--pid;
	if (pid == pidEnd || pid[-1] != '.')
		return false;
	return cliIsSeriesName(name, fileName + 1, (size_t)(pid - 1 - (fileName + 1)));
}

// Whether the earlier series' file @p path can be removed and written again: a regular file
// (a folder or anything else with a series' name would stop the run half-way).
static bool cliSeries_Replaceable(const char* path)
{
	struct stat info;
	if (lstat(path, &info) != 0 || S_ISREG(info.st_mode))
		return true;
	fprintf(stderr,
	        "%s: has the name of a file of the series but is %s: move it away (nothing "
	        "of the earlier series was removed)\n",
	        path, S_ISDIR(info.st_mode) ? "a directory" : "not a regular file");
	return false;
}

// Remove what an earlier run of series @p name left in the folder, so a shorter run does not
// leave stale frames beside its .pvd. Only femto's own names are touched, and only once every
// one of them is known to be a file that can be removed (checked first: a failure removes
// nothing).
static bool cliSeries_RemoveOld(cliSeries* series)
{
	DIR* dir = opendir(series->directory);
	if (dir == NULL || access(series->directory, W_OK) != 0)
	{
		fprintf(stderr, "%s: cannot %s: %s\n", series->directory, dir == NULL ? "list" : "write in",
		        strerror(errno));
		if (dir != NULL)
			closedir(dir);
		return false;
	}
	bool ok = true;
	for (int pass = 0; pass < 2 && ok; ++pass, rewinddir(dir))
		for (struct dirent* entry = readdir(dir); entry != NULL && ok; entry = readdir(dir))
		{
			if (!cliSeries_IsOwnFile(series->name, entry->d_name))
				continue;
			char path[CLI_MAX_PATH];
			ok = cliJoinPath(path, sizeof path, series->directory, entry->d_name);
			if (ok && pass == 0)
				ok = cliSeries_Replaceable(path);
			else if (ok && remove(path) != 0)
			{
				fprintf(stderr, "%s: cannot remove the file of an earlier run: %s\n", path,
				        strerror(errno));
				ok = false;
			}
			series->removed += ok && pass == 1 ? 1 : 0;
		}
	closedir(dir);
	return ok;
}

// The whole collection, written again: every frame so far and the closing tags.
static bool cliSeries_WritePvd(const cliSeries* series)
{
	cliOutput out;
	if (!cliOutput_Open(&out, series->pvdPath))
		return false;
	fprintf(out.file, "<?xml version=\"1.0\"?>\n"
	                  "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	                  "<Collection>\n");
	if (series->entriesLength > 0)
		fwrite(series->entries, 1, series->entriesLength, out.file);
	fprintf(out.file, "</Collection>\n</VTKFile>\n");
	return cliOutput_Commit(&out);
}

bool cliSeries_Open(cliSeries* series, const char* directory, const char* name, bool obj,
                    bool ascii)
{
	memset(series, 0, sizeof *series);
	series->ascii = ascii;
	snprintf(series->directory, sizeof series->directory, "%s", directory);
	snprintf(series->name, sizeof series->name, "%s", name);
	series->obj = obj;
	char fileName[300];
	snprintf(fileName, sizeof fileName, "%s.pvd", name);
	return cliMakeDirectories(directory) &&
	       cliJoinPath(series->pvdPath, sizeof series->pvdPath, directory, fileName) &&
	       cliSeries_RemoveOld(series) && cliSeries_WritePvd(series);
}

// Append one <DataSet/> line to the collection held in memory.
static bool cliSeries_AddEntry(cliSeries* series, const char* fileName, double time)
{
	char line[400];
	int length = snprintf(line, sizeof line,
	                      "<DataSet timestep=\"%.9g\" group=\"\" part=\"0\" file=\"%s\"/>\n", time,
	                      fileName);
	if (length < 0 || (size_t)length >= sizeof line)
		return false;
	if (series->entriesLength + (size_t)length > series->entriesCapacity)
	{
		size_t capacity = series->entriesCapacity > 0 ? 2 * series->entriesCapacity : 4096;
		char* grown = realloc(series->entries, capacity);
		if (grown == NULL)
		{
			fprintf(stderr, "%s: out of memory\n", series->pvdPath);
			return false;
		}
		series->entries = grown;
		series->entriesCapacity = capacity;
	}
	memcpy(series->entries + series->entriesLength, line, (size_t)length);
	series->entriesLength += (size_t)length;
	return true;
}

bool cliSeries_WriteFrame(cliSeries* series, const cliSimulation* sim, int frame, double time)
{
	char fileName[300], objName[300], path[CLI_MAX_PATH];
	snprintf(fileName, sizeof fileName, "%s_%06d.vtu", series->name, frame);
	snprintf(objName, sizeof objName, "%s_%06d.obj", series->name, frame);
	if (!cliJoinPath(path, sizeof path, series->directory, fileName) ||
	    !cliWriteVtu(path, sim, series->ascii))
		return false;
	if (series->obj &&
	    (!cliJoinPath(path, sizeof path, series->directory, objName) || !cliWriteObj(path, sim)))
		return false;
	// The frame's files are complete: now the collection may list it. Relative file names keep
	// the folder movable. Rewriting the whole .pvd costs about 70 bytes per frame so far, small
	// beside a frame's .vtu (70 kB for the house) for any run worth saving.
	if (!cliSeries_AddEntry(series, fileName, time) || !cliSeries_WritePvd(series))
		return false;
	series->written += 1;
	return true;
}

void cliSeries_Free(cliSeries* series)
{
	free(series->entries);
	series->entries = NULL;
	series->entriesLength = 0;
	series->entriesCapacity = 0;
}
