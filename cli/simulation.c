// Turning a scene into a femto world: meshes loaded and placed, bodies created, pins and
// initial velocities applied, and the explicit step checked against its stability estimate.
#include "scene.h"
#include "scene_body.h"

#include "attachments.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The embedded house (cli/embed_file.cmake generates these at build time).
extern const unsigned char fmCliHouse2Node[];
extern const size_t fmCliHouse2Node_size;
extern const unsigned char fmCliHouse2Ele[];
extern const size_t fmCliHouse2Ele_size;

fmResult cliLoadHouseMesh(fmTetMesh* mesh, fmDiagnostic* diag)
{
	// house2.ele numbers its tets oddly (the loader warns and ignores the column): known, muted.
	cliMuteLibraryWarnings(true);
	fmResult result = fmLoadTetGenFromMemory((const char*)fmCliHouse2Node, fmCliHouse2Node_size,
	                                         "builtin:house2.node", (const char*)fmCliHouse2Ele,
	                                         fmCliHouse2Ele_size, "builtin:house2.ele", mesh, diag);
	cliMuteLibraryWarnings(false);
	return result;
}

// A generated box is refused before it is generated when the body it makes would not fit the
// world's memory budget (fmEstimateBodyMemory reads only the mesh's counts): a 200-byte scene
// must not allocate gigabytes first.
static bool cliBoxFitsBudget(const cliScene* scene, int index)
{
	const cliBodySpec* spec = &scene->bodies[index];
	double cells = (double)spec->boxCells[0] * spec->boxCells[1] * spec->boxCells[2];
	double nodes =
	    (spec->boxCells[0] + 1.0) * (spec->boxCells[1] + 1.0) * (spec->boxCells[2] + 1.0);
	if (6.0 * cells > FM_MAX_TETS || nodes > FM_MAX_NODES)
		return true; // fmMakeBoxMesh refuses it with its own message
	fmTetMesh counts;
	memset(&counts, 0, sizeof counts);
	counts.nodeCount = (int)nodes;
	counts.tetCount = (int)(6.0 * cells);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &counts;
	double mesh = 24.0 * nodes + 16.0 * 6.0 * cells; // the generated mesh itself
	double bytes = (double)fmEstimateBodyMemory(&def) + mesh;
	if (bytes <= (double)scene->worldDef.memoryBudget)
		return true;
	cliError("%s: bodies[%d].mesh: box:%d,%d,%d makes %d tets; its body needs about %.3g MiB "
	         "(fmEstimateBodyMemory, plus the mesh), more than the memory budget of %.3g MiB "
	         "(fmWorldDef.memoryBudget, scene key memory_budget_mib): use fewer cells",
	         scene->name, index, spec->boxCells[0], spec->boxCells[1], spec->boxCells[2],
	         counts.tetCount, bytes / 1048576.0, (double)scene->worldDef.memoryBudget / 1048576.0);
	return false;
}

static bool cliLoadBodyMesh(const cliScene* scene, int index, fmTetMesh* mesh)
{
	const cliBodySpec* spec = &scene->bodies[index];
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult result = fm_ok;
	switch (spec->meshSource)
	{
	case cli_meshFile:
		result = fmLoadMesh(spec->nodePath, mesh, &diag); // by extension; .node brings its .ele
		break;
	case cli_meshHouse:
		result = cliLoadHouseMesh(mesh, &diag);
		break;
	case cli_meshBox:
		if (!cliBoxFitsBudget(scene, index))
			return false;
		result = fmMakeBoxMesh(spec->boxCells[0], spec->boxCells[1], spec->boxCells[2],
		                       spec->boxMin, spec->boxMax, mesh);
		if (result != fm_ok)
			snprintf(diag.message, sizeof diag.message, "cannot make the box mesh: %s",
			         fmResultMessage(result));
		break;
	}
	if (result != fm_ok)
	{
		char prefix[CLI_MAX_PATH + 32];
		snprintf(prefix, sizeof prefix, "%s: bodies[%d].mesh", scene->name, index);
		cliPrintDiagnostic(prefix, &diag);
		return false;
	}
	fmTetMesh_Transform(mesh, &spec->transform);
	return true;
}

static void cliMeshBounds(const fmTetMesh* mesh, fmVec3* lo, fmVec3* hi)
{
	double b[6] = {0, 0, 0, 0, 0, 0};
	for (int i = 0; i < mesh->nodeCount; ++i)
		for (int axis = 0; axis < 3; ++axis)
		{
			double x = mesh->positions[3 * i + axis];
			if (i == 0 || x < b[axis])
				b[axis] = x;
			if (i == 0 || x > b[3 + axis])
				b[3 + axis] = x;
		}
	*lo = fmMakeVec3(b[0], b[1], b[2]);
	*hi = fmMakeVec3(b[3], b[4], b[5]);
}

// A body's "render_mesh": the OBJ placed by the body's transform and bound to its rest tets.
// Vertices outside the tets are a note (they follow the nearest tet); errors name the file.
static bool cliSetRenderMesh(const cliScene* scene, int index, cliSimulation* sim)
{
	const cliBodySpec* spec = &scene->bodies[index];
	fmSurfaceMesh surface;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	char prefix[CLI_MAX_PATH + 48];
	snprintf(prefix, sizeof prefix, "%s: bodies[%d].render_mesh", scene->name, index);
	if (fmLoadObj(spec->renderMeshPath, &surface, &diag) != fm_ok)
	{
		cliPrintDiagnostic(prefix, &diag);
		return false;
	}
	fmSurfaceMesh_Transform(&surface, &spec->transform);
	memset(&diag, 0, sizeof diag);
	cliMuteLibraryWarnings(true); // said once below, with the scene's path
	fmResult result =
	    fmBody_SetRenderMesh(sim->bodies[index], surface.positions, surface.vertexCount,
	                         surface.triangles, surface.triangleCount, &diag);
	cliMuteLibraryWarnings(false);
	if (result != fm_ok)
		cliPrintDiagnostic(prefix, &diag);
	else if (diag.warningCount > 0)
		fprintf(stderr, "femto: note: %s: %s\n", prefix, diag.warning);
	fmFreeSurfaceMesh(&surface);
	return result == fm_ok;
}

// A pin entry: a prescribed displacement, rollers on some axes, or a plain pin. Returns the
// vertices caught.
static int cliApplyPin(fmBodyId body, const cliPinBox* box)
{
	if (box->hasDisplacement)
		return fmBody_PrescribeDisplacement(body, box->min, box->max, box->axes, box->displacement,
		                                    box->time);
	if (box->axes != 7u)
		return fmBody_PinBoxAxes(body, box->min, box->max, box->axes);
	return fmBody_PinBox(body, box->min, box->max);
}

// A note for a load box that catches nothing (the body still runs, unloaded there).
static void cliNoteEmptyLoad(const cliScene* scene, int index, const char* key, int entry,
                             const char* what, fmVec3 min, fmVec3 max, const fmTetMesh* mesh)
{
	fmVec3 lo, hi;
	cliMeshBounds(mesh, &lo, &hi);
	fprintf(stderr,
	        "femto: note: %s: bodies[%d].%s[%d]: box [%g %g %g]..[%g %g %g] catches no %s; the "
	        "body spans [%g %g %g]..[%g %g %g] (scene coordinates, after the transform)\n",
	        scene->name, index, key, entry, min.x, min.y, min.z, max.x, max.y, max.z, what, lo.x,
	        lo.y, lo.z, hi.x, hi.y, hi.z);
}

// A body's "loads" (nodal forces) and "pressure" entries.
static void cliApplyLoads(const cliScene* scene, int index, const fmTetMesh* mesh, fmBodyId body)
{
	const cliBodySpec* spec = &scene->bodies[index];
	for (int p = 0; p < spec->loadCount; ++p)
	{
		const cliLoadBox* load = &spec->loads[p];
		if (fmBody_AddNodalForce(body, load->min, load->max, load->force) == 0)
			cliNoteEmptyLoad(scene, index, "loads", p, "vertex", load->min, load->max, mesh);
	}
	for (int p = 0; p < spec->pressureCount; ++p)
	{
		const cliPressureBox* load = &spec->pressures[p];
		if (fmBody_AddPressure(body, load->min, load->max, load->pressure, load->follower) == 0)
			cliNoteEmptyLoad(scene, index, "pressure", p,
			                 "surface triangle (all three vertices must be in the box)", load->min,
			                 load->max, mesh);
	}
}

static bool cliCreateBody(const cliScene* scene, int index, cliSimulation* sim)
{
	const cliBodySpec* spec = &scene->bodies[index];
	fmTetMesh* mesh = &sim->meshes[index];
	if (!cliLoadBodyMesh(scene, index, mesh))
		return false;
	fmBodyDef def = spec->def;
	def.mesh = mesh;
	char problem[256];
	def.tetFibres = cliBodyFibres(spec, mesh, problem, sizeof problem);
	if (problem[0] != 0)
	{
		fprintf(stderr, "%s: bodies[%d].%s\n", scene->name, index, problem);
		return false;
	}
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	fmResult made = fmCreateBody(sim->world, &def, &sim->bodies[index], &diag);
	free((void*)def.tetFibres);
	if (made != fm_ok)
	{
		char prefix[CLI_MAX_PATH + 32];
		snprintf(prefix, sizeof prefix, "%s: bodies[%d]", scene->name, index);
		cliPrintDiagnostic(prefix, &diag);
		return false;
	}
	for (int p = 0; p < spec->pinCount; ++p)
	{
		const cliPinBox* box = &spec->pins[p];
		if (cliApplyPin(sim->bodies[index], box) == 0)
		{
			// Most likely the box was written for the untransformed mesh: show where it is.
			fmVec3 lo, hi;
			cliMeshBounds(mesh, &lo, &hi);
			fprintf(stderr,
			        "%s: bodies[%d].pin[%d]: box [%g %g %g]..[%g %g %g] catches no vertex; the "
			        "body spans [%g %g %g]..[%g %g %g] (scene coordinates, after the transform)\n",
			        scene->name, index, p, box->min.x, box->min.y, box->min.z, box->max.x,
			        box->max.y, box->max.z, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
			return false;
		}
	}
	cliApplyLoads(scene, index, mesh, sim->bodies[index]);
	fmVec3 v = spec->initialVelocity;
	if (v.x != 0.0 || v.y != 0.0 || v.z != 0.0)
		fmBody_ApplyImpulse(sim->bodies[index], v);
	return spec->renderMeshPath[0] == 0 || cliSetRenderMesh(scene, index, sim);
}

// The OBJ of mesh collider @p index, loaded once per file: a collider naming a file an earlier
// one named shares its load (@p loaded: one slot per collider, filled where a file was read).
static const fmSurfaceMesh* cliColliderObj(const cliScene* scene, int index, fmSurfaceMesh* loaded)
{
	const char* path = scene->colliders[index].objPath;
	for (int j = 0; j < index; ++j)
		if (loaded[j].vertexCount > 0 && strcmp(scene->colliders[j].objPath, path) == 0)
			return &loaded[j];
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmLoadObj(path, &loaded[index], &diag) == fm_ok)
		return &loaded[index];
	char prefix[CLI_MAX_PATH + 32];
	snprintf(prefix, sizeof prefix, "%s: colliders[%d].path", scene->name, index);
	cliPrintDiagnostic(prefix, &diag);
	return NULL;
}

// A mesh collider's def from its OBJ (@p source): the surface placed by its transform (into
// @p vertices and @p triangles, malloc'd), its vertices relative to their centroid, which
// becomes the collider's centre (so a kinematic mesh spins about its middle, and "rotation"
// turns it there).
static bool cliMeshColliderDef(const cliScene* scene, int index, const fmSurfaceMesh* source,
                               fmColliderDef* def, fmVec3** vertices, int** triangles)
{
	int n = source->vertexCount, t = source->triangleCount;
	double* positions = malloc(sizeof(double) * 3 * (size_t)n);
	*vertices = malloc(sizeof **vertices * (size_t)n);
	*triangles = malloc(sizeof(int) * 3 * (size_t)t);
	if (positions == NULL || *vertices == NULL || *triangles == NULL)
	{
		free(positions);
		cliError("%s: colliders[%d]: out of memory for %d vertices", scene->name, index, n);
		return false;
	}
	memcpy(positions, source->positions, sizeof(double) * 3 * (size_t)n);
	memcpy(*triangles, source->triangles, sizeof(int) * 3 * (size_t)t);
	fmSurfaceMesh placed = {n, positions, t, *triangles};
	fmSurfaceMesh_Transform(&placed, &scene->colliders[index].transform);
	fmVec3 centroid = fmMakeVec3(0, 0, 0);
	for (int i = 0; i < n; ++i)
		centroid = fmAdd(centroid, fmLoad(positions, i));
	centroid = fmScale(1.0 / n, centroid);
	for (int i = 0; i < n; ++i)
		(*vertices)[i] = fmSub(fmLoad(positions, i), centroid);
	free(positions);
	def->center = centroid;
	def->vertices = *vertices;
	def->vertexCount = n;
	def->triangles = *triangles;
	def->triangleCount = t;
	return true;
}

static bool cliCreateCollider(const cliScene* scene, int index, cliSimulation* sim,
                              fmSurfaceMesh* loaded)
{
	fmColliderDef def = scene->colliders[index].def;
	fmVec3* vertices = NULL;
	int* triangles = NULL;
	bool ok = true;
	if (def.shape == fm_shapeMesh)
	{
		const fmSurfaceMesh* source = cliColliderObj(scene, index, loaded);
		ok =
		    source != NULL && cliMeshColliderDef(scene, index, source, &def, &vertices, &triangles);
	}
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (ok && fmCreateCollider(sim->world, &def, &sim->colliders[index], &diag) != fm_ok)
	{
		char prefix[CLI_MAX_PATH + 32];
		snprintf(prefix, sizeof prefix, "%s: colliders[%d]", scene->name, index);
		cliPrintDiagnostic(prefix, &diag);
		ok = false;
	}
	free(vertices); // the library copies a mesh's arrays
	free(triangles);
	return ok;
}

// Every collider of the scene, each OBJ read once.
static bool cliCreateColliders(const cliScene* scene, cliSimulation* sim)
{
	fmSurfaceMesh* loaded =
	    calloc((size_t)(scene->colliderCount > 0 ? scene->colliderCount : 1), sizeof *loaded);
	bool ok = loaded != NULL;
	if (!ok)
		cliError("%s: out of memory for the colliders", scene->name);
	for (int i = 0; ok && i < scene->colliderCount; ++i)
		ok = cliCreateCollider(scene, i, sim, loaded);
	for (int i = 0; loaded != NULL && i < scene->colliderCount; ++i)
		fmFreeSurfaceMesh(&loaded[i]);
	free(loaded);
	return ok;
}

// The estimate is conservative: damping and smoothing keep the seeds' house stable at 1.6 times
// it, and steps beyond twice it explode (the library's own threshold, where it warns as well).
static void cliCheckExplicitStep(const cliScene* scene, const cliSimulation* sim, bool notes)
{
	if (scene->worldDef.autoSubstep) // the library splits the steps itself
		return;
	double limit = fmWorld_EstimateExplicitStep(sim->world);
	if (!(limit > 0.0) || scene->dt <= limit)
		return;
	if (scene->dt > 2.0 * limit)
	{
		cliWarn("%s: dt = %g s is more than twice the estimated explicit stability limit %g s; "
		        "expect a numerical failure (dt <= %g s, or \"integrator\": \"implicit\")",
		        scene->name, scene->dt, limit, limit);
		cliNoteExplicitStepWarned();
	}
	else if (notes)
		fprintf(stderr,
		        "femto: note: %s: dt = %g s is %.2f times the conservative explicit stability "
		        "estimate %g s (damping keeps the seeds' house stable at 1.6 times); if a step "
		        "fails, lower dt\n",
		        scene->name, scene->dt, scene->dt / limit, limit);
}

bool cliSimulation_Create(const cliScene* scene, cliStepCheck check, cliSimulation* sim)
{
	memset(sim, 0, sizeof *sim);
	sim->bodies = calloc((size_t)scene->bodyCount, sizeof *sim->bodies);
	sim->meshes = calloc((size_t)scene->bodyCount, sizeof *sim->meshes);
	if (sim->bodies == NULL || sim->meshes == NULL)
	{
		cliError("out of memory");
		cliSimulation_Destroy(sim);
		return false;
	}
	sim->bodyCount = scene->bodyCount;
	sim->colliders = calloc((size_t)(scene->colliderCount > 0 ? scene->colliderCount : 1),
	                        sizeof *sim->colliders);
	if (sim->colliders == NULL)
	{
		cliError("out of memory");
		cliSimulation_Destroy(sim);
		return false;
	}
	sim->colliderCount = scene->colliderCount;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmWorldDef_Validate(&scene->worldDef, &diag) != fm_ok)
	{
		cliPrintDiagnostic(scene->name, &diag);
		cliSimulation_Destroy(sim);
		return false;
	}
	sim->world = fmCreateWorld(&scene->worldDef);
	if (!fmWorld_IsValid(sim->world))
	{
		cliError("%s: cannot create the world (out of memory?)", scene->name);
		cliSimulation_Destroy(sim);
		return false;
	}
	for (int i = 0; i < scene->bodyCount; ++i)
	{
		if (!cliCreateBody(scene, i, sim))
		{
			cliSimulation_Destroy(sim);
			return false;
		}
	}
	if (!cliCreateColliders(scene, sim))
	{
		cliSimulation_Destroy(sim);
		return false;
	}
	if (!cliAttachments_Create(scene, sim))
	{
		cliSimulation_Destroy(sim);
		return false;
	}
	if (scene->worldDef.integrator == fm_explicit && check != cli_stepCheckOff)
		cliCheckExplicitStep(scene, sim, check == cli_stepCheckAll);
	return true;
}

void cliSimulation_Destroy(cliSimulation* sim)
{
	if (fmWorld_IsValid(sim->world))
		fmDestroyWorld(sim->world);
	if (sim->meshes != NULL)
		for (int i = 0; i < sim->bodyCount; ++i)
			fmFreeTetMesh(&sim->meshes[i]);
	free(sim->meshes);
	free(sim->bodies);
	free(sim->colliders);
	free(sim->attached);
	memset(sim, 0, sizeof *sim);
}
