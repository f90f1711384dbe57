// Parallel loops (parallel.h) and femto's own thread pool: the caller and workerCount - 1
// threads each take one contiguous range of a loop, in a fixed split; the caller waits for all.
#include "parallel.h"

#include "core.h"
#include "det_math.h"
#include "fp_env.h"

#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

// Polls of a new loop (a worker) or of the last range (the caller) before sleeping on the
// condition variable: a sleeping thread takes tens of microseconds to wake on a shared machine,
// more than a small body's whole stage, and an implicit step's serial stretches between its
// parallel stages (the line search's bookkeeping, a small gather) are about as long. About
// 0.2-0.8 ms of polling, depending on the CPU's pause: measured against a tenth of that, a 10k-tet
// implicit frame on 2 workers 2.5 -> 2.3 ms (box) and 2.7 -> 2.2 ms (beam). An engine that
// wants its threads back sooner gives femto its own job system (fmWorldDef.enqueueTask).
#define FM_SPIN_POLLS 20000

// Let a sibling hyperthread run while polling.
static void fmPause(void)
{
#if defined(__x86_64__) || defined(__i386__)
	__builtin_ia32_pause();
#endif
}

typedef struct fmWorkerArgs
{
	struct fmTaskPool* pool;
	int workerIndex;
} fmWorkerArgs;

struct fmTaskPool
{
	pthread_mutex_t mutex;
	pthread_cond_t wake; // a new loop, or shutdown
	pthread_cond_t done; // the last range of a loop finished
	pthread_t* threads;
	fmWorkerArgs* args; // one per thread, owned by the pool
	int threadCount;
	int capacity; // threads and args allocated
	// The loop being run.
	fmTaskCallback* task;
	void* context;
	int itemCount;
	int rangeCount;
	int nextRange;   // ranges handed out
	int rangesLeft;  // ranges not finished
	unsigned loopId; // changes with every loop
	bool stop;
	// Copies of loopId and rangesLeft that threads poll without the mutex (hints only: every
	// decision is taken again under the mutex).
	atomic_uint loopSignal;
	atomic_int leftSignal;
	bool deterministicMath; // the det_math mode of the thread that started the loop
};

// Range @p k of @p count ranges over @p items items: contiguous, sizes differing by at most one.
static void fmRange(int items, int count, int k, int* start, int* end)
{
	int base = items / count, extra = items % count;
	*start = k * base + (k < extra ? k : extra);
	*end = *start + base + (k < extra ? 1 : 0);
}

// Take and run ranges of the current loop until none is left; called with the mutex held.
static void fmRunRanges(fmTaskPool* pool, int workerIndex)
{
	while (pool->nextRange < pool->rangeCount)
	{
		int k = pool->nextRange++;
		int start, end;
		fmRange(pool->itemCount, pool->rangeCount, k, &start, &end);
		pthread_mutex_unlock(&pool->mutex);
		pool->task(start, end, workerIndex, pool->context);
		pthread_mutex_lock(&pool->mutex);
		atomic_store_explicit(&pool->leftSignal, --pool->rangesLeft, memory_order_release);
		if (pool->rangesLeft == 0)
			pthread_cond_broadcast(&pool->done);
	}
}

static void* fmWorkerMain(void* argument)
{
	fmWorkerArgs args = *(fmWorkerArgs*)argument;
	fmTaskPool* pool = args.pool;
	unsigned seen = 0;
	pthread_mutex_lock(&pool->mutex);
	for (;;)
	{
		if (!pool->stop && pool->loopId == seen)
		{
			// Poll a while for the next loop (stages come back to back), then sleep.
			pthread_mutex_unlock(&pool->mutex);
			for (int k = 0; k < FM_SPIN_POLLS &&
			                atomic_load_explicit(&pool->loopSignal, memory_order_acquire) == seen;
			     ++k)
				fmPause();
			pthread_mutex_lock(&pool->mutex);
		}
		while (!pool->stop && pool->loopId == seen)
			pthread_cond_wait(&pool->wake, &pool->mutex);
		if (pool->stop)
			break;
		seen = pool->loopId;
		// The loop runs in femto's floating-point environment and the caller's det_math mode
		// (fp_env.h), whatever state the thread was started in.
		fmFpEnv env = fmFpEnv_Enter(pool->deterministicMath);
		fmRunRanges(pool, args.workerIndex);
		fmFpEnv_Leave(&env);
	}
	pthread_mutex_unlock(&pool->mutex);
	return NULL;
}

static void fmPoolFree(fmTaskPool* pool)
{
	pthread_mutex_lock(&pool->mutex);
	pool->stop = true;
	pthread_cond_broadcast(&pool->wake);
	pthread_mutex_unlock(&pool->mutex);
	for (int k = 0; k < pool->threadCount; ++k)
		pthread_join(pool->threads[k], NULL);
	pthread_cond_destroy(&pool->done);
	pthread_cond_destroy(&pool->wake);
	pthread_mutex_destroy(&pool->mutex);
	FM_FREE_ARRAY(pool->threads, pthread_t, (size_t)pool->capacity);
	FM_FREE_ARRAY(pool->args, fmWorkerArgs, (size_t)pool->capacity);
	FM_FREE_ARRAY(pool, fmTaskPool, 1);
}

static fmTaskPool* fmPoolCreate(int threads)
{
	fmTaskPool* pool = FM_ALLOC_ZERO(fmTaskPool, 1);
	if (pool == NULL)
		return NULL;
	pool->capacity = threads;
	pool->threads = FM_ALLOC_ZERO(pthread_t, (size_t)threads);
	pool->args = FM_ALLOC_ZERO(fmWorkerArgs, (size_t)threads);
	if (pool->threads == NULL || pool->args == NULL || pthread_mutex_init(&pool->mutex, NULL) != 0)
	{
		FM_FREE_ARRAY(pool->threads, pthread_t, (size_t)threads);
		FM_FREE_ARRAY(pool->args, fmWorkerArgs, (size_t)threads);
		FM_FREE_ARRAY(pool, fmTaskPool, 1);
		return NULL;
	}
	pthread_cond_init(&pool->wake, NULL);
	pthread_cond_init(&pool->done, NULL);
	atomic_init(&pool->loopSignal, 0u);
	atomic_init(&pool->leftSignal, 0);
	for (int k = 0; k < threads; ++k)
	{
		pool->args[k].pool = pool;
		pool->args[k].workerIndex = k + 1; // the caller is worker 0
		if (pthread_create(&pool->threads[k], NULL, fmWorkerMain, &pool->args[k]) != 0)
			break;
		pool->threadCount = k + 1;
	}
	if (pool->threadCount < threads)
	{
		fmPoolFree(pool);
		return NULL;
	}
	return pool;
}

bool fmTaskSystem_Init(fmTaskSystem* system, const fmWorldDef* def)
{
	memset(system, 0, sizeof *system);
	system->workerCount = def->workerCount > 0 ? def->workerCount : 1;
	system->enqueueTask = def->enqueueTask;
	system->finishTask = def->finishTask;
	system->userTaskContext = def->userTaskContext;
	if (system->workerCount == 1 || system->enqueueTask != NULL)
		return true;
	system->pool = fmPoolCreate(system->workerCount - 1);
	if (system->pool == NULL)
	{
		system->workerCount = 1;
		return false;
	}
	return true;
}

void fmTaskSystem_Shutdown(fmTaskSystem* system)
{
	if (system->pool)
		fmPoolFree(system->pool);
	system->pool = NULL;
}

// A task handed to the engine's job system: femto's task, run on the engine's thread in femto's
// floating-point environment and the caller's det_math mode, the thread's own state restored
// after it (fp_env.h).
typedef struct fmWrappedTask
{
	fmTaskCallback* task;
	void* context;
	bool deterministicMath;
} fmWrappedTask;

static void fmRunWrappedTask(int startIndex, int endIndex, int workerIndex, void* taskContext)
{
	const fmWrappedTask* wrapped = taskContext;
	fmFpEnv env = fmFpEnv_Enter(wrapped->deterministicMath);
	wrapped->task(startIndex, endIndex, workerIndex, wrapped->context);
	fmFpEnv_Leave(&env);
}

// fmParallelFor and fmParallelForBalanced: @p rangesPerWorker ranges per worker at most.
static void fmParallelRanges(const fmTaskSystem* system, int itemCount, int minRange,
                             int rangesPerWorker, fmTaskCallback* task, void* taskContext);

void fmParallelFor(const fmTaskSystem* system, int itemCount, int minRange, fmTaskCallback* task,
                   void* taskContext)
{
	fmParallelRanges(system, itemCount, minRange, 1, task, taskContext);
}

void fmParallelForBalanced(const fmTaskSystem* system, int itemCount, int minRange,
                           fmTaskCallback* task, void* taskContext)
{
	fmParallelRanges(system, itemCount, minRange, FM_BALANCED_RANGES, task, taskContext);
}

static void fmParallelRanges(const fmTaskSystem* system, int itemCount, int minRange,
                             int rangesPerWorker, fmTaskCallback* task, void* taskContext)
{
	if (itemCount <= 0)
		return;
	if (system == NULL)
	{
		task(0, itemCount, 0, taskContext);
		return;
	}
	if (system->enqueueTask != NULL)
	{
		fmWrappedTask wrapped = {task, taskContext, fmDetMath_Enabled()};
		void* handle = system->enqueueTask(fmRunWrappedTask, itemCount, minRange > 0 ? minRange : 1,
		                                   &wrapped, system->userTaskContext);
		if (handle != NULL && system->finishTask != NULL)
			system->finishTask(handle, system->userTaskContext);
		return;
	}
	int ranges = system->workerCount * rangesPerWorker;
	if (minRange > 0 && itemCount / minRange < ranges)
		ranges = itemCount / minRange > 1 ? itemCount / minRange : 1;
	if (ranges <= 1 || system->pool == NULL)
	{
		task(0, itemCount, 0, taskContext);
		return;
	}
	fmTaskPool* pool = system->pool;
	pthread_mutex_lock(&pool->mutex);
	pool->task = task;
	pool->context = taskContext;
	pool->itemCount = itemCount;
	pool->rangeCount = ranges;
	pool->nextRange = 0;
	pool->rangesLeft = ranges;
	pool->loopId += 1;
	atomic_store_explicit(&pool->leftSignal, ranges, memory_order_relaxed);
	atomic_store_explicit(&pool->loopSignal, pool->loopId, memory_order_release);
	pool->deterministicMath = fmDetMath_Enabled();
	pthread_cond_broadcast(&pool->wake);
	fmRunRanges(pool, 0);
	if (pool->rangesLeft > 0)
	{
		// The other ranges are running: poll a while before sleeping.
		pthread_mutex_unlock(&pool->mutex);
		for (int k = 0;
		     k < FM_SPIN_POLLS && atomic_load_explicit(&pool->leftSignal, memory_order_acquire) > 0;
		     ++k)
			fmPause();
		pthread_mutex_lock(&pool->mutex);
	}
	while (pool->rangesLeft > 0)
		pthread_cond_wait(&pool->done, &pool->mutex);
	pthread_mutex_unlock(&pool->mutex);
}
