// The GLFW window (window.h).
#include "window.h"

#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char fvGlfwError[256];

static void fvOnGlfwError(int code, const char* description)
{
	snprintf(fvGlfwError, sizeof fvGlfwError, "%s (GLFW error 0x%x)", description, code);
}

// Window coordinates (screen units) to framebuffer pixels, which differ on high-DPI screens.
static void fvToPixels(GLFWwindow* glfw, double x, double y, float* px, float* py)
{
	int width = 0, height = 0, pixelsWide = 0, pixelsHigh = 0;
	glfwGetWindowSize(glfw, &width, &height);
	glfwGetFramebufferSize(glfw, &pixelsWide, &pixelsHigh);
	*px = (float)(x * (width > 0 ? (double)pixelsWide / width : 1.0));
	*py = (float)(y * (height > 0 ? (double)pixelsHigh / height : 1.0));
}

static fvWindow* fvOwner(GLFWwindow* glfw)
{
	fvWindow* window = glfwGetWindowUserPointer(glfw);
	return window != NULL && window->forwardInput ? window : NULL;
}

static void fvOnMouseButton(GLFWwindow* glfw, int button, int action, int mods)
{
	(void)mods;
	fvWindow* w = fvOwner(glfw);
	int mapped = button == GLFW_MOUSE_BUTTON_LEFT     ? 0
	             : button == GLFW_MOUSE_BUTTON_RIGHT  ? 1
	             : button == GLFW_MOUSE_BUTTON_MIDDLE ? 2
	                                                  : -1;
	if (w == NULL || w->input.mouseButton == NULL || mapped < 0)
		return;
	double x = 0.0, y = 0.0;
	float px, py;
	glfwGetCursorPos(glfw, &x, &y);
	fvToPixels(glfw, x, y, &px, &py);
	w->input.mouseButton(w->input.context, mapped, action == GLFW_PRESS, px, py);
}

static void fvOnCursor(GLFWwindow* glfw, double x, double y)
{
	fvWindow* w = fvOwner(glfw);
	float px, py;
	if (w == NULL || w->input.mouseMove == NULL)
		return;
	fvToPixels(glfw, x, y, &px, &py);
	w->input.mouseMove(w->input.context, px, py);
}

static void fvOnScroll(GLFWwindow* glfw, double dx, double dy)
{
	(void)dx;
	fvWindow* w = fvOwner(glfw);
	if (w != NULL && w->input.scroll != NULL)
		w->input.scroll(w->input.context, (float)dy);
}

static const char* fvKeyName(int key)
{
	switch (key)
	{
	case GLFW_KEY_SPACE:
		return "space";
	case GLFW_KEY_P:
		return "p";
	case GLFW_KEY_S:
		return "s";
	case GLFW_KEY_N:
		return "n";
	case GLFW_KEY_R:
		return "r";
	case GLFW_KEY_I:
		return "i";
	case GLFW_KEY_M:
		return "m";
	case GLFW_KEY_F:
		return "f";
	case GLFW_KEY_Q:
		return "q";
	case GLFW_KEY_ESCAPE:
		return "escape";
	default:
		return NULL;
	}
}

static void fvOnKey(GLFWwindow* glfw, int key, int scancode, int action, int mods)
{
	(void)scancode, (void)mods;
	fvWindow* w = fvOwner(glfw);
	const char* name = fvKeyName(key);
	if (w != NULL && w->input.key != NULL && name != NULL && action == GLFW_PRESS)
		w->input.key(w->input.context, name);
}

// Why there is no window: GLFW's message, and the usual cause.
static bool fvWindowError(char* error, size_t size, const char* what)
{
	const char* display = getenv("DISPLAY");
	const char* wayland = getenv("WAYLAND_DISPLAY");
	if ((display == NULL || *display == 0) && (wayland == NULL || *wayland == 0))
		snprintf(error, size,
		         "%s: no display (DISPLAY is not set); run it on a desktop, under xvfb-run, or "
		         "make pictures without a window: femto run --gif FILE",
		         what);
	else
		snprintf(error, size, "%s: %s", what, fvGlfwError[0] ? fvGlfwError : "unknown error");
	return false;
}

bool fvWindow_Create(fvWindow* window, int width, int height, const char* title, char* error,
                     size_t errorSize)
{
	memset(window, 0, sizeof *window);
	glfwSetErrorCallback(fvOnGlfwError);
	if (!glfwInit())
		return fvWindowError(error, errorSize, "cannot start GLFW");
	glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
	glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
	glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
	glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
	GLFWwindow* glfw = glfwCreateWindow(width, height, title, NULL, NULL);
	if (glfw == NULL)
	{
		fvWindowError(error, errorSize, "cannot open an OpenGL 3.3 core window");
		glfwTerminate();
		return false;
	}
	window->glfw = glfw;
	window->forwardInput = true;
	glfwSetWindowUserPointer(glfw, window);
	glfwMakeContextCurrent(glfw);
	glfwSwapInterval(1);
	glfwSetMouseButtonCallback(glfw, fvOnMouseButton);
	glfwSetCursorPosCallback(glfw, fvOnCursor);
	glfwSetScrollCallback(glfw, fvOnScroll);
	glfwSetKeyCallback(glfw, fvOnKey);
	return true;
}

void fvWindow_Destroy(fvWindow* window)
{
	if (window->glfw == NULL)
		return;
	glfwDestroyWindow(window->glfw);
	glfwTerminate();
	memset(window, 0, sizeof *window);
}

void fvWindow_Poll(fvWindow* window)
{
	(void)window;
	glfwPollEvents();
}

void fvWindow_Swap(fvWindow* window)
{
	glfwSwapBuffers(window->glfw);
}

bool fvWindow_ShouldClose(const fvWindow* window)
{
	return glfwWindowShouldClose(window->glfw);
}

void fvWindow_FramebufferSize(const fvWindow* window, int* width, int* height)
{
	glfwGetFramebufferSize(window->glfw, width, height);
}

double fvWindow_Time(void)
{
	return glfwGetTime();
}
