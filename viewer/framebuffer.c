// Offscreen framebuffers (framebuffer.h): multisampling for smooth edges in the GIF and PNG
// frames and in the window alike.
#include "framebuffer.h"

#include <epoxy/gl.h>
#include <string.h>

void fvFramebuffer_Destroy(fvFramebuffer* f)
{
	if (f->drawFramebuffer != 0)
		glDeleteFramebuffers(1, &f->drawFramebuffer);
	if (f->resolveFramebuffer != 0)
		glDeleteFramebuffers(1, &f->resolveFramebuffer);
	GLuint buffers[3] = {f->colorSamples, f->depthStencil, f->resolveColor};
	glDeleteRenderbuffers(3, buffers);
	memset(f, 0, sizeof *f);
}

bool fvFramebuffer_Resize(fvFramebuffer* f, int width, int height, int samples)
{
	if (f->drawFramebuffer != 0 && f->width == width && f->height == height)
		return true;
	fvFramebuffer_Destroy(f);
	GLint maxSamples = 1;
	glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
	f->samples = samples < maxSamples ? samples : maxSamples;
	f->width = width;
	f->height = height;
	glGenRenderbuffers(1, &f->colorSamples);
	glBindRenderbuffer(GL_RENDERBUFFER, f->colorSamples);
	glRenderbufferStorageMultisample(GL_RENDERBUFFER, f->samples, GL_RGBA8, width, height);
	glGenRenderbuffers(1, &f->depthStencil);
	glBindRenderbuffer(GL_RENDERBUFFER, f->depthStencil);
	glRenderbufferStorageMultisample(GL_RENDERBUFFER, f->samples, GL_DEPTH24_STENCIL8, width,
	                                 height);
	glGenFramebuffers(1, &f->drawFramebuffer);
	glBindFramebuffer(GL_FRAMEBUFFER, f->drawFramebuffer);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
	                          f->colorSamples);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
	                          f->depthStencil);
	bool complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
	glGenRenderbuffers(1, &f->resolveColor);
	glBindRenderbuffer(GL_RENDERBUFFER, f->resolveColor);
	glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
	glGenFramebuffers(1, &f->resolveFramebuffer);
	glBindFramebuffer(GL_FRAMEBUFFER, f->resolveFramebuffer);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
	                          f->resolveColor);
	complete = complete && glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	if (!complete)
		fvFramebuffer_Destroy(f);
	return complete;
}

void fvFramebuffer_Bind(const fvFramebuffer* f)
{
	glBindFramebuffer(GL_FRAMEBUFFER, f->drawFramebuffer);
	glViewport(0, 0, f->width, f->height);
}

void fvFramebuffer_Resolve(const fvFramebuffer* f)
{
	glBindFramebuffer(GL_READ_FRAMEBUFFER, f->drawFramebuffer);
	glBindFramebuffer(GL_DRAW_FRAMEBUFFER, f->resolveFramebuffer);
	glBlitFramebuffer(0, 0, f->width, f->height, 0, 0, f->width, f->height, GL_COLOR_BUFFER_BIT,
	                  GL_NEAREST);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// OpenGL's rows start at the bottom; images start at the top.
static void fvFlipRows(unsigned char* rgba, int width, int height)
{
	size_t row = 4 * (size_t)width;
	for (int y = 0; y < height / 2; ++y)
	{
		unsigned char* a = rgba + row * (size_t)y;
		unsigned char* b = rgba + row * (size_t)(height - 1 - y);
		for (size_t i = 0; i < row; ++i)
		{
			unsigned char t = a[i];
			a[i] = b[i];
			b[i] = t;
		}
	}
}

void fvFramebuffer_Read(const fvFramebuffer* f, unsigned char* rgba)
{
	glBindFramebuffer(GL_READ_FRAMEBUFFER, f->resolveFramebuffer);
	glPixelStorei(GL_PACK_ALIGNMENT, 1);
	glReadPixels(0, 0, f->width, f->height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
	glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
	fvFlipRows(rgba, f->width, f->height);
}

void fvFramebuffer_ReadWindow(int width, int height, unsigned char* rgba)
{
	glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
	glReadBuffer(GL_BACK);
	glPixelStorei(GL_PACK_ALIGNMENT, 1);
	glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
	fvFlipRows(rgba, width, height);
}

void fvFramebuffer_BlitToWindow(const fvFramebuffer* f, int width, int height)
{
	glBindFramebuffer(GL_READ_FRAMEBUFFER, f->resolveFramebuffer);
	glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
	glBlitFramebuffer(0, 0, f->width, f->height, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
	                  GL_NEAREST);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
}
