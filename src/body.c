// Bodies: creation from a mesh (rest-shape preprocessing), state access, pins, statistics.
#include "body.h"

#include "core.h"
#include "forces.h"
#include "integrator.h"
#include "world.h"

#include <math.h>
#include <string.h>

fmBodyDef fmDefaultBodyDef(void)
{
	fmBodyDef def;
	memset(&def, 0, sizeof def);
	def.material = fmMakeMaterialLame(fm_stvk, 20000.0, 5000.0);
	def.forceModel = fm_fem;
	def.massMode = fm_massPerParticle;
	def.density = 1000.0;
	def.particleMass = 1.0;
	def.damping = 0.999;
	def.smoothing = 0.1;
	def.rayleighMass = 0.0;
	def.rayleighStiffness = 0.0;
	def.springDamping = 0.1;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

static bool fmIsFinitePositive(double value)
{
	return isfinite(value) && value > 0.0;
}

fmResult fmBodyDef_Validate(const fmBodyDef* def, fmDiagnostic* diag)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "body def not initialised: start from fmDefaultBodyDef()");
	if (def->mesh == NULL || def->mesh->nodeCount <= 0 || def->mesh->tetCount <= 0)
		return fmDiagError(diag, fm_errEmpty, "", 0, 0,
		                   "body def has no mesh, or the mesh has no tets");
	fmResult r = fmMaterial_Validate(&def->material, diag);
	if (r != fm_ok)
		return r;
	if ((unsigned)def->forceModel >= (unsigned)fm_forceModelCount)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown force model %d",
		                   (int)def->forceModel);
	if (def->massMode == fm_massFromDensity && !fmIsFinitePositive(def->density))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "density must be > 0 kg/m^3 (water is 1000), got %g", def->density);
	if (def->massMode == fm_massPerParticle && !fmIsFinitePositive(def->particleMass))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "particle mass must be > 0 kg (the seeds use 1), got %g",
		                   def->particleMass);
	if (def->massMode != fm_massFromDensity && def->massMode != fm_massPerParticle)
		return fmDiagError(diag, fm_errParameter, "", 0, 0, "unknown mass mode %d",
		                   (int)def->massMode);
	if (!(def->damping > 0.0 && def->damping <= 1.0))
		return fmDiagError(
		    diag, fm_errParameter, "", 0, 0,
		    "damping is a velocity factor per step and must be in (0, 1] (1 = none, the "
		    "seeds use 0.999), got %g",
		    def->damping);
	if (!(def->smoothing >= 0.0 && def->smoothing <= 1.0))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "smoothing must be in [0, 1] (0 = none, the seeds use 0.1), got %g",
		                   def->smoothing);
	if (!(def->rayleighMass >= 0.0 && isfinite(def->rayleighMass)) ||
	    !(def->rayleighStiffness >= 0.0 && isfinite(def->rayleighStiffness)))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "Rayleigh damping coefficients must be finite and >= 0, got mass %g, "
		                   "stiffness %g",
		                   def->rayleighMass, def->rayleighStiffness);
	if (!(def->springDamping >= 0.0 && isfinite(def->springDamping)))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "spring damping ratio must be finite and >= 0, got %g",
		                   def->springDamping);
	return fm_ok;
}

// Free every array of a body; safe on a partially built body.
void fmBodyRelease(fmBody* b)
{
	size_t n = (size_t)b->vertexCount, m = (size_t)b->tetCount;
	FM_FREE_ARRAY(b->x, double, 3 * n);
	FM_FREE_ARRAY(b->v, double, 3 * n);
	FM_FREE_ARRAY(b->f, double, 3 * n);
	FM_FREE_ARRAY(b->x0, double, 3 * n);
	FM_FREE_ARRAY(b->xGood, double, 3 * n);
	FM_FREE_ARRAY(b->vGood, double, 3 * n);
	FM_FREE_ARRAY(b->scratch, double, 3 * n);
	FM_FREE_ARRAY(b->mass, double, n);
	FM_FREE_ARRAY(b->invMass, double, n);
	FM_FREE_ARRAY(b->smoothWeight, double, n);
	FM_FREE_ARRAY(b->pinned, uint8_t, n);
	FM_FREE_ARRAY(b->tets, int, 4 * m);
	FM_FREE_ARRAY(b->DmInv, fmMat3, m);
	FM_FREE_ARRAY(b->restVolume, double, m);
	FM_FREE_ARRAY(b->edges, int, 2 * (size_t)b->edgeCount);
	FM_FREE_ARRAY(b->restLength, double, b->edgeCount);
	FM_FREE_ARRAY(b->springK, double, b->edgeCount);
	FM_FREE_ARRAY(b->fvmNormals, fmVec3, 4 * (size_t)b->tetCount);
	fmFree(b->surface);
	fmImplicitCacheFree(b->implicitCache);
	uint16_t generation = b->generation;
	memset(b, 0, sizeof *b);
	b->generation = generation;
}

static bool fmBodyAllocate(fmBody* b, int n, int m)
{
	b->vertexCount = n;
	b->tetCount = m;
	b->x = FM_ALLOC_ARRAY(double, 3 * (size_t)n);
	b->v = FM_ALLOC_ZERO(double, 3 * (size_t)n);
	b->f = FM_ALLOC_ZERO(double, 3 * (size_t)n);
	b->x0 = FM_ALLOC_ARRAY(double, 3 * (size_t)n);
	b->xGood = FM_ALLOC_ARRAY(double, 3 * (size_t)n);
	b->vGood = FM_ALLOC_ZERO(double, 3 * (size_t)n);
	b->scratch = FM_ALLOC_ZERO(double, 3 * (size_t)n);
	b->mass = FM_ALLOC_ZERO(double, n);
	b->invMass = FM_ALLOC_ZERO(double, n);
	b->smoothWeight = FM_ALLOC_ZERO(double, n);
	b->pinned = FM_ALLOC_ZERO(uint8_t, n);
	b->tets = FM_ALLOC_ARRAY(int, 4 * (size_t)m);
	b->DmInv = FM_ALLOC_ARRAY(fmMat3, m);
	b->restVolume = FM_ALLOC_ARRAY(double, m);
	return b->x && b->v && b->f && b->x0 && b->xGood && b->vGood && b->scratch && b->mass &&
	       b->invMass && b->smoothWeight && b->pinned && b->tets && b->DmInv && b->restVolume;
}

// Reference edge matrices, volumes, masses and smoothing weights from the oriented mesh.
static fmResult fmBodyPrecompute(fmBody* b, const fmBodyDef* def, const fmTetMesh* mesh,
                                 fmDiagnostic* diag)
{
	int* tetsAround = (int*)b->scratch; // reuse as a counter: 3n doubles hold n ints
	memset(tetsAround, 0, sizeof(int) * (size_t)b->vertexCount);
	for (int t = 0; t < b->tetCount; ++t)
	{
		const int* n = b->tets + 4 * t;
		fmVec3 X0 = fmLoad(b->x0, n[0]);
		fmMat3 Dm =
		    fmMat3FromColumns(fmSub(fmLoad(b->x0, n[1]), X0), fmSub(fmLoad(b->x0, n[2]), X0),
		                      fmSub(fmLoad(b->x0, n[3]), X0));
		double volume = fmDet(&Dm) / 6.0;
		if (!(volume > 0.0) || !fmInverse(&Dm, &b->DmInv[t]))
			return fmDiagError(diag, fm_errDegenerate, "", 0, 0,
			                   "tet %d (in the mesh's numbering) has zero volume",
			                   t + mesh->firstIndex);
		b->restVolume[t] = volume;
		for (int a = 0; a < 4; ++a)
		{
			tetsAround[n[a]] += 1;
			if (def->massMode == fm_massFromDensity)
				b->mass[n[a]] += def->density * volume / 4.0;
		}
	}
	b->totalMass = 0.0;
	fmVec3 lo = fmLoad(b->x0, 0), hi = lo;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->x0, i);
		lo = fmMakeVec3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
		hi = fmMakeVec3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
		if (def->massMode == fm_massPerParticle)
			b->mass[i] = def->particleMass;
		b->smoothWeight[i] = tetsAround[i] > 0 ? 1.0 / (4.0 * tetsAround[i]) : 0.0;
		// A node no tet uses has no elastic tie to the body: keep it where it is.
		if (tetsAround[i] == 0)
			b->pinned[i] = FM_PIN_ALL;
		b->invMass[i] = b->pinned[i] == FM_PIN_ALL ? 0.0 : 1.0 / b->mass[i];
		b->totalMass += b->mass[i];
	}
	b->restSize = fmLength(fmSub(hi, lo));
	memset(b->scratch, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	return fm_ok;
}

static fmResult fmBodyInit(fmBody* b, const fmBodyDef* def, fmDiagnostic* diag)
{
	fmTetMesh mesh;
	if (fmCopyTetMesh(def->mesh, &mesh) != fm_ok)
		return fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory copying the mesh");
	fmResult r = fmTetMesh_Orient(&mesh, NULL, diag);
	if (r == fm_ok && !fmBodyAllocate(b, mesh.nodeCount, mesh.tetCount))
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0,
		                "out of memory creating a body of %d tets", mesh.tetCount);
	if (r == fm_ok)
	{
		b->firstIndex = mesh.firstIndex;
		b->material = def->material;
		b->forceModel = def->forceModel;
		b->damping = def->damping;
		b->smoothing = def->smoothing;
		b->rayleighMass = def->rayleighMass;
		b->rayleighStiffness = def->rayleighStiffness;
		b->springDamping = def->springDamping;
		size_t n3 = sizeof(double) * 3 * (size_t)mesh.nodeCount;
		memcpy(b->x, mesh.positions, n3);
		memcpy(b->x0, mesh.positions, n3);
		memcpy(b->xGood, mesh.positions, n3);
		memcpy(b->tets, mesh.tets, sizeof(int) * 4 * (size_t)mesh.tetCount);
		r = fmBodyPrecompute(b, def, &mesh, diag);
	}
	if (r == fm_ok && fmTetMesh_ExtractSurface(&mesh, &b->surface, &b->triangleCount) != fm_ok)
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory extracting the surface");
	if (r == fm_ok && b->forceModel == fm_massSpring && fmBuildSprings(b) != 0)
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory building springs");
	if (r == fm_ok && b->forceModel == fm_fvm && fmBuildFvmNormals(b) != 0)
		r = fmDiagError(diag, fm_errOutOfMemory, "", 0, 0, "out of memory building FVM normals");
	if (r == fm_ok)
	{
		b->explicitLimit = fmBodyExplicitStepLimit(b);
		b->energyStale = true;
	}
	fmFreeTetMesh(&mesh);
	return r;
}

fmResult fmCreateBody(fmWorldId worldId, const fmBodyDef* def, fmBodyId* bodyId, fmDiagnostic* diag)
{
	fmDiagClear(diag);
	if (bodyId)
		memset(bodyId, 0, sizeof *bodyId);
	fmWorld* world = fmGetWorld(worldId);
	if (world == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid or destroyed world id");
	fmResult r = fmBodyDef_Validate(def, diag);
	if (r != fm_ok)
		return r;
	int slot = -1;
	for (int i = 0; i < world->bodyCapacity && slot < 0; ++i)
		if (world->bodies[i].x == NULL)
			slot = i;
	if (slot < 0)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "the world holds %d bodies already (maxBodies)", world->bodyCapacity);
	fmBody* b = &world->bodies[slot];
	b->generation += 1;
	r = fmBodyInit(b, def, diag);
	if (r != fm_ok)
	{
		fmBodyRelease(b);
		return r;
	}
	if (bodyId)
	{
		bodyId->index1 = slot + 1;
		bodyId->world0 = (uint16_t)(worldId.index1 - 1);
		bodyId->generation = b->generation;
	}
	return fm_ok;
}

fmBody* fmGetBody(fmBodyId id)
{
	fmWorld* world = fmGetWorldOfBody(id);
	if (world == NULL || id.index1 < 1 || id.index1 > world->bodyCapacity)
		return NULL;
	fmBody* b = &world->bodies[id.index1 - 1];
	if (b->x == NULL || b->generation != id.generation)
		return NULL;
	return b;
}

// Resolve an id for a public call: a stale id is a programmer error.
static fmBody* fmBodyOrAssert(fmBodyId id)
{
	fmBody* b = fmGetBody(id);
	FM_ASSERT(b != NULL);
	return b;
}

void fmDestroyBody(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b)
		fmBodyRelease(b);
}

bool fmBody_IsValid(fmBodyId bodyId)
{
	return fmGetBody(bodyId) != NULL;
}

int fmBody_GetVertexCount(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->vertexCount : 0;
}

int fmBody_GetTetCount(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->tetCount : 0;
}

const double* fmBody_GetPositions(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->x : NULL;
}

const double* fmBody_GetVelocities(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->v : NULL;
}

const double* fmBody_GetMasses(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->mass : NULL;
}

const int* fmBody_GetTets(fmBodyId bodyId)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b ? b->tets : NULL;
}

const int* fmBody_GetSurface(fmBodyId bodyId, int* triangleCount)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (triangleCount)
		*triangleCount = b ? b->triangleCount : 0;
	return b ? b->surface : NULL;
}

void fmBody_SetPositions(fmBodyId bodyId, const double* positions)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b && positions)
		memcpy(b->x, positions, sizeof(double) * 3 * (size_t)b->vertexCount);
}

void fmBody_SetVelocities(fmBodyId bodyId, const double* velocities)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b == NULL || velocities == NULL)
		return;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmStore(b->v, i, fmLoad(velocities, i));
		fmZeroPinnedAxes(b, i, b->v + 3 * i);
	}
}

void fmBody_ApplyImpulse(fmBodyId bodyId, fmVec3 deltaVelocity)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b == NULL)
		return;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmStore(b->v, i, fmAdd(fmLoad(b->v, i), deltaVelocity));
		fmZeroPinnedAxes(b, i, b->v + 3 * i);
	}
}

void fmBody_ApplyVertexImpulse(fmBodyId bodyId, int vertex, fmVec3 deltaVelocity)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->vertexCount));
	if (b && vertex >= 0 && vertex < b->vertexCount)
	{
		fmStore(b->v, vertex, fmAdd(fmLoad(b->v, vertex), deltaVelocity));
		fmZeroPinnedAxes(b, vertex, b->v + 3 * vertex);
	}
}

void fmBody_SetPinned(fmBodyId bodyId, int vertex, bool pinned)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->vertexCount));
	if (b == NULL || vertex < 0 || vertex >= b->vertexCount)
		return;
	fmBody_SetPinnedAxes(bodyId, vertex, pinned ? FM_PIN_ALL : 0u);
}

void fmBody_SetPinnedAxes(fmBodyId bodyId, int vertex, unsigned axes)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	FM_ASSERT(b == NULL || (vertex >= 0 && vertex < b->vertexCount));
	if (b == NULL || vertex < 0 || vertex >= b->vertexCount)
		return;
	b->pinned[vertex] = (uint8_t)(axes & FM_PIN_ALL);
	b->invMass[vertex] = b->pinned[vertex] == FM_PIN_ALL ? 0.0 : 1.0 / b->mass[vertex];
	fmZeroPinnedAxes(b, vertex, b->v + 3 * vertex);
}

bool fmBody_IsPinned(fmBodyId bodyId, int vertex)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	return b && vertex >= 0 && vertex < b->vertexCount && b->pinned[vertex] == FM_PIN_ALL;
}

int fmBody_PinBox(fmBodyId bodyId, fmVec3 min, fmVec3 max)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b == NULL)
		return 0;
	int count = 0;
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->x, i);
		if (p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
		    p.z <= max.z)
		{
			fmBody_SetPinned(bodyId, i, true);
			++count;
		}
	}
	return count;
}

fmResult fmBody_SetMaterial(fmBodyId bodyId, const fmMaterial* material, fmDiagnostic* diag)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b == NULL)
		return fmDiagError(diag, fm_errInvalidId, "", 0, 0, "invalid or destroyed body id");
	fmResult r = fmMaterial_Validate(material, diag);
	if (r != fm_ok)
		return r;
	// Spring stiffness is proportional to Young's modulus (force_spring.c).
	double ratio = fmYoungsModulus(material) / fmYoungsModulus(&b->material);
	for (int e = 0; e < b->edgeCount; ++e)
		b->springK[e] *= ratio;
	b->material = *material;
	b->explicitLimit = fmBodyExplicitStepLimit(b);
	b->energyStale = true;
	return fm_ok;
}

double fmBody_ComputeElasticForces(fmBodyId bodyId, double* forces)
{
	fmBody* b = fmBodyOrAssert(bodyId);
	if (b == NULL || forces == NULL)
		return 0.0;
	memset(forces, 0, sizeof(double) * 3 * (size_t)b->vertexCount);
	return fmAddElasticForces(b, b->x, forces);
}

int fmBodyCountInverted(const fmBody* b)
{
	int inverted = 0;
	for (int t = 0; t < b->tetCount; ++t)
	{
		fmMat3 F = fmTetDeformation(b, b->x, t);
		if (!(fmDet(&F) > 0.0))
			++inverted;
	}
	return inverted;
}

fmBodyStats fmBody_GetStats(fmBodyId bodyId)
{
	fmBodyStats s;
	memset(&s, 0, sizeof s);
	fmBody* b = fmBodyOrAssert(bodyId);
	fmWorld* world = fmGetWorldOfBody(bodyId);
	if (b == NULL || world == NULL)
		return s;
	fmVec3 g = world->def.gravity;
	s.lowestY = INFINITY;
	fmVec3 moment = {0, 0, 0};
	for (int i = 0; i < b->vertexCount; ++i)
	{
		fmVec3 p = fmLoad(b->x, i), v = fmLoad(b->v, i);
		s.kineticEnergy += 0.5 * b->mass[i] * fmDot(v, v);
		s.gravityEnergy -= b->mass[i] * fmDot(g, p);
		moment = fmMulAdd(moment, b->mass[i], p);
		s.lowestY = fmin(s.lowestY, p.y);
	}
	s.centerOfMass = fmScale(1.0 / b->totalMass, moment);
	s.elasticEnergy = fmElasticEnergy(b, b->x);
	s.invertedTets = fmBodyCountInverted(b);
	s.work = b->ledger.work;
	s.initialEnergy = b->ledger.initialEnergy;
	return s;
}
