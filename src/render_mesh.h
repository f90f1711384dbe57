// Render meshes (render_mesh.c): a high-resolution triangle surface embedded in a body's tets by
// barycentric coordinates, deformed with the body on request (fmBody_CopyRenderPositions).
#pragma once

#include "body.h"

// Release a body's render mesh (body->renderMesh); NULL is fine.
void fmRenderMesh_Free(struct fmRenderMesh* mesh);
