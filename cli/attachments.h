// Kinematic attachments of a scene's bodies (attachments.c): the vertices caught by each
// "attachments" box follow its rigid motion through kinematic targets, set before every frame.
#pragma once

#include "scene.h"

/// One attached vertex: where it was at creation and the motion it follows.
typedef struct cliAttached
{
	int body;               ///< the scene's body index
	int vertex;             ///< user numbering
	fmVec3 rest;            ///< m, its position when the simulation was created
	fmVec3 centre;          ///< m, its box's centre (the rotation's)
	fmVec3 velocity;        ///< m/s
	fmVec3 angularVelocity; ///< rad/s
	double stiffness;       ///< N/m
} cliAttached;

/// Catch the vertices of every body's attachment boxes (after the bodies are created). False,
/// with a located message, when a box catches no vertex or memory is short.
bool cliAttachments_Create(const cliScene* scene, cliSimulation* sim);

/// Set every attached body's targets for time @p time (s since the start).
bool cliAttachments_Update(cliSimulation* sim, double time);
