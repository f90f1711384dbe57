// Mesh files by extension (docs/mesh-format.md): fmLoadMesh picks the reader (TetGen in
// mesh_tetgen.c, Gmsh in mesh_gmsh.c, VTK in mesh_vtk.c and mesh_vtu.c, Medit in mesh_medit.c); the
// writers of TetGen .ele, Gmsh .msh 4.1 ASCII and ASCII .vtu, and fmWriteMesh which picks one.
#include "core/core.h"
#include "core/det_math.h"
#include "mesh/mesh_file.h"
#include "mesh/mesh_gmsh.h"
#include "mesh/mesh_internal.h"
#include "mesh/mesh_medit.h"
#include "mesh/mesh_vtk.h"
#include "mesh/mesh_vtu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- formats ----------------------------------------------------------------------------------

// True when @p path ends in @p extension (with its dot), ignoring ASCII case.
static bool fmHasExtension(const char* path, const char* extension)
{
	size_t n = strlen(path), e = strlen(extension);
	if (n <= e)
		return false;
	for (size_t k = 0; k < e; ++k)
	{
		char c = path[n - e + k];
		if (c >= 'A' && c <= 'Z')
			c = (char)(c - 'A' + 'a');
		if (c != extension[k])
			return false;
	}
	return true;
}

fmMeshFormat fmMeshFormatFromPath(const char* path)
{
	if (path == NULL)
		return fm_meshFormatUnknown;
	if (fmHasExtension(path, ".node") || fmHasExtension(path, ".ele"))
		return fm_meshFormatTetGen;
	if (fmHasExtension(path, ".msh"))
		return fm_meshFormatGmsh;
	if (fmHasExtension(path, ".vtk"))
		return fm_meshFormatVtk;
	if (fmHasExtension(path, ".vtu"))
		return fm_meshFormatVtu;
	if (fmHasExtension(path, ".mesh"))
		return fm_meshFormatMedit;
	return fm_meshFormatUnknown;
}

const char* fmMeshFormatName(fmMeshFormat format)
{
	switch (format)
	{
	case fm_meshFormatTetGen:
		return "TetGen";
	case fm_meshFormatGmsh:
		return "Gmsh";
	case fm_meshFormatVtk:
		return "VTK legacy";
	case fm_meshFormatVtu:
		return "VTK XML";
	case fm_meshFormatMedit:
		return "Medit";
	default:
		return "unknown";
	}
}

bool fmMeshFormatHasZlib(void)
{
	return fmVtuHasZlib();
}

// ---- loading ----------------------------------------------------------------------------------

fmResult fmLoadMeshFromMemory(const void* data, size_t size, const char* name, fmMeshFormat format,
                              fmTetMesh* mesh, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	FM_ASSERT(mesh != NULL);
	if (mesh == NULL)
		return fmDiagError(diag, fm_errParameter, name ? name : "", 0, 0, "no mesh to load into");
	memset(mesh, 0, sizeof *mesh);
	name = name ? name : "<mesh text>";
	switch (format)
	{
	case fm_meshFormatGmsh:
		return fmParseGmsh(data, size, name, mesh, diag);
	case fm_meshFormatVtk:
		return fmParseVtkLegacy(data, size, name, mesh, diag);
	case fm_meshFormatVtu:
		return fmParseVtu(data, size, name, mesh, diag);
	case fm_meshFormatMedit:
		return fmParseMedit(data, size, name, mesh, diag);
	default:
		return fmDiagError(diag, fm_errParameter, name, 0, 0,
		                   "format %s cannot be read from one text: expected Gmsh, VTK legacy, "
		                   "VTK XML or Medit (TetGen: fmLoadTetGenFromMemory)",
		                   fmMeshFormatName(format));
	}
}

// @p path with its last @p dropped bytes replaced by @p extension, in a new allocation.
static char* fmSwapExtension(const char* path, size_t dropped, const char* extension, size_t* size)
{
	size_t keep = strlen(path) - dropped;
	*size = keep + strlen(extension) + 1;
	char* out = fmAlloc(*size);
	if (out != NULL)
		snprintf(out, *size, "%.*s%s", (int)keep, path, extension);
	return out;
}

static fmResult fmLoadTetGenPair(const char* path, const fmMeshLoadDef* def, fmTetMesh* mesh,
                                 fmDiagnostic* diag)
{
	bool isNode = fmHasExtension(path, ".node");
	size_t size;
	char* other = fmSwapExtension(path, isNode ? 5 : 4, isNode ? ".ele" : ".node", &size);
	if (other == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, path, 0, 0, "out of memory");
	fmResult result = isNode ? fmLoadTetGenWithDef(path, other, def, mesh, diag)
	                         : fmLoadTetGenWithDef(other, path, def, mesh, diag);
	fmDealloc(other, size);
	return result;
}

fmResult fmLoadMeshWithDef(const char* path, const fmMeshLoadDef* def, fmTetMesh* mesh,
                           fmDiagnostic* diag)
{
	fmResult started = fmStartLoad(mesh, def, diag);
	if (started != fm_ok)
		return started;
	if (path == NULL)
		return fmDiagError(diag, fm_errIo, "", 0, 0, "cannot open: no path given");
	fmMeshFormat format = fmMeshFormatFromPath(path);
	if (format == fm_meshFormatUnknown)
		return fmDiagError(diag, fm_errSyntax, path, 0, 0,
		                   "not a mesh file femto reads: expected a name ending in .node or .ele "
		                   "(TetGen), .msh (Gmsh), .vtk or .vtu (VTK) or .mesh (Medit); a surface "
		                   "mesh must be made into tets first (TetGen or Gmsh)");
	if (format == fm_meshFormatTetGen)
		return fmLoadTetGenPair(path, def, mesh, diag);
	fmFileText text;
	fmResult result = fmReadWholeFile(path, def->maxFileBytes, &text, diag);
	if (result == fm_ok)
		result = fmLoadMeshFromMemory(text.data, text.size, path, format, mesh, diag);
	fmFileText_Free(&text);
	return result;
}

fmResult fmLoadMesh(const char* path, fmTetMesh* mesh, fmDiagnostic* diag)
{
	fmMeshLoadDef def = fmDefaultMeshLoadDef();
	return fmLoadMeshWithDef(path, &def, mesh, diag);
}

// ---- writing ----------------------------------------------------------------------------------

// A mesh the writers accept: points, tets on existing nodes, attributes where counted.
static fmResult fmCheckMeshToWrite(const char* path, const fmTetMesh* m, const double* x,
                                   bool needTets, fmDiagnostic* diag)
{
	bool valid = path != NULL && m != NULL && m->nodeCount > 0 && x != NULL &&
	             (!needTets || (m->tetCount > 0 && m->tets != NULL)) &&
	             (m->tetAttributeCount == 0 || m->tetAttributes != NULL);
	for (size_t k = 0; valid && needTets && k < 4 * (size_t)m->tetCount; ++k)
		valid = m->tets[k] >= 0 && m->tets[k] < m->nodeCount;
	FM_ASSERT(valid);
	if (!valid)
		return fmDiagError(diag, fm_errParameter, path ? path : "", 0, 0,
		                   "expected a path and a mesh with points and tets on them");
	return fmCheckFinitePoints(path, m, x, diag);
}

// fmWriteTetGenEle, staged when @p commit is false (fmWriteTetGenNodeFile).
static fmResult fmWriteTetGenEleFile(const char* path, const fmTetMesh* mesh, bool commit,
                                     fmDiagnostic* diag)
{
	fmDiagClear(diag);
	fmResult result = fmCheckMeshToWrite(path, mesh, mesh ? mesh->positions : NULL, true, diag);
	if (result != fm_ok)
		return result;
	const fmTetMesh* m = mesh;
	for (size_t k = 0; k < (size_t)m->tetCount * (size_t)m->tetAttributeCount; ++k)
		if (!isfinite(m->tetAttributes[k]))
			return fmDiagError(diag, fm_errRange, path, 0, 0,
			                   "tet %d has a non-finite attribute: expected finite values",
			                   (int)(k / (size_t)m->tetAttributeCount) + m->firstIndex);
	FILE* f = fmOpenForWriting(path, diag, &result);
	if (f == NULL)
		return result;
	bool ok = fprintf(f, "%d 4 %d\n", m->tetCount, m->tetAttributeCount) > 0;
	for (int t = 0; t < m->tetCount && ok; ++t)
	{
		const int* v = m->tets + 4 * (size_t)t;
		int b = m->firstIndex;
		ok = fprintf(f, "%d %d %d %d %d", t + b, v[0] + b, v[1] + b, v[2] + b, v[3] + b) > 0;
		for (int a = 0; a < m->tetAttributeCount && ok; ++a)
			ok =
			    fprintf(f, " %.17g",
			            m->tetAttributes[(size_t)t * (size_t)m->tetAttributeCount + (size_t)a]) > 0;
		ok = ok && fputc('\n', f) != EOF;
	}
	return commit ? fmFinishFile(f, ok, path, diag) : fmFinishFileStaged(f, ok, path, diag);
}

fmResult fmWriteTetGenEle(const char* path, const fmTetMesh* mesh, fmDiagnostic* diag)
{
	return fmWriteTetGenEleFile(path, mesh, true, diag);
}

// The regions to write as Gmsh volumes: the distinct values of the first tet attribute when all
// are integers from 1 to INT_MAX (Gmsh physical tags are positive), sorted; else none.
static int fmCompareInts(const void* a, const void* b)
{
	int p = *(const int*)a, q = *(const int*)b;
	return p < q ? -1 : (p > q);
}

static int fmGmshRegions(const fmTetMesh* m, int** regions, int* region)
{
	*regions = NULL;
	if (m->tetAttributeCount < 1)
		return 0;
	for (int t = 0; t < m->tetCount; ++t)
	{
		double a = m->tetAttributes[(size_t)t * (size_t)m->tetAttributeCount];
		if (!(a >= 1.0 && a <= 2147483647.0 && a == floor(a)))
			return 0;
		region[t] = (int)a;
	}
	int* sorted = FM_ALLOC_ARRAY(int, m->tetCount);
	if (sorted == NULL)
		return -1;
	memcpy(sorted, region, sizeof(int) * (size_t)m->tetCount);
	qsort(sorted, (size_t)m->tetCount, sizeof(int), fmCompareInts);
	int count = 0;
	for (int t = 0; t < m->tetCount; ++t)
		if (t == 0 || sorted[t] != sorted[t - 1])
			sorted[count++] = sorted[t];
	*regions = sorted;
	return count;
}

static bool fmWriteGmshText(FILE* f, const fmTetMesh* m, const double* x, const int* regions,
                            int regionCount, const int* region)
{
	int volumes = regionCount > 0 ? regionCount : 1;
	double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]};
	for (size_t k = 0; k < 3 * (size_t)m->nodeCount; ++k)
	{
		lo[k % 3] = fmMin(lo[k % 3], x[k]);
		hi[k % 3] = fmMax(hi[k % 3], x[k]);
	}
	bool ok =
	    fprintf(f, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 %d\n", volumes) > 0;
	for (int v = 0; v < volumes && ok; ++v)
	{
		ok = fprintf(f, "%d %.17g %.17g %.17g %.17g %.17g %.17g ", v + 1, lo[0], lo[1], lo[2],
		             hi[0], hi[1], hi[2]) > 0;
		ok = ok && (regionCount > 0 ? fprintf(f, "1 %d 0\n", regions[v]) : fprintf(f, "0 0\n")) > 0;
	}
	ok = ok && fprintf(f, "$EndEntities\n$Nodes\n1 %d 1 %d\n3 1 0 %d\n", m->nodeCount, m->nodeCount,
	                   m->nodeCount) > 0;
	for (int i = 0; i < m->nodeCount && ok; ++i)
		ok = fprintf(f, "%d\n", i + 1) > 0;
	for (int i = 0; i < m->nodeCount && ok; ++i)
		ok = fprintf(f, "%.17g %.17g %.17g\n", x[3 * (size_t)i], x[3 * (size_t)i + 1],
		             x[3 * (size_t)i + 2]) > 0;
	ok = ok &&
	     fprintf(f, "$EndNodes\n$Elements\n%d %d 1 %d\n", volumes, m->tetCount, m->tetCount) > 0;
	for (int v = 0; v < volumes && ok; ++v)
	{
		int count = 0;
		for (int t = 0; t < m->tetCount; ++t)
			count += regionCount == 0 || region[t] == regions[v];
		ok = fprintf(f, "3 %d 4 %d\n", v + 1, count) > 0;
		for (int t = 0; t < m->tetCount && ok; ++t)
		{
			if (regionCount > 0 && region[t] != regions[v])
				continue;
			const int* n = m->tets + 4 * (size_t)t;
			ok = fprintf(f, "%d %d %d %d %d\n", t + 1, n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1) > 0;
		}
	}
	return ok && fprintf(f, "$EndElements\n") > 0;
}

fmResult fmWriteGmsh(const char* path, const fmTetMesh* mesh, const double* positions,
                     fmDiagnostic* diag)
{
	fmDiagClear(diag);
	const double* x = positions ? positions : mesh ? mesh->positions : NULL;
	fmResult result = fmCheckMeshToWrite(path, mesh, x, true, diag);
	if (result != fm_ok)
		return result;
	int* region = FM_ALLOC_ARRAY(int, mesh->tetCount);
	int* regions = NULL;
	int regionCount = region ? fmGmshRegions(mesh, &regions, region) : -1;
	if (regionCount < 0)
	{
		FM_FREE_ARRAY(region, int, mesh->tetCount);
		return fmDiagError(diag, fm_errOutOfMemory, path, 0, 0, "out of memory");
	}
	FILE* f = fmOpenForWriting(path, diag, &result);
	if (f != NULL)
		result =
		    fmFinishFile(f, fmWriteGmshText(f, mesh, x, regions, regionCount, region), path, diag);
	FM_FREE_ARRAY(region, int, mesh->tetCount);
	FM_FREE_ARRAY(regions, int, mesh->tetCount);
	return result;
}

static bool fmWriteVtuText(FILE* f, const fmTetMesh* m, const double* x)
{
	bool ok = fprintf(f,
	                  "<?xml version=\"1.0\"?>\n"
	                  "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
	                  "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
	                  "  <UnstructuredGrid>\n"
	                  "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n"
	                  "      <Points>\n"
	                  "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" "
	                  "format=\"ascii\">\n",
	                  m->nodeCount, m->tetCount) > 0;
	for (int i = 0; i < m->nodeCount && ok; ++i)
		ok = fprintf(f, "%.17g %.17g %.17g\n", x[3 * (size_t)i], x[3 * (size_t)i + 1],
		             x[3 * (size_t)i + 2]) > 0;
	ok = ok && fprintf(f, "        </DataArray>\n      </Points>\n      <Cells>\n"
	                      "        <DataArray type=\"Int64\" Name=\"connectivity\" "
	                      "format=\"ascii\">\n") > 0;
	for (int t = 0; t < m->tetCount && ok; ++t)
	{
		const int* n = m->tets + 4 * (size_t)t;
		ok = fprintf(f, "%d %d %d %d\n", n[0], n[1], n[2], n[3]) > 0;
	}
	ok = ok &&
	     fprintf(f, "        </DataArray>\n"
	                "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n") > 0;
	for (int t = 0; t < m->tetCount && ok; ++t)
		ok = fprintf(f, "%lld\n", 4LL * (t + 1)) > 0;
	ok = ok &&
	     fprintf(f, "        </DataArray>\n"
	                "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n") > 0;
	for (int t = 0; t < m->tetCount && ok; ++t)
		ok = fputs("10\n", f) != EOF;
	ok = ok && fprintf(f, "        </DataArray>\n      </Cells>\n") > 0;
	if (m->tetAttributeCount > 0 && ok)
	{
		ok = fprintf(f, "      <CellData>\n        <DataArray type=\"Float64\" Name=\"region\" "
		                "format=\"ascii\">\n") > 0;
		for (int t = 0; t < m->tetCount && ok; ++t)
			ok = fprintf(f, "%.17g\n", m->tetAttributes[(size_t)t * (size_t)m->tetAttributeCount]) >
			     0;
		ok = ok && fprintf(f, "        </DataArray>\n      </CellData>\n") > 0;
	}
	return ok && fprintf(f, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n") > 0;
}

fmResult fmWriteVtu(const char* path, const fmTetMesh* mesh, const double* positions,
                    fmDiagnostic* diag)
{
	fmDiagClear(diag);
	const double* x = positions ? positions : mesh ? mesh->positions : NULL;
	fmResult result = fmCheckMeshToWrite(path, mesh, x, true, diag);
	if (result != fm_ok)
		return result;
	for (int t = 0; t < mesh->tetCount * (mesh->tetAttributeCount > 0); ++t)
		if (!isfinite(mesh->tetAttributes[(size_t)t * (size_t)mesh->tetAttributeCount]))
			return fmDiagError(diag, fm_errRange, path, 0, 0,
			                   "tet %d has a non-finite region: expected finite values", t);
	FILE* f = fmOpenForWriting(path, diag, &result);
	if (f == NULL)
		return result;
	return fmFinishFile(f, fmWriteVtuText(f, mesh, x), path, diag);
}

fmResult fmWriteMesh(const char* path, const fmTetMesh* mesh, const double* positions,
                     fmDiagnostic* diag)
{
	fmDiagClear(diag);
	fmMeshFormat format = fmMeshFormatFromPath(path);
	if (format == fm_meshFormatGmsh)
		return fmWriteGmsh(path, mesh, positions, diag);
	if (format == fm_meshFormatVtu)
		return fmWriteVtu(path, mesh, positions, diag);
	if (format != fm_meshFormatTetGen)
		return fmDiagError(diag, fm_errParameter, path ? path : "", 0, 0,
		                   "femto writes meshes as .node/.ele (TetGen), .msh (Gmsh 4.1) or .vtu: "
		                   "expected one of these extensions");
	bool isNode = fmHasExtension(path, ".node");
	size_t size;
	char* other = fmSwapExtension(path, isNode ? 5 : 4, isNode ? ".ele" : ".node", &size);
	if (other == NULL)
		return fmDiagError(diag, fm_errOutOfMemory, path, 0, 0, "out of memory");
	const char* nodePath = isNode ? path : other;
	const char* elePath = isNode ? other : path;
	// Both files are written in full before either is put in place: a failure leaves both as
	// they were.
	fmResult result = fmWriteTetGenNodeFile(nodePath, mesh, positions, false, diag);
	if (result == fm_ok)
		result = fmWriteTetGenEleFile(elePath, mesh, false, diag);
	if (result == fm_ok)
		result = fmCommitFile(nodePath, diag);
	if (result == fm_ok)
		result = fmCommitFile(elePath, diag);
	else
		fmDiscardFile(nodePath), fmDiscardFile(elePath);
	fmDealloc(other, size);
	return result;
}
