// Debug drawing (draw.c): fmWorld_Draw fills float arrays from each body's state and hands
// them to the caller's callbacks. The buffers of a body live in its draw cache, made on its
// first draw and reused after.
#pragma once

#include "body/body.h"

// The colour of a strain level in [0, 1]: blue, cyan, green, yellow, red (RGB in [0, 1]).
void fmStrainColor(double level, float rgb[3]);
