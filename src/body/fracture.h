// Fracture of a body along its tet faces (docs/materials.md, "Fracture").
//
// Rules: the tets and their order never change, so every per-tet array (rest data, plastic
// state, fibres, materials, render-mesh bindings) stays valid through a tear; a tear only
// renumbers the corners of tets. Vertex i < the original count is always the original vertex
// i (or the copy of it that kept its number); copies are appended. The topology is a function
// of the broken faces around each vertex: a vertex is one per group of its tets that hold
// together across unbroken faces through it (Parker and O'Brien 2009's splitting of a node by
// the elements around it, on element faces only). A copy's mass is its original's times its
// tets' share of the original's tet volume: mass and momentum are conserved.
#pragma once

#include <femto/types.h>

#include <stdbool.h>
#include <stdint.h>

struct fmBody;
struct fmWorld;

typedef struct fmCracks
{
	int originalVertexCount; // vertices before any tear
	double* originalMass;    // originalVertexCount: kg, what each original and its copies share
	int* originalTets;       // 4 per tet: the tets before any tear (the body's numbering)
	int* origin;             // vertexCount: the original vertex each vertex copies
	int* neighbour;          // 4 per tet: across face k of tet t (opposite node k), 4 t' + k'; -1
	uint8_t* broken;         // 4 per tet: 1 where face k of tet t is broken (both sides marked)
	int* nearStart;          // tetCount + 1: the tets averaged into tet t's stress are
	int* near;               // near[nearStart[t] .. nearStart[t + 1]) (itself included)
	int* piece;              // tetCount: the piece of each tet (0 .. pieceCount - 1, body order)
	double* frame;           // 16 per tet: a frame's criterion (stresses, averages, face ratios)
	int pieceCount;
	int brokenCount;  // faces broken (each shared face once)
	double minVolume; // m^3, the smallest piece a tear may cut off
} fmCracks;

// Whether a material tears (fracture.strength > 0).
static inline bool fmFracture_Tears(const fmMaterial* m)
{
	return m->fracture.strength > 0.0;
}

// Give body @p b its crack state when one of its materials tears and it has none (the faces'
// neighbours and the stress averages' tets, from the rest shape). fm_errLimit when a fracture
// length takes more than FM_TEAR_MAX_NEAR tets into an average; out of memory.
fmResult fmFracture_Prepare(struct fmBody* b, fmDiagnostic* diag);

// Free body @p b's crack state.
void fmFracture_Free(struct fmBody* b);

// Each tet's largest traction over strength on its unbroken shared faces at the current
// positions (@p tetDamage: tetCount, the body's order, or NULL); returns the largest (0 when
// the body cannot break). @p faceRatio (4 per tet, or NULL) gets each face's; @p faceRatio may
// be the crack state's `frame + 12 tetCount` (the rest of `frame` is the call's scratch).
double fmFracture_Damage(const struct fmBody* b, double* tetDamage, double* faceRatio);

// Break every face of body @p b the criterion holds on (none that would cut off a piece below
// the minimum volume) and split the vertices that no longer hold together. Returns the faces
// broken, or -1 when out of memory (@p diag says so; the body is unchanged). A frame that breaks
// nothing allocates nothing (the crack state's buffers).
int fmFracture_Tear(struct fmWorld* w, struct fmBody* b, fmDiagnostic* diag);

// After a frame every stepping body's checks passed: each torn-capable body tears
// (serially, in body order: deterministic for any worker count). A tear without memory leaves
// its body whole for the frame and says so in a warning.
void fmFracture_EndFrame(struct fmWorld* w);

// The broken faces of body @p b as marked (both sides), and the pieces from them again
// (@p parent: tetCount ints of scratch).
void fmFracture_SetBroken(struct fmBody* b, const uint8_t* broken, int* parent);

// Whether a self-contact pair of body @p b, vertices @p v[0 .. split) against v[split .. count),
// joins two different pieces without a copy of one vertex on both sides: such a pair counts
// whatever its distance at rest (the pieces were one there); a pair of copies of one vertex
// starts at distance 0 and is never tested, the crack's other pairs start apart.
bool fmFracture_AcrossPieces(const struct fmBody* b, const int* v, int split, int count);

// Whether vertices @p u and @p v of body @p b are copies of one vertex (or are one vertex).
static inline bool fmFracture_Siblings(const struct fmCracks* c, int u, int v)
{
	return u == v || (c != NULL && c->origin[u] == c->origin[v]);
}

// Whether body @p b's contact pairs its own surface: self-collision asked for
// (fmBodyDef.selfCollision), or pieces (a tear's, or a mesh of several parts) that meet each
// other whatever the body asked.
bool fmFracture_MeetsItself(const struct fmBody* b);
