// The rows in motion of `femto bench` (motion.h).
#include "motion.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The bars: about 1k, 10k and 100k tets of cubic cells, 4 m along x.
static const struct
{
	const char* label;
	int nominal;
	int cells[3];
} cliMotionBars[] = {
    {"bar 1k", 1000, {20, 3, 3}},
    {"bar 10k", 10000, {40, 6, 7}},
    {"bar 100k", 100000, {86, 14, 14}},
};
#define CLI_MOTION_BAR_COUNT ((int)(sizeof cliMotionBars / sizeof cliMotionBars[0]))

// The bars' length (m).
#define CLI_MOTION_BAR_LENGTH 4.0

// The drop's height above the floor (m; the house starts where the demo does, 1.1 m up).
#define CLI_MOTION_DROP 1.0

// The seeds' jump (viewer/session.c): 0.2 m/s before each of the demo frame's 10 substeps.
#define CLI_MOTION_JUMP_SPEED 2.0

// The drag: the target goes round a horizontal circle of this radius (m) in this period (s),
// lifted this high (m) over the first half second.
#define CLI_MOTION_DRAG_RADIUS 1.0
#define CLI_MOTION_DRAG_PERIOD 2.0
#define CLI_MOTION_DRAG_LIFT 0.5

#define CLI_MOTION_PI 3.14159265358979323846

// The 1e-6 path's Newton iterations a step at most: the reference converges where 20 stop short
// (residuals of 2e-6 in the 10k bar's drag).
#define CLI_MOTION_REFERENCE_NEWTON 200

typedef enum cliMotionScene
{
	cli_motionDrop,
	cli_motionSwing,
	cli_motionDrag,
	cli_motionJump, // the house only
	cli_motionSceneCount
} cliMotionScene;

static const char* const cliMotionSceneNames[cli_motionSceneCount] = {"drop", "swing", "drag",
                                                                      "jump"};

// One case: an integrator on some workers (the tolerance: implicit).
typedef struct cliMotionCase
{
	fmIntegrator integrator;
	int workers;
	double tolerance;
} cliMotionCase;

// What one run of a scene recorded, frame by frame.
typedef struct cliMotionTrack
{
	double* ms;       // the step's wall time
	int* newton;      // implicit: Newton iterations; explicit: substeps
	int* cg;          // implicit: CG iterations
	fmVec3* centre;   // the centre of mass after the frame
	fmVec3* tip;      // the tip vertex after the frame
	unsigned* events; // contact events of the frame: 2 * count + began
	int frames;       // frames run (fewer when one was refused)
	double size;      // m, the body's rest box's diagonal
	char why[600];    // the refused frame's reason
} cliMotionTrack;

static void cliMotionTrack_Free(cliMotionTrack* t)
{
	free(t->ms);
	free(t->newton);
	free(t->cg);
	free(t->centre);
	free(t->tip);
	free(t->events);
	memset(t, 0, sizeof *t);
}

static bool cliMotionTrack_Make(cliMotionTrack* t, int frames)
{
	memset(t, 0, sizeof *t);
	size_t n = (size_t)frames;
	t->ms = calloc(n, sizeof *t->ms);
	t->newton = calloc(n, sizeof *t->newton);
	t->cg = calloc(n, sizeof *t->cg);
	t->centre = calloc(n, sizeof *t->centre);
	t->tip = calloc(n, sizeof *t->tip);
	t->events = calloc(n, sizeof *t->events);
	if (t->ms && t->newton && t->cg && t->centre && t->tip && t->events)
		return true;
	cliMotionTrack_Free(t);
	cliError("bench: out of memory");
	return false;
}

// The body's rest box (its positions before the first step).
static void cliMotionBox(const double* x, int n, fmVec3* lo, fmVec3* hi)
{
	*lo = fmMakeVec3(INFINITY, INFINITY, INFINITY);
	*hi = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
	for (int i = 0; i < n; ++i)
	{
		const double* p = x + 3 * (size_t)i;
		*lo = fmMakeVec3(fmin(lo->x, p[0]), fmin(lo->y, p[1]), fmin(lo->z, p[2]));
		*hi = fmMakeVec3(fmax(hi->x, p[0]), fmax(hi->y, p[1]), fmax(hi->z, p[2]));
	}
}

// The tip: the swing's vertex furthest along +x (the free end), else the one furthest from the
// box's centre; the lowest index among equals.
static int cliMotionTip(const double* x, int n, cliMotionScene scene, fmVec3 lo, fmVec3 hi)
{
	fmVec3 mid = fmScale(0.5, fmAdd(lo, hi));
	int best = 0;
	double far = -INFINITY;
	for (int i = 0; i < n; ++i)
	{
		fmVec3 p = fmMakeVec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
		double d = scene == cli_motionSwing ? p.x : fmLength(fmSub(p, mid));
		if (d > far)
			far = d, best = i;
	}
	return best;
}

// What a scene needs while it runs.
typedef struct cliMotionRun
{
	cliSimulation sim;
	fmBodyId body;
	double* x; // positions, for the tip
	int vertices;
	int tip;
	fmVec3 grabbed; // the drag's grab point
	double size;    // the rest box's diagonal (m)
} cliMotionRun;

// Set the scene up on a fresh world: the swing's clamp, the drag's grab. False with a message.
static bool cliMotionSetUp(cliMotionRun* r, cliMotionScene scene, const char* label)
{
	r->body = r->sim.bodies[0];
	r->vertices = fmBody_GetVertexCount(r->body);
	r->x = malloc(3 * sizeof(double) * (size_t)r->vertices);
	if (r->x == NULL || fmBody_CopyPositions(r->body, r->x, r->vertices) != fm_ok)
	{
		cliError("bench: %s: out of memory", label);
		return false;
	}
	fmVec3 lo, hi;
	cliMotionBox(r->x, r->vertices, &lo, &hi);
	r->size = fmLength(fmSub(hi, lo));
	r->tip = cliMotionTip(r->x, r->vertices, scene, lo, hi);
	if (scene == cli_motionSwing)
	{
		double skin = 1e-6 * r->size;
		fmVec3 a = fmSub(lo, fmMakeVec3(skin, skin, skin));
		fmVec3 b = fmMakeVec3(lo.x + skin, hi.y + skin, hi.z + skin);
		if (fmBody_PinBox(r->body, a, b) == 0)
		{
			cliError("bench: %s: the swing's clamp caught no vertex", label);
			return false;
		}
	}
	if (scene == cli_motionDrag)
	{
		fmVec3 top = fmMakeVec3(0.5 * (lo.x + hi.x), hi.y + 0.5 * r->size, 0.5 * (lo.z + hi.z));
		fmGrabDef grab = fmDefaultGrabDef();
		fmRayHit hit;
		if (!fmWorld_GrabRay(r->sim.world, top, fmMakeVec3(0.0, -2.0 * r->size, 0.0),
		                     fmDefaultFilter(), &grab, &hit))
		{
			cliError("bench: %s: the drag's ray from above missed the body", label);
			return false;
		}
		r->grabbed = hit.point;
	}
	return true;
}

// The scene's input before frame @p f: the drag's target, the jump every second.
static void cliMotionInput(cliMotionRun* r, cliMotionScene scene, int f)
{
	double t = (f + 1) / 60.0;
	if (scene == cli_motionDrag)
	{
		double a = 2.0 * CLI_MOTION_PI * t / CLI_MOTION_DRAG_PERIOD;
		double lift = CLI_MOTION_DRAG_LIFT * fmin(1.0, 2.0 * t);
		fmVec3 to = fmMakeVec3(CLI_MOTION_DRAG_RADIUS * sin(a), lift,
		                       CLI_MOTION_DRAG_RADIUS * (1.0 - cos(a)));
		fmBody_MoveGrab(r->body, fmAdd(r->grabbed, to));
	}
	if (scene == cli_motionJump && f % 60 == 0)
		fmBody_ApplyImpulse(r->body, fmMakeVec3(0.0, CLI_MOTION_JUMP_SPEED, 0.0));
}

// Frame @p f's contact events as one number: twice their count plus those that began.
static unsigned cliMotionEvents(fmWorldId world)
{
	fmContactEvent events[64];
	int count = fmWorld_GetContactEvents(world, events, 64);
	unsigned began = 0;
	for (int k = 0; k < count && k < 64; ++k)
		began += events[k].begin;
	return 2u * (unsigned)count + began;
}

// Run @p scene on @p mesh with @p settings for @p frames frames into @p t. False when the
// world cannot be made; a refused frame stops the run (t->frames says where, t->why why).
static bool cliMotionRunScene(const cliBenchMesh* mesh, const cliBenchWorld* settings,
                              cliMotionScene scene, int frames, cliMotionTrack* t)
{
	cliMotionRun r;
	memset(&r, 0, sizeof r);
	if (!cliBenchMesh_World(mesh, settings, &r.sim))
		return false;
	bool ok = cliMotionSetUp(&r, scene, mesh->label);
	t->size = r.size;
	t->frames = 0;
	t->why[0] = '\0';
	for (int f = 0; ok && f < frames; ++f)
	{
		cliMotionInput(&r, scene, f);
		double start = cliNow();
		fmResult result = fmWorld_Step(r.sim.world, 1.0 / 60.0, 1);
		t->ms[f] = 1e3 * (cliNow() - start);
		if (result != fm_ok)
		{
			snprintf(t->why, sizeof t->why, "frame %d: %s: %s", f, fmResultName(result),
			         fmWorld_GetLastError(r.sim.world)->message);
			break;
		}
		fmStepStats stats = fmWorld_GetStepStats(r.sim.world);
		t->newton[f] = settings->integrator == fm_implicit ? stats.newtonIterations : stats.steps;
		t->cg[f] = stats.cgIterations;
		t->centre[f] = fmBody_GetStats(r.body).centerOfMass;
		fmBody_CopyPositions(r.body, r.x, r.vertices);
		t->tip[f] = fmMakeVec3(r.x[3 * r.tip], r.x[3 * r.tip + 1], r.x[3 * r.tip + 2]);
		t->events[f] = cliMotionEvents(r.sim.world);
		t->frames = f + 1;
	}
	free(r.x);
	cliSimulation_Destroy(&r.sim);
	return ok;
}

// ---- the figures -------------------------------------------------------------------------------

static int cliMotionCompare(const void* a, const void* b)
{
	double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

// The median, 95th percentile and worst of @p count values (sorted in place).
static void cliMotionPercentiles(double* ms, int count, double* median, double* p95, double* worst)
{
	qsort(ms, (size_t)count, sizeof *ms, cliMotionCompare);
	*median = count % 2 ? ms[count / 2] : 0.5 * (ms[count / 2 - 1] + ms[count / 2]);
	*p95 = ms[(int)floor(0.95 * (count - 1))];
	*worst = ms[count - 1];
}

// The game path's largest distance from the accurate one (centre of mass or tip) over the
// frames before their contact events first differ, over the body's size.
static double cliMotionAccuracy(const cliMotionTrack* game, const cliMotionTrack* exact,
                                double size)
{
	double far = 0.0;
	int frames = game->frames < exact->frames ? game->frames : exact->frames;
	for (int f = 0; f < frames && game->events[f] == exact->events[f]; ++f)
		far = fmax(far, fmax(fmLength(fmSub(game->centre[f], exact->centre[f])),
		                     fmLength(fmSub(game->tip[f], exact->tip[f]))));
	return far / size;
}

// ---- the rows ----------------------------------------------------------------------------------

// The cases a body is timed in: explicit and implicit at the game tolerance (as the run asks),
// each on 1 and on the run's workers; returns how many.
static int cliMotionCases(const cliBenchOptions* o, cliMotionCase cases[4])
{
	int n = 0;
	for (int k = 0; k < 2; ++k)
	{
		if (k == 0 ? !o->explicitSteps : !o->implicitFrames)
			continue;
		for (int w = 0; w < (o->workers > 1 ? 2 : 1); ++w)
			cases[n++] = (cliMotionCase){k == 0 ? fm_explicit : fm_implicit,
			                             w == 0 ? 1 : o->workers, FM_TOLERANCE_GAME};
	}
	return n;
}

static cliBenchWorld cliMotionSettings(const cliBenchOptions* o, const cliBenchMesh* mesh,
                                       const cliMotionCase* c, cliMotionScene scene)
{
	cliBenchWorld s = {c->integrator,
	                   mesh->family == cli_benchHouse ? fm_stvk : fm_neoHookean,
	                   c->workers,
	                   c->tolerance,
	                   o->simd,
	                   o->deterministic,
	                   o->solver,
	                   c->integrator == fm_explicit,
	                   scene == cli_motionDrop && mesh->family != cli_benchHouse ? CLI_MOTION_DROP
	                                                                             : 0.0,
	                   scene == cli_motionSwing,
	                   c->tolerance < FM_TOLERANCE_GAME ? CLI_MOTION_REFERENCE_NEWTON : 0,
	                   0.0,
	                   false,
	                   0.0};
	return s;
}

// A row: @p count frames' times (sorted here), their Newton and CG counts (@p newton, @p cg;
// explicit: the substeps, and zeros), the accuracy (NAN: none). Printed and added to the report.
static bool cliMotionRow(const cliBenchMesh* mesh, const cliBenchWorld* settings, const char* scene,
                         double* ms, const int* newton, const int* cg, int count, double accuracy,
                         cliBenchReport* report)
{
	bool implicit = settings->integrator == fm_implicit;
	// The slowest frame's counts, found before the times are sorted.
	int slowest = 0;
	double newtonSum = 0.0, cgSum = 0.0;
	for (int f = 0; f < count; ++f)
	{
		if (ms[f] > ms[slowest])
			slowest = f;
		newtonSum += newton[f];
		cgSum += cg[f];
	}
	cliBenchResult row =
	    cliBenchResult_Make(mesh, implicit ? "implicit game" : "explicit",
	                        fmMaterialModelName(settings->model), settings->workers);
	row.scene = scene;
	if (implicit)
	{
		row.newtonPerFrame = newtonSum / count;
		row.cgPerFrame = cgSum / count;
		row.newtonWorst = newton[slowest];
		row.cgWorst = cg[slowest];
	}
	row.accuracy = accuracy;
	cliMotionPercentiles(ms, count, &row.msPerFrame, &row.p95, &row.worst);
	char counts[64] = "", far[32] = "";
	if (implicit)
		snprintf(counts, sizeof counts, "%6.1f %7.1f %5.0f %6.0f", row.newtonPerFrame,
		         row.cgPerFrame, row.newtonWorst, row.cgWorst);
	else
		snprintf(counts, sizeof counts, "(%.1f substeps a frame)", newtonSum / count);
	if (!isnan(accuracy))
		snprintf(far, sizeof far, "%.3f%%", 100.0 * accuracy);
	printf("%-6s %-9s %7d %-10s %-13s %7d %8.3f %8.3f %8.3f %6.2f %-27s %9s\n", scene, mesh->label,
	       mesh->tets, row.model, row.integrator, row.workers, row.msPerFrame, row.p95, row.worst,
	       row.worst / row.msPerFrame, counts, far);
	fflush(stdout);
	return cliBenchReport_Add(report, &row);
}

// What one body's cases recorded: [case][scene], and the accurate paths [scene].
typedef struct cliMotionBody
{
	cliMotionTrack best[4][cli_motionSceneCount];
	cliMotionTrack exact[cli_motionSceneCount];
	cliMotionTrack scratch;
	int cases;
	int scenes;
} cliMotionBody;

static void cliMotionBody_Free(cliMotionBody* b)
{
	for (int c = 0; c < 4; ++c)
		for (int s = 0; s < cli_motionSceneCount; ++s)
			cliMotionTrack_Free(&b->best[c][s]);
	for (int s = 0; s < cli_motionSceneCount; ++s)
		cliMotionTrack_Free(&b->exact[s]);
	cliMotionTrack_Free(&b->scratch);
}

// Run every case of every scene @p repeats times, interleaved, keeping each frame's fastest
// time. False when a world cannot be made or memory runs out.
static bool cliMotionTime(const cliBenchOptions* o, const cliBenchMesh* mesh,
                          const cliMotionCase* cases, cliMotionBody* b)
{
	if (!cliMotionTrack_Make(&b->scratch, o->frames))
		return false;
	for (int r = 0; r < o->repeats; ++r)
		for (int s = 0; s < b->scenes; ++s)
			for (int c = 0; c < b->cases; ++c)
			{
				cliBenchWorld settings = cliMotionSettings(o, mesh, &cases[c], s);
				cliMotionTrack* best = &b->best[c][s];
				cliMotionTrack* t = r == 0 ? best : &b->scratch;
				if ((r == 0 && !cliMotionTrack_Make(best, o->frames)) ||
				    !cliMotionRunScene(mesh, &settings, s, o->frames, t))
					return false;
				for (int f = 0; r > 0 && f < t->frames && f < best->frames; ++f)
					best->ms[f] = fmin(best->ms[f], t->ms[f]);
			}
	if (!o->implicitFrames)
		return true;
	cliMotionCase accurate = {fm_implicit, 1, FM_TOLERANCE_ACCURATE};
	for (int s = 0; s < b->scenes; ++s)
	{
		cliBenchWorld settings = cliMotionSettings(o, mesh, &accurate, s);
		if (!cliMotionTrack_Make(&b->exact[s], o->frames) ||
		    !cliMotionRunScene(mesh, &settings, s, o->frames, &b->exact[s]))
			return false;
	}
	return true;
}

// The rows of case @p c: a row per scene, then every scene's frames pooled ("all").
static bool cliMotionCaseRows(const cliBenchOptions* o, const cliBenchMesh* mesh,
                              const cliMotionCase* c, cliMotionBody* b, int k,
                              cliBenchReport* report, int* code)
{
	size_t total = (size_t)b->scenes * o->frames;
	double* ms = malloc(total * sizeof *ms);
	int* newton = malloc(total * sizeof *newton);
	int* cg = malloc(total * sizeof *cg);
	bool ok = ms != NULL && newton != NULL && cg != NULL;
	int pooled = 0;
	double accuracy = NAN;
	cliBenchWorld settings = cliMotionSettings(o, mesh, c, cli_motionDrop);
	for (int s = 0; ok && s < b->scenes; ++s)
	{
		cliMotionTrack* t = &b->best[k][s];
		if (t->frames < o->frames)
		{
			printf("%-6s %-9s %7d %-10s %-13s %7d refused: %s\n", cliMotionSceneNames[s],
			       mesh->label, mesh->tets, fmMaterialModelName(settings.model),
			       c->integrator == fm_implicit ? "implicit game" : "explicit", c->workers, t->why);
			*code = cli_exitInput;
			continue;
		}
		double far = NAN;
		if (c->integrator == fm_implicit && b->exact[s].ms != NULL)
			far = cliMotionAccuracy(t, &b->exact[s], t->size);
		accuracy = isnan(accuracy) ? far : fmax(accuracy, far);
		// Frame 0 is the world's first step, its setup with it: start-up, not motion.
		const int timed = o->frames - 1;
		memcpy(ms + pooled, t->ms + 1, (size_t)timed * sizeof *ms);
		memcpy(newton + pooled, t->newton + 1, (size_t)timed * sizeof *newton);
		memcpy(cg + pooled, t->cg + 1, (size_t)timed * sizeof *cg);
		pooled += timed;
		ok = cliMotionRow(mesh, &settings, cliMotionSceneNames[s], t->ms + 1, t->newton + 1,
		                  t->cg + 1, timed, far, report);
	}
	if (ok && pooled > 0)
		ok = cliMotionRow(mesh, &settings, "all", ms, newton, cg, pooled, accuracy, report);
	free(ms);
	free(newton);
	free(cg);
	return ok;
}

static void cliMotionBodyRows(const cliBenchOptions* o, const cliBenchMesh* mesh,
                              cliBenchReport* report, int* code)
{
	cliMotionCase cases[4];
	cliMotionBody b;
	memset(&b, 0, sizeof b);
	b.cases = cliMotionCases(o, cases);
	b.scenes = mesh->family == cli_benchHouse ? cli_motionSceneCount : cli_motionJump;
	bool ok = cliMotionTime(o, mesh, cases, &b);
	for (int c = 0; ok && c < b.cases; ++c)
		ok = cliMotionCaseRows(o, mesh, &cases[c], &b, c, report, code);
	if (!ok)
	{
		printf("%-6s %-9s %7d failed\n", "", mesh->label, mesh->tets);
		*code = cli_exitInput;
	}
	cliMotionBody_Free(&b);
}

// Whether the run asks for family @p f's bodies in motion (every one when it names none).
static bool cliMotionWants(const cliBenchOptions* o, cliBenchFamily f)
{
	unsigned meshes = (1u << cli_benchHouse) | (1u << cli_benchBox) | (1u << cli_benchBeam);
	return (o->families & meshes) == 0 ? f != cli_benchBeam : (o->families & (1u << f)) != 0;
}

void cliBenchMotionRows(const cliBenchOptions* o, const cliBenchMeshSet* meshes,
                        cliBenchReport* report, int* code)
{
	int most = o->quick ? CLI_MOTION_QUICK_MAX_TETS : CLI_MOTION_MAX_TETS;
	most = o->maxTets < most ? o->maxTets : most;
	printf("in motion: %d frames of 1/60 s a scene (drop, swing, drag; the house also jumps), "
	       "each frame its fastest of %d interleaved repeats (the first frame, the world's setup, "
	       "not counted); explicit with autoSubstep, "
	       "implicit at the game tolerance; accuracy: the game path's largest distance from the "
	       "1e-6 path (centre of mass or tip, until their contact events differ), of the body's "
	       "size\n",
	       o->frames, o->repeats);
	printf("%-6s %-9s %7s %-10s %-13s %7s %8s %8s %8s %6s %6s %7s %5s %6s %9s\n", "scene", "mesh",
	       "tets", "model", "integrator", "workers", "median", "p95", "worst", "w/med", "Newton",
	       "CG", "N@w", "CG@w", "accuracy");
	if (cliMotionWants(o, cli_benchHouse) && 1389 <= most)
	{
		cliBenchMesh house = {"house2", cli_benchHouse, 1389, 1389, {0}, 0.0, "", ""};
		cliMotionBodyRows(o, &house, report, code);
	}
	// --quick: the house alone.
	for (int k = 0; k < CLI_MOTION_BAR_COUNT && cliMotionWants(o, cli_benchBox) && !o->quick; ++k)
	{
		cliBenchMesh bar;
		memset(&bar, 0, sizeof bar);
		bar.family = cli_benchBox;
		snprintf(bar.label, sizeof bar.label, "%s", cliMotionBars[k].label);
		bar.nominal = cliMotionBars[k].nominal;
		memcpy(bar.cells, cliMotionBars[k].cells, sizeof bar.cells);
		bar.tets = 6 * bar.cells[0] * bar.cells[1] * bar.cells[2];
		bar.length = CLI_MOTION_BAR_LENGTH;
		if (bar.nominal <= most)
			cliMotionBodyRows(o, &bar, report, code);
	}
	for (int m = 0; m < meshes->count && cliMotionWants(o, cli_benchBeam) && !o->quick; ++m)
		if (meshes->meshes[m].family == cli_benchBeam && meshes->meshes[m].nominal <= most)
			cliMotionBodyRows(o, &meshes->meshes[m], report, code);
}

// ---- many small bodies --------------------------------------------------------------------------

// A prop: a box of 2 x 3 x 4 cells (144 tets), 0.3 x 0.45 x 0.6 m, dropped this high (m) onto
// the Coulomb floor, props this far apart (m) on a square grid.
#define CLI_PROP_DROP 0.5
#define CLI_PROP_SPACING 1.0

// A world of @p count props (implicit, the game tolerance, @p workers), or the null id.
static fmWorldId cliPropsWorld(const cliBenchOptions* o, int count, int workers)
{
	fmWorldDef def = cliBenchFloorWorldDef(o, workers);
	def.maxBodies = count;
	fmWorldId world = fmCreateWorld(&def);
	int side = (int)ceil(sqrt((double)count));
	for (int i = 0; i < count && fmWorld_IsValid(world); ++i)
	{
		double x = CLI_PROP_SPACING * (i % side), z = CLI_PROP_SPACING * (i / side);
		fmTetMesh mesh;
		fmBodyDef body = cliBenchBoxBodyDef(&mesh);
		fmBodyId id;
		bool ok = fmMakeBoxMesh(2, 3, 4, fmMakeVec3(x, CLI_PROP_DROP, z),
		                        fmMakeVec3(x + 0.3, CLI_PROP_DROP + 0.45, z + 0.6), &mesh) == fm_ok;
		ok = ok && fmCreateBody(world, &body, &id, NULL) == fm_ok;
		fmFreeTetMesh(&mesh);
		if (!ok)
		{
			fmDestroyWorld(world);
			return (fmWorldId){0, 0};
		}
	}
	return world;
}

// Step a world of @p count props for o->frames frames, keeping each frame's fastest
// time in @p ms (the first run fills it). False when a frame is refused or the world cannot be
// made (said why).
static bool cliPropsRun(const cliBenchOptions* o, int count, int workers, bool first, double* ms)
{
	fmWorldId world = cliPropsWorld(o, count, workers);
	if (!fmWorld_IsValid(world))
	{
		cliError("bench: props: cannot make a world of %d props", count);
		return false;
	}
	bool ok = true;
	for (int f = 0; ok && f < o->frames; ++f)
	{
		double start = cliNow();
		ok = fmWorld_Step(world, 1.0 / 60.0, 1) == fm_ok;
		double t = 1e3 * (cliNow() - start);
		ms[f] = first ? t : fmin(ms[f], t);
		if (!ok)
			printf("props %d: frame %d refused: %s\n", count, f,
			       fmWorld_GetLastError(world)->message);
	}
	fmDestroyWorld(world);
	return ok;
}

void cliBenchPropsRows(const cliBenchOptions* o, cliBenchReport* report, int* code)
{
	const int count = o->quick ? CLI_PROPS_QUICK : CLI_PROPS;
	printf("many small bodies: %d props of 144 tets dropped %.1f m onto the floor, %.0f m apart, "
	       "implicit at the game tolerance; each frame its fastest of %d interleaved repeats (the "
	       "first frame not counted), beside one prop alone times %d (the sum of the same bodies "
	       "stepped alone)\n",
	       count, CLI_PROP_DROP, CLI_PROP_SPACING, o->repeats, count);
	cliBenchMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	mesh.family = cli_benchBox;
	snprintf(mesh.label, sizeof mesh.label, "props %d", count);
	mesh.tets = 144 * count;
	size_t frames = o->frames;
	double* ms[4] = {calloc(frames, sizeof(double)), calloc(frames, sizeof(double)),
	                 calloc(frames, sizeof(double)), calloc(frames, sizeof(double))};
	const int workers[2] = {1, o->workers};
	const int cases = o->workers > 1 ? 2 : 1;
	bool ok = ms[0] && ms[1] && ms[2] && ms[3];
	// [2 w]: the props on that many workers; [2 w + 1]: one prop alone, scaled by the count.
	for (int r = 0; ok && r < o->repeats; ++r)
		for (int w = 0; ok && w < cases; ++w)
			ok = cliPropsRun(o, count, workers[w], r == 0, ms[2 * w]) &&
			     cliPropsRun(o, 1, workers[w], r == 0, ms[2 * w + 1]);
	for (int w = 0; ok && w < cases; ++w)
	{
		double alone[3], props[3];
		for (size_t f = 0; f < frames; ++f)
			ms[2 * w + 1][f] *= count;
		cliMotionPercentiles(ms[2 * w + 1] + 1, (int)frames - 1, &alone[0], &alone[1], &alone[2]);
		cliMotionPercentiles(ms[2 * w] + 1, (int)frames - 1, &props[0], &props[1], &props[2]);
		printf("props %-5d %7d implicit game %2d workers: median %.2f ms, 95th percentile %.2f, "
		       "worst %.2f; alone (x %d) %.2f, %.2f, %.2f; ratio %.2f (median), %.2f (95th)\n",
		       count, mesh.tets, workers[w], props[0], props[1], props[2], count, alone[0],
		       alone[1], alone[2], props[0] / alone[0], props[1] / alone[1]);
		cliBenchResult row = cliBenchResult_Make(&mesh, "implicit game", "neohookean", workers[w]);
		row.scene = "props";
		row.msPerFrame = props[0];
		row.p95 = props[1];
		row.worst = props[2];
		ok = cliBenchReport_Add(report, &row);
	}
	if (!ok)
		*code = cli_exitInput;
	for (int k = 0; k < 4; ++k)
		free(ms[k]);
}
