// The world: bodies, gravity, floor, integrator settings, step statistics.
#pragma once

#include "body.h"
#include "stability.h"

typedef struct fmWorld
{
	uint16_t generation;
	bool inUse;
	fmWorldDef def;
	int bodyCapacity;
	fmBody* bodies; // bodyCapacity slots; a slot is live when its x != NULL
	fmStepStats stats;
	fmDiagnostic lastError;
	bool warnedStep; // the explicit step-size warning was given
} fmWorld;


// Resolve ids; NULL if stale.
fmWorld* fmGetWorld(fmWorldId id);
fmWorld* fmGetWorldOfBody(fmBodyId id);
