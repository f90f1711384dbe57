// GIF and PNG writers (image_out.h).
#include "image_out.h"

#include <errno.h>
#include <fcntl.h>
#include <gif_lib.h>
#include <spng.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FV_TRANSPARENT 255 // palette index of "unchanged since the last frame"
#define FV_CUBE 6          // levels per channel of the colour cube
#define FV_GREYS 39        // greys between the cube's levels

// The palette (image_out.h) and a 32x32x32 table from 5-bit RGB to its nearest entry.
static GifColorType fvPalette[256];
static unsigned char fvNearest[32 * 32 * 32];
static bool fvPaletteReady;

static void fvMakePalette(void)
{
	int n = 0;
	for (int r = 0; r < FV_CUBE; ++r)
		for (int g = 0; g < FV_CUBE; ++g)
			for (int b = 0; b < FV_CUBE; ++b, ++n)
				fvPalette[n] = (GifColorType){(GifByteType)(51 * r), (GifByteType)(51 * g),
				                              (GifByteType)(51 * b)};
	for (int k = 0; n < FV_TRANSPARENT; ++k)
	{
		// 6 or 7 greys between two cube levels 51 apart: every grey within 4 of one.
		int value = 4 + (k * 247) / (FV_GREYS - 1);
		if (value % 51 == 0)
			value += 3;
		fvPalette[n++] = (GifColorType){(GifByteType)value, (GifByteType)value, (GifByteType)value};
	}
	fvPalette[FV_TRANSPARENT] = (GifColorType){0, 0, 0};
	for (int key = 0; key < 32 * 32 * 32; ++key)
	{
		int rgb[3] = {((key >> 10) & 31) * 255 / 31, ((key >> 5) & 31) * 255 / 31,
		              (key & 31) * 255 / 31};
		int best = 0, bestDistance = INT32_MAX;
		for (int i = 0; i < FV_TRANSPARENT; ++i)
		{
			int dr = rgb[0] - fvPalette[i].Red, dg = rgb[1] - fvPalette[i].Green,
			    db = rgb[2] - fvPalette[i].Blue;
			// Weighted as the eye weighs the channels (green most, blue least).
			int distance = 3 * dr * dr + 4 * dg * dg + 2 * db * db;
			if (distance < bestDistance)
				bestDistance = distance, best = i;
		}
		fvNearest[key] = (unsigned char)best;
	}
	fvPaletteReady = true;
}

static unsigned char fvIndex(const unsigned char* p)
{
	return fvNearest[((p[0] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[2] >> 3)];
}

static bool fvGifError(const fvGifWriter* gif, int code, char* error, size_t size)
{
	snprintf(error, size, "%s: cannot write the GIF: %s", gif->path, GifErrorString(code));
	return false;
}

// The NETSCAPE2.0 application extension: loop forever.
static int fvPutLoop(GifFileType* file)
{
	static const unsigned char loop[3] = {1, 0, 0};
	if (EGifPutExtensionLeader(file, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
	    EGifPutExtensionBlock(file, 11, "NETSCAPE2.0") == GIF_ERROR ||
	    EGifPutExtensionBlock(file, 3, loop) == GIF_ERROR ||
	    EGifPutExtensionTrailer(file) == GIF_ERROR)
		return file->Error;
	return 0;
}

bool fvGif_Open(fvGifWriter* gif, const char* path, int width, int height, int delay, char* error,
                size_t errorSize)
{
	memset(gif, 0, sizeof *gif);
	snprintf(gif->path, sizeof gif->path, "%s", path);
	snprintf(gif->temporaryPath, sizeof gif->temporaryPath, "%s.%ld.tmp", path, (long)getpid());
	if (!fvPaletteReady)
		fvMakePalette();
	size_t pixels = (size_t)width * (size_t)height;
	gif->previous = malloc(pixels);
	gif->current = malloc(pixels);
	gif->row = malloc((size_t)width);
	if (gif->previous == NULL || gif->current == NULL || gif->row == NULL)
	{
		fvGif_Abort(gif);
		snprintf(error, errorSize, "%s: out of memory for %dx%d frames", path, width, height);
		return false;
	}
	int code = 0;
	// Not EGifOpenFileName, which makes the file readable by its owner only.
	int handle = open(gif->temporaryPath, O_WRONLY | O_CREAT | O_TRUNC, 0666);
	GifFileType* file = handle >= 0 ? EGifOpenFileHandle(handle, &code) : NULL;
	if (file == NULL)
	{
		snprintf(error, errorSize, "%s: cannot create: %s", path,
		         handle < 0 ? strerror(errno) : GifErrorString(code));
		if (handle >= 0)
			close(handle);
		fvGif_Abort(gif);
		return false;
	}
	gif->file = file;
	gif->width = width;
	gif->height = height;
	gif->delay = delay;
	EGifSetGifVersion(file, true);
	ColorMapObject* map = GifMakeMapObject(256, fvPalette);
	bool ok = map != NULL && EGifPutScreenDesc(file, width, height, 8, 0, map) != GIF_ERROR;
	GifFreeMapObject(map);
	if (!ok || (code = fvPutLoop(file)) != 0)
	{
		fvGifError(gif, map == NULL ? E_GIF_ERR_NOT_ENOUGH_MEM : file->Error, error, errorSize);
		fvGif_Abort(gif);
		return false;
	}
	return true;
}

// The rectangle of pixels that differ from the last frame ([x0, x1) x [y0, y1)); the whole
// image for the first frame, one pixel when nothing changed.
static void fvChangedRectangle(const fvGifWriter* gif, int box[4])
{
	if (gif->frames == 0)
	{
		box[0] = 0, box[1] = 0, box[2] = gif->width, box[3] = gif->height;
		return;
	}
	int x0 = gif->width, y0 = gif->height, x1 = 0, y1 = 0;
	for (int y = 0; y < gif->height; ++y)
		for (int x = 0; x < gif->width; ++x)
		{
			size_t i = (size_t)y * (size_t)gif->width + (size_t)x;
			if (gif->current[i] == gif->previous[i])
				continue;
			x0 = x < x0 ? x : x0, x1 = x + 1 > x1 ? x + 1 : x1;
			y0 = y < y0 ? y : y0, y1 = y + 1 > y1 ? y + 1 : y1;
		}
	if (x1 == 0)
		x0 = 0, y0 = 0, x1 = 1, y1 = 1;
	box[0] = x0, box[1] = y0, box[2] = x1, box[3] = y1;
}

bool fvGif_AddFrame(fvGifWriter* gif, const unsigned char* rgba, char* error, size_t errorSize)
{
	GifFileType* file = gif->file;
	size_t pixels = (size_t)gif->width * (size_t)gif->height;
	for (size_t i = 0; i < pixels; ++i)
		gif->current[i] = fvIndex(rgba + 4 * i);
	int box[4];
	fvChangedRectangle(gif, box);
	// Graphic control: keep the last frame under this one (disposal 1), index 255 transparent.
	unsigned char control[4] = {(1 << 2) | (gif->frames > 0 ? 1 : 0),
	                            (unsigned char)(gif->delay & 0xff),
	                            (unsigned char)((gif->delay >> 8) & 0xff), FV_TRANSPARENT};
	if (EGifPutExtension(file, GRAPHICS_EXT_FUNC_CODE, 4, control) == GIF_ERROR ||
	    EGifPutImageDesc(file, box[0], box[1], box[2] - box[0], box[3] - box[1], false, NULL) ==
	        GIF_ERROR)
		return fvGifError(gif, file->Error, error, errorSize);
	for (int y = box[1]; y < box[3]; ++y)
	{
		const unsigned char* now = gif->current + (size_t)y * (size_t)gif->width;
		const unsigned char* before = gif->previous + (size_t)y * (size_t)gif->width;
		for (int x = box[0]; x < box[2]; ++x)
			gif->row[x - box[0]] = gif->frames > 0 && now[x] == before[x] ? FV_TRANSPARENT : now[x];
		if (EGifPutLine(file, gif->row, box[2] - box[0]) == GIF_ERROR)
			return fvGifError(gif, file->Error, error, errorSize);
	}
	unsigned char* swap = gif->previous;
	gif->previous = gif->current;
	gif->current = swap;
	gif->frames += 1;
	return true;
}

static void fvGif_Release(fvGifWriter* gif)
{
	free(gif->previous);
	free(gif->current);
	free(gif->row);
	gif->previous = gif->current = gif->row = NULL;
	gif->file = NULL;
}

void fvGif_Abort(fvGifWriter* gif)
{
	if (gif->file != NULL)
	{
		int code = 0;
		EGifCloseFile(gif->file, &code);
		remove(gif->temporaryPath);
	}
	fvGif_Release(gif);
}

bool fvGif_Close(fvGifWriter* gif, char* error, size_t errorSize)
{
	int code = 0;
	bool ok = EGifCloseFile(gif->file, &code) != GIF_ERROR;
	gif->file = NULL;
	if (!ok)
		fvGifError(gif, code, error, errorSize);
	else if (rename(gif->temporaryPath, gif->path) != 0)
	{
		snprintf(error, errorSize, "%s: cannot rename %s into place: %s", gif->path,
		         gif->temporaryPath, strerror(errno));
		ok = false;
	}
	if (!ok)
		remove(gif->temporaryPath);
	fvGif_Release(gif);
	return ok;
}

static bool fvPngEncode(FILE* out, const unsigned char* rgb, int width, int height, int* code)
{
	spng_ctx* ctx = spng_ctx_new(SPNG_CTX_ENCODER);
	if (ctx == NULL)
	{
		*code = SPNG_EMEM;
		return false;
	}
	struct spng_ihdr header = {
	    (uint32_t)width, (uint32_t)height, 8, SPNG_COLOR_TYPE_TRUECOLOR, 0, 0, 0};
	size_t size = 3 * (size_t)width * (size_t)height;
	*code = spng_set_png_file(ctx, out);
	if (*code == 0)
		*code = spng_set_ihdr(ctx, &header);
	if (*code == 0)
		*code = spng_encode_image(ctx, rgb, size, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
	spng_ctx_free(ctx);
	return *code == 0;
}

bool fvPng_Write(const char* path, const unsigned char* rgba, int width, int height, char* error,
                 size_t errorSize)
{
	size_t pixels = (size_t)width * (size_t)height;
	unsigned char* rgb = malloc(3 * pixels);
	if (rgb == NULL)
	{
		snprintf(error, errorSize, "%s: out of memory for a %dx%d image", path, width, height);
		return false;
	}
	for (size_t i = 0; i < pixels; ++i)
		memcpy(rgb + 3 * i, rgba + 4 * i, 3);
	char temporary[1100];
	snprintf(temporary, sizeof temporary, "%s.%ld.tmp", path, (long)getpid());
	FILE* out = fopen(temporary, "wb");
	if (out == NULL)
	{
		snprintf(error, errorSize, "%s: cannot create: %s", path, strerror(errno));
		free(rgb);
		return false;
	}
	int code = 0;
	bool ok = fvPngEncode(out, rgb, width, height, &code);
	free(rgb);
	if (fclose(out) != 0 && ok)
		ok = false, code = SPNG_IO_ERROR;
	if (ok && rename(temporary, path) != 0)
	{
		snprintf(error, errorSize, "%s: cannot rename %s into place: %s", path, temporary,
		         strerror(errno));
		remove(temporary);
		return false;
	}
	if (!ok)
	{
		snprintf(error, errorSize, "%s: cannot write the PNG: %s", path, spng_strerror(code));
		remove(temporary);
	}
	return ok;
}
