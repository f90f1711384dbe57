// The elastic mesh and the state of a body: what the force and solver code work on.
//
// A body (body/body.h) is three parts, after Box2D's body, sim and state: this elastic mesh
// (the rest shape precomputed per tet, the materials, the force model's data), which the
// force, solver and kernel code take as const; the state (positions, velocities, pins), which
// the stages change; and what the world keeps about the body (user numbering, the last good
// state, sleep, targets, loads, each stage's scratch). No file under fem/ or solver/ sees a
// whole body. The body's own code (body/) builds the mesh and changes it only between steps
// (a new material, new masses).
#pragma once

#include <femto/femto.h>

#include <stdint.h>

struct fmTetBlocks;

typedef struct fmElasticMesh
{
	int vertexCount;
	int tetCount;

	// per-tet rest data
	int* tets;          // 4 per tet, positively oriented
	fmMat3* DmInv;      // inverse reference edge matrix [X1-X0, X2-X0, X3-X0]^-1
	double* restVolume; // V0 (m^3), > 0

	// per-vertex rest data
	double* x0;   // rest positions (m), packed xyz
	double* mass; // kg

	// surface triangles (3 per triangle, the body's numbering), for contact, drawing, export
	int* surface;
	int triangleCount;

	// Laplacian smoothing: 1 / (4 * number of tets around each vertex)
	double* smoothWeight;

	// The tets around each vertex, for gathers in tet order (a parallel step's scatter-free
	// sums): vertexTets[vertexTetStart[i] .. vertexTetStart[i + 1]) are 4 t + a, ascending,
	// for every tet t whose node a is vertex i.
	int* vertexTetStart; // vertexCount + 1
	int* vertexTets;     // 4 * tetCount

	// mass-spring force model (edges of the tets)
	int edgeCount;
	int* edges;           // 2 per edge
	double* restLength;   // m
	double* springK;      // N/m
	double springDamping; // N s/m, each spring's dashpot

	// finite volume force model: 4 per tet, 1/3 of the area-weighted rest normals at each node
	fmVec3* fvmNormals;

	fmMaterial material;
	// Per-region materials (fmBodyDef.regionMaterials): tet t has materials[tetMaterial[t]];
	// both NULL for a body of one material (then every tet has `material`).
	fmMaterial* materials; // materialCount: [0] is `material`, then the regions'
	int materialCount;
	uint16_t* tetMaterial; // tetCount, in the body's tet order
	// Per-tet fibres (fmBodyDef.tetFibres, the body's tet order), the first axis of an
	// anisotropic tet's material; NULL: each material's own fibre.
	fmVec3* fibres;
	// Per-tet equivalent plastic strain (body/plasticity.h), NULL while no material flows; a
	// flowing tet's plastic part is in its DmInv.
	double* plasticStrain;
	fmMat3* restDmInv;  // with plasticStrain: DmInv before any flow (a restored elastic state's)
	fmMat3* goodDmInv;  // with plasticStrain: DmInv at the start of the frame being stepped
	double* goodStrain; // and the plastic strains (a refused frame goes back to them)
	// The averaged nodal pressure (fem/nodal_pressure.h), NULL while no material has
	// nodalPressure: each material as its tets evaluate it (a nodal one without its volume
	// term; index as `materials`, [0] alone for a body of one material), and per vertex the rest
	// volume and the bulk-weighted rest volume of its patch (a quarter of each such tet around it).
	fmMaterial* tetParts;
	double* patchVolume; // m^3, 0 for a vertex without a nodal tet
	double* patchBulk;   // Pa m^3: sum of V_e kappa_e / 4
	int nodalLaw;        // fmNodalLaw (nodal_pressure.h) of the nodal materials
	// A step's scratch, made with the patches (no allocation per step): the patches' pressures
	// and curvatures (vertexCount each), and one patch's vertices and gradients (patchMost).
	double* nodalPressure;
	double* nodalCurvature;
	int* patchVertices;
	fmVec3* patchGrads;
	int patchMost;
	fmForceModel forceModel;

	double totalMass; // kg
	double restSize;  // diagonal of the rest shape's bounding box (m)

	// The explicit kernels' layout of the tets (tet_blocks.h), made when first needed and
	// destroyed by the mesh's owner (fmTetBlocks_Destroy), not by fmElasticMesh_Free
	struct fmTetBlocks* tetBlocks;
} fmElasticMesh;

// What the stages change: positions, velocities, forces and pins, packed xyz per vertex.
typedef struct fmBodyState
{
	double* x;       // positions (m)
	double* v;       // velocities (m/s)
	double* f;       // force accumulator (N)
	double* invMass; // 1/kg, 0 for pinned vertices
	uint8_t* pinned; // axes held fixed: bit 0 x, 1 y, 2 z; FM_PIN_ALL = pinned vertex
} fmBodyState;

// state.pinned value of a vertex held on every axis (fmBody_SetPinned); other non-zero values
// are rollers (fmBody_SetPinnedAxes), free along the axes whose bit is clear.
#define FM_PIN_ALL 7u
// The pin bit of the y axis (the floor's normal).
#define FM_PIN_Y 2u

// Whether degree of freedom @p dof (3 * vertex + axis) is pinned.
static inline bool fmIsDofPinned(const fmBodyState* state, int dof)
{
	return (state->pinned[dof / 3] >> (dof % 3)) & 1u;
}

// Zero the components of a velocity (3 doubles) along the axes the vertex is pinned on.
static inline void fmZeroPinnedAxes(const fmBodyState* state, int vertex, double* v)
{
	unsigned pins = state->pinned[vertex];
	for (int k = 0; pins != 0u && k < 3; ++k)
		if ((pins >> k) & 1u)
			v[k] = 0.0;
}

// The material of tet @p t as given (fmBodyDef, fmBody_SetMaterial).
static inline const fmMaterial* fmTetUserMaterial(const fmElasticMesh* mesh, int t)
{
	return mesh->tetMaterial != NULL ? &mesh->materials[mesh->tetMaterial[t]] : &mesh->material;
}

// The material tet @p t's energy evaluates: the user's, less its volume term where that lives on
// vertex patches (fmMaterial.nodalPressure).
static inline const fmMaterial* fmTetMaterial(const fmElasticMesh* mesh, int t)
{
	if (mesh->tetParts != NULL)
		return &mesh->tetParts[mesh->tetMaterial != NULL ? mesh->tetMaterial[t] : 0];
	return fmTetUserMaterial(mesh, t);
}

// psi of tet @p t's material at @p F, with P and dP/dF when not NULL (@p project: dP/dF positive
// semi-definite, for the Newton matrix); an anisotropic tet reads its own fibre when the mesh has
// them.
double fmTetEvaluate(const fmElasticMesh* mesh, int t, const fmMat3* F, fmMat3* P, double* dPdF,
                     bool project);

// Deformation gradient of tet t at positions x: F = Ds Dm^-1.
fmMat3 fmTetDeformation(const fmElasticMesh* mesh, const double* x, int t);

// Whether every tet's material is the linear model (a quadratic elastic energy).
bool fmElasticMesh_IsLinear(const fmElasticMesh* mesh);

// Allocate a mesh's per-vertex and per-tet arrays for @p vertexCount vertices and @p tetCount
// tets (zeroed; the surface, springs, normals and regions are made later); false when out of
// memory (then fmElasticMesh_Free cleans up).
bool fmElasticMesh_Allocate(fmElasticMesh* mesh, int vertexCount, int tetCount);

// Free every array of a mesh (the tet blocks are their maker's); safe on a partly built one.
void fmElasticMesh_Free(fmElasticMesh* mesh);

// Allocate a state's arrays for @p vertexCount vertices (zeroed); false when out of memory.
bool fmBodyState_Allocate(fmBodyState* state, int vertexCount);

// Free a state's arrays (for @p vertexCount vertices); safe on a partly built one.
void fmBodyState_Free(fmBodyState* state, int vertexCount);
