// Output writers: VTK XML unstructured grids (.vtu) collected in a ParaView .pvd series,
// Wavefront OBJ surfaces and TetGen .node positions. Every file is written to a temporary name
// in its folder and renamed over the final name when complete, so a file that exists is whole
// even after a kill or a crash. Every I/O error names the path.
#pragma once

#include "scene.h"

#include <stdio.h>

/// A time series being written to a folder: NAME.pvd plus NAME_000000.vtu (and .obj) per frame.
/// The .pvd is rewritten whole (atomically) after every frame, so it always lists exactly the
/// frames on disk and ParaView opens it even when the run is interrupted.
typedef struct cliSeries
{
	char directory[CLI_MAX_PATH];
	char name[256];
	char pvdPath[CLI_MAX_PATH];
	bool obj;
	bool ascii;             ///< .vtu in ASCII instead of binary appended data
	char* entries;          ///< malloc'd: the <DataSet .../> lines so far
	size_t entriesLength;   ///< bytes used in entries
	size_t entriesCapacity; ///< bytes allocated
	int written;            ///< frames written
	int removed;            ///< files of an earlier series of the same name removed at open
} cliSeries;

/// Create @p directory (and parents), remove the files an earlier series of the same NAME left
/// there (NAME.pvd, NAME_NNNNNN.vtu, NAME_NNNNNN.obj and their temporary files: exactly the
/// names femto writes, nothing else), and write an empty NAME.pvd. @p ascii: the frames' .vtu
/// in ASCII (else binary, cliWriteVtu).
bool cliSeries_Open(cliSeries* series, const char* directory, const char* name, bool obj,
                    bool ascii);

/// Write frame @p frame at simulated time @p time (s) and rewrite the collection with it.
bool cliSeries_WriteFrame(cliSeries* series, const cliSimulation* sim, int frame, double time);

/// Release the series (its .pvd is complete after every frame). Safe on a series that failed to
/// open.
void cliSeries_Free(cliSeries* series);

/// Whether @p fileName is one that series @p name writes: NAME.pvd, NAME_NNNNNN.vtu or
/// NAME_NNNNNN.obj (the frame number printed with %06d) or the temporary file of one of them.
bool cliSeries_IsOwnFile(const char* name, const char* fileName);

/// Write every body of @p sim as one piece of a VTK unstructured grid (tets, VTK_TETRA = 10),
/// with point data "velocity" (m/s): with @p ascii as text (positions to 17 digits), else as
/// binary arrays in the appended data section (encoding raw, header_type UInt64, little-endian),
/// compressed with zlib (vtkZLibDataCompressor, 32 KiB blocks) when cliVtuCompressed().
bool cliWriteVtu(const char* path, const cliSimulation* sim, bool ascii);

/// Whether binary .vtu data is zlib-compressed (the tool was built with zlib).
bool cliVtuCompressed(void);

/// Write every body as one OBJ object with vertex normals (area-weighted, unit): its render mesh
/// (fmBody_SetRenderMesh) deformed now when it has one, else its outward tet surface with only
/// the vertices on it.
bool cliWriteObj(const char* path, const cliSimulation* sim);

/// Write the current positions of every body as TetGen .node files with the input numbering:
/// @p path for one body, "STEM_B.node" for body B of several. Prints "wrote PATH" per file when
/// @p announce.
bool cliWriteNodes(const char* path, const cliSimulation* sim, bool announce);
