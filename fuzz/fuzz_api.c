// libFuzzer entry for the C API's def structs and argument checks: fmWorldDef, fmBodyDef (with
// its fmTetMesh) and fmMaterial filled from the fuzzer's bytes, whole or field by field, go
// through Validate and Create; whatever is created takes a step, then public calls get fuzzed
// arguments (vertex indices, vectors, floors, materials, integrators, stale ids). The assert
// hook counts instead of aborting: a programmer error must come back as a safe result.
// What the harness keeps consistent (the API cannot check it): pointers point to real arrays,
// and a count within the limits never exceeds the array behind it.
#include "fuzz_reader.h"

#include <femto/femto.h>

#include "world/snapshot.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

enum
{
	fuzz_maxNodes = 64,
	fuzz_maxTets = 128,
};

static int s_asserts;

static int fuzzAssert(const char* condition, const char* fileName, int lineNumber)
{
	(void)condition;
	(void)fileName;
	(void)lineNumber;
	++s_asserts;
	return 0;
}

// A count as fuzzed, but within the array's @p capacity unless it is beyond @p limit or not
// positive (those the API rejects without reading the array).
static int fuzzCount(int value, int capacity, int limit)
{
	if (value <= 0 || value > limit)
		return value;
	return 1 + (value - 1) % capacity;
}

// A mesh struct of fuzzed bytes over fixed arrays (valid pointers or NULL).
static void fuzzMesh(fmFuzzReader* r, fmTetMesh* mesh, double* positions, int* tets)
{
	uint8_t how = fmFuzzByte(r);
	if (how & 1)
	{
		// Counts and numbering raw, arrays from the input.
		fmFuzzBytes(r, mesh, sizeof *mesh);
		mesh->nodeCount = fuzzCount(mesh->nodeCount, fuzz_maxNodes, FM_MAX_NODES);
		mesh->tetCount = fuzzCount(mesh->tetCount, fuzz_maxTets, FM_MAX_TETS);
	}
	else
	{
		memset(mesh, 0, sizeof *mesh);
		mesh->nodeCount = 4 + fmFuzzPick(r, fuzz_maxNodes - 3);
		mesh->tetCount = 1 + fmFuzzPick(r, fuzz_maxTets);
		mesh->firstIndex = fmFuzzPick(r, 8) == 0 ? (int)fmFuzzByte(r) - 128 : fmFuzzPick(r, 2);
	}
	mesh->positions = (how & 2) ? NULL : positions;
	mesh->tets = (how & 4) ? NULL : tets;
	mesh->nodeAttributes = NULL;
	mesh->nodeMarkers = NULL;
	mesh->tetAttributes = NULL;
	for (int k = 0; k < 3 * fuzz_maxNodes; ++k)
		positions[k] = (how & 8) ? fmFuzzDouble(r, -2.0, 2.0) : (fmFuzzByte(r) - 128) / 64.0;
	int nodes = mesh->nodeCount > 0 && mesh->nodeCount <= fuzz_maxNodes ? mesh->nodeCount : 4;
	for (int k = 0; k < 4 * fuzz_maxTets; ++k)
		tets[k] = (how & 16) ? (int)fmFuzzByte(r) - 2 : fmFuzzPick(r, nodes);
}

// Whole struct from raw bytes, or the default with some fields replaced. Returns true when the
// caller should keep the default's magic (internalValue) as well.
static bool fuzzStruct(fmFuzzReader* r, void* def, size_t size, const void* defaults)
{
	uint8_t how = fmFuzzByte(r);
	memcpy(def, defaults, size);
	if (how & 1)
		fmFuzzBytes(r, def, size);
	else
	{
		// Overwrite a few 8-byte-aligned words with fuzzed doubles or raw bytes.
		int words = fmFuzzPick(r, 6);
		for (int w = 0; w < words; ++w)
		{
			size_t at = 8 * (size_t)fmFuzzPick(r, (int)(size / 8));
			double value = fmFuzzDouble(r, -10.0, 10.0);
			if (at + sizeof value <= size)
				memcpy((uint8_t*)def + at, &value, sizeof value);
		}
	}
	return (how & 6) != 6;
}

// A bool holds 0 or 1: any other byte in one is undefined behaviour in the caller, not an input
// the library could check.
static void fuzzFixBool(bool* value)
{
	uint8_t byte;
	memcpy(&byte, value, 1);
	*value = byte & 1;
}

static void fuzzFixFloor(fmFloorDef* floor)
{
	fuzzFixBool(&floor->enabled);
}

static fmMaterial fuzzMaterial(fmFuzzReader* r)
{
	fmMaterial material = fmMakeMaterialLame(fm_stvk, 20000.0, 5000.0);
	fmMaterial defaults = material;
	fuzzStruct(r, &material, sizeof material, &defaults);
	uint8_t energies = fmFuzzByte(r);
	material.stretchEnergy = (energies & 1) ? fmFuzzStretchEnergy : NULL;
	material.invariantEnergy = (energies & 2) ? fmFuzzInvariantEnergy : NULL;
	material.userParams = NULL;
	fuzzFixBool(&material.nodalPressure);
	return material;
}

static fmWorldDef fuzzWorldDef(fmFuzzReader* r)
{
	fmWorldDef defaults = fmDefaultWorldDef();
	fmWorldDef def;
	if (fuzzStruct(r, &def, sizeof def, &defaults))
		def.internalValue = defaults.internalValue;
	fuzzFixFloor(&def.floor);
	fuzzFixBool(&def.notConvergedIsError);
	fuzzFixBool(&def.autoSubstep);
	fuzzFixBool(&def.crossPlatformDeterminism);
	fuzzFixBool(&def.contact.bodies);
	fuzzFixBool(&def.contact.enableSleep);
	// Pointers no API can check: the task callbacks are the engine's, never fuzzed bytes; and a
	// few workers at most per input (threads are started per world).
	def.enqueueTask = NULL;
	def.finishTask = NULL;
	def.userTaskContext = NULL;
	def.substepCallback = NULL; // function pointers the fuzzer cannot make valid
	def.substepContext = NULL;
	if (def.workerCount > 4 && def.workerCount <= FM_MAX_WORKERS)
		def.workerCount = 1 + def.workerCount % 4;
	// Bounded work per input: the checks of these limits are still reached (0, negative).
	if (def.newtonIterations > 8)
		def.newtonIterations = 1 + def.newtonIterations % 8;
	if (def.cgIterations > 100)
		def.cgIterations = 1 + def.cgIterations % 100;
	if (def.maxBodies > 64 && def.maxBodies <= (1 << 20))
		def.maxBodies = 1 + def.maxBodies % 64;
	// The frame budget too: a collapsing body runs its whole budget of substeps before the frame
	// is refused, which at the default (FM_MAX_SUBSTEPS) took 10 s of an instrumented build
	// (tests/data/fuzz/api_collapse_substep_budget).
	if (def.maxSubstepsPerFrame > 1000 && def.maxSubstepsPerFrame <= FM_MAX_SUBSTEPS)
		def.maxSubstepsPerFrame = 1000;
	return def;
}

static fmBodyDef fuzzBodyDef(fmFuzzReader* r, const fmTetMesh* mesh)
{
	fmBodyDef defaults = fmDefaultBodyDef();
	fmBodyDef def;
	if (fuzzStruct(r, &def, sizeof def, &defaults))
		def.internalValue = defaults.internalValue;
	fuzzFixBool(&def.selfCollision);
	fuzzFixBool(&def.enableSleep);
	fuzzFixBool(&def.material.nodalPressure);
	def.mesh = fmFuzzPick(r, 8) == 0 ? NULL : mesh;
	// Pointers are the caller's to make valid: the region arrays NULL (their count stays fuzzed).
	def.regionMaterials = NULL;
	def.regionIds = NULL;
	// Per-tet fibres: NULL, or fuzzed directions (some zero) for every tet the mesh may have.
	static fmVec3 fibres[fuzz_maxTets];
	def.tetFibres = NULL;
	if (fmFuzzPick(r, 4) == 0)
	{
		for (int t = 0; t < fuzz_maxTets; ++t)
			fibres[t] = fmFuzzPick(r, 16) == 0 ? fmMakeVec3(0, 0, 0) : fmFuzzVec3(r, -1.0, 1.0);
		def.tetFibres = fibres;
	}
	fmMaterial material = fuzzMaterial(r);
	if (fmFuzzPick(r, 2))
		def.material = material;
	else
	{
		def.material.stretchEnergy = material.stretchEnergy;
		def.material.invariantEnergy = material.invariantEnergy;
		def.material.userParams = NULL;
	}
	return def;
}

// A collider of a fuzzed shape, a mesh among them (small fuzzed vertices and triangles, some of
// them out of range), created, moved and perhaps destroyed again.
static void fuzzCollider(fmFuzzReader* r, fmWorldId world)
{
	fmVec3 vertices[6];
	int triangles[12];
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = (fmShapeType)(fmFuzzPick(r, fm_shapeTypeCount + 1) - 1);
	def.center = fmFuzzVec3(r, -2.0, 2.0);
	def.normal = fmFuzzVec3(r, -1.0, 1.0);
	def.offset = fmFuzzDouble(r, -2.0, 2.0);
	def.radius = fmFuzzDouble(r, -0.1, 1.0);
	def.halfExtents = fmFuzzVec3(r, -0.1, 1.0);
	def.rotation = fmFuzzVec3(r, -4.0, 4.0);
	def.a = fmFuzzVec3(r, -2.0, 2.0);
	def.b = fmFuzzVec3(r, -2.0, 2.0);
	def.friction = fmFuzzDouble(r, -0.1, 1.0);
	def.stick = fmFuzzPick(r, 2) == 1;
	def.velocity = fmFuzzPick(r, 2) ? fmFuzzVec3(r, -5.0, 5.0) : def.velocity;
	def.angularVelocity = fmFuzzPick(r, 2) ? fmFuzzVec3(r, -5.0, 5.0) : def.angularVelocity;
	for (int k = 0; k < 6; ++k)
		vertices[k] = fmFuzzVec3(r, -2.0, 2.0);
	for (int k = 0; k < 12; ++k)
		triangles[k] = fmFuzzPick(r, 8) - 1;
	def.vertices = fmFuzzPick(r, 8) ? vertices : NULL;
	def.vertexCount = fmFuzzPick(r, 7); // the arrays' sizes are the caller's promise
	def.triangles = triangles;
	def.triangleCount = fmFuzzPick(r, 5);
	fmColliderId id;
	if (fmCreateCollider(world, &def, &id, NULL) != fm_ok)
		return;
	if (fmFuzzPick(r, 2))
		fmCollider_SetTransform(id, fmFuzzVec3(r, -2.0, 2.0), fmFuzzVec3(r, -3.0, 3.0));
	if (fmFuzzPick(r, 4) == 0)
		fmCollider_SetVelocity(id, fmFuzzVec3(r, -5.0, 5.0), fmFuzzVec3(r, -5.0, 5.0));
	if (fmFuzzPick(r, 4) == 0)
		fmDestroyCollider(id);
}

// Save a snapshot, change the world or not (a step, a collider created or destroyed, a kinematic
// one's velocity, a body put to sleep or woken), corrupt a few bytes of it (or cut it short) and
// restore it: a bad snapshot or one of other colliders is refused, a corrupted value is reported
// by the next step, nothing crashes.
static void fuzzSnapshot(fmFuzzReader* r, fmWorldId world, fmBodyId body)
{
	static unsigned char buffer[1 << 16];
	size_t size = fmWorld_GetSnapshotSize(world), written = 0;
	if (size == 0 || size > sizeof buffer ||
	    fmWorld_SaveSnapshot(world, buffer, size, &written) != fm_ok)
		return;
	switch (fmFuzzPick(r, 6))
	{
	case 0:
		fmWorld_Step(world, fmFuzzDouble(r, 0.0, 0.05), fmFuzzPick(r, 3));
		break;
	case 1:
		fuzzCollider(r, world);
		break;
	case 2:
		fmBody_SetAwake(body, fmFuzzPick(r, 2) == 0);
		break;
	default:
		break;
	}
	int flips = fmFuzzPick(r, 4);
	for (int k = 0; k < flips; ++k)
		buffer[fmFuzzPick(r, (int)written)] ^= (unsigned char)fmFuzzByte(r);
	// Half the changed snapshots are sealed again (a valid checksum), so that the checks behind
	// the checksum are fuzzed too; the others must be refused by it.
	if (flips > 0 && fmFuzzPick(r, 2) == 0)
		fmSnapshot_Seal(buffer, written);
	fmWorld_RestoreSnapshot(world, buffer,
	                        fmFuzzPick(r, 4) ? written : (size_t)fmFuzzPick(r, (int)written + 1));
}

// Another body, a small box at a fuzzed place: often overlapping the first (or one made before,
// or lying on its surface), which creation must refuse with the reason, and stepped at once.
static void fuzzSecondBody(fmFuzzReader* r, fmWorldId world)
{
	fmVec3 lo = fmFuzzVec3(r, -1.5, 1.5);
	double size = fmFuzzDouble(r, 0.01, 1.5);
	fmTetMesh box;
	if (fmMakeBoxMesh(1 + fmFuzzPick(r, 2), 1, 1, lo, fmAdd(lo, fmMakeVec3(size, size, size)),
	                  &box) != fm_ok)
		return;
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &box;
	def.material = fuzzMaterial(r);
	fmBodyId other;
	fmDiagnostic diag;
	if (fmCreateBody(world, &def, &other, &diag) == fm_ok && fmFuzzPick(r, 2))
		fmWorld_Step(world, fmFuzzDouble(r, 0.0, 0.05), 1 + fmFuzzPick(r, 3));
	fmFreeTetMesh(&box);
}

// A grab with a fuzzed def (sometimes not from fmDefaultGrabDef()), by a ray or at a point.
static void fuzzGrab(fmFuzzReader* r, fmWorldId world, fmBodyId body)
{
	fmGrabDef def = fmDefaultGrabDef();
	def.radius = fmFuzzDouble(r, -0.1, 1.0);
	def.stiffness = fmFuzzDouble(r, -1.0, 1e4);
	def.dampingRatio = fmFuzzDouble(r, -0.5, 3.0);
	def.maxForce = fmFuzzDouble(r, -1.0, 1e3);
	if (fmFuzzPick(r, 16) == 0)
		fmFuzzBytes(r, &def, sizeof def);
	fmVec3 point = fmFuzzVec3(r, -3.0, 3.0);
	if (fmFuzzPick(r, 2))
	{
		fmFilter filter = {fmFuzzPick(r, 4), fmFuzzPick(r, 4)};
		fmRayHit hit;
		fmWorld_GrabRay(world, point, fmFuzzVec3(r, -6.0, 6.0), filter,
		                fmFuzzPick(r, 8) ? &def : NULL, fmFuzzPick(r, 2) ? &hit : NULL);
	}
	else
		fmBody_Grab(body, point, fmFuzzPick(r, 8) ? &def : NULL);
	fmVec3 at, target;
	(void)fmBody_GetGrab(body, fmFuzzPick(r, 2) ? &at : NULL, fmFuzzPick(r, 2) ? &target : NULL);
}

// Attachments with fuzzed vertices and defs (sometimes not from fmDefaultAttachDef()): glue to
// the floor's collider (the null id without a floor), a seam on the body, or clearing them.
static void fuzzAttach(fmFuzzReader* r, fmWorldId world, fmBodyId body, int n)
{
	int vertices[4], others[4], count = fmFuzzPick(r, 6) - 1;
	for (int k = 0; k < 4; ++k)
	{
		vertices[k] = fmFuzzPick(r, n + 3) - 1;
		others[k] = fmFuzzPick(r, n + 3) - 1;
	}
	fmAttachDef def = fmDefaultAttachDef();
	def.stiffness = fmFuzzDouble(r, -1.0, 1e6);
	def.dampingRatio = fmFuzzDouble(r, -0.5, 3.0);
	def.maxForce = fmFuzzDouble(r, -1.0, 1e3);
	if (fmFuzzPick(r, 16) == 0)
		fmFuzzBytes(r, &def, sizeof def);
	const fmAttachDef* d = fmFuzzPick(r, 4) ? &def : NULL;
	switch (fmFuzzPick(r, 3))
	{
	case 0:
		fmBody_AttachToCollider(body, fmFuzzPick(r, 8) ? vertices : NULL, count,
		                        fmWorld_GetFloorCollider(world), d);
		break;
	case 1:
		fmBody_Weld(body, vertices, body, fmFuzzPick(r, 8) ? others : NULL, count, d);
		break;
	default:
		fmBody_ClearAttachments(body);
		break;
	}
	(void)fmBody_GetAttachmentCount(body);
}

// Public calls with fuzzed arguments on a live (or stale) body.
// Fracture's calls: tear, the damage and the pieces, into buffers of the body's tet count.
static void fuzzTear(fmFuzzReader* r, fmBodyId body)
{
	int tets = fmBody_IsValid(body) ? fmBody_GetTetCount(body) : 0;
	double* damage = tets > 0 ? malloc(sizeof(double) * (size_t)tets) : NULL;
	int* pieces = tets > 0 ? malloc(sizeof(int) * (size_t)tets) : NULL;
	if (fmFuzzPick(r, 2))
		(void)fmBody_Fracture(body);
	(void)fmBody_ComputeDamage(body, fmFuzzPick(r, 2) ? damage : NULL);
	(void)fmBody_GetPieces(body, fmFuzzPick(r, 2) ? pieces : NULL);
	(void)fmBody_GetBrokenFaceCount(body);
	free(damage);
	free(pieces);
}

static void fuzzCalls(fmFuzzReader* r, fmWorldId world, fmBodyId body)
{
	int n = fmBody_IsValid(body) ? fmBody_GetVertexCount(body) : 0;
	double state[3 * fuzz_maxNodes];
	int calls = fmFuzzPick(r, 12);
	for (int c = 0; c < calls; ++c)
	{
		n = fmBody_IsValid(body) ? fmBody_GetVertexCount(body) : 0; // (a tear adds vertices)
		int vertex = fmFuzzPick(r, n + 3) - 1;
		switch (fmFuzzPick(r, 21))
		{
		case 0:
			fmBody_ApplyVertexImpulse(body, vertex, fmFuzzVec3(r, -10.0, 10.0));
			break;
		case 1:
			fmBody_SetPinnedAxes(body, vertex, fmFuzzByte(r));
			break;
		case 2:
			fmBody_PinBox(body, fmFuzzVec3(r, -2.0, 2.0), fmFuzzVec3(r, -2.0, 2.0));
			break;
		case 3:
			fmWorld_SetGravity(world, fmFuzzVec3(r, -20.0, 20.0));
			break;
		case 4:
		{
			fmFloorDef floor;
			fmFuzzBytes(r, &floor, sizeof floor);
			fuzzFixFloor(&floor);
			fmWorld_SetFloor(world, fmFuzzPick(r, 8) ? &floor : NULL);
			break;
		}
		case 5:
		{
			fmMaterial material = fuzzMaterial(r);
			fmBody_SetMaterial(body, fmFuzzPick(r, 8) ? &material : NULL, NULL);
			break;
		}
		case 6:
			fmWorld_SetIntegrator(world, (fmIntegrator)(fmFuzzPick(r, 4) - 1));
			break;
		case 7:
			for (int k = 0; k < 3 * n && k < 3 * fuzz_maxNodes; ++k)
				state[k] = fmFuzzDouble(r, -2.0, 2.0);
			if (n <= fuzz_maxNodes && fmFuzzPick(r, 2))
				fmBody_SetVelocities(body, fmFuzzPick(r, 8) ? state : NULL);
			else if (n <= fuzz_maxNodes)
				fmBody_SetPositions(body, fmFuzzPick(r, 8) ? state : NULL);
			break;
		case 8:
			fmBody_ApplyImpulse(body, fmFuzzVec3(r, -10.0, 10.0));
			break;
		case 9:
			(void)fmBody_IsPinned(body, vertex);
			break;
		case 10:
			fmWorld_Step(world, fmFuzzDouble(r, 0.0, 0.05), fmFuzzPick(r, 4) - 1);
			break;
		case 11:
			fuzzSnapshot(r, world, body);
			break;
		case 12:
			fuzzCollider(r, world);
			break;
		case 13:
		{
			fmOverlap overlaps[4];
			fmRayHit hit;
			fmFilter filter = {fmFuzzPick(r, 4), fmFuzzPick(r, 4)};
			fmWorld_OverlapSphere(world, fmFuzzVec3(r, -3.0, 3.0), fmFuzzDouble(r, -0.5, 2.0),
			                      filter, fmFuzzPick(r, 2) ? overlaps : NULL, fmFuzzPick(r, 6) - 1);
			fmWorld_CastRay(world, fmFuzzVec3(r, -3.0, 3.0), fmFuzzVec3(r, -6.0, 6.0), filter,
			                &hit);
			break;
		}
		case 14:
			fmBody_SetAwake(body, fmFuzzPick(r, 2) == 0);
			break;
		case 15:
			fuzzGrab(r, world, body);
			break;
		case 16:
			fmBody_MoveGrab(body, fmFuzzVec3(r, -30.0, 30.0));
			if (fmFuzzPick(r, 4) == 0)
				fmBody_ReleaseGrab(body);
			break;
		case 17:
			fuzzSecondBody(r, world);
			break;
		case 18:
			fuzzAttach(r, world, body, n);
			break;
		case 19:
			fuzzTear(r, body);
			break;
		default:
		{
			double residual;
			fmBody_SolveStatic(body, fmFuzzDouble(r, 0.0, 0.1), fmFuzzPick(r, 4) - 1,
			                   fmFuzzPick(r, 2) ? &residual : NULL, NULL);
			break;
		}
		}
	}
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmSetAssertFcn(fuzzAssert);
	fmFuzzReader reader = {data, size, 0};
	fmFuzzReader* r = &reader;
	double positions[3 * fuzz_maxNodes];
	int tets[4 * fuzz_maxTets];
	fmTetMesh mesh;
	fuzzMesh(r, &mesh, positions, tets);
	fmWorldDef worldDef = fuzzWorldDef(r);
	fmBodyDef bodyDef = fuzzBodyDef(r, &mesh);
	fmDiagnostic diag;
	fmWorldDef_Validate(&worldDef, &diag);
	fmBodyDef_Validate(&bodyDef, &diag);
	(void)fmEstimateBodyMemory(&bodyDef);
	fmWorldId world = fmCreateWorld(fmFuzzPick(r, 16) ? &worldDef : NULL);
	fmBodyId body;
	memset(&body, 0, sizeof body);
	fmCreateBody(world, fmFuzzPick(r, 16) ? &bodyDef : NULL, fmFuzzPick(r, 8) ? &body : NULL,
	             fmFuzzPick(r, 2) ? &diag : NULL);
	if (!fmWorld_IsValid(world))
		memset(&body, 0, sizeof body);
	if (fmWorld_IsValid(world))
		fmWorld_Step(world, 0.003, 1);
	fuzzCalls(r, world, body);
	if (fmBody_IsValid(body) && fmFuzzPick(r, 2))
		fmDestroyBody(body);
	if (fmWorld_IsValid(world))
		fmDestroyWorld(world);
	// Everything is stale now: every call must refuse it.
	fuzzCalls(r, world, body);
	fmDestroyBody(body);
	fmDestroyWorld(world);
	return 0;
}
