// Output writers: VTK XML (ASCII, so any ParaView or a text editor reads it), PVD collections
// and OBJ surfaces.
#include "output.h"

#include <errno.h>
#include <string.h>

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

static FILE* cliOpenForWriting(const char* path)
{
	FILE* file = fopen(path, "w");
	if (file == NULL)
		fprintf(stderr, "%s: cannot open for writing: %s\n", path, strerror(errno));
	return file;
}

static void cliWriteVtuPiece(FILE* file, fmBodyId body)
{
	int vertexCount = fmBody_GetVertexCount(body);
	int tetCount = fmBody_GetTetCount(body);
	const double* x = fmBody_GetPositions(body);
	const double* v = fmBody_GetVelocities(body);
	const int* tets = fmBody_GetTets(body);
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
}

bool cliWriteVtu(const char* path, const cliSimulation* sim)
{
	FILE* file = cliOpenForWriting(path);
	if (file == NULL)
		return false;
	fprintf(file,
	        "<?xml version=\"1.0\"?>\n"
	        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	        "<UnstructuredGrid>\n");
	for (int b = 0; b < sim->bodyCount; ++b)
		cliWriteVtuPiece(file, sim->bodies[b]);
	fprintf(file, "</UnstructuredGrid>\n</VTKFile>\n");
	return cliFinishFile(file, path);
}

bool cliWriteObj(const char* path, const cliSimulation* sim)
{
	FILE* file = cliOpenForWriting(path);
	if (file == NULL)
		return false;
	fprintf(file, "# femto surface\n");
	int vertexBase = 1; // OBJ indices are 1-based and global over the file
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		fmBodyId body = sim->bodies[b];
		int vertexCount = fmBody_GetVertexCount(body);
		int triangleCount = 0;
		const double* x = fmBody_GetPositions(body);
		const int* triangles = fmBody_GetSurface(body, &triangleCount);
		fprintf(file, "o body%d\n", b);
		for (int i = 0; i < vertexCount; ++i)
			fprintf(file, "v %.9g %.9g %.9g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
		for (int t = 0; t < triangleCount; ++t)
			fprintf(file, "f %d %d %d\n", triangles[3 * t] + vertexBase,
			        triangles[3 * t + 1] + vertexBase, triangles[3 * t + 2] + vertexBase);
		vertexBase += vertexCount;
	}
	return cliFinishFile(file, path);
}

bool cliSeries_Open(cliSeries* series, const char* directory, const char* name, bool obj)
{
	memset(series, 0, sizeof *series);
	snprintf(series->directory, sizeof series->directory, "%s", directory);
	snprintf(series->name, sizeof series->name, "%s", name);
	series->obj = obj;
	char fileName[300];
	snprintf(fileName, sizeof fileName, "%s.pvd", name);
	if (!cliMakeDirectories(directory) ||
	    !cliJoinPath(series->pvdPath, sizeof series->pvdPath, directory, fileName))
		return false;
	series->pvd = cliOpenForWriting(series->pvdPath);
	if (series->pvd == NULL)
		return false;
	fprintf(series->pvd,
	        "<?xml version=\"1.0\"?>\n"
	        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
	        "<Collection>\n");
	return true;
}

bool cliSeries_WriteFrame(cliSeries* series, const cliSimulation* sim, int frame, double time)
{
	char fileName[300], path[CLI_MAX_PATH];
	snprintf(fileName, sizeof fileName, "%s_%06d.vtu", series->name, frame);
	if (!cliJoinPath(path, sizeof path, series->directory, fileName) || !cliWriteVtu(path, sim))
		return false;
	// Relative file names keep the folder movable.
	fprintf(series->pvd, "<DataSet timestep=\"%.9g\" group=\"\" part=\"0\" file=\"%s\"/>\n", time,
	        fileName);
	fflush(series->pvd);
	series->written += 1;
	if (series->obj)
	{
		snprintf(fileName, sizeof fileName, "%s_%06d.obj", series->name, frame);
		if (!cliJoinPath(path, sizeof path, series->directory, fileName) || !cliWriteObj(path, sim))
			return false;
	}
	return true;
}

bool cliSeries_Close(cliSeries* series)
{
	if (series->pvd == NULL)
		return true;
	fprintf(series->pvd, "</Collection>\n</VTKFile>\n");
	bool ok = cliFinishFile(series->pvd, series->pvdPath);
	series->pvd = NULL;
	return ok;
}
