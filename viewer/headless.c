// EGL without a window: the surfaceless platform of Mesa (llvmpipe on machines without a GPU,
// the GPU's driver where there is one). The context has no default framebuffer; the renderer
// draws into a framebuffer object of its own (renderer.c).
#include "headless.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <string.h>

static bool fvHasExtension(const char* list, const char* name)
{
	size_t length = strlen(name);
	for (const char* p = list; p != NULL && (p = strstr(p, name)) != NULL; p += length)
		if ((p == list || p[-1] == ' ') && (p[length] == ' ' || p[length] == 0))
			return true;
	return false;
}

static bool fvFail(char* error, size_t size, const char* what)
{
	snprintf(error, size, "%s (EGL error 0x%x)", what, (unsigned)eglGetError());
	return false;
}

// The surfaceless display: needs EGL_MESA_platform_surfaceless (Mesa's libegl-mesa0).
static EGLDisplay fvOpenDisplay(char* error, size_t size)
{
	const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	if (!fvHasExtension(clientExtensions, "EGL_MESA_platform_surfaceless") ||
	    !fvHasExtension(clientExtensions, "EGL_EXT_platform_base"))
	{
		snprintf(error, size,
		         "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless); install Mesa's "
		         "EGL driver: apt-get install libegl-mesa0 libgl1-mesa-dri");
		return EGL_NO_DISPLAY;
	}
	EGLDisplay display =
	    eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
	EGLint major = 0, minor = 0;
	if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
	{
		fvFail(error, size, "cannot initialise the EGL surfaceless display");
		return EGL_NO_DISPLAY;
	}
	return display;
}

bool fvHeadless_Create(fvHeadless* headless, char* error, size_t errorSize)
{
	memset(headless, 0, sizeof *headless);
	EGLDisplay display = fvOpenDisplay(error, errorSize);
	if (display == EGL_NO_DISPLAY)
		return false;
	headless->display = display;
	const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
	if (!fvHasExtension(extensions, "EGL_KHR_surfaceless_context"))
	{
		snprintf(error, errorSize,
		         "the EGL driver cannot make a context current without a surface "
		         "(EGL_KHR_surfaceless_context)");
		fvHeadless_Destroy(headless);
		return false;
	}
	const EGLint configAttributes[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
	                                   EGL_NONE};
	EGLConfig config;
	EGLint count = 0;
	if (!eglBindAPI(EGL_OPENGL_API) ||
	    !eglChooseConfig(display, configAttributes, &config, 1, &count) || count < 1)
	{
		fvHeadless_Destroy(headless);
		return fvFail(error, errorSize, "no EGL configuration for desktop OpenGL");
	}
	const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
	                                    3,
	                                    EGL_CONTEXT_MINOR_VERSION,
	                                    3,
	                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
	                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
	                                    EGL_NONE};
	EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
	if (context == EGL_NO_CONTEXT)
	{
		fvHeadless_Destroy(headless);
		return fvFail(error, errorSize, "cannot create an OpenGL 3.3 core context");
	}
	headless->context = context;
	if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
	{
		fvHeadless_Destroy(headless);
		return fvFail(error, errorSize, "cannot make the OpenGL context current");
	}
	return true;
}

void fvHeadless_Destroy(fvHeadless* headless)
{
	if (headless->display == NULL)
		return;
	eglMakeCurrent(headless->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	if (headless->context != NULL)
		eglDestroyContext(headless->display, headless->context);
	eglTerminate(headless->display);
	memset(headless, 0, sizeof *headless);
}
