// The simulation of `femto view` (session.h).
#include "session.h"

#include "scene_body.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The seeds' jump: m/s added before each substep of the frame (cli/cmd_run.c, docs/cli.md).
#define FV_JUMP_SPEED 0.2

// Most scene frames one Advance steps (a slow frame must not snowball).
#define FV_MAX_FRAMES_PER_ADVANCE 8

// Young's modulus and Poisson ratio of Lamé constants (the inverse of fmMakeMaterial's).
static void fvFromLame(double lambda, double mu, double* youngs, double* poisson)
{
	*youngs = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
	*poisson = lambda / (2.0 * (lambda + mu));
}

static bool fvIsAnisotropic(fmMaterialModel model)
{
	return model == fm_orthotropicLinear || model == fm_orthotropicStvk ||
	       model == fm_fibreNeoHookean;
}

// Body @p b's material under the sliders: an isotropic model from Young's modulus and Poisson's
// ratio (with the scene's plasticity and fracture); while the sliders keep a scene's anisotropic
// model, each body's own scene material with every modulus scaled by the Young's slider over its
// start, its ratios and axes kept.
static fmMaterial fvSliderMaterial(const fvSession* s, int b)
{
	const fvParams* p = &s->params;
	const fmMaterial* scene = &s->scene.bodies[b].def.material;
	if (!fvIsAnisotropic(p->model))
	{
		// The scene's plasticity stays with the models it goes with (not linear), its nodal
		// pressure with the models whose volume term it can move.
		fmMaterial m = fmMakeMaterial(p->model, p->youngs, p->poisson);
		if (p->model != fm_linear)
			m.plasticity = scene->plasticity;
		m.fracture = scene->fracture; // (every model tears)
		return cliKeepNodalPressure(m, scene->nodalPressure);
	}
	fmMaterial m = *scene;
	double k = p->youngs / p->startYoungs;
	for (int e = 0; e < 3; ++e)
	{
		m.orthotropy.E[e] *= k;
		m.orthotropy.G[e] *= k;
	}
	m.lambda *= k;
	m.mu *= k;
	m.c01 *= k;
	m.fibreStiffness *= k;
	return m;
}

// The sliders start at the scene's first body and world.
static void fvInitParams(fvSession* s)
{
	const fmBodyDef* def = &s->scene.bodies[0].def;
	fvParams* p = &s->params;
	p->model = def->material.model;
	if (p->model >= fm_stretchEnergy && !fvIsAnisotropic(p->model))
		p->model = fm_neoHookean;
	fvFromLame(def->material.lambda, def->material.mu, &p->youngs, &p->poisson);
	p->startYoungs = p->youngs;
	p->startPoisson = p->poisson;
	p->perParticle = def->massMode == fm_massPerParticle;
	p->mass = p->perParticle ? def->particleMass : def->density;
	p->damping = def->damping;
	p->dt = s->scene.dt;
	p->substeps = s->scene.substeps;
	p->integrator = s->scene.worldDef.integrator;
	s->explicitDt = 0.0, s->explicitSubsteps = 0;
}

bool fvSession_Load(fvSession* s, const char* path)
{
	memset(s, 0, sizeof *s);
	snprintf(s->path, sizeof s->path, "%s", path != NULL ? path : "");
	if (path == NULL)
		cliScene_MakeHouse(&s->scene);
	else if (!cliScene_Load(path, &s->scene))
		return false;
	if (!s->scene.hasWorkers)
		s->scene.worldDef.workerCount = cliCoresAvailable();
	if (s->scene.bodies == NULL || !cliSimulation_Create(&s->scene, cli_stepCheckWarnings, &s->sim))
	{
		cliScene_Free(&s->scene);
		memset(s, 0, sizeof *s);
		return false;
	}
	fvInitParams(s);
	return true;
}

void fvSession_Free(fvSession* s)
{
	if (s->scene.bodies != NULL)
	{
		cliSimulation_Destroy(&s->sim);
		cliScene_Free(&s->scene);
	}
	memset(s, 0, sizeof *s);
}

// The scene's body definitions with the sliders' values.
static fmBodyDef fvBodyDef(const fvSession* s, int b)
{
	fmBodyDef def = s->scene.bodies[b].def;
	def.mesh = &s->sim.meshes[b];
	def.material = fvSliderMaterial(s, b);
	def.massMode = s->params.perParticle ? fm_massPerParticle : fm_massFromDensity;
	if (s->params.perParticle)
		def.particleMass = s->params.mass;
	else
		def.density = s->params.mass;
	def.damping = s->params.damping;
	return def;
}

bool fvSession_Reset(fvSession* s)
{
	fvSession_Release(s);
	cliSimulation_Destroy(&s->sim);
	if (!cliSimulation_Create(&s->scene, cli_stepCheckOff, &s->sim))
	{
		snprintf(s->status, sizeof s->status, "reset: cannot re-create the scene (see stderr)");
		return false;
	}
	fvSession_ApplyIntegrator(s);
	s->frames = 0;
	s->overBudgetFrames = 0;
	s->historyCount = 0, s->historyNext = 0;
	s->accumulator = 0.0;
	s->status[0] = 0;
	// The initial state with the current sliders: the bodies are made again from them.
	return fvSession_ApplyBodies(s) && fvSession_ApplyMaterial(s);
}

// Step one scene frame: whole, or substep by substep with the jump's impulses.
static fmResult fvStepFrame(fvSession* s)
{
	double frameTime = s->params.dt * s->params.substeps;
	if (s->pendingJumps == 0)
		return fmWorld_Step(s->sim.world, frameTime, s->params.substeps);
	fmVec3 kick = fmMakeVec3(0.0, s->pendingJumps * FV_JUMP_SPEED, 0.0);
	s->pendingJumps = 0;
	for (int k = 0; k < s->params.substeps; ++k)
	{
		for (int b = 0; b < s->sim.bodyCount; ++b)
			fmBody_ApplyImpulse(s->sim.bodies[b], kick);
		fmResult result = fmWorld_Step(s->sim.world, s->params.dt, 1);
		if (result != fm_ok)
			return result;
	}
	return fm_ok;
}

// One frame with its bookkeeping; a failed step pauses with the library's diagnostic.
static void fvFrame(fvSession* s)
{
	double start = cliNow();
	fmResult result = fvStepFrame(s);
	s->stepMs = 1e3 * (cliNow() - start);
	s->overBudget = s->stepMs > FV_STEP_SHARE_MS;
	s->stepHistory[s->historyNext] = (float)s->stepMs;
	s->historyNext = (s->historyNext + 1) % FV_PROFILE_FRAMES;
	s->historyCount += s->historyCount < FV_PROFILE_FRAMES;
	s->overBudgetFrames += s->overBudget;
	s->stats = fmWorld_GetStepStats(s->sim.world);
	s->profile = fmWorld_GetProfile(s->sim.world);
	s->frames += 1;
	if (result != fm_ok)
	{
		char text[1024];
		fmDiagnostic_Format(fmWorld_GetLastError(s->sim.world), text, sizeof text);
		snprintf(s->status, sizeof s->status, "step failed (%s): %s; paused, R resets",
		         fmResultName(result), text);
		s->paused = true;
	}
}

bool fvSession_IsLive(const fvSession* s)
{
	return fmWorld_IsValid(s->sim.world);
}

void fvSession_Advance(fvSession* s, double seconds)
{
	if (!fvSession_IsLive(s))
		return;
	if (s->paused)
	{
		s->accumulator = 0.0;
		for (; s->pendingSteps > 0; --s->pendingSteps)
			fvFrame(s);
		return;
	}
	s->pendingSteps = 0;
	s->accumulator += seconds;
	int frames = 0;
	// A hair of slack so ticks of exactly FV_TICK_SECONDS are never one short from rounding.
	while (s->accumulator >= FV_TICK_SECONDS - 1e-9 && frames < FV_MAX_FRAMES_PER_ADVANCE &&
	       !s->paused)
	{
		s->accumulator -= FV_TICK_SECONDS;
		fvFrame(s);
		frames += 1;
	}
	if (frames == FV_MAX_FRAMES_PER_ADVANCE)
		s->accumulator = 0.0;
}

void fvSession_Jump(fvSession* s)
{
	s->pendingJumps += 1;
}

bool fvSession_ApplyMaterial(fvSession* s)
{
	if (!fvSession_IsLive(s))
		return false;
	if (fvIsAnisotropic(s->params.model) && s->params.poisson != s->params.startPoisson)
	{
		snprintf(s->status, sizeof s->status,
		         "the Poisson slider sets isotropic materials: %s takes its ratios from the "
		         "scene (press m for an isotropic model)",
		         fmMaterialModelName(s->params.model));
		return false;
	}
	for (int b = 0; b < s->sim.bodyCount; ++b)
	{
		fmMaterial material = fvSliderMaterial(s, b);
		fmDiagnostic diag;
		memset(&diag, 0, sizeof diag);
		if (fmBody_SetMaterial(s->sim.bodies[b], &material, &diag) != fm_ok)
		{
			char text[600];
			snprintf(s->status, sizeof s->status, "material rejected: %s",
			         fmDiagnostic_Format(&diag, text, sizeof text));
			return false;
		}
	}
	return true;
}

// Re-create body @p b from the sliders, in its current state. The new body is made before the
// old one goes, so a refusal (memory budget) leaves the old one in place.
static bool fvRecreateBody(fvSession* s, int b)
{
	fmBodyId old = s->sim.bodies[b], made;
	double* x = cliCopyState(old, false);
	double* v = cliCopyState(old, true);
	fmBodyDef def = fvBodyDef(s, b);
	char problem[256];
	fmVec3* fibres = cliBodyFibres(&s->scene.bodies[b], def.mesh, problem, sizeof problem);
	def.tetFibres = fibres; // the scene's "fibres" (its mesh was loaded before: no problem left)
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	bool ok = x != NULL && v != NULL && problem[0] == 0 &&
	          fmCreateBody(s->sim.world, &def, &made, &diag) == fm_ok;
	free(fibres);
	if (ok)
	{
		fmDestroyBody(old);
		s->sim.bodies[b] = made;
		const cliBodySpec* spec = &s->scene.bodies[b];
		for (int p = 0; p < spec->pinCount; ++p)
			fmBody_PinBox(made, spec->pins[p].min, spec->pins[p].max);
		fmBody_SetPositions(made, x);
		fmBody_SetVelocities(made, v);
	}
	else
	{
		char text[600];
		snprintf(s->status, sizeof s->status, "body %d rejected: %s", b,
		         x && v ? fmDiagnostic_Format(&diag, text, sizeof text) : "out of memory");
	}
	free(x);
	free(v);
	return ok;
}

bool fvSession_ApplyBodies(fvSession* s)
{
	if (!fvSession_IsLive(s))
		return false;
	fvSession_Release(s);
	for (int b = 0; b < s->sim.bodyCount; ++b)
		if (!fvRecreateBody(s, b))
			return false;
	return true;
}

void fvSession_SwitchIntegrator(fvSession* s, fmIntegrator integrator)
{
	fvParams* p = &s->params;
	if (p->integrator == integrator)
		return;
	double frame = p->dt * p->substeps;
	p->integrator = integrator;
	fvSession_ApplyIntegrator(s);
	if (integrator == fm_implicit)
	{
		s->explicitDt = p->dt, s->explicitSubsteps = p->substeps;
		p->dt = frame, p->substeps = 1;
		return;
	}
	if (s->explicitSubsteps > 0 &&
	    fabs(s->explicitDt * s->explicitSubsteps - frame) <= 1e-9 * frame)
	{
		p->dt = s->explicitDt, p->substeps = s->explicitSubsteps;
		return;
	}
	double limit = fvSession_IsLive(s) ? fmWorld_EstimateExplicitStep(s->sim.world) : 0.0;
	double count = limit > 0.0 ? ceil(frame / (0.9 * limit)) : 1.0;
	p->substeps = (int)fmin(fmax(count, 1.0), 1000.0);
	p->dt = frame / p->substeps;
}

void fvSession_ApplyIntegrator(fvSession* s)
{
	if (!fvSession_IsLive(s))
		return;
	fmWorld_SetIntegrator(s->sim.world, s->params.integrator);
}

bool fvSession_Grab(fvSession* s, fmVec3 origin, fmVec3 translation, fmVec3* point)
{
	fvSession_Release(s);
	if (!fvSession_IsLive(s))
		return false;
	fmGrabDef def = fmDefaultGrabDef();
	fmRayHit hit;
	if (!fmWorld_GrabRay(s->sim.world, origin, translation, fmDefaultFilter(), &def, &hit))
	{
		if (fmBody_IsValid(hit.body))
		{
			char text[600];
			snprintf(s->status, sizeof s->status, "grab refused: %s",
			         fmDiagnostic_Format(fmWorld_GetLastError(s->sim.world), text, sizeof text));
		}
		return false;
	}
	s->dragBody = fvSession_BodyIndex(s, hit.body);
	s->dragging = s->dragBody >= 0;
	*point = hit.point;
	return s->dragging;
}

void fvSession_MoveGrab(fvSession* s, fmVec3 target)
{
	if (s->dragging)
		fmBody_MoveGrab(s->sim.bodies[s->dragBody], target);
}

void fvSession_Release(fvSession* s)
{
	if (!s->dragging)
		return;
	if (fmBody_IsValid(s->sim.bodies[s->dragBody]))
		fmBody_ReleaseGrab(s->sim.bodies[s->dragBody]);
	s->dragging = false;
}

int fvSession_BodyIndex(const fvSession* s, fmBodyId body)
{
	for (int b = 0; b < s->sim.bodyCount; ++b)
		if (s->sim.bodies[b].index1 == body.index1 &&
		    s->sim.bodies[b].generation == body.generation)
			return b;
	return -1;
}
