// libFuzzer entry for the simulation: a small body (at most 64 nodes and 128 tets) built from the
// fuzzer's bytes, with a fuzzed material, force model, mass, damping, floor, gravity and pins,
// takes a few frames with each integrator (switched between frames) and a short static solve.
// Any failure must come back as a result code: never a crash, hang, leak, assert or undefined
// behaviour; and a body is never left non-finite: after every step and static solve, whatever it
// returned, its positions, velocities and energies are finite (a failed step restores the last
// good state), or the fuzzer traps. Input: a header of structured values (fuzz_reader.h), then the
// mesh as raw nodes and tets, a generated box, or TetGen text ("<node text>\n%%\n<ele text>").
#include "fuzz_reader.h"

#include <femto/femto.h>

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

enum
{
	fuzz_maxNodes = 64,
	fuzz_maxTets = 128,
};

// Nodes in [-2, 2]^3 and tets of any 4 of them (out-of-range and repeated nodes included, which
// validation must catch).
static void fuzzRawMesh(fmFuzzReader* r, fmTetMesh* mesh, double* positions, int* tets)
{
	memset(mesh, 0, sizeof *mesh);
	mesh->nodeCount = 4 + fmFuzzPick(r, fuzz_maxNodes - 3);
	mesh->tetCount = 1 + fmFuzzPick(r, fuzz_maxTets);
	mesh->positions = positions;
	mesh->tets = tets;
	for (int k = 0; k < 3 * mesh->nodeCount; ++k)
		positions[k] = fmFuzzDouble(r, -2.0, 2.0);
	for (int k = 0; k < 4 * mesh->tetCount; ++k)
		tets[k] = fmFuzzPick(r, mesh->nodeCount + 1) - (k % 16 == 15);
}

// A box of up to 3 x 3 x 2 cubes (108 tets, 48 nodes), its nodes moved by a fuzzed amount.
static bool fuzzBoxMesh(fmFuzzReader* r, fmTetMesh* mesh)
{
	int nx = 1 + fmFuzzPick(r, 3), ny = 1 + fmFuzzPick(r, 3), nz = 1 + fmFuzzPick(r, 2);
	fmVec3 size = fmMakeVec3(fmFuzzDouble(r, 0.05, 3.0), fmFuzzDouble(r, 0.05, 3.0),
	                         fmFuzzDouble(r, 0.05, 3.0));
	if (fmMakeBoxMesh(nx, ny, nz, fmMakeVec3(0, 0, 0), size, mesh) != fm_ok)
		return false;
	double jitter = fmFuzzDouble(r, 0.0, 0.5);
	for (int k = 0; k < 3 * mesh->nodeCount && r->at < r->size; ++k)
		mesh->positions[k] += jitter * (fmFuzzByte(r) / 127.5 - 1.0);
	return true;
}

// The rest of the input as TetGen text; meshes beyond the bounds are skipped.
static bool fuzzTetGenMesh(fmFuzzReader* r, fmTetMesh* mesh)
{
	const char* text = (const char*)r->data + r->at;
	size_t size = r->size - r->at;
	r->at = r->size;
	for (size_t i = 0; i + 3 <= size; ++i)
		if (text[i] == '%' && text[i + 1] == '%' && text[i + 2] == '\n')
		{
			if (fmLoadTetGenFromMemory(text, i, "fuzz.node", text + i + 3, size - i - 3, "fuzz.ele",
			                           mesh, NULL) != fm_ok)
				return false;
			if (mesh->nodeCount <= fuzz_maxNodes && mesh->tetCount <= fuzz_maxTets)
				return true;
			fmFreeTetMesh(mesh);
			return false;
		}
	return false;
}

static fmMaterial fuzzMaterial(fmFuzzReader* r)
{
	fmMaterialModel model = (fmMaterialModel)fmFuzzPick(r, fm_materialModelCount);
	double youngs = pow(10.0, fmFuzzDouble(r, 1.0, 7.0));
	double poisson = fmFuzzDouble(r, -0.5, 0.499);
	fmMaterial material = fmMakeMaterial(model, youngs, poisson);
	if (model == fm_mooneyRivlin)
		material.c01 = fmFuzzDouble(r, 0.0, 0.5) * material.mu;
	material.stretchEnergy = fmFuzzStretchEnergy;
	material.invariantEnergy = fmFuzzInvariantEnergy;
	return material;
}

static fmWorldDef fuzzWorldDef(fmFuzzReader* r)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.gravity = fmFuzzVec3(r, -20.0, 20.0);
	uint8_t floorBits = fmFuzzByte(r);
	def.floor.enabled = floorBits & 1;
	def.floor.friction = (floorBits & 2) ? fm_floorCoulomb : fm_floorStick;
	def.floor.height = fmFuzzDouble(r, -3.0, 1.0);
	def.floor.frictionCoefficient = fmFuzzDouble(r, 0.0, 2.0);
	def.floor.restitution = fmFuzzDouble(r, 0.0, 1.0);
	def.integrator = fmFuzzPick(r, 2) ? fm_implicit : fm_explicit;
	// Bounded solver work keeps the fuzzer fast; the limits themselves are fuzzed by fuzz_api.
	def.newtonIterations = 1 + fmFuzzPick(r, 8);
	def.cgIterations = 1 + fmFuzzPick(r, 100);
	def.tolerance = pow(10.0, -fmFuzzDouble(r, 1.0, 10.0));
	return def;
}

static fmBodyDef fuzzBodyDef(fmFuzzReader* r)
{
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fuzzMaterial(r);
	def.forceModel = (fmForceModel)fmFuzzPick(r, fm_forceModelCount);
	def.massMode = fmFuzzPick(r, 2) ? fm_massFromDensity : fm_massPerParticle;
	def.density = fmFuzzDouble(r, 1.0, 5000.0);
	def.particleMass = fmFuzzDouble(r, 0.01, 10.0);
	def.damping = fmFuzzDouble(r, 0.9, 1.0);
	def.smoothing = fmFuzzDouble(r, 0.0, 1.0);
	def.rayleighMass = fmFuzzPick(r, 4) == 0 ? fmFuzzDouble(r, 0.0, 10.0) : 0.0;
	def.rayleighStiffness = fmFuzzPick(r, 4) == 0 ? fmFuzzDouble(r, 0.0, 0.1) : 0.0;
	def.springDamping = fmFuzzDouble(r, 0.0, 1.0);
	return def;
}

// Vectors handed to calls on a live body: NaN there is a programmer error (fuzz_api's domain),
// huge and infinite values are not.
static fmVec3 fuzzVector(fmFuzzReader* r, double lo, double hi)
{
	fmVec3 v = fmFuzzVec3(r, lo, hi);
	return fmMakeVec3(isnan(v.x) ? 0.0 : v.x, isnan(v.y) ? 0.0 : v.y, isnan(v.z) ? 0.0 : v.z);
}

// Traps (a crash the fuzzer and the replay report) when the body's state is not finite.
static void checkFinite(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	double* state = malloc(sizeof(double) * 6 * (size_t)n);
	if (state == NULL)
		return;
	if (fmBody_CopyPositions(body, state, n) != fm_ok ||
	    fmBody_CopyVelocities(body, state + 3 * (size_t)n, n) != fm_ok)
		__builtin_trap();
	for (size_t k = 0; k < 6 * (size_t)n; ++k)
		if (!isfinite(state[k]))
			__builtin_trap();
	free(state);
	fmBodyStats stats = fmBody_GetStats(body);
	if (!isfinite(stats.kineticEnergy) || !isfinite(stats.elasticEnergy) ||
	    !isfinite(stats.centerOfMass.x + stats.centerOfMass.y + stats.centerOfMass.z))
		__builtin_trap();
}

// Pins, rollers and a pin box, a kick; then frames with each integrator and a static solve.
static void fuzzRun(fmFuzzReader* r, fmWorldId world, fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	int pins = fmFuzzPick(r, 4);
	for (int p = 0; p < pins; ++p)
		fmBody_SetPinnedAxes(body, fmFuzzPick(r, n), (unsigned)fmFuzzPick(r, 8));
	if (fmFuzzPick(r, 4) == 0)
	{
		fmVec3 lo = fuzzVector(r, -2.0, 2.0), size = fuzzVector(r, 0.0, 2.0);
		fmVec3 hi = fmMakeVec3(lo.x + size.x, lo.y + size.y, lo.z + size.z); // -inf + inf: NaN
		fmBody_PinBox(body, lo,
		              fmMakeVec3(isnan(hi.x) ? 0.0 : hi.x, isnan(hi.y) ? 0.0 : hi.y,
		                         isnan(hi.z) ? 0.0 : hi.z));
	}
	fmVec3 kick = fuzzVector(r, -5.0, 5.0), vertexKick = fuzzVector(r, -50.0, 50.0);
	// Infinite kicks are finite-checked too (an infinite velocity is no velocity).
	if (isfinite(kick.x + kick.y + kick.z))
		fmBody_ApplyImpulse(body, kick);
	if (isfinite(vertexKick.x + vertexKick.y + vertexKick.z))
		fmBody_ApplyVertexImpulse(body, fmFuzzPick(r, n), vertexKick);

	static const double s_steps[] = {1e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1};
	int frames = 1 + fmFuzzPick(r, 3);
	for (int pass = 0; pass < 2; ++pass)
	{
		for (int f = 0; f < frames; ++f)
		{
			double dt = s_steps[fmFuzzPick(r, 6)];
			fmWorld_Step(world, dt, 1 + fmFuzzPick(r, 3));
			checkFinite(body);
			(void)fmWorld_GetLastError(world);
			(void)fmWorld_GetStepStats(world);
		}
		fmBodyStats stats = fmBody_GetStats(body);
		(void)stats;
		fmIntegrator next =
		    fmWorld_GetStepStats(world).newtonIterations > 0 ? fm_explicit : fm_implicit;
		fmWorld_SetIntegrator(world, pass == 0 ? next : fm_implicit);
	}
	if (fmFuzzPick(r, 2))
	{
		double residual;
		fmBody_SolveStatic(body, pow(10.0, -fmFuzzDouble(r, 1.0, 10.0)), 1 + fmFuzzPick(r, 5),
		                   &residual, NULL);
		checkFinite(body);
	}
	double forces[3 * fuzz_maxNodes];
	if (n <= fuzz_maxNodes)
		fmBody_ComputeElasticForces(body, forces);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzReader reader = {data, size, 0};
	fmFuzzReader* r = &reader;
	fmWorldDef worldDef = fuzzWorldDef(r);
	fmBodyDef bodyDef = fuzzBodyDef(r);
	double positions[3 * fuzz_maxNodes];
	int tets[4 * fuzz_maxTets];
	fmTetMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	bool owned = false; // the mesh's arrays are femto's (box, TetGen), not the stack's
	switch (fmFuzzPick(r, 3))
	{
	case 0:
		fuzzRawMesh(r, &mesh, positions, tets);
		break;
	case 1:
		owned = fuzzBoxMesh(r, &mesh);
		if (!owned)
			return 0;
		break;
	default:
		owned = fuzzTetGenMesh(r, &mesh);
		if (!owned)
			return 0;
		break;
	}
	bodyDef.mesh = &mesh;
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyId body;
	if (fmWorld_IsValid(world) && fmCreateBody(world, &bodyDef, &body, NULL) == fm_ok)
		fuzzRun(r, world, body);
	if (fmWorld_IsValid(world))
		fmDestroyWorld(world);
	if (owned)
		fmFreeTetMesh(&mesh);
	return 0;
}
