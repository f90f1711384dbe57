// The contact rows of `femto bench` (contact.h). Each case is a scene built in code and run for
// a fixed simulated time; every frame is timed, and the row gives the median ms per frame, the
// median contact count after a frame (fmWorld_GetContacts: bodies on colliders and on each
// other; the floor's vertices are not in it) and the shares of the timed frames' step time
// spent in the contact stage, its broad phase and its narrow phase (sums of fmProfile).
#include "contact.h"

#include "meshes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The ground under the 100k box: a heightfield of CLI_GROUND_CELLS^2 quads (two triangles
// each) over [-CLI_GROUND_HALF, CLI_GROUND_HALF]^2 m, undulating by CLI_GROUND_AMPLITUDE m
// with a wavelength of CLI_GROUND_WAVELENGTH m around y = CLI_BENCH_FLOOR_Y.
#define CLI_GROUND_CELLS 48
#define CLI_GROUND_HALF 1.5
#define CLI_GROUND_AMPLITUDE 0.02
#define CLI_GROUND_WAVELENGTH 1.0
#define CLI_BENCH_PI 3.14159265358979323846

// Wall seconds a case's timed frames may take: a pile stuck in refused frames (each one
// restored and retried) costs seconds a frame, and the bench must end. The row says how many
// frames it timed.
#define CLI_CONTACT_BUDGET_S 60.0

// The pile's houses "apart": each shifted this far (m) along x per place in the pile, so that
// they fall the same heights and land alone (the house is 4 m wide).
#define CLI_BENCH_APART 8.0

// One timed case: a scene, how long it runs untimed and timed.
typedef struct cliContactCase
{
	const char* label;      // the row's mesh column
	const char* integrator; // the row's integrator column
	const char* model;      // the row's model column
	int untimedFrames;      // frames run before the timing (settling)
	int timedFrames;        // frames timed
} cliContactCase;

// What the timed frames measured.
typedef struct cliContactTimes
{
	double msPerFrame;   // median
	double p95;          // ms, the 95th percentile frame
	double worst;        // ms, the slowest frame
	double contacts;     // median contacts after a frame
	double contactShare; // of the step time: the contact stage
	double broadShare;   // its broad phase
	double narrowShare;  // its narrow phase
	int refused;         // frames the library refused (state restored), e.g. by the energy check
	int frames;          // frames timed (fewer than asked when the budget ran out)
} cliContactTimes;

static int cliContactCompare(const void* a, const void* b)
{
	double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

static double cliContactMedian(double* values, int count)
{
	qsort(values, (size_t)count, sizeof *values, cliContactCompare);
	return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

// Step @p frames frames of the scene, timing them when @p ms is not NULL, within
// CLI_CONTACT_BUDGET_S; returns the frames stepped. A refused frame (the library restores the
// frame's start) is counted, not fatal: the pile's energy checks refuse frames where pointed
// roofs meet floors (docs/contact.md, "Limits").
static int cliContactFrames(const cliScene* scene, cliSimulation* sim, int frames, double* ms,
                            double* contacts, fmProfile* sum, int* refused)
{
	double frameTime = cliScene_FrameTime(scene), begin = cliNow();
	for (int f = 0; f < frames; ++f)
	{
		if (ms != NULL && cliNow() - begin > CLI_CONTACT_BUDGET_S)
			return f;
		double start = cliNow();
		fmResult result = fmWorld_Step(sim->world, frameTime, scene->substeps);
		double elapsed = cliNow() - start;
		*refused += result != fm_ok;
		if (ms == NULL)
			continue;
		ms[f] = 1e3 * elapsed;
		contacts[f] = fmWorld_GetContacts(sim->world, NULL, 0);
		fmProfile p = fmWorld_GetProfile(sim->world);
		sum->step += p.step;
		sum->contact += p.contact;
		sum->broadPhase += p.broadPhase;
		sum->narrowPhase += p.narrowPhase;
	}
	return frames;
}

static bool cliContactTime(const cliContactCase* c, const cliScene* scene, cliContactTimes* out)
{
	cliSimulation sim;
	if (!cliSimulation_Create(scene, cli_stepCheckOff, &sim))
		return false;
	double* ms = calloc((size_t)c->timedFrames, sizeof *ms);
	double* contacts = calloc((size_t)c->timedFrames, sizeof *contacts);
	fmProfile sum;
	memset(&sum, 0, sizeof sum);
	memset(out, 0, sizeof *out);
	bool ok = ms != NULL && contacts != NULL;
	if (ok)
	{
		cliContactFrames(scene, &sim, c->untimedFrames, NULL, NULL, NULL, &out->refused);
		out->frames =
		    cliContactFrames(scene, &sim, c->timedFrames, ms, contacts, &sum, &out->refused);
		out->msPerFrame = cliContactMedian(ms, out->frames);
		out->p95 = out->frames > 0 ? ms[(int)floor(0.95 * (out->frames - 1))] : 0.0;
		out->worst = out->frames > 0 ? ms[out->frames - 1] : 0.0;
		out->contacts = cliContactMedian(contacts, out->frames);
		double step = sum.step > 0.0 ? sum.step : 1.0;
		out->contactShare = sum.contact / step;
		out->broadShare = sum.broadPhase / step;
		out->narrowShare = sum.narrowPhase / step;
	}
	free(ms);
	free(contacts);
	cliSimulation_Destroy(&sim);
	return ok;
}

// ---- the scenes ---------------------------------------------------------------------------------

// How the houses of a pile scene stand and what they are made of.
typedef struct cliPileKind
{
	bool implicit; // one implicit step a frame (else explicit, autoSubstep)
	bool apart;    // each shifted CLI_BENCH_APART m along x per place: they land alone
	bool aligned;  // stacked straight up (else every other one shifted: the column topples)
	fmMaterialModel model;
	int columns; // piles of count / columns houses, side by side CLI_BENCH_APART m apart along z
} cliPileKind;

// The seeds' house (cliScene_MakeHouse) copied @p count times, stacked 4.2 m apart
// (the house is 4 m tall: 0.2 m gaps), every other one shifted so that the column topples into
// a pile unless @p kind says aligned, Neo-Hookean or the seeds' StVK (mu 5 kPa, lambda 20 kPa, 1 kg
// a vertex) in 1/60 s frames. Explicit: autoSubstep on the seeds' stick floor with their damping
// and smoothing (their StVK house at mu 5 kPa cannot carry another explicitly: its tets invert,
// docs/contact.md). Implicit: one step per frame on a Coulomb floor, as
// scenes/house_implicit.json, to the game tolerance.
static bool cliPileScene(int count, cliPileKind kind, int workers, cliScene* scene)
{
	const bool implicit = kind.implicit, apart = kind.apart;
	cliScene_MakeHouse(scene);
	cliBodySpec* houses = realloc(scene->bodies, (size_t)count * sizeof *houses);
	if (houses == NULL)
		return false;
	scene->bodies = houses;
	for (int i = 1; i < count; ++i)
		houses[i] = houses[0];
	scene->bodyCount = count;
	const int columns = kind.columns > 1 ? kind.columns : 1, tall = count / columns;
	for (int i = 0; i < count; ++i)
	{
		int level = i % tall, column = i / tall;
		double x = apart ? CLI_BENCH_APART * level : 0.0, z = CLI_BENCH_APART * column;
		houses[i].transform.translate = kind.aligned
		                                    ? fmMakeVec3(x, 4.2 * level, z)
		                                    : fmMakeVec3((level % 2 ? 0.4 : -0.4) + x, 4.2 * level,
		                                                 z + ((level / 2) % 2 ? 0.3 : -0.3));
	}
	snprintf(scene->name, sizeof scene->name, "bench houses %d", count);
	scene->worldDef.workerCount = workers;
	if (scene->worldDef.maxBodies < count)
		scene->worldDef.maxBodies = count;
	scene->dt = 1.0 / 60.0;
	scene->substeps = 1;
	for (int i = 0; i < count; ++i)
		houses[i].def.material = fmMakeMaterialLame(kind.model, 20000.0, 5000.0);
	if (!implicit)
	{
		scene->worldDef.autoSubstep = true;
		return true;
	}
	scene->worldDef.integrator = fm_implicit;
	scene->worldDef.tolerance = FM_TOLERANCE_GAME;
	scene->worldDef.floor.friction = fm_floorCoulomb;
	scene->worldDef.floor.frictionCoefficient = 0.5;
	for (int i = 0; i < count; ++i)
	{
		houses[i].def.damping = 1.0;
		houses[i].def.smoothing = 0.0;
	}
	return true;
}

// Write the heightfield ground as an OBJ in @p folder (the scene reads colliders from files).
static bool cliWriteGround(const char* folder, char* path, size_t size)
{
	if (snprintf(path, size, "%s/ground.obj", folder) >= (int)size)
		return false;
	FILE* file = fopen(path, "w");
	if (file == NULL)
		return false;
	const int n = CLI_GROUND_CELLS;
	const double h = 2.0 * CLI_GROUND_HALF / n, k = 2.0 * CLI_BENCH_PI / CLI_GROUND_WAVELENGTH;
	fprintf(file, "# femto bench: a gently undulating ground, %d x %d quads\n", n, n);
	for (int i = 0; i <= n; ++i)
		for (int j = 0; j <= n; ++j)
		{
			double x = -CLI_GROUND_HALF + i * h, z = -CLI_GROUND_HALF + j * h;
			fprintf(file, "v %.17g %.17g %.17g\n", x,
			        CLI_BENCH_FLOOR_Y + CLI_GROUND_AMPLITUDE * sin(k * x) * cos(k * z), z);
		}
	// Vertex (i, j) is 1 + i (n + 1) + j; both triangles of a quad face +y (counter-clockwise
	// seen from above): the ground is solid below them.
	for (int i = 0; i < n; ++i)
		for (int j = 0; j < n; ++j)
		{
			int a = 1 + i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
			fprintf(file, "f %d %d %d\nf %d %d %d\n", a, b, c, c, b, d);
		}
	bool ok = !ferror(file);
	return fclose(file) == 0 && ok;
}

// The bench's 100k box (a 1 m cube of 26 x 26 x 25 cells, Neo-Hookean E = 1 MPa, 1000 kg/m^3,
// game tolerance) on the heightfield, the floor off: all its support is the mesh collider.
static bool cliGroundScene(const char* folder, int workers, cliScene* scene)
{
	cliScene_MakeHouse(scene);
	if (scene->bodies == NULL)
		return false;
	snprintf(scene->name, sizeof scene->name, "bench box on a mesh ground");
	scene->worldDef.workerCount = workers;
	scene->worldDef.integrator = fm_implicit;
	scene->worldDef.tolerance = FM_TOLERANCE_GAME;
	scene->worldDef.floor.enabled = false;
	scene->dt = 1.0 / 60.0;
	scene->substeps = 1;
	cliBodySpec* box = &scene->bodies[0];
	box->meshSource = cli_meshBox;
	box->boxCells[0] = 26;
	box->boxCells[1] = 25;
	box->boxCells[2] = 26;
	double bottom = CLI_BENCH_FLOOR_Y + CLI_GROUND_AMPLITUDE + 0.005;
	box->boxMin = fmMakeVec3(-0.5, bottom, -0.5);
	box->boxMax = fmMakeVec3(0.5, bottom + 1.0, 0.5);
	box->transform = fmDefaultMeshTransform();
	box->def.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	box->def.massMode = fm_massFromDensity;
	box->def.density = 1000.0;
	scene->colliders = calloc(1, sizeof *scene->colliders);
	if (scene->colliders == NULL)
		return false;
	scene->colliderCount = 1;
	cliColliderSpec* ground = &scene->colliders[0];
	ground->def = fmDefaultColliderDef();
	ground->def.shape = fm_shapeMesh;
	ground->transform = fmDefaultMeshTransform();
	return cliWriteGround(folder, ground->objPath, sizeof ground->objPath);
}

// ---- the rows -----------------------------------------------------------------------------------

static bool cliContactRow(const cliContactCase* c, const cliScene* scene, int tets, int workers,
                          cliBenchReport* report, int* code, cliContactTimes* times)
{
	cliContactTimes local;
	cliContactTimes* tp = times != NULL ? times : &local;
	cliContactTimes t;
	cliBenchMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	snprintf(mesh.label, sizeof mesh.label, "%s", c->label);
	mesh.family = cli_benchContact;
	mesh.tets = tets;
	if (!cliContactTime(c, scene, &t))
	{
		printf("%-12s %7d %-14s %7d %9s\n", c->label, tets, c->integrator, workers, "failed");
		*code = cli_exitInput;
		return false;
	}
	*tp = t;
	printf("%-12s %7d %-14s %7d %9.2f %9.0f %7.1f%% %6.1f%% %6.1f%% %4d/%-4d\n", c->label, tets,
	       c->integrator, workers, t.msPerFrame, t.contacts, 100.0 * t.contactShare,
	       100.0 * t.broadShare, 100.0 * t.narrowShare, t.refused, t.frames);
	fflush(stdout);
	cliBenchResult row = cliBenchResult_Make(&mesh, c->integrator, c->model, workers);
	row.msPerFrame = t.msPerFrame;
	row.contacts = t.contacts;
	row.contactShare = t.contactShare;
	row.broadShare = t.broadShare;
	row.narrowShare = t.narrowShare;
	row.scene = "contact";
	row.p95 = t.p95;
	row.worst = t.worst;
	if (!cliBenchReport_Add(report, &row))
		*code = cli_exitInput;
	return true;
}

// One pile row (@p count houses of @p kind, timed over @p c) and, under it, its frames' 95th
// percentile and worst and the same houses apart, with the ratios.
static void cliPileRow(const cliBenchOptions* o, const cliContactCase* c, int count,
                       cliPileKind kind, cliBenchReport* report, int* code)
{
	cliScene scene, apart;
	cliContactTimes pile, alone;
	memset(&scene, 0, sizeof scene);
	memset(&apart, 0, sizeof apart);
	cliPileKind spread = kind;
	spread.apart = true;
	if (!cliPileScene(count, kind, o->workers, &scene) ||
	    !cliPileScene(count, spread, o->workers, &apart))
	{
		cliError("bench: out of memory for the pile");
		*code = cli_exitInput;
	}
	else if (cliContactRow(c, &scene, count * CLI_BENCH_HOUSE_TETS, o->workers, report, code,
	                       &pile) &&
	         cliContactTime(c, &apart, &alone))
		printf("%-12s   the frames: 95th percentile %.2f ms, worst %.2f ms; the same houses "
		       "apart %.2f ms (median), 95th percentile %.2f: pile / apart %.2f (median), "
		       "%.2f (95th)\n",
		       "", pile.p95, pile.worst, alone.msPerFrame, alone.p95,
		       pile.msPerFrame / alone.msPerFrame, pile.p95 / alone.p95);
	cliScene_Free(&scene);
	cliScene_Free(&apart);
}

// Three houses stacked straight up for 5 s (they drop 0.2 m onto each other and settle),
// implicit, the seeds' StVK and Neo-Hookean; then ten houses piled for 5 s: the top one falls
// 38 m (2.8 s) and the pile settles; then ten such piles side by side, implicit (the frames
// within CLI_CONTACT_BUDGET_S). --quick: the stacks for 1.5 s and a pile of three. Frames of
// 1/60 s: explicit ones cut by autoSubstep, implicit ones one step.
static void cliPileRows(const cliBenchOptions* o, cliBenchReport* report, int* code)
{
	int count = o->quick ? CLI_BENCH_QUICK_PILE_HOUSES : CLI_BENCH_PILE_HOUSES;
	int frames = (int)ceil((o->quick ? 1.5 : 5.0) * 60.0);
	cliContactCase stacks[2] = {
	    {"stack 3 stvk", "implicit game", "stvk", 0, frames},
	    {"stack 3 neo", "implicit game", "neohookean", 0, frames},
	};
	for (int k = 0; k < 2 && 3 * CLI_BENCH_HOUSE_TETS <= o->maxTets; ++k)
		cliPileRow(o, &stacks[k], 3,
		           (cliPileKind){true, false, true, k ? fm_neoHookean : fm_stvk, 1}, report, code);
	char label[16];
	snprintf(label, sizeof label, "houses %d", count);
	cliContactCase cases[2] = {
	    {label, "explicit auto", "neohookean", 0, frames},
	    {label, "implicit game", "neohookean", 0, frames},
	};
	for (int k = 0; k < 2 && count * CLI_BENCH_HOUSE_TETS <= o->maxTets; ++k)
		cliPileRow(o, &cases[k], count, (cliPileKind){k == 1, false, false, fm_neoHookean, 1},
		           report, code);
	// A hundred houses: ten such piles side by side, implicit (not --quick).
	cliContactCase hundred = {"houses 100", "implicit game", "neohookean", 0, frames};
	if (!o->quick && CLI_BENCH_BIG_PILE_HOUSES * CLI_BENCH_HOUSE_TETS <= o->maxTets)
		cliPileRow(o, &hundred, CLI_BENCH_BIG_PILE_HOUSES,
		           (cliPileKind){true, false, false, fm_neoHookean, CLI_BENCH_BIG_PILE_HOUSES / 10},
		           report, code);
}

static void cliGroundRow(const cliBenchOptions* o, const char* folder, cliBenchReport* report,
                         int* code)
{
	cliContactCase c = {"ground 100k", "implicit game", "neohookean", 30, o->repeats};
	if (c.timedFrames < 5)
		c.timedFrames = 5;
	cliScene scene;
	if (folder == NULL || !cliGroundScene(folder, o->workers, &scene))
	{
		printf("ground 100k: skipped: cannot write the ground's OBJ in a temporary folder\n");
		if (folder != NULL)
			cliScene_Free(&scene);
		return;
	}
	cliContactRow(&c, &scene, 6 * 26 * 25 * 26, o->workers, report, code, NULL);
	cliScene_Free(&scene);
}

void cliBenchContactRows(const cliBenchOptions* o, cliBenchReport* report, const char* folder,
                         int* code)
{
	bool pile = 3 * CLI_BENCH_HOUSE_TETS <= o->maxTets, ground = 100000 <= o->maxTets;
	if (!pile && !ground)
		return;
	printf("contact: ms per frame (median), contacts after a frame (median), share of the step in "
	       "the contact stage, its broad and narrow phases; frames refused by the health checks "
	       "of the frames timed (at most %.0f s of them)\n",
	       CLI_CONTACT_BUDGET_S);
	printf("%-12s %7s %-14s %7s %9s %9s %8s %7s %7s %9s\n", "scene", "tets", "integrator",
	       "workers", "ms/frame", "contacts", "contact", "broad", "narrow", "refused");
	if (pile)
		cliPileRows(o, report, code);
	if (ground)
		cliGroundRow(o, folder, report, code);
}
