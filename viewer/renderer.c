// The renderer (renderer.h). One frame, in order:
//   1. background: a vertical grey gradient (full-screen triangle, no depth);
//   2. floor: the plane the library draws, checkered (box-filtered so it does not shimmer),
//      darkened under each body by a soft occlusion blob and faded into the background with
//      distance; it marks the stencil buffer;
//   3. shadows: the surfaces flattened onto the floor along the key light (the planar
//      projection matrix of Blinn, "Me and my (fake) shadow", 1988), blended once per pixel
//      where the floor is (stencil);
//   4. surfaces: per-vertex normals and colours, hemisphere ambient (sky above, ground below),
//      a key light with a little specular, darker near the floor (contact occlusion);
//   5. lines, then round points, a hair in front of the surfaces they lie on.
#include "renderer.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FV_MAX_BLOBS 16

struct fvRenderer
{
	GLuint surfaceProgram, floorProgram, colorProgram, backgroundProgram;
	GLuint surfaceArray, surfaceBuffer, surfaceIndices;
	GLuint lineArray, lineBuffer;
	GLuint pointArray, pointBuffer;
	GLuint emptyArray;
	float* vertices; ///< staging: 9 floats a surface vertex
	size_t vertexCapacity;
	unsigned* indices; ///< staging
	size_t indexCapacity;
	float floorCell;
};

// The key light's direction (toward the light), unnormalised: high and from the left, so the
// shadows fall to the right of the default view, beside the bodies.
static const float fvLight[3] = {-0.45f, 1.0f, 0.35f};

static const char* const fvSurfaceVertex =
    "#version 330 core\n"
    "layout(location = 0) in vec3 aPosition;\n"
    "layout(location = 1) in vec3 aNormal;\n"
    "layout(location = 2) in vec3 aColor;\n"
    "uniform mat4 uViewProjection;\n"
    "uniform mat4 uModel;\n"
    "out vec3 vPosition;\n"
    "out vec3 vNormal;\n"
    "out vec3 vColor;\n"
    "void main() {\n"
    "  vPosition = aPosition;\n"
    "  vNormal = aNormal;\n"
    "  vColor = aColor;\n"
    "  gl_Position = uViewProjection * (uModel * vec4(aPosition, 1.0));\n"
    "}\n";

static const char* const fvSurfaceFragment =
    "#version 330 core\n"
    "in vec3 vPosition;\n"
    "in vec3 vNormal;\n"
    "in vec3 vColor;\n"
    "uniform vec3 uEye;\n"
    "uniform vec3 uLight;\n"
    "uniform vec4 uPlane;\n" // normal and offset: n.x + w = height above the floor
    "uniform float uContactHeight;\n"
    "uniform int uShadow;\n"
    "out vec4 fragColor;\n"
    "void main() {\n"
    "  if (uShadow == 1) { fragColor = vec4(0.0, 0.0, 0.0, 0.28); return; }\n"
    "  vec3 n = normalize(vNormal);\n"
    "  if (!gl_FrontFacing) n = -n;\n"
    "  vec3 v = normalize(uEye - vPosition);\n"
    "  float up = dot(n, uPlane.xyz);\n"
    "  vec3 ambient = mix(vec3(0.22, 0.21, 0.20), vec3(0.50, 0.53, 0.58), 0.5 + 0.5 * up);\n"
    "  float height = dot(uPlane.xyz, vPosition) + uPlane.w;\n"
    "  float contact = mix(0.55, 1.0, clamp(height / uContactHeight, 0.0, 1.0));\n"
    "  float diffuse = max(dot(n, uLight), 0.0);\n"
    "  float specular = pow(max(dot(n, normalize(uLight + v)), 0.0), 40.0) * 0.18;\n"
    "  vec3 c = vColor * (ambient * contact + 0.78 * diffuse * vec3(1.0, 0.97, 0.92));\n"
    "  fragColor = vec4(c + specular * contact, 1.0);\n"
    "}\n";

static const char* const fvFloorVertex =
    "#version 330 core\n"
    "uniform mat4 uViewProjection;\n"
    "uniform vec3 uCenter;\n"
    "uniform vec3 uAxisU;\n"
    "uniform vec3 uAxisV;\n"
    "out vec3 vWorld;\n"
    "out vec2 vPlane;\n"
    "void main() {\n"
    "  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;\n"
    "  vWorld = uCenter + corner.x * uAxisU + corner.y * uAxisV;\n"
    "  vPlane = vec2(dot(vWorld, normalize(uAxisU)), dot(vWorld, normalize(uAxisV)));\n"
    "  gl_Position = uViewProjection * vec4(vWorld, 1.0);\n"
    "}\n";

// The checker is a product of two square waves box-filtered over the pixel's footprint
// (Quilez, "Filtering procedurals: checkerboard"), so it does not alias at grazing angles.
static const char* const fvFloorFragment =
    "#version 330 core\n"
    "in vec3 vWorld;\n"
    "in vec2 vPlane;\n"
    "uniform vec3 uColor;\n"
    "uniform vec3 uEye;\n"
    "uniform vec3 uFog;\n"
    "uniform vec3 uFogTop;\n"
    "uniform float uViewportHeight;\n"
    "uniform float uCell;\n"
    "uniform vec2 uFade;\n"
    "uniform vec4 uBlobs[16];\n"
    "uniform int uBlobCount;\n"
    "out vec4 fragColor;\n"
    "void main() {\n"
    "  vec2 p = vPlane / uCell;\n"
    "  vec2 w = max(fwidth(p), vec2(1e-4));\n"
    "  vec2 i = 2.0 * (abs(fract((p - 0.5 * w) * 0.5) - 0.5) -\n"
    "                  abs(fract((p + 0.5 * w) * 0.5) - 0.5)) / w;\n"
    "  float checker = 0.5 - 0.5 * i.x * i.y;\n"
    "  vec3 color = uColor * mix(0.80, 1.0, checker);\n"
    "  float occlusion = 1.0;\n"
    "  for (int k = 0; k < uBlobCount; ++k) {\n"
    "    vec3 d = vWorld - uBlobs[k].xyz;\n"
    "    occlusion *= 1.0 - 0.5 * exp(-2.0 * dot(d, d) / (uBlobs[k].w * uBlobs[k].w));\n"
    "  }\n"
    "  float fade = smoothstep(uFade.x, uFade.y, length(vWorld - uEye));\n"
    "  // Into the background's own grey at this row (its vertical gradient), so the floor's far\n"
    "  // edge melts into it instead of ending in a darker band at the horizon.\n"
    "  vec3 fog = mix(uFog, uFogTop, clamp(gl_FragCoord.y / uViewportHeight, 0.0, 1.0));\n"
    "  fragColor = vec4(mix(color * occlusion, fog, fade), 1.0);\n"
    "}\n";

static const char* const fvColorVertex = "#version 330 core\n"
                                         "layout(location = 0) in vec3 aPosition;\n"
                                         "layout(location = 1) in vec3 aColor;\n"
                                         "layout(location = 2) in float aSize;\n"
                                         "uniform mat4 uViewProjection;\n"
                                         "uniform float uBias;\n"
                                         "out vec3 vColor;\n"
                                         "void main() {\n"
                                         "  vColor = aColor;\n"
                                         "  gl_Position = uViewProjection * vec4(aPosition, 1.0);\n"
                                         "  gl_Position.z -= uBias * gl_Position.w;\n"
                                         "  gl_PointSize = aSize;\n"
                                         "}\n";

static const char* const fvColorFragment =
    "#version 330 core\n"
    "in vec3 vColor;\n"
    "uniform int uRound;\n"
    "out vec4 fragColor;\n"
    "void main() {\n"
    "  if (uRound == 1 && length(gl_PointCoord - vec2(0.5)) > 0.5) discard;\n"
    "  fragColor = vec4(vColor, 1.0);\n"
    "}\n";

static const char* const fvBackgroundVertex =
    "#version 330 core\n"
    "out float vHeight;\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID >> 1) * 4 - 1));\n"
    "  vHeight = 0.5 * p.y + 0.5;\n"
    "  gl_Position = vec4(p, 1.0, 1.0);\n"
    "}\n";

static const char* const fvBackgroundFragment =
    "#version 330 core\n"
    "in float vHeight;\n"
    "uniform vec3 uBottom;\n"
    "uniform vec3 uTop;\n"
    "out vec4 fragColor;\n"
    "void main() { fragColor = vec4(mix(uBottom, uTop, clamp(vHeight, 0.0, 1.0)), 1.0); }\n";

// The background's grey at the bottom and top of the image; the floor fades into the bottom's.
static const float fvBottomGrey[3] = {0.70f, 0.70f, 0.70f};
static const float fvTopGrey[3] = {0.88f, 0.88f, 0.88f};

static GLuint fvCompile(GLenum kind, const char* source, const char* name, char* error,
                        size_t errorSize)
{
	GLuint shader = glCreateShader(kind);
	glShaderSource(shader, 1, &source, NULL);
	glCompileShader(shader);
	GLint ok = 0;
	glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
	if (ok)
		return shader;
	char log[1024] = "";
	glGetShaderInfoLog(shader, sizeof log, NULL, log);
	snprintf(error, errorSize, "the %s shader does not compile: %s", name, log);
	glDeleteShader(shader);
	return 0;
}

static GLuint fvLink(const char* vertex, const char* fragment, const char* name, char* error,
                     size_t errorSize)
{
	GLuint vs = fvCompile(GL_VERTEX_SHADER, vertex, name, error, errorSize);
	GLuint fs = vs ? fvCompile(GL_FRAGMENT_SHADER, fragment, name, error, errorSize) : 0;
	if (fs == 0)
	{
		glDeleteShader(vs);
		return 0;
	}
	GLuint program = glCreateProgram();
	glAttachShader(program, vs);
	glAttachShader(program, fs);
	glLinkProgram(program);
	glDeleteShader(vs);
	glDeleteShader(fs);
	GLint ok = 0;
	glGetProgramiv(program, GL_LINK_STATUS, &ok);
	if (ok)
		return program;
	char log[1024] = "";
	glGetProgramInfoLog(program, sizeof log, NULL, log);
	snprintf(error, errorSize, "the %s shaders do not link: %s", name, log);
	glDeleteProgram(program);
	return 0;
}

// A vertex array over one buffer of @p stride floats a vertex, attributes of the given sizes.
static void fvMakeArray(GLuint* array, GLuint* buffer, int stride, const int* sizes, int count)
{
	glGenVertexArrays(1, array);
	glGenBuffers(1, buffer);
	glBindVertexArray(*array);
	glBindBuffer(GL_ARRAY_BUFFER, *buffer);
	size_t offset = 0;
	for (int i = 0; i < count; ++i)
	{
		glEnableVertexAttribArray((GLuint)i);
		glVertexAttribPointer((GLuint)i, sizes[i], GL_FLOAT, GL_FALSE,
		                      stride * (GLsizei)sizeof(float),
		                      (const void*)(offset * sizeof(float)));
		offset += (size_t)sizes[i];
	}
}

fvRenderer* fvRenderer_Create(char* error, size_t errorSize)
{
	fvRenderer* r = calloc(1, sizeof *r);
	if (r == NULL)
	{
		snprintf(error, errorSize, "out of memory");
		return NULL;
	}
	r->floorCell = 1.0f;
	r->surfaceProgram = fvLink(fvSurfaceVertex, fvSurfaceFragment, "surface", error, errorSize);
	r->floorProgram = fvLink(fvFloorVertex, fvFloorFragment, "floor", error, errorSize);
	r->colorProgram = fvLink(fvColorVertex, fvColorFragment, "line", error, errorSize);
	r->backgroundProgram =
	    fvLink(fvBackgroundVertex, fvBackgroundFragment, "background", error, errorSize);
	if (!r->surfaceProgram || !r->floorProgram || !r->colorProgram || !r->backgroundProgram)
	{
		fvRenderer_Destroy(r);
		return NULL;
	}
	static const int surfaceSizes[3] = {3, 3, 3}, lineSizes[2] = {3, 3}, pointSizes[3] = {3, 3, 1};
	fvMakeArray(&r->surfaceArray, &r->surfaceBuffer, 9, surfaceSizes, 3);
	glGenBuffers(1, &r->surfaceIndices);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->surfaceIndices);
	fvMakeArray(&r->lineArray, &r->lineBuffer, 6, lineSizes, 2);
	fvMakeArray(&r->pointArray, &r->pointBuffer, 7, pointSizes, 3);
	glGenVertexArrays(1, &r->emptyArray);
	glBindVertexArray(0);
	return r;
}

void fvRenderer_Destroy(fvRenderer* r)
{
	if (r == NULL)
		return;
	GLuint programs[4] = {r->surfaceProgram, r->floorProgram, r->colorProgram,
	                      r->backgroundProgram};
	for (int i = 0; i < 4; ++i)
		if (programs[i] != 0)
			glDeleteProgram(programs[i]);
	GLuint arrays[4] = {r->surfaceArray, r->lineArray, r->pointArray, r->emptyArray};
	GLuint buffers[4] = {r->surfaceBuffer, r->surfaceIndices, r->lineBuffer, r->pointBuffer};
	glDeleteVertexArrays(4, arrays);
	glDeleteBuffers(4, buffers);
	free(r->vertices);
	free(r->indices);
	free(r);
}

void fvRenderer_SetFloorCell(fvRenderer* r, float metres)
{
	if (metres > 0.0f && isfinite(metres))
		r->floorCell = metres;
}

static void fvUniform3(GLuint program, const char* name, const float* v)
{
	glUniform3fv(glGetUniformLocation(program, name), 1, v);
}

static void fvUniformMatrix(GLuint program, const char* name, const float* m)
{
	glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m);
}

// out = a * b, column-major.
static void fvMultiply(const float a[16], const float b[16], float out[16])
{
	for (int c = 0; c < 4; ++c)
		for (int r = 0; r < 4; ++r)
		{
			float sum = 0.0f;
			for (int k = 0; k < 4; ++k)
				sum += a[4 * k + r] * b[4 * c + k];
			out[4 * c + r] = sum;
		}
}

static void fvUnitLight(float light[3])
{
	float length =
	    sqrtf(fvLight[0] * fvLight[0] + fvLight[1] * fvLight[1] + fvLight[2] * fvLight[2]);
	for (int i = 0; i < 3; ++i)
		light[i] = fvLight[i] / length;
}

// Copy every surface into one vertex and one index array (indices offset per surface).
static bool fvStageSurfaces(fvRenderer* r, const fvDrawList* list, size_t* indexCount)
{
	size_t vertices = 0, indices = 0;
	for (int s = 0; s < list->surfaceCount; ++s)
	{
		vertices += (size_t)list->surfaces[s].vertexCount;
		indices += 3 * (size_t)list->surfaces[s].triangleCount;
	}
	if (vertices > UINT32_MAX || vertices > SIZE_MAX / (9 * sizeof(float)))
		return false;
	if (vertices > r->vertexCapacity)
	{
		float* grown = realloc(r->vertices, vertices * 9 * sizeof(float));
		if (grown == NULL)
			return false;
		r->vertices = grown;
		r->vertexCapacity = vertices;
	}
	if (indices > r->indexCapacity)
	{
		unsigned* grown = realloc(r->indices, indices * sizeof(unsigned));
		if (grown == NULL)
			return false;
		r->indices = grown;
		r->indexCapacity = indices;
	}
	size_t v = 0, i = 0;
	for (int s = 0; s < list->surfaceCount; ++s)
	{
		const fvSurface* surface = &list->surfaces[s];
		for (int k = 0; k < surface->vertexCount; ++k, ++v)
		{
			memcpy(r->vertices + 9 * v, surface->positions + 3 * k, 3 * sizeof(float));
			memcpy(r->vertices + 9 * v + 3, surface->normals + 3 * k, 3 * sizeof(float));
			memcpy(r->vertices + 9 * v + 6, surface->colors + 3 * k, 3 * sizeof(float));
		}
		unsigned base = (unsigned)(v - (size_t)surface->vertexCount);
		for (int k = 0; k < 3 * surface->triangleCount; ++k)
			r->indices[i++] = base + (unsigned)surface->indices[k];
	}
	*indexCount = i;
	glBindVertexArray(r->surfaceArray);
	glBindBuffer(GL_ARRAY_BUFFER, r->surfaceBuffer);
	glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(v * 9 * sizeof(float)), r->vertices, GL_STREAM_DRAW);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->surfaceIndices);
	glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(i * sizeof(unsigned)), r->indices,
	             GL_STREAM_DRAW);
	return true;
}

static void fvDrawBackground(const fvRenderer* r)
{
	glDisable(GL_DEPTH_TEST);
	glUseProgram(r->backgroundProgram);
	fvUniform3(r->backgroundProgram, "uBottom", fvBottomGrey);
	fvUniform3(r->backgroundProgram, "uTop", fvTopGrey);
	glBindVertexArray(r->emptyArray);
	glDrawArrays(GL_TRIANGLES, 0, 3);
}

// A blob (centre, radius) per body's surface: the centre of its box, radius half the box's
// diagonal. Colliders cast none (they rest on nothing).
static int fvBlobs(const fvDrawList* list, float blobs[][4])
{
	int count = 0;
	for (int s = 0; s < list->surfaceCount && count < FV_MAX_BLOBS; ++s)
	{
		const fvSurface* surface = &list->surfaces[s];
		if (surface->body.index1 == 0)
			continue;
		float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
		for (int k = 0; k < surface->vertexCount; ++k)
			for (int a = 0; a < 3; ++a)
			{
				lo[a] = fminf(lo[a], surface->positions[3 * k + a]);
				hi[a] = fmaxf(hi[a], surface->positions[3 * k + a]);
			}
		if (surface->vertexCount == 0)
			continue;
		float diagonal = 0.0f;
		for (int a = 0; a < 3; ++a)
		{
			blobs[count][a] = 0.5f * (lo[a] + hi[a]);
			diagonal += (hi[a] - lo[a]) * (hi[a] - lo[a]);
		}
		blobs[count++][3] = fmaxf(0.5f * sqrtf(diagonal), 1e-3f);
	}
	return count;
}

// Two unit axes spanning the plane.
static void fvPlaneAxes(const float n[3], float u[3], float v[3])
{
	float helper[3] = {1.0f, 0.0f, 0.0f};
	if (fabsf(n[0]) > 0.9f)
		helper[0] = 0.0f, helper[2] = 1.0f;
	u[0] = helper[1] * n[2] - helper[2] * n[1];
	u[1] = helper[2] * n[0] - helper[0] * n[2];
	u[2] = helper[0] * n[1] - helper[1] * n[0];
	float length = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
	for (int i = 0; i < 3; ++i)
		u[i] /= length;
	v[0] = n[1] * u[2] - n[2] * u[1];
	v[1] = n[2] * u[0] - n[0] * u[2];
	v[2] = n[0] * u[1] - n[1] * u[0];
}

static void fvDrawFloor(const fvRenderer* r, const fvDrawList* list, const fvCamera* camera,
                        const float viewProjection[16])
{
	GLuint p = r->floorProgram;
	float eye[3], u[3], v[3], center[3];
	fvCamera_Eye(camera, eye);
	fvPlaneAxes(list->planeNormal, u, v);
	// The quad is centred below the camera's target and reaches past the fade-out distance.
	float fadeStart = 2.5f * camera->distance, fadeEnd = 7.0f * camera->distance;
	float halfSize = fadeEnd + camera->distance;
	float toTarget = 0.0f;
	for (int i = 0; i < 3; ++i)
		toTarget += (camera->target[i] - list->planePoint[i]) * list->planeNormal[i];
	for (int i = 0; i < 3; ++i)
	{
		center[i] = camera->target[i] - toTarget * list->planeNormal[i];
		u[i] *= halfSize;
		v[i] *= halfSize;
	}
	float blobs[FV_MAX_BLOBS][4];
	int blobCount = fvBlobs(list, blobs);
	glUseProgram(p);
	fvUniformMatrix(p, "uViewProjection", viewProjection);
	fvUniform3(p, "uCenter", center);
	fvUniform3(p, "uAxisU", u);
	fvUniform3(p, "uAxisV", v);
	fvUniform3(p, "uColor", list->planeColor);
	fvUniform3(p, "uEye", eye);
	fvUniform3(p, "uFog", fvBottomGrey);
	fvUniform3(p, "uFogTop", fvTopGrey);
	GLint viewport[4];
	glGetIntegerv(GL_VIEWPORT, viewport);
	glUniform1f(glGetUniformLocation(p, "uViewportHeight"),
	            (float)(viewport[3] > 0 ? viewport[3] : 1));
	glUniform1f(glGetUniformLocation(p, "uCell"), r->floorCell);
	glUniform2f(glGetUniformLocation(p, "uFade"), fadeStart, fadeEnd);
	glUniform4fv(glGetUniformLocation(p, "uBlobs"), blobCount, &blobs[0][0]);
	glUniform1i(glGetUniformLocation(p, "uBlobCount"), blobCount);
	glEnable(GL_DEPTH_TEST);
	glEnable(GL_STENCIL_TEST);
	glStencilFunc(GL_ALWAYS, 1, 0xff);
	glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
	glBindVertexArray(r->emptyArray);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glDisable(GL_STENCIL_TEST);
}

// The matrix that flattens points onto the plane along the light: (plane . light) I -
// light plane^T, with plane = (n, -n.p) and light = (L, 0) a direction (Blinn 1988).
static void fvShadowMatrix(const fvDrawList* list, const float light[3], float m[16])
{
	const float* n = list->planeNormal;
	float plane[4] = {
	    n[0], n[1], n[2],
	    -(n[0] * list->planePoint[0] + n[1] * list->planePoint[1] + n[2] * list->planePoint[2])};
	float l[4] = {light[0], light[1], light[2], 0.0f};
	float dot = plane[0] * l[0] + plane[1] * l[1] + plane[2] * l[2];
	for (int c = 0; c < 4; ++c)
		for (int row = 0; row < 4; ++row)
			m[4 * c + row] = (c == row ? dot : 0.0f) - l[row] * plane[c];
}

static void fvSurfaceUniforms(const fvRenderer* r, const fvDrawList* list, const fvCamera* camera,
                              const float viewProjection[16], const float model[16], int shadow)
{
	GLuint p = r->surfaceProgram;
	float eye[3], light[3];
	fvCamera_Eye(camera, eye);
	fvUnitLight(light);
	float plane[4] = {0.0f, 1.0f, 0.0f, 1e6f}; // no floor: up is +y, far below
	if (list->hasPlane)
	{
		memcpy(plane, list->planeNormal, 3 * sizeof(float));
		plane[3] = -(plane[0] * list->planePoint[0] + plane[1] * list->planePoint[1] +
		             plane[2] * list->planePoint[2]);
	}
	float blobs[FV_MAX_BLOBS][4];
	int blobCount = fvBlobs(list, blobs);
	float contactHeight = 0.1f;
	for (int i = 0; i < blobCount; ++i)
		contactHeight = fmaxf(contactHeight, 0.35f * blobs[i][3]);
	glUseProgram(p);
	fvUniformMatrix(p, "uViewProjection", viewProjection);
	fvUniformMatrix(p, "uModel", model);
	fvUniform3(p, "uEye", eye);
	fvUniform3(p, "uLight", light);
	glUniform4fv(glGetUniformLocation(p, "uPlane"), 1, plane);
	glUniform1f(glGetUniformLocation(p, "uContactHeight"), contactHeight);
	glUniform1i(glGetUniformLocation(p, "uShadow"), shadow);
}

static void fvDrawShadows(const fvRenderer* r, const fvDrawList* list, const fvCamera* camera,
                          const float viewProjection[16], size_t indexCount)
{
	float light[3], shadow[16];
	fvUnitLight(light);
	if (light[0] * list->planeNormal[0] + light[1] * list->planeNormal[1] +
	        light[2] * list->planeNormal[2] <=
	    0.05f)
		return; // the light is at or below the floor's horizon
	fvShadowMatrix(list, light, shadow);
	fvSurfaceUniforms(r, list, camera, viewProjection, shadow, 1);
	glEnable(GL_STENCIL_TEST);
	glStencilFunc(GL_EQUAL, 1, 0xff); // on the floor, once per pixel
	glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
	glEnable(GL_BLEND);
	glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
	glDepthMask(GL_FALSE);
	glEnable(GL_POLYGON_OFFSET_FILL);
	glPolygonOffset(-2.0f, -2.0f);
	glBindVertexArray(r->surfaceArray);
	glDrawElements(GL_TRIANGLES, (GLsizei)indexCount, GL_UNSIGNED_INT, NULL);
	glDisable(GL_POLYGON_OFFSET_FILL);
	glDepthMask(GL_TRUE);
	glDisable(GL_BLEND);
	glDisable(GL_STENCIL_TEST);
}

static void fvDrawLinesAndPoints(const fvRenderer* r, const fvDrawList* list,
                                 const float viewProjection[16])
{
	GLuint p = r->colorProgram;
	glUseProgram(p);
	fvUniformMatrix(p, "uViewProjection", viewProjection);
	glUniform1f(glGetUniformLocation(p, "uBias"), 2e-4f);
	glUniform1i(glGetUniformLocation(p, "uRound"), 0);
	if (list->lineVertexCount > 0)
	{
		glBindVertexArray(r->lineArray);
		glBindBuffer(GL_ARRAY_BUFFER, r->lineBuffer);
		glBufferData(GL_ARRAY_BUFFER,
		             (GLsizeiptr)(6 * sizeof(float) * (size_t)list->lineVertexCount), list->lines,
		             GL_STREAM_DRAW);
		glVertexAttrib1f(2, 1.0f);
		glDrawArrays(GL_LINES, 0, list->lineVertexCount);
	}
	if (list->pointCount > 0)
	{
		glUniform1f(glGetUniformLocation(p, "uBias"), 1e-3f);
		glUniform1i(glGetUniformLocation(p, "uRound"), 1);
		glEnable(GL_PROGRAM_POINT_SIZE);
		glBindVertexArray(r->pointArray);
		glBindBuffer(GL_ARRAY_BUFFER, r->pointBuffer);
		glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(7 * sizeof(float) * (size_t)list->pointCount),
		             list->points, GL_STREAM_DRAW);
		glDrawArrays(GL_POINTS, 0, list->pointCount);
		glDisable(GL_PROGRAM_POINT_SIZE);
	}
}

bool fvRenderer_Draw(fvRenderer* r, const fvDrawList* list, const fvCamera* camera, int width,
                     int height)
{
	size_t indexCount = 0;
	if (!fvStageSurfaces(r, list, &indexCount))
		return false;
	float view[16], projection[16], viewProjection[16];
	static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
	fvCamera_Matrices(camera, (float)width / (float)(height > 0 ? height : 1), view, projection);
	fvMultiply(projection, view, viewProjection);
	glViewport(0, 0, width, height);
	glClearStencil(0);
	glClearDepth(1.0);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
	glDisable(GL_CULL_FACE);
	fvDrawBackground(r);
	glEnable(GL_DEPTH_TEST);
	glDepthFunc(GL_LEQUAL);
	if (list->hasPlane)
	{
		fvDrawFloor(r, list, camera, viewProjection);
		if (indexCount > 0)
			fvDrawShadows(r, list, camera, viewProjection, indexCount);
	}
	if (indexCount > 0)
	{
		fvSurfaceUniforms(r, list, camera, viewProjection, identity, 0);
		glBindVertexArray(r->surfaceArray);
		glDrawElements(GL_TRIANGLES, (GLsizei)indexCount, GL_UNSIGNED_INT, NULL);
	}
	fvDrawLinesAndPoints(r, list, viewProjection);
	glBindVertexArray(0);
	glUseProgram(0);
	return true;
}
