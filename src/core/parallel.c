// Parallel loops (parallel.h) and femto's own thread pool: the caller and workerCount - 1
// threads claim the contiguous ranges of a loop's fixed split, without a lock; the caller waits
// for all.
#include "core/parallel.h"

#include "core/core.h"
#include "core/det_math.h"
#include "core/fp_env.h"

#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

// Polls of a new loop (a worker) or of the last range (the caller) before sleeping on the
// condition variable: a sleeping thread takes tens of microseconds to wake on a shared machine,
// more than a small body's whole stage, and an implicit step's serial stretches between its
// parallel stages (the line search's bookkeeping, a small gather) are about as long. About
// 0.2-0.8 ms of polling, depending on the CPU's pause (docs/decisions.md, "Spinning workers"). An
// engine that wants its threads back sooner gives femto its own job system
// (fmWorldDef.enqueueTask).
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

// The pool hands out a loop's ranges without a lock: one 64-bit word holds the loop's range count
// (high half) and the ranges claimed (low half), and a fetch-and-add on it is a claim, valid when
// the count it returns is below the range count. The caller sets the word for the next loop only
// when every range of the last one finished, so a late claim on a finished loop's word fails and
// a claim on the new word is the new loop's (its fields published before the word, with release).
// The mutex and condition variables serve only the threads that sleep.
struct fmTaskPool
{
	pthread_mutex_t mutex;
	pthread_cond_t wake; // a new loop, or shutdown
	pthread_cond_t done; // the last range of a loop finished
	pthread_t* threads;
	fmWorkerArgs* args; // one per thread, owned by the pool
	int threadCount;
	int capacity; // threads and args allocated
	// The loop being run: set by the caller before it publishes the loop's claims word.
	fmTaskCallback* task;
	void* context;
	int itemCount;
	bool deterministicMath;       // the det_math mode of the thread that started the loop
	atomic_uint_least64_t claims; // range count << 32 | ranges claimed
	atomic_int rangesLeft;        // ranges not finished
	atomic_uint loopId;           // changes with every loop
	atomic_int sleepers;          // workers waiting on wake (changed under the mutex)
	atomic_bool stop;
};

// Range @p k of @p count ranges over @p items items: contiguous, sizes differing by at most one.
static void fmRange(int items, int count, int k, int* start, int* end)
{
	int base = items / count, extra = items % count;
	*start = k * base + (k < extra ? k : extra);
	*end = *start + base + (k < extra ? 1 : 0);
}

// Claim and run ranges of the current loop until none is left, each in femto's floating-point
// environment and the loop's det_math mode (fp_env.h), whatever state the thread is in.
static void fmRunRanges(fmTaskPool* pool, int workerIndex)
{
	for (;;)
	{
		uint64_t claim = atomic_fetch_add_explicit(&pool->claims, 1, memory_order_acq_rel);
		int k = (int)(uint32_t)claim, count = (int)(claim >> 32);
		if (k >= count)
			return;
		int start, end;
		fmRange(pool->itemCount, count, k, &start, &end);
		fmFpEnv env = fmFpEnv_Enter(pool->deterministicMath);
		pool->task(start, end, workerIndex, pool->context);
		fmFpEnv_Leave(&env);
		if (atomic_fetch_sub_explicit(&pool->rangesLeft, 1, memory_order_acq_rel) == 1 &&
		    workerIndex != 0)
		{
			// The last range: wake the caller if it sleeps.
			pthread_mutex_lock(&pool->mutex);
			pthread_cond_broadcast(&pool->done);
			pthread_mutex_unlock(&pool->mutex);
		}
	}
}

// Whether a worker that last ran loop @p seen has nothing new to do.
static bool fmIdle(fmTaskPool* pool, unsigned seen)
{
	return !atomic_load(&pool->stop) && atomic_load(&pool->loopId) == seen;
}

static void* fmWorkerMain(void* argument)
{
	fmWorkerArgs args = *(fmWorkerArgs*)argument;
	fmTaskPool* pool = args.pool;
	unsigned seen = 0;
	for (;;)
	{
		// Poll a while for the next loop (stages come back to back), then sleep.
		for (int k = 0; k < FM_SPIN_POLLS && fmIdle(pool, seen); ++k)
			fmPause();
		if (fmIdle(pool, seen))
		{
			pthread_mutex_lock(&pool->mutex);
			atomic_fetch_add(&pool->sleepers, 1);
			while (fmIdle(pool, seen))
				pthread_cond_wait(&pool->wake, &pool->mutex);
			atomic_fetch_sub(&pool->sleepers, 1);
			pthread_mutex_unlock(&pool->mutex);
		}
		if (atomic_load(&pool->stop))
			break;
		seen = atomic_load(&pool->loopId);
		fmRunRanges(pool, args.workerIndex);
	}
	return NULL;
}

static void fmPoolFree(fmTaskPool* pool)
{
	pthread_mutex_lock(&pool->mutex);
	atomic_store(&pool->stop, true);
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
	atomic_init(&pool->claims, 0u); // no ranges: every claim fails
	atomic_init(&pool->rangesLeft, 0);
	atomic_init(&pool->loopId, 0u);
	atomic_init(&pool->sleepers, 0);
	atomic_init(&pool->stop, false);
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
	pool->task = task;
	pool->context = taskContext;
	pool->itemCount = itemCount;
	pool->deterministicMath = fmDetMath_Enabled();
	atomic_store_explicit(&pool->rangesLeft, ranges, memory_order_relaxed);
	atomic_store_explicit(&pool->claims, (uint64_t)ranges << 32, memory_order_release);
	atomic_fetch_add(&pool->loopId, 1u);
	if (atomic_load(&pool->sleepers) > 0)
	{
		pthread_mutex_lock(&pool->mutex);
		pthread_cond_broadcast(&pool->wake);
		pthread_mutex_unlock(&pool->mutex);
	}
	fmRunRanges(pool, 0);
	// The other ranges are running: poll a while before sleeping.
	for (int k = 0;
	     k < FM_SPIN_POLLS && atomic_load_explicit(&pool->rangesLeft, memory_order_acquire) > 0;
	     ++k)
		fmPause();
	if (atomic_load_explicit(&pool->rangesLeft, memory_order_acquire) > 0)
	{
		pthread_mutex_lock(&pool->mutex);
		while (atomic_load_explicit(&pool->rangesLeft, memory_order_acquire) > 0)
			pthread_cond_wait(&pool->done, &pool->mutex);
		pthread_mutex_unlock(&pool->mutex);
	}
}
