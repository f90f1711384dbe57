// A body's definition (body_def.c): fmDefaultBodyDef, the checks of fmBodyDef_Validate and
// fmCreateBody (mesh counts, numbering, coordinates, materials, masses, damping, regions), and
// the memory estimate of fmEstimateBodyMemory and the world's memory budget.
#pragma once

#include <femto/femto.h>

#include <stddef.h>

// Everything fmCreateBody relies on in @p def, with the field named in @p diag on failure.
fmResult fmBodyDef_Check(const fmBodyDef* def, fmDiagnostic* diag);

// Estimated bytes of a body: its own arrays, and the implicit (and static) solver's cache.
typedef struct fmBodyMemory
{
	size_t body;
	size_t solver;
} fmBodyMemory;

// The estimate behind fmEstimateBodyMemory() for a mesh of these counts (@p def may be NULL:
// the FEM force model without damping).
fmBodyMemory fmBodyMemoryOf(int nodeCount, int tetCount, const fmBodyDef* def);
