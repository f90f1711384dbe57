// The interactive viewer's state and its reactions to input (`femto view`): the session, the
// camera, what was drawn last, the mouse (orbit, pan, drag a body) and the keys. The window
// (window.c) and scripts (script.c) call the same functions, so a script exercises exactly
// what a user does.
#pragma once

#include "camera.h"
#include "draw_list.h"
#include "session.h"
#include "ui.h"
#include "view_options.h"

/// What a mouse drag does.
typedef enum fvMouseMode
{
	fv_mouseNone,
	fv_mouseOrbit, ///< left drag off the bodies
	fv_mousePan,   ///< right or middle drag
	fv_mouseDrag,  ///< left drag on a body: it follows the cursor
} fvMouseMode;

/// The viewer.
typedef struct fvApp
{
	fvSession session;
	fvCamera camera;
	fvDrawList list; ///< the last frame's debug draw
	unsigned drawFlags;
	int width, height; ///< framebuffer pixels
	fvMouseMode mouse;
	float cursor[2];    ///< pixels
	float grabPlane[3]; ///< a point of the plane the drag moves on (facing the camera)
	bool (*uiWantsMouse)(void);
	float panelRight;  ///< pixels the panel covers from the left (0: none or collapsed)
	bool cameraGiven;  ///< the camera's target or distance was given (not reframed for the panel)
	char** sceneNames; ///< "(built-in house)", then the .json files of the scene folder
	char** scenePaths; ///< NULL for the built-in house
	int* sceneTopics;  ///< each scene's "topic" (cliTopicNames), -1 none: the list is grouped
	int sceneCount;
	int sceneIndex;
	bool quit;
} fvApp;

/// Load @p scenePath (NULL: the built-in house) and list the scenes of @p sceneFolder.
bool fvApp_Init(fvApp* app, const char* scenePath, const char* sceneFolder, unsigned drawFlags);

/// Release everything.
void fvApp_Free(fvApp* app);

/// Draw the world into the list (fmWorld_Draw) for the renderer.
void fvApp_Capture(fvApp* app);

/// The panel covers the window's left @p panelRight pixels (0: none): the view's centre moves
/// to the middle of the rest (fvCamera.shiftX), and framing fits the bodies there.
void fvApp_SetPanel(fvApp* app, float panelRight);

/// Keep the camera's eye above the floor last drawn (fvCamera_KeepAbove); every camera move
/// ends with it.
void fvApp_KeepCameraAbove(fvApp* app);

/// Aim the camera at the bodies and the floor under them.
void fvApp_FrameCamera(fvApp* app);

/// Place the camera for the scene just loaded: @p given's --camera-* parts (NULL: none) over the
/// scene's "camera" preset, over the automatic framing.
void fvApp_PlaceCamera(fvApp* app, const cliViewOptions* given);

/// Load scene @p index of the list (keeps the current one on failure, with the status set).
void fvApp_SelectScene(fvApp* app, int index);

/// The list entry named @p name (a file name of the scene folder), -1 if none.
int fvApp_FindScene(const fvApp* app, const char* name);

/// A mouse button went down or up: @p button 0 left (grab a body or orbit), 1 right, 2 middle
/// (pan); pixels from the top-left.
void fvApp_MouseButton(fvApp* app, int button, bool down, float x, float y);

/// The cursor moved to (@p x, @p y) pixels: orbit, pan or move the drag's target.
void fvApp_MouseMove(fvApp* app, float x, float y);

/// The wheel turned @p steps (positive: closer).
void fvApp_Scroll(fvApp* app, float steps);

/// A key by name (window.h): space jump, p pause, s/n step, r reset, i integrator, m model, f
/// frame the camera, escape/q quit.
void fvApp_Key(fvApp* app, const char* name);

/// A slider by name (youngs, poisson, mass, damping, dt, substeps), applied as the panel does.
void fvApp_Slider(fvApp* app, const char* name, double value);

/// Flip a debug view by its --draw name.
void fvApp_Toggle(fvApp* app, const char* name);

/// Fill the panel's model from the state.
void fvApp_FillUi(const fvApp* app, fvUiModel* model, double fps);

/// Apply what the panel changed.
void fvApp_ApplyUi(fvApp* app, const fvUiModel* model);

/// Where the grabbed point is drawn and where the cursor is (pixels). False when not dragging.
bool fvApp_DragPixels(const fvApp* app, float vertex[2], float cursor[2]);
