// Scenes: what `femto run` and `femto static` simulate. Read from JSON (docs/scene-format.md)
// or made in code (the built-in bouncy house), then turned into a femto world.
#pragma once

#include "cli.h"

#include <stdio.h>

/// Where a body's rest mesh comes from.
typedef enum cliMeshSource
{
	cli_meshFile,  ///< a TetGen .node/.ele pair on disk
	cli_meshHouse, ///< the bouncy house embedded in the binary ("builtin:house2")
	cli_meshBox,   ///< a generated box ("box:nx,ny,nz")
} cliMeshSource;

/// A pin box in scene coordinates (after the body's transform).
typedef struct cliPinBox
{
	fmVec3 min;           ///< m
	fmVec3 max;           ///< m
	unsigned axes;        ///< held axes: bit 0 x, 1 y, 2 z ("axes", default all three)
	bool hasDisplacement; ///< "displacement" given: a prescribed displacement
	fmVec3 displacement;  ///< m, along the held axes
	double time;          ///< s to reach it in a dynamic run (0: at the first step)
} cliPinBox;

/// A nodal force box ("loads" on a body): @p force on each vertex in the box.
typedef struct cliLoadBox
{
	fmVec3 min;   ///< m
	fmVec3 max;   ///< m
	fmVec3 force; ///< N on each vertex
} cliLoadBox;

/// An attachment's default stiffness (N/m on each vertex): stiff against a vertex's share of a
/// game-sized body's weight; the explicit integrator caps it at m / h^2 (fmBody_SetTargets).
#define CLI_ATTACHMENT_STIFFNESS 1e5

/// An attachment ("attachments" on a body): the vertices in the box (at creation) are pulled by
/// kinematic targets (fmBody_SetTargets) along a rigid motion: their rest positions turned by
/// angular_velocity * t about the box's centre and moved by velocity * t; or, with a collider,
/// glued to it (fmBody_AttachToCollider).
typedef struct cliAttachment
{
	fmVec3 min;             ///< m
	fmVec3 max;             ///< m
	fmVec3 velocity;        ///< m/s
	fmVec3 angularVelocity; ///< rad/s, about the box's centre
	double stiffness;       ///< N/m on each vertex (glue: 0 for the library's default)
	int collider;           ///< the scene's collider the vertices are glued to, or -1
	double dampingRatio;    ///< glue: fmAttachDef.dampingRatio
} cliAttachment;

/// A weld ("welds" on a body, fmBody_Weld): every vertex of the body within `distance` of a
/// vertex of the other body is welded to the nearest such vertex.
typedef struct cliWeld
{
	int body;            ///< the scene's other body
	double distance;     ///< m
	double stiffness;    ///< N/m on each end (0: the library's default)
	double dampingRatio; ///< fmAttachDef.dampingRatio
} cliWeld;

/// A pressure box ("pressure" on a body): every surface triangle with its vertices in the box.
typedef struct cliPressureBox
{
	fmVec3 min;      ///< m
	fmVec3 max;      ///< m
	double pressure; ///< Pa, positive pushes into the body
	bool follower;   ///< follows the deformation (default true)
} cliPressureBox;

/// One body of a scene, before it exists in a world.
/// A body's "fibres" (docs/scene-format.md): per-tet fibre directions for its anisotropic
/// materials, from three of the mesh's tet attributes or turning around an axis.
typedef enum cliFibreSource
{
	cli_fibresNone,       ///< each material's own fibre
	cli_fibresAttributes, ///< tet attributes [attribute, attribute + 3)
	cli_fibresAround,     ///< axis x (centroid - point): circumferential about the line
} cliFibreSource;

typedef struct cliFibres
{
	cliFibreSource source;
	int attribute; ///< cli_fibresAttributes: the first of the three
	fmVec3 axis;   ///< cli_fibresAround: the line's direction
	fmVec3 point;  ///< cli_fibresAround: a point on it (scene coordinates)
} cliFibres;

typedef struct cliBodySpec
{
	cliMeshSource meshSource;
	char nodePath[CLI_MAX_PATH]; ///< cli_meshFile: resolved mesh path (.node, .msh, .vtu, ...)
	char elePath[CLI_MAX_PATH];  ///< cli_meshFile: the .ele beside a .node (else nodePath)
	int boxCells[3];             ///< cli_meshBox: cells along x, y, z
	fmVec3 boxMin;               ///< cli_meshBox: m
	fmVec3 boxMax;               ///< cli_meshBox: m
	fmMeshTransform transform;   ///< placement of the loaded mesh
	fmBodyDef def;               ///< material, masses, damping (mesh set when built)
	cliPinBox* pins;             ///< malloc'd, pinCount boxes
	int pinCount;
	cliLoadBox* loads; ///< malloc'd, loadCount boxes ("loads")
	int loadCount;
	cliPressureBox* pressures; ///< malloc'd, pressureCount boxes ("pressure")
	int pressureCount;
	cliAttachment* attachments; ///< malloc'd, attachmentCount ("attachments")
	int attachmentCount;
	cliWeld* welds; ///< malloc'd, weldCount ("welds")
	int weldCount;
	fmMaterial* regionMaterials; ///< malloc'd, def.regionCount ("regions"), def points at them
	int* regionIds;              ///< malloc'd, def.regionCount
	cliFibres fibres;            ///< "fibres"
	fmVec3 initialVelocity;      ///< m/s
	/// "render_mesh": the resolved OBJ path, empty without one; placed by @p transform
	char renderMeshPath[CLI_MAX_PATH];
} cliBodySpec;

/// One rigid collider of a scene (docs/scene-format.md, "Colliders").
typedef struct cliColliderSpec
{
	fmColliderDef def;          ///< shape, friction, velocities (a mesh's arrays set when built)
	char objPath[CLI_MAX_PATH]; ///< mesh: the resolved OBJ path
	fmMeshTransform transform;  ///< mesh: placement of the OBJ's vertices
} cliColliderSpec;

/// The topics the samples are grouped by (a scene's "topic"; femto view's list and the web
/// page's picker show them in this order).
#define CLI_TOPIC_COUNT 6
extern const char* const cliTopicNames[CLI_TOPIC_COUNT]; ///< "materials" ... "render meshes"

/// A scene's "camera": where femto view and the page put the orbit camera when the scene loads
/// (the parts given; the others framed on the bodies, as --camera-* do).
typedef struct cliCameraPreset
{
	bool hasTarget, hasDistance, hasYaw, hasPitch;
	fmVec3 target;   ///< m, the point the camera orbits and looks at
	double distance; ///< m from the target, in [1e-3, 1e6]
	double yaw;      ///< degrees about +y from looking down -z, in [-360, 360]
	double pitch;    ///< degrees above the horizon, in [-89, 89]
} cliCameraPreset;

/// A whole scene.
typedef struct cliScene
{
	char name[CLI_MAX_PATH]; ///< the scene file as given, or "builtin:house"
	char description[512];   ///< the scene's "description" (cut at 511 bytes), "" if none
	int topic;               ///< "topic": an index of cliTopicNames, -1 if none
	cliCameraPreset camera;  ///< "camera" (nothing given: all framed)
	fmWorldDef worldDef;     ///< gravity, floor, integrator settings
	double dt;               ///< s, one substep (with worldDef.autoSubstep: the frame)
	int substeps;            ///< substeps a frame (a frame is dt * substeps); 1 with autoSubstep
	int frames;              ///< default frame count for run, 0 if not given
	double seconds;          ///< default duration for run, 0 if not given
	cliBodySpec* bodies;     ///< malloc'd
	int bodyCount;
	cliColliderSpec* colliders; ///< malloc'd, or NULL without colliders
	int colliderCount;
	bool hasWorkers; ///< the scene gave "workers" (else the tool picks the cores available)
} cliScene;

/// A scene turned into a world: the ids and the meshes (kept for .node export).
typedef struct cliSimulation
{
	fmWorldId world;
	int bodyCount;
	fmBodyId* bodies;  ///< malloc'd
	fmTetMesh* meshes; ///< malloc'd, the placed rest meshes, input numbering
	int colliderCount;
	fmColliderId* colliders;      ///< malloc'd, the scene's colliders in order
	struct cliAttached* attached; ///< malloc'd, every attached vertex (attachments.h)
	int attachedCount;
	double time; ///< s simulated, for the attachments' motion
} cliSimulation;

/// The built-in bouncy house: data/house2 scaled 0.4, centred, y/z swapped, floor y = -3
/// (stick), StVK lambda 20000 mu 5000, particle mass 1, dt 3 ms, 10 substeps, 5 s.
void cliScene_MakeHouse(cliScene* scene);

/// Read and validate a JSON scene. Prints "file:line: path: message" and returns false on error.
bool cliScene_Load(const char* path, cliScene* scene);

/// Same as cliScene_Load() from text in memory (need not be NUL-terminated); @p name is used in
/// messages and its folder resolves relative mesh paths. Messages go to @p messages (stderr for
/// the tool; NULL prints nothing, for the fuzzer).
bool cliScene_LoadText(const char* name, const char* text, size_t size, FILE* messages,
                       cliScene* scene);

/// Release what a scene holds.
void cliScene_Free(cliScene* scene);

/// Seconds of one frame.
double cliScene_FrameTime(const cliScene* scene);

/// What cliSimulation_Create says about an explicit dt above the estimated stable step.
typedef enum cliStepCheck
{
	cli_stepCheckOff,      ///< nothing (static solves, benchmarks with their own dt)
	cli_stepCheckWarnings, ///< only the warning beyond twice the estimate (run --quiet)
	cli_stepCheckAll,      ///< also a note between the estimate and twice it
} cliStepCheck;

/// Load meshes, create the world and bodies, pin, set initial velocities, check the explicit
/// step as @p check says. Prints errors, returns false.
bool cliSimulation_Create(const cliScene* scene, cliStepCheck check, cliSimulation* sim);

/// Destroy the world and free the meshes.
void cliSimulation_Destroy(cliSimulation* sim);

/// Load the embedded bouncy house mesh (untransformed).
fmResult cliLoadHouseMesh(fmTetMesh* mesh, fmDiagnostic* diag);
