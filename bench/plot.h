// The PNG plot of `femto bench` (plot.c): explicit StVK ns per tet-step against the tet count,
// log-log, one line per mesh family (box, beam) and worker count, the bandwidth bound of each
// worker count dashed; beside it, when the run timed frames in motion, each body's 95th
// percentile (solid) and median (dashed) frame over every scene against its tets, one colour
// per integrator and worker count. Drawn by gnuplot, found on PATH at run time.
#pragma once

#include "report.h"

/// What became of the plot.
typedef enum cliBenchPlotResult
{
	cli_plotWritten, ///< @p png is written (whole: under a temporary name, then renamed)
	cli_plotSkipped, ///< nothing to plot or no gnuplot: said so on stdout, not an error
	cli_plotFailed,  ///< gnuplot or the file failed: said so on stderr
} cliBenchPlotResult;

/// Plot the explicit StVK rows and the rows in motion of @p report into @p png. @p folder is the
/// run's temporary folder (the gnuplot script goes there; NULL skips the plot); @p title heads the
/// plot.
cliBenchPlotResult cliBenchPlot_Write(const cliBenchReport* report, const char* png,
                                      const char* folder, const char* title);
