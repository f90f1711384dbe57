// A body's definition (body_def.h): the defaults, the checks a def passes before a body is
// made from it, and the memory a body of it will take.
#include "body/body_def.h"

#include "core/core.h"
#include "fem/tet_blocks.h"
#include "material/material.h"
#include "material/material_aniso.h"
#include "material/material_plastic.h"
#include "solver/multigrid.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
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
	def.friction = -1.0;
	def.filter = fmDefaultFilter();
	def.enableSleep = true;
	def.internalValue = FM_DEF_MAGIC;
	return def;
}

static bool fmIsFinitePositive(double value)
{
	return isfinite(value) && value > 0.0;
}

// Counts, pointers and numbering of a mesh a body is made from (the arrays are not read).
static fmResult fmCheckMeshShape(const fmTetMesh* mesh, fmDiagnostic* diag)
{
	if (mesh == NULL || mesh->nodeCount <= 0 || mesh->tetCount <= 0)
		return fmDiagError(diag, fm_errEmpty, "", 0, 0,
		                   "body def has no mesh, or the mesh has no tets");
	if (mesh->nodeCount > FM_MAX_NODES || mesh->tetCount > FM_MAX_TETS)
		return fmDiagError(diag, fm_errLimit, "", 0, 0,
		                   "mesh of %d nodes and %d tets exceeds the limits of %d nodes and %d "
		                   "tets (FM_MAX_NODES, FM_MAX_TETS)",
		                   mesh->nodeCount, mesh->tetCount, FM_MAX_NODES, FM_MAX_TETS);
	if (mesh->positions == NULL || mesh->tets == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "mesh of %d nodes and %d tets has NULL %s", mesh->nodeCount,
		                   mesh->tetCount, mesh->positions == NULL ? "positions" : "tets");
	if (mesh->firstIndex != 0 && mesh->firstIndex != 1)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "mesh firstIndex must be 0 or 1 (the numbering of the source file), "
		                   "got %d",
		                   mesh->firstIndex);
	const int counts[2] = {mesh->nodeAttributeCount, mesh->tetAttributeCount};
	const double* arrays[2] = {mesh->nodeAttributes, mesh->tetAttributes};
	static const char* const names[2] = {"nodeAttribute", "tetAttribute"};
	for (int k = 0; k < 2; ++k)
		if (counts[k] < 0 || counts[k] > FM_MAX_ATTRIBUTES || (counts[k] > 0 && arrays[k] == NULL))
			return fmDiagError(diag, fm_errParameter, "", 0, 0,
			                   "mesh %sCount is %d with %s %ss: expected 0 to %d "
			                   "(FM_MAX_ATTRIBUTES), and an array of that many per %s",
			                   names[k], counts[k], arrays[k] == NULL ? "NULL" : "non-NULL",
			                   names[k], FM_MAX_ATTRIBUTES, k == 0 ? "node" : "tet");
	return fm_ok;
}

// Coordinates finite and within FM_MAX_COORDINATE; tets of 4 distinct in-range nodes with a
// volume that is not zero relative to their size (the test fmTetMesh_Orient() applies).
static fmResult fmCheckMeshData(const fmTetMesh* mesh, fmDiagnostic* diag)
{
	const int first = mesh->firstIndex;
	for (size_t k = 0; k < 3 * (size_t)mesh->nodeCount; ++k)
		if (!(fabs(mesh->positions[k]) <= FM_MAX_COORDINATE))
			return fmDiagError(diag, fm_errRange, "", 0, 0,
			                   "node %d has coordinate %g: expected finite, |x| <= %g m "
			                   "(FM_MAX_COORDINATE)",
			                   (int)(k / 3) + first, mesh->positions[k], FM_MAX_COORDINATE);
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		const int* v = mesh->tets + 4 * (size_t)t;
		for (int a = 0; a < 4; ++a)
		{
			if (v[a] < 0 || v[a] >= mesh->nodeCount)
				return fmDiagError(diag, fm_errIndex, "", 0, 0,
				                   "tet %d refers to node %d: expected 0 to %d (0-based)",
				                   t + first, v[a], mesh->nodeCount - 1);
			for (int c = 0; c < a; ++c)
				if (v[c] == v[a])
					return fmDiagError(diag, fm_errIndex, "", 0, 0,
					                   "tet %d repeats node %d: expected 4 distinct nodes",
					                   t + first, v[a] + first);
		}
		fmTetQuality quality;
		if (fmTetMesh_GetTetQuality(mesh, t, &quality) != fm_ok || quality.degenerate)
			return fmDiagError(diag, fm_errDegenerate, "", 0, 0,
			                   "tet %d (in the mesh's numbering) has zero volume relative to its "
			                   "size (|6V| <= 1e-12 (longest edge)^3)",
			                   t + first);
		if (quality.volumeOutOfRange)
			return fmDiagError(diag, fm_errRange, "", 0, 0,
			                   "tet %d (in the mesh's numbering) has a volume out of the range of "
			                   "a double",
			                   t + first);
	}
	return fm_ok;
}

// Per-region materials: a count in range, the arrays, distinct ids, valid materials, and a
// mesh with tet attributes to read the regions from.
static fmResult fmValidateRegions(const fmBodyDef* def, fmDiagnostic* diag)
{
	int count = def->regionCount;
	if (count == 0)
		return fm_ok;
	if (count < 0 || count > FM_MAX_REGIONS || def->regionMaterials == NULL ||
	    def->regionIds == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "regionCount must be in [0, %d] with non-NULL regionMaterials and "
		                   "regionIds, got %d",
		                   FM_MAX_REGIONS, count);
	if (def->mesh->tetAttributeCount < 1 || def->mesh->tetAttributes == NULL)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "per-region materials need a mesh with region numbers (tet "
		                   "attributes: TetGen's region attribute, Gmsh's physical groups); this "
		                   "mesh has none");
	for (int k = 0; k < count; ++k)
	{
		for (int other = 0; other < k; ++other)
			if (def->regionIds[other] == def->regionIds[k])
				return fmDiagError(diag, fm_errParameter, "", 0, 0,
				                   "region %d is given two materials (regionIds[%d] and [%d])",
				                   def->regionIds[k], other, k);
		fmResult r = fmMaterial_Validate(&def->regionMaterials[k], diag);
		if (r != fm_ok)
		{
			char message[sizeof diag->message];
			snprintf(message, sizeof message, "%s", diag != NULL ? diag->message : "");
			return fmDiagError(diag, r, "", 0, 0, "region %d: %s", def->regionIds[k], message);
		}
	}
	return fm_ok;
}

// Anisotropic and plastic materials: a force model that reads the stress (springs on the tet
// edges carry one stiffness each; plasticity: the fem model, whose rest data holds the plastic
// part), and per-tet fibres finite and non-zero.
static fmResult fmValidateAnisotropy(const fmBodyDef* def, fmDiagnostic* diag)
{
	bool anisotropic = fmMaterialModel_IsAnisotropic(def->material.model);
	for (int k = 0; k < def->regionCount; ++k)
		anisotropic = anisotropic || fmMaterialModel_IsAnisotropic(def->regionMaterials[k].model);
	bool plastic = fmPlasticity_Flows(&def->material);
	for (int k = 0; k < def->regionCount; ++k)
		plastic = plastic || fmPlasticity_Flows(&def->regionMaterials[k]);
	if (plastic && def->forceModel != fm_fem)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "plasticity needs the fem force model (a tet's plastic part lives in "
		                   "its rest data), not %s",
		                   fmForceModelName(def->forceModel));
	bool tears = def->material.fracture.strength > 0.0;
	for (int k = 0; k < def->regionCount; ++k)
		tears = tears || def->regionMaterials[k].fracture.strength > 0.0;
	if (tears && def->forceModel != fm_fem)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "fracture needs the fem force model (it reads each tet's stress and "
		                   "splits vertices), not %s",
		                   fmForceModelName(def->forceModel));
	if (anisotropic && def->forceModel == fm_massSpring)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "anisotropic materials need the fem or fvm force model: mass-spring's "
		                   "springs on the tet edges carry one stiffness each");
	for (int t = 0; def->tetFibres != NULL && t < def->mesh->tetCount; ++t)
	{
		fmVec3 a = def->tetFibres[t];
		double n2 = fmDot(a, a);
		if (!(n2 > 0.0 && isfinite(n2)))
			return fmDiagError(diag, fm_errParameter, "", 0, 0,
			                   "tetFibres[%d] = (%g, %g, %g) must be finite and non-zero (a "
			                   "direction: its length does not matter)",
			                   t, a.x, a.y, a.z);
	}
	return fm_ok;
}

fmResult fmBodyDef_Check(const fmBodyDef* def, fmDiagnostic* diag)
{
	if (def == NULL || def->internalValue != FM_DEF_MAGIC)
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "body def not initialised: start from fmDefaultBodyDef()");
	fmResult r = fmCheckMeshShape(def->mesh, diag);
	if (r == fm_ok)
		r = fmCheckMeshData(def->mesh, diag);
	if (r != fm_ok)
		return r;
	r = fmMaterial_Validate(&def->material, diag);
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
	if (!(def->friction == -1.0 || (def->friction >= 0.0 && isfinite(def->friction))))
		return fmDiagError(diag, fm_errParameter, "", 0, 0,
		                   "friction must be finite and >= 0, or -1 for the world's contact "
		                   "friction, got %g",
		                   def->friction);
	r = fmValidateRegions(def, diag);
	return r == fm_ok ? fmValidateAnisotropy(def, diag) : r;
}

// ---- memory estimate ---------------------------------------------------------------------------

// Bytes of @p count elements of @p size, rounded up to fmAlloc's 64-byte granule.
static uint64_t fmArrayBytes(uint64_t count, uint64_t size)
{
	return count == 0 ? 0 : (count * size + 63) / 64 * 64;
}

static bool fmTears(const fmMaterial* m)
{
	return m->fracture.strength > 0.0;
}

static bool fmHasNodalPressure(const fmMaterial* m)
{
	return m->nodalPressure;
}

static bool fmYields(const fmMaterial* m)
{
	return m->plasticity.yieldStress > 0.0;
}

// Whether a material of @p def (the body's or a region's) has the property @p has.
static bool fmDefAny(const fmBodyDef* def, bool (*has)(const fmMaterial*))
{
	bool any = def && has(&def->material);
	for (int k = 0;
	     def && def->regionMaterials != NULL && k < def->regionCount && k < FM_MAX_REGIONS; ++k)
		any = any || has(&def->regionMaterials[k]);
	return any;
}

// The bytes the materials' own state adds to a body of @p n vertices and @p m tets: plastic
// strains, the nodal pressure's patches and scratch, the crack state.
static uint64_t fmMaterialStateBytes(const fmBodyDef* def, uint64_t n, uint64_t m)
{
	const uint64_t d = sizeof(double);
	uint64_t body = 0;
	if (fmDefAny(def, fmYields)) // plastic strains (now and kept), rest data (before flow and kept)
		body += 2 * fmArrayBytes(m, sizeof(double)) + 2 * fmArrayBytes(m, sizeof(fmMat3));
	bool nodal = fmDefAny(def, fmHasNodalPressure);
	if (nodal) // the tet parts, the patches' volumes and bulk
		body += fmArrayBytes(def->regionCount > 0 && def->regionCount <= FM_MAX_REGIONS
		                         ? (uint64_t)def->regionCount + 1
		                         : 1,
		                     sizeof(fmMaterial)) +
		        2 * fmArrayBytes(n, d);
	if (nodal) // the step's scratch: pressures, curvatures and one patch (about 64 vertices)
		body += 2 * fmArrayBytes(n, d) + fmArrayBytes(64, sizeof(int)) +
		        fmArrayBytes(64, sizeof(fmVec3));
	if (fmDefAny(def,
	             fmTears)) // the crack state (fracture.h); a length's averages counted at 2 a tet
		body += fmArrayBytes(n, d) + fmArrayBytes(n, sizeof(int)) +
		        2 * fmArrayBytes(4 * m, sizeof(int)) + fmArrayBytes(4 * m, 1) +
		        fmArrayBytes(m, sizeof(int)) + fmArrayBytes(16 * m, d) +
		        fmArrayBytes(m + 1, sizeof(int)) + fmArrayBytes(2 * m, sizeof(int));
	return body;
}

// What a body allocates (body.c, force_spring.c, force_fvm.c) and what the implicit solver and
// the static solver add at their first use (solver_cache.c fmSolverCache_Get, bsr.c fmBsr_Build):
// counted for every body, since fmWorld_SetIntegrator() and fmBody_SolveStatic() may need them
// later. Two counts depend on the connectivity and are estimated: the edges E, from Euler's
// formula for a solid (V - E + F - T = 1 with F = 2 T + B / 2 faces for B boundary triangles:
// E ~ V + T + B / 2, at most 6 T), which sets the matrix blocks V + 2 E; and B, about 6 T^(2/3).
fmBodyMemory fmBodyMemoryOf(int nodeCount, int tetCount, const fmBodyDef* def)
{
	fmBodyMemory memory = {0, 0};
	if (nodeCount <= 0 || tetCount <= 0)
		return memory;
	const uint64_t n = (uint64_t)nodeCount, m = (uint64_t)tetCount, d = sizeof(double);
	uint64_t surface = (uint64_t)(6.0 * cbrt((double)m * (double)m)) + 4;
	surface = surface < 4 * m ? surface : 4 * m;
	uint64_t edges = n + m + surface / 2 < 6 * m ? n + m + surface / 2 : 6 * m;
	if (n < 1u << 20 && edges > n * (n - 1) / 2)
		edges = n * (n - 1) / 2;
	bool springs = def && def->forceModel == fm_massSpring;

	// The body: 6 vectors of 3n doubles, 3 of n doubles, pins, tets, rest data, surface, the
	// two vectors of 3n doubles it may need in the world's step arena, and the previous
	// positions fmWorld_Advance keeps.
	uint64_t body = 9 * fmArrayBytes(3 * n, d) + 3 * fmArrayBytes(n, d) + fmArrayBytes(n, 1) +
	                2 * fmArrayBytes(4 * m, sizeof(int)) + fmArrayBytes(n + 1, sizeof(int)) +
	                fmArrayBytes(m, sizeof(fmMat3)) + fmArrayBytes(m, d) +
	                fmArrayBytes(3 * surface, sizeof(int)) + 64;
	// The user's numbering: two vertex maps, the user's masses, tets, tet map and surface.
	body += 2 * fmArrayBytes(n, sizeof(int)) + fmArrayBytes(n, d) +
	        fmArrayBytes(5 * m, sizeof(int)) + fmArrayBytes(3 * surface, sizeof(int));
	if (springs)
		body += fmArrayBytes(2 * edges, sizeof(int)) + 2 * fmArrayBytes(edges, d);
	if (def && def->forceModel == fm_fvm)
		body += fmArrayBytes(4 * m, sizeof(fmVec3));
	if (def && def->tetFibres != NULL) // per-tet fibres
		body += fmArrayBytes(m, sizeof(fmVec3));
	body += fmMaterialStateBytes(def, n, m);
	if (def && def->regionCount > 0 && def->regionCount <= FM_MAX_REGIONS) // per-region materials
		body += fmArrayBytes(m, sizeof(uint16_t)) +
		        fmArrayBytes((uint64_t)def->regionCount + 1, sizeof(fmMaterial));

	// The implicit cache: slots (16 ints a tet, 4 a spring), the Hessian's blocks (9 doubles, a
	// second matrix for damping), the block pattern, 3x3 preconditioner blocks, 11 vectors, the
	// floor bounds and the best state (statics), the static solver's equilibrium, and for a body
	// of FM_MG_MIN_ROWS vertices or more the multigrid levels.
	// The nodal pressure's pattern is the tet graph's square: 3.7 times its blocks on the house,
	// 4.0 on a 16^3 box (fmBsr_Square), counted as 5.
	uint64_t blocks = (n + 2 * edges) * (fmDefAny(def, fmHasNodalPressure) ? 5 : 1);
	bool damping = def && (def->rayleighStiffness > 0.0 || (springs && def->springDamping > 0.0));
	uint64_t solver =
	    fmArrayBytes(16 * m, sizeof(int)) + (damping ? 2 : 1) * fmArrayBytes(9 * blocks, d) +
	    fmArrayBytes(n + 1, sizeof(int)) + fmArrayBytes(blocks, sizeof(int)) +
	    fmArrayBytes(n, sizeof(int)) + fmArrayBytes(9 * n, d) + 7 * fmArrayBytes(3 * n, d) +
	    fmArrayBytes(12 * n, d) + fmArrayBytes(3 * n, 1) + fmArrayBytes(n, d) +
	    2 * fmArrayBytes(3 * n, d) + 1024;
	if (springs)
		solver += fmArrayBytes(4 * edges, sizeof(int));
	if (n >= FM_MG_MIN_ROWS) // the multigrid preconditioner's levels
		solver += fmMultigrid_EstimateBytes((size_t)n, (size_t)blocks);
	// An explicit world's FEM bodies have the batched kernels' layout instead (the larger of the
	// two: a world has one integrator).
	uint64_t layout = def == NULL || def->forceModel == fm_fem ? fmTetBlocks_Bytes(m, n) : 0;
	solver = layout > solver ? layout : solver;
	memory.body = body > SIZE_MAX ? SIZE_MAX : (size_t)body;
	memory.solver = solver > SIZE_MAX ? SIZE_MAX : (size_t)solver;
	return memory;
}

size_t fmEstimateBodyMemory(const fmBodyDef* def)
{
	FM_ASSERT(def != NULL);
	if (def == NULL || def->mesh == NULL)
		return 0;
	fmBodyMemory memory = fmBodyMemoryOf(def->mesh->nodeCount, def->mesh->tetCount, def);
	return memory.body > SIZE_MAX - memory.solver ? SIZE_MAX : memory.body + memory.solver;
}
