// Image and camera options (view_options.h).
#include "view_options.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/// Most pixels along a side of a picture.
#define CLI_MAX_IMAGE_SIDE 8192

// The names of the fmDrawFlags on the command line and in scripts.
static const struct
{
	const char* name;
	unsigned flag;
} cliDrawNames[] = {
    {"surfaces", fm_drawSurfaces},
    {"stress", fm_drawStress},
    {"tets", fm_drawTetEdges},
    {"inverted", fm_drawInvertedTets},
    {"pins", fm_drawPins},
    {"targets", fm_drawTargets},
    {"floor", fm_drawFloor},
    {"contacts", fm_drawContacts},
    {"colliders", fm_drawColliders},
    {"fibres", fm_drawFibres},
    {"plastic", fm_drawPlastic},
    {"damage", fm_drawDamage},
    {"all", fm_drawAll},
    {"none", 0},
};

void cliViewOptions_Init(cliViewOptions* o)
{
	memset(o, 0, sizeof *o);
	o->width = 640;
	o->height = 480;
	o->fps = 30.0;
	o->drawFlags = fm_drawSurfaces | fm_drawFloor | fm_drawPins | fm_drawTargets | fm_drawColliders;
}

bool cliParseDrawFlags(const char* text, unsigned* flags, char* bad, size_t badSize)
{
	unsigned result = 0;
	const char* p = text;
	for (;;)
	{
		size_t length = strcspn(p, ",");
		bool known = false;
		for (size_t i = 0; i < sizeof cliDrawNames / sizeof cliDrawNames[0] && !known; ++i)
			if (strlen(cliDrawNames[i].name) == length &&
			    strncmp(cliDrawNames[i].name, p, length) == 0)
			{
				result |= cliDrawNames[i].flag;
				known = true;
			}
		if (!known)
		{
			snprintf(bad, badSize, "%.*s", (int)length, p);
			return false;
		}
		if (p[length] == 0)
			break;
		p += length + 1;
	}
	*flags = result;
	return true;
}

// "640x480" with both sides in [16, CLI_MAX_IMAGE_SIDE].
static bool cliParseSize(const char* text, int* width, int* height)
{
	char tail = 0;
	if (sscanf(text, "%dx%d%c", width, height, &tail) != 2)
		return false;
	return *width >= 16 && *height >= 16 && *width <= CLI_MAX_IMAGE_SIDE &&
	       *height <= CLI_MAX_IMAGE_SIDE;
}

// "X,Y,Z" as three finite numbers.
static bool cliParseTriple(const char* text, fmVec3* v)
{
	char copy[256];
	if (strlen(text) >= sizeof copy)
		return false;
	strcpy(copy, text);
	double xyz[3];
	char* rest = copy;
	for (int i = 0; i < 3; ++i)
	{
		char* comma = strchr(rest, ',');
		if ((comma == NULL) != (i == 2))
			return false;
		if (comma != NULL)
			*comma = 0;
		if (!cliParseDouble(rest, &xyz[i]))
			return false;
		rest = comma + 1;
	}
	*v = fmMakeVec3(xyz[0], xyz[1], xyz[2]);
	return true;
}

// One "--camera-*" angle or distance in [lo, hi].
static bool cliParseRanged(const char* command, const char* option, const char* value, double lo,
                           double hi, double* out, int* code)
{
	if (!cliParseDouble(value, out) || *out < lo || *out > hi)
	{
		*code = cliUsageError(command, "%s: expected a number in [%g, %g], got '%s'", option, lo,
		                      hi, value);
		return false;
	}
	return true;
}

// The options with a value; *code set on error.
static void cliParseValued(cliViewOptions* o, const char* command, const char* arg,
                           const char* value, int* code)
{
	char bad[64];
	if (strcmp(arg, "--gif") == 0)
		o->gifPath = value;
	else if (strcmp(arg, "--png") == 0)
		o->pngDirectory = value;
	else if (strcmp(arg, "--size") == 0)
	{
		o->hasSize = true;
		if (!cliParseSize(value, &o->width, &o->height))
			*code = cliUsageError(command, "--size: expected WxH with sides in [16, %d], got '%s'",
			                      CLI_MAX_IMAGE_SIDE, value);
	}
	else if (strcmp(arg, "--fps") == 0)
		o->hasFps = cliParseRanged(command, arg, value, 1.0, 1000.0, &o->fps, code);
	else if (strcmp(arg, "--camera-distance") == 0)
		o->hasDistance = cliParseRanged(command, arg, value, 1e-3, 1e6, &o->distance, code);
	else if (strcmp(arg, "--camera-yaw") == 0)
		o->hasYaw = cliParseRanged(command, arg, value, -360.0, 360.0, &o->yaw, code);
	else if (strcmp(arg, "--camera-pitch") == 0)
		o->hasPitch = cliParseRanged(command, arg, value, -89.0, 89.0, &o->pitch, code);
	else if (strcmp(arg, "--camera-target") == 0)
	{
		o->hasTarget = cliParseTriple(value, &o->target);
		if (!o->hasTarget)
			*code = cliUsageError(command, "--camera-target: expected X,Y,Z (m), got '%s'", value);
	}
	else if (strcmp(arg, "--draw") == 0)
	{
		o->hasDraw = true;
		if (!cliParseDrawFlags(value, &o->drawFlags, bad, sizeof bad))
			*code = cliUsageError(command,
			                      "--draw: unknown '%s' (expected a comma-separated list of "
			                      "surfaces, stress, tets, inverted, pins, targets, floor, "
			                      "contacts, colliders, fibres, plastic, damage, all, none)",
			                      bad);
	}
}

bool cliViewOptions_Parse(cliViewOptions* o, const char* command, int argc, char** argv, int* index,
                          int* code)
{
	static const char* const valued[] = {
	    "--gif",        "--png",          "--size",          "--fps", "--camera-distance",
	    "--camera-yaw", "--camera-pitch", "--camera-target", "--draw"};
	const char* arg = argv[*index];
	*code = -1;
	for (size_t i = 0; i < sizeof valued / sizeof valued[0]; ++i)
	{
		if (strcmp(arg, valued[i]) != 0)
			continue;
		const char* value = cliOptionValue(command, argc, argv, index);
		if (value == NULL)
			*code = cli_exitUsage;
		else
			cliParseValued(o, command, arg, value, code);
		return true;
	}
	return false;
}

bool cliViewOptions_WantsImages(const cliViewOptions* o)
{
	return o->gifPath != NULL || o->pngDirectory != NULL;
}

void cliViewOptions_TakeCamera(cliViewOptions* o, const cliCameraPreset* preset)
{
	if (!o->hasTarget && preset->hasTarget)
		o->hasTarget = true, o->target = preset->target;
	if (!o->hasDistance && preset->hasDistance)
		o->hasDistance = true, o->distance = preset->distance;
	if (!o->hasYaw && preset->hasYaw)
		o->hasYaw = true, o->yaw = preset->yaw;
	if (!o->hasPitch && preset->hasPitch)
		o->hasPitch = true, o->pitch = preset->pitch;
}
