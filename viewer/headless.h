// An OpenGL 3.3 core context without a window or display: EGL on Mesa's surfaceless platform
// (EGL_PLATFORM_SURFACELESS_MESA), no pbuffer; the renderer draws into its own framebuffer.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// The EGL display and context of a headless session.
typedef struct fvHeadless
{
	void* display; ///< EGLDisplay
	void* context; ///< EGLContext
} fvHeadless;

/// Create an OpenGL 3.3 core context on the surfaceless platform and make it current. On
/// failure writes what is missing (EGL extension, driver) into @p error and returns false.
bool fvHeadless_Create(fvHeadless* headless, char* error, size_t errorSize);

/// Release the context and the display. Safe on a session that failed to create.
void fvHeadless_Destroy(fvHeadless* headless);
