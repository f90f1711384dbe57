// The orbit camera (camera.h): a look-at view and a perspective projection, the same matrices
// for drawing, grabbing and projecting.
#include "camera.h"

#include <math.h>
#include <string.h>

#define FV_PI 3.14159265358979323846f
#define FV_NEAR_FRACTION 0.01f // near plane: this fraction of the distance
#define FV_FAR_FACTOR 50.0f    // far plane: this many distances (the floor fades out before)
#define FV_FLOOR_MARGIN 0.02f  // the eye keeps this many distances above the floor

static float fvRadians(float degrees)
{
	return degrees * (FV_PI / 180.0f);
}

static void fvNormalize(float v[3])
{
	float length = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	if (length > 0.0f)
		for (int i = 0; i < 3; ++i)
			v[i] /= length;
}

static void fvCross(const float a[3], const float b[3], float out[3])
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

fvCamera fvCamera_Default(void)
{
	fvCamera camera = {{0.0f, 0.0f, 0.0f}, 10.0f, 30.0f, 20.0f, 45.0f, 0.0f};
	return camera;
}

// Unit vector from the target toward the eye.
static void fvBackward(const fvCamera* camera, float back[3])
{
	float yaw = fvRadians(camera->yaw), pitch = fvRadians(camera->pitch);
	back[0] = cosf(pitch) * sinf(yaw);
	back[1] = sinf(pitch);
	back[2] = cosf(pitch) * cosf(yaw);
}

// The camera's right, up and forward unit vectors.
static void fvBasis(const fvCamera* camera, float right[3], float up[3], float forward[3])
{
	float back[3], worldUp[3] = {0.0f, 1.0f, 0.0f};
	fvBackward(camera, back);
	for (int i = 0; i < 3; ++i)
		forward[i] = -back[i];
	fvCross(forward, worldUp, right);
	fvNormalize(right);
	fvCross(right, forward, up);
}

void fvCamera_Frame(fvCamera* camera, const float lo[3], const float hi[3], float aspect)
{
	float radius = 0.0f;
	for (int i = 0; i < 3; ++i)
	{
		camera->target[i] = 0.5f * (lo[i] + hi[i]);
		radius += 0.25f * (hi[i] - lo[i]) * (hi[i] - lo[i]);
	}
	radius = fmaxf(sqrtf(radius), 0.1f);
	// The bounding sphere fits the narrower of the two fields of view, with a margin.
	float halfY = 0.5f * fvRadians(camera->fovY);
	float halfX = atanf(tanf(halfY) * (aspect > 0.0f ? aspect : 1.0f));
	camera->distance = 1.15f * radius / sinf(fminf(halfX, halfY));
}

void fvCamera_Eye(const fvCamera* camera, float eye[3])
{
	float back[3];
	fvBackward(camera, back);
	for (int i = 0; i < 3; ++i)
		eye[i] = camera->target[i] + camera->distance * back[i];
}

void fvCamera_Matrices(const fvCamera* camera, float aspect, float view[16], float projection[16])
{
	float right[3], up[3], forward[3], eye[3];
	fvBasis(camera, right, up, forward);
	fvCamera_Eye(camera, eye);
	memset(view, 0, 16 * sizeof *view);
	for (int i = 0; i < 3; ++i)
	{
		view[4 * i + 0] = right[i];
		view[4 * i + 1] = up[i];
		view[4 * i + 2] = -forward[i];
	}
	view[12] = -(right[0] * eye[0] + right[1] * eye[1] + right[2] * eye[2]);
	view[13] = -(up[0] * eye[0] + up[1] * eye[1] + up[2] * eye[2]);
	view[14] = forward[0] * eye[0] + forward[1] * eye[1] + forward[2] * eye[2];
	view[15] = 1.0f;
	float nearZ = FV_NEAR_FRACTION * camera->distance, farZ = FV_FAR_FACTOR * camera->distance;
	float f = 1.0f / tanf(0.5f * fvRadians(camera->fovY));
	memset(projection, 0, 16 * sizeof *projection);
	projection[0] = f / (aspect > 0.0f ? aspect : 1.0f);
	projection[5] = f;
	projection[8] = -camera->shiftX; // x_ndc += shiftX (w = -z_eye)
	projection[10] = (farZ + nearZ) / (nearZ - farZ);
	projection[11] = -1.0f;
	projection[14] = 2.0f * farZ * nearZ / (nearZ - farZ);
}

void fvCamera_Orbit(fvCamera* camera, float dx, float dy)
{
	camera->yaw = fmodf(camera->yaw - 0.3f * dx, 360.0f);
	camera->pitch = fminf(89.0f, fmaxf(-89.0f, camera->pitch + 0.3f * dy));
}

void fvCamera_Pan(fvCamera* camera, float dx, float dy, int height)
{
	float right[3], up[3], forward[3];
	fvBasis(camera, right, up, forward);
	// Metres per pixel at the target's depth.
	float scale = 2.0f * camera->distance * tanf(0.5f * fvRadians(camera->fovY)) /
	              (float)(height > 0 ? height : 1);
	for (int i = 0; i < 3; ++i)
		camera->target[i] += scale * (-dx * right[i] + dy * up[i]);
}

// The eye's height above the plane through @p point with unit normal @p normal.
static float fvEyeHeight(const fvCamera* camera, const float point[3], const float normal[3])
{
	float eye[3];
	fvCamera_Eye(camera, eye);
	return (eye[0] - point[0]) * normal[0] + (eye[1] - point[1]) * normal[1] +
	       (eye[2] - point[2]) * normal[2];
}

void fvCamera_KeepAbove(fvCamera* camera, const float point[3], const float normal[3])
{
	float margin = FV_FLOOR_MARGIN * camera->distance;
	if (fvEyeHeight(camera, point, normal) >= margin)
		return;
	// The least pitch (looking further down) that lifts the eye clear: bisection between the
	// current pitch and straight down.
	float low = camera->pitch, high = 89.0f;
	camera->pitch = high;
	float top = fvEyeHeight(camera, point, normal);
	if (top < margin)
	{
		// Even from above the target the eye is under the plane: the target is, lift it.
		for (int i = 0; i < 3; ++i)
			camera->target[i] += (margin - top) * normal[i];
		return;
	}
	for (int k = 0; k < 30; ++k)
	{
		camera->pitch = 0.5f * (low + high);
		if (fvEyeHeight(camera, point, normal) >= margin)
			high = camera->pitch;
		else
			low = camera->pitch;
	}
	camera->pitch = high;
}

void fvCamera_Zoom(fvCamera* camera, float steps)
{
	camera->distance = fmaxf(0.05f, camera->distance * powf(0.9f, steps));
}

void fvCamera_Ray(const fvCamera* camera, int width, int height, float px, float py,
                  float origin[3], float direction[3])
{
	float right[3], up[3], forward[3];
	fvBasis(camera, right, up, forward);
	fvCamera_Eye(camera, origin);
	float aspect = (float)width / (float)(height > 0 ? height : 1);
	float t = tanf(0.5f * fvRadians(camera->fovY));
	float x = (2.0f * px / (float)width - 1.0f - camera->shiftX) * t * aspect;
	float y = (1.0f - 2.0f * py / (float)height) * t;
	for (int i = 0; i < 3; ++i)
		direction[i] = forward[i] + x * right[i] + y * up[i];
	fvNormalize(direction);
}

bool fvCamera_Project(const fvCamera* camera, int width, int height, const float point[3],
                      float pixel[2])
{
	float right[3], up[3], forward[3], eye[3], d[3];
	fvBasis(camera, right, up, forward);
	fvCamera_Eye(camera, eye);
	for (int i = 0; i < 3; ++i)
		d[i] = point[i] - eye[i];
	float z = d[0] * forward[0] + d[1] * forward[1] + d[2] * forward[2];
	if (!(z > 0.0f))
		return false;
	float aspect = (float)width / (float)(height > 0 ? height : 1);
	float t = tanf(0.5f * fvRadians(camera->fovY));
	float x = (d[0] * right[0] + d[1] * right[1] + d[2] * right[2]) / (z * t * aspect);
	float y = (d[0] * up[0] + d[1] * up[1] + d[2] * up[2]) / (z * t);
	pixel[0] = 0.5f * (x + camera->shiftX + 1.0f) * (float)width;
	pixel[1] = 0.5f * (1.0f - y) * (float)height;
	return true;
}
