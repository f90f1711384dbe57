// Picking: which drawn surface triangle a ray hits first (on the CPU, against the triangles the
// library drew), and which of its vertices is closest to the hit.
#pragma once

#include "draw_list.h"

/// A ray's first hit on a drawn surface.
typedef struct fvPick
{
	int surface;       ///< index in fvDrawList.surfaces
	int vertex;        ///< the body's vertex index (user numbering) closest to the hit
	float distance;    ///< m along the ray
	float point[3];    ///< the hit point (m)
	float vertexAt[3]; ///< that vertex's drawn position (m)
} fvPick;

/// Cast the ray from @p origin along unit @p direction against every surface of @p list
/// (Möller-Trumbore, both faces). False when it hits nothing.
bool fvPick_Ray(const fvDrawList* list, const float origin[3], const float direction[3],
                fvPick* pick);
