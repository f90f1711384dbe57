// The orbit camera: a target point, a distance and two angles; view and projection matrices,
// grab rays and projection to pixels. Matrices are column-major float[16] as OpenGL takes
// them. Pixels count from the top-left corner of the image, y down.
#pragma once

#include <stdbool.h>

/// An orbit camera looking at target from distance along (yaw, pitch).
typedef struct fvCamera
{
	float target[3]; ///< m, the point looked at and orbited
	float distance;  ///< m, from the eye to the target, > 0
	float yaw;       ///< degrees about +y; 0 looks along -z (the eye on the +z side)
	float pitch;     ///< degrees above the horizon, in [-89, 89]; positive looks down
	float fovY;      ///< degrees, vertical field of view
	/// Where the view's centre lies on the picture, as a horizontal offset in normalised device
	/// units (0 the middle, 0.5 a quarter of the width right of it): a panel covering the left
	/// of the window moves it to the middle of the part left free.
	float shiftX;
} fvCamera;

/// A camera at the origin, 10 m away, yaw 30, pitch 20, 45 degrees field of view.
fvCamera fvCamera_Default(void);

/// Aim at the box [@p lo, @p hi] (m) with the camera's angles: the target at its centre and the
/// distance at which the whole box fits the view of aspect @p aspect (width / height).
void fvCamera_Frame(fvCamera* camera, const float lo[3], const float hi[3], float aspect);

/// The eye position (m).
void fvCamera_Eye(const fvCamera* camera, float eye[3]);

/// View and projection matrices for an image of aspect @p aspect (width / height).
void fvCamera_Matrices(const fvCamera* camera, float aspect, float view[16], float projection[16]);

/// Rotate by @p dx, @p dy pixels of mouse motion (0.3 degree a pixel).
void fvCamera_Orbit(fvCamera* camera, float dx, float dy);

/// Move the target by @p dx, @p dy pixels of mouse motion in a @p height pixel high view, so the
/// point under the cursor follows it.
void fvCamera_Pan(fvCamera* camera, float dx, float dy, int height);

/// Keep the eye above the plane through @p point with unit normal @p normal (the floor), by
/// 2% of the distance: the least change of pitch that does (looking further down), or the
/// target lifted when even looking straight down leaves the eye under it. An orbit, pan or zoom
/// is followed by it, so the floor never becomes a ceiling.
void fvCamera_KeepAbove(fvCamera* camera, const float point[3], const float normal[3]);

/// Zoom by @p steps wheel steps (positive: closer, 10% a step).
void fvCamera_Zoom(fvCamera* camera, float steps);

/// The ray through pixel (@p px, @p py) of a @p width x @p height image: the eye and a unit
/// direction.
void fvCamera_Ray(const fvCamera* camera, int width, int height, float px, float py,
                  float origin[3], float direction[3]);

/// The pixel (x, y from the top-left) where @p point is seen in a @p width x @p height image.
/// False when the point is behind the eye.
bool fvCamera_Project(const fvCamera* camera, int width, int height, const float point[3],
                      float pixel[2]);
