// The gnuplot script and its run (plot.h).
#include "plot.h"

#include "tools.h"

#include <errno.h>
#include <math.h>
#include <string.h>

// Whether @p row is an explicit StVK row of @p family (or any family for -1) on @p workers.
static bool cliPlotRow(const cliBenchResult* row, int family, int workers)
{
	return strcmp(row->integrator, "explicit") == 0 && strcmp(row->model, "stvk") == 0 &&
	       (family < 0 || (int)row->family == family) && row->workers == workers &&
	       !isnan(row->nsPerTetStep);
}

// The worker counts of the explicit StVK rows, ascending, at most @p max.
static int cliPlotWorkerCounts(const cliBenchReport* report, int* counts, int max)
{
	int n = 0;
	for (int i = 0; i < report->count; ++i)
	{
		const cliBenchResult* row = &report->rows[i];
		bool seen = false;
		for (int k = 0; k < n; ++k)
			seen = seen || counts[k] == row->workers;
		if (!seen && n < max && cliPlotRow(row, -1, row->workers))
		{
			int k = n++;
			for (; k > 0 && counts[k - 1] > row->workers; --k)
				counts[k] = counts[k - 1];
			counts[k] = row->workers;
		}
	}
	return n;
}

// A gnuplot single-quoted string: a quote inside is doubled.
static void cliPlotQuoted(FILE* script, const char* text)
{
	fputc('\'', script);
	for (const char* c = text; *c != '\0'; ++c)
	{
		if (*c == '\'')
			fputc('\'', script);
		fputc(*c, script);
	}
	fputc('\'', script);
}

// Data block $sK: tets and ns of one family and worker count; false when it has no point.
// The bound block $bK: the bound of that worker count from the smallest to the largest mesh.
static bool cliPlotBlock(FILE* script, const cliBenchReport* report, int family, int workers,
                         int block)
{
	int points = 0;
	for (int i = 0; i < report->count; ++i)
		points += cliPlotRow(&report->rows[i], family, workers);
	if (points == 0)
		return false;
	fprintf(script, "$s%d << EOD\n", block);
	for (int i = 0; i < report->count; ++i)
		if (cliPlotRow(&report->rows[i], family, workers))
			fprintf(script, "%d %.6g\n", report->rows[i].tets, report->rows[i].nsPerTetStep);
	fprintf(script, "EOD\n");
	return true;
}

static bool cliPlotBoundBlock(FILE* script, const cliBenchReport* report, int workers, int block)
{
	int lo = 0, hi = 0;
	double bound = NAN;
	for (int i = 0; i < report->count; ++i)
	{
		const cliBenchResult* row = &report->rows[i];
		if (!cliPlotRow(row, -1, workers))
			continue;
		lo = lo == 0 || row->tets < lo ? row->tets : lo;
		hi = row->tets > hi ? row->tets : hi;
		bound = isnan(row->boundNs) || row->boundNs <= 0.0 ? bound : row->boundNs;
	}
	if (isnan(bound))
		return false;
	fprintf(script, "$b%d << EOD\n%d %.6g\n%d %.6g\nEOD\n", block, lo, bound, hi, bound);
	return true;
}

static void cliPlotHeader(FILE* script, const char* output, const char* title, bool panels)
{
	fprintf(script, "set terminal pngcairo size %d,600 noenhanced font ',10'\nset output ",
	        panels ? 1500 : 900);
	cliPlotQuoted(script, output);
	fprintf(script, "\n");
	if (panels)
	{
		fprintf(script, "set multiplot layout 1,2 title ");
		cliPlotQuoted(script, title);
		fprintf(script, "\n");
	}
	else
	{
		fprintf(script, "set title ");
		cliPlotQuoted(script, title);
		fprintf(script, "\n");
	}
	fprintf(script, "set logscale xy\nset grid xtics ytics mxtics mytics\nset xlabel 'tets'\n"
	                "set key outside right top\nset format x '%%.0f'\n");
}

// Append ", clause" (or " clause" first) to the plot command.
static void cliPlotClause(char* plot, size_t size, const char* clause)
{
	size_t used = strlen(plot);
	snprintf(plot + used, size - used, "%s%s", strcmp(plot, "plot") == 0 ? " " : ", \\\n  ",
	         clause);
}

// The explicit panel: data blocks, then one plot command over them. False when nothing is
// plotted (nothing written but the blocks).
static bool cliPlotExplicit(FILE* script, const cliBenchReport* report)
{
	static const int families[2] = {cli_benchBox, cli_benchBeam};
	int workers[16];
	int counts = cliPlotWorkerCounts(report, workers, 16);
	char plot[8192] = "plot", clause[256];
	for (int w = 0; w < counts; ++w)
	{
		const char* plural = workers[w] == 1 ? "" : "s";
		for (int f = 0; f < 2; ++f)
		{
			int block = 3 * w + f;
			if (!cliPlotBlock(script, report, families[f], workers[w], block))
				continue;
			snprintf(clause, sizeof clause,
			         "$s%d with linespoints lw 2 pt %d lc %d title '%s, %d worker%s'", block,
			         7 + 2 * f, w + 1, cliBenchFamilyName(families[f]), workers[w], plural);
			cliPlotClause(plot, sizeof plot, clause);
		}
		if (cliPlotBoundBlock(script, report, workers[w], 3 * w + 2))
		{
			snprintf(clause, sizeof clause,
			         "$b%d with lines dt 2 lw 1 lc %d title 'bandwidth bound, %d worker%s'",
			         3 * w + 2, w + 1, workers[w], plural);
			cliPlotClause(plot, sizeof plot, clause);
		}
	}
	if (strcmp(plot, "plot") == 0)
		return false;
	fprintf(script, "set ylabel 'ns per tet-step (explicit StVK)'\n%s\n", plot);
	return true;
}

// Whether @p row pools a body's frames in motion ("all") with @p integrator on @p workers.
static bool cliPlotMotionRow(const cliBenchResult* row, const char* integrator, int workers)
{
	return strcmp(row->scene, "all") == 0 && strcmp(row->integrator, integrator) == 0 &&
	       row->workers == workers && !isnan(row->p95);
}

// The panel in motion: each body's frames in motion (every scene), the 95th percentile solid
// and the median dashed, one colour per integrator and worker count. False when no row is.
static bool cliPlotMotion(FILE* script, const cliBenchReport* report)
{
	static const char* const integrators[2] = {"explicit", "implicit game"};
	int workers[16];
	int counts = 0;
	for (int i = 0; i < report->count && counts < 16; ++i)
	{
		const cliBenchResult* row = &report->rows[i];
		bool seen = strcmp(row->scene, "all") != 0;
		for (int k = 0; k < counts; ++k)
			seen = seen || workers[k] == row->workers;
		if (!seen)
			workers[counts++] = row->workers;
	}
	char plot[8192] = "plot", clause[256];
	for (int k = 0; k < 2; ++k)
		for (int w = 0; w < counts; ++w)
		{
			int block = 100 + 2 * k * 16 + w, points = 0;
			for (int i = 0; i < report->count; ++i)
				points += cliPlotMotionRow(&report->rows[i], integrators[k], workers[w]);
			if (points == 0)
				continue;
			fprintf(script, "$m%d << EOD\n", block);
			for (int i = 0; i < report->count; ++i)
				if (cliPlotMotionRow(&report->rows[i], integrators[k], workers[w]))
					fprintf(script, "%d %.6g %.6g\n", report->rows[i].tets, report->rows[i].p95,
					        report->rows[i].msPerFrame);
			fprintf(script, "EOD\n");
			const char* plural = workers[w] == 1 ? "" : "s";
			int colour = 1 + k * counts + w;
			snprintf(clause, sizeof clause,
			         "$m%d using 1:2 with linespoints lw 2 pt 7 lc %d title '%s, %d worker%s, "
			         "95th percentile'",
			         block, colour, integrators[k], workers[w], plural);
			cliPlotClause(plot, sizeof plot, clause);
			snprintf(clause, sizeof clause,
			         "$m%d using 1:3 with linespoints dt 2 lw 1 pt 6 lc %d title 'median'", block,
			         colour);
			cliPlotClause(plot, sizeof plot, clause);
		}
	if (strcmp(plot, "plot") == 0)
		return false;
	fprintf(script, "set ylabel 'ms a 1/60 s frame in motion (every scene)'\n%s\n", plot);
	return true;
}

// Whether the report has rows for the explicit panel, and for the panel in motion.
static void cliPlotPanels(const cliBenchReport* report, bool* explicitRows, bool* motionRows)
{
	*explicitRows = *motionRows = false;
	for (int i = 0; i < report->count; ++i)
	{
		const cliBenchResult* row = &report->rows[i];
		*explicitRows = *explicitRows || (cliPlotRow(row, cli_benchBox, row->workers) ||
		                                  cliPlotRow(row, cli_benchBeam, row->workers));
		*motionRows = *motionRows || (strcmp(row->scene, "all") == 0 && !isnan(row->p95));
	}
}

// The script: the explicit panel and the panel in motion, side by side when both have rows.
// False when nothing is plotted.
static bool cliPlotScript(FILE* script, const cliBenchReport* report, const char* output,
                          const char* title)
{
	bool explicitRows, motionRows;
	cliPlotPanels(report, &explicitRows, &motionRows);
	if (!explicitRows && !motionRows)
		return false;
	cliPlotHeader(script, output, title, explicitRows && motionRows);
	if (explicitRows)
		cliPlotExplicit(script, report);
	if (motionRows)
		cliPlotMotion(script, report);
	if (explicitRows && motionRows)
		fprintf(script, "unset multiplot\n");
	return true;
}

// Run gnuplot on @p script, its messages to @p log; shows them on failure.
static bool cliPlotRun(const char* gnuplot, const char* script, const char* log)
{
	char command[4 * CLI_MAX_PATH] = "";
	if (!cliBenchAppendQuoted(command, sizeof command, gnuplot) ||
	    !cliBenchAppendQuoted(command, sizeof command, script) ||
	    !cliBenchAppendText(command, sizeof command, " >") ||
	    !cliBenchAppendQuoted(command, sizeof command, log) ||
	    !cliBenchAppendText(command, sizeof command, " 2>&1"))
	{
		cliError("bench: the gnuplot command for %s is too long", script);
		return false;
	}
	int status = cliBenchRunCommand(command);
	if (status == 0)
		return true;
	cliError("bench: %s %s failed (exit status %d)", gnuplot, script, status);
	FILE* messages = fopen(log, "r");
	char line[512];
	for (int n = 0; messages != NULL && n < 8 && fgets(line, sizeof line, messages) != NULL; ++n)
		fprintf(stderr, "  gnuplot: %s", line);
	if (messages != NULL)
		fclose(messages);
	return false;
}

// Write the script for @p output into @p path. -1 on a write error, 0 nothing to plot, 1 ok.
static int cliPlotWriteScript(const char* path, const cliBenchReport* report, const char* output,
                              const char* title)
{
	FILE* script = fopen(path, "w");
	if (script == NULL)
	{
		cliError("bench: %s: cannot open for writing: %s", path, strerror(errno));
		return -1;
	}
	bool any = cliPlotScript(script, report, output, title);
	bool ok = !ferror(script);
	ok = fclose(script) == 0 && ok;
	if (!ok)
	{
		cliError("bench: %s: write error", path);
		return -1;
	}
	return any ? 1 : 0;
}

cliBenchPlotResult cliBenchPlot_Write(const cliBenchReport* report, const char* png,
                                      const char* folder, const char* title)
{
	char gnuplot[CLI_MAX_PATH], script[CLI_MAX_PATH], log[CLI_MAX_PATH], temp[CLI_MAX_PATH + 64];
	if (!cliBenchFindProgram("gnuplot", gnuplot, sizeof gnuplot))
	{
		printf("plot: skipped: gnuplot is not on PATH (Debian: apt-get install gnuplot-nox); no "
		       "%s\n",
		       png);
		return cli_plotSkipped;
	}
	if (folder == NULL)
	{
		printf("plot: skipped: no temporary folder for the gnuplot script; no %s\n", png);
		return cli_plotSkipped;
	}
	if (!cliJoinPath(script, sizeof script, folder, "plot.gp") ||
	    !cliJoinPath(log, sizeof log, folder, "gnuplot.log") ||
	    !cliBenchTempName(png, temp, sizeof temp))
		return cli_plotFailed;
	int written = cliPlotWriteScript(script, report, temp, title);
	if (written <= 0)
	{
		if (written == 0)
			printf(
			    "plot: skipped: no explicit StVK box or beam rows and no rows in motion to plot; "
			    "no %s\n",
			    png);
		return written == 0 ? cli_plotSkipped : cli_plotFailed;
	}
	if (!cliPlotRun(gnuplot, script, log))
	{
		remove(temp);
		return cli_plotFailed;
	}
	if (rename(temp, png) != 0)
	{
		cliError("%s: cannot rename %s over it: %s", png, temp, strerror(errno));
		remove(temp);
		return cli_plotFailed;
	}
	printf("plot: wrote %s\n", png);
	return cli_plotWritten;
}
