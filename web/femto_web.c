// The page's door to libfemto (docs/web.md): plain functions of ints and doubles that the
// page's JavaScript (web/femto.js) calls on the WebAssembly build, and that the native side of
// the Node.js comparison (web/test/compare_native.c) calls on the native build, so both run the
// same scene code. It keeps one world at a time: a scene of scenes/*.json (the menu's files, or
// any scene text), read by the tool's own schema code (cli/scene.h), or a dropped mesh. The glue
// reads no file itself: its caller gives it the files it names (fw_file_path, fw_set_file), as
// the page fetches them and the tests read them from disk.
//
// Conventions: bodies are numbered 0 to fw_body_count() - 1; pointers returned point into the
// module's memory and stay valid until the next scene is loaded; a call that fails returns a
// result code (fmResult, 0 = ok) and fw_error() says why.
#define _POSIX_C_SOURCE 200809L // fmemopen

#include "scene.h"
#include "scene_body.h"

#include <femto/femto.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__EMSCRIPTEN__)
#include <emscripten/emscripten.h>
#define FW_EXPORT EMSCRIPTEN_KEEPALIVE
#else
#define FW_EXPORT
#endif

#define FW_MAX_BODIES 8

// The seeds' jump (viewer/session.c): 2 m/s upward spread over the next frame's substeps.
#define FW_JUMP_SPEED 2.0

// Bigger dropped meshes fit in this (m, the house's size) and fall from this height above the
// floor.
#define FW_USER_MESH_SIZE 4.0
#define FW_USER_MESH_DROP 1.0

// The page's scenes: its menu's title and the file of scenes/ it reads. scripts/web.sh copies
// the files this list names (it reads the X(...) lines) into web/dist/scenes/.
#define FW_SCENES(X)                                                                               \
	X("house (StVK, the seeds)", house)                                                            \
	X("house, linear", house_linear)                                                               \
	X("house, corotated", house_corotated)                                                         \
	X("house, Neo-Hookean", house_neohookean)                                                      \
	X("house, Mooney-Rivlin", house_mooneyrivlin)                                                  \
	X("pile of boxes", pile)                                                                       \
	X("thrown cube", drop)                                                                         \
	X("two houses (implicit)", two_houses)                                                         \
	X("house, StVK", house_stvk)                                                                   \
	X("house, implicit (Neo-Hookean)", house_implicit)                                             \
	X("rubber house (nu = 0.4999)", rubber)

// One entry of the menu: its title and its file.
typedef struct fwSceneFile
{
	const char* title;
	const char* file;
} fwSceneFile;

#define FW_SCENE_ENTRY(title, file) {title, "scenes/" #file ".json"},
static const fwSceneFile fw_scenes[] = {FW_SCENES(FW_SCENE_ENTRY)};
#define FW_SCENE_COUNT ((int)(sizeof fw_scenes / sizeof fw_scenes[0]))

// The mesh of "builtin:house2" (scripts/web.sh copies these files into web/dist/data/ and reads
// these two lines).
#define FW_HOUSE_NODE "data/house2.node"
#define FW_HOUSE_ELE "data/house2.ele"

// The files the glue reads, numbered as fw_file_path numbers them: the menu's scenes, then the
// house's .node and .ele.
#define FW_FILE_COUNT (FW_SCENE_COUNT + 2)
#define FW_FILE_HOUSE_NODE FW_SCENE_COUNT
#define FW_FILE_HOUSE_ELE (FW_SCENE_COUNT + 1)

// A file given by fw_set_file: a copy of its bytes (NULL until given).
typedef struct fwFile
{
	char* text;
	size_t size;
} fwFile;

static fwFile s_files[FW_FILE_COUNT];

// The world the page shows, and the sliders' values applied to it.
typedef struct fwApp
{
	fmWorldId world;
	cliScene scene; // what was loaded (read by the tool's schema, scene.h)
	bool hasScene;  // scene holds a scene to free
	bool userBody;  // body 0's mesh is userMesh (a dropped mesh's scene)
	bool deterministic;
	int bodyCount;
	fmBodyId bodies[FW_MAX_BODIES];
	fmTetMesh meshes[FW_MAX_BODIES];
	float* floatPositions[FW_MAX_BODIES];
	double* doublePositions[FW_MAX_BODIES];
	fmVec3* fibres[FW_MAX_BODIES]; // the scene's per-tet fibres ("fibres"), or NULL
	fmTetMesh userMesh;            // the last dropped mesh (kept for reloading its scene)
	// sliders
	fmMaterial material; // the first body's, shown by the sliders
	bool materialSet;    // the sliders set material for every body (else each keeps the scene's)
	fmMaterialModel model;
	double youngs, poisson, damping;
	int substeps;
	fmIntegrator integrator;
	// input
	int pendingJumps;
	bool dragging; // the library's grab (fmBody_Grab) holds body dragBody
	int dragBody;
	fmRayHit hit;
	int hitBody;
	double stepMs;
	char error[1024];
	char warning[512]; // the last loaded mesh's (skipped elements), or ""
} fwApp;

static fwApp s_app;

FW_EXPORT void fw_drag_end(void);

static void fwSetError(const char* what, const fmDiagnostic* diag)
{
	char text[900];
	snprintf(s_app.error, sizeof s_app.error, "%s: %s", what,
	         diag != NULL ? fmDiagnostic_Format(diag, text, sizeof text) : "");
}

// Young's modulus and Poisson ratio of Lame constants (the inverse of fmMakeMaterial's).
static void fwFromLame(double lambda, double mu, double* youngs, double* poisson)
{
	*youngs = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
	*poisson = lambda / (2.0 * (lambda + mu));
}

// Body @p b's rest mesh, placed by its transform as `femto run` places it (simulation.c); the
// house's files were given (fw_load_scene_text checks).
static fmResult fwMakeMesh(int b, fmTetMesh* mesh, fmDiagnostic* diag)
{
	const cliBodySpec* spec = &s_app.scene.bodies[b];
	if (b == 0 && s_app.userBody)
		return fmCopyTetMesh(&s_app.userMesh, mesh); // placed when dropped
	fmResult r = spec->meshSource == cli_meshBox
	                 ? fmMakeBoxMesh(spec->boxCells[0], spec->boxCells[1], spec->boxCells[2],
	                                 spec->boxMin, spec->boxMax, mesh)
	                 : fmLoadTetGenFromMemory(
	                       s_files[FW_FILE_HOUSE_NODE].text, s_files[FW_FILE_HOUSE_NODE].size,
	                       FW_HOUSE_NODE, s_files[FW_FILE_HOUSE_ELE].text,
	                       s_files[FW_FILE_HOUSE_ELE].size, FW_HOUSE_ELE, mesh, diag);
	if (r == fm_ok)
		fmTetMesh_Transform(mesh, &spec->transform);
	return r;
}

// Body @p b's def: the scene's, with the sliders' damping, and their material once they set it.
static fmBodyDef fwBodyDef(const fwApp* app, int b)
{
	fmBodyDef def = app->scene.bodies[b].def;
	def.mesh = (fmTetMesh*)&app->meshes[b];
	def.tetFibres = app->fibres[b];
	if (app->materialSet)
		def.material = app->material;
	def.damping = app->damping;
	return def;
}

static void fwFreeScene(void)
{
	if (fmWorld_IsValid(s_app.world))
		fmDestroyWorld(s_app.world);
	for (int b = 0; b < s_app.bodyCount; ++b)
	{
		fmFreeTetMesh(&s_app.meshes[b]);
		free(s_app.floatPositions[b]);
		free(s_app.doublePositions[b]);
		free(s_app.fibres[b]);
		s_app.fibres[b] = NULL;
	}
	memset(s_app.bodies, 0, sizeof s_app.bodies);
	memset(s_app.meshes, 0, sizeof s_app.meshes);
	memset(s_app.floatPositions, 0, sizeof s_app.floatPositions);
	memset(s_app.doublePositions, 0, sizeof s_app.doublePositions);
	s_app.world = (fmWorldId){0, 0};
	s_app.bodyCount = 0;
	s_app.dragging = false;
	s_app.pendingJumps = 0;
	if (s_app.hasScene)
		cliScene_Free(&s_app.scene);
	s_app.hasScene = false;
	s_app.userBody = false;
}

// Body @p b of s_app.scene in the world, with its position buffers and initial velocity.
static fmResult fwCreateBody(int b)
{
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult r = fwMakeMesh(b, &s_app.meshes[b], &diag);
	s_app.bodyCount = b + 1; // the mesh and fibres are freed with the scene from here on
	char problem[256] = "";
	if (r == fm_ok)
		s_app.fibres[b] =
		    cliBodyFibres(&s_app.scene.bodies[b], &s_app.meshes[b], problem, sizeof problem);
	if (problem[0] != 0)
	{
		r = fm_errParameter;
		snprintf(diag.message, sizeof diag.message, "%s", problem);
	}
	fmBodyDef def = fwBodyDef(&s_app, b);
	if (r == fm_ok)
		r = fmCreateBody(s_app.world, &def, &s_app.bodies[b], &diag);
	int n = r == fm_ok ? fmBody_GetVertexCount(s_app.bodies[b]) : 0;
	s_app.floatPositions[b] = r == fm_ok ? calloc(3 * (size_t)n, sizeof(float)) : NULL;
	s_app.doublePositions[b] = r == fm_ok ? calloc(3 * (size_t)n, sizeof(double)) : NULL;
	if (r == fm_ok && (s_app.floatPositions[b] == NULL || s_app.doublePositions[b] == NULL))
		r = fm_errOutOfMemory;
	if (r != fm_ok)
	{
		fwSetError("the scene's body was refused", &diag);
		return r;
	}
	fmVec3 v = s_app.scene.bodies[b].initialVelocity;
	if (v.x != 0.0 || v.y != 0.0 || v.z != 0.0)
		fmBody_ApplyImpulse(s_app.bodies[b], v);
	return fm_ok;
}

// Build the world of s_app.scene (as `femto run` does, on one thread) with the sliders' values
// set from its first body.
static fmResult fwBuildScene(void)
{
	const cliScene* scene = &s_app.scene;
	const fmMaterial* first = &scene->bodies[0].def.material;
	s_app.model = first->model;
	s_app.material = *first;
	s_app.materialSet = false;
	fwFromLame(first->lambda, first->mu, &s_app.youngs, &s_app.poisson);
	s_app.damping = scene->bodies[0].def.damping;
	s_app.substeps = scene->substeps;
	s_app.integrator = scene->worldDef.integrator;

	fmWorldDef worldDef = scene->worldDef;
	worldDef.workerCount = 1; // threads need cross-origin isolation on the web (docs/web.md)
	worldDef.crossPlatformDeterminism = s_app.deterministic;
	s_app.world = fmCreateWorld(&worldDef);
	if (!fmWorld_IsValid(s_app.world))
	{
		snprintf(s_app.error, sizeof s_app.error, "cannot create the world");
		fwFreeScene();
		return fm_errOutOfMemory;
	}
	for (int b = 0; b < scene->bodyCount; ++b)
	{
		fmResult r = fwCreateBody(b);
		if (r != fm_ok)
		{
			fwFreeScene();
			return r;
		}
	}
	s_app.error[0] = 0;
	return fm_ok;
}

// What of a scene the page cannot show yet: NULL when it shows all of it.
static const char* fwUnshown(const cliScene* scene)
{
	if (scene->bodyCount > FW_MAX_BODIES)
		return "more than 8 bodies";
	if (scene->colliderCount > 0)
		return "colliders";
	for (int b = 0; b < scene->bodyCount; ++b)
	{
		const cliBodySpec* spec = &scene->bodies[b];
		if (spec->meshSource == cli_meshFile)
			return "mesh files (only \"builtin:house2\" and \"box:nx,ny,nz\")";
		if (spec->pinCount + spec->loadCount + spec->pressureCount + spec->attachmentCount +
		        spec->weldCount >
		    0)
			return "pins, loads, pressures, attachments and welds";
		if (spec->renderMeshPath[0] != 0)
			return "render meshes";
	}
	return NULL;
}

// Read a scene's JSON text with the tool's schema (scene.h) into @p scene; false with fw_error()
// saying where the text is wrong, or what the page cannot show.
static bool fwReadScene(const char* name, const char* text, size_t size, cliScene* scene)
{
	s_app.error[0] = 0;
	FILE* messages = fmemopen(s_app.error, sizeof s_app.error, "w");
	bool ok = cliScene_LoadText(name, text, size, messages, scene);
	if (messages != NULL)
		fclose(messages);
	s_app.error[strcspn(s_app.error, "\n")] = 0;
	const char* unshown = ok ? fwUnshown(scene) : NULL;
	if (unshown != NULL)
	{
		snprintf(s_app.error, sizeof s_app.error, "%s: the web page does not show %s", name,
		         unshown);
		cliScene_Free(scene);
		return false;
	}
	if (!ok && s_app.error[0] == 0)
		snprintf(s_app.error, sizeof s_app.error, "%s: cannot read the scene", name);
	return ok;
}

/// Number of built-in scenes.
FW_EXPORT int fw_scene_count(void)
{
	return FW_SCENE_COUNT;
}

/// The menu title of built-in scene @p index (NUL-terminated), or "" out of range.
FW_EXPORT const char* fw_scene_name(int index)
{
	return index >= 0 && index < FW_SCENE_COUNT ? fw_scenes[index].title : "";
}

/// The file of built-in scene @p index ("scenes/house.json"), or "" out of range.
FW_EXPORT const char* fw_scene_file(int index)
{
	return index >= 0 && index < FW_SCENE_COUNT ? fw_scenes[index].file : "";
}

/// The "topic" of built-in scene @p index (docs/scene-format.md: the page's picker groups the
/// scenes by it), read from its file by the schema; "" when it has none, or its file was not
/// given yet or does not read.
FW_EXPORT const char* fw_scene_topic(int index)
{
	if (index < 0 || index >= FW_SCENE_COUNT || s_files[index].text == NULL)
		return "";
	cliScene scene;
	if (!cliScene_LoadText(fw_scenes[index].file, s_files[index].text, s_files[index].size, NULL,
	                       &scene))
		return "";
	int topic = scene.topic;
	cliScene_Free(&scene);
	return topic >= 0 ? cliTopicNames[topic] : "";
}

/// The loaded scene's "camera" preset: 0-2 its target (m), 3 its distance (m), 4 its yaw and 5
/// its pitch (degrees); NaN for a part it does not give (the page frames that part).
FW_EXPORT double fw_camera(int which)
{
	const cliCameraPreset* c = &s_app.scene.camera;
	const double parts[6] = {c->hasTarget ? c->target.x : NAN, c->hasTarget ? c->target.y : NAN,
	                         c->hasTarget ? c->target.z : NAN, c->hasDistance ? c->distance : NAN,
	                         c->hasYaw ? c->yaw : NAN,         c->hasPitch ? c->pitch : NAN};
	return s_app.hasScene && which >= 0 && which < 6 ? parts[which] : NAN;
}

/// Number of files the glue reads (fw_file_path).
FW_EXPORT int fw_file_count(void)
{
	return FW_FILE_COUNT;
}

/// The path of file @p k that the glue reads, relative to the repository (and to the page's
/// web/dist/, where scripts/web.sh copies them): the menu's scenes (fw_scene_file) for @p k below
/// fw_scene_count(), then data/house2.node and data/house2.ele, the mesh of "builtin:house2".
/// "" out of range.
FW_EXPORT const char* fw_file_path(int k)
{
	if (k == FW_FILE_HOUSE_NODE)
		return FW_HOUSE_NODE;
	return k == FW_FILE_HOUSE_ELE ? FW_HOUSE_ELE : fw_scene_file(k);
}

/// Give the glue file @p path, one of fw_file_path's (@p text need not be NUL-terminated): it
/// keeps a copy, in place of one given before. Another path is refused.
FW_EXPORT int fw_set_file(const char* path, const char* text, int size)
{
	int k = 0;
	while (k < FW_FILE_COUNT && (path == NULL || strcmp(path, fw_file_path(k)) != 0))
		++k;
	if (k == FW_FILE_COUNT)
	{
		snprintf(s_app.error, sizeof s_app.error, "%s: not a file the page reads (fw_file_path)",
		         path != NULL ? path : "");
		return fm_errParameter;
	}
	size_t n = size > 0 ? (size_t)size : 0;
	char* copy = malloc(n + 1);
	if (copy == NULL)
	{
		snprintf(s_app.error, sizeof s_app.error, "%s: out of memory", path);
		return fm_errOutOfMemory;
	}
	if (n > 0)
		memcpy(copy, text, n);
	copy[n] = 0;
	free(s_files[k].text);
	s_files[k] = (fwFile){copy, n};
	return fm_ok;
}

// File @p k as given, or NULL with fw_error() saying that it was not given yet.
static const fwFile* fwGivenFile(int k)
{
	if (s_files[k].text != NULL)
		return &s_files[k];
	snprintf(s_app.error, sizeof s_app.error, "%s was not given yet (fw_set_file)",
	         fw_file_path(k));
	return NULL;
}

// Whether a body of @p scene is "builtin:house2" while the house's files were not given; then
// fw_error() says so.
static bool fwLacksHouse(const char* name, const cliScene* scene)
{
	if (s_files[FW_FILE_HOUSE_NODE].text != NULL && s_files[FW_FILE_HOUSE_ELE].text != NULL)
		return false;
	for (int b = 0; b < scene->bodyCount; ++b)
		if (scene->bodies[b].meshSource == cli_meshHouse)
		{
			snprintf(s_app.error, sizeof s_app.error,
			         "%s: \"builtin:house2\" needs " FW_HOUSE_NODE " and " FW_HOUSE_ELE
			         ", not given yet (fw_set_file)",
			         name);
			return true;
		}
	return false;
}

/// Load the scene of a JSON text (docs/scene-format.md; need not be NUL-terminated) named
/// @p name in messages, read by the tool's own schema code; @p deterministic sets
/// fmWorldDef.crossPlatformDeterminism. A text the schema refuses, or one with what the page
/// cannot show (mesh files, colliders, pins, loads), or "builtin:house2" before its files were
/// given (fw_set_file), leaves the current scene and fw_error() says why ("name:line:column:
/// path: message").
FW_EXPORT int fw_load_scene_text(const char* name, const char* text, int size, int deterministic)
{
	cliScene scene;
	if (!fwReadScene(name, text, (size_t)(size > 0 ? size : 0), &scene))
		return fm_errParameter;
	if (fwLacksHouse(name, &scene))
	{
		cliScene_Free(&scene);
		return fm_errParameter;
	}
	fwFreeScene();
	s_app.scene = scene;
	s_app.hasScene = true;
	s_app.deterministic = deterministic != 0;
	return fwBuildScene();
}

/// Load built-in scene @p index: its file of scenes/ as given (fw_set_file), through
/// fw_load_scene_text; @p deterministic sets fmWorldDef.crossPlatformDeterminism.
FW_EXPORT int fw_load_scene(int index, int deterministic)
{
	if (index < 0 || index >= FW_SCENE_COUNT)
	{
		snprintf(s_app.error, sizeof s_app.error, "no scene %d", index);
		return fm_errParameter;
	}
	const fwFile* f = fwGivenFile(index);
	if (f == NULL)
		return fm_errParameter;
	return fw_load_scene_text(fw_scenes[index].file, f->text, (int)f->size, deterministic);
}

// Make a scene of a loaded mesh (@p r its reader's result): checked as fmCreateBody would check
// it, placed (scaled down to fit FW_USER_MESH_SIZE when bigger, centred, FW_USER_MESH_DROP above
// the floor) and given the world and material of the menu's first scene (the seeds' house, its
// file as given). A mesh that was not read or that fmBodyDef_Validate refuses (repeated nodes,
// flat tets), or a first scene not given yet, leaves the current scene.
static fmResult fwLoadUserMesh(fmResult r, fmTetMesh* mesh, fmDiagnostic* diag)
{
	if (r == fm_ok)
	{
		fmBodyDef check = fmDefaultBodyDef();
		check.mesh = mesh;
		r = fmBodyDef_Validate(&check, diag);
		if (r != fm_ok)
			fmFreeTetMesh(mesh);
	}
	if (r != fm_ok)
	{
		fwSetError("the mesh was refused", diag);
		return r;
	}
	// The menu's first scene (the seeds' house) with the mesh as its body.
	cliScene scene;
	const fwFile* house = fwGivenFile(0);
	if (house == NULL || !fwReadScene(fw_scenes[0].file, house->text, house->size, &scene))
	{
		fmFreeTetMesh(mesh);
		return fm_errParameter;
	}
	snprintf(s_app.warning, sizeof s_app.warning, "%s",
	         diag->warningCount > 0 ? diag->warning : "");
	fmVec3 lo = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	fmVec3 hi = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		const double* p = mesh->positions + 3 * i;
		lo = fmMakeVec3(fmin(lo.x, p[0]), fmin(lo.y, p[1]), fmin(lo.z, p[2]));
		hi = fmMakeVec3(fmax(hi.x, p[0]), fmax(hi.y, p[1]), fmax(hi.z, p[2]));
	}
	double size = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
	fmMeshTransform placement = fmDefaultMeshTransform();
	placement.scale = size > FW_USER_MESH_SIZE ? FW_USER_MESH_SIZE / size : 1.0;
	placement.center = true;
	fmTetMesh_Transform(mesh, &placement);
	double lowest = INFINITY;
	for (int i = 0; i < mesh->nodeCount; ++i)
		lowest = fmin(lowest, mesh->positions[3 * i + 1]);
	placement = fmDefaultMeshTransform();
	placement.translate =
	    fmMakeVec3(0.0, scene.worldDef.floor.height + FW_USER_MESH_DROP - lowest, 0.0);
	fmTetMesh_Transform(mesh, &placement);

	fmTetMesh previous = s_app.userMesh;
	s_app.userMesh = *mesh;
	fwFreeScene();
	s_app.scene = scene;
	s_app.hasScene = true;
	s_app.userBody = true;
	r = fwBuildScene();
	fmFreeTetMesh(&previous);
	return r;
}

/// Load a scene of a TetGen .node and .ele pair (the texts need not be NUL-terminated), read by
/// fmLoadTetGenFromMemory, placed as fwLoadUserMesh says. On failure the current scene stays
/// and fw_error() says where the files are wrong.
FW_EXPORT int fw_load_tetgen(const char* nodeText, int nodeSize, const char* eleText, int eleSize)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult r =
	    fmLoadTetGenFromMemory(nodeText, (size_t)(nodeSize > 0 ? nodeSize : 0), "node", eleText,
	                           (size_t)(eleSize > 0 ? eleSize : 0), "ele", &mesh, &diag);
	return fwLoadUserMesh(r, &mesh, &diag);
}

/// Load a scene of a one-file mesh: Gmsh .msh, VTK .vtk or .vtu, Medit .mesh, the format chosen
/// by @p name's extension (fmMeshFormatFromPath), read by fmLoadMeshFromMemory, placed as
/// fw_load_tetgen places its mesh. TetGen files come in pairs: fw_load_tetgen.
FW_EXPORT int fw_load_mesh(const char* name, const void* data, int size)
{
	fmMeshFormat format = fmMeshFormatFromPath(name);
	if (format == fm_meshFormatUnknown || format == fm_meshFormatTetGen)
	{
		snprintf(s_app.error, sizeof s_app.error,
		         "%s: expected a .msh, .vtk, .vtu or .mesh file, or a TetGen .node and .ele pair",
		         name != NULL ? name : "");
		return fm_errParameter;
	}
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult r =
	    fmLoadMeshFromMemory(data, (size_t)(size > 0 ? size : 0), name, format, &mesh, &diag);
	return fwLoadUserMesh(r, &mesh, &diag);
}

/// The warning of the last mesh loaded (e.g. the triangles a .msh file had beside its tets,
/// skipped), or "".
FW_EXPORT const char* fw_warning(void)
{
	return s_app.warning;
}

/// The reason of the last failure ("" after a success).
FW_EXPORT const char* fw_error(void)
{
	return s_app.error;
}

/// Bodies in the scene.
FW_EXPORT int fw_body_count(void)
{
	return s_app.bodyCount;
}

static bool fwBodyOk(int b)
{
	return b >= 0 && b < s_app.bodyCount;
}

/// Vertices of body @p b.
FW_EXPORT int fw_vertex_count(int b)
{
	return fwBodyOk(b) ? fmBody_GetVertexCount(s_app.bodies[b]) : 0;
}

/// Tets of body @p b.
FW_EXPORT int fw_tet_count(int b)
{
	return fwBodyOk(b) ? fmBody_GetTetCount(s_app.bodies[b]) : 0;
}

/// Surface triangles of body @p b (3 vertex indices each, counter-clockwise from outside).
FW_EXPORT const int* fw_surface(int b)
{
	return fwBodyOk(b) ? fmBody_GetSurface(s_app.bodies[b], NULL) : NULL;
}

/// Number of surface triangles of body @p b.
FW_EXPORT int fw_surface_count(int b)
{
	int count = 0;
	if (fwBodyOk(b))
		fmBody_GetSurface(s_app.bodies[b], &count);
	return count;
}

/// Copy body @p b's positions into its float buffer (3 a vertex) and return the buffer.
FW_EXPORT const float* fw_positions(int b)
{
	if (!fwBodyOk(b))
		return NULL;
	fmBody_CopyPositionsFloat(s_app.bodies[b], s_app.floatPositions[b],
	                          fmBody_GetVertexCount(s_app.bodies[b]));
	return s_app.floatPositions[b];
}

/// Copy body @p b's positions into its double buffer (the comparison's exact read-back).
FW_EXPORT const double* fw_positions_double(int b)
{
	if (!fwBodyOk(b))
		return NULL;
	fmBody_CopyPositions(s_app.bodies[b], s_app.doublePositions[b],
	                     fmBody_GetVertexCount(s_app.bodies[b]));
	return s_app.doublePositions[b];
}

/// The floor's height (m).
FW_EXPORT double fw_floor_height(void)
{
	return s_app.scene.worldDef.floor.height;
}

// One frame: whole, or substep by substep with the jump's impulses (as viewer/session.c).
static fmResult fwStepFrame(void)
{
	double frame = cliScene_FrameTime(&s_app.scene);
	int substeps = s_app.substeps;
	if (s_app.pendingJumps == 0)
		return fmWorld_Step(s_app.world, frame, substeps);
	fmVec3 kick = fmMakeVec3(0.0, s_app.pendingJumps * FW_JUMP_SPEED / substeps, 0.0);
	s_app.pendingJumps = 0;
	for (int k = 0; k < substeps; ++k)
	{
		for (int b = 0; b < s_app.bodyCount; ++b)
			fmBody_ApplyImpulse(s_app.bodies[b], kick);
		fmResult r = fmWorld_Step(s_app.world, frame / substeps, 1);
		if (r != fm_ok)
			return r;
	}
	return fm_ok;
}

/// Step one frame of the scene: the scene's frame time (its dt times its substeps) in
/// fw_set_substeps() substeps. On a failed step the library has restored the last good state
/// and fw_error() has its diagnostic.
FW_EXPORT int fw_step(void)
{
	if (!fmWorld_IsValid(s_app.world))
		return fm_errInvalidId;
	fmResult r = fwStepFrame();
	s_app.stepMs = fmWorld_GetProfile(s_app.world).step;
	if (r != fm_ok)
		fwSetError("the step failed", fmWorld_GetLastError(s_app.world));
	return r;
}

/// The library's wall time of the last fmWorld_Step (ms, fmProfile.step).
FW_EXPORT double fw_step_ms(void)
{
	return s_app.stepMs;
}

/// A stage of the last step's profile (ms, fmProfile): 0 step, 1 forces, 2 integrate, 3 solve,
/// 4 finish, 5 check, 6 contact, 7 broad phase, 8 narrow phase.
FW_EXPORT double fw_profile(int which)
{
	if (!fmWorld_IsValid(s_app.world))
		return 0.0;
	fmProfile p = fmWorld_GetProfile(s_app.world);
	const double stages[] = {p.step,  p.forces,  p.integrate,  p.solve,      p.finish,
	                         p.check, p.contact, p.broadPhase, p.narrowPhase};
	return which >= 0 && which < 9 ? stages[which] : 0.0;
}

/// Whether body @p b is awake (0 while its island sleeps: fmBody_IsAwake; the page dims it).
FW_EXPORT int fw_awake(int b)
{
	return fwBodyOk(b) ? fmBody_IsAwake(s_app.bodies[b]) : 0;
}

// The contacts' lines of the last fw_contact_lines(): 6 floats a line (point, tip), grown as
// needed and kept across scenes.
static float* s_contactLines;
static int s_contactLineCount, s_contactLineCapacity;

static void fwTakeContactLines(const float* points, int lineCount, fmHexColor color, void* context)
{
	(void)color;
	(void)context;
	if (s_contactLineCount + lineCount > s_contactLineCapacity)
	{
		int capacity = 2 * (s_contactLineCount + lineCount);
		float* grown = realloc(s_contactLines, 6 * sizeof(float) * (size_t)capacity);
		if (grown == NULL)
			return;
		s_contactLines = grown;
		s_contactLineCapacity = capacity;
	}
	memcpy(s_contactLines + 6 * (size_t)s_contactLineCount, points,
	       6 * sizeof(float) * (size_t)lineCount);
	s_contactLineCount += lineCount;
}

static void fwSkipPoints(const float* points, int count, float size, fmHexColor color,
                         void* context)
{
	(void)points, (void)count, (void)size, (void)color, (void)context;
}

/// The last substep's contacts as the library draws them (fmWorld_Draw, fm_drawContacts): from
/// each contact point a line along its normal, longer the harder it pushes; 6 floats a line
/// (point, tip, m), fw_contact_line_count() of them. Valid until the next call.
FW_EXPORT const float* fw_contact_lines(void)
{
	s_contactLineCount = 0;
	if (!fmWorld_IsValid(s_app.world))
		return s_contactLines;
	fmDebugDraw draw = fmDefaultDebugDraw();
	draw.flags = fm_drawContacts;
	draw.drawLines = fwTakeContactLines;
	draw.drawPoints = fwSkipPoints;
	fmWorld_Draw(s_app.world, &draw);
	return s_contactLines;
}

/// Lines fw_contact_lines() gave.
FW_EXPORT int fw_contact_line_count(void)
{
	return s_contactLineCount;
}

/// Queue the seeds' jump for the next frame.
FW_EXPORT void fw_jump(void)
{
	s_app.pendingJumps += 1;
}

/// Set the material of every body: model (fmMaterialModel), Young's modulus (Pa), Poisson ratio.
FW_EXPORT int fw_set_material(int model, double youngs, double poisson)
{
	if (model < 0 || model >= fm_stretchEnergy)
	{
		snprintf(s_app.error, sizeof s_app.error, "no material model %d", model);
		return fm_errParameter;
	}
	fmMaterial material = fmMakeMaterial((fmMaterialModel)model, youngs, poisson);
	// The scene's nodal pressure stays with the models that take it (as the viewer's sliders).
	material = cliKeepNodalPressure(material, s_app.scene.bodies[0].def.material.nodalPressure);
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult r = fmMaterial_Validate(&material, &diag);
	for (int b = 0; r == fm_ok && b < s_app.bodyCount; ++b)
		r = fmBody_SetMaterial(s_app.bodies[b], &material, &diag);
	if (r != fm_ok)
	{
		fwSetError("the material was refused", &diag);
		return r;
	}
	s_app.material = material;
	s_app.materialSet = true;
	s_app.model = (fmMaterialModel)model;
	s_app.youngs = youngs;
	s_app.poisson = poisson;
	return fm_ok;
}

/// The sliders' values: 0 model, 1 Young's modulus, 2 Poisson ratio, 3 damping, 4 substeps,
/// 5 integrator; 6 the scene's frame time (s).
FW_EXPORT double fw_get_param(int which)
{
	switch (which)
	{
	case 0:
		return s_app.model;
	case 1:
		return s_app.youngs;
	case 2:
		return s_app.poisson;
	case 3:
		return s_app.damping;
	case 4:
		return s_app.substeps;
	case 5:
		return s_app.integrator;
	case 6:
		return cliScene_FrameTime(&s_app.scene);
	default:
		return 0.0;
	}
}

/// Velocity damping factor per 3 ms, in (0, 1]: the bodies are made again in their current
// A grab on @p old goes on on @p made (the same body made again): the same point, the same
// target.
static void fwRegrab(fmBodyId old, fmBodyId made)
{
	fmVec3 point, target;
	if (!s_app.dragging || !fmBody_GetGrab(old, &point, &target))
		return;
	fmGrabDef def = fmDefaultGrabDef();
	if (fmBody_Grab(made, point, &def) != fm_ok || fmBody_MoveGrab(made, target) != fm_ok)
		s_app.dragging = false;
}

/// state (fmBodyDef.damping is fixed at creation).
FW_EXPORT int fw_set_damping(double damping)
{
	double previous = s_app.damping;
	s_app.damping = damping;
	for (int b = 0; b < s_app.bodyCount; ++b)
	{
		fmBodyDef def = fwBodyDef(&s_app, b);
		fmDiagnostic diag;
		memset(&diag, 0, sizeof diag);
		fmBodyId made;
		fmResult r = fmCreateBody(s_app.world, &def, &made, &diag);
		if (r != fm_ok)
		{
			s_app.damping = previous;
			fwSetError("the damping was refused", &diag);
			return r;
		}
		fmBodyId old = s_app.bodies[b];
		fwRegrab(old, made);
		double* state = s_app.doublePositions[b];
		fmBody_CopyPositions(old, state, fmBody_GetVertexCount(old));
		fmBody_SetPositions(made, state);
		fmBody_CopyVelocities(old, state, fmBody_GetVertexCount(old));
		fmBody_SetVelocities(made, state);
		fmDestroyBody(old);
		s_app.bodies[b] = made;
	}
	return fm_ok;
}

/// Substeps a frame, in [1, 1000]; the frame time stays the scene's (more substeps: shorter
/// ones, stable with stiffer materials).
FW_EXPORT int fw_set_substeps(int substeps)
{
	if (substeps < 1 || substeps > 1000)
	{
		snprintf(s_app.error, sizeof s_app.error, "substeps %d not in [1, 1000]", substeps);
		return fm_errParameter;
	}
	s_app.substeps = substeps;
	return fm_ok;
}

/// 0 explicit, 1 implicit (fmWorld_SetIntegrator).
FW_EXPORT void fw_set_integrator(int integrator)
{
	s_app.integrator = integrator != 0 ? fm_implicit : fm_explicit;
	if (fmWorld_IsValid(s_app.world))
		fmWorld_SetIntegrator(s_app.world, s_app.integrator);
}

/// Cast a ray (origin, direction times range) against the bodies; returns the body hit or -1.
/// fw_hit(0..3) then gives the vertex hit and the point.
FW_EXPORT int fw_pick(double ox, double oy, double oz, double dx, double dy, double dz)
{
	s_app.hitBody = -1;
	if (!fmWorld_IsValid(s_app.world) ||
	    !fmWorld_CastRay(s_app.world, fmMakeVec3(ox, oy, oz), fmMakeVec3(dx, dy, dz),
	                     fmDefaultFilter(), &s_app.hit))
		return -1;
	for (int b = 0; b < s_app.bodyCount; ++b)
		if (s_app.hit.body.index1 == s_app.bodies[b].index1 &&
		    s_app.hit.body.generation == s_app.bodies[b].generation)
			s_app.hitBody = b;
	return s_app.hitBody;
}

/// The last pick: 0 the vertex, 1-3 the point (m).
FW_EXPORT double fw_hit(int which)
{
	switch (which)
	{
	case 0:
		return s_app.hit.vertex;
	case 1:
		return s_app.hit.point.x;
	case 2:
		return s_app.hit.point.y;
	default:
		return s_app.hit.point.z;
	}
}

/// Start dragging body @p b at the point (x, y, z) on it (fw_pick's) with the library's grab
/// (fmBody_Grab, fmDefaultGrabDef(): the vertices around the point share a damped spring whose
/// whole pull is bounded, so no pointer speed breaks the body); fw_drag_move() moves its target.
FW_EXPORT int fw_drag_start(int b, double x, double y, double z)
{
	fw_drag_end();
	if (!fwBodyOk(b))
		return fm_errParameter;
	fmGrabDef def = fmDefaultGrabDef();
	fmResult r = fmBody_Grab(s_app.bodies[b], fmMakeVec3(x, y, z), &def);
	if (r != fm_ok)
	{
		fwSetError("the drag was refused", fmWorld_GetLastError(s_app.world));
		return r;
	}
	s_app.dragging = true;
	s_app.dragBody = b;
	return fm_ok;
}

/// Vertices the drag holds (0 when none).
FW_EXPORT int fw_drag_count(void)
{
	return s_app.dragging && fwBodyOk(s_app.dragBody)
	           ? fmBody_GetTargetCount(s_app.bodies[s_app.dragBody])
	           : 0;
}

/// Move the drag's target (m), reached over the next frame.
FW_EXPORT void fw_drag_move(double x, double y, double z)
{
	if (s_app.dragging && fwBodyOk(s_app.dragBody))
		fmBody_MoveGrab(s_app.bodies[s_app.dragBody], fmMakeVec3(x, y, z));
}

// The drag's spring of the last fw_grab_line(): the grabbed point, then the pointer's target.
static float s_grabLine[6];

/// The drag's spring as femto view draws it (fmBody_GetGrab, fm_drawTargets' grab): 6 floats,
/// the grabbed patch's point now and the pointer's target; NULL when nothing is dragged.
FW_EXPORT const float* fw_grab_line(void)
{
	fmVec3 point, target;
	if (!s_app.dragging || !fwBodyOk(s_app.dragBody) ||
	    !fmBody_GetGrab(s_app.bodies[s_app.dragBody], &point, &target))
		return NULL;
	const float line[6] = {(float)point.x,  (float)point.y,  (float)point.z,
	                       (float)target.x, (float)target.y, (float)target.z};
	memcpy(s_grabLine, line, sizeof line);
	return s_grabLine;
}

/// Let go.
FW_EXPORT void fw_drag_end(void)
{
	if (s_app.dragging && fwBodyOk(s_app.dragBody))
		fmBody_ReleaseGrab(s_app.bodies[s_app.dragBody]);
	s_app.dragging = false;
}

/// Bytes the page may write into with fw_alloc (a dropped file's text), freed by fw_free.
FW_EXPORT void* fw_alloc(int size)
{
	return size > 0 ? malloc((size_t)size) : NULL;
}

/// Free what fw_alloc gave.
FW_EXPORT void fw_free(void* memory)
{
	free(memory);
}
