// `femto view`: options, the window, the frame loop, scripts, the screenshot and the report.
// Each window frame: input (the user's, or the script's for this frame), one tick of the
// simulation (real time, or exactly 1/60 s with --frames so scripted runs are repeatable), the
// debug draw, the scene into an offscreen framebuffer, copied to the window, the panel over it.
#include "cmd_view.h"

#include "app.h"
#include "framebuffer.h"
#include "image_out.h"
#include "renderer.h"
#include "script.h"
#include "view_options.h"
#include "whole_file.h"
#include "window.h"

#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef FEMTO_SCENES_DIR
#define FEMTO_SCENES_DIR "scenes"
#endif

static const char* const fvViewHelp =
    "usage: femto view [SCENE.json] [options]\n"
    "\n"
    "Open a window on a scene (default: the built-in bouncy house) and play with it: drag\n"
    "bodies with the left mouse button, jump with space, change the material with the sliders.\n"
    "\n"
    "options:\n"
    "  --size WxH         window size in pixels (default 1280x720)\n"
    "  --camera-distance D, --camera-yaw DEG, --camera-pitch DEG, --camera-target X,Y,Z\n"
    "                     the orbit camera (default: the bodies and the floor framed)\n"
    "  --draw LIST        debug views: surfaces,stress,tets,inverted,pins,targets,floor,\n"
    "                     contacts, colliders, fibres, plastic, damage, all or none\n"
    "                     (default surfaces,floor,pins,targets,colliders)\n"
    "  --scenes DIR       the scenes the panel lists (default: the scene's folder, else\n"
    "                     femto's scenes/)\n"
    "  --script FILE      play a script of input (docs/viewer.md, \"Scripts\")\n"
    "  --frames N         quit after N frames; every frame steps exactly 1/60 s\n"
    "  --screenshot FILE  at the end, save the window as a PNG (with the panel unless --no-ui)\n"
    "  --report FILE      at the end, write where the bodies and the drag are seen (pixels)\n"
    "  --no-ui            no panel (the keys and the mouse still work)\n"
    "  --help             this text\n"
    "\n"
    "keys: space jump, P pause, S/N single step, R reset, I integrator, M material model,\n"
    "F frame the camera, Esc/Q quit. Mouse: left drag on a body pulls it, elsewhere orbits;\n"
    "right or middle drag pans; the wheel zooms.\n"
    "\n"
    "Exit status: 0 ok, 1 bad scene or script, no display, I/O error, 2 usage error.\n";

typedef struct fvViewOptions
{
	const char* scenePath;
	const char* sceneFolder;
	const char* scriptPath;
	const char* screenshotPath;
	const char* reportPath;
	int frames; ///< 0: until the window closes
	bool noUi;
	cliViewOptions view;
} fvViewOptions;

// The options that take a value; -1 to go on, or an exit code.
static int fvParseValued(fvViewOptions* o, int argc, char** argv, int* i)
{
	const char* arg = argv[*i];
	const char** slot = strcmp(arg, "--script") == 0       ? &o->scriptPath
	                    : strcmp(arg, "--screenshot") == 0 ? &o->screenshotPath
	                    : strcmp(arg, "--report") == 0     ? &o->reportPath
	                    : strcmp(arg, "--scenes") == 0     ? &o->sceneFolder
	                                                       : NULL;
	if (slot == NULL && strcmp(arg, "--frames") != 0)
		return cliUsageError("view", "unknown option '%s'", arg);
	const char* value = cliOptionValue("view", argc, argv, i);
	if (value == NULL)
		return cli_exitUsage;
	if (slot != NULL)
		*slot = value;
	else if (!cliParseIntOption("view", "--frames", value, 1, CLI_MAX_FRAMES, &o->frames))
		return cli_exitUsage;
	return -1;
}

static int fvParseOptions(int argc, char** argv, fvViewOptions* o)
{
	memset(o, 0, sizeof *o);
	cliViewOptions_Init(&o->view);
	o->view.width = 1280, o->view.height = 720;
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		int code = -1;
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(fvViewHelp, stdout);
			return cli_exitOk;
		}
		if (strcmp(arg, "--no-ui") == 0)
			o->noUi = true;
		else if (cliViewOptions_Parse(&o->view, "view", argc, argv, &i, &code))
		{
			if (code >= 0)
				return code;
			if (o->view.gifPath || o->view.pngDirectory || o->view.hasFps)
				return cliUsageError("view",
				                     "%s is an option of femto run (pictures without a "
				                     "window)",
				                     arg);
		}
		else if (arg[0] == '-' && arg[1] != 0)
		{
			if ((code = fvParseValued(o, argc, argv, &i)) >= 0)
				return code;
		}
		else if (o->scenePath == NULL)
			o->scenePath = arg;
		else
			return cliUsageError("view", "more than one scene ('%s' and '%s')", o->scenePath, arg);
	}
	if (o->scriptPath != NULL && o->frames == 0)
		return cliUsageError("view", "--script needs --frames N (when to stop)");
	return -1;
}

// The scene folder the panel lists: --scenes, the scene's own folder, femto's scenes/.
static void fvSceneFolder(const fvViewOptions* o, char* folder, size_t size)
{
	if (o->sceneFolder != NULL)
		snprintf(folder, size, "%s", o->sceneFolder);
	else if (o->scenePath != NULL && strrchr(o->scenePath, '/') != NULL)
		snprintf(folder, size, "%.*s", (int)(strrchr(o->scenePath, '/') - o->scenePath),
		         o->scenePath);
	else if (o->scenePath != NULL)
		snprintf(folder, size, ".");
	else
		snprintf(folder, size, "%s", FEMTO_SCENES_DIR);
}

// Everything a viewer run holds.
typedef struct fvView
{
	fvViewOptions options;
	fvApp app;
	fvWindow window;
	fvRenderer* renderer;
	fvFramebuffer framebuffer;
	fvScript script;
	int nextAction;
	bool ui;
	// A scripted drag in progress: moving from -> to until frame dragEnd.
	bool scriptDragging;
	float dragFrom[2], dragTo[2];
	int dragStart, dragEnd;
} fvView;

static void fvInputMouseButton(void* c, int button, bool down, float x, float y)
{
	fvApp_MouseButton(c, button, down, x, y);
}

static void fvInputMouseMove(void* c, float x, float y)
{
	fvApp_MouseMove(c, x, y);
}

static void fvInputScroll(void* c, float steps)
{
	fvApp_Scroll(c, steps);
}

static void fvInputKey(void* c, const char* name)
{
	fvApp_Key(c, name);
}

static int fvOpen(fvView* v)
{
	const fvViewOptions* o = &v->options;
	char error[1024] = "";
	if (o->scriptPath != NULL && !fvScript_Load(o->scriptPath, &v->script, error, sizeof error))
	{
		cliError("%s", error);
		return cli_exitInput;
	}
	char folder[CLI_MAX_PATH];
	fvSceneFolder(o, folder, sizeof folder);
	if (!fvApp_Init(&v->app, o->scenePath, folder, o->view.drawFlags))
		return cli_exitInput;
	if (!fvWindow_Create(&v->window, o->view.width, o->view.height, "femto view", error,
	                     sizeof error))
	{
		cliError("view: %s", error);
		return cli_exitInput;
	}
	fvInputHandler input = {fvInputMouseButton, fvInputMouseMove, fvInputScroll, fvInputKey,
	                        &v->app};
	v->window.input = input;
	// A script plays alone: the real mouse over the window must not interfere.
	v->window.forwardInput = o->scriptPath == NULL;
	if ((v->renderer = fvRenderer_Create(error, sizeof error)) == NULL)
	{
		cliError("view: %s", error);
		return cli_exitInput;
	}
	v->ui = !o->noUi && fvUi_Init(v->window.glfw);
	v->app.uiWantsMouse = v->ui ? fvUi_WantsMouse : NULL;
	fvWindow_FramebufferSize(&v->window, &v->app.width, &v->app.height);
	fvApp_PlaceCamera(&v->app, &v->options.view);
	return -1;
}

static void fvClose(fvView* v)
{
	if (v->ui)
		fvUi_Shutdown();
	if (v->window.glfw != NULL)
	{
		fvFramebuffer_Destroy(&v->framebuffer);
		fvRenderer_Destroy(v->renderer);
	}
	fvWindow_Destroy(&v->window);
	fvApp_Free(&v->app);
	fvScript_Free(&v->script);
}

// A script's window fraction in pixels.
static float fvPixel(const fvView* v, float fraction, int axis)
{
	return fraction * (float)(axis == 0 ? v->app.width : v->app.height);
}

// Pick a scene by name; a name not in the list ends the run (false).
static bool fvScriptScene(fvView* v, const fvAction* a)
{
	int index = fvApp_FindScene(&v->app, a->name);
	if (index < 0)
	{
		cliError("%s:%d: expected a scene of the list (the .json files of the scene folder), got "
		         "'%s'",
		         v->options.scriptPath, a->line, a->name);
		return false;
	}
	fvApp_SelectScene(&v->app, index);
	return v->app.sceneIndex == index;
}

// Run one action; false when the run must stop (a scene that is not there or does not load).
static bool fvRunAction(fvView* v, const fvAction* a, int frame)
{
	fvApp* app = &v->app;
	switch (a->kind)
	{
	case fv_actionDrag:
		fvApp_MouseButton(app, 0, true, fvPixel(v, a->from[0], 0), fvPixel(v, a->from[1], 1));
		v->scriptDragging = true;
		memcpy(v->dragFrom, a->from, sizeof v->dragFrom);
		memcpy(v->dragTo, a->to, sizeof v->dragTo);
		v->dragStart = frame;
		v->dragEnd = frame + a->over;
		break;
	case fv_actionRelease:
		v->scriptDragging = false;
		fvApp_MouseButton(app, 0, false, app->cursor[0], app->cursor[1]);
		break;
	case fv_actionKey:
		fvApp_Key(app, a->name);
		break;
	case fv_actionSlider:
		fvApp_Slider(app, a->name, a->value);
		break;
	case fv_actionToggle:
		fvApp_Toggle(app, a->name);
		break;
	case fv_actionScene:
		v->scriptDragging = false;
		return fvScriptScene(v, a);
	}
	return true;
}

// This frame's script actions, and the scripted cursor's move. False to stop the run.
static bool fvPlayScript(fvView* v, int frame)
{
	if (v->scriptDragging && frame > v->dragStart)
	{
		float t = (float)(frame - v->dragStart) / (float)(v->dragEnd - v->dragStart);
		t = t > 1.0f ? 1.0f : t;
		float x = v->dragFrom[0] + t * (v->dragTo[0] - v->dragFrom[0]);
		float y = v->dragFrom[1] + t * (v->dragTo[1] - v->dragFrom[1]);
		fvApp_MouseMove(&v->app, fvPixel(v, x, 0), fvPixel(v, y, 1));
	}
	while (v->nextAction < v->script.count && v->script.actions[v->nextAction].frame <= frame)
		if (!fvRunAction(v, &v->script.actions[v->nextAction++], frame))
			return false;
	return true;
}

// The panel: fill its model, draw it, apply what it changed.
static void fvPanel(fvView* v, double fps)
{
	fvUiModel model;
	fvApp_FillUi(&v->app, &model, fps);
	fvUi_Frame(&model);
	fvApp_ApplyUi(&v->app, &model);
}

static bool fvSaveScreenshot(const fvView* v, const char* path);

// Draw one frame (and save it as @p screenshot when not NULL); false when the offscreen
// framebuffer cannot be had or the screenshot not written.
static bool fvDrawFrame(fvView* v, double fps, const char* screenshot)
{
	fvApp* app = &v->app;
	fvWindow_FramebufferSize(&v->window, &app->width, &app->height);
	if (app->width < 1 || app->height < 1)
		return true; // minimised
	if (!fvFramebuffer_Resize(&v->framebuffer, app->width, app->height, 4))
		return false;
	fvApp_Capture(app);
	fvFramebuffer_Bind(&v->framebuffer);
	fvRenderer_Draw(v->renderer, &app->list, &app->camera, app->width, app->height);
	fvFramebuffer_Resolve(&v->framebuffer);
	fvFramebuffer_BlitToWindow(&v->framebuffer, app->width, app->height);
	glViewport(0, 0, app->width, app->height);
	if (v->ui)
		fvPanel(v, fps);
	if (screenshot != NULL && !fvSaveScreenshot(v, screenshot))
		return false;
	fvWindow_Swap(&v->window);
	return true;
}

static int fvLoop(fvView* v)
{
	const fvViewOptions* o = &v->options;
	double last = fvWindow_Time(), fps = 60.0;
	for (int frame = 0; o->frames == 0 || frame < o->frames; ++frame)
	{
		fvWindow_Poll(&v->window);
		if (fvWindow_ShouldClose(&v->window) || v->app.quit)
			break;
		if (!fvPlayScript(v, frame))
			return cli_exitInput;
		double now = fvWindow_Time();
		double elapsed = now - last;
		last = now;
		fps = elapsed > 0.0 ? 0.9 * fps + 0.1 / elapsed : fps;
		// Scripted runs step exactly one tick a frame: the same result on any machine.
		fvSession_Advance(&v->app.session,
		                  o->frames > 0 ? FV_TICK_SECONDS : (elapsed < 0.25 ? elapsed : 0.25));
		if (!fvDrawFrame(v, fps, NULL))
		{
			cliError("view: cannot make a %dx%d framebuffer", v->app.width, v->app.height);
			return cli_exitInput;
		}
	}
	// The screenshot: the last state drawn once more, read before it is shown.
	if (o->screenshotPath != NULL && !fvDrawFrame(v, fps, o->screenshotPath))
		return cli_exitInput;
	return cli_exitOk;
}

// What the window shows, panel included (--no-ui for the scene alone).
static bool fvSaveScreenshot(const fvView* v, const char* path)
{
	int width = v->app.width, height = v->app.height;
	unsigned char* pixels = malloc(4 * (size_t)width * (size_t)height);
	char error[1024] = "";
	bool ok = pixels != NULL;
	if (ok)
	{
		fvFramebuffer_ReadWindow(width, height, pixels);
		ok = fvPng_Write(path, pixels, width, height, error, sizeof error);
	}
	free(pixels);
	if (!ok)
		cliError("%s", pixels == NULL ? "out of memory for the screenshot" : error);
	return ok;
}

// The report: the picture size, where the camera sees the bodies' centre, and the drag.
static bool fvWriteReport(const fvView* v, const char* path)
{
	cliOutput file;
	if (!cliOutput_Open(&file, path))
		return false;
	FILE* out = file.file;
	const fvApp* app = &v->app;
	fprintf(out, "frames %ld\nsize %d %d\n", app->session.frames, app->width, app->height);
	const fvParams* p = &app->session.params;
	fprintf(out,
	        "integrator %s\nsubsteps %d\ndt %.9g\nover_budget_frames %ld\npanel_right %.1f\n"
	        "profile_frames %d\n",
	        p->integrator == fm_implicit ? "implicit" : "explicit", p->substeps, p->dt,
	        app->session.overBudgetFrames, app->panelRight, app->session.historyCount);
	fprintf(out, "material %s youngs %.6g poisson %.6g\nstatus %s\n", fmMaterialModelName(p->model),
	        p->youngs, p->poisson, app->session.status);
	const fvCamera* c = &app->camera;
	fprintf(out, "camera %.4g %.4g %.4g %.4g %.4g %.4g\n", c->target[0], c->target[1], c->target[2],
	        c->distance, c->yaw, c->pitch);
	// The scene list as the panel shows it: grouped by topic, the built-in house first.
	for (int i = 0; i < app->sceneCount; ++i)
		fprintf(out, "scene %s %s\n",
		        app->sceneTopics[i] >= 0 ? cliTopicNames[app->sceneTopics[i]] : "-",
		        app->sceneNames[i]);
	float lo[3], hi[3], pixel[2], vertex[2], cursor[2];
	if (fvDrawList_Bounds(&app->list, lo, hi))
	{
		float center[3] = {0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
		if (fvCamera_Project(&app->camera, app->width, app->height, center, pixel))
			fprintf(out, "body_pixel %.1f %.1f\n", pixel[0], pixel[1]);
	}
	if (fvApp_DragPixels(app, vertex, cursor))
		fprintf(out, "drag_vertex_pixel %.1f %.1f\ndrag_cursor_pixel %.1f %.1f\n", vertex[0],
		        vertex[1], cursor[0], cursor[1]);
	return cliOutput_Commit(&file);
}

int fvViewMain(int argc, char** argv)
{
	fvView* v = calloc(1, sizeof *v);
	if (v == NULL)
	{
		cliError("out of memory");
		return cli_exitInput;
	}
	int code = fvParseOptions(argc, argv, &v->options);
	if (code < 0)
		code = fvOpen(v);
	if (code < 0)
		code = fvLoop(v);
	if (code == cli_exitOk && v->options.reportPath != NULL &&
	    !fvWriteReport(v, v->options.reportPath))
		code = cli_exitInput;
	fvClose(v);
	free(v);
	return code;
}
