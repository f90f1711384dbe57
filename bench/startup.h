// The start-up rows of `femto bench` (startup.c): the time from a mesh file to a body's first
// implicit step, stage by stage: reading the TetGen file, creating the world and the body (its
// reordering, rest data and surface), the first 1/60 s step (the solver's pattern, the first
// Hessian and, on large bodies, the multigrid hierarchy) and, for scale, the second step. On
// boxes of about 10k, 100k and 1M tets written as TetGen files.
#pragma once

#include "meshes.h"
#include "options.h"
#include "report.h"

/// Time the start-up of the boxes of at most o->maxTets tets (--quick: up to 10k), each stage
/// its fastest of the run's repeats (one for meshes over 200k tets), print a row each and add
/// them to @p report (scene "startup": the stages in load_ms, create_ms and first_step_ms, the
/// second step in ms_per_frame); the files are written in @p folder (NULL: skipped, and says
/// why). Sets *code to cli_exitInput when a row fails.
void cliBenchStartupRows(const cliBenchOptions* o, const char* folder, cliBenchReport* report,
                         int* code);
