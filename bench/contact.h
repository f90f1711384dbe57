// The contact rows of `femto bench` (contact.c): three of the seeds' houses stacked (StVK and
// Neo-Hookean, implicit), ten piled on the floor (explicit at the seeds' settings, implicit at
// 1/60 s) and ten such piles side by side (implicit), each beside the same houses apart, and a
// 100k-tet box resting on a triangle-mesh ground, with the contact count and the share of the
// step spent in the contact stage and its broad and narrow phases (fmWorld_GetProfile).
#pragma once

#include "options.h"
#include "report.h"

/// The houses in the pile (--quick: CLI_BENCH_QUICK_PILE_HOUSES).
#define CLI_BENCH_PILE_HOUSES 10
/// The houses in the pile of a --quick run.
#define CLI_BENCH_QUICK_PILE_HOUSES 3

/// The houses of the big pile: ten piles of CLI_BENCH_PILE_HOUSES side by side (not --quick).
#define CLI_BENCH_BIG_PILE_HOUSES 100
/// Tets of one house (data/house2.ele).
#define CLI_BENCH_HOUSE_TETS 1389

/// Time the contact rows whose size is at most o->maxTets (the pile counts all its houses'
/// tets; --quick piles three houses for 1.5 s instead of ten for 5 s), print them and add them to
/// @p report; the ground's OBJ is written in @p folder (NULL: that row is skipped, and says why).
/// Sets *code to cli_exitInput when a row fails.
void cliBenchContactRows(const cliBenchOptions* o, cliBenchReport* report, const char* folder,
                         int* code);
