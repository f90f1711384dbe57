// Options of the pictures femto draws: `femto run --gif/--png` and `femto view` share the image
// size, the camera and what is drawn (docs/viewer.md).
#pragma once

#include "cli.h"

/// Image output and camera options as given on the command line.
typedef struct cliViewOptions
{
	const char* gifPath;      ///< --gif FILE
	const char* pngDirectory; ///< --png DIR
	int width;                ///< --size WxH (pixels, default 640x480)
	int height;
	bool hasSize;
	double fps; ///< --fps N: pictures a simulated second (default 30)
	bool hasFps;
	bool hasDistance, hasYaw, hasPitch, hasTarget;
	double distance;    ///< --camera-distance D (m)
	double yaw;         ///< --camera-yaw DEG
	double pitch;       ///< --camera-pitch DEG
	fmVec3 target;      ///< --camera-target X,Y,Z (m)
	unsigned drawFlags; ///< --draw LIST (fmDrawFlags)
	bool hasDraw;
} cliViewOptions;

/// The defaults: no files, 640x480, 30 fps, automatic camera, surfaces, floor, pins, targets.
void cliViewOptions_Init(cliViewOptions* options);

/// If argv[*index] is one of the options above, parse it and its value (advancing *index) and
/// return true, with *code -1, or a usage exit code after printing the problem. False when the
/// argument is not one of them.
bool cliViewOptions_Parse(cliViewOptions* options, const char* command, int argc, char** argv,
                          int* index, int* code);

struct cliCameraPreset;

/// The parts of a scene's "camera" preset that the options do not give (the command line wins).
void cliViewOptions_TakeCamera(cliViewOptions* o, const struct cliCameraPreset* preset);

/// Whether --gif or --png was given.
bool cliViewOptions_WantsImages(const cliViewOptions* options);

/// Parse a --draw list such as "surfaces,floor,tets" (names in docs/viewer.md; "all", "none").
/// False on an unknown name, with it in @p bad.
bool cliParseDrawFlags(const char* text, unsigned* flags, char* bad, size_t badSize);
