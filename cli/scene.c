// JSON scenes (docs/scene-format.md): every key checked for type and range, every error named
// by its JSON path ("bodies[0].material.youngs_modulus") and, when it can be found, its line.
#include "scene.h"
#include "json_locate.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Parse state: the file name and text (for line numbers), the scene's folder (for paths) and
// where messages go (NULL: nowhere, for the fuzzer; they are still composed).
typedef struct cliJson
{
	const char* file;
	const char* text;
	size_t size;
	char folder[CLI_MAX_PATH];
	FILE* messages;
} cliJson;

// A numeric range; open ends exclude the bound, infinite bounds mean "unbounded".
typedef struct cliRange
{
	double lo;
	double hi;
	bool loOpen;
	bool hiOpen;
} cliRange;

static const cliRange cliAnyFinite = {-INFINITY, INFINITY, true, true};
static const cliRange cliPositive = {0.0, INFINITY, true, true};
static const cliRange cliNonNegative = {0.0, INFINITY, false, true};
static const cliRange cliUnit = {0.0, 1.0, false, false};

// Largest generated box, cells per axis (6 tets a cell; 400^3 cells is already 384M tets).
#define CLI_MAX_BOX_CELLS 1000

// ---- messages -------------------------------------------------------------------------------

// 1-based line and column of byte @p offset in @p text.
static void cliLineColumn(const char* text, size_t offset, int* line, int* column)
{
	*line = 1;
	*column = 1;
	for (size_t i = 0; i < offset && text[i] != 0; ++i)
	{
		if (text[i] == '\n')
		{
			*line += 1;
			*column = 1;
		}
		else
			*column += 1;
	}
}

// cJSON keeps no positions: walk the text to the path's key.
static bool cliFindKeyLine(const cliJson* j, const char* path, int* line, int* column)
{
	size_t offset = 0;
	if (!cliJsonLocate(j->text, j->size, path, &offset))
		return false;
	cliLineColumn(j->text, offset, line, column);
	return true;
}

// Print "file[:line:column]: path: message[, got VALUE]" to j->messages and return false.
static bool cliJsonFail(const cliJson* j, const char* path, const cJSON* got, const char* format,
                        ...) __attribute__((format(printf, 4, 5)));
static bool cliJsonFail(const cliJson* j, const char* path, const cJSON* got, const char* format,
                        ...)
{
	char where[CLI_MAX_PATH + 300], message[1024], value[80] = "";
	int line = 0, column = 0;
	if (path[0] != 0 && cliFindKeyLine(j, path, &line, &column))
		snprintf(where, sizeof where, "%s:%d:%d: %s: ", j->file, line, column, path);
	else if (path[0] != 0)
		snprintf(where, sizeof where, "%s: %s: ", j->file, path);
	else
		snprintf(where, sizeof where, "%s: ", j->file);
	va_list args;
	va_start(args, format);
	vsnprintf(message, sizeof message, format, args);
	va_end(args);
	if (got != NULL)
	{
		char* printed = cJSON_PrintUnformatted(got);
		if (printed != NULL)
		{
			size_t length = strlen(printed);
			snprintf(value, sizeof value, length > 60 ? ", got %.57s..." : ", got %s", printed);
			cJSON_free(printed);
		}
	}
	if (j->messages != NULL)
		fprintf(j->messages, "%s%s%s\n", where, message, value);
	return false;
}

// "parent.key" (or "key" at the top); a path too long for the buffer is cut, which only
// shortens a message.
static void cliJoinKey(char* out, size_t size, const char* parent, const char* key)
{
	int written =
	    parent[0] == 0 ? snprintf(out, size, "%s", key) : snprintf(out, size, "%s.%s", parent, key);
	if (written < 0)
		out[0] = 0;
}

static void cliDescribeRange(cliRange range, char* out, size_t size)
{
	bool hasLo = isfinite(range.lo), hasHi = isfinite(range.hi);
	if (!hasLo && !hasHi)
		snprintf(out, size, "a finite number");
	else if (!hasHi)
		snprintf(out, size, "a number %s %g", range.loOpen ? ">" : ">=", range.lo);
	else if (!hasLo)
		snprintf(out, size, "a number %s %g", range.hiOpen ? "<" : "<=", range.hi);
	else
		snprintf(out, size, "a number in %c%g, %g%c", range.loOpen ? '(' : '[', range.lo, range.hi,
		         range.hiOpen ? ')' : ']');
}

static bool cliInRange(double value, cliRange range)
{
	if (!isfinite(value))
		return false;
	if (range.loOpen ? !(value > range.lo) : !(value >= range.lo))
		return false;
	if (range.hiOpen ? !(value < range.hi) : !(value <= range.hi))
		return false;
	return true;
}

// ---- typed getters: absent keys leave the value alone ----------------------------------------

// Most keys one object of the format allows.
#define CLI_MAX_KEYS 32

// Reject keys not in @p allowed (NULL-terminated, at most CLI_MAX_KEYS) and repeated keys. One
// pass over the members: each is looked up in the short allowed list and marked seen there.
static bool cliCheckKeys(const cliJson* j, const cJSON* object, const char* parent,
                         const char* const* allowed)
{
	bool seen[CLI_MAX_KEYS] = {false};
	const cJSON* item = NULL;
	cJSON_ArrayForEach(item, object)
	{
		char path[256];
		cliJoinKey(path, sizeof path, parent, item->string);
		int known = -1;
		for (int i = 0; allowed[i] != NULL && known < 0; ++i)
			if (strcmp(item->string, allowed[i]) == 0)
				known = i;
		if (known < 0)
		{
			char list[512] = "";
			for (int i = 0; allowed[i] != NULL; ++i)
			{
				strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
				strncat(list, allowed[i], sizeof list - strlen(list) - 1);
			}
			return cliJsonFail(j, path, NULL, "unknown key (expected one of: %s)", list);
		}
		FM_ASSERT(known < CLI_MAX_KEYS);
		if (seen[known])
			return cliJsonFail(j, path, NULL, "key given twice");
		seen[known] = true;
	}
	return true;
}

static bool cliGetNumber(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                         cliRange range, double* value, bool* present)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (present != NULL)
		*present = item != NULL;
	if (item == NULL)
		return true;
	char path[256], expected[96];
	cliJoinKey(path, sizeof path, parent, key);
	cliDescribeRange(range, expected, sizeof expected);
	if (!cJSON_IsNumber(item) || !cliInRange(item->valuedouble, range))
		return cliJsonFail(j, path, item, "expected %s", expected);
	*value = item->valuedouble;
	return true;
}

static bool cliGetInt(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                      int lo, int hi, int* value, bool* present)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (present != NULL)
		*present = item != NULL;
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	double number = cJSON_IsNumber(item) ? item->valuedouble : NAN;
	if (!isfinite(number) || number != floor(number))
		return cliJsonFail(j, path, item, "expected an integer in [%d, %d]", lo, hi);
	if (number > hi)
		return cliJsonFail(j, path, item, "too large (at most %d)", hi);
	if (number < lo)
		return cliJsonFail(j, path, item, "too small (at least %d)", lo);
	*value = (int)number;
	return true;
}

static bool cliGetBool(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                       bool* value)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	if (!cJSON_IsBool(item))
		return cliJsonFail(j, path, item, "expected true or false");
	*value = cJSON_IsTrue(item);
	return true;
}

static bool cliGetString(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                         const char** value)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	if (!cJSON_IsString(item) || item->valuestring == NULL)
		return cliJsonFail(j, path, item, "expected a string");
	*value = item->valuestring;
	return true;
}

static bool cliGetVec3(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                       fmVec3* value, bool* present)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (present != NULL)
		*present = item != NULL;
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	double xyz[3];
	int count = 0;
	const cJSON* element = NULL;
	if (!cJSON_IsArray(item))
		return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
	// One walk that stops at a fourth element: a long array costs no more than a short one.
	cJSON_ArrayForEach(element, item)
	{
		if (count == 3)
			return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
		if (!cJSON_IsNumber(element) || !isfinite(element->valuedouble))
			return cliJsonFail(j, path, item, "expected an array of 3 finite numbers [x, y, z]");
		xyz[count++] = element->valuedouble;
	}
	if (count != 3)
		return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
	*value = fmMakeVec3(xyz[0], xyz[1], xyz[2]);
	return true;
}

// An optional object member: NULL if absent; fails on a non-object.
static bool cliGetObject(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                         const cJSON** value)
{
	*value = NULL;
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	if (!cJSON_IsObject(item))
		return cliJsonFail(j, path, item, "expected an object {...}");
	*value = item;
	return true;
}

// ---- bodies ---------------------------------------------------------------------------------

static bool cliFileReadable(const char* path)
{
	FILE* file = fopen(path, "rb");
	if (file == NULL)
		return false;
	fclose(file);
	return true;
}

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

static bool cliParseMesh(const cliJson* j, const cJSON* body, const char* parent, cliBodySpec* spec)
{
	char path[256];
	cliJoinKey(path, sizeof path, parent, "mesh");
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(body, "mesh");
	if (item == NULL)
		return cliJsonFail(
		    j, parent, NULL,
		    "missing \"mesh\" (a .node path, \"builtin:house2\" or \"box:nx,ny,nz\")");
	if (!cJSON_IsString(item) || item->valuestring == NULL || item->valuestring[0] == 0)
		return cliJsonFail(j, path, item,
		                   "expected a .node path, \"builtin:house2\" or \"box:nx,ny,nz\"");
	const char* text = item->valuestring;
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
	// Relative paths are relative to the scene file's folder, so scenes can be run from anywhere.
	int written = text[0] == '/'
	                  ? snprintf(spec->nodePath, sizeof spec->nodePath, "%s", text)
	                  : snprintf(spec->nodePath, sizeof spec->nodePath, "%s%s", j->folder, text);
	if (written < 0 || (size_t)written >= sizeof spec->nodePath)
		return cliJsonFail(j, path, item, "path too long");
	memcpy(spec->elePath, spec->nodePath, sizeof spec->elePath);
	if (isNode)
		memcpy(spec->elePath + strlen(spec->elePath) - 5, ".ele", 5);
	if (!cliFileReadable(spec->nodePath))
		return cliJsonFail(j, path, NULL,
		                   "cannot open %s (\"%s\" is relative to the scene's folder)",
		                   spec->nodePath, text);
	if (isNode && !cliFileReadable(spec->elePath))
		return cliJsonFail(j, path, NULL, "cannot open %s (the .ele beside the .node)",
		                   spec->elePath);
	return true;
}

// A body's or a mesh collider's "transform" (the identity when absent).
static bool cliParseTransform(const cliJson* j, const cJSON* object, const char* parent,
                              fmMeshTransform* out)
{
	static const char* const keys[] = {"scale", "center", "swap_yz", "translate", NULL};
	char path[256];
	cliJoinKey(path, sizeof path, parent, "transform");
	const cJSON* transform = NULL;
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

static bool cliParseMaterial(const cliJson* j, const cJSON* body, const char* parent,
                             cliBodySpec* spec)
{
	static const char* const keys[] = {"model", "youngs_modulus", "poisson_ratio", "lambda",
	                                   "mu",    "mooney_c01",     "density",       "particle_mass",
	                                   NULL};
	char path[256];
	cliJoinKey(path, sizeof path, parent, "material");
	const cJSON* material = NULL;
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
		return cliJsonFail(j, modelPath, cJSON_GetObjectItemCaseSensitive(material, "model"),
		                   "expected \"linear\", \"corotated\", \"stvk\", \"neohookean\" or "
		                   "\"mooney-rivlin\"");
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

	bool hasC01 = false;
	if (!cliGetNumber(j, material, path, "mooney_c01", cliNonNegative, &spec->def.material.c01,
	                  &hasC01))
		return false;
	if (hasC01 && model != fm_mooneyRivlin)
		return cliJsonFail(j, path, NULL,
		                   "mooney_c01 only applies to \"model\": \"mooney-rivlin\"");
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmMaterial_Validate(&spec->def.material, &diag) != fm_ok)
		return cliJsonFail(j, path, NULL, "%s",
		                   diag.message[0] ? diag.message : "invalid material");

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

static bool cliParsePinExtras(const cliJson* j, const cJSON* box, const char* boxPath,
                              cliPinBox* pin);

static bool cliParsePins(const cliJson* j, const cJSON* body, const char* parent, cliBodySpec* spec)
{
	static const char* const keys[] = {"min", "max", "axes", "displacement", "time", NULL};
	char path[256];
	cliJoinKey(path, sizeof path, parent, "pin");
	const cJSON* pins = cJSON_GetObjectItemCaseSensitive(body, "pin");
	if (pins == NULL)
		return true;
	if (!cJSON_IsArray(pins))
		return cliJsonFail(j, path, pins,
		                   "expected a list of {\"min\": [x,y,z], \"max\": [x,y,z]}");
	// cJSON's arrays are linked lists: count once, then walk once (cJSON_GetArrayItem(i) in a
	// loop walks the list again for every box, quadratic in the number of boxes).
	int count = cJSON_GetArraySize(pins);
	spec->pins = calloc((size_t)(count > 0 ? count : 1), sizeof *spec->pins);
	if (spec->pins == NULL)
		return cliJsonFail(j, path, NULL, "out of memory");
	int i = 0;
	const cJSON* box = NULL;
	cJSON_ArrayForEach(box, pins)
	{
		char boxPath[256];
		if (snprintf(boxPath, sizeof boxPath, "%s[%d]", path, i) < 0)
			boxPath[0] = 0;
		if (!cJSON_IsObject(box))
			return cliJsonFail(j, boxPath, box, "expected {\"min\": [x,y,z], \"max\": [x,y,z]}");
		bool hasMin = false, hasMax = false;
		cliPinBox* pin = &spec->pins[i];
		if (!cliCheckKeys(j, box, boxPath, keys) ||
		    !cliGetVec3(j, box, boxPath, "min", &pin->min, &hasMin) ||
		    !cliGetVec3(j, box, boxPath, "max", &pin->max, &hasMax))
			return false;
		if (!hasMin || !hasMax)
			return cliJsonFail(j, boxPath, NULL, "a pin box needs both \"min\" and \"max\"");
		if (!(pin->min.x <= pin->max.x && pin->min.y <= pin->max.y && pin->min.z <= pin->max.z))
			return cliJsonFail(j, boxPath, NULL, "min must not exceed max on any axis");
		if (!cliParsePinExtras(j, box, boxPath, pin))
			return false;
		spec->pinCount = ++i;
	}
	return true;
}

// ---- loads and boundary conditions: pin axes and displacements, nodal forces, pressure --------

// A body's keys for loads and per-region materials (docs/scene-format.md, docs/loads.md).
#define CLI_BODY_LOAD_KEYS "loads", "pressure", "regions", "attachments"

// "axes": a string of the letters x, y, z, each at most once (e.g. "y", "xz").
static bool cliGetAxes(const cliJson* j, const cJSON* box, const char* boxPath, unsigned* axes)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(box, "axes");
	if (item == NULL)
		return true;
	char path[300];
	cliJoinKey(path, sizeof path, boxPath, "axes");
	const char* text = cJSON_IsString(item) ? item->valuestring : NULL;
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
static bool cliParsePinExtras(const cliJson* j, const cJSON* box, const char* boxPath,
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

// A load or pressure entry's "min" and "max": both given, finite, ordered.
static bool cliGetBox(const cliJson* j, const cJSON* entry, const char* path, fmVec3* min,
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

// The array @p key of a body, counted: NULL when absent; false (with a message) when not an
// array. @p entries gets calloc'd room for its elements.
static bool cliGetEntries(const cliJson* j, const cJSON* body, const char* path, const char* key,
                          const char* expected, size_t size, const cJSON** array, void** entries)
{
	*array = cJSON_GetObjectItemCaseSensitive(body, key);
	if (*array == NULL)
		return true;
	if (!cJSON_IsArray(*array))
		return cliJsonFail(j, path, *array, "expected a list of %s", expected);
	int count = cJSON_GetArraySize(*array);
	*entries = calloc((size_t)(count > 0 ? count : 1), size);
	if (*entries == NULL)
		return cliJsonFail(j, path, NULL, "out of memory");
	return true;
}

// "loads": [{"min": [..], "max": [..], "force": [fx, fy, fz]}] (N on each vertex in the box).
static bool cliParseLoads(const cliJson* j, const cJSON* body, const char* parent,
                          cliBodySpec* spec)
{
	static const char* const keys[] = {"min", "max", "force", NULL};
	static const char* const expected = "{\"min\": [x,y,z], \"max\": [x,y,z], \"force\": "
	                                    "[fx,fy,fz]}";
	char path[256];
	cliJoinKey(path, sizeof path, parent, "loads");
	const cJSON* array = NULL;
	void* entries = NULL;
	if (!cliGetEntries(j, body, path, "loads", expected, sizeof *spec->loads, &array, &entries))
		return false;
	spec->loads = entries;
	int i = 0;
	const cJSON* entry = NULL;
	cJSON_ArrayForEach(entry, array)
	{
		char entryPath[300];
		if (snprintf(entryPath, sizeof entryPath, "%s[%d]", path, i) < 0)
			entryPath[0] = 0;
		cliLoadBox* load = &spec->loads[i];
		bool hasForce = false;
		if (!cJSON_IsObject(entry))
			return cliJsonFail(j, entryPath, entry, "expected %s", expected);
		if (!cliCheckKeys(j, entry, entryPath, keys) ||
		    !cliGetBox(j, entry, entryPath, &load->min, &load->max) ||
		    !cliGetVec3(j, entry, entryPath, "force", &load->force, &hasForce))
			return false;
		if (!hasForce)
			return cliJsonFail(j, entryPath, NULL,
			                   "a load needs \"force\": [fx, fy, fz] (N on each vertex)");
		spec->loadCount = ++i;
	}
	return true;
}

// "attachments": [{"min": [..], "max": [..], "velocity": [..], "angular_velocity": [..],
// "stiffness": N/m}]: kinematic attachments (cliAttachment).
static bool cliParseAttachments(const cliJson* j, const cJSON* body, const char* parent,
                                cliBodySpec* spec)
{
	static const char* const keys[] = {"min",       "max", "velocity", "angular_velocity",
	                                   "stiffness", NULL};
	static const char* const expected = "{\"min\": [x,y,z], \"max\": [x,y,z], \"velocity\": "
	                                    "[vx,vy,vz], \"angular_velocity\": [wx,wy,wz]}";
	char path[256];
	cliJoinKey(path, sizeof path, parent, "attachments");
	const cJSON* array = NULL;
	void* entries = NULL;
	if (!cliGetEntries(j, body, path, "attachments", expected, sizeof *spec->attachments, &array,
	                   &entries))
		return false;
	spec->attachments = entries;
	int i = 0;
	const cJSON* entry = NULL;
	cJSON_ArrayForEach(entry, array)
	{
		char entryPath[300];
		if (snprintf(entryPath, sizeof entryPath, "%s[%d]", path, i) < 0)
			entryPath[0] = 0;
		cliAttachment* a = &spec->attachments[i];
		a->stiffness = CLI_ATTACHMENT_STIFFNESS;
		if (!cJSON_IsObject(entry))
			return cliJsonFail(j, entryPath, entry, "expected %s", expected);
		if (!cliCheckKeys(j, entry, entryPath, keys) ||
		    !cliGetBox(j, entry, entryPath, &a->min, &a->max) ||
		    !cliGetVec3(j, entry, entryPath, "velocity", &a->velocity, NULL) ||
		    !cliGetVec3(j, entry, entryPath, "angular_velocity", &a->angularVelocity, NULL) ||
		    !cliGetNumber(j, entry, entryPath, "stiffness", cliPositive, &a->stiffness, NULL))
			return false;
		const double v[6] = {a->velocity.x,        a->velocity.y,        a->velocity.z,
		                     a->angularVelocity.x, a->angularVelocity.y, a->angularVelocity.z};
		for (int k = 0; k < 6; ++k)
			if (!(fabs(v[k]) <= 1e6))
				return cliJsonFail(j, entryPath, NULL,
				                   "velocity and angular_velocity must be within 1e6 (m/s, rad/s)");
		spec->attachmentCount = ++i;
	}
	return true;
}

// "pressure": [{"min": [..], "max": [..], "pressure": Pa, "follower": true}].
static bool cliParsePressures(const cliJson* j, const cJSON* body, const char* parent,
                              cliBodySpec* spec)
{
	static const char* const keys[] = {"min", "max", "pressure", "follower", NULL};
	static const char* const expected = "{\"min\": [x,y,z], \"max\": [x,y,z], \"pressure\": Pa}";
	char path[256];
	cliJoinKey(path, sizeof path, parent, "pressure");
	const cJSON* array = NULL;
	void* entries = NULL;
	if (!cliGetEntries(j, body, path, "pressure", expected, sizeof *spec->pressures, &array,
	                   &entries))
		return false;
	spec->pressures = entries;
	int i = 0;
	const cJSON* entry = NULL;
	cJSON_ArrayForEach(entry, array)
	{
		char entryPath[300];
		if (snprintf(entryPath, sizeof entryPath, "%s[%d]", path, i) < 0)
			entryPath[0] = 0;
		cliPressureBox* load = &spec->pressures[i];
		load->follower = true;
		bool hasPressure = false;
		if (!cJSON_IsObject(entry))
			return cliJsonFail(j, entryPath, entry, "expected %s", expected);
		if (!cliCheckKeys(j, entry, entryPath, keys) ||
		    !cliGetBox(j, entry, entryPath, &load->min, &load->max) ||
		    !cliGetNumber(j, entry, entryPath, "pressure", cliAnyFinite, &load->pressure,
		                  &hasPressure) ||
		    !cliGetBool(j, entry, entryPath, "follower", &load->follower))
			return false;
		if (!hasPressure)
			return cliJsonFail(j, entryPath, NULL,
			                   "a pressure entry needs \"pressure\": Pa (positive pushes into "
			                   "the body)");
		spec->pressureCount = ++i;
	}
	return true;
}

// One region's material: the body's material changed by the keys given ("model", and
// "youngs_modulus" + "poisson_ratio" or "lambda" + "mu", "mooney_c01"), validated.
static bool cliParseRegionMaterial(const cliJson* j, const cJSON* object, const char* path,
                                   const fmMaterial* base, fmMaterial* out)
{
	static const char* const keys[] = {
	    "model", "youngs_modulus", "poisson_ratio", "lambda", "mu", "mooney_c01", NULL};
	if (!cJSON_IsObject(object))
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
		return cliJsonFail(j, modelPath, cJSON_GetObjectItemCaseSensitive(object, "model"),
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
	*out = hasE ? fmMakeMaterial(model, youngs, poisson) : fmMakeMaterialLame(model, lambda, mu);
	if (!cliGetNumber(j, object, path, "mooney_c01", cliNonNegative, &out->c01, &hasC01))
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
static bool cliParseRegions(const cliJson* j, const cJSON* body, const char* parent,
                            cliBodySpec* spec)
{
	char path[256];
	cliJoinKey(path, sizeof path, parent, "regions");
	const cJSON* regions = NULL;
	if (!cliGetObject(j, body, parent, "regions", &regions))
		return false;
	if (regions == NULL)
		return true;
	int count = cJSON_GetArraySize(regions);
	if (count < 1 || count > FM_MAX_REGIONS)
		return cliJsonFail(j, path, NULL, "expected 1 to %d regions {\"1\": {material}, ...}",
		                   FM_MAX_REGIONS);
	spec->regionMaterials = calloc((size_t)count, sizeof *spec->regionMaterials);
	spec->regionIds = calloc((size_t)count, sizeof *spec->regionIds);
	if (spec->regionMaterials == NULL || spec->regionIds == NULL)
		return cliJsonFail(j, path, NULL, "out of memory");
	int i = 0;
	const cJSON* region = NULL;
	cJSON_ArrayForEach(region, regions)
	{
		char regionPath[300];
		cliJoinKey(regionPath, sizeof regionPath, path, region->string);
		char* end = NULL;
		errno = 0;
		long id = strtol(region->string, &end, 10);
		if (region->string[0] == 0 || *end != 0 || errno != 0 || id < INT_MIN || id > INT_MAX)
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

// ---- contact: filters, bodies' contact keys, colliders, the contact object --------------------

// A 32-bit mask: an integer in [0, 2^32 - 1] (JSON numbers hold it exactly).
static bool cliGetBits(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                       uint32_t* value)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(object, key);
	if (item == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	double number = cJSON_IsNumber(item) ? item->valuedouble : NAN;
	if (!(number >= 0.0 && number <= 4294967295.0) || number != floor(number))
		return cliJsonFail(j, path, item, "expected an integer in [0, 4294967295] (32 bits)");
	*value = (uint32_t)number;
	return true;
}

// "filter": {"category": bits, "mask": bits} (fmFilter; absent keys keep the defaults).
static bool cliParseFilter(const cliJson* j, const cJSON* object, const char* parent,
                           fmFilter* filter)
{
	static const char* const keys[] = {"category", "mask", NULL};
	const cJSON* item = NULL;
	char path[256];
	cliJoinKey(path, sizeof path, parent, "filter");
	if (!cliGetObject(j, object, parent, "filter", &item))
		return false;
	return item == NULL || (cliCheckKeys(j, item, path, keys) &&
	                        cliGetBits(j, item, path, "category", &filter->categoryBits) &&
	                        cliGetBits(j, item, path, "mask", &filter->maskBits));
}

// A body's "self_collision", "friction" (against other bodies), "sleep" and "filter".
static bool cliParseBodyContact(const cliJson* j, const cJSON* body, const char* path,
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
}

// A body's "render_mesh": an OBJ surface (relative to the scene's folder) that follows the body,
// placed by the body's own transform (fmBody_SetRenderMesh).
static bool cliParseRenderMesh(const cliJson* j, const cJSON* body, const char* parent,
                               cliBodySpec* spec)
{
	const char* text = NULL;
	if (!cliGetString(j, body, parent, "render_mesh", &text))
		return false;
	if (text == NULL)
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, "render_mesh");
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(body, "render_mesh");
	size_t length = strlen(text);
	if (length < 5 ||
	    (strcmp(text + length - 4, ".obj") != 0 && strcmp(text + length - 4, ".OBJ") != 0))
		return cliJsonFail(j, path, item, "expected a Wavefront .obj path");
	int written =
	    text[0] == '/'
	        ? snprintf(spec->renderMeshPath, sizeof spec->renderMeshPath, "%s", text)
	        : snprintf(spec->renderMeshPath, sizeof spec->renderMeshPath, "%s%s", j->folder, text);
	if (written < 0 || (size_t)written >= sizeof spec->renderMeshPath)
		return cliJsonFail(j, path, item, "path too long");
	if (!cliFileReadable(spec->renderMeshPath))
		return cliJsonFail(j, path, NULL,
		                   "cannot open %s (\"%s\" is relative to the scene's folder)",
		                   spec->renderMeshPath, text);
	return true;
}

static bool cliParseBody(const cliJson* j, const cJSON* body, int index, cliBodySpec* spec)
{
	static const char* const keys[] = {
	    "mesh",        "box_min",          "box_max",          "transform", "material",
	    "force_model", "damping",          "smoothing",        "rayleigh",  "spring_damping",
	    "pin",         "initial_velocity", "self_collision",   "friction",  "sleep",
	    "filter",      "render_mesh",      CLI_BODY_LOAD_KEYS, NULL};
	static const char* const rayleighKeys[] = {"mass", "stiffness", NULL};
	char path[64];
	snprintf(path, sizeof path, "bodies[%d]", index);
	if (!cJSON_IsObject(body))
		return cliJsonFail(j, path, body, "expected a body object {\"mesh\": ...}");
	cliBodyDefaults(spec);
	if (!cliCheckKeys(j, body, path, keys) || !cliParseMesh(j, body, path, spec) ||
	    !cliParseRenderMesh(j, body, path, spec) ||
	    !cliParseTransform(j, body, path, &spec->transform) ||
	    !cliParseMaterial(j, body, path, spec))
		return false;

	const char* forceModel = NULL;
	if (!cliGetString(j, body, path, "force_model", &forceModel))
		return false;
	if (forceModel != NULL && !fmForceModelFromName(forceModel, &spec->def.forceModel))
	{
		char itemPath[128];
		cliJoinKey(itemPath, sizeof itemPath, path, "force_model");
		return cliJsonFail(j, itemPath, cJSON_GetObjectItemCaseSensitive(body, "force_model"),
		                   "expected \"fem\", \"fvm\" or \"mass-spring\"");
	}
	const cliRange dampingRange = {0.0, 1.0, true, false};
	const cJSON* rayleigh = NULL;
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
	return cliParsePins(j, body, path, spec) && cliParseLoads(j, body, path, spec) &&
	       cliParsePressures(j, body, path, spec) && cliParseRegions(j, body, path, spec) &&
	       cliParseAttachments(j, body, path, spec) &&
	       cliGetVec3(j, body, path, "initial_velocity", &spec->initialVelocity, NULL) &&
	       cliParseBodyContact(j, body, path, &spec->def);
}

// Collider shapes by scene name, with the keys each takes (the common ones included).
typedef struct cliShapeInfo
{
	const char* name;
	fmShapeType shape;
	const char* const* keys; // NULL-terminated
} cliShapeInfo;

#define CLI_COLLIDER_COMMON_KEYS                                                                   \
	"shape", "friction", "stick", "restitution", "velocity", "angular_velocity", "filter"
static const char* const cliPlaneKeys[] = {CLI_COLLIDER_COMMON_KEYS, "normal", "offset", NULL};
static const char* const cliSphereKeys[] = {CLI_COLLIDER_COMMON_KEYS, "center", "radius", NULL};
static const char* const cliBoxKeys[] = {CLI_COLLIDER_COMMON_KEYS, "center", "half_extents",
                                         "rotation", NULL};
static const char* const cliCapsuleKeys[] = {CLI_COLLIDER_COMMON_KEYS, "a", "b", "radius", NULL};
static const char* const cliMeshKeys[] = {CLI_COLLIDER_COMMON_KEYS, "path", "transform", "rotation",
                                          NULL};
static const cliShapeInfo cliShapes[] = {
    {"plane", fm_shapePlane, cliPlaneKeys}, {"sphere", fm_shapeSphere, cliSphereKeys},
    {"box", fm_shapeBox, cliBoxKeys},       {"capsule", fm_shapeCapsule, cliCapsuleKeys},
    {"mesh", fm_shapeMesh, cliMeshKeys},
};
#define CLI_SHAPE_NAMES "\"plane\", \"sphere\", \"box\", \"capsule\" or \"mesh\""

// Colliders' sizes and coordinates stay within the library's FM_MAX_COORDINATE.
static const cliRange cliLength = {0.0, FM_MAX_COORDINATE, true, false};
static const cliRange cliCoordinate = {-FM_MAX_COORDINATE, FM_MAX_COORDINATE, false, false};

// The keys @p keys (NULL-terminated) must all be present; @p what names the shape.
static bool cliRequireKeys(const cliJson* j, const cJSON* object, const char* path,
                           const char* const* keys, const char* what)
{
	for (int i = 0; keys[i] != NULL; ++i)
		if (cJSON_GetObjectItemCaseSensitive(object, keys[i]) == NULL)
			return cliJsonFail(j, path, NULL, "missing \"%s\" (%s)", keys[i], what);
	return true;
}

// A vector key whose coordinates must each lie in @p range (@p expected says so).
static bool cliGetVec3In(const cliJson* j, const cJSON* object, const char* parent, const char* key,
                         cliRange range, const char* expected, fmVec3* value)
{
	bool present = false;
	if (!cliGetVec3(j, object, parent, key, value, &present))
		return false;
	if (!present ||
	    (cliInRange(value->x, range) && cliInRange(value->y, range) && cliInRange(value->z, range)))
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	return cliJsonFail(j, path, cJSON_GetObjectItemCaseSensitive(object, key), "expected %s",
	                   expected);
}

static bool cliParseShapeName(const cliJson* j, const cJSON* item, const char* path,
                              const cliShapeInfo** info)
{
	const char* name = NULL;
	if (!cliGetString(j, item, path, "shape", &name))
		return false;
	if (name == NULL)
		return cliJsonFail(j, path, NULL, "missing \"shape\": expected " CLI_SHAPE_NAMES);
	for (size_t i = 0; i < sizeof cliShapes / sizeof cliShapes[0]; ++i)
		if (strcmp(name, cliShapes[i].name) == 0)
		{
			*info = &cliShapes[i];
			return true;
		}
	char shapePath[256];
	cliJoinKey(shapePath, sizeof shapePath, path, "shape");
	return cliJsonFail(j, shapePath, cJSON_GetObjectItemCaseSensitive(item, "shape"),
	                   "expected " CLI_SHAPE_NAMES);
}

static bool cliParsePlane(const cliJson* j, const cJSON* item, const char* path, fmColliderDef* d)
{
	static const char* const required[] = {"normal", NULL};
	const char* far = "3 numbers within 1e9";
	if (!cliRequireKeys(j, item, path, required,
	                    "a plane needs its normal; offset defaults to 0") ||
	    !cliGetVec3In(j, item, path, "normal", cliCoordinate, far, &d->normal) ||
	    !cliGetNumber(j, item, path, "offset", cliCoordinate, &d->offset, NULL))
		return false;
	if (d->normal.x != 0.0 || d->normal.y != 0.0 || d->normal.z != 0.0)
		return true;
	char normalPath[256];
	cliJoinKey(normalPath, sizeof normalPath, path, "normal");
	return cliJsonFail(j, normalPath, cJSON_GetObjectItemCaseSensitive(item, "normal"),
	                   "expected a non-zero normal [x, y, z]");
}

static bool cliParseSolidShape(const cliJson* j, const cJSON* item, const char* path,
                               fmShapeType shape, fmColliderDef* d)
{
	static const char* const sphere[] = {"center", "radius", NULL};
	static const char* const box[] = {"center", "half_extents", NULL};
	static const char* const capsule[] = {"a", "b", "radius", NULL};
	const char* far = "3 numbers within 1e9";
	const cliRange rotation = {-1e3, 1e3, false, false};
	switch (shape)
	{
	case fm_shapeSphere:
		return cliRequireKeys(j, item, path, sphere, "a sphere needs center and radius") &&
		       cliGetVec3In(j, item, path, "center", cliCoordinate, far, &d->center) &&
		       cliGetNumber(j, item, path, "radius", cliLength, &d->radius, NULL);
	case fm_shapeBox:
		return cliRequireKeys(j, item, path, box, "a box needs center and half_extents") &&
		       cliGetVec3In(j, item, path, "center", cliCoordinate, far, &d->center) &&
		       cliGetVec3In(j, item, path, "half_extents", cliLength, "3 numbers in (0, 1e9] (m)",
		                    &d->halfExtents) &&
		       cliGetVec3In(j, item, path, "rotation", rotation,
		                    "an axis-angle [x, y, z] in radians, each within 1000", &d->rotation);
	case fm_shapeCapsule:
		return cliRequireKeys(j, item, path, capsule, "a capsule needs a, b and radius") &&
		       cliGetVec3In(j, item, path, "a", cliCoordinate, far, &d->a) &&
		       cliGetVec3In(j, item, path, "b", cliCoordinate, far, &d->b) &&
		       cliGetNumber(j, item, path, "radius", cliLength, &d->radius, NULL);
	default:
		return false;
	}
}

// "path" (an OBJ file, relative to the scene's folder), "transform" and "rotation".
static bool cliParseMeshCollider(const cliJson* j, const cJSON* item, const char* path,
                                 cliColliderSpec* spec)
{
	static const char* const required[] = {"path", NULL};
	const char* file = NULL;
	const cliRange rotation = {-1e3, 1e3, false, false};
	if (!cliRequireKeys(j, item, path, required, "a mesh collider needs an OBJ file") ||
	    !cliGetString(j, item, path, "path", &file) ||
	    !cliParseTransform(j, item, path, &spec->transform) ||
	    !cliGetVec3In(j, item, path, "rotation", rotation,
	                  "an axis-angle [x, y, z] in radians, each within 1000", &spec->def.rotation))
		return false;
	char filePath[256];
	cliJoinKey(filePath, sizeof filePath, path, "path");
	const cJSON* fileItem = cJSON_GetObjectItemCaseSensitive(item, "path");
	if (file[0] == 0)
		return cliJsonFail(j, filePath, fileItem, "expected the path of an OBJ file");
	int written = file[0] == '/'
	                  ? snprintf(spec->objPath, sizeof spec->objPath, "%s", file)
	                  : snprintf(spec->objPath, sizeof spec->objPath, "%s%s", j->folder, file);
	if (written < 0 || (size_t)written >= sizeof spec->objPath)
		return cliJsonFail(j, filePath, fileItem, "path too long");
	if (!cliFileReadable(spec->objPath))
		return cliJsonFail(j, filePath, NULL,
		                   "cannot open %s (\"%s\" is relative to the scene's folder)",
		                   spec->objPath, file);
	return true;
}

static bool cliParseCollider(const cliJson* j, const cJSON* item, int index, cliColliderSpec* spec)
{
	char path[64];
	snprintf(path, sizeof path, "colliders[%d]", index);
	if (!cJSON_IsObject(item))
		return cliJsonFail(j, path, item, "expected a collider object {\"shape\": ...}");
	const cliShapeInfo* info = NULL;
	spec->def = fmDefaultColliderDef();
	spec->transform = fmDefaultMeshTransform();
	if (!cliParseShapeName(j, item, path, &info) || !cliCheckKeys(j, item, path, info->keys))
		return false;
	fmColliderDef* d = &spec->def;
	d->shape = info->shape;
	const cliRange speed = {-1e6, 1e6, false, false};
	const char* fast = "3 numbers within 1e6";
	bool shaped = info->shape == fm_shapePlane  ? cliParsePlane(j, item, path, d)
	              : info->shape == fm_shapeMesh ? cliParseMeshCollider(j, item, path, spec)
	                                            : cliParseSolidShape(j, item, path, d->shape, d);
	if (!shaped || !cliGetNumber(j, item, path, "friction", cliNonNegative, &d->friction, NULL) ||
	    !cliGetBool(j, item, path, "stick", &d->stick) ||
	    !cliGetNumber(j, item, path, "restitution", cliUnit, &d->restitution, NULL) ||
	    !cliGetVec3In(j, item, path, "velocity", speed, fast, &d->velocity) ||
	    !cliGetVec3In(j, item, path, "angular_velocity", speed, fast, &d->angularVelocity) ||
	    !cliParseFilter(j, item, path, &d->filter))
		return false;
	// A mesh's triangles come when the scene is built; its def is checked then.
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (d->shape != fm_shapeMesh && fmColliderDef_Validate(d, &diag) != fm_ok)
		return cliJsonFail(j, path, NULL, "%s", diag.message);
	return true;
}

static bool cliParseColliders(const cliJson* j, const cJSON* root, cliScene* scene)
{
	const cJSON* list = cJSON_GetObjectItemCaseSensitive(root, "colliders");
	if (list == NULL)
		return true;
	if (!cJSON_IsArray(list))
		return cliJsonFail(j, "colliders", list, "expected a list of collider objects");
	int count = cJSON_GetArraySize(list);
	if (count > FM_MAX_COLLIDERS)
		return cliJsonFail(j, "colliders", NULL, "%d colliders, at most %d", count,
		                   FM_MAX_COLLIDERS);
	scene->colliders = calloc((size_t)(count > 0 ? count : 1), sizeof *scene->colliders);
	if (scene->colliders == NULL)
		return cliJsonFail(j, "colliders", NULL, "out of memory");
	const cJSON* item = NULL;
	cJSON_ArrayForEach(item, list)
	{
		int i = scene->colliderCount++;
		if (!cliParseCollider(j, item, i, &scene->colliders[i]))
			return false;
	}
	return true;
}

// "contact": body-body contact and sleeping (fmContactDef).
static bool cliParseContact(const cliJson* j, const cJSON* root, fmContactDef* def)
{
	static const char* const keys[] = {"bodies",      "thickness",  "friction",
	                                   "restitution", "iterations", "sleep",
	                                   "sleep_speed", "sleep_time", NULL};
	const cliRange below1e6 = {0.0, 1e6, true, true};
	const cJSON* item = NULL;
	if (!cliGetObject(j, root, "", "contact", &item))
		return false;
	return item == NULL ||
	       (cliCheckKeys(j, item, "contact", keys) &&
	        cliGetBool(j, item, "contact", "bodies", &def->bodies) &&
	        cliGetNumber(j, item, "contact", "thickness", below1e6, &def->thickness, NULL) &&
	        cliGetNumber(j, item, "contact", "friction", cliNonNegative, &def->friction, NULL) &&
	        cliGetNumber(j, item, "contact", "restitution", cliUnit, &def->restitution, NULL) &&
	        cliGetInt(j, item, "contact", "iterations", 1, 64, &def->iterations, NULL) &&
	        cliGetBool(j, item, "contact", "sleep", &def->enableSleep) &&
	        cliGetNumber(j, item, "contact", "sleep_speed", below1e6, &def->sleepSpeed, NULL) &&
	        cliGetNumber(j, item, "contact", "sleep_time", below1e6, &def->sleepTime, NULL));
}

// ---- the world ------------------------------------------------------------------------------

// "tolerance": a number, or a preset: "accurate" (1e-6) or "game" (1e-2).
static bool cliGetTolerance(const cliJson* j, const cJSON* root, cliRange range, double* value)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(root, "tolerance");
	if (cJSON_IsString(item) && strcmp(item->valuestring, "accurate") == 0)
		*value = FM_TOLERANCE_ACCURATE;
	else if (cJSON_IsString(item) && strcmp(item->valuestring, "game") == 0)
		*value = FM_TOLERANCE_GAME;
	else if (cJSON_IsString(item))
		return cliJsonFail(j, "tolerance", item,
		                   "expected \"accurate\", \"game\" or a number in [1e-12, 1)");
	else
		return cliGetNumber(j, root, "", "tolerance", range, value, NULL);
	return true;
}

static bool cliParseFloor(const cliJson* j, const cJSON* root, fmFloorDef* floorDef)
{
	static const char* const keys[] = {
	    "height", "friction", "restitution", "max_depenetration_speed", "filter", NULL};
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(root, "floor");
	if (item == NULL)
		return true;
	if (cJSON_IsFalse(item))
	{
		floorDef->enabled = false;
		return true;
	}
	if (!cJSON_IsObject(item))
		return cliJsonFail(j, "floor", item, "expected an object {\"height\": ...} or false");
	floorDef->enabled = true;
	if (!cliCheckKeys(j, item, "floor", keys) ||
	    !cliGetNumber(j, item, "floor", "height", cliAnyFinite, &floorDef->height, NULL) ||
	    !cliGetNumber(j, item, "floor", "restitution", cliUnit, &floorDef->restitution, NULL) ||
	    !cliGetNumber(j, item, "floor", "max_depenetration_speed", cliPositive,
	                  &floorDef->maxDepenetrationSpeed, NULL) ||
	    !cliParseFilter(j, item, "floor", &floorDef->filter))
		return false;
	const cJSON* friction = cJSON_GetObjectItemCaseSensitive(item, "friction");
	if (friction == NULL)
		return true;
	if (cJSON_IsString(friction) && strcmp(friction->valuestring, "stick") == 0)
	{
		floorDef->friction = fm_floorStick;
		return true;
	}
	if (!cJSON_IsNumber(friction) || !cliInRange(friction->valuedouble, cliNonNegative))
		return cliJsonFail(j, "floor.friction", friction,
		                   "expected \"stick\" or a Coulomb coefficient >= 0");
	floorDef->friction = fm_floorCoulomb;
	floorDef->frictionCoefficient = friction->valuedouble;
	return true;
}

// The frame length of a scene with automatic substeps that gives no "dt": a 60 Hz frame.
#define CLI_AUTO_FRAME (1.0 / 60.0)

// "substeps": a count, or "auto"; an explicit scene without it is "auto" too. Automatic substeps
// (fmWorldDef.autoSubstep) make "dt" the frame length (default 1/60 s): each frame is split into
// steps of at most 0.3 of the estimated stability limit at the current deformation, so a mesh
// with slivers or a stiff material is stable without tuning (docs/scene-format.md).
static bool cliParseSubsteps(const cliJson* j, const cJSON* root, cliScene* scene)
{
	const cJSON* item = cJSON_GetObjectItemCaseSensitive(root, "substeps");
	bool automatic = item == NULL && scene->worldDef.integrator == fm_explicit;
	if (cJSON_IsString(item))
	{
		if (item->valuestring == NULL || strcmp(item->valuestring, "auto") != 0)
			return cliJsonFail(j, "substeps", item,
			                   "expected a whole number in [1, 100000] or \"auto\"");
		if (scene->worldDef.integrator != fm_explicit)
			return cliJsonFail(j, "substeps", item,
			                   "\"auto\" is for the explicit integrator (an implicit step is "
			                   "stable at any size: give a count)");
		automatic = true;
	}
	else if (!cliGetInt(j, root, "", "substeps", 1, 100000, &scene->substeps, NULL))
		return false;
	if (!automatic)
		return true;
	scene->worldDef.autoSubstep = true;
	scene->substeps = 1;
	if (cJSON_GetObjectItemCaseSensitive(root, "dt") == NULL)
		scene->dt = CLI_AUTO_FRAME;
	return true;
}

static bool cliParseWorld(const cliJson* j, const cJSON* root, cliScene* scene)
{
	fmWorldDef* def = &scene->worldDef;
	const cliRange dtRange = {0.0, 10.0, true, false};
	const cliRange secondsRange = {0.0, 1e6, true, false};
	bool hasFrames = false, hasSeconds = false;
	const char* integrator = NULL;
	const char* notConverged = NULL;
	const char* simd = NULL;
	const char* solver = NULL;
	const cliRange toleranceRange = {FM_MIN_TOLERANCE, 1.0, false, true};
	const cliRange budgetRange = {0.0, 1e9, true, false};
	double budgetMiB = 0.0;
	bool hasBudget = false;
	if (!cliGetVec3(j, root, "", "gravity", &def->gravity, NULL) ||
	    !cliGetNumber(j, root, "", "dt", dtRange, &scene->dt, NULL) ||
	    !cliGetInt(j, root, "", "frames", 1, CLI_MAX_FRAMES, &scene->frames, &hasFrames) ||
	    !cliGetNumber(j, root, "", "seconds", secondsRange, &scene->seconds, &hasSeconds) ||
	    !cliGetString(j, root, "", "integrator", &integrator) ||
	    !cliGetInt(j, root, "", "newton_iterations", 1, FM_MAX_NEWTON_ITERATIONS,
	               &def->newtonIterations, NULL) ||
	    !cliGetTolerance(j, root, toleranceRange, &def->tolerance) ||
	    !cliGetInt(j, root, "", "cg_iterations", 1, FM_MAX_CG_ITERATIONS, &def->cgIterations,
	               NULL) ||
	    !cliGetString(j, root, "", "not_converged", &notConverged) ||
	    !cliGetString(j, root, "", "simd", &simd) ||
	    !cliGetString(j, root, "", "implicit_solver", &solver) ||
	    !cliGetBool(j, root, "", "auto_substep", &def->autoSubstep) ||
	    !cliGetBool(j, root, "", "deterministic", &def->crossPlatformDeterminism) ||
	    !cliGetNumber(j, root, "", "memory_budget_mib", budgetRange, &budgetMiB, &hasBudget) ||
	    !cliGetInt(j, root, "", "workers", 1, FM_MAX_WORKERS, &def->workerCount,
	               &scene->hasWorkers) ||
	    !cliGetInt(j, root, "", "max_newton_per_frame", 1, INT_MAX, &def->maxNewtonPerFrame,
	               NULL) ||
	    !cliGetInt(j, root, "", "max_substeps_per_frame", 1, FM_MAX_SUBSTEPS,
	               &def->maxSubstepsPerFrame, NULL) ||
	    !cliParseFloor(j, root, &def->floor) || !cliParseContact(j, root, &def->contact))
		return false;
	if (hasBudget)
		def->memoryBudget = (size_t)(budgetMiB * 1048576.0);
	if (notConverged != NULL)
	{
		if (strcmp(notConverged, "warn") != 0 && strcmp(notConverged, "error") != 0)
			return cliJsonFail(j, "not_converged",
			                   cJSON_GetObjectItemCaseSensitive(root, "not_converged"),
			                   "expected \"warn\" or \"error\"");
		def->notConvergedIsError = strcmp(notConverged, "error") == 0;
	}
	if (solver != NULL)
	{
		if (strcmp(solver, "newton") != 0 && strcmp(solver, "vbd") != 0)
			return cliJsonFail(j, "implicit_solver",
			                   cJSON_GetObjectItemCaseSensitive(root, "implicit_solver"),
			                   "expected \"newton\" or \"vbd\"");
		def->implicitSolver = strcmp(solver, "vbd") == 0 ? fm_solverVbd : fm_solverNewton;
	}
	if (simd != NULL && !fmSimdLevelFromName(simd, &def->simd))
		return cliJsonFail(j, "simd", cJSON_GetObjectItemCaseSensitive(root, "simd"),
		                   "expected \"auto\", \"off\", \"scalar\", \"sse2\", \"avx2\" or "
		                   "\"avx512\"");
	if (hasFrames && hasSeconds)
		return cliJsonFail(j, "seconds", NULL, "give frames or seconds, not both");
	if (integrator != NULL)
	{
		if (strcmp(integrator, "explicit") == 0)
			def->integrator = fm_explicit;
		else if (strcmp(integrator, "implicit") == 0)
			def->integrator = fm_implicit;
		else
			return cliJsonFail(j, "integrator",
			                   cJSON_GetObjectItemCaseSensitive(root, "integrator"),
			                   "expected \"explicit\" or \"implicit\"");
	}
	if (!cliParseSubsteps(j, root, scene))
		return false;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmWorldDef_Validate(def, &diag) != fm_ok)
		return cliJsonFail(j, "", NULL, "%s", diag.message);
	return true;
}

static bool cliParseScene(const cliJson* j, const cJSON* root, cliScene* scene)
{
	static const char* const keys[] = {"description",
	                                   "gravity",
	                                   "dt",
	                                   "substeps",
	                                   "frames",
	                                   "seconds",
	                                   "integrator",
	                                   "newton_iterations",
	                                   "tolerance",
	                                   "cg_iterations",
	                                   "floor",
	                                   "bodies",
	                                   "not_converged",
	                                   "auto_substep",
	                                   "memory_budget_mib",
	                                   "workers",
	                                   "max_newton_per_frame",
	                                   "max_substeps_per_frame",
	                                   "simd",
	                                   "implicit_solver",
	                                   "deterministic",
	                                   "colliders",
	                                   "contact",
	                                   NULL};
	if (!cJSON_IsObject(root))
		return cliJsonFail(j, "", root, "a scene is a JSON object {...}");
	const char* description = NULL;
	if (!cliCheckKeys(j, root, "", keys) ||
	    !cliGetString(j, root, "", "description", &description) || !cliParseWorld(j, root, scene))
		return false;
	const cJSON* bodies = cJSON_GetObjectItemCaseSensitive(root, "bodies");
	if (bodies == NULL)
		return cliJsonFail(j, "", NULL, "missing \"bodies\": a scene needs at least one body");
	int count = cJSON_IsArray(bodies) ? cJSON_GetArraySize(bodies) : 0;
	if (count < 1)
		return cliJsonFail(j, "bodies", bodies, "expected a non-empty list of bodies");
	if (count > scene->worldDef.maxBodies)
		return cliJsonFail(j, "bodies", NULL, "%d bodies, at most %d", count,
		                   scene->worldDef.maxBodies);
	scene->bodies = calloc((size_t)count, sizeof *scene->bodies);
	if (scene->bodies == NULL)
		return cliJsonFail(j, "bodies", NULL, "out of memory");
	const cJSON* body = NULL;
	cJSON_ArrayForEach(body, bodies)
	{
		int i = scene->bodyCount++; // so cliScene_Free releases what was parsed
		if (!cliParseBody(j, body, i, &scene->bodies[i]))
			return false;
	}
	return cliParseColliders(j, root, scene);
}

// ---- public ---------------------------------------------------------------------------------

static void cliSceneDefaults(cliScene* scene, const char* name)
{
	memset(scene, 0, sizeof *scene);
	snprintf(scene->name, sizeof scene->name, "%s", name);
	scene->worldDef = fmDefaultWorldDef();
	scene->dt = 0.003;
	scene->substeps = 10;
}

void cliScene_MakeHouse(cliScene* scene)
{
	cliSceneDefaults(scene, "builtin:house");
	scene->seconds = 5.0;
	// Every value spelled out, so a change of library defaults cannot change the demo.
	fmWorldDef* world = &scene->worldDef;
	world->gravity = fmMakeVec3(0.0, -9.8, 0.0);
	world->integrator = fm_explicit;
	world->floor.enabled = true;
	world->floor.height = -3.0;
	world->floor.friction = fm_floorStick;
	scene->bodies = calloc(1, sizeof *scene->bodies);
	if (scene->bodies == NULL)
		return;
	scene->bodyCount = 1;
	cliBodySpec* body = &scene->bodies[0];
	body->meshSource = cli_meshHouse;
	body->transform = fmDefaultMeshTransform();
	body->transform.scale = 0.4;
	body->transform.center = true;
	body->transform.swapYZ = true;
	body->def = fmDefaultBodyDef();
	body->def.material = fmMakeMaterialLame(fm_stvk, 20000.0, 5000.0);
	body->def.forceModel = fm_fem;
	body->def.massMode = fm_massPerParticle;
	body->def.particleMass = 1.0;
	body->def.damping = 0.999;
	body->def.smoothing = 0.1;
	body->def.rayleighMass = 0.0;
	body->def.rayleighStiffness = 0.0;
	body->initialVelocity = fmMakeVec3(0, 0, 0);
}

bool cliScene_Load(const char* path, cliScene* scene)
{
	cliSceneDefaults(scene, path);
	size_t size = 0;
	char* text = cliReadFile(path, &size);
	if (text == NULL)
		return false;
	bool ok = cliScene_LoadText(path, text, size, stderr, scene);
	free(text);
	return ok;
}

// "file:line:column: message" for byte @p offset of the text.
static bool cliJsonFailAt(const cliJson* j, size_t offset, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
static bool cliJsonFailAt(const cliJson* j, size_t offset, const char* format, ...)
{
	int line, column;
	cliLineColumn(j->text, offset, &line, &column);
	char message[512];
	va_list args;
	va_start(args, format);
	vsnprintf(message, sizeof message, format, args);
	va_end(args);
	if (j->messages != NULL)
		fprintf(j->messages, "%s:%d:%d: %s\n", j->file, line, column, message);
	return false;
}

// What the text holds at @p offset, for messages: up to 24 bytes of its line in quotes
// (other bytes than printable ASCII as '?'), or "the end of the file".
static void cliDescribeText(const cliJson* j, size_t offset, char* out, size_t size)
{
	size_t rest = offset;
	while (rest < j->size && strchr(" \t\r\n", j->text[rest]) != NULL)
		rest += 1;
	if (rest >= j->size)
	{
		snprintf(out, size, "the end of the file");
		return;
	}
	char shown[32];
	size_t n = 0;
	for (size_t i = offset; i < j->size && n < 24 && j->text[i] != '\n' && j->text[i] != '\r'; ++i)
	{
		unsigned char c = (unsigned char)j->text[i];
		shown[n++] = c >= 32 && c < 127 ? (char)c : '?';
	}
	shown[n] = 0;
	bool cut = offset + n < j->size && j->text[offset + n] != '\n' && j->text[offset + n] != '\r';
	snprintf(out, size, "'%s%s'", shown, cut ? "..." : "");
}

// Containers open at byte @p offset (strings skipped): tells a nesting limit from a syntax error.
static int cliJsonDepthAt(const cliJson* j, size_t offset)
{
	int depth = 0;
	bool inString = false;
	for (size_t i = 0; i < offset && i < j->size; ++i)
	{
		char c = j->text[i];
		if (inString)
		{
			if (c == '\\')
				++i;
			else if (c == '"')
				inString = false;
		}
		else if (c == '"')
			inString = true;
		else if (c == '{' || c == '[')
			++depth;
		else if (c == '}' || c == ']')
			--depth;
	}
	return depth;
}

// cJSON decodes "\u0000" into a NUL byte that ends its C string, silently truncating the
// string (a key "mesh\u0000x" would read as "mesh"). Find the first such escape in valid JSON.
static bool cliFindNulEscape(const cliJson* j, size_t* offset)
{
	bool inString = false;
	for (size_t i = 0; i < j->size; ++i)
	{
		char c = j->text[i];
		if (!inString)
			inString = c == '"';
		else if (c == '"')
			inString = false;
		else if (c == '\\')
		{
			if (i + 5 < j->size && j->text[i + 1] == 'u' && memcmp(j->text + i + 2, "0000", 4) == 0)
			{
				*offset = i;
				return true;
			}
			++i; // the escaped character
		}
	}
	return false;
}

// JSON text to a cJSON tree, or a located message: a syntax error says what it found, a
// nesting limit is named, text after the scene object and NUL escapes are errors.
// The first offset at or after @p at that is not JSON whitespace (j->size at the end).
static size_t cliSkipSpace(const cliJson* j, size_t at)
{
	while (at < j->size && strchr(" \t\r\n", j->text[at]) != NULL)
		at += 1;
	return at;
}

static cJSON* cliParseJson(const cliJson* j)
{
	char found[48];
	const char* end = NULL;
	cJSON* root = cJSON_ParseWithLengthOpts(j->text, j->size, &end, false);
	size_t offset = end != NULL && end >= j->text ? (size_t)(end - j->text) : 0;
	if (root == NULL)
	{
		// cJSON reports a text that ends too early at its last byte: point past it instead.
		if (cliSkipSpace(j, offset) >= j->size)
			offset = j->size; // only whitespace left: the file ended too early
		cliDescribeText(j, offset, found, sizeof found);
		if (offset < j->size && (j->text[offset] == '{' || j->text[offset] == '[') &&
		    cliJsonDepthAt(j, offset) >= CJSON_NESTING_LIMIT)
			cliJsonFailAt(j, offset,
			              "JSON nested too deeply: more than %d arrays and objects "
			              "inside each other",
			              CJSON_NESTING_LIMIT);
		else
			cliJsonFailAt(j, offset, "JSON syntax error at %s", found);
		return NULL;
	}
	// Only whitespace may follow the scene (cJSON stops after the first value and, without
	// require_null_terminated, would ignore a second object or any trailing text).
	offset = cliSkipSpace(j, offset);
	size_t nul = 0;
	if (offset < j->size)
	{
		cliDescribeText(j, offset, found, sizeof found);
		if (j->text[offset] == '{' || j->text[offset] == '[')
			cliJsonFailAt(j, offset,
			              "a second JSON value after the scene object, found %s (a scene file "
			              "holds one object)",
			              found);
		else
			cliJsonFailAt(j, offset, "text after the end of the scene object, found %s", found);
	}
	else if (cliFindNulEscape(j, &nul))
		cliJsonFailAt(j, nul,
		              "\\u0000 (a NUL character) in a string: scene strings cannot "
		              "hold one");
	else
		return root;
	cJSON_Delete(root);
	return NULL;
}

bool cliScene_LoadText(const char* name, const char* text, size_t size, FILE* messages,
                       cliScene* scene)
{
	cliSceneDefaults(scene, name);
	if (size > CLI_MAX_FILE_BYTES)
	{
		if (messages != NULL)
			fprintf(messages, "%s: %zu bytes, more than the %zu MiB limit\n", name, size,
			        CLI_MAX_FILE_BYTES >> 20);
		return false;
	}
	cliJson j;
	j.file = name;
	j.text = text;
	j.size = size;
	j.messages = messages;
	const char* nul = memchr(text, 0, size);
	if (nul != NULL)
		return cliJsonFailAt(&j, (size_t)(nul - text), "NUL byte in a JSON file");
	// The folder of the scene, with its trailing slash ("" for the current directory).
	const char* slash = strrchr(name, '/');
	size_t folderLength = slash ? (size_t)(slash - name) + 1 : 0;
	if (folderLength >= sizeof j.folder)
	{
		if (messages != NULL)
			fprintf(messages, "%s: path too long\n", name);
		return false;
	}
	memcpy(j.folder, name, folderLength);
	j.folder[folderLength] = 0;
	// A NUL-terminated copy: the line finder searches the text with strstr.
	char* copy = malloc(size + 1);
	if (copy == NULL)
	{
		if (messages != NULL)
			fprintf(messages, "%s: out of memory\n", name);
		return false;
	}
	memcpy(copy, text, size);
	copy[size] = 0;
	j.text = copy;

	cJSON* root = cliParseJson(&j);
	bool ok = root != NULL && cliParseScene(&j, root, scene);
	cJSON_Delete(root);
	free(copy);
	if (!ok)
		cliScene_Free(scene);
	return ok;
}

void cliScene_Free(cliScene* scene)
{
	for (int i = 0; i < scene->bodyCount; ++i)
	{
		free(scene->bodies[i].pins);
		free(scene->bodies[i].loads);
		free(scene->bodies[i].pressures);
		free(scene->bodies[i].attachments);
		free(scene->bodies[i].regionMaterials);
		free(scene->bodies[i].regionIds);
	}
	free(scene->bodies);
	scene->bodies = NULL;
	scene->bodyCount = 0;
	free(scene->colliders);
	scene->colliders = NULL;
	scene->colliderCount = 0;
}

double cliScene_FrameTime(const cliScene* scene)
{
	return scene->dt * scene->substeps;
}
