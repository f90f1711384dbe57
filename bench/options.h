// The options of `femto bench` (options.c); the help text is cliBenchHelp (cmd_bench.c).
#pragma once

#include <femto/femto.h>

#include <stdbool.h>

/// What the peers should do.
typedef enum cliBenchPeerMode
{
	cli_peersAuto,     ///< when femto-bench-bullet was built
	cli_peersRequired, ///< --peers, --bullet: an error without it
	cli_peersOff,      ///< --no-peers
} cliBenchPeerMode;

/// The parsed options, defaults filled in.
typedef struct cliBenchOptions
{
	bool quick;              ///< --quick: up to 10368 tets, 3 repetitions
	int maxTets;             ///< --max-tets (default 2000000)
	unsigned families;       ///< --meshes: bit 1 << cliBenchFamily (default all)
	bool explicitSteps;      ///< time explicit steps (not --implicit)
	bool implicitFrames;     ///< time implicit frames (not --explicit)
	int repeats;             ///< --repeats (default 5, --quick 3)
	int frames;              ///< --frames: each motion scene's and the props' (default 120)
	int workers;             ///< --workers (default: the cores available)
	const char* csvPath;     ///< --csv, or NULL
	const char* plotPath;    ///< --plot, or NULL
	bool noPlot;             ///< --no-plot
	cliBenchPeerMode peers;  ///< --peers, --bullet, --no-peers
	bool noPeers;            ///< --no-peers was given
	const char* bulletPath;  ///< --bullet, or NULL
	fmSimdLevel simd;        ///< --simd (default fm_simdAuto)
	bool deterministic;      ///< --deterministic
	fmImplicitSolver solver; ///< --implicit-solver (default fm_solverNewton)
} cliBenchOptions;

/// Parse @p argv (argv[0] is "bench"). Returns -1 when the run should go on, else the exit code:
/// cli_exitOk after printing the help, cli_exitUsage after a usage error.
int cliBenchParseOptions(int argc, char** argv, cliBenchOptions* o);
