// A soft body: rest shape (precomputed per tet), material, per-vertex state.
#pragma once

#include <femto/femto.h>

#include "contact/contact_body.h"
#include "core/attachment.h"
#include "fem/elastic_mesh.h"
#include "world/energy_ledger.h"

#include <stdint.h>

typedef struct fmBody
{
	uint32_t generation; // of the body in the slot; UINT32_MAX retires the slot
	int slot;            // its slot in the world's body table
	int firstIndex;      // numbering of the source mesh, for export

	fmElasticMesh mesh; // rest shape, materials, force model data: const to the stages
	fmBodyState state;  // positions, velocities, forces, pins

	// The user's numbering. The body keeps its vertices and tets in its own order (reorder.h:
	// close in memory what is close in space); every public call translates.
	int* userVertex;     // vertexCount: the user's index of each vertex
	int* internalVertex; // vertexCount: the body's index of each user vertex
	int* userTet;        // tetCount: the user's index of each tet
	int* userTets;       // 4 per tet: the (oriented) tets in the user's order and numbering
	int* userSurface;    // 3 per surface triangle, in the user's numbering
	double* userMass;    // vertexCount: masses in the user's numbering

	// last good state, restored on numerical failure
	double* xGood;
	double* vGood;
	double energyGood; // kinetic + elastic energy of the good state (runaway check)
	bool energyStale;  // energyGood must be recomputed (new body, new material)
	bool positionsSet; // fmBody_SetPositions since the last frame: audited against the others
	// Positions (the body's order) at the start of the last frame fmWorld_Advance stepped, for
	// the interpolated copies (world/step.c); NULL before the first advance. Not valid
	// after the caller moved the vertices (set positions, a restored snapshot, a static solve).
	double* previousX;
	bool previousValid;
	// The box of its vertices as audit.c found it while the world's verticesEpoch was boxEpoch
	// (0: never; the world's epoch starts at 1).
	fmVec3 boxLower, boxUpper;
	uint64_t boxEpoch;
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
	double plasticWork;      // J, the plastic work of the flow since creation (plasticity.h)
	double plasticWorkGood;  // the same at the start of the frame being stepped
	bool plasticKept;        // the frame being stepped kept the plastic state to go back to

	double damping;
	double smoothing;
	double rayleighMass;
	double rayleighStiffness;
	double friction;    // against other bodies, or -1 for the world's
	bool selfCollision; // surface against its own non-adjacent surface (contact_pair.c)
	// Sleeping (island.c)
	bool canSleep;        // fmBodyDef.enableSleep
	bool asleep;          // not stepped until woken
	bool wakeRequested;   // touched while asleep: wakes with its island at the end of the frame
	double sleepTimer;    // s the body has been slower than the sleep speed
	int island;           // while asleep: the island's id (the slot of its first body)
	fmFilter filter;      // collision filtering
	double explicitLimit; // estimated largest stable explicit step (s), see world.c

	// Kinematic targets (targets.h): vertices pulled toward caller-given positions, set by the
	// caller or by a grab (grab.h, NULL when none) that owns them while it lasts.
	int targetCount;
	int targetCapacity;
	struct fmTarget* targets;
	struct fmGrab* grab;
	// Attachments (anchors.h): glue to colliders and weld ends, each with its spring, a target
	// placed every substep (anchorTargets, after the targets above in every sum).
	int anchorCount;
	int anchorCapacity;
	struct fmAnchor* anchors;
	struct fmTarget* anchorTargets;
	// Welded, implicit: the body's momentum when its anchors were placed, and its acceleration
	// over the last substep from everything but its welds (anchors.c).
	fmVec3 weldMomentum, weldAcceleration;
	// Let go of a grab and still stretched or moving: the stiffening proxy (stability.h) at the
	// grab, which the body must relax to, and the kinetic energy it must settle below (J), before
	// an explicit world gives up adaptive substeps; 0 when none (grab.h).
	double grabRelaxProxy, grabRelaxKinetic;

	// Loads and prescribed displacements (loads.h), NULL until the first is added.
	struct fmLoadSet* loads;
	// Fracture (fracture.h): the broken faces and what the tears were made from; NULL while no
	// material of the body tears.
	struct fmCracks* cracks;
	bool massPerParticle; // fmBodyDef.massMode was fm_massPerParticle (a tear shares by tets)

	// Each stage's scratch, typed, made and freed by the stage
	fmBodyContact contact;               // the contact stage's (contact_body.h)
	struct fmImplicitCache* solverCache; // the implicit solve's (solver_cache.h), or NULL
	fmAttachment drawCache;              // fmWorld_Draw's buffers (draw.c's fmDrawCache), or none
	fmAttachment renderMesh; // fmBody_SetRenderMesh's embedded surface (render_mesh.h), or none
	size_t memoryEstimate;   // fmEstimateBodyMemory() at creation, counted against the budget
} fmBody;

// Whether a body slot holds a live body (a retired or never used slot does not).
static inline bool fmBody_IsLive(const fmBody* body)
{
	return body->state.x != NULL;
}

// Resolve an id; NULL if stale.
fmBody* fmGetBody(fmBodyId id);

// Free every array of a body (keeps its generation); safe on a partly built body.
void fmBodyRelease(fmBody* body);

// Tets with det F <= 0 at the current positions.
int fmBodyCountInverted(const fmBody* body);

// The body's kinetic energy (J), summed vertex by vertex in order.
double fmBodyKineticEnergy(const fmBody* body);

// Tets with det F <= 0 at positions @p x (3 per vertex, the body's order).
int fmBodyCountInvertedAt(const fmBody* body, const double* x);

// The same on the workers of @p tasks, with a byte a tet from @p arena (serially when the body
// is small, there is no room, or @p tasks is NULL): an exact count whatever the split.
int fmBodyCountInvertedOn(const fmBody* body, const struct fmTaskSystem* tasks,
                          struct fmArena* arena);
