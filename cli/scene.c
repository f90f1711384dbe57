// JSON scenes (docs/scene-format.md): the schema of a scene's top level (the world's settings,
// the floor, contact, colliders and the list of bodies, which scene_body.c reads), checked key
// by key with the kit in json_check.h, and the built-in bouncy house.
#include "scene.h"
#include "json_check.h"
#include "scene_body.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- colliders ------------------------------------------------------------------------------

// Collider shapes by scene name, with the keys each takes (the common ones included).
typedef struct cliShapeInfo
{
	const char* name;
	fmShapeType shape;
	const char* const* keys; // NULL-terminated
} cliShapeInfo;

#define CLI_COLLIDER_COMMON_KEYS                                                                   \
	"shape", "friction", "stick", "restitution", "velocity", "angular_velocity", "filter"
static const char* const cliPlaneKeys[] = {CLI_COLLIDER_COMMON_KEYS, "normal", "offset", NULL};
static const char* const cliSphereKeys[] = {CLI_COLLIDER_COMMON_KEYS, "center", "radius", NULL};
static const char* const cliBoxKeys[] = {CLI_COLLIDER_COMMON_KEYS, "center", "half_extents",
                                         "rotation", NULL};
static const char* const cliCapsuleKeys[] = {CLI_COLLIDER_COMMON_KEYS, "a", "b", "radius", NULL};
static const char* const cliMeshKeys[] = {CLI_COLLIDER_COMMON_KEYS, "path", "transform", "rotation",
                                          NULL};
static const cliShapeInfo cliShapes[] = {
    {"plane", fm_shapePlane, cliPlaneKeys}, {"sphere", fm_shapeSphere, cliSphereKeys},
    {"box", fm_shapeBox, cliBoxKeys},       {"capsule", fm_shapeCapsule, cliCapsuleKeys},
    {"mesh", fm_shapeMesh, cliMeshKeys},
};
#define CLI_SHAPE_NAMES "\"plane\", \"sphere\", \"box\", \"capsule\" or \"mesh\""

// Colliders' sizes and coordinates stay within the library's FM_MAX_COORDINATE.
static const cliRange cliLength = {0.0, FM_MAX_COORDINATE, true, false};
static const cliRange cliCoordinate = {-FM_MAX_COORDINATE, FM_MAX_COORDINATE, false, false};

static bool cliParseShapeName(const cliJson* j, const cliJsonNode* item, const char* path,
                              const cliShapeInfo** info)
{
	const char* name = NULL;
	if (!cliGetString(j, item, path, "shape", &name))
		return false;
	if (name == NULL)
		return cliJsonFail(j, path, NULL, "missing \"shape\": expected " CLI_SHAPE_NAMES);
	for (size_t i = 0; i < sizeof cliShapes / sizeof cliShapes[0]; ++i)
		if (strcmp(name, cliShapes[i].name) == 0)
		{
			*info = &cliShapes[i];
			return true;
		}
	char shapePath[256];
	cliJoinKey(shapePath, sizeof shapePath, path, "shape");
	return cliJsonFail(j, shapePath, cliJsonTree_Member(item, "shape"),
	                   "expected " CLI_SHAPE_NAMES);
}

static bool cliParsePlane(const cliJson* j, const cliJsonNode* item, const char* path,
                          fmColliderDef* d)
{
	static const char* const required[] = {"normal", NULL};
	const char* far = "3 numbers within 1e9";
	if (!cliRequireKeys(j, item, path, required,
	                    "a plane needs its normal; offset defaults to 0") ||
	    !cliGetVec3In(j, item, path, "normal", cliCoordinate, far, &d->normal) ||
	    !cliGetNumber(j, item, path, "offset", cliCoordinate, &d->offset, NULL))
		return false;
	if (d->normal.x != 0.0 || d->normal.y != 0.0 || d->normal.z != 0.0)
		return true;
	char normalPath[256];
	cliJoinKey(normalPath, sizeof normalPath, path, "normal");
	return cliJsonFail(j, normalPath, cliJsonTree_Member(item, "normal"),
	                   "expected a non-zero normal [x, y, z]");
}

static bool cliParseSolidShape(const cliJson* j, const cliJsonNode* item, const char* path,
                               fmShapeType shape, fmColliderDef* d)
{
	static const char* const sphere[] = {"center", "radius", NULL};
	static const char* const box[] = {"center", "half_extents", NULL};
	static const char* const capsule[] = {"a", "b", "radius", NULL};
	const char* far = "3 numbers within 1e9";
	const cliRange rotation = {-1e3, 1e3, false, false};
	switch (shape)
	{
	case fm_shapeSphere:
		return cliRequireKeys(j, item, path, sphere, "a sphere needs center and radius") &&
		       cliGetVec3In(j, item, path, "center", cliCoordinate, far, &d->center) &&
		       cliGetNumber(j, item, path, "radius", cliLength, &d->radius, NULL);
	case fm_shapeBox:
		return cliRequireKeys(j, item, path, box, "a box needs center and half_extents") &&
		       cliGetVec3In(j, item, path, "center", cliCoordinate, far, &d->center) &&
		       cliGetVec3In(j, item, path, "half_extents", cliLength, "3 numbers in (0, 1e9] (m)",
		                    &d->halfExtents) &&
		       cliGetVec3In(j, item, path, "rotation", rotation,
		                    "an axis-angle [x, y, z] in radians, each within 1000", &d->rotation);
	case fm_shapeCapsule:
		return cliRequireKeys(j, item, path, capsule, "a capsule needs a, b and radius") &&
		       cliGetVec3In(j, item, path, "a", cliCoordinate, far, &d->a) &&
		       cliGetVec3In(j, item, path, "b", cliCoordinate, far, &d->b) &&
		       cliGetNumber(j, item, path, "radius", cliLength, &d->radius, NULL);
	default:
		return false;
	}
}

// "path" (an OBJ file, relative to the scene's folder), "transform" and "rotation".
static bool cliParseMeshCollider(const cliJson* j, const cliJsonNode* item, const char* path,
                                 cliColliderSpec* spec)
{
	static const char* const required[] = {"path", NULL};
	const char* file = NULL;
	const cliRange rotation = {-1e3, 1e3, false, false};
	if (!cliRequireKeys(j, item, path, required, "a mesh collider needs an OBJ file") ||
	    !cliGetString(j, item, path, "path", &file) ||
	    !cliParseTransform(j, item, path, &spec->transform) ||
	    !cliGetVec3In(j, item, path, "rotation", rotation,
	                  "an axis-angle [x, y, z] in radians, each within 1000", &spec->def.rotation))
		return false;
	char filePath[256];
	cliJoinKey(filePath, sizeof filePath, path, "path");
	const cliJsonNode* fileItem = cliJsonTree_Member(item, "path");
	if (file[0] == 0)
		return cliJsonFail(j, filePath, fileItem, "expected the path of an OBJ file");
	return cliResolveFile(j, filePath, fileItem, file, spec->objPath, sizeof spec->objPath);
}

static bool cliParseCollider(const cliJson* j, const cliJsonNode* item, int index,
                             cliColliderSpec* spec)
{
	char path[64];
	snprintf(path, sizeof path, "colliders[%d]", index);
	if (!cliJsonIs(item, cli_jsonObject))
		return cliJsonFail(j, path, item, "expected a collider object {\"shape\": ...}");
	const cliShapeInfo* info = NULL;
	spec->def = fmDefaultColliderDef();
	spec->transform = fmDefaultMeshTransform();
	if (!cliParseShapeName(j, item, path, &info) || !cliCheckKeys(j, item, path, info->keys))
		return false;
	fmColliderDef* d = &spec->def;
	d->shape = info->shape;
	const cliRange speed = {-1e6, 1e6, false, false};
	const char* fast = "3 numbers within 1e6";
	bool shaped = info->shape == fm_shapePlane  ? cliParsePlane(j, item, path, d)
	              : info->shape == fm_shapeMesh ? cliParseMeshCollider(j, item, path, spec)
	                                            : cliParseSolidShape(j, item, path, d->shape, d);
	if (!shaped || !cliGetNumber(j, item, path, "friction", cliNonNegative, &d->friction, NULL) ||
	    !cliGetBool(j, item, path, "stick", &d->stick) ||
	    !cliGetNumber(j, item, path, "restitution", cliUnit, &d->restitution, NULL) ||
	    !cliGetVec3In(j, item, path, "velocity", speed, fast, &d->velocity) ||
	    !cliGetVec3In(j, item, path, "angular_velocity", speed, fast, &d->angularVelocity) ||
	    !cliParseFilter(j, item, path, &d->filter))
		return false;
	// A mesh's triangles come when the scene is built; its def is checked then.
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (d->shape != fm_shapeMesh && fmColliderDef_Validate(d, &diag) != fm_ok)
		return cliJsonFail(j, path, NULL, "%s", diag.message);
	return true;
}

static bool cliParseColliders(const cliJson* j, const cliJsonNode* root, cliScene* scene)
{
	const cliJsonNode* list = cliJsonTree_Member(root, "colliders");
	if (list == NULL)
		return true;
	if (!cliJsonIs(list, cli_jsonArray))
		return cliJsonFail(j, "colliders", list, "expected a list of collider objects");
	int count = (list)->count;
	if (count > FM_MAX_COLLIDERS)
		return cliJsonFail(j, "colliders", NULL, "%d colliders, at most %d", count,
		                   FM_MAX_COLLIDERS);
	scene->colliders = calloc((size_t)(count > 0 ? count : 1), sizeof *scene->colliders);
	if (scene->colliders == NULL)
		return cliJsonFail(j, "colliders", NULL, "out of memory");
	const cliJsonNode* item = NULL;
	for (item = (list)->child; item != NULL; item = item->next)
	{
		int i = scene->colliderCount++;
		if (!cliParseCollider(j, item, i, &scene->colliders[i]))
			return false;
	}
	return true;
}

// ---- contact ----------------------------------------------------------------------------------

// "contact": body-body contact and sleeping (fmContactDef).
static bool cliParseContact(const cliJson* j, const cliJsonNode* root, fmContactDef* def)
{
	static const char* const keys[] = {"bodies",      "thickness",  "friction",
	                                   "restitution", "iterations", "sleep",
	                                   "sleep_speed", "sleep_time", NULL};
	const cliRange below1e6 = {0.0, 1e6, true, true};
	const cliJsonNode* item = NULL;
	if (!cliGetObject(j, root, "", "contact", &item))
		return false;
	return item == NULL ||
	       (cliCheckKeys(j, item, "contact", keys) &&
	        cliGetBool(j, item, "contact", "bodies", &def->bodies) &&
	        cliGetNumber(j, item, "contact", "thickness", below1e6, &def->thickness, NULL) &&
	        cliGetNumber(j, item, "contact", "friction", cliNonNegative, &def->friction, NULL) &&
	        cliGetNumber(j, item, "contact", "restitution", cliUnit, &def->restitution, NULL) &&
	        cliGetInt(j, item, "contact", "iterations", 1, 64, &def->iterations, NULL) &&
	        cliGetBool(j, item, "contact", "sleep", &def->enableSleep) &&
	        cliGetNumber(j, item, "contact", "sleep_speed", below1e6, &def->sleepSpeed, NULL) &&
	        cliGetNumber(j, item, "contact", "sleep_time", below1e6, &def->sleepTime, NULL));
}

// ---- the world ------------------------------------------------------------------------------

// "tolerance": a number, or a preset: "accurate" (1e-6) or "game" (1e-2).
static bool cliGetTolerance(const cliJson* j, const cliJsonNode* root, cliRange range,
                            double* value)
{
	const cliJsonNode* item = cliJsonTree_Member(root, "tolerance");
	if (cliJsonIs(item, cli_jsonString) && strcmp(item->string, "accurate") == 0)
		*value = FM_TOLERANCE_ACCURATE;
	else if (cliJsonIs(item, cli_jsonString) && strcmp(item->string, "game") == 0)
		*value = FM_TOLERANCE_GAME;
	else if (cliJsonIs(item, cli_jsonString))
		return cliJsonFail(j, "tolerance", item,
		                   "expected \"accurate\", \"game\" or a number in [1e-12, 1)");
	else
		return cliGetNumber(j, root, "", "tolerance", range, value, NULL);
	return true;
}

static bool cliParseFloor(const cliJson* j, const cliJsonNode* root, fmFloorDef* floorDef)
{
	static const char* const keys[] = {
	    "height", "friction", "restitution", "max_depenetration_speed", "filter", NULL};
	const cliJsonNode* item = cliJsonTree_Member(root, "floor");
	if (item == NULL)
		return true;
	if ((cliJsonIs(item, cli_jsonBool) && !item->boolean))
	{
		floorDef->enabled = false;
		return true;
	}
	if (!cliJsonIs(item, cli_jsonObject))
		return cliJsonFail(j, "floor", item, "expected an object {\"height\": ...} or false");
	floorDef->enabled = true;
	if (!cliCheckKeys(j, item, "floor", keys) ||
	    !cliGetNumber(j, item, "floor", "height", cliAnyFinite, &floorDef->height, NULL) ||
	    !cliGetNumber(j, item, "floor", "restitution", cliUnit, &floorDef->restitution, NULL) ||
	    !cliGetNumber(j, item, "floor", "max_depenetration_speed", cliPositive,
	                  &floorDef->maxDepenetrationSpeed, NULL) ||
	    !cliParseFilter(j, item, "floor", &floorDef->filter))
		return false;
	const cliJsonNode* friction = cliJsonTree_Member(item, "friction");
	if (friction == NULL)
		return true;
	if (cliJsonIs(friction, cli_jsonString) && strcmp(friction->string, "stick") == 0)
	{
		floorDef->friction = fm_floorStick;
		return true;
	}
	if (!cliJsonIs(friction, cli_jsonNumber) || !cliInRange(friction->number, cliNonNegative))
		return cliJsonFail(j, "floor.friction", friction,
		                   "expected \"stick\" or a Coulomb coefficient >= 0");
	floorDef->friction = fm_floorCoulomb;
	floorDef->frictionCoefficient = friction->number;
	return true;
}

// The frame length of a scene with automatic substeps that gives no "dt": a 60 Hz frame.
#define CLI_AUTO_FRAME (1.0 / 60.0)

// "substeps": a count, or "auto"; an explicit scene without it is "auto" too. Automatic substeps
// (fmWorldDef.autoSubstep) make "dt" the frame length (default 1/60 s): each frame is split into
// steps of at most 0.3 of the estimated stability limit at the current deformation, so a mesh
// with slivers or a stiff material is stable without tuning (docs/scene-format.md).
static bool cliParseSubsteps(const cliJson* j, const cliJsonNode* root, cliScene* scene)
{
	const cliJsonNode* item = cliJsonTree_Member(root, "substeps");
	bool automatic = item == NULL && scene->worldDef.integrator == fm_explicit;
	if (cliJsonIs(item, cli_jsonString))
	{
		if (item->string == NULL || strcmp(item->string, "auto") != 0)
			return cliJsonFail(j, "substeps", item,
			                   "expected a whole number in [1, 100000] or \"auto\"");
		if (scene->worldDef.integrator != fm_explicit)
			return cliJsonFail(j, "substeps", item,
			                   "\"auto\" is for the explicit integrator (an implicit step is "
			                   "stable at any size: give a count)");
		automatic = true;
	}
	else if (!cliGetInt(j, root, "", "substeps", 1, 100000, &scene->substeps, NULL))
		return false;
	if (!automatic)
		return true;
	scene->worldDef.autoSubstep = true;
	scene->substeps = 1;
	if (cliJsonTree_Member(root, "dt") == NULL)
		scene->dt = CLI_AUTO_FRAME;
	return true;
}

// The world's "not_converged", "implicit_solver" and "simd" strings (read by cliParseWorld).
static bool cliParseSolverNames(const cliJson* j, const cliJsonNode* root, const char* notConverged,
                                const char* solver, const char* simd, fmWorldDef* def)
{
	if (notConverged != NULL)
	{
		if (strcmp(notConverged, "warn") != 0 && strcmp(notConverged, "error") != 0)
			return cliJsonFail(j, "not_converged", cliJsonTree_Member(root, "not_converged"),
			                   "expected \"warn\" or \"error\"");
		def->notConvergedIsError = strcmp(notConverged, "error") == 0;
	}
	if (solver != NULL)
	{
		if (strcmp(solver, "newton") != 0 && strcmp(solver, "vbd") != 0)
			return cliJsonFail(j, "implicit_solver", cliJsonTree_Member(root, "implicit_solver"),
			                   "expected \"newton\" or \"vbd\"");
		def->implicitSolver = strcmp(solver, "vbd") == 0 ? fm_solverVbd : fm_solverNewton;
	}
	if (simd != NULL && !fmSimdLevelFromName(simd, &def->simd))
		return cliJsonFail(j, "simd", cliJsonTree_Member(root, "simd"),
		                   "expected \"auto\", \"off\", \"scalar\", \"sse2\", \"avx2\" or "
		                   "\"avx512\"");
	return true;
}

static bool cliParseWorld(const cliJson* j, const cliJsonNode* root, cliScene* scene)
{
	fmWorldDef* def = &scene->worldDef;
	const cliRange dtRange = {0.0, 10.0, true, false};
	const cliRange secondsRange = {0.0, 1e6, true, false};
	bool hasFrames = false, hasSeconds = false;
	const char* integrator = NULL;
	const char* notConverged = NULL;
	const char* simd = NULL;
	const char* solver = NULL;
	const cliRange toleranceRange = {FM_MIN_TOLERANCE, 1.0, false, true};
	const cliRange budgetRange = {0.0, 1e9, true, false};
	double budgetMiB = 0.0;
	bool hasBudget = false;
	if (!cliGetVec3(j, root, "", "gravity", &def->gravity, NULL) ||
	    !cliGetNumber(j, root, "", "dt", dtRange, &scene->dt, NULL) ||
	    !cliGetInt(j, root, "", "frames", 1, CLI_MAX_FRAMES, &scene->frames, &hasFrames) ||
	    !cliGetNumber(j, root, "", "seconds", secondsRange, &scene->seconds, &hasSeconds) ||
	    !cliGetString(j, root, "", "integrator", &integrator) ||
	    !cliGetInt(j, root, "", "newton_iterations", 1, FM_MAX_NEWTON_ITERATIONS,
	               &def->newtonIterations, NULL) ||
	    !cliGetTolerance(j, root, toleranceRange, &def->tolerance) ||
	    !cliGetInt(j, root, "", "cg_iterations", 1, FM_MAX_CG_ITERATIONS, &def->cgIterations,
	               NULL) ||
	    !cliGetString(j, root, "", "not_converged", &notConverged) ||
	    !cliGetString(j, root, "", "simd", &simd) ||
	    !cliGetString(j, root, "", "implicit_solver", &solver) ||
	    !cliGetBool(j, root, "", "auto_substep", &def->autoSubstep) ||
	    !cliGetBool(j, root, "", "deterministic", &def->crossPlatformDeterminism) ||
	    !cliGetNumber(j, root, "", "memory_budget_mib", budgetRange, &budgetMiB, &hasBudget) ||
	    !cliGetInt(j, root, "", "workers", 1, FM_MAX_WORKERS, &def->workerCount,
	               &scene->hasWorkers) ||
	    !cliGetInt(j, root, "", "max_newton_per_frame", 1, INT_MAX, &def->maxNewtonPerFrame,
	               NULL) ||
	    !cliGetInt(j, root, "", "max_substeps_per_frame", 1, FM_MAX_SUBSTEPS,
	               &def->maxSubstepsPerFrame, NULL) ||
	    !cliParseFloor(j, root, &def->floor) || !cliParseContact(j, root, &def->contact))
		return false;
	if (hasBudget)
		def->memoryBudget = (size_t)(budgetMiB * 1048576.0);
	if (!cliParseSolverNames(j, root, notConverged, solver, simd, def))
		return false;
	if (hasFrames && hasSeconds)
		return cliJsonFail(j, "seconds", NULL, "give frames or seconds, not both");
	if (integrator != NULL)
	{
		if (strcmp(integrator, "explicit") == 0)
			def->integrator = fm_explicit;
		else if (strcmp(integrator, "implicit") == 0)
			def->integrator = fm_implicit;
		else
			return cliJsonFail(j, "integrator", cliJsonTree_Member(root, "integrator"),
			                   "expected \"explicit\" or \"implicit\"");
	}
	if (!cliParseSubsteps(j, root, scene))
		return false;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmWorldDef_Validate(def, &diag) != fm_ok)
		return cliJsonFail(j, "", NULL, "%s", diag.message);
	return true;
}

// ---- how the samples are shown --------------------------------------------------------------

const char* const cliTopicNames[CLI_TOPIC_COUNT] = {"materials", "integrators", "contact",
                                                    "colliders", "loads",       "render meshes"};

// "topic": one of cliTopicNames.
static bool cliParseTopic(const cliJson* j, const cliJsonNode* root, cliScene* scene)
{
	const char* topic = NULL;
	scene->topic = -1;
	if (!cliGetString(j, root, "", "topic", &topic))
		return false;
	if (topic == NULL)
		return true;
	for (int k = 0; k < CLI_TOPIC_COUNT; ++k)
		if (strcmp(topic, cliTopicNames[k]) == 0)
			scene->topic = k;
	if (scene->topic < 0)
		return cliJsonFail(j, "topic", cliJsonTree_Member(root, "topic"),
		                   "expected one of \"materials\", \"integrators\", \"contact\", "
		                   "\"colliders\", \"loads\", \"render meshes\"");
	return true;
}

// "camera": {"target": [x, y, z], "distance": m, "yaw": deg, "pitch": deg}, each optional, with
// the ranges of femto view's --camera-* options.
static bool cliParseCamera(const cliJson* j, const cliJsonNode* root, cliCameraPreset* camera)
{
	static const char* const keys[] = {"target", "distance", "yaw", "pitch", NULL};
	const cliRange distance = {1e-3, 1e6, false, false};
	const cliRange yaw = {-360.0, 360.0, false, false};
	const cliRange pitch = {-89.0, 89.0, false, false};
	const cliJsonNode* item = NULL;
	memset(camera, 0, sizeof *camera);
	if (!cliGetObject(j, root, "", "camera", &item))
		return false;
	return item == NULL ||
	       (cliCheckKeys(j, item, "camera", keys) &&
	        cliGetVec3(j, item, "camera", "target", &camera->target, &camera->hasTarget) &&
	        cliGetNumber(j, item, "camera", "distance", distance, &camera->distance,
	                     &camera->hasDistance) &&
	        cliGetNumber(j, item, "camera", "yaw", yaw, &camera->yaw, &camera->hasYaw) &&
	        cliGetNumber(j, item, "camera", "pitch", pitch, &camera->pitch, &camera->hasPitch));
}

static bool cliParseScene(const cliJson* j, const cliJsonNode* root, cliScene* scene)
{
	static const char* const keys[] = {"description",
	                                   "gravity",
	                                   "dt",
	                                   "substeps",
	                                   "frames",
	                                   "seconds",
	                                   "integrator",
	                                   "newton_iterations",
	                                   "tolerance",
	                                   "cg_iterations",
	                                   "floor",
	                                   "bodies",
	                                   "not_converged",
	                                   "auto_substep",
	                                   "memory_budget_mib",
	                                   "workers",
	                                   "max_newton_per_frame",
	                                   "max_substeps_per_frame",
	                                   "simd",
	                                   "implicit_solver",
	                                   "deterministic",
	                                   "colliders",
	                                   "contact",
	                                   "topic",
	                                   "camera",
	                                   NULL};
	if (!cliJsonIs(root, cli_jsonObject))
		return cliJsonFail(j, "", root, "a scene is a JSON object {...}");
	const char* description = NULL;
	if (!cliCheckKeys(j, root, "", keys) ||
	    !cliGetString(j, root, "", "description", &description) || !cliParseTopic(j, root, scene) ||
	    !cliParseCamera(j, root, &scene->camera) || !cliParseWorld(j, root, scene))
		return false;
	if (description != NULL)
		snprintf(scene->description, sizeof scene->description, "%s", description);
	const cliJsonNode* bodies = cliJsonTree_Member(root, "bodies");
	if (bodies == NULL)
		return cliJsonFail(j, "", NULL, "missing \"bodies\": a scene needs at least one body");
	int count = cliJsonIs(bodies, cli_jsonArray) ? (bodies)->count : 0;
	if (count < 1)
		return cliJsonFail(j, "bodies", bodies, "expected a non-empty list of bodies");
	if (count > scene->worldDef.maxBodies)
		return cliJsonFail(j, "bodies", NULL, "%d bodies, at most %d", count,
		                   scene->worldDef.maxBodies);
	scene->bodies = calloc((size_t)count, sizeof *scene->bodies);
	if (scene->bodies == NULL)
		return cliJsonFail(j, "bodies", NULL, "out of memory");
	const cliJsonNode* body = NULL;
	for (body = (bodies)->child; body != NULL; body = body->next)
	{
		int i = scene->bodyCount++; // so cliScene_Free releases what was parsed
		if (!cliParseBody(j, body, i, &scene->bodies[i]))
			return false;
	}
	return cliParseColliders(j, root, scene);
}

// ---- public ---------------------------------------------------------------------------------

static void cliSceneDefaults(cliScene* scene, const char* name)
{
	memset(scene, 0, sizeof *scene);
	snprintf(scene->name, sizeof scene->name, "%s", name);
	scene->worldDef = fmDefaultWorldDef();
	scene->dt = 0.003;
	scene->substeps = 10;
	scene->topic = -1;
}

void cliScene_MakeHouse(cliScene* scene)
{
	cliSceneDefaults(scene, "builtin:house");
	scene->seconds = 5.0;
	// Every value spelled out, so a change of library defaults cannot change the demo.
	fmWorldDef* world = &scene->worldDef;
	world->gravity = fmMakeVec3(0.0, -9.8, 0.0);
	world->integrator = fm_explicit;
	world->floor.enabled = true;
	world->floor.height = -3.0;
	world->floor.friction = fm_floorStick;
	scene->bodies = calloc(1, sizeof *scene->bodies);
	if (scene->bodies == NULL)
		return;
	scene->bodyCount = 1;
	cliBodySpec* body = &scene->bodies[0];
	body->meshSource = cli_meshHouse;
	body->transform = fmDefaultMeshTransform();
	body->transform.scale = 0.4;
	body->transform.center = true;
	body->transform.swapYZ = true;
	body->def = fmDefaultBodyDef();
	body->def.material = fmMakeMaterialLame(fm_stvk, 20000.0, 5000.0);
	body->def.forceModel = fm_fem;
	body->def.massMode = fm_massPerParticle;
	body->def.particleMass = 1.0;
	body->def.damping = 0.999;
	body->def.smoothing = 0.1;
	body->def.rayleighMass = 0.0;
	body->def.rayleighStiffness = 0.0;
	body->initialVelocity = fmMakeVec3(0, 0, 0);
}

bool cliScene_Load(const char* path, cliScene* scene)
{
	cliSceneDefaults(scene, path);
	size_t size = 0;
	char* text = cliReadFile(path, &size);
	if (text == NULL)
		return false;
	bool ok = cliScene_LoadText(path, text, size, stderr, scene);
	free(text);
	return ok;
}

bool cliScene_LoadText(const char* name, const char* text, size_t size, FILE* messages,
                       cliScene* scene)
{
	cliSceneDefaults(scene, name);
	cliJson j;
	cliJsonNode* root = cliJsonOpen(&j, name, text, size, messages);
	bool ok = root != NULL && cliParseScene(&j, root, scene);
	cliJsonClose(&j, root);
	if (!ok)
		cliScene_Free(scene);
	return ok;
}

void cliScene_Free(cliScene* scene)
{
	for (int i = 0; i < scene->bodyCount; ++i)
	{
		free(scene->bodies[i].pins);
		free(scene->bodies[i].loads);
		free(scene->bodies[i].pressures);
		free(scene->bodies[i].attachments);
		free(scene->bodies[i].welds);
		free(scene->bodies[i].regionMaterials);
		free(scene->bodies[i].regionIds);
	}
	free(scene->bodies);
	scene->bodies = NULL;
	scene->bodyCount = 0;
	free(scene->colliders);
	scene->colliders = NULL;
	scene->colliderCount = 0;
}

double cliScene_FrameTime(const cliScene* scene)
{
	return scene->dt * scene->substeps;
}
