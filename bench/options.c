// Parsing `femto bench`'s options (options.h).
#include "options.h"

#include "cli.h"
#include "commands.h"
#include "meshes.h"
#include "motion.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

// One option with a value: false (and *code set) when the value is missing or bad.
static bool cliBenchIntOption(int argc, char** argv, int* i, int lo, int hi, int* value, int* code)
{
	const char* option = argv[*i];
	const char* text = cliOptionValue("bench", argc, argv, i);
	if (text == NULL || !cliParseIntOption("bench", option, text, lo, hi, value))
	{
		*code = cli_exitUsage;
		return false;
	}
	return true;
}

static bool cliBenchTextOption(int argc, char** argv, int* i, const char** value, int* code)
{
	*value = cliOptionValue("bench", argc, argv, i);
	if (*value == NULL)
		*code = cli_exitUsage;
	return *value != NULL;
}

// A switch without a value; false when @p arg is none of them.
static bool cliBenchSwitch(const char* arg, cliBenchOptions* o, bool* onlyExplicit,
                           bool* onlyImplicit)
{
	if (strcmp(arg, "--quick") == 0)
		o->quick = true;
	else if (strcmp(arg, "--explicit") == 0)
		*onlyExplicit = true;
	else if (strcmp(arg, "--implicit") == 0)
		*onlyImplicit = true;
	else if (strcmp(arg, "--no-plot") == 0)
		o->noPlot = true;
	else if (strcmp(arg, "--peers") == 0)
		o->peers = cli_peersRequired;
	else if (strcmp(arg, "--no-peers") == 0)
		o->noPeers = true;
	else if (strcmp(arg, "--deterministic") == 0)
		o->deterministic = true;
	else
		return false;
	return true;
}

// An option with a value; false with *code set when it is bad, or with *code -1 when @p argv[*i]
// is no such option.
static bool cliBenchValueOption(int argc, char** argv, int* i, cliBenchOptions* o, int* code)
{
	const char* arg = argv[*i];
	const char* families = NULL;
	*code = -1;
	if (strcmp(arg, "--max-tets") == 0)
		return cliBenchIntOption(argc, argv, i, 1, INT_MAX, &o->maxTets, code);
	if (strcmp(arg, "--repeats") == 0)
		return cliBenchIntOption(argc, argv, i, 1, 1000, &o->repeats, code);
	if (strcmp(arg, "--frames") == 0)
		return cliBenchIntOption(argc, argv, i, 2, 100000, &o->frames, code);
	if (strcmp(arg, "--workers") == 0)
		return cliBenchIntOption(argc, argv, i, 1, FM_MAX_WORKERS, &o->workers, code);
	if (strcmp(arg, "--implicit-solver") == 0)
	{
		const char* name = NULL;
		if (!cliBenchTextOption(argc, argv, i, &name, code))
			return false;
		if (strcmp(name, "newton") != 0 && strcmp(name, "vbd") != 0)
		{
			*code =
			    cliUsageError("bench", "--implicit-solver: expected newton or vbd, got '%s'", name);
			return false;
		}
		o->solver = strcmp(name, "vbd") == 0 ? fm_solverVbd : fm_solverNewton;
		return true;
	}
	if (strcmp(arg, "--simd") == 0)
	{
		const char* level = NULL;
		if (!cliBenchTextOption(argc, argv, i, &level, code))
			return false;
		if (!fmSimdLevelFromName(level, &o->simd))
		{
			*code = cliUsageError(
			    "bench", "--simd: expected auto, off, scalar, sse2, avx2 or avx512, got '%s'",
			    level);
			return false;
		}
		return true;
	}
	if (strcmp(arg, "--csv") == 0)
		return cliBenchTextOption(argc, argv, i, &o->csvPath, code);
	if (strcmp(arg, "--plot") == 0)
		return cliBenchTextOption(argc, argv, i, &o->plotPath, code);
	if (strcmp(arg, "--bullet") == 0)
	{
		o->peers = cli_peersRequired;
		return cliBenchTextOption(argc, argv, i, &o->bulletPath, code);
	}
	if (strcmp(arg, "--meshes") == 0)
	{
		if (!cliBenchTextOption(argc, argv, i, &families, code))
			return false;
		*code = cliBenchParseFamilies(families, &o->families) ? -1 : cli_exitUsage;
		return *code < 0;
	}
	return false;
}

// Fill the defaults and check the combinations; -1 when the options are good.
static int cliBenchFinishOptions(cliBenchOptions* o, bool onlyExplicit, bool onlyImplicit)
{
	if (onlyExplicit && onlyImplicit)
		return cliUsageError("bench", "give --explicit or --implicit, not both");
	if (o->noPlot && o->plotPath != NULL)
		return cliUsageError("bench", "give --plot or --no-plot, not both");
	if (o->noPeers && o->peers == cli_peersRequired)
		return cliUsageError("bench", "give --peers (or --bullet) or --no-peers, not both");
	if (o->noPeers)
		o->peers = cli_peersOff;
	o->explicitSteps = !onlyImplicit;
	o->implicitFrames = !onlyExplicit;
	if (o->quick && o->maxTets > 10368)
		o->maxTets = 10368;
	if (o->repeats == 0)
		o->repeats = o->quick ? 3 : 5;
	if (o->workers == 0)
		o->workers = cliCoresAvailable();
	if (o->frames == 0)
		o->frames = CLI_MOTION_FRAMES;
	return -1;
}

int cliBenchParseOptions(int argc, char** argv, cliBenchOptions* o)
{
	memset(o, 0, sizeof *o);
	o->maxTets = 2000000;
	o->families = CLI_BENCH_ALL_FAMILIES;
	bool onlyExplicit = false, onlyImplicit = false;
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		int code = -1;
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(cliBenchHelp, stdout);
			return cli_exitOk;
		}
		if (cliBenchSwitch(arg, o, &onlyExplicit, &onlyImplicit) ||
		    cliBenchValueOption(argc, argv, &i, o, &code))
			continue;
		if (code >= 0)
			return code;
		return cliUsageError("bench", "unknown argument '%s'", arg);
	}
	return cliBenchFinishOptions(o, onlyExplicit, onlyImplicit);
}
