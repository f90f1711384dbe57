// The rows of one `femto bench` run (report.c): kept for the plot and the peers' ratios, and
// written as CSV, one row per case, under a temporary name renamed when the run ends.
#pragma once

#include "meshes.h"

#include <stdio.h>

/// The CSV's header (the columns).
#define CLI_BENCH_CSV_HEADER                                                                       \
	"mesh,tets,integrator,model,workers,ns_per_tet_step,ms_per_frame,newton_per_frame,"            \
	"cg_per_frame,bound_ns_per_tet_step,contacts,contact_share,broad_phase_share,"                 \
	"narrow_phase_share,scene,p95_ms,worst_ms,newton_worst,cg_worst,accuracy,"                     \
	"load_ms,create_ms,first_step_ms"

/// One case; NAN in a number that does not apply (written as an empty field).
typedef struct cliBenchResult
{
	char mesh[16];         ///< the mesh's label
	cliBenchFamily family; ///< the mesh's family
	int tets;              ///< tets
	char integrator[32];   ///< "explicit", "implicit game", "implicit 1e-6", "bullet implicit"
	const char* model;     ///< fmMaterialModelName()
	int workers;           ///< workers
	double nsPerTetStep;   ///< explicit: median ns per tet per step
	double msPerFrame;     ///< implicit: median ms per 1/60 s frame
	double newtonPerFrame; ///< implicit: mean Newton iterations a frame
	double cgPerFrame;     ///< implicit: mean CG iterations a frame
	double boundNs;        ///< explicit: ns per tet-step at the triad bandwidth
	double contacts;       ///< contact rows: median contacts after a frame
	double contactShare;   ///< contact rows: of the step time, the contact stage (0 to 1)
	double broadShare;     ///< contact rows: its broad phase
	double narrowShare;    ///< contact rows: its narrow phase
	const char* scene;     ///< "steps", "rest", "contact", or the motion scene ("all": pooled)
	double p95;            ///< ms, the 95th percentile frame (contact and motion rows)
	double worst;          ///< ms, the slowest frame (contact and motion rows)
	double newtonWorst;    ///< motion rows, implicit: Newton iterations of the slowest frame
	double cgWorst;        ///< motion rows, implicit: CG iterations of the slowest frame
	double accuracy;       ///< motion rows, implicit game: distance from the 1e-6 path / size
	double loadMs;         ///< start-up rows: reading the mesh file
	double createMs;       ///< start-up rows: creating the world and the body
	double firstStepMs;    ///< start-up rows: the first step
} cliBenchResult;

/// A result with every number NAN.
cliBenchResult cliBenchResult_Make(const cliBenchMesh* mesh, const char* integrator,
                                   const char* model, int workers);

/// The rows so far and the CSV being written (if any).
typedef struct cliBenchReport
{
	cliBenchResult* rows; ///< malloc'd
	int count;
	FILE* csv;                       ///< NULL without --csv
	const char* csvPath;             ///< the final name
	char csvTemp[CLI_MAX_PATH + 64]; ///< the name written to until the run ends
} cliBenchReport;

/// Start a report; with @p csvPath (not NULL), open its temporary file and write the header.
/// Prints the reason and returns false when the file cannot be opened.
bool cliBenchReport_Open(cliBenchReport* report, const char* csvPath);

/// Keep @p row and write it to the CSV. False (with a message) when memory runs out.
bool cliBenchReport_Add(cliBenchReport* report, const cliBenchResult* row);

/// The first row of @p mesh with @p integrator, @p model and @p workers, or NULL.
const cliBenchResult* cliBenchReport_Find(const cliBenchReport* report, const char* mesh,
                                          const char* integrator, const char* model, int workers);

/// Finish the CSV (rename it into place) and free the rows. False, with a message and no file
/// left behind, on a write error.
bool cliBenchReport_Close(cliBenchReport* report);
