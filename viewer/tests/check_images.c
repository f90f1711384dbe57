// Checks of the pictures femto draws, for the CTest cases in tests/viewer_tests.cmake. Decodes
// with giflib and libspng, independently of the writers in viewer/image_out.c.
//
//   femto_check_images gif FILE FRAMES [FALLING]
//       FILE has FRAMES frames of the same size; with FALLING, the bodies' pixels (the saturated
//       ones: femto draws the floor and the background in greys) move down the picture over the
//       first FALLING frames: their mean row grows from frame to frame (2 pixels of slack) and by
//       at least 10 pixels in all.
//   femto_check_images png DIR COUNT WxH
//       DIR/frame_0000.png ... frame_COUNT-1.png decode to WxH and DIR/frame_COUNT.png does not
//       exist.
//   femto_check_images view SHOT.png REPORT [OTHER.png]
//       SHOT is not blank (bodies cover 0.5% to 90% of it); the bodies' pixels are centred
//       within a fifth of the picture of where REPORT says the camera sees their centre; when
//       REPORT has a drag, the dragged vertex ends within 10 pixels of the cursor; and SHOT
//       differs from OTHER (the same script without the drag) in at least 0.5% of its pixels.
// Exit status 0 when every check passes, 1 with the failed check's values otherwise.
#include <gif_lib.h>
#include <math.h>
#include <spng.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct Image
{
	int width, height;
	unsigned char* rgb; // 3 bytes a pixel, rows from the top
} Image;

static int fail(const char* format, ...) __attribute__((format(printf, 1, 2)));

static int fail(const char* format, ...)
{
	va_list args;
	va_start(args, format);
	fputs("check_images: ", stderr);
	vfprintf(stderr, format, args);
	fputc('\n', stderr);
	va_end(args);
	return 1;
}

// A body pixel: femto's floor and background are grey, bodies are coloured.
static bool isBody(const unsigned char* p)
{
	int hi = p[0] > p[1] ? p[0] : p[1], lo = p[0] < p[1] ? p[0] : p[1];
	hi = p[2] > hi ? p[2] : hi;
	lo = p[2] < lo ? p[2] : lo;
	return hi - lo > 40;
}

// Mean row and column of the body pixels; their count.
static long bodyCentroid(const Image* image, double* row, double* column)
{
	long count = 0;
	double sumRow = 0.0, sumColumn = 0.0;
	for (int y = 0; y < image->height; ++y)
		for (int x = 0; x < image->width; ++x)
			if (isBody(image->rgb + 3 * ((size_t)y * (size_t)image->width + (size_t)x)))
			{
				count += 1;
				sumRow += y;
				sumColumn += x;
			}
	*row = count > 0 ? sumRow / (double)count : NAN;
	*column = count > 0 ? sumColumn / (double)count : NAN;
	return count;
}

// Paint frame @p k of @p gif over the canvas of palette indices (frames keep what is under
// them: femto writes disposal 1 with a transparent index for unchanged pixels).
static void paintFrame(const GifFileType* gif, int k, unsigned char* canvas)
{
	const SavedImage* frame = &gif->SavedImages[k];
	GraphicsControlBlock control = {0, false, 0, NO_TRANSPARENT_COLOR};
	DGifSavedExtensionToGCB((GifFileType*)gif, k, &control);
	const GifImageDesc* d = &frame->ImageDesc;
	for (int y = 0; y < d->Height; ++y)
		for (int x = 0; x < d->Width; ++x)
		{
			int index = frame->RasterBits[(size_t)y * (size_t)d->Width + (size_t)x];
			int cx = d->Left + x, cy = d->Top + y;
			if (index == control.TransparentColor || cx >= gif->SWidth || cy >= gif->SHeight)
				continue;
			canvas[(size_t)cy * (size_t)gif->SWidth + (size_t)cx] = (unsigned char)index;
		}
}

static void canvasToImage(const GifFileType* gif, int k, const unsigned char* canvas, Image* out)
{
	const ColorMapObject* map = gif->SavedImages[k].ImageDesc.ColorMap
	                                ? gif->SavedImages[k].ImageDesc.ColorMap
	                                : gif->SColorMap;
	size_t pixels = (size_t)gif->SWidth * (size_t)gif->SHeight;
	for (size_t i = 0; i < pixels; ++i)
	{
		const GifColorType* c = &map->Colors[canvas[i] % map->ColorCount];
		out->rgb[3 * i] = c->Red, out->rgb[3 * i + 1] = c->Green, out->rgb[3 * i + 2] = c->Blue;
	}
}

static int checkFalling(const GifFileType* gif, int falling)
{
	size_t pixels = (size_t)gif->SWidth * (size_t)gif->SHeight;
	unsigned char* canvas = calloc(pixels, 1);
	Image image = {gif->SWidth, gif->SHeight, malloc(3 * pixels)};
	double first = NAN, last = NAN;
	int code = canvas && image.rgb ? 0 : fail("out of memory");
	for (int k = 0; code == 0 && k <= falling && k < gif->ImageCount; ++k)
	{
		paintFrame(gif, k, canvas);
		canvasToImage(gif, k, canvas, &image);
		double row, column;
		long count = bodyCentroid(&image, &row, &column);
		printf("frame %d: %ld body pixels, mean row %.1f\n", k, count, row);
		if (count == 0)
			code = fail("frame %d has no body pixels", k);
		else if (k > 0 && row < last - 2.0)
			code = fail("frame %d: the bodies moved up to mean row %.1f (from %.1f)", k, row, last);
		first = k == 0 ? row : first;
		last = row;
	}
	if (code == 0 && !(last > first + 10.0))
		code = fail("the bodies' mean row went from %.1f to %.1f, not down 10 pixels", first, last);
	free(canvas);
	free(image.rgb);
	return code;
}

static int checkGif(const char* path, int frames, int falling)
{
	int error = 0;
	GifFileType* gif = DGifOpenFileName(path, &error);
	if (gif == NULL)
		return fail("%s: cannot open: %s", path, GifErrorString(error));
	if (DGifSlurp(gif) == GIF_ERROR)
	{
		fprintf(stderr, "check_images: %s: %s\n", path, GifErrorString(gif->Error));
		DGifCloseFile(gif, &error);
		return 1;
	}
	printf("%s: %dx%d, %d frames\n", path, gif->SWidth, gif->SHeight, gif->ImageCount);
	int code = 0;
	if (gif->ImageCount != frames)
		code = fail("%s: %d frames, expected %d", path, gif->ImageCount, frames);
	else if (falling > 0)
		code = checkFalling(gif, falling);
	DGifCloseFile(gif, &error);
	return code;
}

static bool readPng(const char* path, Image* image)
{
	FILE* in = fopen(path, "rb");
	if (in == NULL)
		return false;
	spng_ctx* ctx = spng_ctx_new(0);
	struct spng_ihdr header;
	size_t size = 0;
	bool ok = ctx && spng_set_png_file(ctx, in) == 0 && spng_get_ihdr(ctx, &header) == 0 &&
	          spng_decoded_image_size(ctx, SPNG_FMT_RGB8, &size) == 0;
	image->rgb = ok ? malloc(size) : NULL;
	ok = ok && image->rgb && spng_decode_image(ctx, image->rgb, size, SPNG_FMT_RGB8, 0) == 0;
	if (ok)
		image->width = (int)header.width, image->height = (int)header.height;
	spng_ctx_free(ctx);
	fclose(in);
	return ok;
}

static int checkPngs(const char* directory, int count, const char* size)
{
	int width = 0, height = 0;
	if (sscanf(size, "%dx%d", &width, &height) != 2)
		return fail("%s: expected WxH", size);
	char path[4096];
	for (int k = 0; k < count; ++k)
	{
		snprintf(path, sizeof path, "%s/frame_%04d.png", directory, k);
		Image image = {0, 0, NULL};
		if (!readPng(path, &image))
			return fail("%s: cannot decode", path);
		free(image.rgb);
		if (image.width != width || image.height != height)
			return fail("%s: %dx%d, expected %dx%d", path, image.width, image.height, width,
			            height);
	}
	snprintf(path, sizeof path, "%s/frame_%04d.png", directory, count);
	FILE* extra = fopen(path, "rb");
	if (extra != NULL)
	{
		fclose(extra);
		return fail("%s: one frame too many", path);
	}
	printf("%s: %d frames of %dx%d\n", directory, count, width, height);
	return 0;
}

// "key x y" lines of femto view --report.
static bool reportPair(const char* path, const char* key, double* x, double* y)
{
	FILE* in = fopen(path, "r");
	char line[256], name[64];
	bool found = false;
	while (in != NULL && !found && fgets(line, sizeof line, in) != NULL)
		found = sscanf(line, "%63s %lf %lf", name, x, y) == 3 && strcmp(name, key) == 0;
	if (in != NULL)
		fclose(in);
	return found;
}

static int checkDifferent(const Image* shot, const char* otherPath)
{
	Image other = {0, 0, NULL};
	if (!readPng(otherPath, &other))
		return fail("%s: cannot decode", otherPath);
	long differ = 0, pixels = (long)shot->width * shot->height;
	for (long i = 0; other.width == shot->width && other.height == shot->height && i < pixels; ++i)
		differ += memcmp(shot->rgb + 3 * i, other.rgb + 3 * i, 3) != 0;
	free(other.rgb);
	printf("%ld of %ld pixels differ from %s\n", differ, pixels, otherPath);
	if (differ < pixels / 200)
		return fail("%s: the pictures differ in only %ld pixels of %ld", otherPath, differ, pixels);
	return 0;
}

static int checkView(const char* shotPath, const char* report, const char* otherPath)
{
	Image shot = {0, 0, NULL};
	if (!readPng(shotPath, &shot))
		return fail("%s: cannot decode", shotPath);
	double row, column, seenX, seenY, vertexX, vertexY, cursorX, cursorY;
	long count = bodyCentroid(&shot, &row, &column), pixels = (long)shot.width * shot.height;
	printf("%s: %dx%d, %ld body pixels centred at (%.1f, %.1f)\n", shotPath, shot.width,
	       shot.height, count, column, row);
	int code = 0;
	if (count < pixels / 200 || count > pixels * 9 / 10)
		code = fail("%s: %ld body pixels of %ld: blank or all body", shotPath, count, pixels);
	else if (!reportPair(report, "body_pixel", &seenX, &seenY))
		code = fail("%s: no body_pixel line", report);
	else if (fabs(seenX - column) > shot.width / 5.0 || fabs(seenY - row) > shot.height / 5.0)
		code = fail("%s: bodies seen around (%.0f, %.0f), the camera puts them at (%.0f, %.0f)",
		            shotPath, column, row, seenX, seenY);
	if (code == 0 && reportPair(report, "drag_vertex_pixel", &vertexX, &vertexY))
	{
		if (!reportPair(report, "drag_cursor_pixel", &cursorX, &cursorY))
			code = fail("%s: a drag_vertex_pixel without drag_cursor_pixel", report);
		double d = hypot(vertexX - cursorX, vertexY - cursorY);
		printf("dragged vertex %.1f pixels from the cursor\n", d);
		if (code == 0 && d > 10.0)
			code = fail("%s: the dragged vertex ends %.1f pixels from the cursor (at most 10)",
			            report, d);
	}
	if (code == 0 && otherPath != NULL)
		code = checkDifferent(&shot, otherPath);
	free(shot.rgb);
	return code;
}

int main(int argc, char** argv)
{
	if (argc >= 4 && strcmp(argv[1], "gif") == 0)
		return checkGif(argv[2], atoi(argv[3]), argc > 4 ? atoi(argv[4]) : 0);
	if (argc == 5 && strcmp(argv[1], "png") == 0)
		return checkPngs(argv[2], atoi(argv[3]), argv[4]);
	if ((argc == 4 || argc == 5) && strcmp(argv[1], "view") == 0)
		return checkView(argv[2], argv[3], argc == 5 ? argv[4] : NULL);
	fprintf(stderr, "usage: femto_check_images gif FILE FRAMES [FALLING] | png DIR COUNT WxH | "
	                "view SHOT.png REPORT [OTHER.png]\n");
	return 2;
}
