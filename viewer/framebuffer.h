// An offscreen framebuffer: multisampled colour and depth-stencil renderbuffers, resolved into a
// single-sampled colour buffer that can be read back or copied to a window.
#pragma once

#include <stdbool.h>

/// Framebuffer objects and renderbuffers (OpenGL names).
typedef struct fvFramebuffer
{
	unsigned drawFramebuffer; ///< multisampled: colour + depth-stencil
	unsigned colorSamples;
	unsigned depthStencil;
	unsigned resolveFramebuffer; ///< single-sampled colour
	unsigned resolveColor;
	int width;
	int height;
	int samples;
} fvFramebuffer;

/// Create (or re-create at a new size) a @p width x @p height framebuffer with up to
/// @p samples samples a pixel (fewer where the driver has fewer). Needs a current context.
bool fvFramebuffer_Resize(fvFramebuffer* framebuffer, int width, int height, int samples);

/// Bind for drawing, with the viewport covering it.
void fvFramebuffer_Bind(const fvFramebuffer* framebuffer);

/// Resolve the samples into the single-sampled buffer.
void fvFramebuffer_Resolve(const fvFramebuffer* framebuffer);

/// Read the resolved image as RGBA, 4 bytes a pixel, rows from the top (after Resolve).
void fvFramebuffer_Read(const fvFramebuffer* framebuffer, unsigned char* rgba);

/// Copy the resolved image to the window's framebuffer (@p width x @p height pixels).
void fvFramebuffer_BlitToWindow(const fvFramebuffer* framebuffer, int width, int height);

/// Read the window's back buffer (@p width x @p height pixels) as RGBA, rows from the top:
/// what the next swap shows.
void fvFramebuffer_ReadWindow(int width, int height, unsigned char* rgba);

/// Release the GL objects.
void fvFramebuffer_Destroy(fvFramebuffer* framebuffer);
