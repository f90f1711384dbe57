// A scene's welds (welds.c): every vertex of a body within a weld's distance of a vertex of the
// other body is welded to the nearest such vertex (fmBody_Weld).
#pragma once

#include "scene.h"

/// Weld the scene's bodies as their "welds" say (after the bodies are created). False, with a
/// located message, for a body index out of range, a weld that pairs no vertex, or a refusal.
bool cliWelds_Create(const cliScene* scene, cliSimulation* sim);
