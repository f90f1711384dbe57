// A body's record in a snapshot (snapshot_body.h).
#include "world/snapshot_body.h"

#include "body/fracture.h"
#include "body/plasticity.h"
#include "body/tear_topology.h"
#include "core/core.h"
#include "fem/nodal_pressure.h"
#include "material/material.h"
#include "material/material_aniso.h"
#include "material/material_plastic.h"
#include "solver/solver_cache.h"

#include <string.h>

static void fmMoveLedger(fmStream* s, bool save, fmEnergyLedger* l)
{
	fmStream_MoveBool(s, save, &l->started);
	double* fields[] = {&l->initialEnergy, &l->work,         &l->workIn,
	                    &l->floor,         &l->gravityStart, &l->frameGravityWork,
	                    &l->measureStep,   &l->plainGood,    &l->framePlain};
	for (size_t k = 0; k < sizeof fields / sizeof fields[0]; ++k)
		fmStream_MoveDouble(s, save, fields[k]);
}

static void fmMoveMaterial(fmStream* s, bool save, fmMaterial* m)
{
	int32_t model = (int32_t)m->model;
	fmStream_Move(s, save, &model, sizeof model);
	m->model = (fmMaterialModel)model;
	fmStream_MoveDouble(s, save, &m->lambda);
	fmStream_MoveDouble(s, save, &m->mu);
	fmStream_MoveDouble(s, save, &m->c01);
	double* anisotropy[] = {
	    m->orthotropy.E,      m->orthotropy.E + 1,  m->orthotropy.E + 2, m->orthotropy.nu,
	    m->orthotropy.nu + 1, m->orthotropy.nu + 2, m->orthotropy.G,     m->orthotropy.G + 1,
	    m->orthotropy.G + 2,  &m->fibreStiffness,   &m->fibre.x,         &m->fibre.y,
	    &m->fibre.z,          &m->sheet.x,          &m->sheet.y,         &m->sheet.z};
	for (size_t k = 0; k < sizeof anisotropy / sizeof anisotropy[0]; ++k)
		fmStream_MoveDouble(s, save, anisotropy[k]);
	fmPlasticity* p = &m->plasticity;
	double* plasticity[] = {&p->yieldStress, &p->hardening, &p->creepRate, &p->maxPlasticStrain};
	for (size_t k = 0; k < 4; ++k)
		fmStream_MoveDouble(s, save, plasticity[k]);
	fmStream_MoveBool(s, save, &m->nodalPressure); // (version 12)
	// User energies: function and parameter pointers, valid within the process that saved them.
	fmStream_Move(s, save, &m->stretchEnergy, sizeof m->stretchEnergy);
	fmStream_Move(s, save, &m->invariantEnergy, sizeof m->invariantEnergy);
	fmStream_Move(s, save, &m->userParams, sizeof m->userParams);
}

// The implicit solver's state carried from step to step: a flags byte (bit 0: a kept matrix
// follows, bit 1: the last step started from x + h v, the guess the next one tries first, bit 2:
// the kept matrix's base without its contact terms follows it), the steps before the other guess
// is tried again (a byte), then the kept matrix's terms and values, then the base's values. A cache
// that does not exist (no implicit step yet) is saved as none of these; restoring "no matrix" into
// a body that has one marks it stale, which is what the saved body would have done.
static bool fmMoveSolverMatrix(fmStream* s, bool save, fmBody* b)
{
	fmImplicitCache* c = b->solverCache;
	bool base = c != NULL && c->hessianValid && c->hessianBaseValid;
	uint8_t flags = (uint8_t)((c != NULL && c->hessianValid ? 1u : 0u) |
	                          (c != NULL && c->coasted ? 2u : 0u) | (base ? 4u : 0u));
	uint8_t recheck = (uint8_t)(c != NULL ? c->guessRecheck : 0);
	fmStream_Move(s, save, &flags, 1);
	fmStream_Move(s, save, &recheck, 1);
	bool warm = (flags & 2u) || recheck > 0;
	if (!save && warm && (c = fmSolverCache_Get(&b->solverCache, &b->mesh)) == NULL)
		return false;
	if (!save && c != NULL)
	{
		c->coasted = (flags & 2u) != 0;
		c->guessRecheck = recheck;
	}
	if (!save && c != NULL)
		c->hessianBaseValid = false;
	if (!(flags & 1u))
	{
		if (!save && c != NULL)
			c->hessianValid = false;
		return true;
	}
	if (!save && (c = fmSolverCache_Get(&b->solverCache, &b->mesh)) == NULL)
		return false;
	int64_t blocks = c->pattern.blocks;
	fmStream_Move(s, save, &blocks, sizeof blocks);
	if (blocks != c->pattern.blocks)
		return false;
	c->hessianValid = true;
	fmStream_MoveDouble(s, save, &c->hessianInertia);
	fmStream_MoveDouble(s, save, &c->hessianMassDamping);
	fmStream_MoveBool(s, save, &c->hessianDamping);
	fmStream_MoveBool(s, save, &c->hessianExact);
	fmStream_Move(s, save, c->hessian, sizeof(double) * 9 * (size_t)blocks);
	if (!save)
		c->hessianVersion += 1; // the multigrid's levels are set up again from it
	if (!(flags & 4u))
		return true;
	if (!save && fmSolverCache_Base(c) == NULL)
		return false;
	fmStream_Move(s, save, c->hessianBase, sizeof(double) * 9 * (size_t)blocks);
	c->hessianBaseValid = true;
	return true;
}

fmBodyKey fmSnapshotBody_Key(const fmBody* b, int slot)
{
	fmBodyKey key = {slot,
	                 b->generation,
	                 b->mesh.vertexCount,
	                 b->mesh.tetCount,
	                 b->mesh.edgeCount,
	                 (int32_t)b->mesh.forceModel};
	return key;
}

static void fmMoveBodyState(fmStream* s, bool save, fmBody* b)
{
	size_t n3 = 3 * (size_t)b->mesh.vertexCount, n = (size_t)b->mesh.vertexCount;
	fmStream_Move(s, save, b->state.x, sizeof(double) * n3);
	fmStream_Move(s, save, b->state.v, sizeof(double) * n3);
	fmStream_Move(s, save, b->xGood, sizeof(double) * n3);
	fmStream_Move(s, save, b->vGood, sizeof(double) * n3);
	fmStream_Move(s, save, b->state.pinned, n);
	fmStream_Move(s, save, b->mesh.springK, sizeof(double) * (size_t)b->mesh.edgeCount);
	fmMoveMaterial(s, save, &b->mesh.material);
	fmStream_MoveDouble(s, save, &b->energyGood);
	fmStream_MoveBool(s, save, &b->energyStale);
	fmStream_MoveDouble(s, save, &b->explicitLimit);
	fmMoveLedger(s, save, &b->ledger);
}

// The plastic state (version 11): the plastic work, a byte saying whether the body has per-tet
// plastic state, and then its rest data (each tet's Dm^-1 Fp^-1) and plastic strains. Restoring
// "none" into a body that has flowed since gives it back its rest data from before any flow.
static bool fmMovePlastic(fmStream* s, bool save, fmBody* b)
{
	fmStream_MoveDouble(s, save, &b->plasticWork);
	uint8_t plastic = b->mesh.plasticStrain != NULL ? 1u : 0u;
	fmStream_Move(s, save, &plastic, 1);
	size_t m = (size_t)b->mesh.tetCount;
	if (!save && plastic == 0u)
	{
		fmPlasticity_Unflowed(b);
		if (!fmPlasticity_AnyFlows(b)) // (then the explicit float blocks apply again)
			fmPlasticity_Free(b);
	}
	if (plastic == 0u)
		return true;
	if (!save && !fmPlasticity_Allocate(b))
		return false;
	fmStream_Move(s, save, b->mesh.DmInv, sizeof(fmMat3) * m);
	fmStream_Move(s, save, b->mesh.plasticStrain, sizeof(double) * m);
	return true;
}

bool fmSnapshotBody_Move(fmStream* s, bool save, fmBody* b)
{
	fmMoveBodyState(s, save, b);
	if (!save) // the tets' parts and the patches' bulk of the material restored (same flag)
		fmNodalPressure_Refresh(&b->mesh);
	return fmMovePlastic(s, save, b) && fmMoveSolverMatrix(s, save, b);
}

// The material saved in body @p b's record at @p offset is one fmMaterial_Validate accepts (a
// corrupted model number would index past the model table).
static bool fmRecordMaterialValid(const fmBody* b, const void* buffer, size_t size, size_t offset)
{
	size_t n = (size_t)b->mesh.vertexCount;
	size_t at = offset + sizeof(double) * (12 * n + (size_t)b->mesh.edgeCount) + n;
	if (offset > size || at > size)
		return false;
	fmStream s = {NULL, buffer, size, at, false};
	fmMaterial material = b->mesh.material;
	fmMoveMaterial(&s, false, &material);
	// What the body itself allows (fmBody_SetMaterial's checks): plasticity with the fem force
	// model, anisotropy with a stress (not springs); and the body's own volume term (per tet or
	// on patches: the Newton matrix's pattern, which the record's kept matrix has, differs).
	fmForceModel model = b->mesh.forceModel;
	bool fits = (model == fm_fem || !fmPlasticity_Flows(&material)) &&
	            (model != fm_massSpring || !fmMaterialModel_IsAnisotropic(material.model)) &&
	            material.nodalPressure == b->mesh.material.nodalPressure;
	return !s.overflow && fits && fmMaterial_Validate(&material, NULL) == fm_ok;
}

// Bytes of body @p b's record at @p offset of the buffer (after its key), or SIZE_MAX when the
// record does not fit @p b (another matrix size), the buffer, or holds an invalid material.
size_t fmSnapshotBody_RecordBytes(fmBody* b, const void* buffer, size_t size, size_t offset)
{
	if (!fmRecordMaterialValid(b, buffer, size, offset))
		return SIZE_MAX;
	fmStream count = {NULL, NULL, 0, 0, false};
	fmMoveBodyState(&count, true, b);
	if (offset > size || count.used > size - offset)
		return SIZE_MAX;
	fmStream s = {NULL, buffer, size, offset + count.used, false};
	fmStream_Skip(&s, sizeof(double)); // the plastic work
	uint8_t plastic = 0;
	fmStream_Get(&s, &plastic, 1);
	if (plastic > 1u)
		return SIZE_MAX;
	if (plastic == 1u)
	{
		fmStream_Skip(&s, (sizeof(fmMat3) + sizeof(double)) * (size_t)b->mesh.tetCount);
		if (!fmPlasticity_Allocate(b)) // its memory taken before anything is restored
			return SIZE_MAX;
	}
	uint8_t present = 0;
	fmStream_Get(&s, &present, 1);
	fmStream_Skip(&s, 1); // the first guess's recheck countdown
	if (present & 1u)
	{
		int64_t blocks = 0;
		fmStream_Get(&s, &blocks, sizeof blocks);
		fmImplicitCache* c =
		    fmSolverCache_Get(&b->solverCache, &b->mesh); // the same mesh gives the same pattern
		if (c == NULL || blocks != c->pattern.blocks)
			return SIZE_MAX;
		fmStream_Skip(&s, 2 * sizeof(double) + 2 + sizeof(double) * 9 * (size_t)blocks);
		// The base's memory is taken here, before anything is restored.
		if ((present & 4u) && fmSolverCache_Base(c) == NULL)
			return SIZE_MAX;
		if (present & 4u)
			fmStream_Skip(&s, sizeof(double) * 9 * (size_t)blocks);
	}
	else if (present & 4u)
		return SIZE_MAX; // a base without its matrix
	return s.overflow || s.used > size ? SIZE_MAX : s.used - offset;
}

// ---- the topology (fracture.h) -----------------------------------------------------------------

static bool fmTorn(const fmBody* b)
{
	const fmCracks* c = b->cracks;
	return c != NULL && (c->brokenCount > 0 || b->mesh.vertexCount > c->originalVertexCount);
}

void fmSnapshotBody_PutTopology(fmStream* s, const fmBody* b)
{
	uint8_t torn = fmTorn(b) ? 1u : 0u;
	fmStream_Put(s, &torn, 1);
	if (!torn)
		return;
	int32_t count = b->mesh.vertexCount;
	size_t m = (size_t)b->mesh.tetCount;
	fmStream_Put(s, &count, sizeof count);
	fmStream_Put(s, b->mesh.tets, sizeof(int32_t) * 4 * m);
	fmStream_Put(s, b->cracks->broken, 4 * m);
}

// Broken marks of 0 or 1, on shared faces, on both sides.
static bool fmBrokenValid(const fmCracks* c, const uint8_t* broken, int tetCount)
{
	for (int f = 0; f < 4 * tetCount; ++f)
		if (broken[f] > 1u || (broken[f] && (c->neighbour[f] < 0 || !broken[c->neighbour[f]])))
			return false;
	return true;
}

int fmSnapshotBody_CheckTopology(fmStream* s, const fmBody* b, int* vertexCount)
{
	uint8_t torn = 2;
	fmStream_Get(s, &torn, 1);
	*vertexCount = b->cracks != NULL ? b->cracks->originalVertexCount : b->mesh.vertexCount;
	if (s->overflow || torn > 1u || (torn == 1u && b->cracks == NULL))
		return -1;
	if (torn == 0u)
		return fmTorn(b) ? 1 : 0;
	int32_t count = -1;
	fmStream_Get(s, &count, sizeof count);
	size_t m = (size_t)b->mesh.tetCount;
	if (s->overflow || 4 * m * (sizeof(int32_t) + 1) > s->size - s->used)
		return -1;
	const uint8_t* broken = s->in + s->used + sizeof(int32_t) * 4 * m;
	int* copy = FM_ALLOC_ARRAY(int, 4 * m);
	if (copy == NULL)
		return -2;
	memcpy(copy, s->in + s->used, sizeof(int32_t) * 4 * m);
	const char* problem = fmTearTopology_Problem(b, copy, count);
	bool valid = problem == NULL && fmBrokenValid(b->cracks, broken, (int)m);
	bool same = valid && count == b->mesh.vertexCount &&
	            memcmp(copy, b->mesh.tets, sizeof(int) * 4 * m) == 0 &&
	            memcmp(broken, b->cracks->broken, 4 * m) == 0;
	FM_FREE_ARRAY(copy, int, 4 * m);
	fmStream_Skip(s, 4 * m * (sizeof(int32_t) + 1));
	*vertexCount = count;
	return problem != NULL && strcmp(problem, FM_TEAR_NO_MEMORY) == 0 ? -2
	       : !valid                                                   ? -1
	       : same                                                     ? 0
	                                                                  : 1;
}

// The record's vertex sources: a vertex the body has now with the same original keeps its own
// state (and its loads), another takes its original's (the restore overwrites the state).
static void fmTopologySources(const fmBody* b, const int* tets, int count, int* from)
{
	const fmCracks* c = b->cracks;
	size_t m = (size_t)b->mesh.tetCount;
	for (size_t e = 0; e < 4 * m; ++e)
	{
		int v = tets[e], o = c->originalTets[e];
		from[v] = v < b->mesh.vertexCount && c->origin[v] == o ? v : o;
	}
	for (int i = 0; i < c->originalVertexCount && i < count; ++i)
		from[i] = i;
}

bool fmSnapshotBody_ApplyTopology(fmStream* s, struct fmWorld* w, fmBody* b)
{
	fmStream probe = *s;
	int count = 0;
	if (fmSnapshotBody_CheckTopology(&probe, b, &count) == 0)
	{
		*s = probe; // (the body's own: unchanged)
		return true;
	}
	uint8_t torn = 0;
	fmStream_Get(s, &torn, 1);
	size_t m = (size_t)b->mesh.tetCount;
	if (torn)
		fmStream_Skip(s, sizeof(int32_t));
	int* tets = FM_ALLOC_ARRAY(int, 4 * m);
	int* from = FM_ALLOC_ARRAY(int, (size_t)count);
	int* parent = FM_ALLOC_ARRAY(int, m);
	uint8_t* broken = FM_ALLOC_ZERO(uint8_t, 4 * m);
	bool ok = tets != NULL && from != NULL && parent != NULL && broken != NULL;
	if (ok && torn)
	{
		fmStream_Get(s, tets, sizeof(int32_t) * 4 * m);
		fmStream_Get(s, broken, 4 * m);
	}
	else if (ok)
		memcpy(tets, b->cracks->originalTets, sizeof(int) * 4 * m);
	if (ok)
		fmTopologySources(b, tets, count, from);
	ok = ok && fmTearTopology_Set(w, b, tets, count, from);
	if (ok)
		fmFracture_SetBroken(b, broken, parent);
	FM_FREE_ARRAY(tets, int, 4 * m);
	FM_FREE_ARRAY(from, int, (size_t)count);
	FM_FREE_ARRAY(parent, int, m);
	FM_FREE_ARRAY(broken, uint8_t, 4 * m);
	return ok;
}
