// The GIF's 255 colours (image_out.c), chosen from its first picture: 32 greys (the floor, the
// background and the shadows stay exactly grey), a 4x4x4 colour cube (colours that appear only
// later: stress colours, markers), and up to 159 colours by median cut of the first picture's
// coloured pixels (Heckbert, "Color image quantization for frame buffer display", 1982), so
// the shading of the bodies keeps its hue instead of banding through a fixed cube.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// Colours and the nearest-colour table.
typedef struct fvPalette
{
	unsigned char colors[256][3]; ///< RGB; entry 255 is left for transparency
	int count;                    ///< entries used, at most 255
	unsigned char nearest[32768]; ///< 5-bit RGB (r << 10 | g << 5 | b) to its nearest entry
} fvPalette;

/// Build the palette for an image of @p pixels RGBA pixels. False when memory is short.
bool fvPalette_Build(fvPalette* palette, const unsigned char* rgba, size_t pixels);

/// The entry nearest to the RGB colour at @p rgb.
unsigned char fvPalette_Index(const fvPalette* palette, const unsigned char* rgb);
