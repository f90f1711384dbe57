// Parallel loops (parallel.c): the world's stages split their items into ranges that run on the
// engine's job system (fmWorldDef.enqueueTask / finishTask, as Box2D v3), on femto's own small
// pool of threads, or serially with one worker. A task writes only its own items' outputs, so
// the results are the same bits for any number of workers and any schedule.
#pragma once

#include <femto/types.h>

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
