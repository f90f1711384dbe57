// Parallel loops (parallel.c): the world's stages split their items into ranges that run on the
// engine's job system (fmWorldDef.enqueueTask / finishTask, as Box2D v3), on femto's own small
// pool of threads, or serially with one worker. A task writes only its own items' outputs, so
// the results are the same bits for any number of workers and any schedule.
#pragma once

#include <femto/types.h>

// Items a task range takes at least: small bodies stay on one worker (waking a worker costs tens
// of microseconds on a shared machine), large ones split (docs/decisions.md, "Task ranges").
#define FM_PARALLEL_MIN_RANGE 4096

// Vertices a range of the explicit step's vertex passes takes at least (the velocity filter's
// too). With the pool's threads polling between the step's back-to-back loops, handing out a
// range costs about 0.5 us, and these passes cost 1-15 ns a vertex: a 10k-tet body's 2200
// vertices split in two.
#define FM_PARALLEL_MIN_VERTICES 1024

typedef struct fmTaskPool fmTaskPool;

// How a world runs its tasks.
typedef struct fmTaskSystem
{
	int workerCount;                    // >= 1
	fmEnqueueTaskCallback* enqueueTask; // the engine's, or NULL
	fmFinishTaskCallback* finishTask;
	void* userTaskContext;
	fmTaskPool* pool; // femto's threads when workerCount > 1 and the engine gives none
} fmTaskSystem;

// Set up from a world def: starts workerCount - 1 threads when the def has no task callbacks.
// False when threads cannot be started (the system then runs serially).
bool fmTaskSystem_Init(fmTaskSystem* system, const fmWorldDef* def);

// Stop and join the threads.
void fmTaskSystem_Shutdown(fmTaskSystem* system);

// Run @p task over items [0, itemCount) in ranges of at least @p minRange items, and wait.
// A NULL @p system runs it serially.
void fmParallelFor(const fmTaskSystem* system, int itemCount, int minRange, fmTaskCallback* task,
                   void* taskContext);

// A task to run on each range of a vertex pass right after the pass's own work on it (while the
// range is in cache): a stage that needs only its own vertices' results of the pass, without a
// pass and a wait of its own.
typedef struct fmThenTask
{
	fmTaskCallback* task;
	void* context;
} fmThenTask;

// Ranges per worker fmParallelForBalanced cuts at most.
#define FM_BALANCED_RANGES 8

// As fmParallelFor, for items whose costs differ widely (the contact detection: vertices far
// from every other body cost a box test, those in a pile a hash query and tens of triangle
// tests): up to FM_BALANCED_RANGES ranges per worker, which the workers take as they finish,
// instead of one each. The results do not depend on the ranges.
void fmParallelForBalanced(const fmTaskSystem* system, int itemCount, int minRange,
                           fmTaskCallback* task, void* taskContext);
