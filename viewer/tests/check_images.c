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

// The panel's right edge (pixels) from REPORT's "panel_right" line.
static bool reportPanelRight(const char* path, double* right)
{
	FILE* in = fopen(path, "r");
	char line[256];
	bool found = false;
	while (in != NULL && !found && fgets(line, sizeof line, in) != NULL)
		found = sscanf(line, "panel_right %lf", right) == 1;
	if (in != NULL)
		fclose(in);
	return found;
}

// A screenshot and its report's panel edge (pixels), which must lie within it: 0, or 1 after
// saying what is wrong.
static int openPanelShot(const char* shotPath, const char* report, Image* shot, double* right)
{
	if (!readPng(shotPath, shot))
		return fail("%s: cannot decode", shotPath);
	if (!reportPanelRight(report, right) || *right < 100.0 || *right > shot->width)
	{
		free(shot->rgb);
		shot->rgb = NULL;
		return fail("%s: no panel_right line with a panel", report);
	}
	return 0;
}

static const unsigned char* pixelAt(const Image* image, int x, int y)
{
	return image->rgb + 3 * ((size_t)y * (size_t)image->width + (size_t)x);
}

// The failure's text: femto view draws it in red (1, 0.35, 0.3), blended into the dark panel at
// the glyphs' edges, so green and blue stay about a third of red.
static bool isRedText(const unsigned char* p)
{
	return p[0] > 110 && p[1] * 2 < p[0] && p[2] * 2 < p[0];
}

// A long failure message is fully visible: within the panel (left of panel_right), its red text
// lies on at least two lines (wrapped) and none of it reaches the last 8 columns before the
// panel's right edge (a line cut there by the panel's clipping would).
static int checkMessage(const char* shotPath, const char* report)
{
	Image shot = {0, 0, NULL};
	double right = 0.0;
	if (openPanelShot(shotPath, report, &shot, &right) != 0)
		return 1;
	int panel = (int)right, lines = 0, top = -1, bottom = -1, atEdge = 0, rightmost = -1;
	bool inLine = false;
	for (int y = 0; y < shot.height; ++y)
	{
		int count = 0;
		for (int x = 0; x < panel; ++x)
			if (isRedText(pixelAt(&shot, x, y)))
			{
				count += 1;
				atEdge += x >= panel - 8;
				rightmost = x > rightmost ? x : rightmost;
			}
		if (count >= 3 && !inLine)
			lines += 1, top = top < 0 ? y : top;
		bottom = count >= 3 ? y : bottom;
		inLine = count >= 3;
	}
	free(shot.rgb);
	printf(
	    "%s: red text on %d lines (rows %d to %d), rightmost column %d, %d pixels in the panel's "
	    "last 8 columns (it ends at %d)\n",
	    shotPath, lines, top, bottom, rightmost, atEdge, panel);
	if (lines < 2)
		return fail("%s: the failure's text is on %d line(s), not wrapped", shotPath, lines);
	if (atEdge > 0)
		return fail("%s: the failure's text reaches the panel's right edge (%d pixels): cut off",
		            shotPath, atEdge);
	return 0;
}

// Which channel of a pixel is largest: 0 red, 1 green, 2 blue.
static int dominant(const unsigned char* p)
{
	return p[0] >= p[1] && p[0] >= p[2] ? 0 : p[1] >= p[2] ? 1 : 2;
}

static bool isWhiteText(const unsigned char* p)
{
	return p[0] > 150 && p[1] > 150 && p[2] > 150;
}

// Text pixels in the rows [y0, y1) and columns [x0, x1).
static int textPixels(const Image* image, int x0, int x1, int y0, int y1)
{
	int count = 0;
	for (int y = y0 < 0 ? 0 : y0; y < y1 && y < image->height; ++y)
		for (int x = x0 < 0 ? 0 : x0; x < x1 && x < image->width; ++x)
			count += isWhiteText(pixelAt(image, x, y));
	return count;
}

// The strain legend in the panel: a row with a run of at least 200 saturated pixels going from
// blue-dominant through green-dominant to red-dominant (the library's ramp; the panel's blue bars
// are one hue), and white text under it at its left end, middle and right end (0, the middle
// value, the top value).
static int checkLegend(const char* shotPath, const char* report)
{
	Image shot = {0, 0, NULL};
	double right = 0.0;
	if (openPanelShot(shotPath, report, &shot, &right) != 0)
		return 1;
	int row = -1, start = 0, length = 0;
	for (int y = 0; y < shot.height && row < 0; ++y)
		for (int x = 0, run = 0; x < (int)right && row < 0; ++x)
		{
			run = isBody(pixelAt(&shot, x, y)) ? run + 1 : 0;
			bool ends = run > 0 && (x + 1 == (int)right || !isBody(pixelAt(&shot, x + 1, y)));
			if (!ends || run < 200)
				continue;
			int first = x + 1 - run, hues[3] = {0, 0, 0};
			for (int k = first; k <= x; ++k)
				hues[dominant(pixelAt(&shot, k, y))] += 1;
			if (dominant(pixelAt(&shot, first, y)) == 2 && dominant(pixelAt(&shot, x, y)) == 0 &&
			    hues[1] > run / 10)
				row = y, start = first, length = run;
		}
	if (row < 0)
	{
		free(shot.rgb);
		return fail("%s: no strain ramp (blue to green to red, 200 pixels) in the panel", shotPath);
	}
	int bottom = row;
	while (bottom + 1 < shot.height && isBody(pixelAt(&shot, start + length / 2, bottom + 1)))
		bottom += 1;
	int y0 = bottom + 2, y1 = bottom + 22, mid = start + length / 2;
	int left = textPixels(&shot, start - 2, start + 20, y0, y1);
	int middle = textPixels(&shot, mid - 25, mid + 25, y0, y1);
	int end = textPixels(&shot, start + length - 50, start + length + 100, y0, y1);
	free(shot.rgb);
	printf("%s: strain ramp at row %d, columns %d to %d; text under it: %d, %d, %d pixels\n",
	       shotPath, row, start, start + length - 1, left, middle, end);
	if (left < 5 || middle < 5 || end < 5)
		return fail("%s: the ramp's values are not written under it (%d, %d, %d text pixels)",
		            shotPath, left, middle, end);
	return 0;
}

// Any body pixel, a face in shade too (isBody wants more colour than the house's dark side has):
// femto's floor and background are exactly grey.
static bool isTinted(const unsigned char* p)
{
	int hi = p[0] > p[1] ? p[0] : p[1], lo = p[0] < p[1] ? p[0] : p[1];
	return (p[2] > hi ? p[2] : hi) - (p[2] < lo ? p[2] : lo) > 15;
}

static double luminance(const unsigned char* p)
{
	return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

// Mean, smallest and largest luminance of row @p y's columns [x0, x1].
static void rowSpan(const Image* image, int y, int x0, int x1, double* mean, double* lo, double* hi)
{
	*mean = 0.0, *lo = INFINITY, *hi = -INFINITY;
	for (int x = x0; x <= x1; ++x)
	{
		double l = luminance(pixelAt(image, x, y));
		*mean += l / (x1 - x0 + 1);
		*lo = fmin(*lo, l), *hi = fmax(*hi, l);
	}
}

// A crease drawn sharp: along row ROW, columns X0..X1 (all body pixels, tinted) cross one hard edge
// of the house; at the strongest step of luminance, the 8 pixels either side (2 pixels off the
// edge) are each uniform (within 5 levels of 255) and differ from each other by at least 12.
// Normals smoothed across the edge spread the change over the faces beside it (a streak).
static int checkCrease(const char* shotPath, int row, int x0, int x1)
{
	Image shot = {0, 0, NULL};
	if (!readPng(shotPath, &shot))
		return fail("%s: cannot decode", shotPath);
	int code = 0;
	if (row < 0 || row >= shot.height || x0 < 0 || x1 >= shot.width || x1 - x0 < 30)
		code = fail("%s: row %d, columns %d to %d are outside the picture", shotPath, row, x0, x1);
	for (int x = x0; code == 0 && x <= x1; ++x)
		if (!isTinted(pixelAt(&shot, x, row)))
			code = fail("%s: (%d, %d) is not on a body: the house is not where expected", shotPath,
			            x, row);
	int edge = -1;
	double best = -1.0;
	for (int x = x0 + 11; code == 0 && x <= x1 - 11; ++x)
	{
		double step =
		    fabs(luminance(pixelAt(&shot, x + 1, row)) - luminance(pixelAt(&shot, x - 1, row)));
		if (step > best)
			best = step, edge = x;
	}
	if (code == 0)
	{
		double left, leftLo, leftHi, right, rightLo, rightHi;
		rowSpan(&shot, row, edge - 10, edge - 3, &left, &leftLo, &leftHi);
		rowSpan(&shot, row, edge + 3, edge + 10, &right, &rightLo, &rightHi);
		printf("%s: row %d, crease at column %d: left %.1f (%.1f to %.1f), right %.1f (%.1f to "
		       "%.1f)\n",
		       shotPath, row, edge, left, leftLo, leftHi, right, rightLo, rightHi);
		if (leftHi - leftLo > 5.0 || rightHi - rightLo > 5.0)
			code = fail("%s: the shading beside the crease varies by %.1f and %.1f levels (at "
			            "most 5): smoothed across it",
			            shotPath, leftHi - leftLo, rightHi - rightLo);
		else if (fabs(left - right) < 12.0)
			code = fail("%s: the two faces at the crease differ by %.1f levels (at least 12)",
			            shotPath, fabs(left - right));
	}
	free(shot.rgb);
	return code;
}

int main(int argc, char** argv)
{
	if (argc == 4 && strcmp(argv[1], "message") == 0)
		return checkMessage(argv[2], argv[3]);
	if (argc == 4 && strcmp(argv[1], "legend") == 0)
		return checkLegend(argv[2], argv[3]);
	if (argc == 6 && strcmp(argv[1], "crease") == 0)
		return checkCrease(argv[2], atoi(argv[3]), atoi(argv[4]), atoi(argv[5]));
	if (argc >= 4 && strcmp(argv[1], "gif") == 0)
		return checkGif(argv[2], atoi(argv[3]), argc > 4 ? atoi(argv[4]) : 0);
	if (argc == 5 && strcmp(argv[1], "png") == 0)
		return checkPngs(argv[2], atoi(argv[3]), argv[4]);
	if ((argc == 4 || argc == 5) && strcmp(argv[1], "view") == 0)
		return checkView(argv[2], argv[3], argc == 5 ? argv[4] : NULL);
	fprintf(stderr, "usage: femto_check_images gif FILE FRAMES [FALLING] | png DIR COUNT WxH | "
	                "view SHOT.png REPORT [OTHER.png] | message SHOT.png REPORT | legend SHOT.png "
	                "REPORT | crease SHOT.png ROW X0 X1\n");
	return 2;
}
