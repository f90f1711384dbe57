// The world: bodies, gravity, floor, integrator settings, step statistics.
#pragma once

#include "body/body.h"
#include "contact/collider.h"
#include "core/arena.h"
#include "core/parallel.h"
#include "core/step_context.h"
#include "fem/stability.h"
#include "solver/newton.h"
#include "world/schedule.h"

#include <stdatomic.h>

// Floats fmWorld_Draw keeps a contact in fmWorld.drawPoints: its point (3), then its line's two
// ends (6).
#define FM_DRAW_CONTACT_FLOATS 9

// The largest bodies a world's arenas hold a step's buffers for (vertices, tets; small: the
// largest body that steps beside others, below FM_BODY_PARALLEL_MAX_VERTICES).
typedef struct fmArenaSizes
{
	size_t vertices, tets, small;
} fmArenaSizes;

typedef struct fmWorld
{
	uint32_t generation; // of the world in the slot; UINT32_MAX retires the slot
	bool inUse;
	fmWorldDef def;
	int bodyCapacity;
	fmBody* bodies;         // bodyCapacity slots (fmBody_IsLive)
	fmFrameWork* frameWork; // bodyCapacity: the work the stages booked in the frame being stepped
	// 1 inside fmWorld_Step: a second step (another thread's, or from the substep callback) is
	// refused by the atomic exchange that sets it, before it touches anything.
	atomic_int stepping;
	bool advancing; // fmWorld_Advance is stepping: its frames keep the bodies' previous positions
	fmStepStats stats;
	fmProfile profile; // the last step's stage times (ms)
	fmDiagnostic lastError;
	bool warnedStep; // the explicit step-size warning was given
	// The frame's fastest kinematic collider for its size, when one moves more than its
	// thickness in a substep near a body (-1: none): the warning and the failure advice name it.
	int fastCollider;
	double fastSweep, fastThickness; // m in a substep, m
	int fastSubsteps;                // substeps a frame that would keep it within its thickness
	double budgetNeed; // substeps the frame's stability limit asked for beyond the budget (0: none)
	fmSolverOptions solverOptions; // implicit and static solves (measurements; defaults measured)
	fmArena arena;                 // step temporaries, reserved for the largest body
	// Workers 1 to workerCount - 1's step temporaries while bodies step at once (worker 0 takes
	// arena), reserved for the largest body stepped that way (FM_BODY_PARALLEL_MAX_VERTICES).
	fmArena* workerArenas;
	fmSchedule schedule; // the substep's groups of bodies (schedule.h)
	fmTaskSystem tasks;  // how the stages run in parallel
	fmSimdLevel simd;    // the element kernels' instruction set: def.simd resolved on this CPU
	struct fmCollider* colliders; // colliderCapacity slots (collider.h)
	fmCollider floorCollider;     // def.floor as a plane collider: its id, reports and queries
	int colliderCapacity;         // grows by doubling up to FM_MAX_COLLIDERS
	struct fmContactState* contactState; // the contact stage's buffers (contact_state.h)
	// Moving meshes' frame stages, set when one is first moved (mesh_motion.h); NULL before.
	const struct fmMeshMotionStages* meshMotion;
	// Attachments' substep stages, set when the first is made (anchors.h); NULL before.
	const struct fmAnchorStages* anchorStages;
	double contactStep;  // s, the substep the contact stage is working on
	bool embeddedSearch; // the frame's first body-body detection looks for embedded vertices
	// Barrier worlds look for them only where something outside the solve can have put a vertex
	// inside another body (fmContact_BeginFrame): embeddedDue (a new world, another
	// integrator), positions that differ from the last frame's end (positionsPrint, its
	// fingerprint), a known overlap, moving prescribed displacements, a collider's push.
	bool embeddedDue;
	uint64_t positionsPrint;
	// Within fmWorld_Step (stepKnown): what no stage of a step changes and every body's step
	// asks, each an O(bodies) loop (fmContact_Thickness, fmContact_BodiesMeet).
	bool stepKnown;
	double stepThickness;
	bool stepBodiesMeet;
	// Moved on by every call that may move a body's vertices (fmWorld_MovedVertices): a body's
	// box that audit.c cached under the same value still holds (creating a thousand props audits
	// each against the boxes of those before it, not their vertices).
	uint64_t verticesEpoch;
	fmArenaSizes reserved; // the bodies the arenas were last reserved for
	size_t bodyMemory;     // the live bodies' memoryEstimate, summed (the memory budget's)
	int freeSlotHint;      // no body slot below it is free
	float* drawPoints;     // fmWorld_Draw's buffer: a contact's point, then its line
	                       // (FM_DRAW_CONTACT_FLOATS)
	int drawPointCapacity;
	fmAttachment drawShape;    // fmWorld_Draw's collider triangles (draw_shapes.h's fmShapeBuffer)
	fmSleepEvent* sleepEvents; // since the start of the last step (island.c)
	int* islandParent;         // island.c's union-find (bodyCapacity), made at need
	double* islandLeast;       // per island root: its bodies' least sleep timer
	int islandCapacity;
	int sleepEventCount;
	int sleepEventCapacity;
} fmWorld;

// The id of a live world.
fmWorldId fmWorldIdOf(const fmWorld* world);

// The floor's collider slot: outside the colliders table, so that its id (index1
// FM_FLOOR_SLOT + 1) is never a created collider's.
#define FM_FLOOR_SLOT FM_MAX_COLLIDERS

// The public ids of body slot @p slot and collider slot @p slot (FM_FLOOR_SLOT: the floor's) of
// a live world.
fmBodyId fmWorldBodyId(const fmWorld* world, int slot);
fmColliderId fmWorldColliderId(const fmWorld* world, int slot);

// The collider in slot @p slot (FM_FLOOR_SLOT: the floor's), live or not.
fmCollider* fmWorldCollider(fmWorld* world, int slot);

// A body's vertices may have moved: every box cached under the old epoch is stale.
static inline void fmWorld_MovedVertices(fmWorld* world)
{
	world->verticesEpoch += 1;
}

// Set the floor's collider from def.floor (at creation and by fmWorld_SetFloor), keeping the
// force it reports.
void fmWorldSyncFloor(fmWorld* world);

// Resolve ids; NULL if null or stale (a body id must match its world's slot and generation).
fmWorld* fmGetWorld(fmWorldId id);
// fmGetWorld for a public call, which asserts (FM_ASSERT) that the id is live.
fmWorld* fmWorldOrAssert(fmWorldId id);
fmWorld* fmGetWorldOfBody(fmBodyId id);

// Bytes of a world's body table (counted against fmWorldDef.memoryBudget).
size_t fmWorldTableBytes(int maxBodies);

// What a world holds against fmWorldDef.memoryBudget: its body table, its live bodies'
// estimates (fmEstimateBodyMemory), its collider table and its mesh colliders' shapes.
size_t fmWorldMemoryInUse(const fmWorld* world);

// Bodies of fewer vertices than this step on one worker each, several at once (their own loops
// would not split: FM_PARALLEL_MIN_VERTICES); larger ones one after another, each on all.
#define FM_BODY_PARALLEL_MAX_VERTICES FM_PARALLEL_MIN_VERTICES

// Reserve the world's arena for its largest body (the buffers a step takes at once), and the
// workers' arenas for the largest body that steps beside others; false when memory is short.
// Allocates only when a larger body arrived.
bool fmWorldReserveArena(fmWorld* world);

// fmWorldReserveArena for the bodies the last reservation covered and body @p body (a new one):
// no pass over the bodies (arenas never shrink, so what a destroyed body left is kept anyway).
bool fmWorldReserveArenaFor(fmWorld* world, const fmBody* body);

// The smallest explicit stability limit (s) of the world's live bodies at their current
// deformation (each body's explicitLimit updated), INFINITY without bodies.
double fmWorldExplicitLimit(fmWorld* world);

// The explicit stability limit (s) of @p body at its current deformation, from the world's arena
// (reserved for it).
double fmWorldBodyStepLimit(fmWorld* world, const fmBody* body);
