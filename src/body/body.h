// A soft body: rest shape (precomputed per tet), material, per-vertex state.
#pragma once

#include <femto/femto.h>

#include "world/energy_ledger.h"

#include <stdint.h>

typedef struct fmBody
{
	uint32_t generation; // of the body in the slot; UINT32_MAX retires the slot
	int vertexCount;
	int tetCount;
	int firstIndex; // numbering of the source mesh, for export

	// per-vertex state, packed xyz
	double* x;       // positions (m)
	double* v;       // velocities (m/s)
	double* f;       // force accumulator (N)
	double* x0;      // rest positions
	double* mass;    // kg
	double* invMass; // 1/kg, 0 for pinned vertices
	uint8_t* pinned; // axes held fixed: bit 0 x, 1 y, 2 z; FM_PIN_ALL = pinned vertex

	// per-tet rest data
	int* tets;          // 4 per tet, positively oriented
	fmMat3* DmInv;      // inverse reference edge matrix [X1-X0, X2-X0, X3-X0]^-1
	double* restVolume; // V0 (m^3), > 0

	// surface, for rendering and export
	int* surface;
	int triangleCount;

	// The user's numbering. The body keeps its vertices and tets in its own order (reorder.h:
	// close in memory what is close in space); every public call translates.
	int* userVertex;     // vertexCount: the user's index of each vertex
	int* internalVertex; // vertexCount: the body's index of each user vertex
	int* userTet;        // tetCount: the user's index of each tet
	int* userTets;       // 4 per tet: the (oriented) tets in the user's order and numbering
	int* userSurface;    // 3 per surface triangle, in the user's numbering
	double* userMass;    // vertexCount: masses in the user's numbering

	// Laplacian smoothing: 1 / (4 * number of tets around each vertex)
	double* smoothWeight;

	// The tets around each vertex, for gathers in tet order (a parallel step's scatter-free
	// sums): vertexTets[vertexTetStart[i] .. vertexTetStart[i + 1]) are 4 t + a, ascending,
	// for every tet t whose node a is vertex i.
	int* vertexTetStart; // vertexCount + 1
	int* vertexTets;     // 4 * tetCount

	// mass-spring force model (edges of the tets)
	int edgeCount;
	int* edges;         // 2 per edge
	double* restLength; // m
	double* springK;    // N/m

	// finite volume force model: 4 per tet, 1/3 of the area-weighted rest normals at each node
	fmVec3* fvmNormals;

	// last good state, restored on numerical failure
	double* xGood;
	double* vGood;
	double energyGood; // kinetic + elastic energy of the good state (runaway check)
	bool energyStale;  // energyGood must be recomputed (new body, new material)
	// What the body's last substep produced, merged into the world's statistics and errors in
	// body order after every body has stepped (world.c), so that no step writes shared state.
	fmResult stepResult;
	double stepResidual;     // implicit: relative residual reached
	int stepNewton;          // implicit: Newton iterations
	int stepCg;              // implicit: CG iterations
	bool stepConverged;      // implicit: reached the tolerance
	const char* stepStopped; // implicit, not converged: why it stopped
	double energyAfter;      // kinetic + elastic energy at the end of the frame being checked
	int invertedAfter;       // its inverted tets when the check's energy pass counted them, or -1
	double stepStage[2];     // s, the last substep's two stages (explicit: forces, then
	                         // integration; implicit: the solve, then velocities and floor)
	fmEnergyLedger ledger;   // work done on the body: the runaway bound (energy_ledger.h)

	fmMaterial material;
	// Per-region materials (fmBodyDef.regionMaterials): tet t has materials[tetMaterial[t]];
	// both NULL for a body of one material (then every tet has `material`).
	fmMaterial* materials; // materialCount: [0] is `material`, then the regions'
	int materialCount;
	uint16_t* tetMaterial; // tetCount, in the body's tet order
	fmForceModel forceModel;
	double damping;
	double smoothing;
	double rayleighMass;
	double rayleighStiffness;
	double springDamping;
	double friction;    // against other bodies, or -1 for the world's
	bool selfCollision; // surface against its own non-adjacent surface (contact_pair.c)
	// Sleeping (island.c)
	bool canSleep;      // fmBodyDef.enableSleep
	bool asleep;        // not stepped until woken
	bool wakeRequested; // touched while asleep: wakes with its island at the end of the frame
	double sleepTimer;  // s the body has been slower than the sleep speed
	int island;         // while asleep: the island's id (the slot of its first body)
	fmFilter filter;    // collision filtering
	double totalMass;
	double restSize;      // diagonal of the rest shape's bounding box (m)
	double explicitLimit; // estimated largest stable explicit step (s), see world.c

	// Kinematic targets (targets.h): vertices pulled toward caller-given positions.
	int targetCount;
	int targetCapacity;
	int* targetVertex;      // targetCount: the body's index of each pulled vertex
	double* targetPosition; // 3 per target (m)
	double targetStiffness; // N/m, each spring

	// Loads and prescribed displacements (loads.h), NULL until the first is added.
	struct fmLoadSet* loads;

	// Contact (contact.c), made when the contact stage first needs them.
	int surfaceVertexCount;
	int* surfaceVertex;      // the vertices on the surface, ascending
	double* contactStart;    // 3n: positions at the start of the substep (the swept tests)
	int* contactMark;        // n: 1 + the contact log entry of a vertex the stage changed, or 0
	double* contactPlane;    // 4n: an implicit step's frozen plane of another body near each
	                         // surface vertex (n, n . q), NaN where none (penalty.h)
	uint8_t* contactTetMark; // tetCount: scratch marks of the ledger's energy change
	int* embeddedHolder;     // n: 1 + the slot of the body whose tet held the vertex this frame
	                         // (its later substeps push it on), or 0
	// An implicit step's frozen planes of other bodies' surface edges near this body's surface
	// edges (penalty.h), made before the step like contactPlane
	struct fmEdgePlane* edgePlanes;
	int edgePlaneCount;
	int edgePlaneCapacity;
	// 8n: implicit friction against colliders, lagged one step (penalty.h): per vertex the
	// contact normal, the Coulomb limit mu lambda (N, 0: none) and the collider's surface velocity
	double* contactFriction;
	double* contactFrictionNext; // 8n: what the contact stage found this step, for the next one
	double contactThinness;      // 2 V / S at rest (m): how thick the body is (contact.c)
	// The floor's contacts of the last substep (floor.h), for the contact list and the floor's
	// reaction
	struct fmFloorHit* floorHits;
	int floorHitCount;
	int floorHitCapacity;
	struct fmDrawCache* drawCache;   // fmWorld_Draw's buffers (draw.h), made on the first draw
	struct fmRenderMesh* renderMesh; // fmBody_SetRenderMesh's embedded surface, or NULL
	void* implicitCache; // solver buffers (solver_cache.h: fmSolverCache_Get, fmSolverCache_Free)
	struct fmTetBlocks* tetBlocks; // the explicit kernels' layout (tet_blocks.h), made at need
	size_t memoryEstimate;         // fmEstimateBodyMemory() at creation, counted against the budget
} fmBody;

// body->pinned value of a vertex held on every axis (fmBody_SetPinned); other non-zero values
// are rollers (fmBody_SetPinnedAxes), free along the axes whose bit is clear.
#define FM_PIN_ALL 7u
// The pin bit of the y axis (the floor's normal).
#define FM_PIN_Y 2u

// Whether degree of freedom @p dof (3 * vertex + axis) is pinned.
static inline bool fmIsDofPinned(const fmBody* body, int dof)
{
	return (body->pinned[dof / 3] >> (dof % 3)) & 1u;
}

// Zero the components of a velocity (3 doubles) along the axes the vertex is pinned on.
static inline void fmZeroPinnedAxes(const fmBody* body, int vertex, double* v)
{
	unsigned pins = body->pinned[vertex];
	for (int k = 0; pins != 0u && k < 3; ++k)
		if ((pins >> k) & 1u)
			v[k] = 0.0;
}

// The material of tet @p t.
static inline const fmMaterial* fmTetMaterial(const fmBody* body, int t)
{
	return body->tetMaterial != NULL ? &body->materials[body->tetMaterial[t]] : &body->material;
}

// Whether every tet's material is the linear model (a quadratic elastic energy).
static inline bool fmBodyIsLinear(const fmBody* body)
{
	for (int k = 0; k < body->materialCount; ++k)
		if (body->materials[k].model != fm_linear)
			return false;
	return body->material.model == fm_linear;
}

// Resolve an id; NULL if stale.
fmBody* fmGetBody(fmBodyId id);

// Free every array of a body (keeps its generation); safe on a partly built body.
void fmBodyRelease(fmBody* body);

// Tets with det F <= 0 at the current positions.
int fmBodyCountInverted(const fmBody* body);

// The same on the workers of @p tasks, with a byte a tet from @p arena (serially when the body
// is small, there is no room, or @p tasks is NULL): an exact count whatever the split.
int fmBodyCountInvertedOn(const fmBody* body, const struct fmTaskSystem* tasks,
                          struct fmArena* arena);
