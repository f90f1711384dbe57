// The benchmark meshes and their worlds (meshes.h).
#include "meshes.h"

#include "beams.h"
#include "tools.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* const cliBenchFamilyNames[cli_benchFamilyCount] = {
    "house", "box", "beam", "contact", "motion", "startup"};

// The sizes, each with the box's cells: about 1k, 10k, 100k and 1M tets.
static const struct
{
	const char* suffix;
	int nominal;
	int cells[3];
} cliBenchSizes[] = {
    {"1k", 1000, {6, 6, 5}},
    {"10k", 10000, {12, 12, 12}},
    {"100k", 100000, {26, 26, 25}},
    {"1M", 1000000, {55, 55, 55}},
};
#define CLI_BENCH_SIZE_COUNT ((int)(sizeof cliBenchSizes / sizeof cliBenchSizes[0]))

// The house's tet count (data/house2.ele).
#define CLI_HOUSE_TETS 1389

const char* cliBenchFamilyName(cliBenchFamily family)
{
	return family >= 0 && family < cli_benchFamilyCount ? cliBenchFamilyNames[family] : "?";
}

bool cliBenchParseFamilies(const char* text, unsigned* mask)
{
	*mask = 0;
	const char* p = text;
	for (;;)
	{
		size_t length = strcspn(p, ",");
		int found = -1;
		for (int f = 0; f < cli_benchFamilyCount; ++f)
			if (length == strlen(cliBenchFamilyNames[f]) &&
			    strncmp(p, cliBenchFamilyNames[f], length) == 0)
				found = f;
		if (found < 0)
		{
			cliUsageError("bench",
			              "--meshes: unknown mesh family '%.*s' in '%s' (expected a "
			              "comma-separated list of house, box, beam, contact, motion, startup)",
			              (int)length, p, text);
			return false;
		}
		*mask |= 1u << found;
		if (p[length] == '\0')
			return true;
		p += length + 1;
	}
}

static bool cliBenchMeshSet_Add(cliBenchMeshSet* set, const cliBenchMesh* mesh)
{
	cliBenchMesh* grown = realloc(set->meshes, (size_t)(set->count + 1) * sizeof *grown);
	if (grown == NULL)
	{
		cliError("bench: out of memory");
		return false;
	}
	set->meshes = grown;
	set->meshes[set->count++] = *mesh;
	return true;
}

static bool cliBenchAddBox(cliBenchMeshSet* set, int size)
{
	cliBenchMesh box;
	memset(&box, 0, sizeof box);
	box.family = cli_benchBox;
	snprintf(box.label, sizeof box.label, "box %s", cliBenchSizes[size].suffix);
	box.nominal = cliBenchSizes[size].nominal;
	memcpy(box.cells, cliBenchSizes[size].cells, sizeof box.cells);
	box.tets = 6 * box.cells[0] * box.cells[1] * box.cells[2];
	return cliBenchMeshSet_Add(set, &box);
}

static bool cliBenchAddBeam(cliBenchMeshSet* set, int size, const char* tetgen, const char* folder)
{
	cliBenchMesh beam;
	memset(&beam, 0, sizeof beam);
	beam.family = cli_benchBeam;
	snprintf(beam.label, sizeof beam.label, "beam %s", cliBenchSizes[size].suffix);
	beam.nominal = cliBenchSizes[size].nominal;
	printf("meshing %s with tetgen ...", beam.label);
	fflush(stdout);
	double start = cliNow();
	bool ok = cliBenchBeam_Make(tetgen, folder, beam.nominal, beam.nodePath, beam.elePath,
	                            sizeof beam.nodePath, &beam.tets);
	if (ok)
		printf(" %d tets (%.1f s)\n", beam.tets, cliNow() - start);
	else
		printf(" failed\n");
	return ok && cliBenchMeshSet_Add(set, &beam);
}

// Whether the beams can be made: tetgen on PATH and a temporary folder; says why not.
static bool cliBenchCanMakeBeams(const char* folder, char* tetgen, size_t size)
{
	if (!cliBenchFindProgram("tetgen", tetgen, size))
	{
		printf("beams: skipped: tetgen is not on PATH (Debian: apt-get install tetgen)\n");
		return false;
	}
	if (folder == NULL)
	{
		printf("beams: skipped: no temporary folder to mesh them in\n");
		return false;
	}
	return true;
}

bool cliBenchMeshSet_Make(unsigned mask, int maxTets, const char* folder, cliBenchMeshSet* set)
{
	memset(set, 0, sizeof *set);
	char tetgen[CLI_MAX_PATH];
	bool beams = (mask & (1u << cli_benchBeam)) != 0 && cliBenchSizes[0].nominal <= maxTets &&
	             cliBenchCanMakeBeams(folder, tetgen, sizeof tetgen);
	if ((mask & (1u << cli_benchHouse)) != 0 && CLI_HOUSE_TETS <= maxTets)
	{
		cliBenchMesh house = {
		    "house2", cli_benchHouse, CLI_HOUSE_TETS, CLI_HOUSE_TETS, {0}, 0.0, "", ""};
		if (!cliBenchMeshSet_Add(set, &house))
			return false;
	}
	for (int size = 0; size < CLI_BENCH_SIZE_COUNT && cliBenchSizes[size].nominal <= maxTets;
	     ++size)
	{
		if ((mask & (1u << cli_benchBox)) != 0 && !cliBenchAddBox(set, size))
			return false;
		if (beams && !cliBenchAddBeam(set, size, tetgen, folder))
			return false;
	}
	return true;
}

void cliBenchMeshSet_Free(cliBenchMeshSet* set)
{
	free(set->meshes);
	memset(set, 0, sizeof *set);
}

fmMaterial cliBenchMesh_Material(const cliBenchMesh* mesh, fmMaterialModel model)
{
	fmMaterial m = mesh->family == cli_benchHouse ? fmMakeMaterialLame(model, 20000.0, 5000.0)
	                                              : fmMakeMaterial(model, 1e6, 0.3);
	// The anisotropic laws (the bench's "laws" rows): the same Young's modulus across a grain
	// three times stiffer along (1, 1, 0).
	double E = m.mu * (3.0 * m.lambda + 2.0 * m.mu) / (m.lambda + m.mu);
	if (model == fm_orthotropicLinear || model == fm_orthotropicStvk)
		m = fmMakeOrthotropicMaterial(model, fmTransverselyIsotropic(3.0 * E, E, 0.3, 0.3, m.mu));
	m.fibreStiffness = model == fm_fibreNeoHookean ? 2.0 * E : 0.0;
	m.fibre = fmMakeVec3(1.0, 1.0, 0.0);
	return m;
}

bool cliBenchMesh_World(const cliBenchMesh* mesh, const cliBenchWorld* settings, cliSimulation* sim)
{
	cliScene scene;
	cliScene_MakeHouse(&scene);
	if (scene.bodies == NULL)
		return false;
	snprintf(scene.name, sizeof scene.name, "bench %s", mesh->label);
	scene.worldDef.integrator = settings->integrator;
	scene.worldDef.workerCount = settings->workers;
	scene.worldDef.tolerance = settings->tolerance;
	scene.worldDef.simd = settings->simd;
	scene.worldDef.crossPlatformDeterminism = settings->deterministic;
	scene.worldDef.implicitSolver = settings->solver;
	scene.worldDef.autoSubstep = settings->autoSubstep;
	scene.worldDef.floor.enabled = !settings->noFloor;
	if (settings->newtonIterations > 0)
		scene.worldDef.newtonIterations = settings->newtonIterations;
	cliBodySpec* body = &scene.bodies[0];
	body->def.material = cliBenchMesh_Material(mesh, settings->model);
	body->def.material.nodalPressure = settings->nodalPressure;
	body->def.material.fracture.strength = settings->fractureStrength;
	if (settings->yieldStrain > 0.0) // E = mu (3 lambda + 2 mu) / (lambda + mu)
	{
		const fmMaterial* m = &body->def.material;
		double E = m->mu * (3.0 * m->lambda + 2.0 * m->mu) / (m->lambda + m->mu);
		body->def.material.plasticity.yieldStress = settings->yieldStrain * E;
		body->def.material.plasticity.hardening = 0.1 * E;
	}
	if (mesh->family != cli_benchHouse)
	{
		// Resting on the floor, density-based masses so refinement keeps the physics.
		body->transform = fmDefaultMeshTransform();
		body->def.massMode = fm_massFromDensity;
		body->def.density = 1000.0;
	}
	if (mesh->family == cli_benchBox)
	{
		// A 1 m cube, or a bar of cubic cells.
		body->meshSource = cli_meshBox;
		memcpy(body->boxCells, mesh->cells, sizeof body->boxCells);
		double cell = mesh->length / mesh->cells[0];
		fmVec3 size = mesh->length > 0.0
		                  ? fmMakeVec3(mesh->length, cell * mesh->cells[1], cell * mesh->cells[2])
		                  : fmMakeVec3(1.0, 1.0, 1.0);
		body->boxMin = fmMakeVec3(-0.5 * size.x, -3.0 + settings->lift, -0.5 * size.z);
		body->boxMax = fmMakeVec3(0.5 * size.x, -3.0 + settings->lift + size.y, 0.5 * size.z);
	}
	else if (mesh->family == cli_benchBeam)
	{
		// tetgen's beam, y in [0, 1], lowered onto the floor; read by femto's TetGen reader.
		body->meshSource = cli_meshFile;
		snprintf(body->nodePath, sizeof body->nodePath, "%s", mesh->nodePath);
		snprintf(body->elePath, sizeof body->elePath, "%s", mesh->elePath);
		body->transform.translate = fmMakeVec3(0.0, -3.0 + settings->lift, 0.0);
	}
	bool ok = cliSimulation_Create(&scene, cli_stepCheckOff, sim);
	cliScene_Free(&scene);
	return ok;
}

fmWorldDef cliBenchFloorWorldDef(const cliBenchOptions* o, int workers)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.integrator = fm_implicit;
	def.tolerance = FM_TOLERANCE_GAME;
	def.workerCount = workers;
	def.simd = o->simd;
	def.crossPlatformDeterminism = o->deterministic;
	def.implicitSolver = o->solver;
	def.floor.height = 0.0;
	def.floor.friction = fm_floorCoulomb;
	def.floor.frictionCoefficient = 0.5;
	return def;
}

fmBodyDef cliBenchBoxBodyDef(const fmTetMesh* mesh)
{
	fmBodyDef body = fmDefaultBodyDef();
	body.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	body.massMode = fm_massFromDensity;
	body.density = 1000.0;
	body.mesh = mesh;
	return body;
}
