// Render meshes (render_mesh.c): a high-resolution triangle surface embedded in a body's tets by
// barycentric coordinates, deformed with the body on request (fmBody_CopyRenderPositions).
#pragma once

#include "body/body.h"

// The tet (the body's own numbering) render vertex @p vertex is bound to, and its barycentric
// coordinates into @p w; -1 without a render mesh or for a vertex out of range. For tests.
int fmRenderMesh_Binding(const fmBody* body, int vertex, double w[4]);

// How far @p p lies outside rest tet @p tet (0 inside), as the binding measures it. For tests.
double fmRenderMesh_TetDistance(const fmBody* body, int tet, fmVec3 p);
