// `femto run`: step a scene frame by frame, show progress, write a VTK series, print a summary.
#include "commands.h"

#include "attachments.h"
#include "output.h"
#include "scene.h"
#include "viewer_hook.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* const cliRunHelp =
    "usage: femto run [SCENE.json] [options]\n"
    "\n"
    "Simulate a scene (docs/scene-format.md); without SCENE, the built-in bouncy house.\n"
    "\n"
    "options:\n"
    "  --seconds S        simulate S seconds (rounded up to whole frames)\n"
    "  --frames N         simulate N frames (a frame is dt * substeps of the scene)\n"
    "  --out DIR          write DIR/NAME.pvd and DIR/NAME_NNNNNN.vtu (created if missing):\n"
    "                     binary appended data, zlib-compressed where femto was built with\n"
    "                     zlib; the .pvd lists every frame written so far at any moment\n"
    "  --vtu-ascii        with --out: the .vtu files in ASCII (larger, readable as text)\n"
    "  --every N          with --out: write every Nth frame (default 1)\n"
    "  --obj              with --out: also write DIR/NAME_NNNNNN.obj surfaces with normals:\n"
    "                     a body's render mesh (\"render_mesh\" in the scene) when it has\n"
    "                     one, else its tet surface\n"
    "  --export-obj FILE  write the final surfaces (as --obj) to FILE\n"
    "  --export-node FILE write the final positions as a TetGen .node (FILE_B.node per body\n"
    "                     B when the scene has several bodies)\n"
    "  --impulse-at T     the seeds' space-bar jump in the first frame that starts at or after\n"
    "                     T seconds: 0.2 m/s upward added to every free vertex before each\n"
    "                     substep of that frame (2 m/s over the house's 10); repeatable\n"
    "  --impulse-speed V  a custom jump instead: V m/s added once at that frame's start\n"
    "  --strict           an implicit step that ends above the solver tolerance is an error\n"
    "                     (the scene's \"not_converged\": \"error\"); by default a warning,\n"
    "                     counted in the summary\n"
    "  --workers N        threads the stages run on, 1 to 64 (default: the scene's \"workers\",\n"
    "                     else the cores available); results are the same bits for any N\n"
    "  --simd LEVEL       the explicit element kernels' instruction set: auto (default: the\n"
    "                     best the CPU has), avx512, avx2, sse2, scalar (the same bits on\n"
    "                     each), or off (the double-precision reference kernel)\n"
    "  --deterministic    cross-machine determinism (the scene's \"deterministic\": true,\n"
    "                     fmWorldDef.crossPlatformDeterminism): the same bits on any machine\n"
    "  --gif FILE         also draw the run into an animated GIF (docs/viewer.md)\n"
    "  --png DIR          also draw it as DIR/frame_0000.png, frame_0001.png, ...\n"
    "  --size WxH         picture size in pixels (default 640x480)\n"
    "  --fps N            pictures per simulated second, 1 to 1000 (default 30; a GIF\n"
    "                     at most 50)\n"
    "  --camera-distance D, --camera-yaw DEG, --camera-pitch DEG, --camera-target X,Y,Z\n"
    "                     the orbit camera (default: the bodies and the floor under them\n"
    "                     framed from yaw 30, pitch 20)\n"
    "  --draw LIST        what to draw: surfaces,stress,tets,inverted,pins,targets,floor,\n"
    "                     contacts, colliders, fibres, plastic, damage, all or none\n"
    "                     (default surfaces,floor,pins,targets,colliders)\n"
    "  --audit            check the bodies for intersections after every substep\n"
    "                     (fmWorld_AuditContact: surface crossings between bodies and within\n"
    "                     self-colliding ones, vertices inside another body, inverted tets)\n"
    "                     and print the worst seen; frame ends only, not every substep\n"
    "  --progress S       off a terminal (CI logs, scripts), a progress line every S seconds\n"
    "                     of wall time (default 5; on a terminal one line is redrawn)\n"
    "  --quiet            no progress lines\n"
    "  --help             this text\n"
    "\n"
    "Exit status: 0 ok, 1 bad scene/file, I/O error or numerical failure, 2 usage error.\n";

#define CLI_MAX_IMPULSES 64

// Seconds between progress lines when stderr is not a terminal (--progress).
#define CLI_PROGRESS_LOG_SECONDS 5.0

typedef struct cliRunOptions
{
	const char* scenePath;
	double seconds;
	int frames;
	const char* outDir;
	int every;
	bool obj;
	bool vtuAscii;
	const char* exportNode;
	const char* exportObj;
	double impulseTimes[CLI_MAX_IMPULSES];
	int impulseCount;
	double impulseSpeed; ///< m/s added once by a custom jump (only with hasImpulseSpeed)
	bool hasImpulseSpeed;
	bool strict;
	int workers;        ///< --workers, 0 if not given
	const char* simd;   ///< --simd, NULL if not given
	bool deterministic; ///< --deterministic
	bool quiet;
	bool audit;             ///< --audit
	double progressSeconds; ///< --progress: wall seconds between lines off a terminal
	cliViewOptions view;    ///< --gif, --png and their picture options
} cliRunOptions;

// Implicit solves of the run that ended above the tolerance, and the most contacts a step ended
// with (fmWorld_GetContacts: bodies and colliders).
typedef struct cliSolveTotals
{
	long long steps; ///< substeps taken (fmStepStats.steps: automatic substeps vary)
	int unconvergedSteps;
	double maxResidual;
	int maxContacts;
	bool audit;           ///< --audit: fmWorld_AuditContact after every substep
	int audits;           ///< audits made (substeps)
	int auditedFindings;  ///< audits that found something
	int firstFindingStep; ///< the substep of the first such audit (1-based), 0 when none
	fmContactAudit worst; ///< each count's largest over the run
	fmContactAudit first; ///< the first audit that found something
} cliSolveTotals;

// --audit's hook: the simulation it audits and where the counts go.
typedef struct cliAuditHook
{
	const cliSimulation* sim;
	cliSolveTotals* totals;
} cliAuditHook;

static void cliAuditStep(const cliSimulation* sim, cliSolveTotals* totals);

// fmWorldDef.substepCallback of --audit: every substep is audited.
static void cliAuditSubstep(int substep, double time, void* context)
{
	(void)substep;
	(void)time;
	const cliAuditHook* hook = context;
	cliAuditStep(hook->sim, hook->totals);
}

// --audit: the world will call the hook after every substep.
static void cliInstallAudit(cliScene* scene, cliAuditHook* hook)
{
	if (!hook->totals->audit)
		return;
	scene->worldDef.substepCallback = cliAuditSubstep;
	scene->worldDef.substepContext = hook;
}

// Whether an audit found anything.
static bool cliAuditFound(const fmContactAudit* a)
{
	return a->crossings + a->selfCrossings + a->verticesInside + a->invertedTets > 0;
}

// --audit: audit the world after a substep and keep each count's worst.
static void cliAuditStep(const cliSimulation* sim, cliSolveTotals* totals)
{
	fmContactAudit a;
	if (fmWorld_AuditContact(sim->world, &a) != fm_ok)
		return;
	totals->audits += 1;
	if (cliAuditFound(&a) && totals->auditedFindings++ == 0)
	{
		totals->first = a;
		totals->firstFindingStep = totals->audits;
	}
	fmContactAudit* w = &totals->worst;
	w->crossings = a.crossings > w->crossings ? a.crossings : w->crossings;
	w->selfCrossings = a.selfCrossings > w->selfCrossings ? a.selfCrossings : w->selfCrossings;
	w->verticesInside = a.verticesInside > w->verticesInside ? a.verticesInside : w->verticesInside;
	w->invertedTets = a.invertedTets > w->invertedTets ? a.invertedTets : w->invertedTets;
	w->deepest = fmax(w->deepest, a.deepest);
}

// The picture options need --gif or --png; a GIF shows at most 50 pictures a second (its delays
// are whole centiseconds, and players show delays under 2 cs as 10). -1 or an exit code.
static int cliCheckPictureOptions(const cliViewOptions* v)
{
	bool pictureOption = v->hasSize || v->hasFps || v->hasDistance || v->hasYaw || v->hasPitch ||
	                     v->hasTarget || v->hasDraw;
	if (pictureOption && !cliViewOptions_WantsImages(v))
		return cliUsageError("run", "--size, --fps, --camera-* and --draw need --gif FILE or "
		                            "--png DIR");
	if (v->gifPath != NULL && v->fps > 50.0)
		return cliUsageError("run",
		                     "--fps: %g is too many pictures a second for a GIF (at most "
		                     "50; --png takes up to 1000)",
		                     v->fps);
	// Before the scene loads: a build without the renderer says so at once.
	if (cliViewOptions_WantsImages(v) && !cliVideo_Available(v->gifPath ? "--gif" : "--png"))
		return cli_exitInput;
	return -1;
}

// Parse the options; returns -1 to go on, or an exit code.
// The run's length and the seeds' jump: --seconds, --frames, --every, --impulse-at,
// --impulse-speed. True when argv[*i] is one of them; *code is then -1, or the exit code of a
// usage error. @p hasSeconds and @p hasFrames say which length was given.
static bool cliParseRunTime(cliRunOptions* o, int argc, char** argv, int* i, bool* hasSeconds,
                            bool* hasFrames, int* code)
{
	const char* arg = argv[*i];
	const char* value = NULL;
	*code = -1;
	if (strcmp(arg, "--seconds") == 0)
	{
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL)
			*code = cli_exitUsage;
		else if (!cliParseDouble(value, &o->seconds) || !(o->seconds > 0.0) || o->seconds > 1e6)
			*code =
			    cliUsageError("run", "--seconds: expected a number in (0, 1e6], got '%s'", value);
		*hasSeconds = true;
	}
	else if (strcmp(arg, "--frames") == 0)
	{
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL ||
		    !cliParseIntOption("run", "--frames", value, 0, CLI_MAX_FRAMES, &o->frames))
			*code = cli_exitUsage;
		*hasFrames = true;
	}
	else if (strcmp(arg, "--every") == 0)
	{
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL ||
		    !cliParseIntOption("run", "--every", value, 1, INT_MAX, &o->every))
			*code = cli_exitUsage;
	}
	else if (strcmp(arg, "--impulse-at") == 0)
	{
		double t = 0;
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL)
			*code = cli_exitUsage;
		else if (!cliParseDouble(value, &t) || t < 0.0)
			*code = cliUsageError("run", "--impulse-at: expected a time >= 0 s, got '%s'", value);
		else if (o->impulseCount == CLI_MAX_IMPULSES)
			*code = cliUsageError("run", "--impulse-at: at most %d impulses", CLI_MAX_IMPULSES);
		else
			o->impulseTimes[o->impulseCount++] = t;
	}
	else if (strcmp(arg, "--impulse-speed") == 0)
	{
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL)
			*code = cli_exitUsage;
		else if (!cliParseDouble(value, &o->impulseSpeed))
			*code =
			    cliUsageError("run", "--impulse-speed: expected a number (m/s), got '%s'", value);
		o->hasImpulseSpeed = true;
	}
	else
		return false;
	return true;
}

// What the run writes and says: --out, --obj, --vtu-ascii, --export-obj, --export-node,
// --audit, --progress, --quiet. As cliParseRunTime.
static bool cliParseRunOutput(cliRunOptions* o, int argc, char** argv, int* i, int* code)
{
	const char* arg = argv[*i];
	const char* value = NULL;
	*code = -1;
	if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0)
		o->quiet = true;
	else if (strcmp(arg, "--obj") == 0)
		o->obj = true;
	else if (strcmp(arg, "--audit") == 0)
		o->audit = true;
	else if (strcmp(arg, "--vtu-ascii") == 0)
		o->vtuAscii = true;
	else if (strcmp(arg, "--progress") == 0)
	{
		if ((value = cliOptionValue("run", argc, argv, i)) == NULL)
			*code = cli_exitUsage;
		else if (!cliParseDouble(value, &o->progressSeconds) || !(o->progressSeconds >= 0.0))
			*code = cliUsageError("run", "--progress: expected seconds >= 0, got '%s'", value);
	}
	else if (strcmp(arg, "--export-obj") == 0)
		*code = (o->exportObj = cliOptionValue("run", argc, argv, i)) == NULL ? cli_exitUsage : -1;
	else if (strcmp(arg, "--out") == 0)
		*code = (o->outDir = cliOptionValue("run", argc, argv, i)) == NULL ? cli_exitUsage : -1;
	else if (strcmp(arg, "--export-node") == 0)
		*code = (o->exportNode = cliOptionValue("run", argc, argv, i)) == NULL ? cli_exitUsage : -1;
	else
		return false;
	return true;
}

static int cliParseRunOptions(int argc, char** argv, cliRunOptions* o)
{
	memset(o, 0, sizeof *o);
	o->every = 1;
	o->progressSeconds = CLI_PROGRESS_LOG_SECONDS;
	cliViewOptions_Init(&o->view);
	bool hasSeconds = false, hasFrames = false;
	int code = -1;
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(cliRunHelp, stdout);
			return cli_exitOk;
		}
		else if (strcmp(arg, "--strict") == 0)
			o->strict = true;
		else if (strcmp(arg, "--deterministic") == 0)
			o->deterministic = true;
		else if (strcmp(arg, "--workers") == 0)
		{
			const char* value = cliOptionValue("run", argc, argv, &i);
			if (value == NULL ||
			    !cliParseIntOption("run", "--workers", value, 1, FM_MAX_WORKERS, &o->workers))
				return cli_exitUsage;
		}
		else if (strcmp(arg, "--simd") == 0)
		{
			fmSimdLevel level;
			if ((o->simd = cliOptionValue("run", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!fmSimdLevelFromName(o->simd, &level))
				return cliUsageError("run",
				                     "--simd: expected auto, off, scalar, sse2, avx2 or avx512, "
				                     "got '%s'",
				                     o->simd);
		}
		else if (cliParseRunTime(o, argc, argv, &i, &hasSeconds, &hasFrames, &code) ||
		         cliParseRunOutput(o, argc, argv, &i, &code) ||
		         cliViewOptions_Parse(&o->view, "run", argc, argv, &i, &code))
		{
			if (code >= 0)
				return code;
		}
		else if (arg[0] == '-' && arg[1] != 0)
			return cliUsageError("run", "unknown option '%s'", arg);
		else if (o->scenePath == NULL)
			o->scenePath = arg;
		else
			return cliUsageError("run", "more than one scene ('%s' and '%s')", o->scenePath, arg);
	}
	if (hasSeconds && hasFrames)
		return cliUsageError("run", "give --seconds or --frames, not both");
	if (o->obj && o->outDir == NULL)
		return cliUsageError("run", "--obj needs --out DIR");
	if (o->vtuAscii && o->outDir == NULL)
		return cliUsageError("run", "--vtu-ascii needs --out DIR");
	if (!hasSeconds && !hasFrames)
		o->seconds = -1.0; // the scene decides
	return cliCheckPictureOptions(&o->view);
}

// Frames to run: the command line, then the scene, then 5 s. -1 (with a message) when a
// duration is more frames than CLI_MAX_FRAMES.
static int cliFrameCount(const cliRunOptions* o, const cliScene* scene)
{
	double frameTime = cliScene_FrameTime(scene);
	double seconds = o->seconds;
	if (seconds < 0.0)
	{
		if (o->frames > 0 || scene->frames > 0)
			return o->frames > 0 ? o->frames : scene->frames;
		seconds = scene->seconds > 0.0 ? scene->seconds : 5.0;
	}
	else if (seconds == 0.0)
		return o->frames;
	// A tiny allowance so 10 s of 0.03 s frames is 334 frames, not 335 from rounding noise; any
	// time at all is at least a frame.
	double frames = fmax(1.0, ceil(seconds / frameTime - 1e-9));
	if (frames > CLI_MAX_FRAMES)
	{
		cliError("%s: %g s is too long: %.6g frames of %g s, more than the %d frame limit",
		         scene->name, seconds, frames, frameTime, CLI_MAX_FRAMES);
		return -1;
	}
	return (int)frames;
}

// The series name: the scene file's stem, "house" for the built-in.
static void cliSeriesName(const char* scenePath, char* name, size_t size)
{
	if (scenePath == NULL)
	{
		snprintf(name, size, "house");
		return;
	}
	const char* base = strrchr(scenePath, '/');
	base = base ? base + 1 : scenePath;
	size_t length = strcspn(base, ".");
	if (length == 0)
		length = strlen(base);
	snprintf(name, size, "%.*s", (int)length, base);
}

typedef struct cliTotals
{
	double lowestReached; // over the whole run, after every frame
	double kinetic;
	double elastic;
	double lowestY;
	int inverted;
	int tets;
} cliTotals;

static cliTotals cliSumStats(const cliSimulation* sim)
{
	cliTotals totals = {INFINITY, 0.0, 0.0, INFINITY, 0, 0};
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		fmBodyStats stats = fmBody_GetStats(sim->bodies[b]);
		totals.kinetic += stats.kineticEnergy;
		totals.elastic += stats.elasticEnergy;
		totals.lowestY = fmin(totals.lowestY, stats.lowestY);
		totals.inverted += stats.invertedTets;
		totals.tets += fmBody_GetTetCount(sim->bodies[b]);
	}
	return totals;
}

// On a terminal the line is rewritten in place (\r); elsewhere (a CI log, a pipe) each is a line
// of its own, with the elapsed wall time and an estimate of what is left.
static void cliPrintProgress(int frame, int frames, double time, const cliSimulation* sim, bool tty,
                             double elapsed)
{
	cliTotals totals = cliSumStats(sim);
	if (tty)
		fprintf(stderr,
		        "\rframe %d/%d  t = %.2f s  lowest y = %.3f m  KE = %.4g J  inverted = %d   ",
		        frame, frames, time, totals.lowestY, totals.kinetic, totals.inverted);
	else
		fprintf(stderr,
		        "femto: frame %d/%d (%.0f%%)  t = %.3g s  wall %.0f s, about %.0f s left  "
		        "lowest y = %.3f m  KE = %.4g J  inverted = %d\n",
		        frame, frames, 100.0 * frame / frames, time, elapsed,
		        frame > 0 ? elapsed * (frames - frame) / frame : 0.0, totals.lowestY,
		        totals.kinetic, totals.inverted);
	fflush(stderr);
}

// Mass-weighted mean height of all bodies (m).
static double cliCenterOfMassY(const cliSimulation* sim)
{
	double mass = 0.0, moment = 0.0;
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		double* x = cliCopyState(sim->bodies[b], false);
		const double* m = fmBody_GetMasses(sim->bodies[b]);
		int count = x ? fmBody_GetVertexCount(sim->bodies[b]) : 0;
		for (int i = 0; i < count; ++i)
		{
			mass += m[i];
			moment += m[i] * x[3 * i + 1];
		}
		free(x);
	}
	return mass > 0.0 ? moment / mass : 0.0;
}

static double cliLowestY(const cliSimulation* sim)
{
	double lowest = INFINITY;
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		double* x = cliCopyState(sim->bodies[b], false);
		int count = x ? fmBody_GetVertexCount(sim->bodies[b]) : 0;
		for (int i = 0; i < count; ++i)
			lowest = fmin(lowest, x[3 * i + 1]);
		free(x);
	}
	return lowest;
}

// The seeds' jump, in m/s added per substep: their space-bar check sits inside the substep loop
// (PhysicsStep/_Update, called 10 times per Update), and Input.GetKeyDown stays true for the
// whole frame of the press, so a press adds 0.2 m/s before each of the 10 substeps: 2 m/s.
#define CLI_SEEDS_JUMP_SPEED 0.2

// Step one frame. @p jumps impulses start in it: the seeds' jump steps the substeps one at a
// time with CLI_SEEDS_JUMP_SPEED added before each (the same dt as a whole frame); a custom
// --impulse-speed adds its velocity once at the start.
// Book a step's unconverged implicit solves.
static fmResult cliBookStep(const cliSimulation* sim, fmResult result, cliSolveTotals* totals)
{
	fmStepStats stats = fmWorld_GetStepStats(sim->world);
	totals->steps += stats.steps;
	totals->unconvergedSteps += stats.unconvergedSteps;
	if (stats.unconvergedSteps > 0)
		totals->maxResidual = fmax(totals->maxResidual, stats.maxResidual);
	int contacts = fmWorld_GetContacts(sim->world, NULL, 0);
	totals->maxContacts = contacts > totals->maxContacts ? contacts : totals->maxContacts;
	return result;
}

static fmResult cliStepFrame(const cliRunOptions* o, const cliScene* scene, cliSimulation* sim,
                             int jumps, cliSolveTotals* totals)
{
	double frameTime = cliScene_FrameTime(scene);
	if (sim->attachedCount > 0 && !cliAttachments_Update(sim, sim->time + frameTime))
		return fm_errParameter;
	sim->time += frameTime;
	if (jumps == 0 || o->hasImpulseSpeed)
	{
		for (int b = 0; b < sim->bodyCount && jumps > 0; ++b)
			fmBody_ApplyImpulse(sim->bodies[b], fmMakeVec3(0.0, jumps * o->impulseSpeed, 0.0));
		return cliBookStep(sim, fmWorld_Step(sim->world, frameTime, scene->substeps), totals);
	}
	double dt = frameTime / scene->substeps; // what fmWorld_Step divides a frame into
	for (int s = 0; s < scene->substeps; ++s)
	{
		for (int b = 0; b < sim->bodyCount; ++b)
			fmBody_ApplyImpulse(sim->bodies[b], fmMakeVec3(0.0, jumps * CLI_SEEDS_JUMP_SPEED, 0.0));
		fmResult result = cliBookStep(sim, fmWorld_Step(sim->world, dt, 1), totals);
		if (result != fm_ok)
			return result;
	}
	return fm_ok;
}

static void cliPrintAudit(const cliSimulation* sim, const cliSolveTotals* solves);

// Step @p frames frames with impulses, progress and output. Returns an exit code.
static int cliRunFrames(const cliRunOptions* o, const cliScene* scene, cliSimulation* sim,
                        cliSeries* series, cliVideo* video, int frames, double* stepSeconds,
                        double* lowestReached, cliSolveTotals* totals)
{
	*lowestReached = cliLowestY(sim);
	double frameTime = cliScene_FrameTime(scene);
	bool tty = cliStderrIsTty();
	bool progress = !o->quiet;
	double progressEvery = tty ? 0.2 : o->progressSeconds;
	double runStart = cliNow();
	bool applied[CLI_MAX_IMPULSES] = {false};
	double lastProgress = -1.0;
	*stepSeconds = 0.0;
	for (int frame = 0; frame < frames; ++frame)
	{
		double time = frame * frameTime;
		int jumps = 0;
		for (int k = 0; k < o->impulseCount; ++k)
		{
			// The first frame boundary at or after the requested time (tolerating rounding).
			if (applied[k] || o->impulseTimes[k] > time + 1e-9 * frameTime)
				continue;
			applied[k] = true;
			jumps += 1;
		}
		double start = cliNow();
		fmResult result = cliStepFrame(o, scene, sim, jumps, totals);
		*stepSeconds += cliNow() - start;
		*lowestReached = fmin(*lowestReached, cliLowestY(sim));
		if (result != fm_ok)
		{
			if (progress && tty)
				fputc('\n', stderr);
			const fmDiagnostic* diag = fmWorld_GetLastError(sim->world);
			char text[1024];
			fmDiagnostic_Format(diag, text, sizeof text);
			cliError("%s: step failed in frame %d (t = %.4g s): %s: %s", scene->name, frame + 1,
			         time, fmResultName(result), text);
			if (totals->audit && totals->audits > 0)
				cliPrintAudit(sim, totals); // what the frames before the failure showed
			return cli_exitInput;
		}
		if (series != NULL && (frame + 1) % o->every == 0 &&
		    !cliSeries_WriteFrame(series, sim, frame + 1, time + frameTime))
			return cli_exitInput;
		if (video != NULL && !cliVideo_Advance(video, sim, time + frameTime))
			return cli_exitInput;
		double now = cliNow();
		if (lastProgress < 0.0)
			lastProgress = runStart;
		// Off a terminal, the last frame gets no line: the summary follows at once.
		if (progress && (now - lastProgress > progressEvery || (tty && frame + 1 == frames)))
		{
			lastProgress = now;
			cliPrintProgress(frame + 1, frames, time + frameTime, sim, tty, now - runStart);
		}
	}
	if (progress && tty && frames > 0)
		fputc('\n', stderr);
	for (int k = 0; k < o->impulseCount; ++k)
		if (!applied[k])
			cliWarn("--impulse-at %g: after the end of the run (%g s); not applied",
			        o->impulseTimes[k], frames * frameTime);
	return cli_exitOk;
}

// Colliders listed in the summary at most (the rest are counted).
#define CLI_LISTED_COLLIDERS 8

static const char* cliShapeName(fmShapeType shape)
{
	static const char* const names[] = {"plane", "sphere", "box", "capsule", "mesh"};
	return shape >= 0 && shape < fm_shapeTypeCount ? names[shape] : "collider";
}

// When bodies touched the floor, colliders or each other during the run: the last substep's
// contacts, split by kind, and the force the bodies exert on the floor and on each collider
// (fmCollider_GetContactForce).
static void cliPrintContacts(const cliScene* scene, const cliSimulation* sim,
                             const cliSolveTotals* solves)
{
	if (solves->maxContacts == 0)
		return;
	int count = fmWorld_GetContacts(sim->world, NULL, 0);
	fmContactPoint* points = count > 0 ? malloc(sizeof *points * (size_t)count) : NULL;
	int withColliders = 0;
	if (points != NULL)
	{
		count = fmWorld_GetContacts(sim->world, points, count);
		for (int i = 0; i < count; ++i)
			withColliders += points[i].collider.index1 != 0;
	}
	free(points);
	printf("contacts         %d at the end (%d on colliders, %d between bodies); at most %d after "
	       "a step\n",
	       count, withColliders, count - withColliders, solves->maxContacts);
	fmColliderId floor = fmWorld_GetFloorCollider(sim->world);
	fmVec3 floorForce = {0.0, 0.0, 0.0};
	if (fmCollider_IsValid(floor))
		fmCollider_GetContactForce(floor, &floorForce, NULL);
	if (fmLength(floorForce) > 0.0)
		printf("floor            force %.4g N (%.4g, %.4g, %.4g)\n", fmLength(floorForce),
		       floorForce.x, floorForce.y, floorForce.z);
	for (int c = 0; c < sim->colliderCount && c < CLI_LISTED_COLLIDERS; ++c)
	{
		fmVec3 force, torque;
		fmCollider_GetContactForce(sim->colliders[c], &force, &torque);
		if (fmLength(force) > 0.0)
			printf("colliders[%d]     %s: force %.4g N (%.4g, %.4g, %.4g)\n", c,
			       cliShapeName(scene->colliders[c].def.shape), fmLength(force), force.x, force.y,
			       force.z);
	}
	if (scene->worldDef.contact.enableSleep)
	{
		int asleep = 0;
		for (int b = 0; b < sim->bodyCount; ++b)
			asleep += !fmBody_IsAwake(sim->bodies[b]);
		printf("asleep           %d of %d bod%s at the end\n", asleep, sim->bodyCount,
		       sim->bodyCount == 1 ? "y" : "ies");
	}
	if (sim->colliderCount > CLI_LISTED_COLLIDERS)
		printf("                 (%d more colliders)\n", sim->colliderCount - CLI_LISTED_COLLIDERS);
}

// The scene's index of body @p id (-1 when none).
static int cliBodyIndex(const cliSimulation* sim, fmBodyId id)
{
	for (int b = 0; b < sim->bodyCount; ++b)
		if (sim->bodies[b].index1 == id.index1 && id.index1 != 0)
			return b;
	return -1;
}

// --audit: the worst counts seen after any step, and the first finding.
static void cliPrintAudit(const cliSimulation* sim, const cliSolveTotals* solves)
{
	const fmContactAudit* w = &solves->worst;
	printf("contact audit    %d substeps: at worst %d crossings, %d self crossings, %d vertices "
	       "inside (deepest %.4g m), %d inverted tets\n",
	       solves->audits, w->crossings, w->selfCrossings, w->verticesInside, w->deepest,
	       w->invertedTets);
	if (solves->auditedFindings == 0)
		return;
	const fmContactAudit* f = &solves->first;
	printf("                 %d with findings, the first after substep %d:",
	       solves->auditedFindings, solves->firstFindingStep);
	if (f->firstCrossing.body.index1 != 0)
		printf(" bodies[%d] edge %d-%d crosses bodies[%d] triangle %d;",
		       cliBodyIndex(sim, f->firstCrossing.body), f->firstCrossing.vertex[0],
		       f->firstCrossing.vertex[1], cliBodyIndex(sim, f->firstCrossing.otherBody),
		       f->firstCrossing.index);
	if (f->firstSelfCrossing.body.index1 != 0)
		printf(" bodies[%d] edge %d-%d crosses its own triangle %d;",
		       cliBodyIndex(sim, f->firstSelfCrossing.body), f->firstSelfCrossing.vertex[0],
		       f->firstSelfCrossing.vertex[1], f->firstSelfCrossing.index);
	if (f->firstInside.body.index1 != 0)
		printf(" bodies[%d] vertex %d inside bodies[%d] (%.4g m);",
		       cliBodyIndex(sim, f->firstInside.body), f->firstInside.vertex[0],
		       cliBodyIndex(sim, f->firstInside.otherBody), f->firstInside.depth);
	if (f->firstInverted.body.index1 != 0)
		printf(" bodies[%d] tet %d inverted;", cliBodyIndex(sim, f->firstInverted.body),
		       f->firstInverted.index);
	printf("\n");
}

static void cliPrintSummary(const cliScene* scene, const cliSimulation* sim, int frames,
                            double wallSeconds, double stepSeconds, double lowestReached,
                            const cliSeries* series, const cliSolveTotals* solves)
{
	cliTotals totals = cliSumStats(sim);
	double steps = (double)solves->steps;
	double simulated = frames * cliScene_FrameTime(scene);
	printf("scene            %s (%d bod%s, %d tets, %s, %d worker%s)\n", scene->name,
	       sim->bodyCount, sim->bodyCount == 1 ? "y" : "ies", totals.tets,
	       scene->worldDef.integrator == fm_explicit ? "explicit" : "implicit",
	       scene->worldDef.workerCount, scene->worldDef.workerCount == 1 ? "" : "s");
	if (scene->worldDef.autoSubstep && scene->worldDef.integrator == fm_explicit)
		printf("frames           %d of %g s (automatic substeps: %lld in all, %.1f a frame)\n",
		       frames, cliScene_FrameTime(scene), solves->steps, frames > 0 ? steps / frames : 0.0);
	else
		printf("frames           %d (%d substep%s of %g s each)\n", frames, scene->substeps,
		       scene->substeps == 1 ? "" : "s", scene->dt);
	if (scene->worldDef.crossPlatformDeterminism)
		printf("determinism      cross-platform (femto's own log and pow: the same bits on any "
		       "machine)\n");
	printf("simulated time   %.6g s\n", simulated);
	printf("wall time        %.3f s (stepping %.3f s, %.2fx real time)\n", wallSeconds, stepSeconds,
	       stepSeconds > 0.0 ? simulated / stepSeconds : 0.0);
	printf("steps per second %.0f\n", stepSeconds > 0.0 ? steps / stepSeconds : 0.0);
	printf("lowest vertex y  %.6g m\n", totals.lowestY);
	printf("lowest y reached %.6g m (after any frame)\n", lowestReached);
	printf("centre of mass y %.6g m\n", cliCenterOfMassY(sim));
	printf("kinetic energy   %.6g J\n", totals.kinetic);
	printf("elastic energy   %.6g J\n", totals.elastic);
	printf("inverted tets    %d\n", totals.inverted);
	for (int b = 0; b < sim->bodyCount; ++b)
		if (fmBody_GetBrokenFaceCount(sim->bodies[b]) > 0)
			printf("bodies[%d] torn   %d faces broken, %d pieces, %d vertices\n", b,
			       fmBody_GetBrokenFaceCount(sim->bodies[b]),
			       fmBody_GetPieces(sim->bodies[b], NULL), fmBody_GetVertexCount(sim->bodies[b]));
	for (int b = 0; b < sim->bodyCount; ++b)
	{
		fmBodyStats s = fmBody_GetStats(sim->bodies[b]);
		if (s.plasticWork > 0.0)
			printf("bodies[%d]        plastic work %.6g J, largest plastic strain %.6g\n", b,
			       s.plasticWork, s.plasticStrain);
	}
	if (scene->worldDef.integrator == fm_implicit && solves->unconvergedSteps == 0)
		printf("implicit solves  every step converged (tolerance %g)\n", scene->worldDef.tolerance);
	else if (scene->worldDef.integrator == fm_implicit)
		printf("implicit solves  %d steps ended above the tolerance %g (largest residual %.3g)\n",
		       solves->unconvergedSteps, scene->worldDef.tolerance, solves->maxResidual);
	cliPrintContacts(scene, sim, solves);
	if (solves->audit)
		cliPrintAudit(sim, solves);
	if (series != NULL)
		printf("output           %s (%d frames)\n", series->pvdPath, series->written);
}

static void cliPrintPictures(const cliViewOptions* v, int pictures)
{
	if (v->gifPath != NULL)
		printf("gif              %s (%d pictures, %dx%d, %g a second)\n", v->gifPath, pictures,
		       v->width, v->height, v->fps);
	if (v->pngDirectory != NULL)
		printf("png              %s/frame_0000.png ... frame_%04d.png (%dx%d)\n", v->pngDirectory,
		       pictures > 0 ? pictures - 1 : 0, v->width, v->height);
}

int cliRun(int argc, char** argv)
{
	cliRunOptions o;
	int code = cliParseRunOptions(argc, argv, &o);
	if (code >= 0)
		return code;
	double wallStart = cliNow();
	cliScene scene;
	if (o.scenePath == NULL)
		cliScene_MakeHouse(&scene);
	else if (!cliScene_Load(o.scenePath, &scene))
		return cli_exitInput;
	if (o.strict)
		scene.worldDef.notConvergedIsError = true;
	if (o.deterministic)
		scene.worldDef.crossPlatformDeterminism = true;
	if (o.workers > 0)
		scene.worldDef.workerCount = o.workers;
	else if (!scene.hasWorkers)
		scene.worldDef.workerCount = cliCoresAvailable();
	if (o.simd != NULL)
		fmSimdLevelFromName(o.simd, &scene.worldDef.simd);
	cliSimulation sim;
	cliSolveTotals solves = {.audit = o.audit};
	cliAuditHook hook = {&sim, &solves};
	cliInstallAudit(&scene, &hook);
	if (scene.bodies == NULL ||
	    !cliSimulation_Create(&scene, o.quiet ? cli_stepCheckWarnings : cli_stepCheckAll, &sim))
	{
		cliScene_Free(&scene);
		return cli_exitInput;
	}
	int frames = cliFrameCount(&o, &scene);
	cliSeries series;
	cliSeries* seriesPtr = NULL;
	code = frames >= 0 ? cli_exitOk : cli_exitInput;
	if (o.outDir != NULL && code == cli_exitOk)
	{
		char name[256];
		cliSeriesName(o.scenePath, name, sizeof name);
		seriesPtr = &series;
		if (!cliSeries_Open(&series, o.outDir, name, o.obj, o.vtuAscii))
			code = cli_exitInput;
		else if (series.removed > 0 && !o.quiet)
			fprintf(stderr,
			        "femto: note: removed %d file%s of an earlier '%s' series from %s (%s.pvd, "
			        "%s_NNNNNN.vtu/.obj)\n",
			        series.removed, series.removed == 1 ? "" : "s", name, o.outDir, name, name);
		if (code == cli_exitOk && !cliSeries_WriteFrame(&series, &sim, 0, 0.0))
			code = cli_exitInput;
	}
	cliVideo* video = NULL;
	cliViewOptions_TakeCamera(&o.view, &scene.camera); // the scene's "camera" where not given
	if (code == cli_exitOk && cliViewOptions_WantsImages(&o.view) &&
	    (video = cliVideo_Open(&o.view, &sim)) == NULL)
		code = cli_exitInput;
	double stepSeconds = 0.0, lowestReached = 0.0;
	if (code == cli_exitOk)
		code = cliRunFrames(&o, &scene, &sim, seriesPtr, video, frames, &stepSeconds,
		                    &lowestReached, &solves);
	int pictures = cliVideo_FrameCount(video);
	if (!cliVideo_Close(video, code == cli_exitOk) && code == cli_exitOk)
		code = cli_exitInput;
	// The collection is complete after every frame (rewritten whole each time), so the frames
	// written before a failure or an interruption stay viewable.
	if (seriesPtr != NULL)
		cliSeries_Free(&series);
	if (code == cli_exitOk && o.exportNode != NULL && !cliWriteNodes(o.exportNode, &sim, false))
		code = cli_exitInput;
	if (code == cli_exitOk && o.exportObj != NULL && !cliWriteObj(o.exportObj, &sim))
		code = cli_exitInput;
	if (code == cli_exitOk)
	{
		cliPrintSummary(&scene, &sim, frames, cliNow() - wallStart, stepSeconds, lowestReached,
		                seriesPtr, &solves);
		cliPrintPictures(&o.view, pictures);
	}
	cliSimulation_Destroy(&sim);
	cliScene_Free(&scene);
	return code;
}
