// Output writers: VTK XML unstructured grids (.vtu) collected in a ParaView .pvd series, and
// Wavefront OBJ surfaces. Every I/O error names the path.
#pragma once

#include "scene.h"

#include <stdio.h>

/// A time series being written to a folder: NAME.pvd plus NAME_000000.vtu (and .obj) per frame.
typedef struct cliSeries
{
	char directory[CLI_MAX_PATH];
	char name[256];
	char pvdPath[CLI_MAX_PATH];
	bool obj;
	FILE* pvd;
	int written;
} cliSeries;

/// Create @p directory (and parents) and start NAME.pvd in it.
bool cliSeries_Open(cliSeries* series, const char* directory, const char* name, bool obj);

/// Write frame @p frame at simulated time @p time (s) and add it to the collection.
bool cliSeries_WriteFrame(cliSeries* series, const cliSimulation* sim, int frame, double time);

/// Finish the .pvd so ParaView can open it. Safe to call on a series that failed to open.
bool cliSeries_Close(cliSeries* series);

/// Write every body of @p sim as one piece of a VTK unstructured grid (tets, VTK_TETRA = 10),
/// with point data "velocity" (m/s).
bool cliWriteVtu(const char* path, const cliSimulation* sim);

/// Write the outward surface of every body (one OBJ object per body).
bool cliWriteObj(const char* path, const cliSimulation* sim);
