// GIF and PNG writers (image_out.h).
#include "image_out.h"

#include "palette.h"

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
	size_t pixels = (size_t)width * (size_t)height;
	gif->previous = malloc(pixels);
	gif->current = malloc(pixels);
	gif->row = malloc((size_t)width);
	gif->palette = malloc(sizeof(fvPalette));
	if (gif->previous == NULL || gif->current == NULL || gif->row == NULL || gif->palette == NULL)
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
	return true;
}

// The header, written with the first picture, whose colours make the palette (palette.h).
static bool fvPutHeader(fvGifWriter* gif, const unsigned char* rgba, char* error, size_t size)
{
	GifFileType* file = gif->file;
	fvPalette* palette = gif->palette;
	if (!fvPalette_Build(palette, rgba, (size_t)gif->width * (size_t)gif->height))
		return fvGifError(gif, E_GIF_ERR_NOT_ENOUGH_MEM, error, size);
	GifColorType colors[256];
	memset(colors, 0, sizeof colors);
	for (int i = 0; i < palette->count; ++i)
		colors[i] =
		    (GifColorType){palette->colors[i][0], palette->colors[i][1], palette->colors[i][2]};
	ColorMapObject* map = GifMakeMapObject(256, colors);
	if (map == NULL)
		return fvGifError(gif, E_GIF_ERR_NOT_ENOUGH_MEM, error, size);
	bool ok = EGifPutScreenDesc(file, gif->width, gif->height, 8, 0, map) != GIF_ERROR;
	GifFreeMapObject(map);
	int code = ok ? fvPutLoop(file) : file->Error;
	return code == 0 || fvGifError(gif, code, error, size);
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
	if (gif->frames == 0 && !fvPutHeader(gif, rgba, error, errorSize))
		return false;
	for (size_t i = 0; i < pixels; ++i)
		gif->current[i] = fvPalette_Index(gif->palette, rgba + 4 * i);
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
	free(gif->palette);
	gif->previous = gif->current = gif->row = NULL;
	gif->palette = NULL;
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
	if (gif->frames == 0)
		ok = false, snprintf(error, errorSize, "%s: no picture to write", gif->path);
	else if (!ok)
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
