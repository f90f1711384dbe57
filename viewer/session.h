// The simulation behind `femto view`: a scene loaded through the CLI's code (cli/scene.c,
// cli/simulation.c), stepped at a fixed rate, with the live parameters the sliders change, the
// seeds' jump, pause and single steps, reset, and the mouse drag (kinematic targets). No window
// or graphics here: the window (window.c) and scripts (script.c) drive it alike.
#pragma once

#include "scene.h"

/// The seeds' Update rate: each tick of 1/60 s steps one scene frame (dt * substeps).
#define FV_TICK_SECONDS (1.0 / 60.0)

/// What the sliders change; applied to every body of the scene.
typedef struct fvParams
{
	/// linear ... Mooney-Rivlin (the user-energy models are not offered), or the scene's
	/// anisotropic model, whose constants the Young's slider scales
	fmMaterialModel model;
	double youngs;       ///< Pa (an anisotropic model's: its Voigt average's)
	double poisson;      ///< in (-1, 0.5)
	double startYoungs;  ///< youngs when the scene loaded: an anisotropic model's scale 1
	double startPoisson; ///< poisson when the scene loaded
	bool perParticle;    ///< masses per vertex (the seeds) or from a density
	double mass;         ///< kg per vertex (perParticle) or kg/m^3
	double damping;      ///< velocity factor per 3 ms, in (0, 1]
	double dt;           ///< s, one substep
	int substeps;        ///< substeps a frame
	fmIntegrator integrator;
} fvParams;

/// The physics' share of a 60 Hz frame (ms): half of its 16.7 ms, the rest for drawing and the
/// game. A frame whose steps take longer is marked in the panel ("over budget").
#define FV_STEP_SHARE_MS 8.3

/// Frames the panel's profile graph shows (5 s at 60 a second).
#define FV_PROFILE_FRAMES 300

/// A loaded scene and its world.
typedef struct fvSession
{
	char path[CLI_MAX_PATH]; ///< the scene file, "" for the built-in house
	cliScene scene;
	cliSimulation sim;
	fvParams params;
	bool paused;
	double explicitDt;    ///< s, the explicit substep before a switch to implicit (0: none)
	int explicitSubsteps; ///< and its count, restored on the way back
	int pendingSteps;     ///< single steps asked for while paused
	int pendingJumps;     ///< jumps to add to the next frame
	double accumulator;   ///< s of real time not yet stepped
	long frames;          ///< scene frames stepped since the load or reset
	double stepMs;        ///< wall time of the last frame's fmWorld_Step calls
	bool overBudget;      ///< the last frame's steps took more than FV_STEP_SHARE_MS
	float stepHistory[FV_PROFILE_FRAMES]; ///< ms of the last frames' steps, a ring
	int historyCount;                     ///< frames in it (at most FV_PROFILE_FRAMES)
	int historyNext;                      ///< where the next one goes
	long overBudgetFrames;                ///< frames over it since the scene was loaded
	fmStepStats stats;                    ///< of the last step
	fmProfile profile;                    ///< of the last step
	bool dragging;
	int dragBody;      ///< index in sim.bodies of the body grabbed (fmWorld_GrabRay)
	char status[2048]; ///< the last problem (a failed step, a rejected parameter), "" if none
} fvSession;

/// Load @p path (NULL: the built-in house) and create its world. Prints what is wrong and
/// returns false; the session is then empty (safe to free).
bool fvSession_Load(fvSession* session, const char* path);

/// Release the world and the scene.
void fvSession_Free(fvSession* session);

/// Re-create the world from the scene: the initial state, with the current parameters.
bool fvSession_Reset(fvSession* session);

/// Whether the session has a world (false after a reset that could not re-create it).
bool fvSession_IsLive(const fvSession* session);

/// Let @p seconds of time pass: one scene frame per FV_TICK_SECONDS (at most 8 a call, so a
/// slow machine slows down instead of falling ever further behind), plus single steps asked
/// for while paused.
void fvSession_Advance(fvSession* session, double seconds);

/// The seeds' jump (space): 0.2 m/s upward on every free vertex before each substep of the
/// next frame, 2 m/s over the house's 10 substeps (docs/cli.md, "The jump").
void fvSession_Jump(fvSession* session);

/// Apply params.model, .youngs, .poisson to every body (fmBody_SetMaterial). False (with
/// status) when the library rejects them; the bodies keep their material.
bool fvSession_ApplyMaterial(fvSession* session);

/// Apply params.mass and .damping: the bodies are re-created in their current state (positions
/// and velocities carry over; the drag is released).
bool fvSession_ApplyBodies(fvSession* session);

/// Switch to @p integrator with substeps that suit it, the frame (dt times substeps) kept:
/// implicit takes the frame as one step (the explicit dt and substeps remembered), explicit
/// gets back what it had, or else substeps within 0.9 of its stability limit (at most 1000).
void fvSession_SwitchIntegrator(fvSession* session, fmIntegrator integrator);

/// Apply params.integrator (fmWorld_SetIntegrator).
void fvSession_ApplyIntegrator(fvSession* session);

/// Grab the first body the ray from @p origin along @p translation (m) hits, with the library's
/// grab (fmWorld_GrabRay, its defaults); the point grabbed goes to @p point. False when the ray
/// hits no body (a collider is scenery) or the grab was refused (the status says why).
bool fvSession_Grab(fvSession* session, fmVec3 origin, fmVec3 translation, fmVec3* point);

/// Move the grab's target (m).
void fvSession_MoveGrab(fvSession* session, fmVec3 target);

/// Let go (fmBody_ReleaseGrab).
void fvSession_Release(fvSession* session);

/// The index in sim.bodies of @p body, -1 if none.
int fvSession_BodyIndex(const fvSession* session, fmBodyId body);
