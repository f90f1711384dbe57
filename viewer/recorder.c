// Headless recording (recorder.h).
#include "recorder.h"

#include "camera.h"
#include "draw_list.h"
#include "framebuffer.h"
#include "headless.h"
#include "image_out.h"
#include "renderer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct fvRecorder
{
	fvRecordSettings settings;
	fvHeadless headless;
	fvRenderer* renderer;
	fvFramebuffer framebuffer;
	fvDrawList list;
	fvCamera camera;
	fvGifWriter gif;
	bool gifOpen;
	unsigned char* pixels;
	int frames;
};

fvRecordSettings fvDefaultRecordSettings(void)
{
	fvRecordSettings s;
	memset(&s, 0, sizeof s);
	s.width = 640;
	s.height = 480;
	s.fps = 30.0;
	s.drawFlags = fm_drawSurfaces | fm_drawFloor | fm_drawPins | fm_drawTargets | fm_drawColliders;
	return s;
}

// The first frame's camera: the settings' angles, the rest framed automatically.
static void fvChooseCamera(fvRecorder* r)
{
	const fvRecordSettings* s = &r->settings;
	fvCamera camera = fvCamera_Default();
	if (s->hasYaw)
		camera.yaw = s->yaw;
	if (s->hasPitch)
		camera.pitch = s->pitch;
	float lo[3], hi[3];
	if (fvDrawList_FramingBox(&r->list, lo, hi))
		fvCamera_Frame(&camera, lo, hi, (float)s->width / (float)s->height);
	if (s->hasTarget)
		memcpy(camera.target, s->target, sizeof camera.target);
	if (s->hasDistance)
		camera.distance = s->distance;
	r->camera = camera;
}

static bool fvRecorder_Start(fvRecorder* r, fmWorldId world, char* error, size_t errorSize)
{
	const fvRecordSettings* s = &r->settings;
	if (!fvHeadless_Create(&r->headless, error, errorSize))
		return false;
	if ((r->renderer = fvRenderer_Create(error, errorSize)) == NULL)
		return false;
	if (!fvFramebuffer_Resize(&r->framebuffer, s->width, s->height, 4))
	{
		snprintf(error, errorSize, "cannot make a %dx%d offscreen framebuffer", s->width,
		         s->height);
		return false;
	}
	r->pixels = malloc(4 * (size_t)s->width * (size_t)s->height);
	if (r->pixels == NULL)
	{
		snprintf(error, errorSize, "out of memory for %dx%d frames", s->width, s->height);
		return false;
	}
	fmResult result = fvDrawList_Capture(&r->list, world, s->drawFlags);
	if (result != fm_ok)
	{
		snprintf(error, errorSize, "fmWorld_Draw failed: %s", fmResultMessage(result));
		return false;
	}
	fvChooseCamera(r);
	int delay = (int)lround(100.0 / s->fps);
	if (s->gifPath != NULL && !(r->gifOpen = fvGif_Open(&r->gif, s->gifPath, s->width, s->height,
	                                                    delay < 1 ? 1 : delay, error, errorSize)))
		return false;
	return true;
}

fvRecorder* fvRecorder_Open(const fvRecordSettings* settings, fmWorldId world, char* error,
                            size_t errorSize)
{
	fvRecorder* r = calloc(1, sizeof *r);
	if (r == NULL)
	{
		snprintf(error, errorSize, "out of memory");
		return NULL;
	}
	r->settings = *settings;
	fvDrawList_Init(&r->list);
	if (!fvRecorder_Start(r, world, error, errorSize))
	{
		fvRecorder_Abort(r);
		return NULL;
	}
	return r;
}

bool fvRecorder_Capture(fvRecorder* r, fmWorldId world, char* error, size_t errorSize)
{
	const fvRecordSettings* s = &r->settings;
	fmResult result = fvDrawList_Capture(&r->list, world, s->drawFlags);
	if (result != fm_ok)
	{
		snprintf(error, errorSize, "fmWorld_Draw failed: %s", fmResultMessage(result));
		return false;
	}
	fvFramebuffer_Bind(&r->framebuffer);
	if (!fvRenderer_Draw(r->renderer, &r->list, &r->camera, s->width, s->height))
	{
		snprintf(error, errorSize, "out of memory drawing frame %d", r->frames);
		return false;
	}
	fvFramebuffer_Resolve(&r->framebuffer);
	fvFramebuffer_Read(&r->framebuffer, r->pixels);
	if (r->gifOpen && !fvGif_AddFrame(&r->gif, r->pixels, error, errorSize))
		return false;
	if (s->pngDirectory != NULL)
	{
		char path[2048];
		snprintf(path, sizeof path, "%s/frame_%04d.png", s->pngDirectory, r->frames);
		if (!fvPng_Write(path, r->pixels, s->width, s->height, error, errorSize))
			return false;
	}
	r->frames += 1;
	return true;
}

int fvRecorder_FrameCount(const fvRecorder* r)
{
	return r->frames;
}

// Release everything; the GIF is finished (@p finish) or dropped.
static bool fvRecorder_Release(fvRecorder* r, bool finish, char* error, size_t errorSize)
{
	bool ok = true;
	if (r->gifOpen && finish)
		ok = fvGif_Close(&r->gif, error, errorSize);
	else if (r->gifOpen)
		fvGif_Abort(&r->gif);
	if (r->headless.context != NULL)
	{
		fvFramebuffer_Destroy(&r->framebuffer);
		fvRenderer_Destroy(r->renderer);
	}
	fvHeadless_Destroy(&r->headless);
	fvDrawList_Free(&r->list);
	free(r->pixels);
	free(r);
	return ok;
}

bool fvRecorder_Close(fvRecorder* r, char* error, size_t errorSize)
{
	return r == NULL || fvRecorder_Release(r, true, error, errorSize);
}

void fvRecorder_Abort(fvRecorder* r)
{
	char ignored[16];
	if (r != NULL)
		fvRecorder_Release(r, false, ignored, sizeof ignored);
}
