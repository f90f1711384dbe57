// The order a body keeps its vertices and tets in (reorder.c): close in memory what is close in
// space, whatever order the mesh file had. TetGen numbers tets in creation order, scattered over
// the body; a generated box numbers vertices row by row. Every public call keeps the user's
// numbering (body.c translates); only the body's own arrays are reordered.
#pragma once

#include <stdbool.h>

// The internal order of a mesh of @p vertexCount vertices at @p positions (3 per vertex) and
// @p tetCount tets (4 vertex indices each): tetOrder[k] is the user's tet at internal place k
// (tets in Morton order of their centroids, ties in user order), vertexOrder[k] the user's
// vertex at internal place k (in the order those tets first use them; vertices no tet uses last,
// in user order). False when memory is short.
bool fmReorder_Compute(const double* positions, int vertexCount, const int* tets, int tetCount,
                       int* tetOrder, int* vertexOrder);
