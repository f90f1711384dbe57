// A torn body's topology (fracture.h): the per-vertex arrays made again for new tet corners,
// and the check of a topology a snapshot brings.
#pragma once

#include <stdbool.h>

struct fmBody;
struct fmWorld;

// Give body @p b the corners @p tets (4 per tet, body order) over @p vertexCount vertices,
// each vertex i taking the state (position, velocity, pins) of vertex @p from[i] of the body as
// it is; masses are shared again by tet volume. false when out of memory (body unchanged).
bool fmTearTopology_Set(struct fmWorld* w, struct fmBody* b, const int* tets, int vertexCount,
                        const int* from);

// What is wrong with @p tets over @p vertexCount vertices as a torn topology of body @p b, or
// NULL: every corner a copy of the original corner, every vertex used, vertex i < the original
// count the original i and on a tet when it was; FM_TEAR_NO_MEMORY (this very string) when
// there was no memory to check.
const char* fmTearTopology_Problem(const struct fmBody* b, const int* tets, int vertexCount);

#define FM_TEAR_NO_MEMORY "no memory to check it"

// The highest vertex number of body @p b that something holds: its targets (a grab's too), its
// attachments, its prescribed displacements and follower pressure, other bodies' welds to it;
// -1 when none. A topology of fewer vertices would leave them past the end.
int fmTearTopology_HighestHeld(const struct fmWorld* w, const struct fmBody* b);
