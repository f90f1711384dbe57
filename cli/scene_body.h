// A scene's bodies (docs/scene-format.md, docs/loads.md): one entry of "bodies" read into a
// cliBodySpec: its mesh, placement, material and regions, pins, loads, pressures, attachments
// and contact keys. Part of the scene schema with scene.c, which reads the rest of a scene.
#pragma once

#include "json_check.h"
#include "scene.h"

/// Read bodies[@p index] into @p spec; what it allocates is kept in @p spec on failure too.
bool cliParseBody(const cliJson* j, const cliJsonNode* body, int index, cliBodySpec* spec);

/// The "transform" of @p object (a body or a mesh collider); the identity when absent.
bool cliParseTransform(const cliJson* j, const cliJsonNode* object, const char* parent,
                       fmMeshTransform* out);

/// The "filter" of @p object (a body, a collider or the floor): {"category": bits, "mask":
/// bits} (fmFilter; absent keys keep the defaults).
bool cliParseFilter(const cliJson* j, const cliJsonNode* object, const char* parent,
                    fmFilter* filter);

/// @p material with its nodal pressure kept where its model takes one (fmMaterial_Validate's
/// rule, asked of a tame material of that model so that nothing is logged), else dropped: the
/// scene's flag carried to a material the viewer's or page's sliders or a region make.
fmMaterial cliKeepNodalPressure(fmMaterial material, bool nodalPressure);

/// The per-tet fibres of @p spec's "fibres" on its loaded, placed @p mesh (fmBodyDef.tetFibres):
/// malloc'd (the caller frees it), or NULL with @p problem empty when the body has none, or NULL
/// with the reason in @p problem (the mesh lacks the attributes, out of memory).
fmVec3* cliBodyFibres(const cliBodySpec* spec, const fmTetMesh* mesh, char* problem, size_t size);
