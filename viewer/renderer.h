// The OpenGL 3.3 core renderer of a draw list (draw_list.h): smooth-shaded surfaces with
// hemisphere light, a key light and contact darkening, a checkered floor that fades into the
// distance with the bodies' projected shadows and soft occlusion blobs on it, lines and round
// points. Draws into whatever framebuffer is bound (a window's or an offscreen one).
#pragma once

#include "camera.h"
#include "draw_list.h"

#include <stddef.h>

/// Shaders, buffers and staging memory.
typedef struct fvRenderer fvRenderer;

/// Compile the shaders and make the buffers; needs a current OpenGL 3.3 core context. NULL on
/// failure, with the reason (a shader's compile log) in @p error.
fvRenderer* fvRenderer_Create(char* error, size_t errorSize);

/// Release everything (with the context still current). Safe on NULL.
void fvRenderer_Destroy(fvRenderer* renderer);

/// Side of the floor's checker squares (m, default 1).
void fvRenderer_SetFloorCell(fvRenderer* renderer, float metres);

/// Clear and draw @p list seen by @p camera into the bound framebuffer's @p width x @p height
/// pixels. False when the staging memory cannot be had (nothing is drawn).
bool fvRenderer_Draw(fvRenderer* renderer, const fvDrawList* list, const fvCamera* camera,
                     int width, int height);
