// Headless recording for `femto run --gif FILE / --png DIR`: an EGL context without a window,
// the renderer drawing the world's debug draw into an offscreen framebuffer, frames appended to
// an animated GIF or written as DIR/frame_0000.png, frame_0001.png, ...
#pragma once

#include <femto/femto.h>

#include <stdbool.h>
#include <stddef.h>

/// What to record and from where. Camera fields left unset (has* false) are found by framing
/// the bodies and the floor under them in the first frame.
typedef struct fvRecordSettings
{
	const char* gifPath;      ///< animated GIF to write, or NULL
	const char* pngDirectory; ///< folder for frame_NNNN.png (created), or NULL
	int width;                ///< pixels
	int height;               ///< pixels
	double fps;               ///< frames a simulated second (the GIF's delay is 100 / fps cs)
	bool hasDistance, hasYaw, hasPitch, hasTarget;
	float distance; ///< m
	float yaw;      ///< degrees
	float pitch;    ///< degrees
	float target[3];
	unsigned drawFlags; ///< fmDrawFlags
} fvRecordSettings;

/// A recording in progress.
typedef struct fvRecorder fvRecorder;

/// Settings with the defaults: 640x480, 30 fps, automatic camera, surfaces, floor, pins and
/// targets, no files.
fvRecordSettings fvDefaultRecordSettings(void);

/// Start a recording of @p world (the GL context, the renderer, the files). NULL on failure,
/// with the reason in @p error.
fvRecorder* fvRecorder_Open(const fvRecordSettings* settings, fmWorldId world, char* error,
                            size_t errorSize);

/// Draw @p world now and append the picture to the GIF and/or write the next PNG.
bool fvRecorder_Capture(fvRecorder* recorder, fmWorldId world, char* error, size_t errorSize);

/// Pictures captured so far.
int fvRecorder_FrameCount(const fvRecorder* recorder);

/// Finish the GIF (renamed into place) and release everything. False (with @p error) when the
/// GIF could not be finished; everything is released either way. Safe on NULL.
bool fvRecorder_Close(fvRecorder* recorder, char* error, size_t errorSize);

/// Stop a recording without finishing it: an unfinished GIF is removed (PNGs written stay).
/// Safe on NULL.
void fvRecorder_Abort(fvRecorder* recorder);
