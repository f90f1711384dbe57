// The tool's one door to viewer/ (the optional renderer and the `femto view` window): recording
// pictures during `femto run` and the `view` command. cli/ itself calls no graphics API; when
// femto is built without the viewer's packages, these say which Debian packages to install.
#pragma once

#include "scene.h"
#include "view_options.h"

/// A recording of a run's pictures (--gif, --png).
typedef struct cliVideo cliVideo;

/// Whether this femto can record pictures; prints what to install (naming @p option) when not.
bool cliVideo_Available(const char* option);

/// Start recording @p sim as @p options say and capture its initial state (time 0). Prints
/// the problem and returns NULL when it cannot (no renderer in this build, no EGL, a file).
cliVideo* cliVideo_Open(const cliViewOptions* options, const cliSimulation* sim);

/// Capture the pictures due up to simulated time @p time (s): one every 1 / fps seconds.
/// Prints the problem and returns false on failure.
bool cliVideo_Advance(cliVideo* video, const cliSimulation* sim, double time);

/// Finish the files (@p ok) or drop an unfinished GIF (!@p ok), and release the recording.
/// Returns false (with a message) when the GIF could not be finished. Safe on NULL.
bool cliVideo_Close(cliVideo* video, bool ok);

/// Pictures captured so far.
int cliVideo_FrameCount(const cliVideo* video);

/// `femto view [SCENE] [options]`: the interactive viewer (docs/viewer.md).
int cliView(int argc, char** argv);
