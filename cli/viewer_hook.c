// The door to viewer/ (viewer_hook.h). FEMTO_HAVE_RENDERER and FEMTO_HAVE_VIEW are defined by
// viewer/CMakeLists.txt when the packages of the headless renderer (EGL, epoxy, giflib,
// libspng) and of the window (GLFW, Dear ImGui) were found; FEMTO_VIEWER_MISSING names the
// Debian packages that were not.
#include "viewer_hook.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef FEMTO_HAVE_RENDERER
#include "../viewer/recorder.h"
#endif
#ifdef FEMTO_HAVE_VIEW
#include "../viewer/cmd_view.h"
#endif

#ifndef FEMTO_VIEWER_MISSING
#define FEMTO_VIEWER_MISSING                                                                       \
	"libepoxy-dev libegl-dev libgl-dev libgif-dev libspng-dev libglfw3-dev libimgui-dev"
#endif

#if !defined(FEMTO_HAVE_RENDERER) || !defined(FEMTO_HAVE_VIEW)
// Say that a part of the viewer was not built and how to get it.
static void cliReportMissing(const char* what)
{
	cliError("%s needs femto's renderer, and this femto was built without it; install the "
	         "packages (apt-get install " FEMTO_VIEWER_MISSING ") and build again "
	         "(docs/viewer.md)",
	         what);
}
#endif

#ifdef FEMTO_HAVE_RENDERER

bool cliVideo_Available(const char* option)
{
	(void)option;
	return true;
}

struct cliVideo
{
	fvRecorder* recorder;
	double fps;
	const char* pngDirectory;
};

// Whether @p name is a picture --png writes: frame_ and at least 4 digits, .png.
static bool cliIsFramePng(const char* name)
{
	size_t digits = strspn(name + (strncmp(name, "frame_", 6) == 0 ? 6 : 0), "0123456789");
	return strncmp(name, "frame_", 6) == 0 && digits >= 4 && strcmp(name + 6 + digits, ".png") == 0;
}

// Remove the frame_NNNN.png an earlier run left in @p directory (exactly those names), so a
// shorter run leaves no stale pictures after its own; says how many.
static void cliRemoveOldFrames(const char* directory)
{
	DIR* dir = opendir(directory);
	int removed = 0;
	for (struct dirent* e = dir ? readdir(dir) : NULL; e != NULL; e = readdir(dir))
	{
		char path[CLI_MAX_PATH];
		if (cliIsFramePng(e->d_name) && cliJoinPath(path, sizeof path, directory, e->d_name) &&
		    remove(path) == 0)
			removed += 1;
	}
	if (dir != NULL)
		closedir(dir);
	if (removed > 0)
		fprintf(stderr, "femto: note: removed %d frame_NNNN.png of an earlier run from %s\n",
		        removed, directory);
}

cliVideo* cliVideo_Open(const cliViewOptions* o, const cliSimulation* sim)
{
	if (o->pngDirectory != NULL && !cliMakeDirectories(o->pngDirectory))
		return NULL;
	if (o->pngDirectory != NULL)
		cliRemoveOldFrames(o->pngDirectory);
	fvRecordSettings s = fvDefaultRecordSettings();
	s.gifPath = o->gifPath;
	s.pngDirectory = o->pngDirectory;
	s.width = o->width;
	s.height = o->height;
	s.fps = o->fps;
	s.hasDistance = o->hasDistance, s.distance = (float)o->distance;
	s.hasYaw = o->hasYaw, s.yaw = (float)o->yaw;
	s.hasPitch = o->hasPitch, s.pitch = (float)o->pitch;
	s.hasTarget = o->hasTarget;
	s.target[0] = (float)o->target.x, s.target[1] = (float)o->target.y;
	s.target[2] = (float)o->target.z;
	s.drawFlags = o->drawFlags;
	cliVideo* video = calloc(1, sizeof *video);
	char error[1024] = "";
	if (video == NULL ||
	    (video->recorder = fvRecorder_Open(&s, sim->world, error, sizeof error)) == NULL ||
	    !fvRecorder_Capture(video->recorder, sim->world, error, sizeof error))
	{
		cliError("%s", video == NULL ? "out of memory" : error);
		if (video != NULL)
			fvRecorder_Abort(video->recorder);
		free(video);
		return NULL;
	}
	video->fps = o->fps;
	video->pngDirectory = o->pngDirectory;
	return video;
}

bool cliVideo_Advance(cliVideo* video, const cliSimulation* sim, double time)
{
	char error[1024] = "";
	// Picture k shows time k / fps: the state of the first frame that ends at or after it (a
	// tiny allowance so 30 fps of 1/30 s frames are not one frame late from rounding).
	while (fvRecorder_FrameCount(video->recorder) / video->fps <= time + 1e-9)
		if (!fvRecorder_Capture(video->recorder, sim->world, error, sizeof error))
		{
			cliError("%s", error);
			return false;
		}
	return true;
}

bool cliVideo_Close(cliVideo* video, bool ok)
{
	if (video == NULL)
		return true;
	char error[1024] = "";
	if (!ok)
		fvRecorder_Abort(video->recorder);
	else if (!fvRecorder_Close(video->recorder, error, sizeof error))
	{
		cliError("%s", error);
		ok = false;
	}
	free(video);
	return ok;
}

int cliVideo_FrameCount(const cliVideo* video)
{
	return video != NULL ? fvRecorder_FrameCount(video->recorder) : 0;
}

#else // no renderer: --gif and --png say what to install

struct cliVideo
{
	int unused;
};

bool cliVideo_Available(const char* option)
{
	cliReportMissing(option);
	return false;
}

cliVideo* cliVideo_Open(const cliViewOptions* o, const cliSimulation* sim)
{
	(void)sim;
	cliReportMissing(o->gifPath != NULL ? "--gif" : "--png");
	return NULL;
}

bool cliVideo_Advance(cliVideo* video, const cliSimulation* sim, double time)
{
	(void)video, (void)sim, (void)time;
	return false;
}

bool cliVideo_Close(cliVideo* video, bool ok)
{
	(void)video;
	return ok;
}

int cliVideo_FrameCount(const cliVideo* video)
{
	(void)video;
	return 0;
}

#endif

int cliView(int argc, char** argv)
{
#ifdef FEMTO_HAVE_VIEW
	return fvViewMain(argc, argv);
#else
	(void)argc, (void)argv;
	cliReportMissing("femto view");
	return cli_exitInput;
#endif
}
