// Output writers: VTK XML (ASCII, so any ParaView or a text editor reads it), PVD collections,
// OBJ surfaces and .node positions, each written whole to a temporary file and renamed.
#include "output.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

// VTK cell type of a linear tetrahedron (vtkCellType.h).
#define CLI_VTK_TETRA 10

// Close @p file and report a write error by path. Returns true if everything reached the disk.
static bool cliFinishFile(FILE* file, const char* path)
{
	bool failed = ferror(file) != 0;
	int savedErrno = errno;
	if (fclose(file) != 0)
	{
		failed = true;
		savedErrno = errno;
	}
	if (failed)
		fprintf(stderr, "%s: write error: %s\n", path, strerror(savedErrno));
	return !failed;
}

// ---- whole files or none: a temporary file in the same folder, renamed when complete ---------

// A file being written: the stream goes to @p temp, renamed to @p path by cliOutput_Commit.
typedef struct cliOutput
{
	FILE* file;
	const char* path;
	char temp[CLI_MAX_PATH];
} cliOutput;

// "dir/name" -> "dir/.name.PID.tmp": hidden, in the same folder (rename within one file system
// is atomic), unique per process. A path that exists and is not a regular file (a FIFO,
// /dev/stdout) is written in place: renaming over it would replace it.
static bool cliTempPath(const char* path, char* temp, size_t size)
{
	struct stat info;
	if (stat(path, &info) == 0 && !S_ISREG(info.st_mode))
		return snprintf(temp, size, "%s", path) < (int)size;
	const char* slash = strrchr(path, '/');
	size_t folder = slash != NULL ? (size_t)(slash - path) + 1 : 0;
	int written =
	    snprintf(temp, size, "%.*s.%s.%ld.tmp", (int)folder, path, path + folder, (long)getpid());
	if (written < 0 || (size_t)written >= size)
	{
		fprintf(stderr, "%s: path too long\n", path);
		return false;
	}
	return true;
}

// Put the finished temporary file in place (or remove it when @p ok is false).
static bool cliReplace(const char* temp, const char* path, bool ok)
{
	if (strcmp(temp, path) == 0)
		return ok;
	if (ok && rename(temp, path) != 0)
	{
		fprintf(stderr, "%s: cannot rename %s over it: %s\n", path, temp, strerror(errno));
		ok = false;
	}
	if (!ok)
		remove(temp);
	return ok;
}

static bool cliOutput_Open(cliOutput* out, const char* path)
{
	out->path = path;
	out->file = NULL;
	if (!cliTempPath(path, out->temp, sizeof out->temp))
		return false;
	out->file = fopen(out->temp, "w");
	if (out->file == NULL)
		fprintf(stderr, "%s: cannot open for writing: %s\n", out->temp, strerror(errno));
	return out->file != NULL;
}

static bool cliOutput_Commit(cliOutput* out)
{
	bool ok = cliFinishFile(out->file, out->temp);
	out->file = NULL;
	return cliReplace(out->temp, out->path, ok);
}

// Drop a file being written (a failure half-way): nothing replaces @p out->path.
static bool cliOutput_Abort(cliOutput* out)
{
	fclose(out->file);
	out->file = NULL;
	return cliReplace(out->temp, out->path, false);
}

static bool cliWriteVtuPiece(FILE* file, fmBodyId body)
{
	int vertexCount = fmBody_GetVertexCount(body);
	int tetCount = fmBody_GetTetCount(body);
	double* x = cliCopyState(body, false);
	double* v = cliCopyState(body, true);
	const int* tets = fmBody_GetTets(body);
	if (x == NULL || v == NULL)
	{
		free(x);
		free(v);
		cliError("out of memory writing a .vtu piece of %d vertices", vertexCount);
		return false;
	}
	fprintf(file, "<Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", vertexCount, tetCount);
	fprintf(file, "<PointData Vectors=\"velocity\">\n"
	              "<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
	              "format=\"ascii\">\n");
	for (int i = 0; i < vertexCount; ++i)
		fprintf(file, "%.9g %.9g %.9g\n", v[3 * i], v[3 * i + 1], v[3 * i + 2]);
	fprintf(file, "</DataArray>\n</PointData>\n<Points>\n"
	              "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
	// 17 significant digits: the positions round-trip exactly.
	for (int i = 0; i < vertexCount; ++i)
		fprintf(file, "%.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
	fprintf(file, "</DataArray>\n</Points>\n<Cells>\n"
	              "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
	for (int t = 0; t < tetCount; ++t)
		fprintf(file, "%d %d %d %d\n", tets[4 * t], tets[4 * t + 1], tets[4 * t + 2],
		        tets[4 * t + 3]);
	fprintf(file, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
	for (int t = 0; t < tetCount; ++t)
		fprintf(file, "%d\n", 4 * (t + 1));
	fprintf(file, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
	for (int t = 0; t < tetCount; ++t)
		fprintf(file, "%d\n", CLI_VTK_TETRA);
	fprintf(file, "</DataArray>\n</Cells>\n</Piece>\n");
	free(x);
	free(v);
	return true;
}

bool cliWriteVtu(const char* path, const cliSimulation* sim)
{
	cliOutput out;
	if (!cliOutput_Open(&out, path))
		return false;
	FILE* file = out.file;
	fprintf(file,
	        "<?xml version=\"1.0\"?>\n"
	        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	        "<UnstructuredGrid>\n");
	bool ok = true;
	for (int b = 0; b < sim->bodyCount && ok; ++b)
		ok = cliWriteVtuPiece(file, sim->bodies[b]);
	if (!ok)
		return cliOutput_Abort(&out);
	fprintf(file, "</UnstructuredGrid>\n</VTKFile>\n");
	return cliOutput_Commit(&out);
}

bool cliWriteObj(const char* path, const cliSimulation* sim)
{
	cliOutput out;
	if (!cliOutput_Open(&out, path))
		return false;
	FILE* file = out.file;
	fprintf(file, "# femto surface\n");
	int vertexBase = 1; // OBJ indices are 1-based and global over the file
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		fmBodyId body = sim->bodies[b];
		int vertexCount = fmBody_GetVertexCount(body);
		int triangleCount = 0;
		double* x = cliCopyState(body, false);
		const int* triangles = fmBody_GetSurface(body, &triangleCount);
		if (x == NULL)
		{
			cliError("out of memory writing the surface of a body of %d vertices", vertexCount);
			return cliOutput_Abort(&out);
		}
		fprintf(file, "o body%d\n", b);
		for (int i = 0; i < vertexCount; ++i)
			fprintf(file, "v %.9g %.9g %.9g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
		free(x);
		for (int t = 0; t < triangleCount; ++t)
			fprintf(file, "f %d %d %d\n", triangles[3 * t] + vertexBase,
			        triangles[3 * t + 1] + vertexBase, triangles[3 * t + 2] + vertexBase);
		vertexBase += vertexCount;
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

// Remove what an earlier run of series @p name left in the folder, so a shorter run does not
// leave stale frames beside its .pvd. Only femto's own names are touched.
static bool cliSeries_RemoveOld(cliSeries* series)
{
	DIR* dir = opendir(series->directory);
	if (dir == NULL)
	{
		fprintf(stderr, "%s: cannot list: %s\n", series->directory, strerror(errno));
		return false;
	}
	bool ok = true;
	for (struct dirent* entry = readdir(dir); entry != NULL && ok; entry = readdir(dir))
	{
		if (!cliSeries_IsOwnFile(series->name, entry->d_name))
			continue;
		char path[CLI_MAX_PATH];
		ok = cliJoinPath(path, sizeof path, series->directory, entry->d_name);
		if (ok && remove(path) != 0)
		{
			fprintf(stderr, "%s: cannot remove the file of an earlier run: %s\n", path,
			        strerror(errno));
			ok = false;
		}
		series->removed += ok ? 1 : 0;
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

bool cliSeries_Open(cliSeries* series, const char* directory, const char* name, bool obj)
{
	memset(series, 0, sizeof *series);
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
	if (!cliJoinPath(path, sizeof path, series->directory, fileName) || !cliWriteVtu(path, sim))
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
