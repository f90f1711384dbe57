// A scene's bodies (docs/scene-format.md, docs/loads.md): one entry of "bodies" checked key by
// key (json_check.h) into a cliBodySpec.
#include "scene_body.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Largest generated box, cells per axis (6 tets a cell; 400^3 cells is already 384M tets).
#define CLI_MAX_BOX_CELLS 1000

// ---- anisotropy ------------------------------------------------------------------------------

static bool cliIsOrthotropic(fmMaterialModel model)
{
	return model == fm_orthotropicLinear || model == fm_orthotropicStvk;
}

// "orthotropy": {"E": [E1, E2, E3], "nu": [nu12, nu13, nu23], "G": [G12, G13, G23]}.
static bool cliParseOrthotropy(const cliJson* j, const cliJsonNode* object, const char* path,
                               fmOrthotropy* o)
{
	static const char* const keys[] = {"E", "nu", "G", NULL};
	fmVec3 E, nu, G;
	if (!cliCheckKeys(j, object, path, keys) ||
	    !cliRequireKeys(j, object, path, keys, "the nine engineering constants") ||
	    !cliGetVec3In(j, object, path, "E", cliPositive, "Young's moduli > 0 (Pa)", &E) ||
	    !cliGetVec3In(j, object, path, "nu", cliAnyFinite, "Poisson ratios", &nu) ||
	    !cliGetVec3In(j, object, path, "G", cliPositive, "shear moduli > 0 (Pa)", &G))
		return false;
	const fmOrthotropy read = {{E.x, E.y, E.z}, {nu.x, nu.y, nu.z}, {G.x, G.y, G.z}};
	*o = read;
	return true;
}

// "transversely_isotropic": {"E_along", "E_across", "nu_along", "nu_across", "G_along"}.
static bool cliParseTransverse(const cliJson* j, const cliJsonNode* object, const char* path,
                               fmOrthotropy* o)
{
	static const char* const keys[] = {"E_along",   "E_across", "nu_along",
	                                   "nu_across", "G_along",  NULL};
	const cliRange poisson = {-1.0, 1.0, true, true};
	double v[5];
	if (!cliCheckKeys(j, object, path, keys) ||
	    !cliRequireKeys(j, object, path, keys, "a transversely isotropic solid's five constants"))
		return false;
	for (int k = 0; k < 5; ++k)
		if (!cliGetNumber(j, object, path, keys[k], k == 2 || k == 3 ? poisson : cliPositive, &v[k],
		                  NULL))
			return false;
	*o = fmTransverselyIsotropic(v[0], v[1], v[2], v[3], v[4]);
	return true;
}

// The anisotropic models' keys of a material object (docs/materials.md, "Anisotropy"):
// "orthotropy" or "transversely_isotropic" for the orthotropic models (in place of
// youngs_modulus and poisson_ratio: @p isotropicGiven; a region's material may keep the constants
// @p m already has: @p inherited), "fibre_stiffness" for fibre-neohookean, "fibre" and "sheet"
// (the axes) for all three.
static bool cliParseAnisotropy(const cliJson* j, const cliJsonNode* object, const char* path,
                               bool isotropicGiven, bool inherited, fmMaterial* m)
{
	const cliJsonNode *ortho = NULL, *transverse = NULL;
	if (!cliGetObject(j, object, path, "orthotropy", &ortho) ||
	    !cliGetObject(j, object, path, "transversely_isotropic", &transverse))
		return false;
	bool orthotropic = cliIsOrthotropic(m->model);
	bool anisotropic = orthotropic || m->model == fm_fibreNeoHookean;
	if (orthotropic && ortho == NULL && transverse == NULL && !inherited)
		return cliJsonFail(j, path, NULL,
		                   "model %s needs \"orthotropy\": {\"E\": [E1, E2, E3], \"nu\": [nu12, "
		                   "nu13, nu23], \"G\": [G12, G13, G23]} or \"transversely_isotropic\": "
		                   "{\"E_along\", \"E_across\", \"nu_along\", \"nu_across\", \"G_along\"}",
		                   fmMaterialModelName(m->model));
	if (ortho != NULL && transverse != NULL)
		return cliJsonFail(j, path, NULL, "give orthotropy or transversely_isotropic, not both");
	if (orthotropic && isotropicGiven)
		return cliJsonFail(j, path, NULL,
		                   "model %s takes its constants from orthotropy (or "
		                   "transversely_isotropic), not youngs_modulus, poisson_ratio, lambda, mu",
		                   fmMaterialModelName(m->model));
	static const char* const only[4] = {"orthotropy", "transversely_isotropic", "fibre_stiffness",
	                                    NULL};
	for (int k = 0; k < 3; ++k)
		if (cliJsonTree_Member(object, only[k]) != NULL &&
		    (k < 2 ? !orthotropic : m->model != fm_fibreNeoHookean))
		{
			char keyPath[300];
			cliJoinKey(keyPath, sizeof keyPath, path, only[k]);
			return cliJsonFail(j, keyPath, NULL, "only goes with \"model\": %s",
			                   k < 2 ? "\"orthotropic-linear\" or \"orthotropic-stvk\""
			                         : "\"fibre-neohookean\"");
		}
	char sub[300];
	fmOrthotropy o;
	if (ortho != NULL)
	{
		cliJoinKey(sub, sizeof sub, path, "orthotropy");
		if (!cliParseOrthotropy(j, ortho, sub, &o))
			return false;
	}
	if (transverse != NULL)
	{
		cliJoinKey(sub, sizeof sub, path, "transversely_isotropic");
		if (!cliParseTransverse(j, transverse, sub, &o))
			return false;
	}
	if (orthotropic && (ortho != NULL || transverse != NULL))
	{
		fmVec3 fibre = m->fibre, sheet = m->sheet;
		*m = fmMakeOrthotropicMaterial(m->model, o);
		m->fibre = fibre, m->sheet = sheet;
	}
	bool hasFibre = false, hasSheet = false;
	if (!cliGetNumber(j, object, path, "fibre_stiffness", cliNonNegative, &m->fibreStiffness,
	                  NULL) ||
	    !cliGetVec3(j, object, path, "fibre", &m->fibre, &hasFibre) ||
	    !cliGetVec3(j, object, path, "sheet", &m->sheet, &hasSheet))
		return false;
	if ((hasFibre || hasSheet) && !anisotropic)
		return cliJsonFail(j, path, NULL,
		                   "fibre and sheet (material axes) only go with the anisotropic models "
		                   "(\"orthotropic-linear\", \"orthotropic-stvk\", \"fibre-neohookean\")");
	return true;
}

// "fibres": {"attributes": k} (tet attributes k, k + 1, k + 2: a direction each tet) or
// {"around": [x, y, z], "through": [x, y, z]} (circumferential about that line).
static bool cliParseFibres(const cliJson* j, const cliJsonNode* body, const char* parent,
                           cliFibres* fibres)
{
	static const char* const keys[] = {"attributes", "around", "through", NULL};
	const cliJsonNode* object = NULL;
	if (!cliGetObject(j, body, parent, "fibres", &object))
		return false;
	if (object == NULL)
		return true;
	char path[300];
	cliJoinKey(path, sizeof path, parent, "fibres");
	bool hasAttributes = false, hasAround = false;
	if (!cliCheckKeys(j, object, path, keys) ||
	    !cliGetInt(j, object, path, "attributes", 0, 1000000, &fibres->attribute, &hasAttributes) ||
	    !cliGetVec3(j, object, path, "around", &fibres->axis, &hasAround) ||
	    !cliGetVec3(j, object, path, "through", &fibres->point, NULL))
		return false;
	if (hasAttributes == hasAround)
		return cliJsonFail(j, path, NULL,
		                   "expected {\"attributes\": k} (the mesh's tet attributes k, k+1, k+2) "
		                   "or {\"around\": [x, y, z], \"through\": [x, y, z]}");
	if (hasAround && !(fmLength(fibres->axis) > 0.0))
		return cliJsonFail(j, path, NULL, "\"around\" must be a direction, not [0, 0, 0]");
	if (cliJsonTree_Member(object, "through") != NULL && !hasAround)
		return cliJsonFail(j, path, NULL, "\"through\" goes with \"around\"");
	fibres->source = hasAround ? cli_fibresAround : cli_fibresAttributes;
	return true;
}

fmVec3* cliBodyFibres(const cliBodySpec* spec, const fmTetMesh* mesh, char* problem, size_t size)
{
	problem[0] = 0;
	const cliFibres* rule = &spec->fibres;
	if (rule->source == cli_fibresNone)
		return NULL;
	int k = rule->attribute, count = mesh->tetAttributeCount;
	if (rule->source == cli_fibresAttributes && (mesh->tetAttributes == NULL || k + 3 > count))
	{
		snprintf(problem, size,
		         "fibres.attributes %d needs tet attributes %d to %d; the mesh has %d per tet", k,
		         k, k + 2, count);
		return NULL;
	}
	fmVec3* fibres = malloc(sizeof(fmVec3) * (size_t)(mesh->tetCount > 0 ? mesh->tetCount : 1));
	if (fibres == NULL)
	{
		snprintf(problem, size, "out of memory for %d fibres", mesh->tetCount);
		return NULL;
	}
	for (int t = 0; t < mesh->tetCount; ++t)
	{
		if (rule->source == cli_fibresAttributes)
		{
			const double* a = mesh->tetAttributes + (size_t)t * (size_t)count + (size_t)k;
			// The placement's y-z swap turns directions as it turns positions.
			fibres[t] = spec->transform.swapYZ ? fmMakeVec3(a[0], a[2], a[1])
			                                   : fmMakeVec3(a[0], a[1], a[2]);
			continue;
		}
		fmVec3 c = {0, 0, 0};
		for (int n = 0; n < 4; ++n)
		{
			int node = mesh->tets[4 * t + n] - mesh->firstIndex;
			c = fmAdd(c, fmScale(0.25, fmMakeVec3(mesh->positions[3 * node],
			                                      mesh->positions[3 * node + 1],
			                                      mesh->positions[3 * node + 2])));
		}
		fmVec3 hoop = fmCross(rule->axis, fmSub(c, rule->point));
		// A tet on the line itself has no circumference: its fibre runs along the line.
		fibres[t] = fmLength(hoop) > 1e-12 * fmLength(rule->axis) ? hoop : rule->axis;
	}
	return fibres;
}

// "plasticity": {"yield_stress": Pa or "yield_strain": (times Young's modulus), "hardening": Pa,
// "creep_rate": 1/s, "max_plastic_strain"} (fmPlasticity; docs/materials.md, "Plasticity").
// "fracture": {"strength": Pa, "length": m, "min_volume": m^3} (fmFracture).
static bool cliParseFracture(const cliJson* j, const cliJsonNode* object, const char* parent,
                             fmMaterial* m)
{
	static const char* const keys[] = {"strength", "length", "min_volume", NULL};
	const cliJsonNode* fracture = NULL;
	if (!cliGetObject(j, object, parent, "fracture", &fracture))
		return false;
	if (fracture == NULL)
		return true;
	char path[300];
	cliJoinKey(path, sizeof path, parent, "fracture");
	fmFracture* f = &m->fracture;
	bool hasStrength = false;
	if (!cliCheckKeys(j, fracture, path, keys) ||
	    !cliGetNumber(j, fracture, path, "strength", cliPositive, &f->strength, &hasStrength) ||
	    !cliGetNumber(j, fracture, path, "length", cliNonNegative, &f->length, NULL) ||
	    !cliGetNumber(j, fracture, path, "min_volume", cliNonNegative, &f->minVolume, NULL))
		return false;
	if (!hasStrength)
		return cliJsonFail(j, path, NULL, "expected \"strength\" (Pa): the tensile strength");
	return true;
}

static bool cliParsePlasticity(const cliJson* j, const cliJsonNode* object, const char* parent,
                               fmMaterial* m)
{
	static const char* const keys[] = {"yield_stress", "yield_strain",       "hardening",
	                                   "creep_rate",   "max_plastic_strain", NULL};
	const cliJsonNode* plastic = NULL;
	if (!cliGetObject(j, object, parent, "plasticity", &plastic))
		return false;
	if (plastic == NULL)
		return true;
	char path[300];
	cliJoinKey(path, sizeof path, parent, "plasticity");
	fmPlasticity* p = &m->plasticity;
	bool hasStress = false, hasStrain = false;
	double strain = 0.0;
	if (!cliCheckKeys(j, plastic, path, keys) ||
	    !cliGetNumber(j, plastic, path, "yield_stress", cliPositive, &p->yieldStress, &hasStress) ||
	    !cliGetNumber(j, plastic, path, "yield_strain", cliPositive, &strain, &hasStrain) ||
	    !cliGetNumber(j, plastic, path, "hardening", cliNonNegative, &p->hardening, NULL) ||
	    !cliGetNumber(j, plastic, path, "creep_rate", cliNonNegative, &p->creepRate, NULL) ||
	    !cliGetNumber(j, plastic, path, "max_plastic_strain", cliNonNegative, &p->maxPlasticStrain,
	                  NULL))
		return false;
	if (hasStress == hasStrain)
		return cliJsonFail(j, path, NULL,
		                   "give yield_stress (Pa) or yield_strain (times Young's modulus), one "
		                   "of them");
	if (hasStrain) // E = mu (3 lambda + 2 mu) / (lambda + mu)
		p->yieldStress = strain * m->mu * (3.0 * m->lambda + 2.0 * m->mu) / (m->lambda + m->mu);
	return true;
}

// ---- mesh, placement, material --------------------------------------------------------------

// "box:nx,ny,nz" -> cell counts. On failure @p problem says what was wrong.
static bool cliParseBoxSpec(const char* spec, int cells[3], char* problem, size_t size)
{
	const char* at = spec + 4;
	snprintf(problem, size, "expected \"box:nx,ny,nz\" with counts in [1, %d]", CLI_MAX_BOX_CELLS);
	for (int axis = 0; axis < 3; ++axis)
	{
		char* end = NULL;
		errno = 0;
		long count = strtol(at, &end, 10);
		if (end == at)
			return false;
		if (errno == ERANGE || count > CLI_MAX_BOX_CELLS)
		{
			snprintf(problem, size, "box cell count %.*s is too large (at most %d)",
			         (int)(end - at > 24 ? 24 : end - at), at, CLI_MAX_BOX_CELLS);
			return false;
		}
		if (count < 1)
		{
			snprintf(problem, size, "box cell count %ld is too small (at least 1)", count);
			return false;
		}
		cells[axis] = (int)count;
		if (axis < 2 && *end != ',')
			return false;
		at = end + (axis < 2 ? 1 : 0);
		if (axis == 2 && *end != 0)
			return false;
	}
	return true;
}

static bool cliParseMesh(const cliJson* j, const cliJsonNode* body, const char* parent,
                         cliBodySpec* spec)
{
	char path[256];
	cliJoinKey(path, sizeof path, parent, "mesh");
	const cliJsonNode* item = cliJsonTree_Member(body, "mesh");
	if (item == NULL)
		return cliJsonFail(
		    j, parent, NULL,
		    "missing \"mesh\" (a .node path, \"builtin:house2\" or \"box:nx,ny,nz\")");
	if (!cliJsonIs(item, cli_jsonString) || item->string == NULL || item->string[0] == 0)
		return cliJsonFail(j, path, item,
		                   "expected a .node path, \"builtin:house2\" or \"box:nx,ny,nz\"");
	const char* text = item->string;
	bool hasMin = false, hasMax = false;
	spec->boxMin = fmMakeVec3(0, 0, 0);
	spec->boxMax = fmMakeVec3(1, 1, 1);
	if (!cliGetVec3(j, body, parent, "box_min", &spec->boxMin, &hasMin) ||
	    !cliGetVec3(j, body, parent, "box_max", &spec->boxMax, &hasMax))
		return false;
	if (strncmp(text, "box:", 4) == 0)
	{
		spec->meshSource = cli_meshBox;
		char problem[128];
		if (!cliParseBoxSpec(text, spec->boxCells, problem, sizeof problem))
			return cliJsonFail(j, path, item, "%s", problem);
		double tets = 6.0 * spec->boxCells[0] * spec->boxCells[1] * spec->boxCells[2];
		if (tets > (double)FM_MAX_TETS)
			return cliJsonFail(j, path, item, "box of %.0f tets exceeds the %d tet limit", tets,
			                   FM_MAX_TETS);
		if (!(spec->boxMin.x < spec->boxMax.x && spec->boxMin.y < spec->boxMax.y &&
		      spec->boxMin.z < spec->boxMax.z))
			return cliJsonFail(j, parent, NULL, "box_min must be below box_max on every axis");
		return true;
	}
	if (hasMin || hasMax)
		return cliJsonFail(j, parent, NULL, "box_min and box_max only go with a \"box:\" mesh");
	if (strcmp(text, "builtin:house2") == 0)
	{
		spec->meshSource = cli_meshHouse;
		return true;
	}
	if (strncmp(text, "builtin:", 8) == 0)
		return cliJsonFail(j, path, item,
		                   "unknown built-in mesh (the one there is: builtin:house2)");
	// Any mesh file femto reads, by its extension (fmLoadMesh); a .node brings its .ele.
	size_t length = strlen(text);
	bool isNode = length >= 5 && strcmp(text + length - 5, ".node") == 0;
	if (fmMeshFormatFromPath(text) == fm_meshFormatUnknown)
		return cliJsonFail(j, path, item,
		                   "expected a mesh file (.node, .msh, .vtk, .vtu, .mesh), "
		                   "\"builtin:house2\" or \"box:nx,ny,nz\"");
	spec->meshSource = cli_meshFile;
	if (!cliResolveFile(j, path, item, text, spec->nodePath, sizeof spec->nodePath))
		return false;
	memcpy(spec->elePath, spec->nodePath, sizeof spec->elePath);
	if (isNode)
		memcpy(spec->elePath + strlen(spec->elePath) - 5, ".ele", 5);
	const char* why = isNode ? cliFileUnreadable(spec->elePath) : NULL;
	if (why != NULL)
		return cliJsonFail(j, path, NULL, "cannot open %s: %s (the .ele beside the .node)",
		                   spec->elePath, why);
	return true;
}

// A body's or a mesh collider's "transform" (the identity when absent).
bool cliParseTransform(const cliJson* j, const cliJsonNode* object, const char* parent,
                       fmMeshTransform* out)
{
	static const char* const keys[] = {"scale", "center", "swap_yz", "translate", NULL};
	char path[256];
	cliJoinKey(path, sizeof path, parent, "transform");
	const cliJsonNode* transform = NULL;
	*out = fmDefaultMeshTransform();
	if (!cliGetObject(j, object, parent, "transform", &transform))
		return false;
	if (transform == NULL)
		return true;
	return cliCheckKeys(j, transform, path, keys) &&
	       cliGetNumber(j, transform, path, "scale", cliPositive, &out->scale, NULL) &&
	       cliGetBool(j, transform, path, "center", &out->center) &&
	       cliGetBool(j, transform, path, "swap_yz", &out->swapYZ) &&
	       cliGetVec3(j, transform, path, "translate", &out->translate, NULL);
}

// A material's "density" or "particle_mass" (one of them), which set the body's mass mode.
static bool cliParseMass(const cliJson* j, const cliJsonNode* material, const char* path,
                         cliBodySpec* spec)
{
	bool hasDensity = false, hasParticleMass = false;
	if (!cliGetNumber(j, material, path, "density", cliPositive, &spec->def.density, &hasDensity) ||
	    !cliGetNumber(j, material, path, "particle_mass", cliPositive, &spec->def.particleMass,
	                  &hasParticleMass))
		return false;
	if (hasDensity && hasParticleMass)
		return cliJsonFail(j, path, NULL, "give density or particle_mass, not both");
	if (hasDensity)
		spec->def.massMode = fm_massFromDensity;
	if (hasParticleMass)
		spec->def.massMode = fm_massPerParticle;
	return true;
}

// The body material's keys after its constants: "mooney_c01" (mooney-rivlin only), the
// anisotropic models' keys, "plasticity", "fracture", "nodal_pressure".
static bool cliParseMaterialExtras(const cliJson* j, const cliJsonNode* material, const char* path,
                                   bool constants, fmMaterial* m)
{
	bool hasC01 = false;
	if (!cliGetNumber(j, material, path, "mooney_c01", cliNonNegative, &m->c01, &hasC01))
		return false;
	if (hasC01 && m->model != fm_mooneyRivlin)
		return cliJsonFail(j, path, NULL,
		                   "mooney_c01 only applies to \"model\": \"mooney-rivlin\"");
	return cliParseAnisotropy(j, material, path, constants, false, m) &&
	       cliParsePlasticity(j, material, path, m) && cliParseFracture(j, material, path, m) &&
	       cliGetBool(j, material, path, "nodal_pressure", &m->nodalPressure);
}

static bool cliParseMaterial(const cliJson* j, const cliJsonNode* body, const char* parent,
                             cliBodySpec* spec)
{
	static const char* const keys[] = {"model",
	                                   "youngs_modulus",
	                                   "poisson_ratio",
	                                   "lambda",
	                                   "mu",
	                                   "mooney_c01",
	                                   "density",
	                                   "particle_mass",
	                                   "orthotropy",
	                                   "fibre",
	                                   "sheet",
	                                   "fibre_stiffness",
	                                   "transversely_isotropic",
	                                   "plasticity",
	                                   "nodal_pressure",
	                                   "fracture",
	                                   NULL};
	char path[256];
	cliJoinKey(path, sizeof path, parent, "material");
	const cliJsonNode* material = NULL;
	if (!cliGetObject(j, body, parent, "material", &material))
		return false;
	if (material == NULL)
		return true; // the default body's material (the seeds' StVK)
	if (!cliCheckKeys(j, material, path, keys))
		return false;

	fmMaterialModel model = spec->def.material.model;
	const char* modelName = NULL;
	if (!cliGetString(j, material, path, "model", &modelName))
		return false;
	if (modelName != NULL && !fmMaterialModelFromName(modelName, &model))
	{
		char modelPath[256];
		cliJoinKey(modelPath, sizeof modelPath, path, "model");
		return cliJsonFail(j, modelPath, cliJsonTree_Member(material, "model"),
		                   "expected \"linear\", \"corotated\", \"stvk\", \"neohookean\", "
		                   "\"mooney-rivlin\", \"neohookean-isochoric\", \"orthotropic-linear\", "
		                   "\"orthotropic-stvk\" or \"fibre-neohookean\"");
	}

	double youngs = 0, poisson = 0, lambda = 0, mu = 0;
	bool hasE = false, hasNu = false, hasLambda = false, hasMu = false;
	const cliRange poissonRange = {-1.0, 0.5, true, true};
	if (!cliGetNumber(j, material, path, "youngs_modulus", cliPositive, &youngs, &hasE) ||
	    !cliGetNumber(j, material, path, "poisson_ratio", poissonRange, &poisson, &hasNu) ||
	    !cliGetNumber(j, material, path, "lambda", cliAnyFinite, &lambda, &hasLambda) ||
	    !cliGetNumber(j, material, path, "mu", cliPositive, &mu, &hasMu))
		return false;
	bool engineering = hasE || hasNu, lame = hasLambda || hasMu;
	if (engineering && lame)
		return cliJsonFail(j, path, NULL,
		                   "give youngs_modulus + poisson_ratio or lambda + mu, not both pairs");
	if (engineering && !(hasE && hasNu))
		return cliJsonFail(j, path, NULL, "youngs_modulus and poisson_ratio go together");
	if (lame && !(hasLambda && hasMu))
		return cliJsonFail(j, path, NULL, "lambda and mu go together");
	if (engineering)
		spec->def.material = fmMakeMaterial(model, youngs, poisson);
	else if (lame)
		spec->def.material = fmMakeMaterialLame(model, lambda, mu);
	else
		spec->def.material =
		    fmMakeMaterialLame(model, spec->def.material.lambda, spec->def.material.mu);

	if (!cliParseMaterialExtras(j, material, path, engineering || lame, &spec->def.material))
		return false;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmMaterial_Validate(&spec->def.material, &diag) != fm_ok)
		return cliJsonFail(j, path, NULL, "%s",
		                   diag.message[0] ? diag.message : "invalid material");

	return cliParseMass(j, material, path, spec);
}

fmMaterial cliKeepNodalPressure(fmMaterial material, bool nodalPressure)
{
	fmMaterial probe = fmMakeMaterialLame(material.model, 1.0, 1.0);
	probe.nodalPressure = true;
	material.nodalPressure = nodalPressure && fmMaterial_Validate(&probe, NULL) == fm_ok;
	return material;
}

// ---- regions --------------------------------------------------------------------------------

// One region's material: the body's material changed by the keys given ("model", and
// "youngs_modulus" + "poisson_ratio" or "lambda" + "mu", "mooney_c01", the anisotropic models'
// keys), validated.
static bool cliParseRegionMaterial(const cliJson* j, const cliJsonNode* object, const char* path,
                                   const fmMaterial* base, fmMaterial* out)
{
	static const char* const keys[] = {
	    "model",           "youngs_modulus", "poisson_ratio",          "lambda",   "mu",
	    "mooney_c01",      "orthotropy",     "transversely_isotropic", "fibre",    "sheet",
	    "fibre_stiffness", "plasticity",     "nodal_pressure",         "fracture", NULL};
	if (!cliJsonIs(object, cli_jsonObject))
		return cliJsonFail(j, path, object,
		                   "expected a material {\"model\": ..., \"youngs_modulus\": ..., "
		                   "\"poisson_ratio\": ...}");
	if (!cliCheckKeys(j, object, path, keys))
		return false;
	fmMaterialModel model = base->model;
	const char* name = NULL;
	if (!cliGetString(j, object, path, "model", &name))
		return false;
	if (name != NULL && !fmMaterialModelFromName(name, &model))
	{
		char modelPath[300];
		cliJoinKey(modelPath, sizeof modelPath, path, "model");
		return cliJsonFail(j, modelPath, cliJsonTree_Member(object, "model"),
		                   "unknown material model (docs/materials.md lists them)");
	}
	double youngs = 0, poisson = 0, lambda = base->lambda, mu = base->mu;
	bool hasE = false, hasNu = false, hasLambda = false, hasMu = false, hasC01 = false;
	const cliRange poissonRange = {-1.0, 0.5, true, true};
	if (!cliGetNumber(j, object, path, "youngs_modulus", cliPositive, &youngs, &hasE) ||
	    !cliGetNumber(j, object, path, "poisson_ratio", poissonRange, &poisson, &hasNu) ||
	    !cliGetNumber(j, object, path, "lambda", cliAnyFinite, &lambda, &hasLambda) ||
	    !cliGetNumber(j, object, path, "mu", cliPositive, &mu, &hasMu))
		return false;
	if ((hasE || hasNu) && (hasLambda || hasMu))
		return cliJsonFail(j, path, NULL,
		                   "give youngs_modulus + poisson_ratio or lambda + mu, not both pairs");
	if (hasE != hasNu || hasLambda != hasMu)
		return cliJsonFail(j, path, NULL,
		                   "youngs_modulus and poisson_ratio (or lambda and mu) go together");
	// The body's material with what the region changes: its plasticity, axes and constants
	// stay unless given, those of another model's do not carry over.
	fmMaterial made =
	    hasE ? fmMakeMaterial(model, youngs, poisson) : fmMakeMaterialLame(model, lambda, mu);
	*out = *base;
	out->model = model;
	out->lambda = made.lambda;
	out->mu = made.mu;
	if (model != base->model)
	{
		out->c01 = made.c01;
		out->fibreStiffness = 0.0;
		memset(&out->orthotropy, 0, sizeof out->orthotropy);
		bool flows = model == fm_stvk || model == fm_corotated || model == fm_neoHookean ||
		             model == fm_mooneyRivlin || model == fm_neoHookeanIsochoric;
		if (!flows) // (a model plasticity does not go with leaves it)
			memset(&out->plasticity, 0, sizeof out->plasticity);
		// and a model the nodal pressure does not go with leaves it (unless the region asks)
		*out = cliKeepNodalPressure(*out, out->nodalPressure);
	}
	bool inherited = model == base->model;
	if (!cliGetNumber(j, object, path, "mooney_c01", cliNonNegative, &out->c01, &hasC01) ||
	    !cliParseAnisotropy(j, object, path, hasE || hasLambda, inherited, out) ||
	    !cliParsePlasticity(j, object, path, out) || !cliParseFracture(j, object, path, out) ||
	    !cliGetBool(j, object, path, "nodal_pressure", &out->nodalPressure))
		return false;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmMaterial_Validate(out, &diag) != fm_ok)
		return cliJsonFail(j, path, NULL, "%s",
		                   diag.message[0] ? diag.message : "invalid material");
	return true;
}

// "regions": {"1": {material}, "2": {...}}: a material per region number of the mesh (its tets'
// first attribute: TetGen's region attribute, Gmsh's physical group).
static bool cliParseRegions(const cliJson* j, const cliJsonNode* body, const char* parent,
                            cliBodySpec* spec)
{
	char path[256];
	cliJoinKey(path, sizeof path, parent, "regions");
	const cliJsonNode* regions = NULL;
	if (!cliGetObject(j, body, parent, "regions", &regions))
		return false;
	if (regions == NULL)
		return true;
	int count = (regions)->count;
	if (count < 1 || count > FM_MAX_REGIONS)
		return cliJsonFail(j, path, NULL, "expected 1 to %d regions {\"1\": {material}, ...}",
		                   FM_MAX_REGIONS);
	spec->regionMaterials = calloc((size_t)count, sizeof *spec->regionMaterials);
	spec->regionIds = calloc((size_t)count, sizeof *spec->regionIds);
	if (spec->regionMaterials == NULL || spec->regionIds == NULL)
		return cliJsonFail(j, path, NULL, "out of memory");
	int i = 0;
	const cliJsonNode* region = NULL;
	for (region = (regions)->child; region != NULL; region = region->next)
	{
		char regionPath[300];
		cliJoinKey(regionPath, sizeof regionPath, path, region->key);
		char* end = NULL;
		errno = 0;
		long id = strtol(region->key, &end, 10);
		if (region->key[0] == 0 || *end != 0 || errno != 0 || id < INT_MIN || id > INT_MAX)
			return cliJsonFail(j, regionPath, NULL,
			                   "a region is named by its number in the mesh, e.g. \"1\"");
		for (int other = 0; other < i; ++other)
			if (spec->regionIds[other] == (int)id)
				return cliJsonFail(j, regionPath, NULL, "region %ld is given twice", id);
		spec->regionIds[i] = (int)id;
		if (!cliParseRegionMaterial(j, region, regionPath, &spec->def.material,
		                            &spec->regionMaterials[i]))
			return false;
		++i;
	}
	spec->def.regionMaterials = spec->regionMaterials;
	spec->def.regionIds = spec->regionIds;
	spec->def.regionCount = i;
	return true;
}

// ---- pins, loads, pressures and attachments: lists of boxes read by cliGetEntries ------------

// A body's keys for loads and per-region materials (docs/scene-format.md, docs/loads.md).
#define CLI_BODY_LOAD_KEYS "loads", "pressure", "regions", "attachments", "welds"

// "axes": a string of the letters x, y, z, each at most once (e.g. "y", "xz").
static bool cliGetAxes(const cliJson* j, const cliJsonNode* box, const char* boxPath,
                       unsigned* axes)
{
	const cliJsonNode* item = cliJsonTree_Member(box, "axes");
	if (item == NULL)
		return true;
	char path[300];
	cliJoinKey(path, sizeof path, boxPath, "axes");
	const char* text = cliJsonIs(item, cli_jsonString) ? item->string : NULL;
	unsigned bits = 0;
	for (const char* c = text; c != NULL && *c != 0; ++c)
	{
		unsigned bit = *c == 'x' ? 1u : *c == 'y' ? 2u : *c == 'z' ? 4u : 0u;
		if (bit == 0 || (bits & bit))
		{
			bits = 0;
			break;
		}
		bits |= bit;
	}
	if (bits == 0)
		return cliJsonFail(j, path, item,
		                   "expected the axes the pin holds: \"x\", \"y\", \"z\" or several "
		                   "of them, each once (e.g. \"xz\")");
	*axes = bits;
	return true;
}

// A pin entry's "axes", "displacement" and "time".
static bool cliParsePinExtras(const cliJson* j, const cliJsonNode* box, const char* boxPath,
                              cliPinBox* pin)
{
	pin->axes = 7u;
	bool hasTime = false;
	const cliRange timeRange = {0.0, 1e9, false, false};
	if (!cliGetAxes(j, box, boxPath, &pin->axes) ||
	    !cliGetVec3(j, box, boxPath, "displacement", &pin->displacement, &pin->hasDisplacement) ||
	    !cliGetNumber(j, box, boxPath, "time", timeRange, &pin->time, &hasTime))
		return false;
	char path[300];
	cliJoinKey(path, sizeof path, boxPath, hasTime ? "time" : "displacement");
	if (hasTime && !pin->hasDisplacement)
		return cliJsonFail(j, path, NULL,
		                   "\"time\" is the time a \"displacement\" takes: give "
		                   "the displacement too");
	const double d[3] = {pin->displacement.x, pin->displacement.y, pin->displacement.z};
	for (int axis = 0; pin->hasDisplacement && axis < 3; ++axis)
	{
		if (fabs(d[axis]) > FM_MAX_COORDINATE)
			return cliJsonFail(j, path, NULL, "the displacement must be within %g m",
			                   FM_MAX_COORDINATE);
		if (d[axis] != 0.0 && !(pin->axes & (1u << axis)))
			return cliJsonFail(j, path, NULL,
			                   "the displacement moves %c, which the pin does not hold (its "
			                   "\"axes\"): add %c to the axes or set that component to 0",
			                   "xyz"[axis], "xyz"[axis]);
	}
	return true;
}

// "pin": [{"min": [..], "max": [..], "axes": "xz", "displacement": [..], "time": s}].
static bool cliReadPin(const cliJson* j, const cliJsonNode* box, const char* boxPath, void* out)
{
	cliPinBox* pin = out;
	bool hasMin = false, hasMax = false;
	if (!cliGetVec3(j, box, boxPath, "min", &pin->min, &hasMin) ||
	    !cliGetVec3(j, box, boxPath, "max", &pin->max, &hasMax))
		return false;
	if (!hasMin || !hasMax)
		return cliJsonFail(j, boxPath, NULL, "a pin box needs both \"min\" and \"max\"");
	if (!(pin->min.x <= pin->max.x && pin->min.y <= pin->max.y && pin->min.z <= pin->max.z))
		return cliJsonFail(j, boxPath, NULL, "min must not exceed max on any axis");
	return cliParsePinExtras(j, box, boxPath, pin);
}

// A load or pressure entry's "min" and "max": both given, finite, ordered.
static bool cliGetBox(const cliJson* j, const cliJsonNode* entry, const char* path, fmVec3* min,
                      fmVec3* max)
{
	bool hasMin = false, hasMax = false;
	if (!cliGetVec3(j, entry, path, "min", min, &hasMin) ||
	    !cliGetVec3(j, entry, path, "max", max, &hasMax))
		return false;
	if (!hasMin || !hasMax)
		return cliJsonFail(j, path, NULL, "a load box needs both \"min\" and \"max\"");
	if (!(min->x <= max->x && min->y <= max->y && min->z <= max->z))
		return cliJsonFail(j, path, NULL, "the box is empty: min must not exceed max on any axis");
	return true;
}

// "loads": [{"min": [..], "max": [..], "force": [fx, fy, fz]}] (N on each vertex in the box).
static bool cliReadLoad(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                        void* out)
{
	cliLoadBox* load = out;
	bool hasForce = false;
	if (!cliGetBox(j, entry, entryPath, &load->min, &load->max) ||
	    !cliGetVec3(j, entry, entryPath, "force", &load->force, &hasForce))
		return false;
	if (!hasForce)
		return cliJsonFail(j, entryPath, NULL,
		                   "a load needs \"force\": [fx, fy, fz] (N on each vertex)");
	return true;
}

// "pressure": [{"min": [..], "max": [..], "pressure": Pa, "follower": true}].
static bool cliReadPressure(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                            void* out)
{
	cliPressureBox* load = out;
	load->follower = true;
	bool hasPressure = false;
	if (!cliGetBox(j, entry, entryPath, &load->min, &load->max) ||
	    !cliGetNumber(j, entry, entryPath, "pressure", cliAnyFinite, &load->pressure,
	                  &hasPressure) ||
	    !cliGetBool(j, entry, entryPath, "follower", &load->follower))
		return false;
	if (!hasPressure)
		return cliJsonFail(j, entryPath, NULL,
		                   "a pressure entry needs \"pressure\": Pa (positive pushes into "
		                   "the body)");
	return true;
}

// An entry's spring: "stiffness" (N/m, kept when absent) and "damping_ratio" (default 1).
static bool cliGetSpring(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                         double* stiffness, double* ratio)
{
	const cliRange ratios = {0.0, 1e6, false, false};
	*ratio = 1.0;
	return cliGetNumber(j, entry, entryPath, "stiffness", cliPositive, stiffness, NULL) &&
	       cliGetNumber(j, entry, entryPath, "damping_ratio", ratios, ratio, NULL);
}

// An attachment's "collider" and spring (glue takes the library's default stiffness unless
// given; a kinematic attachment CLI_ATTACHMENT_STIFFNESS).
static bool cliReadGlue(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                        cliAttachment* a)
{
	bool glued = false;
	a->collider = -1;
	if (!cliGetInt(j, entry, entryPath, "collider", 0, FM_MAX_COLLIDERS - 1, &a->collider, &glued))
		return false;
	a->stiffness = glued ? 0.0 : CLI_ATTACHMENT_STIFFNESS;
	if (!cliGetSpring(j, entry, entryPath, &a->stiffness, &a->dampingRatio))
		return false;
	if (glued && (fmLength(a->velocity) > 0.0 || fmLength(a->angularVelocity) > 0.0))
		return cliJsonFail(j, entryPath, NULL,
		                   "glued to a collider, it moves with it: no velocity of its own");
	return true;
}

// "attachments": [{"min": [..], "max": [..], "velocity": [..], "angular_velocity": [..],
// "stiffness": N/m, "collider": index, "damping_ratio": r}]: attachments (cliAttachment).
static bool cliReadAttachment(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                              void* out)
{
	cliAttachment* a = out;
	if (!cliGetBox(j, entry, entryPath, &a->min, &a->max) ||
	    !cliGetVec3(j, entry, entryPath, "velocity", &a->velocity, NULL) ||
	    !cliGetVec3(j, entry, entryPath, "angular_velocity", &a->angularVelocity, NULL))
		return false;
	const double v[6] = {a->velocity.x,        a->velocity.y,        a->velocity.z,
	                     a->angularVelocity.x, a->angularVelocity.y, a->angularVelocity.z};
	for (int k = 0; k < 6; ++k)
		if (!(fabs(v[k]) <= 1e6))
			return cliJsonFail(j, entryPath, NULL,
			                   "velocity and angular_velocity must be within 1e6 (m/s, rad/s)");
	return cliReadGlue(j, entry, entryPath, a);
}

// "welds": [{"body": index, "distance": m, "stiffness": N/m, "damping_ratio": r}] (cliWeld).
static bool cliReadWeld(const cliJson* j, const cliJsonNode* entry, const char* entryPath,
                        void* out)
{
	cliWeld* weld = out;
	const cliRange distance = {0.0, 1.0, true, false};
	bool hasBody = false;
	weld->distance = 1e-6;
	if (!cliGetInt(j, entry, entryPath, "body", 0, INT_MAX - 1, &weld->body, &hasBody) ||
	    !cliGetNumber(j, entry, entryPath, "distance", distance, &weld->distance, NULL) ||
	    !cliGetSpring(j, entry, entryPath, &weld->stiffness, &weld->dampingRatio))
		return false;
	return hasBody || cliJsonFail(j, entryPath, NULL, "a weld needs \"body\"");
}

static const char* const cliPinKeys[] = {"min", "max", "axes", "displacement", "time", NULL};
static const char* const cliLoadKeys[] = {"min", "max", "force", NULL};
static const char* const cliPressureKeys[] = {"min", "max", "pressure", "follower", NULL};
static const char* const cliAttachmentKeys[] = {
    "min", "max", "velocity", "angular_velocity", "stiffness", "collider", "damping_ratio", NULL};
static const char* const cliWeldKeys[] = {"body", "distance", "stiffness", "damping_ratio", NULL};
static const cliEntryList cliPinList = {"pin", "{\"min\": [x,y,z], \"max\": [x,y,z]}", cliPinKeys,
                                        sizeof(cliPinBox), cliReadPin};
static const cliEntryList cliLoadList = {
    "loads", "{\"min\": [x,y,z], \"max\": [x,y,z], \"force\": [fx,fy,fz]}", cliLoadKeys,
    sizeof(cliLoadBox), cliReadLoad};
static const cliEntryList cliPressureList = {
    "pressure", "{\"min\": [x,y,z], \"max\": [x,y,z], \"pressure\": Pa}", cliPressureKeys,
    sizeof(cliPressureBox), cliReadPressure};
static const cliEntryList cliAttachmentList = {
    "attachments",
    "{\"min\": [x,y,z], \"max\": [x,y,z], \"velocity\": [vx,vy,vz], \"angular_velocity\": "
    "[wx,wy,wz]}",
    cliAttachmentKeys, sizeof(cliAttachment), cliReadAttachment};
static const cliEntryList cliWeldList = {"welds", "{\"body\": index, \"distance\": m}", cliWeldKeys,
                                         sizeof(cliWeld), cliReadWeld};

// A body's lists in the order they are checked, "regions" among them; what was read is kept in
// @p spec on failure too, for cliScene_Free.
static bool cliParseBodyLists(const cliJson* j, const cliJsonNode* body, const char* path,
                              cliBodySpec* spec)
{
	void *pins = NULL, *loads = NULL, *pressures = NULL, *attachments = NULL, *welds = NULL;
	bool ok =
	    cliGetEntries(j, body, path, &cliPinList, &pins, &spec->pinCount) &&
	    cliGetEntries(j, body, path, &cliLoadList, &loads, &spec->loadCount) &&
	    cliGetEntries(j, body, path, &cliPressureList, &pressures, &spec->pressureCount) &&
	    cliParseRegions(j, body, path, spec) &&
	    cliGetEntries(j, body, path, &cliAttachmentList, &attachments, &spec->attachmentCount) &&
	    cliGetEntries(j, body, path, &cliWeldList, &welds, &spec->weldCount);
	spec->pins = pins;
	spec->loads = loads;
	spec->pressures = pressures;
	spec->attachments = attachments;
	spec->welds = welds;
	return ok;
}

// ---- contact and the body --------------------------------------------------------------------

// "filter": {"category": bits, "mask": bits} (fmFilter; absent keys keep the defaults).
bool cliParseFilter(const cliJson* j, const cliJsonNode* object, const char* parent,
                    fmFilter* filter)
{
	static const char* const keys[] = {"category", "mask", NULL};
	const cliJsonNode* item = NULL;
	char path[256];
	cliJoinKey(path, sizeof path, parent, "filter");
	if (!cliGetObject(j, object, parent, "filter", &item))
		return false;
	return item == NULL || (cliCheckKeys(j, item, path, keys) &&
	                        cliGetBits(j, item, path, "category", &filter->categoryBits) &&
	                        cliGetBits(j, item, path, "mask", &filter->maskBits));
}

// A body's "self_collision", "friction" (against other bodies), "sleep" and "filter".
static bool cliParseBodyContact(const cliJson* j, const cliJsonNode* body, const char* path,
                                fmBodyDef* def)
{
	return cliGetBool(j, body, path, "self_collision", &def->selfCollision) &&
	       cliGetNumber(j, body, path, "friction", cliNonNegative, &def->friction, NULL) &&
	       cliGetBool(j, body, path, "sleep", &def->enableSleep) &&
	       cliParseFilter(j, body, path, &def->filter);
}

// A scene body's defaults: the library's default body, except that its mass comes from its
// density (1000 kg/m^3 unless the material gives "density"), so a body weighs the same at any
// resolution; "particle_mass" asks for the seeds' per-vertex mass instead.
static void cliBodyDefaults(cliBodySpec* spec)
{
	spec->def = fmDefaultBodyDef();
	spec->def.massMode = fm_massFromDensity;
	spec->initialVelocity = fmMakeVec3(0, 0, 0);
	spec->renderMeshPath[0] = 0;
	memset(&spec->fibres, 0, sizeof spec->fibres);
}

// A body's "render_mesh": an OBJ surface (relative to the scene's folder) that follows the body,
// placed by the body's own transform (fmBody_SetRenderMesh).
static bool cliParseRenderMesh(const cliJson* j, const cliJsonNode* body, const char* parent,
                               cliBodySpec* spec)
{
	const char* text = NULL;
	if (!cliGetString(j, body, parent, "render_mesh", &text))
		return false;
	if (text == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, "render_mesh");
	const cliJsonNode* item = cliJsonTree_Member(body, "render_mesh");
	size_t length = strlen(text);
	if (length < 5 ||
	    (strcmp(text + length - 4, ".obj") != 0 && strcmp(text + length - 4, ".OBJ") != 0))
		return cliJsonFail(j, path, item, "expected a Wavefront .obj path");
	return cliResolveFile(j, path, item, text, spec->renderMeshPath, sizeof spec->renderMeshPath);
}

bool cliParseBody(const cliJson* j, const cliJsonNode* body, int index, cliBodySpec* spec)
{
	static const char* const keys[] = {
	    "mesh",        "box_min",          "box_max",        "transform",        "material",
	    "force_model", "damping",          "smoothing",      "rayleigh",         "spring_damping",
	    "pin",         "initial_velocity", "self_collision", "friction",         "sleep",
	    "filter",      "render_mesh",      "fibres",         CLI_BODY_LOAD_KEYS, NULL};
	static const char* const rayleighKeys[] = {"mass", "stiffness", NULL};
	char path[64];
	snprintf(path, sizeof path, "bodies[%d]", index);
	if (!cliJsonIs(body, cli_jsonObject))
		return cliJsonFail(j, path, body, "expected a body object {\"mesh\": ...}");
	cliBodyDefaults(spec);
	if (!cliCheckKeys(j, body, path, keys) || !cliParseMesh(j, body, path, spec) ||
	    !cliParseRenderMesh(j, body, path, spec) ||
	    !cliParseTransform(j, body, path, &spec->transform) ||
	    !cliParseMaterial(j, body, path, spec) || !cliParseFibres(j, body, path, &spec->fibres))
		return false;

	const char* forceModel = NULL;
	if (!cliGetString(j, body, path, "force_model", &forceModel))
		return false;
	if (forceModel != NULL && !fmForceModelFromName(forceModel, &spec->def.forceModel))
	{
		char itemPath[128];
		cliJoinKey(itemPath, sizeof itemPath, path, "force_model");
		return cliJsonFail(j, itemPath, cliJsonTree_Member(body, "force_model"),
		                   "expected \"fem\", \"fvm\" or \"mass-spring\"");
	}
	const cliRange dampingRange = {0.0, 1.0, true, false};
	const cliJsonNode* rayleigh = NULL;
	char rayleighPath[128];
	cliJoinKey(rayleighPath, sizeof rayleighPath, path, "rayleigh");
	if (!cliGetNumber(j, body, path, "damping", dampingRange, &spec->def.damping, NULL) ||
	    !cliGetNumber(j, body, path, "smoothing", cliUnit, &spec->def.smoothing, NULL) ||
	    !cliGetNumber(j, body, path, "spring_damping", cliNonNegative, &spec->def.springDamping,
	                  NULL) ||
	    !cliGetObject(j, body, path, "rayleigh", &rayleigh))
		return false;
	if (rayleigh != NULL && (!cliCheckKeys(j, rayleigh, rayleighPath, rayleighKeys) ||
	                         !cliGetNumber(j, rayleigh, rayleighPath, "mass", cliNonNegative,
	                                       &spec->def.rayleighMass, NULL) ||
	                         !cliGetNumber(j, rayleigh, rayleighPath, "stiffness", cliNonNegative,
	                                       &spec->def.rayleighStiffness, NULL)))
		return false;
	return cliParseBodyLists(j, body, path, spec) &&
	       cliGetVec3(j, body, path, "initial_velocity", &spec->initialVelocity, NULL) &&
	       cliParseBodyContact(j, body, path, &spec->def);
}
