// Image files: animated GIF (giflib) and PNG (libspng). Every file is written under a temporary
// name beside it and renamed over the final name when complete, so a file that exists is whole.
// Errors name the path.
//
// GIF colours: one global palette made from the first picture (palette.h: greys, a small
// colour cube, and the first picture's colours by median cut), index 255 transparent. Pixels
// take the nearest palette colour (no dithering, which would make the frames noisy and larger);
// greys stay exactly grey. Each frame after the first stores only the rectangle that changed,
// with unchanged pixels transparent, which the LZW coder squeezes to almost nothing.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// An animated GIF being written.
typedef struct fvGifWriter
{
	void* file; ///< GifFileType*
	int width;
	int height;
	int delay;                 ///< centiseconds a frame
	unsigned char* previous;   ///< palette indices of the last frame, width * height
	unsigned char* current;    ///< palette indices of this frame
	unsigned char* row;        ///< one row of the changed rectangle
	struct fvPalette* palette; ///< made from the first frame
	int frames;                ///< frames written
	char path[1024];
	char temporaryPath[1100];
} fvGifWriter;

/// Start a looping GIF of @p width x @p height pixels showing each frame @p delay centiseconds.
/// On failure fills @p error ("path: reason") and returns false.
bool fvGif_Open(fvGifWriter* gif, const char* path, int width, int height, int delay, char* error,
                size_t errorSize);

/// Append a frame: @p rgba is width * height pixels, 4 bytes each, rows from the top.
bool fvGif_AddFrame(fvGifWriter* gif, const unsigned char* rgba, char* error, size_t errorSize);

/// Finish the file and rename it into place. Releases the writer, also on failure.
bool fvGif_Close(fvGifWriter* gif, char* error, size_t errorSize);

/// Drop an unfinished GIF (its temporary file is removed).
void fvGif_Abort(fvGifWriter* gif);

/// Write an RGB PNG from @p rgba (width * height pixels, 4 bytes each, rows from the top; the
/// alpha is dropped).
bool fvPng_Write(const char* path, const unsigned char* rgba, int width, int height, char* error,
                 size_t errorSize);
