// Scripts of `femto view --script FILE`: what a user does, frame by frame, so a run with a window
// can be replayed and tested (docs/viewer.md, "Scripts"). One action a line:
//
//   # a comment; blank lines are ignored
//   at 10 drag 0.5 0.45 to 0.6 0.3 over 20   press at (x, y), move to (x2, y2) in 20 frames
//   at 80 release                            let go of the mouse
//   at 50 key space                          a key: space, p, s, n, r, i, m, f
//   at 60 slider youngs 2e5                  a slider: youngs, poisson, mass, damping, dt, substeps
//   at 70 toggle tets                        a debug view (the --draw names)
//   at 90 scene drop.json                    pick a scene of the panel's list
//
// Coordinates are fractions of the window, from the top-left corner. Frames count the window's
// frames from 0; actions of one frame run in the file's order.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/// What a script line does.
typedef enum fvActionKind
{
	fv_actionDrag,    ///< press at from, move to to over `over` frames, keep holding
	fv_actionRelease, ///< release the mouse button
	fv_actionKey,     ///< press a key (name)
	fv_actionSlider,  ///< set a slider (name) to value
	fv_actionToggle,  ///< flip a debug view (name)
	fv_actionScene,   ///< pick a scene of the list (name)
} fvActionKind;

/// One line of a script.
typedef struct fvAction
{
	int frame; ///< the window frame it happens in
	fvActionKind kind;
	float from[2]; ///< fractions of the window
	float to[2];
	int over; ///< frames the drag's move takes (>= 1)
	char name[256];
	double value;
	int line; ///< in the script file
} fvAction;

/// A whole script, actions sorted by frame (stable: a frame's actions keep the file's order).
typedef struct fvScript
{
	fvAction* actions;
	int count;
} fvScript;

/// Keys a script may press.
extern const char* const fvScriptKeys[];

/// Read @p path. On an error writes "path:line: expected ..." into @p error and returns false.
bool fvScript_Load(const char* path, fvScript* script, char* error, size_t errorSize);

/// Read a script from an open stream; @p name stands for the file in error messages.
bool fvScript_Read(FILE* in, const char* name, fvScript* script, char* error, size_t errorSize);

/// Release the actions.
void fvScript_Free(fvScript* script);
