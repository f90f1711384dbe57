// The `femto view` window: GLFW with an OpenGL 3.3 core context (functions through libepoxy).
// Input events go to a handler as framebuffer pixels (from the top-left) and key names, the
// same terms scripts use (script.h).
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// Where the window's input goes.
typedef struct fvInputHandler
{
	/// @p button: 0 left, 1 right, 2 middle; @p x, @p y in framebuffer pixels.
	void (*mouseButton)(void* context, int button, bool down, float x, float y);
	void (*mouseMove)(void* context, float x, float y);
	void (*scroll)(void* context, float steps);
	/// A key went down: "space", "p", "s", "n", "r", "i", "m", "f", "escape", "q".
	void (*key)(void* context, const char* name);
	void* context;
} fvInputHandler;

/// A window and its handler.
typedef struct fvWindow
{
	void* glfw; ///< GLFWwindow*
	fvInputHandler input;
	bool forwardInput; ///< false while a script plays: real input is ignored
} fvWindow;

/// Open a @p width x @p height window titled @p title with an OpenGL 3.3 core context, current.
/// On failure (no display, no OpenGL 3.3) writes why into @p error and returns false.
bool fvWindow_Create(fvWindow* window, int width, int height, const char* title, char* error,
                     size_t errorSize);

/// Close the window and shut GLFW down. Safe on a window that failed to open.
void fvWindow_Destroy(fvWindow* window);

/// Process pending events (calls the handler).
void fvWindow_Poll(fvWindow* window);

/// Show the frame drawn.
void fvWindow_Swap(fvWindow* window);

/// Whether the user closed the window.
bool fvWindow_ShouldClose(const fvWindow* window);

/// The framebuffer's size in pixels.
void fvWindow_FramebufferSize(const fvWindow* window, int* width, int* height);

/// Seconds since GLFW started.
double fvWindow_Time(void);
