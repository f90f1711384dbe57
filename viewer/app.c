// The viewer's state and input (app.h).
#include "app.h"

#include "view_options.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Add one entry to the scene list with its topic (cliTopicNames; -1 none); false when memory
// is short.
static bool fvAddScene(fvApp* app, const char* name, const char* path, int topic)
{
	char** names = realloc(app->sceneNames, (size_t)(app->sceneCount + 1) * sizeof *names);
	if (names != NULL)
		app->sceneNames = names;
	char** paths = realloc(app->scenePaths, (size_t)(app->sceneCount + 1) * sizeof *paths);
	if (paths != NULL)
		app->scenePaths = paths;
	int* topics = realloc(app->sceneTopics, (size_t)(app->sceneCount + 1) * sizeof *topics);
	if (topics != NULL)
		app->sceneTopics = topics;
	if (names == NULL || paths == NULL || topics == NULL)
		return false;
	names[app->sceneCount] = strdup(name);
	paths[app->sceneCount] = path != NULL ? strdup(path) : NULL;
	topics[app->sceneCount] = topic;
	app->sceneCount += 1;
	return names[app->sceneCount - 1] != NULL;
}

// The "topic" of the scene file @p path (a cliTopicNames index), -1 when it has none or does
// not load (it is still listed: picking it says why).
static int fvSceneTopic(const char* path)
{
	const size_t most = 1u << 20; // scene files are a few kB; a longer one reads as no topic
	FILE* f = fopen(path, "rb");
	char* text = f != NULL ? malloc(most) : NULL;
	size_t size = text != NULL ? fread(text, 1, most, f) : 0;
	bool whole = text != NULL && feof(f) != 0;
	if (f != NULL)
		fclose(f);
	cliScene scene;
	int topic = -1;
	if (whole && cliScene_LoadText(path, text, size, NULL, &scene))
	{
		topic = scene.topic;
		cliScene_Free(&scene);
	}
	free(text);
	return topic;
}

// A scene file of the listed folder, sorted by topic (in cliTopicNames' order, none last),
// then by name.
typedef struct fvFoundScene
{
	char* name;
	int topic;
} fvFoundScene;

static int fvCompareScenes(const void* a, const void* b)
{
	const fvFoundScene *x = a, *y = b;
	int tx = x->topic >= 0 ? x->topic : CLI_TOPIC_COUNT;
	int ty = y->topic >= 0 ? y->topic : CLI_TOPIC_COUNT;
	return tx != ty ? tx - ty : strcmp(x->name, y->name);
}

// The .json files of @p folder grouped by topic, after the built-in house.
static void fvListScenes(fvApp* app, const char* folder)
{
	fvAddScene(app, "(built-in house)", NULL, -1);
	DIR* dir = folder != NULL ? opendir(folder) : NULL;
	if (dir == NULL)
		return;
	fvFoundScene found[256];
	int count = 0;
	for (struct dirent* e = readdir(dir); e != NULL && count < 256; e = readdir(dir))
	{
		size_t length = strlen(e->d_name);
		char path[CLI_MAX_PATH];
		if (length > 5 && strcmp(e->d_name + length - 5, ".json") == 0 && e->d_name[0] != '.' &&
		    cliJoinPath(path, sizeof path, folder, e->d_name) &&
		    (found[count].name = strdup(e->d_name)) != NULL)
			found[count++].topic = fvSceneTopic(path);
	}
	closedir(dir);
	qsort(found, (size_t)count, sizeof *found, fvCompareScenes);
	for (int i = 0; i < count; ++i)
	{
		char path[CLI_MAX_PATH];
		if (cliJoinPath(path, sizeof path, folder, found[i].name))
			fvAddScene(app, found[i].name, path, found[i].topic);
		free(found[i].name);
	}
}

// The list entry of @p path (same file name in the listed folder), 0 (the house) if none.
static int fvFindScene(const fvApp* app, const char* path)
{
	if (path == NULL)
		return 0;
	const char* base = strrchr(path, '/');
	base = base != NULL ? base + 1 : path;
	for (int i = 1; i < app->sceneCount; ++i)
		if (strcmp(app->sceneNames[i], base) == 0)
			return i;
	return -1;
}

bool fvApp_Init(fvApp* app, const char* scenePath, const char* sceneFolder, unsigned drawFlags)
{
	memset(app, 0, sizeof *app);
	fvDrawList_Init(&app->list);
	app->drawFlags = drawFlags;
	app->camera = fvCamera_Default();
	app->width = app->height = 1;
	if (!fvSession_Load(&app->session, scenePath))
		return false;
	fvListScenes(app, sceneFolder);
	app->sceneIndex = fvFindScene(app, scenePath);
	if (app->sceneIndex < 0 && scenePath != NULL &&
	    fvAddScene(app, scenePath, scenePath, app->session.scene.topic))
		app->sceneIndex = app->sceneCount - 1;
	return true;
}

void fvApp_Free(fvApp* app)
{
	fvSession_Free(&app->session);
	fvDrawList_Free(&app->list);
	for (int i = 0; i < app->sceneCount; ++i)
	{
		free(app->sceneNames[i]);
		free(app->scenePaths[i]);
	}
	free(app->sceneNames);
	free(app->scenePaths);
	free(app->sceneTopics);
	memset(app, 0, sizeof *app);
}

void fvApp_Capture(fvApp* app)
{
	// With the drag's targets drawn too, so the pulled spring shows.
	// Picking uses the drawn surfaces: with surfaces off, nothing can be grabbed.
	unsigned flags = app->drawFlags | (app->session.dragging ? fm_drawTargets : 0u);
	if (fvSession_IsLive(&app->session))
		fvDrawList_Capture(&app->list, app->session.sim.world, flags);
	else
		fvDrawList_Clear(&app->list);
}

void fvApp_FrameCamera(fvApp* app)
{
	fvApp_Capture(app);
	float lo[3], hi[3];
	float free = fmaxf((float)app->width - app->panelRight, 0.25f * (float)app->width);
	if (fvDrawList_FramingBox(&app->list, lo, hi))
		fvCamera_Frame(&app->camera, lo, hi, free / (float)app->height);
	fvApp_KeepCameraAbove(app);
}

void fvApp_PlaceCamera(fvApp* app, const cliViewOptions* given)
{
	cliViewOptions o;
	cliViewOptions_Init(&o);
	if (given != NULL)
		o = *given;
	cliViewOptions_TakeCamera(&o, &app->session.scene.camera);
	fvCamera* camera = &app->camera;
	if (o.hasYaw)
		camera->yaw = (float)o.yaw;
	if (o.hasPitch)
		camera->pitch = (float)o.pitch;
	fvApp_FrameCamera(app);
	if (o.hasTarget)
		camera->target[0] = (float)o.target.x, camera->target[1] = (float)o.target.y,
		camera->target[2] = (float)o.target.z;
	if (o.hasDistance)
		camera->distance = (float)o.distance;
	fvApp_KeepCameraAbove(app);
	app->cameraGiven = o.hasTarget || o.hasDistance;
}

void fvApp_SetPanel(fvApp* app, float panelRight)
{
	float width = (float)(app->width > 0 ? app->width : 1);
	app->panelRight = fminf(fmaxf(panelRight, 0.0f), 0.75f * width);
	app->camera.shiftX = app->panelRight / width; // the middle of [panelRight, width]
}

void fvApp_KeepCameraAbove(fvApp* app)
{
	if (app->list.hasPlane)
		fvCamera_KeepAbove(&app->camera, app->list.planePoint, app->list.planeNormal);
}

int fvApp_FindScene(const fvApp* app, const char* name)
{
	for (int i = 0; i < app->sceneCount; ++i)
		if (strcmp(app->sceneNames[i], name) == 0)
			return i;
	return -1;
}

void fvApp_SelectScene(fvApp* app, int index)
{
	if (index < 0 || index >= app->sceneCount)
		return;
	fvSession next;
	if (!fvSession_Load(&next, app->scenePaths[index]))
	{
		snprintf(app->session.status, sizeof app->session.status,
		         "%s does not load (the reason is on stderr)", app->sceneNames[index]);
		return;
	}
	fvSession_Free(&app->session);
	app->session = next;
	app->sceneIndex = index;
	app->mouse = fv_mouseNone;
	fvApp_PlaceCamera(app, NULL);
}

// The point where the cursor's ray meets the plane through app->grabPlane facing the camera.
static bool fvCursorOnGrabPlane(const fvApp* app, float x, float y, float point[3])
{
	float origin[3], direction[3], eye[3], normal[3];
	fvCamera_Ray(&app->camera, app->width, app->height, x, y, origin, direction);
	fvCamera_Eye(&app->camera, eye);
	float length = 0.0f;
	for (int i = 0; i < 3; ++i)
	{
		normal[i] = app->camera.target[i] - eye[i];
		length += normal[i] * normal[i];
	}
	float along = 0.0f, toPlane = 0.0f;
	for (int i = 0; i < 3; ++i)
	{
		normal[i] /= sqrtf(length);
		along += direction[i] * normal[i];
		toPlane += (app->grabPlane[i] - origin[i]) * normal[i];
	}
	if (fabsf(along) < 1e-6f)
		return false;
	float t = toPlane / along;
	for (int i = 0; i < 3; ++i)
		point[i] = origin[i] + t * direction[i];
	return t > 0.0f;
}

// How far a press's ray reaches (m).
#define FV_GRAB_RANGE 1e4f

// Left press: grab the body under the cursor (the library's ray and grab), or orbit.
static void fvPress(fvApp* app, float x, float y)
{
	float origin[3], direction[3];
	fvCamera_Ray(&app->camera, app->width, app->height, x, y, origin, direction);
	fmVec3 point;
	if (!fvSession_Grab(&app->session, fmMakeVec3(origin[0], origin[1], origin[2]),
	                    fmMakeVec3(FV_GRAB_RANGE * direction[0], FV_GRAB_RANGE * direction[1],
	                               FV_GRAB_RANGE * direction[2]),
	                    &point))
	{
		app->mouse = fv_mouseOrbit;
		return;
	}
	// The grabbed point follows the cursor on the plane through it facing the camera.
	app->grabPlane[0] = (float)point.x, app->grabPlane[1] = (float)point.y;
	app->grabPlane[2] = (float)point.z;
	app->mouse = fv_mouseDrag;
}

void fvApp_MouseButton(fvApp* app, int button, bool down, float x, float y)
{
	if (down && app->uiWantsMouse != NULL && app->uiWantsMouse())
		return;
	app->cursor[0] = x, app->cursor[1] = y;
	if (!down)
	{
		if (app->mouse == fv_mouseDrag)
			fvSession_Release(&app->session);
		app->mouse = fv_mouseNone;
		return;
	}
	if (button == 0)
		fvPress(app, x, y);
	else
		app->mouse = fv_mousePan;
}

void fvApp_MouseMove(fvApp* app, float x, float y)
{
	float dx = x - app->cursor[0], dy = y - app->cursor[1];
	app->cursor[0] = x, app->cursor[1] = y;
	float target[3];
	switch (app->mouse)
	{
	case fv_mouseOrbit:
		fvCamera_Orbit(&app->camera, dx, dy);
		fvApp_KeepCameraAbove(app);
		break;
	case fv_mousePan:
		fvCamera_Pan(&app->camera, dx, dy, app->height);
		fvApp_KeepCameraAbove(app);
		break;
	case fv_mouseDrag:
		if (fvCursorOnGrabPlane(app, x, y, target))
			fvSession_MoveGrab(&app->session, fmMakeVec3(target[0], target[1], target[2]));
		break;
	case fv_mouseNone:
		break;
	}
}

void fvApp_Scroll(fvApp* app, float steps)
{
	if (app->uiWantsMouse == NULL || !app->uiWantsMouse())
		fvCamera_Zoom(&app->camera, steps);
	fvApp_KeepCameraAbove(app);
}

// M: the next of the five built-in models.
static void fvNextModel(fvApp* app)
{
	fvParams* p = &app->session.params;
	p->model = (fmMaterialModel)((p->model + 1) % (fm_mooneyRivlin + 1));
	fvSession_ApplyMaterial(&app->session);
}

void fvApp_Key(fvApp* app, const char* name)
{
	fvSession* s = &app->session;
	if (strcmp(name, "space") == 0)
		fvSession_Jump(s);
	else if (strcmp(name, "p") == 0)
		s->paused = !s->paused;
	else if (strcmp(name, "s") == 0 || strcmp(name, "n") == 0)
		s->paused = true, s->pendingSteps += 1;
	else if (strcmp(name, "r") == 0)
		fvSession_Reset(s);
	else if (strcmp(name, "i") == 0)
		fvSession_SwitchIntegrator(s,
		                           s->params.integrator == fm_explicit ? fm_implicit : fm_explicit);
	else if (strcmp(name, "m") == 0)
		fvNextModel(app);
	else if (strcmp(name, "f") == 0)
		fvApp_FrameCamera(app);
	else if (strcmp(name, "escape") == 0 || strcmp(name, "q") == 0)
		app->quit = true;
}

void fvApp_Slider(fvApp* app, const char* name, double value)
{
	fvParams* p = &app->session.params;
	fvParams before = *p;
	if (strcmp(name, "youngs") == 0)
		p->youngs = value;
	else if (strcmp(name, "poisson") == 0)
		p->poisson = value;
	else if (strcmp(name, "mass") == 0)
		p->mass = value;
	else if (strcmp(name, "damping") == 0)
		p->damping = value;
	else if (strcmp(name, "dt") == 0)
		p->dt = value;
	else if (strcmp(name, "substeps") == 0)
		p->substeps = value >= 1.0 && value <= 1000.0 ? (int)value : 0; // 0: refused below
	bool material = strcmp(name, "youngs") == 0 || strcmp(name, "poisson") == 0;
	bool bodies = strcmp(name, "mass") == 0 || strcmp(name, "damping") == 0;
	bool time = !(p->dt >= 1e-6 && p->dt <= 1.0 && p->substeps >= 1 && p->substeps <= 1000);
	if ((material && !fvSession_ApplyMaterial(&app->session)) ||
	    (bodies && !fvSession_ApplyBodies(&app->session)))
		*p = before; // rejected (the status says why): the sliders go back
	else if (time)
	{
		snprintf(app->session.status, sizeof app->session.status,
		         "dt must be in [1e-6, 1] s and substeps in [1, 1000]");
		*p = before;
	}
}

void fvApp_Toggle(fvApp* app, const char* name)
{
	unsigned flags = 0;
	char bad[64];
	if (cliParseDrawFlags(name, &flags, bad, sizeof bad))
		app->drawFlags ^= flags;
}

void fvApp_FillUi(const fvApp* app, fvUiModel* m, double fps)
{
	const fvSession* s = &app->session;
	memset(m, 0, sizeof *m);
	m->fps = fps;
	m->stepMs = s->stepMs;
	m->overBudget = s->overBudget;
	m->stepShareMs = FV_STEP_SHARE_MS;
	m->stepHistory = s->stepHistory;
	m->historyCount = s->historyCount;
	m->historyNext = s->historyCount < FV_PROFILE_FRAMES ? 0 : s->historyNext;
	m->description = s->scene.description;
	m->profile = s->profile;
	m->stats = s->stats;
	m->frames = s->frames;
	m->simTime = (double)s->frames * s->params.dt * s->params.substeps;
	m->paused = s->paused;
	m->dragging = s->dragging;
	m->status = s->status;
	m->sceneNames = (const char* const*)app->sceneNames;
	m->sceneTopics = app->sceneTopics;
	m->topicNames = cliTopicNames;
	m->topicCount = CLI_TOPIC_COUNT;
	m->sceneCount = app->sceneCount;
	m->sceneIndex = app->sceneIndex;
	m->model = (int)s->params.model;
	m->youngs = (float)s->params.youngs;
	m->poisson = (float)s->params.poisson;
	m->perParticle = s->params.perParticle;
	m->mass = (float)s->params.mass;
	m->damping = (float)s->params.damping;
	m->dt = (float)s->params.dt;
	m->substeps = s->params.substeps;
	m->integrator = (int)s->params.integrator;
	m->drawFlags = app->drawFlags;
}

void fvApp_ApplyUi(fvApp* app, const fvUiModel* m)
{
	fvSession* s = &app->session;
	app->drawFlags = m->drawFlags;
	bool reframe = (m->panelRight > 0.0f) != (app->panelRight > 0.0f);
	fvApp_SetPanel(app, m->panelRight);
	if (reframe && !app->cameraGiven) // the panel opened or collapsed: frame what is left free
		fvApp_FrameCamera(app);
	if (m->sceneChanged)
	{
		fvApp_SelectScene(app, m->sceneIndex);
		return;
	}
	if (m->materialChanged)
	{
		s->params.model = (fmMaterialModel)m->model;
		fvApp_Slider(app, "youngs", m->youngs);
		fvApp_Slider(app, "poisson", m->poisson);
	}
	if (m->bodiesChanged)
	{
		fvApp_Slider(app, "mass", m->mass);
		fvApp_Slider(app, "damping", m->damping);
	}
	if (m->timeChanged)
	{
		fvApp_Slider(app, "dt", m->dt);
		fvApp_Slider(app, "substeps", m->substeps);
	}
	if (m->integratorChanged)
		fvSession_SwitchIntegrator(s, (fmIntegrator)m->integrator);
	const char* keys[5] = {m->jump ? "space" : NULL, m->pause ? "p" : NULL, m->step ? "s" : NULL,
	                       m->reset ? "r" : NULL, m->frame ? "f" : NULL};
	for (int i = 0; i < 5; ++i)
		if (keys[i] != NULL)
			fvApp_Key(app, keys[i]);
}

bool fvApp_DragPixels(const fvApp* app, float vertex[2], float cursor[2])
{
	const fvSession* s = &app->session;
	fmVec3 point;
	if (!s->dragging || !fmBody_GetGrab(s->sim.bodies[s->dragBody], &point, NULL))
		return false;
	cursor[0] = app->cursor[0], cursor[1] = app->cursor[1];
	float at[3] = {(float)point.x, (float)point.y, (float)point.z};
	return fvCamera_Project(&app->camera, app->width, app->height, at, vertex);
}
