/// @file femto.h
/// femto: real-time finite-element soft bodies. The whole public API.
///
/// @code
/// fmTetMesh mesh;
/// fmLoadTetGen("house2.node", "house2.ele", &mesh, NULL);
/// fmWorldId world = fmCreateWorld(&(fmWorldDef){...fmDefaultWorldDef()});
/// fmBodyDef bodyDef = fmDefaultBodyDef();
/// bodyDef.mesh = &mesh;
/// fmBodyId body;
/// fmCreateBody(world, &bodyDef, &body, NULL);
/// fmWorld_Step(world, 1.0 / 60.0, 10);
/// @endcode
#pragma once

#include "base.h"
#include "fm_math.h"
#include "mesh.h"
#include "types.h"

FM_C_BEGIN

/// Largest absolute node coordinate a body accepts (m); beyond it energies and stiffnesses
/// overflow long before anything is simulated.
#define FM_MAX_COORDINATE 1e9

// Argument checks: a call with a stale or null id, a NULL pointer it needs, a vertex index out
// of range or a non-finite vector is a programmer error. It goes to the assert hook
// (fmSetAssertFcn, in builds with FM_ASSERT) and, whatever the hook returns, the call does
// nothing and returns a safe value: 0, NULL, false, an empty struct or fm_errInvalidId /
// fm_errParameter. Bad data in a def (fmWorldDef_Validate, fmBodyDef_Validate) is not a
// programmer error: it gets a result code and a diagnostic, never an assert.

/// Create a world. Returns a null id (index1 == 0) if the def is invalid or memory is short,
/// or when all 128 world slots are in use.
FM_API fmWorldId fmCreateWorld(const fmWorldDef* def);

/// Check a world def; the diagnostic says which field is wrong and what would work.
FM_API fmResult fmWorldDef_Validate(const fmWorldDef* def, fmDiagnostic* diag);

/// Destroy a world and all its bodies.
FM_API void fmDestroyWorld(fmWorldId worldId);

/// True if the id refers to a live world.
FM_API bool fmWorld_IsValid(fmWorldId worldId);

/// Advance by @p timeStep seconds (a frame), split into @p subStepCount equal steps
/// (1 to FM_MAX_SUBSTEPS, each of FM_MIN_SUBSTEP to FM_MAX_SUBSTEP seconds, else
/// fm_errParameter and nothing moves).
/// On numerical failure (NaN, Inf, or energy beyond the body's ledger: initial energy plus the
/// work done on it) every body goes back to its last good state (the end of the last frame that
/// passed the checks: what the caller set since is dropped too), the step returns
/// fm_errNumerical and fmWorld_GetLastError() says which body, vertices and tets. An implicit
/// step that ends above the tolerance is a warning in the last error's warning fields, counted
/// in fmStepStats.unconvergedSteps, or fm_errNotConverged with fmWorldDef.notConvergedIsError.
/// Runs in femto's floating-point state (round to nearest, no flush-to-zero or
/// denormals-are-zero), as every call that computes, and gives the caller's back
/// (docs/determinism.md). A world steps on one thread at a time: a call while it is stepping
/// (from another thread, or from its substep callback) returns fm_errBusy and changes nothing,
/// its last error included.
FM_API fmResult fmWorld_Step(fmWorldId worldId, double timeStep, int subStepCount);

/// The game loop's step (fmFixedStep): adds @p elapsed seconds of real time to the clock and
/// steps the world as many whole frames of clock->frameTime (in clock->substeps substeps) as the
/// accumulated time holds, at most clock->maxFrames (the rest of the time is dropped); then
/// clock->alpha is the part of a frame left over. Before each frame it keeps every body's
/// positions, for fmBody_CopyInterpolatedPositionsFloat and
/// fmBody_CopyInterpolatedRenderPositionsFloat (3 doubles a vertex, once per body).
/// @p framesStepped (may be NULL) gets the frames stepped. fm_errParameter (the last error says
/// why; nothing stepped) for a clock not from fmDefaultFixedStep(), a member out of its range,
/// or @p elapsed negative, not finite or above 1e6 s; fm_errBusy while the world is in a step;
/// fm_errOutOfMemory when the positions cannot be kept; a failed fmWorld_Step's result (that
/// frame's time is spent: the clock does not retry it).
FM_API fmResult fmWorld_Advance(fmWorldId worldId, fmFixedStep* clock, double elapsed,
                                int* framesStepped);

/// The diagnostic of the last failed step (for a stale id: one that says so, never NULL).
FM_API const fmDiagnostic* fmWorld_GetLastError(fmWorldId worldId);

/// Counters of the last step.
FM_API fmStepStats fmWorld_GetStepStats(fmWorldId worldId);

/// Wall-clock time of the last step's stages (fmProfile).
FM_API fmProfile fmWorld_GetProfile(fmWorldId worldId);

/// Draw the world through @p draw's callbacks: the surfaces, tets, pins, targets, floor and
/// contacts that draw->flags asks for, body by body (docs/viewer.md). The library keeps no
/// graphics state and calls no graphics API: the arrays are built in buffers the world keeps
/// (allocated on the first draw of a body, reused after). fm_errInvalidId for a stale world,
/// fm_errOutOfMemory when a buffer cannot be had (nothing more is drawn).
FM_API fmResult fmWorld_Draw(fmWorldId worldId, const fmDebugDraw* draw);

/// The equivalent strain sqrt(2 psi / E) that fm_drawStress colours red (0 is blue).
#define FM_DRAW_FULL_STRAIN 0.2

/// The colour fm_drawStress gives an equivalent strain @p strain (RGB in [0, 1] into @p rgb):
/// blue at 0 through cyan, green and yellow to red at FM_DRAW_FULL_STRAIN and beyond, for a
/// legend beside the picture.
FM_API void fmDraw_StrainColor(double strain, float rgb[3]);

/// Change gravity (m/s^2), validated as in fmWorldDef_Validate: on fm_errParameter gravity is
/// unchanged and fmWorld_GetLastError() says why.
FM_API fmResult fmWorld_SetGravity(fmWorldId worldId, fmVec3 gravity);

/// Change the floor, validated by fmFloorDef_Validate: on fm_errParameter the floor is
/// unchanged and fmWorld_GetLastError() says why.
FM_API fmResult fmWorld_SetFloor(fmWorldId worldId, const fmFloorDef* floor);

/// Switch the integrator between frames (e.g. a game going from a cutscene to gameplay).
/// Positions and velocities carry over; the implicit solver's caches are rebuilt as needed.
FM_API void fmWorld_SetIntegrator(fmWorldId worldId, fmIntegrator integrator);

/// Estimated largest stable explicit step (s) for the bodies in the world at their current
/// deformation: 0.9 * 2 / omega_max, with omega_max bounded by Gershgorin's theorem on M^-1 K(x),
/// K(x) the true tangent stiffness of every model (stiffening under compression included).
/// Costs one tangent-stiffness pass (about a microsecond per tet). Returns 0 for an empty world.
FM_API double fmWorld_EstimateExplicitStep(fmWorldId worldId);

/// Bytes fmWorld_SaveSnapshot() writes for the world as it is now. It changes when bodies or
/// colliders are created or destroyed, when an implicit step first builds a body's solver
/// matrix, and from step to step with the contacts (the pairs that touched in the last frame and
/// the vertices with implicit collider friction are saved as lists): ask before each save, or
/// keep a buffer with room to spare.
FM_API size_t fmWorld_GetSnapshotSize(fmWorldId worldId);

/// Save the world's complete simulation state into @p buffer (@p size bytes): every body's
/// state, last good state, pins, material, energy ledger and the implicit solver's kept matrix,
/// the world's settings, and the contact state the next step reads: every collider's pose,
/// velocity and angular velocity (and last contact force and torque), every body's sleep state
/// (asleep, sleep timer, island), its attachments (glue and welds) and the implicit collider
/// friction found in the last step, and the pairs that touched in the last frame. A mesh
/// collider's vertices set by fmCollider_SetMeshVertices are saved (those it has now and a
/// target not yet reached); not saved: its triangles (they cannot change), targets and loads
/// (the caller's input), the last step's results (contacts, events, statistics). fm_errLimit
/// when the buffer is smaller than fmWorld_GetSnapshotSize(); @p written (may be NULL) gets the
/// bytes used. The snapshot is for this process: user energy functions are saved as pointers.
FM_API fmResult fmWorld_SaveSnapshot(fmWorldId worldId, void* buffer, size_t size, size_t* written);

/// Restore a snapshot saved from this world with the same bodies and colliders: the world then
/// continues bit-identically to the world that saved it, kinematic colliders where they were.
/// Bodies are matched by slot, generation and sizes, colliders by slot, generation, shape and (a
/// mesh) vertex and triangle counts. fm_errParameter (and nothing changed, the reason in
/// fmWorld_GetLastError: which body or collider differs, or which part is truncated or invalid)
/// when the buffer is not a snapshot of this format version, is truncated or corrupt (the
/// header's length and 64-bit checksum catch any changed byte before anything is read), or its
/// bodies or colliders do not match the world's (created or destroyed since).
FM_API fmResult fmWorld_RestoreSnapshot(fmWorldId worldId, const void* buffer, size_t size);

/// Create a body from a def with a mesh. The mesh's positions and tets are copied (the mesh is
/// not modified); tets are reoriented positive; degenerate tets are rejected (fm_errDegenerate
/// with the tet index in @p diag). A body whose estimated memory (fmEstimateBodyMemory()) does
/// not fit in what the world's memory budget has left is refused with fm_errLimit before
/// anything is allocated. In a world with contact between bodies (fmContactDef.bodies), a body
/// whose surface would start crossing, or lying inside, another body it collides with (filters
/// that meet; interiors overlapping: a tet's centre inside the other) is refused with
/// fm_errParameter, @p diag naming that body and the crossings:
/// contact holds bodies apart and cannot separate surfaces that already cross (touching is
/// allowed). @p bodyId (optional) is zeroed on failure.
FM_API fmResult fmCreateBody(fmWorldId worldId, const fmBodyDef* def, fmBodyId* bodyId,
                             fmDiagnostic* diag);

/// Check a body def without creating anything: material, mass, damping ranges and the mesh:
/// node and tet counts in [1, FM_MAX_NODES] and [1, FM_MAX_TETS], non-NULL positions and tets,
/// firstIndex 0 or 1, finite coordinates within FM_MAX_COORDINATE, tets of 4 distinct nodes in
/// range and not degenerate. Whatever passes, fmCreateBody() can build (memory permitting).
FM_API fmResult fmBodyDef_Validate(const fmBodyDef* def, fmDiagnostic* diag);

/// Estimated bytes a body of this def takes: its arrays, and the implicit (and static) solver's
/// cache that the first implicit step or fmBody_SolveStatic() adds (about 16 ints a tet for the
/// matrix slots plus 9 doubles a matrix block, twice with stiffness damping). Only the mesh's
/// counts are read; the number of edges is estimated (within a few percent for solid meshes).
/// Returns 0 if there is no mesh. fmCreateBody() checks it against fmWorldDef.memoryBudget.
FM_API size_t fmEstimateBodyMemory(const fmBodyDef* def);

/// Destroy a body.
FM_API void fmDestroyBody(fmBodyId bodyId);

/// True if the id refers to a live body.
FM_API bool fmBody_IsValid(fmBodyId bodyId);

/// Number of vertices (the mesh's nodes, same order).
FM_API int fmBody_GetVertexCount(fmBodyId bodyId);

/// Number of tets.
FM_API int fmBody_GetTetCount(fmBodyId bodyId);

/// Copy the current positions (m) into @p positions, 3 doubles a vertex in the mesh's numbering
/// (vertex i at 3 i), whatever order femto keeps internally: the way to read a body's state.
/// @p vertexCapacity is how many vertices the buffer holds. Errors (the buffer untouched, the
/// reason in fmWorld_GetLastError()): fm_errInvalidId for a stale id and fm_errParameter for a
/// NULL buffer (both programmer errors, also asserted), fm_errLimit when @p vertexCapacity is
/// below fmBody_GetVertexCount().
FM_API fmResult fmBody_CopyPositions(fmBodyId bodyId, double* positions, int vertexCapacity);

/// fmBody_CopyPositions() into floats (a renderer's vertex buffer), each rounded to nearest.
FM_API fmResult fmBody_CopyPositionsFloat(fmBodyId bodyId, float* positions, int vertexCapacity);

/// Copy the current velocities (m/s), as fmBody_CopyPositions() copies positions.
FM_API fmResult fmBody_CopyVelocities(fmBodyId bodyId, double* velocities, int vertexCapacity);

/// fmBody_CopyVelocities() into floats, each rounded to nearest.
FM_API fmResult fmBody_CopyVelocitiesFloat(fmBodyId bodyId, float* velocities, int vertexCapacity);

/// Positions for the picture between the last two frames fmWorld_Advance stepped: @p alpha 0
/// gives the positions at the start of the last frame, 1 at its end (now), between them the
/// straight line (pass fmFixedStep.alpha). Before the first advance, after the caller moved
/// the body (fmBody_SetPositions, fmWorld_RestoreSnapshot, fmBody_SolveStatic) or after a frame
/// stepped by fmWorld_Step itself, the positions now. fm_errParameter for @p alpha outside [0, 1]
/// or a NULL buffer, and as fmBody_CopyPositionsFloat otherwise.
FM_API fmResult fmBody_CopyInterpolatedPositionsFloat(fmBodyId bodyId, double alpha,
                                                      float* positions, int vertexCapacity);

/// Overwrite positions (3 * vertexCount); e.g. for dragging or restoring a state. Non-finite
/// values are taken: the next fmWorld_Step() reports them (fm_errNumerical) and restores the
/// last state that passed its checks. Same for fmBody_SetVelocities(). Positions that put the
/// body across or inside another body it collides with, or turn it inside out (most of its tets
/// inverted: a mirror), are refused by the next fmWorld_Step(): fm_errParameter saying which
/// body and why, nothing stepped, every body back at its last good state.
FM_API void fmBody_SetPositions(fmBodyId bodyId, const double* positions);

/// Overwrite velocities (3 * vertexCount).
FM_API void fmBody_SetVelocities(fmBodyId bodyId, const double* velocities);

/// Vertex masses (kg), vertexCount doubles.
FM_API const double* fmBody_GetMasses(fmBodyId bodyId);

/// Tets of the body (4 per tet, 0-based, after orientation).
FM_API const int* fmBody_GetTets(fmBodyId bodyId);

/// Outward surface triangles (3 per triangle); @p triangleCount gets the count.
FM_API const int* fmBody_GetSurface(fmBodyId bodyId, int* triangleCount);

/// Add @p deltaVelocity (m/s) to every free vertex: the seeds' space-bar jump.
FM_API void fmBody_ApplyImpulse(fmBodyId bodyId, fmVec3 deltaVelocity);

/// Add @p deltaVelocity to one vertex (kicks, dragging).
FM_API void fmBody_ApplyVertexImpulse(fmBodyId bodyId, int vertex, fmVec3 deltaVelocity);

/// Pin every vertex inside the box [min, max] (inclusive) at its current position.
/// Returns how many were pinned (0 means the box catches nothing).
FM_API int fmBody_PinBox(fmBodyId bodyId, fmVec3 min, fmVec3 max);

/// Pin or release one vertex. A pinned vertex never moves.
FM_API void fmBody_SetPinned(fmBodyId bodyId, int vertex, bool pinned);

/// Hold one vertex on some axes only (a roller): bit 0 of @p axes fixes x, bit 1 y, bit 2 z;
/// 7 is the same as fmBody_SetPinned(true), 0 releases it. The vertex keeps its coordinates on
/// the fixed axes and moves freely along the others; its velocity on fixed axes is zeroed.
/// fmBody_IsPinned() is true only for all three axes.
FM_API void fmBody_SetPinnedAxes(fmBodyId bodyId, int vertex, unsigned axes);

/// Whether a vertex is pinned.
FM_API bool fmBody_IsPinned(fmBodyId bodyId, int vertex);

/// Create a rigid collider (validated by fmColliderDef_Validate, whose diagnostic goes to
/// @p diag). Soft bodies' surface vertices are kept out of it, with its friction and
/// restitution, in both integrators (docs/contact.md). fm_errLimit beyond FM_MAX_COLLIDERS.
FM_API fmResult fmCreateCollider(fmWorldId worldId, const fmColliderDef* def,
                                 fmColliderId* colliderId, fmDiagnostic* diag);

/// Destroy a collider. The floor's collider (fmWorld_GetFloorCollider) may be destroyed too:
/// the world then has no floor (as fmWorld_SetFloor with enabled false).
FM_API void fmDestroyCollider(fmColliderId colliderId);

/// The world floor's collider id (the null id while the world has no floor). The floor's
/// response stays the seeds' (src/contact/floor.c), but it is reported as a collider: its contacts
/// in fmWorld_GetContacts, its begin and end events, the force the bodies exert on it
/// (fmCollider_GetContactForce: a resting body's weight), and ray casts and overlap queries hit
/// it. It is moved and changed only through fmWorld_SetFloor: fmCollider_SetTransform and
/// fmCollider_SetVelocity on it assert and do nothing.
FM_API fmColliderId fmWorld_GetFloorCollider(fmWorldId worldId);

/// True if the id refers to a live collider.
FM_API bool fmCollider_IsValid(fmColliderId colliderId);

/// Place a collider: its centre at @p position (plane: the point of the plane nearest the
/// origin; capsule: the segment's midpoint) and its orientation @p rotation (axis-angle, rad,
/// relative to the def's shape). An engine that moves a collider every frame calls this and
/// sets the velocities, which the contact uses for friction and pushing.
FM_API void fmCollider_SetTransform(fmColliderId colliderId, fmVec3 position, fmVec3 rotation);

/// Set a collider's velocity (m/s) and angular velocity (rad/s about its centre); non-zero
/// makes it kinematic: it moves by them every step.
FM_API void fmCollider_SetVelocity(fmColliderId colliderId, fmVec3 velocity,
                                   fmVec3 angularVelocity);

/// Move a mesh collider's vertices: @p vertices (m, in the mesh's own frame, @p vertexCount of
/// them, as many as at creation; the triangles stay) are reached at the end of the next
/// fmWorld_Step, along straight lines over its substeps (as fmBody_MoveGrab's target). Over that
/// step their velocity, (new - old) / the step's length turned by the collider's rotation, adds
/// to the collider's own at its surface (the nearest triangle's blend) for friction and pushing;
/// a mesh not set again stops after it. fm_errParameter (the reason in fmWorld_GetLastError, the
/// mesh unchanged) for a collider that is not a mesh, NULL, another count, or vertices not finite
/// or beyond FM_MAX_COORDINATE; fm_errBusy in a step (its substep callback); fm_errLimit or
/// fm_errOutOfMemory for the first call's copies (three of the vertices). Saved in snapshots;
/// docs/contact.md, "Moving mesh colliders".
FM_API fmResult fmCollider_SetMeshVertices(fmColliderId colliderId, const fmVec3* vertices,
                                           int vertexCount);

/// The collider's centre now (it moves when kinematic).
FM_API fmVec3 fmCollider_GetPosition(fmColliderId colliderId);

/// The force (N) and torque (N m, about its centre) the soft bodies exerted on the collider,
/// averaged over the last fmWorld_Step(): for two-way coupling with an engine's rigid body.
FM_API void fmCollider_GetContactForce(fmColliderId colliderId, fmVec3* force, fmVec3* torque);

/// Copy the last substep's contacts into @p contacts (at most @p capacity); returns how many
/// there were (call with capacity 0 to size the buffer).
FM_API int fmWorld_GetContacts(fmWorldId worldId, fmContactPoint* contacts, int capacity);

/// Copy the last step's contact events (pairs that began or stopped touching) into @p events
/// (at most @p capacity); returns how many there were.
FM_API int fmWorld_GetContactEvents(fmWorldId worldId, fmContactEvent* events, int capacity);

/// Cast a ray from @p origin along @p translation (its length is the range) against every
/// body's deformed surface and every collider that @p filter collides with; the nearest hit
/// goes to @p hit. Returns false when nothing is hit.
FM_API bool fmWorld_CastRay(fmWorldId worldId, fmVec3 origin, fmVec3 translation, fmFilter filter,
                            fmRayHit* hit);

/// Everything that @p filter collides with and that a sphere of @p radius at @p center touches:
/// bodies whose deformed surface (or interior) it reaches, and colliders. Copies at most
/// @p capacity into @p overlaps and returns how many there were (an explosion's victims).
FM_API int fmWorld_OverlapSphere(fmWorldId worldId, fmVec3 center, double radius, fmFilter filter,
                                 fmOverlap* overlaps, int capacity);

/// Audit the world for intersections, an independent check of the contact (it shares no code
/// with the contact stage): surface edges of one body that cross a surface triangle of another
/// (and, in a self-colliding body, a triangle of its own that shares no vertex with the edge),
/// surface vertices strictly inside another body, and inverted tets, in every live body, asleep
/// or not; colliders and the floor are not audited. Crossings are proper ones, decided by the
/// signs of orientation determinants that a static error bound certifies (a sign it cannot
/// certify counts as zero: touching is not crossing); a vertex is inside by the parity of a ray's
/// crossings with a symbolic tie-break, and not inside when within 1e-12 of the body's size of
/// its surface. A uniform grid per body keeps it about linear in the surface size (ms for ten
/// houses). Fills @p audit; fm_errInvalidId for a stale world, fm_errParameter for a NULL
/// @p audit (both asserted), fm_errNumerical when a body's positions are not finite (nothing to
/// audit: the step that made them fails its checks), fm_errOutOfMemory; @p audit is untouched
/// on an error.
FM_API fmResult fmWorld_AuditContact(fmWorldId worldId, fmContactAudit* audit);

/// Copy the last step's sleep events into @p events (at most @p capacity); returns how many.
FM_API int fmWorld_GetSleepEvents(fmWorldId worldId, fmSleepEvent* events, int capacity);

/// Whether the body is awake (false while its island sleeps; fmContactDef.enableSleep).
FM_API bool fmBody_IsAwake(fmBodyId bodyId);

/// Wake a body and its island, or put its island to sleep now (@p awake false).
FM_API void fmBody_SetAwake(fmBodyId bodyId, bool awake);

/// Kinematic targets: pull @p count vertices (user numbering) toward @p positions (m) with
/// zero-length springs of @p stiffness (N/m each), a mouse drag or a character's hand. The set
/// replaces the previous one and stays until changed; move the positions every frame to drag.
/// Both integrators: implicit steps add the springs' energy to the step's minimisation
/// (unconditionally stable at any stiffness); explicit substeps add their forces, each limited
/// to mass / substep^2 (a spring stiffer than that would make the substep unstable). The work
/// the springs do on the body is booked in its energy ledger. @p count 0 clears (the arrays
/// may then be NULL). fm_errParameter (and the last error says why) for a vertex out of range,
/// a non-finite or too distant position, a negative or non-finite stiffness, or a count below 0;
/// fm_errOutOfMemory when the set cannot be stored. The previous set is kept on an error.
/// Not saved in snapshots: targets are the caller's input, set again every frame.
FM_API fmResult fmBody_SetTargets(fmBodyId bodyId, const int* vertices, const fmVec3* positions,
                                  int count, double stiffness);

/// The number of kinematic targets set on the body (0 for a stale id).
FM_API int fmBody_GetTargetCount(fmBodyId bodyId);

/// Grab the body at @p point (m, on or near its surface: an fmRayHit's point) with @p def: the
/// body's vertices around the point are pulled toward the target (fmBody_MoveGrab; at first the
/// point itself) by a damped spring whose whole force is bounded by def->maxForce, in both
/// integrators (implicit steps add its energy to the step's minimisation; explicit substeps its
/// force, the spring and dashpot limited to each substep's stability). A new target is reached
/// along a straight line over the next fmWorld_Step's substeps. The grab replaces the body's
/// kinematic targets (fmBody_SetTargets replaces a grab); it keeps the body awake, does its
/// work in the body's energy ledger and lasts until fmBody_ReleaseGrab (not saved in snapshots).
/// fm_errParameter (the last error says why) for a def not from fmDefaultGrabDef(), a negative
/// or non-finite member, a point not finite or beyond FM_MAX_COORDINATE; fm_errOutOfMemory.
FM_API fmResult fmBody_Grab(fmBodyId bodyId, fmVec3 point, const fmGrabDef* def);

/// Move the grab's target (m), reached at the end of the next fmWorld_Step. fm_errParameter for a
/// body not grabbed or a target not finite or beyond FM_MAX_COORDINATE (the target is kept).
FM_API fmResult fmBody_MoveGrab(fmBodyId bodyId, fmVec3 target);

/// Let go of the body (nothing when it is not grabbed).
FM_API void fmBody_ReleaseGrab(fmBodyId bodyId);

/// Where the grabbed point is now (@p point: the patch's mean motion since the grab added to the
/// point grabbed) and the grab's target (@p target); either may be NULL. False when the body is
/// not grabbed.
FM_API bool fmBody_GetGrab(fmBodyId bodyId, fmVec3* point, fmVec3* target);

/// Cast a ray as fmWorld_CastRay() does and grab the body it hits first at the hit point with
/// @p def (fmBody_Grab). @p hit (may be NULL) gets the hit. False when the ray hits no body
/// (a collider hit is reported in @p hit and not grabbed) or the grab is refused (last error).
FM_API bool fmWorld_GrabRay(fmWorldId worldId, fmVec3 origin, fmVec3 translation, fmFilter filter,
                            const fmGrabDef* def, fmRayHit* hit);

/// Glue @p count vertices (user numbering) to a collider, a game's rigid body seen by femto: each
/// is held by a spring and dashpot (@p def; NULL: fmDefaultAttachDef()) to the point of the
/// collider's frame where the vertex is now, which then moves with the collider
/// (fmCollider_SetTransform, fmCollider_SetVelocity: placed each substep where the collider's
/// motion leaves it). What the body pulls on the collider through them is part of its force and
/// torque (fmCollider_GetContactForce), so an engine's rigid body carries the body and feels
/// it. Both integrators and static solves; the glue's work is in the body's energy ledger; kept
/// in snapshots; dropped with the collider. A body hung on a moving collider does not sleep.
/// fm_errParameter (the last error says why) for a vertex out of range, a collider not live in
/// the body's world, a def not from fmDefaultAttachDef() or out of range; fm_errLimit beyond
/// FM_MAX_ANCHORS_PER_VERTEX attachments per vertex of the body. docs/contact.md, "Attachments".
FM_API fmResult fmBody_AttachToCollider(fmBodyId bodyId, const int* vertices, int count,
                                        fmColliderId colliderId, const fmAttachDef* def);

/// Weld @p count vertices of the body to vertices of another body of its world (or of itself: a
/// seam), vertices[k] to otherVertices[k] (each in its body's user numbering): both ends are
/// pulled, each by a spring and dashpot (@p def; NULL: the default, from the lighter body's
/// weight), to the same point every substep, the two vertices' midpoint (implicit: of their
/// free flights), so each body's own solve brings its vertex there and the two ends' forces are
/// equal and opposite at rest: welded bodies carry each other's weight exactly, and keep their
/// momentum to round-off (explicit) or the solve's tolerance (implicit). Welded bodies do not
/// collide with each other (as a game engine's jointed bodies), sleep and wake together, are
/// kept in snapshots, and lose the weld when either is destroyed. Errors as
/// fmBody_AttachToCollider's (the same vertex at both ends of a seam is fm_errParameter).
FM_API fmResult fmBody_Weld(fmBodyId bodyId, const int* vertices, fmBodyId otherId,
                            const int* otherVertices, int count, const fmAttachDef* def);

/// The body's attachments: glued vertices and weld ends (a weld between two bodies counts once
/// on each). 0 for a stale id.
FM_API int fmBody_GetAttachmentCount(fmBodyId bodyId);

/// Remove the body's glue and its welds, at both ends.
FM_API void fmBody_ClearAttachments(fmBodyId bodyId);

/// Give the body a render mesh: a triangle surface of any resolution (an artist's mesh) that
/// follows the body's deformation. @p vertices (3 per vertex, m) are in the frame of the mesh the
/// body was created from, at rest; each is bound once to the tet that contains it at rest, or,
/// for a vertex outside every tet (a surface slightly larger than the tet mesh), to the nearest
/// tet, whose affine map it then follows extrapolated: rigid motions are reproduced exactly and
/// smooth deformations to first order (docs/embedding.md). A uniform grid over the tets makes the
/// binding about linear in vertices plus tets. @p triangles (3 per triangle, 0-based,
/// counter-clockwise seen from outside; may be NULL when @p triangleCount is 0) are copied and
/// used for the normals. Replaces any previous render mesh. Vertices outside the tets are a
/// warning in @p diag (how many, how far). Errors, the previous render mesh kept: fm_errParameter
/// for counts out of [1, FM_MAX_SURFACE_VERTICES] / [0, FM_MAX_SURFACE_TRIANGLES] or NULL
/// arrays, fm_errRange for a non-finite coordinate, fm_errIndex for a triangle's vertex out of
/// range, fm_errOutOfMemory, fm_errInvalidId for a stale id (also asserted).
FM_API fmResult fmBody_SetRenderMesh(fmBodyId bodyId, const double* vertices, int vertexCount,
                                     const int* triangles, int triangleCount, fmDiagnostic* diag);

/// Remove the body's render mesh (nothing when it has none).
FM_API void fmBody_ClearRenderMesh(fmBodyId bodyId);

/// Vertices of the body's render mesh (0 when it has none).
FM_API int fmBody_GetRenderVertexCount(fmBodyId bodyId);

/// The render mesh's triangles as given to fmBody_SetRenderMesh (3 per triangle); NULL and a
/// count of 0 when the body has none.
FM_API const int* fmBody_GetRenderTriangles(fmBodyId bodyId, int* triangleCount);

/// The render mesh deformed with the body's current positions: positions (m, 3 per vertex)
/// into @p positions and, when @p normals is not NULL, unit vertex normals (the area-weighted
/// mean of the normals of the triangles around each vertex; 0 for a vertex on no triangle) into
/// @p normals. Computed on each call (call it once a frame, after fmWorld_Step); not to be called
/// for the same body from two threads at once. Errors (buffers untouched, the reason in
/// fmWorld_GetLastError()): fm_errInvalidId, fm_errParameter for a NULL @p positions,
/// fm_errEmpty when the body has no render mesh, fm_errLimit when @p vertexCapacity is below
/// fmBody_GetRenderVertexCount().
FM_API fmResult fmBody_CopyRenderPositions(fmBodyId bodyId, double* positions, double* normals,
                                           int vertexCapacity);

/// fmBody_CopyRenderPositions() into floats (an engine's vertex buffer for GPU upload), each
/// rounded to nearest.
FM_API fmResult fmBody_CopyRenderPositionsFloat(fmBodyId bodyId, float* positions, float* normals,
                                                int vertexCapacity);

/// The render mesh between the last two frames fmWorld_Advance stepped (@p alpha as in
/// fmBody_CopyInterpolatedPositionsFloat): the render mesh of the interpolated positions, its
/// normals from them. Errors as fmBody_CopyRenderPositionsFloat, and fm_errParameter for
/// @p alpha outside [0, 1].
FM_API fmResult fmBody_CopyInterpolatedRenderPositionsFloat(fmBodyId bodyId, double alpha,
                                                            float* positions, float* normals,
                                                            int vertexCapacity);

/// Nodal force: add @p force (N, on each vertex, not shared out) to every vertex within the
/// box [min, max] (inclusive, at its current position). Returns how many vertices it caught (0:
/// the box catches nothing), -1 when memory is short (fmWorld_GetLastError() says so). A NaN or
/// non-finite force, a NaN or empty box (min > max on an axis) is a programmer error (asserted,
/// -1). Loads act in the explicit step, the implicit step and fmBody_SolveStatic() (scaled by
/// its load fraction, as gravity); their work is booked in the body's energy ledger. They stay
/// until fmBody_ClearLoads() and are not saved in snapshots. docs/loads.md.
FM_API int fmBody_AddNodalForce(fmBodyId bodyId, fmVec3 min, fmVec3 max, fmVec3 force);

/// Pressure (Pa) on every surface triangle whose three vertices lie in the box [min, max]:
/// positive pushes against the outward normal (into the body), as in CalculiX and Abaqus; each
/// triangle's force p A n is shared in thirds among its vertices. @p follower true: the normal
/// and the area follow the deformation (evaluated every explicit substep, at the start of each
/// implicit step, and lagged to a fixed point in fmBody_SolveStatic; its non-symmetric stiffness
/// never enters the Newton matrix); false: fixed direction and area, those of the rest shape.
/// The scene's default is the follower, as CalculiX's and Abaqus's pressure under large
/// deformation. Returns the number of triangles caught, -1 as fmBody_AddNodalForce().
FM_API int fmBody_AddPressure(fmBodyId bodyId, fmVec3 min, fmVec3 max, double pressure,
                              bool follower);

/// Remove every nodal force and pressure of the body (pins and prescribed displacements stay).
FM_API void fmBody_ClearLoads(fmBodyId bodyId);

/// The body's loads at its current positions (N), 3 doubles a vertex in the user's numbering:
/// what the next step applies (follower pressure at the current shape).
FM_API void fmBody_ComputeLoadForces(fmBodyId bodyId, double* forces);

/// Pin the vertices within the box [min, max] on @p axes (bit 0 x, bit 1 y, bit 2 z, as
/// fmBody_SetPinnedAxes), combined with the axes they are already pinned on: rollers. Returns
/// how many vertices it caught; a bad box or axes above 7 is a programmer error (-1).
FM_API int fmBody_PinBoxAxes(fmBodyId bodyId, fmVec3 min, fmVec3 max, unsigned axes);

/// Prescribed displacement: the vertices within the box [min, max] are pinned on @p axes
/// (1 to 7, combined with their pins) and moved along those axes by the matching components
/// of @p displacement (m) from where they are now: linearly over @p time seconds of simulated
/// time in fmWorld_Step() (0: at the next step), or over the load steps of fmBody_SolveStatic(),
/// which reaches the full displacement (a dynamic run after it keeps it). The elastic energy
/// the motion puts into the body is booked in its energy ledger. Returns how many vertices it
/// caught, -1 as fmBody_AddNodalForce(). Not saved in snapshots. docs/loads.md.
FM_API int fmBody_PrescribeDisplacement(fmBodyId bodyId, fmVec3 min, fmVec3 max, unsigned axes,
                                        fmVec3 displacement, double time);

/// Energies, lowest point, inverted tets.
FM_API fmBodyStats fmBody_GetStats(fmBodyId bodyId);

/// Tear the body where its material's fracture criterion holds at the current positions
/// (fmMaterial.fracture; fmWorld_Step does this after every frame): faces whose tensile
/// traction reaches the strength break, vertices whose tets no longer hold together are split
/// (the copies numbered after the others: the vertex count grows). Returns the faces broken,
/// 0 when none, or -1 with fmWorld_GetLastError set (out of memory; the body is unchanged).
FM_API int fmBody_Fracture(fmBodyId bodyId);

/// The fracture criterion at the current positions: fills @p tetDamage (tet count entries,
/// user numbering, or NULL) with each tet's largest traction over strength on its unbroken
/// shared faces (1 breaks) and returns the largest; 0 for a body that cannot break.
FM_API double fmBody_ComputeDamage(fmBodyId bodyId, double* tetDamage);

/// The pieces the body is torn into (1 for a whole body); fills @p tetPiece (tet count
/// entries, user numbering, or NULL) with each tet's piece, numbered by their first tet.
FM_API int fmBody_GetPieces(fmBodyId bodyId, int* tetPiece);

/// Faces broken since the body was created (each shared face once).
FM_API int fmBody_GetBrokenFaceCount(fmBodyId bodyId);

/// Change the material (validated; the rest shape is kept).
FM_API fmResult fmBody_SetMaterial(fmBodyId bodyId, const fmMaterial* material, fmDiagnostic* diag);

/// Elastic forces (N) at the current positions into @p forces (3 * vertexCount); returns the
/// elastic energy (J). Used by tests and tools; the step does not need it.
FM_API double fmBody_ComputeElasticForces(fmBodyId bodyId, double* forces);

/// Solve for static equilibrium under gravity with the body's pins (Newton with line search and
/// load stepping). The floor is ignored. @p tolerance in [FM_MIN_TOLERANCE, 1), @p maxIterations
/// (per load step) in [1, FM_MAX_NEWTON_ITERATIONS]. @p residual gets |f| / |m g| reached.
/// fm_errNotConverged keeps a state rather than the start: at full load the best state reached
/// (when the residual stagnated at round-off above the tolerance), otherwise the equilibrium of
/// the largest load fraction that converged; the diagnostic says which and how close it got.
FM_API fmResult fmBody_SolveStatic(fmBodyId bodyId, double tolerance, int maxIterations,
                                   double* residual, fmDiagnostic* diag);

FM_C_END
