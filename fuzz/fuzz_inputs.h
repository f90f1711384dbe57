// What the fuzzers do with one input, shared with the CTest suite that replays the committed
// corpus and every crash ever found (tests/test_fuzz_regressions.c).
#pragma once

#include <stddef.h>
#include <stdint.h>

// TetGen .node/.ele: "<node text>\n%%\n<ele text>", or one text tried as either file. Loads,
// orients, extracts the surface, takes statistics and simulates a step of small meshes.
void fmFuzzTetGen(const uint8_t* data, size_t size);

// TetGen .face with 0- and 1-based numbering against 100 nodes.
void fmFuzzFace(const uint8_t* data, size_t size);

// Wavefront OBJ: loads the surface, checks every triangle names a vertex, places it and, for
// small surfaces, makes it a mesh collider under a falling box for one step.
void fmFuzzObj(const uint8_t* data, size_t size);

// The other mesh formats (fmLoadMeshFromMemory): Gmsh .msh, VTK legacy .vtk, VTK XML .vtu, Medit
// .mesh. A mesh that loads is measured, its surface extracted and (when small) simulated.
void fmFuzzGmsh(const uint8_t* data, size_t size);
void fmFuzzVtk(const uint8_t* data, size_t size);
void fmFuzzVtu(const uint8_t* data, size_t size);
void fmFuzzMedit(const uint8_t* data, size_t size);
