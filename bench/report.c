// The rows of a bench run and its CSV (report.h).
#include "report.h"

#include "tools.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

cliBenchResult cliBenchResult_Make(const cliBenchMesh* mesh, const char* integrator,
                                   const char* model, int workers)
{
	cliBenchResult row;
	memset(&row, 0, sizeof row);
	snprintf(row.mesh, sizeof row.mesh, "%s", mesh->label);
	row.family = mesh->family;
	row.tets = mesh->tets;
	snprintf(row.integrator, sizeof row.integrator, "%s", integrator);
	row.model = model;
	row.workers = workers;
	row.nsPerTetStep = row.msPerFrame = row.newtonPerFrame = row.cgPerFrame = row.boundNs = NAN;
	row.contacts = row.contactShare = row.broadShare = row.narrowShare = NAN;
	row.scene = "";
	row.p95 = row.worst = row.newtonWorst = row.cgWorst = row.accuracy = NAN;
	row.loadMs = row.createMs = row.firstStepMs = NAN;
	return row;
}

bool cliBenchReport_Open(cliBenchReport* report, const char* csvPath)
{
	memset(report, 0, sizeof *report);
	report->csvPath = csvPath;
	if (csvPath == NULL)
		return true;
	if (!cliBenchTempName(csvPath, report->csvTemp, sizeof report->csvTemp))
		return false;
	report->csv = fopen(report->csvTemp, "w");
	if (report->csv == NULL)
	{
		cliError("%s: cannot open for writing: %s", report->csvTemp, strerror(errno));
		return false;
	}
	fprintf(report->csv, "%s\n", CLI_BENCH_CSV_HEADER);
	return true;
}

// ",value" with @p digits decimals, or "," alone for NAN.
static void cliBenchCsvNumber(FILE* csv, double value, int digits)
{
	if (isnan(value))
		fputc(',', csv);
	else
		fprintf(csv, ",%.*f", digits, value);
}

bool cliBenchReport_Add(cliBenchReport* report, const cliBenchResult* row)
{
	cliBenchResult* grown = realloc(report->rows, (size_t)(report->count + 1) * sizeof *grown);
	if (grown == NULL)
	{
		cliError("bench: out of memory");
		return false;
	}
	report->rows = grown;
	report->rows[report->count++] = *row;
	if (report->csv != NULL)
	{
		fprintf(report->csv, "%s,%d,%s,%s,%d", row->mesh, row->tets, row->integrator, row->model,
		        row->workers);
		cliBenchCsvNumber(report->csv, row->nsPerTetStep, 3);
		cliBenchCsvNumber(report->csv, row->msPerFrame, 3);
		cliBenchCsvNumber(report->csv, row->newtonPerFrame, 2);
		cliBenchCsvNumber(report->csv, row->cgPerFrame, 1);
		cliBenchCsvNumber(report->csv, row->boundNs, 3);
		cliBenchCsvNumber(report->csv, row->contacts, 0);
		cliBenchCsvNumber(report->csv, row->contactShare, 4);
		cliBenchCsvNumber(report->csv, row->broadShare, 4);
		cliBenchCsvNumber(report->csv, row->narrowShare, 4);
		fprintf(report->csv, ",%s", row->scene);
		cliBenchCsvNumber(report->csv, row->p95, 3);
		cliBenchCsvNumber(report->csv, row->worst, 3);
		cliBenchCsvNumber(report->csv, row->newtonWorst, 0);
		cliBenchCsvNumber(report->csv, row->cgWorst, 0);
		cliBenchCsvNumber(report->csv, row->accuracy, 5);
		cliBenchCsvNumber(report->csv, row->loadMs, 2);
		cliBenchCsvNumber(report->csv, row->createMs, 2);
		cliBenchCsvNumber(report->csv, row->firstStepMs, 2);
		fputc('\n', report->csv);
	}
	return true;
}

const cliBenchResult* cliBenchReport_Find(const cliBenchReport* report, const char* mesh,
                                          const char* integrator, const char* model, int workers)
{
	for (int i = 0; i < report->count; ++i)
	{
		const cliBenchResult* row = &report->rows[i];
		if (strcmp(row->mesh, mesh) == 0 && strcmp(row->integrator, integrator) == 0 &&
		    strcmp(row->model, model) == 0 && row->workers == workers)
			return row;
	}
	return NULL;
}

bool cliBenchReport_Close(cliBenchReport* report)
{
	bool ok = true;
	if (report->csv != NULL)
	{
		ok = !ferror(report->csv);
		ok = fclose(report->csv) == 0 && ok;
		if (!ok)
			cliError("%s: write error", report->csvTemp);
		else if (rename(report->csvTemp, report->csvPath) != 0)
		{
			cliError("%s: cannot rename %s over it: %s", report->csvPath, report->csvTemp,
			         strerror(errno));
			ok = false;
		}
		if (!ok)
			remove(report->csvTemp);
	}
	free(report->rows);
	memset(report, 0, sizeof *report);
	return ok;
}
