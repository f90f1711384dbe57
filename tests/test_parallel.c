// Parallel stages: the same bits for any number of workers, on femto's own threads and on an
// engine's job system (task callbacks), as the determinism promise says (docs/simulation.md).
#include "support.h"
#include "test.h"

#include "core/parallel.h"

#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

// A toy engine job system: runs a task's ranges on the calling thread, last range first, each
// with its own worker index, and records how many ranges it ran.
typedef struct fmToyEngine
{
	int ranges;
	int workers;
} fmToyEngine;

static void* toyEnqueue(fmTaskCallback* task, int itemCount, int minRange, void* taskContext,
                        void* userContext)
{
	fmToyEngine* engine = userContext;
	int count = itemCount / minRange;
	count = count < 1 ? 1 : count > engine->workers ? engine->workers : count;
	for (int k = count - 1; k >= 0; --k)
	{
		int start = (int)((long long)itemCount * k / count);
		int end = (int)((long long)itemCount * (k + 1) / count);
		task(start, end, k, taskContext);
		engine->ranges += 1;
	}
	return NULL; // done already
}

static void toyFinish(void* userTask, void* userContext)
{
	(void)userTask;
	(void)userContext;
}

// 8 frames (4 quick) of the house and a 20x20x20 box (landing on the floor when implicit) (48000
// tets, 9261 vertices: loops of more than two FM_PARALLEL_MIN_RANGE) with @p workers, or on the toy
// engine; the final positions and velocities of both (caller frees).
static double* runWithCounting(int* failures_, int workers, fmToyEngine* engine,
                               fmIntegrator integrator, size_t* length, int* newton)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.workerCount = workers;
	// Implicit: the box lands within the first frames (free flight takes no Newton iteration).
	if (integrator == fm_implicit)
		wdef.floor.height = -2.01;
	if (engine)
	{
		wdef.enqueueTask = toyEnqueue;
		wdef.finishTask = toyFinish;
		wdef.userTaskContext = engine;
	}
	fmWorldId world;
	fmBodyId bodies[2];
	bodies[0] = fmTestMakeHouse(&world, &wdef, NULL);
	fmTetMesh box;
	CHECK_INT(fmMakeBoxMesh(20, 20, 20, fmMakeVec3(3, -2, -1), fmMakeVec3(5, 0, 1), &box), fm_ok);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &box;
	CHECK_INT(fmCreateBody(world, &bdef, &bodies[1], NULL), fm_ok);
	fmFreeTetMesh(&box);
	*newton = 0;
	// 4 frames with FEMTO_TEST_QUICK (ThreadSanitizer): the implicit box has landed by the third.
	const int frames = fmTestCount(8, 4);
	for (int frame = 0; frame < frames; ++frame)
	{
		CHECK_INT(integrator == fm_implicit ? fmWorld_Step(world, 1.0 / 60.0, 1)
		                                    : fmWorld_Step(world, 0.03, 10),
		          fm_ok);
		*newton += fmWorld_GetStepStats(world).newtonIterations;
	}
	size_t total = 0;
	for (int b = 0; b < 2; ++b)
		total += 6 * (size_t)fmBody_GetVertexCount(bodies[b]);
	double* out = malloc(sizeof(double) * total);
	size_t at = 0;
	for (int b = 0; b < 2; ++b)
	{
		size_t n3 = 3 * (size_t)fmBody_GetVertexCount(bodies[b]);
		memcpy(out + at, fmTestPositions(bodies[b]), sizeof(double) * n3);
		memcpy(out + at + n3, fmTestVelocities(bodies[b]), sizeof(double) * n3);
		at += 2 * n3;
	}
	*length = total;
	fmDestroyWorld(world);
	return out;
}

static double* runWith(int* failures_, int workers, fmToyEngine* engine, fmIntegrator integrator,
                       size_t* length)
{
	int newton;
	return runWithCounting(failures_, workers, engine, integrator, length, &newton);
}

TEST(explicit_results_are_bit_identical_for_any_worker_count)
{
	size_t length, other;
	double* serial = runWith(failures_, 1, NULL, fm_explicit, &length);
	for (int workers = 2; workers <= 4; ++workers)
	{
		double* parallel = runWith(failures_, workers, NULL, fm_explicit, &other);
		CHECK(other == length);
		if (memcmp(serial, parallel, sizeof(double) * length) != 0)
			FAIL_AT("%d workers differ from one", workers);
		free(parallel);
	}
	fmToyEngine engine = {0, 3};
	double* engineRun = runWith(failures_, 3, &engine, fm_explicit, &other);
	CHECK(memcmp(serial, engineRun, sizeof(double) * length) == 0);
	printf("  1, 2, 3 and 4 workers and a 3-worker engine (%d ranges run): the same bits\n",
	       engine.ranges);
	CHECK(engine.ranges > 0);
	free(engineRun);
	free(serial);
}

TEST(worker_count_and_callbacks_are_validated)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	fmDiagnostic diag;
	wdef.workerCount = 0;
	CHECK_INT(fmWorldDef_Validate(&wdef, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "workerCount");
	wdef.workerCount = FM_MAX_WORKERS + 1;
	CHECK_INT(fmWorldDef_Validate(&wdef, &diag), fm_errParameter);
	wdef.workerCount = 2;
	wdef.enqueueTask = toyEnqueue;
	CHECK_INT(fmWorldDef_Validate(&wdef, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "both task callbacks");
}

// The implicit step's stages on the workers (element forces, Hessian assembly by block rows,
// the multigrid preconditioner's Gauss-Seidel parts and residuals, the matrix products, velocity
// smoothing): the same bits for 1 to 4 workers and on an engine's job system. The box (9261
// vertices, so the default preconditioner is multigrid) is more than one range of the assembly
// and three parts of the finest level's sweeps, and the frames
// take Newton iterations (the box lands), so every stage runs split.
TEST(implicit_results_are_bit_identical_for_any_worker_count)
{
	size_t length, other;
	int newton, newtonParallel;
	double* serial = runWithCounting(failures_, 1, NULL, fm_implicit, &length, &newton);
	printf("  %d Newton iterations in %d frames\n", newton, fmTestCount(8, 4));
	CHECK(newton > 0);
	for (int workers = 2; workers <= 4; ++workers)
	{
		double* parallel =
		    runWithCounting(failures_, workers, NULL, fm_implicit, &other, &newtonParallel);
		CHECK(other == length);
		CHECK_INT(newtonParallel, newton);
		if (memcmp(serial, parallel, sizeof(double) * length) != 0)
			FAIL_AT("%d workers differ from one", workers);
		free(parallel);
	}
	fmToyEngine engine = {0, 3};
	double* engineRun = runWith(failures_, 3, &engine, fm_implicit, &other);
	CHECK(other == length);
	CHECK(memcmp(serial, engineRun, sizeof(double) * length) == 0);
	CHECK(engine.ranges > 0);
	free(engineRun);
	free(serial);
}

// What the pool test's task records: how often each item ran, and whether every range came
// with a worker index in range.
typedef struct fmPoolCount
{
	int* runs;
	int workers;
	int badWorker;
} fmPoolCount;

static void poolCountTask(int start, int end, int worker, void* context)
{
	fmPoolCount* c = context;
	for (int i = start; i < end; ++i)
		c->runs[i] += 1; // a range run twice, or two ranges overlapping, would count twice
	if (worker < 0 || worker >= c->workers)
		c->badWorker = 1;
}

// femto's own pool claims a loop's ranges without a lock (parallel.c): thousands of back-to-back
// loops of every size from 1 to 300 items, plain and balanced, on 2, 3 and 4 workers, each item
// run exactly once a loop. Loops this short end while the other threads are still claiming,
// which is when a claim on a finished loop could leak into the next one. (scripts/check-tsan.sh
// runs this test under ThreadSanitizer.)
TEST(the_pool_runs_every_item_exactly_once)
{
	enum
	{
		maxItems = 300,
		rounds = 12
	};
	int runs[maxItems];
	for (int workers = 2; workers <= 4; ++workers)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.workerCount = workers;
		fmTaskSystem tasks;
		CHECK(fmTaskSystem_Init(&tasks, &wdef));
		CHECK_INT(tasks.workerCount, workers);
		fmPoolCount count = {runs, workers, 0};
		int wrong = 0;
		for (int round = 0; round < rounds; ++round)
			for (int items = 1; items <= maxItems; ++items)
			{
				memset(runs, 0, sizeof runs);
				if (round % 2 == 0)
					fmParallelFor(&tasks, items, 1 + round / 4, poolCountTask, &count);
				else
					fmParallelForBalanced(&tasks, items, 1, poolCountTask, &count);
				for (int i = 0; i < items; ++i)
					wrong += runs[i] != 1;
			}
		fmTaskSystem_Shutdown(&tasks);
		CHECK_INT(wrong, 0);
		CHECK_INT(count.badWorker, 0);
	}
}

// ---- one world, two threads ---------------------------------------------------------------------

// Two threads stepping one world (docs/embedding.md, "Threading": one thread at a time). The
// second step is refused with fm_errBusy before it touches anything, however the two meet.
typedef struct SharedWorld
{
	fmWorldId world;
	atomic_int inside;   // the first step has reached its substep callback
	atomic_int tried;    // the second thread has made its call
	atomic_int substeps; // substep callbacks seen, by every step that ran
	atomic_int ok, busy, other;
	fmResult second;
	fmBodyId body;
} SharedWorld;

static void holdInCallback(int substep, double time, void* context)
{
	(void)substep, (void)time;
	SharedWorld* s = context;
	atomic_fetch_add(&s->substeps, 1);
	if (atomic_exchange(&s->inside, 1) != 0)
		return;
	// Hold the first step here until the other thread has called (a few seconds at most).
	for (long spin = 0; spin < 200000000L && atomic_load(&s->tried) == 0; ++spin)
		sched_yield();
}

static void* stepWhileHeld(void* context)
{
	SharedWorld* s = context;
	for (long spin = 0; spin < 200000000L && atomic_load(&s->inside) == 0; ++spin)
		sched_yield();
	s->second = fmWorld_Step(s->world, 1.0 / 60.0, 1);
	atomic_store(&s->tried, 1);
	return NULL;
}

static void* stepRepeatedly(void* context)
{
	SharedWorld* s = context;
	for (int k = 0; k < 200; ++k)
	{
		fmResult r = fmWorld_Step(s->world, 1.0 / 60.0, 1);
		atomic_fetch_add(r == fm_ok ? &s->ok : r == fm_errBusy ? &s->busy : &s->other, 1);
	}
	return NULL;
}

static fmWorldId sharedWorld(int* failures_, SharedWorld* s)
{
	fmWorldDef def = fmTestFreeWorldDef();
	def.substepCallback = holdInCallback;
	def.substepContext = s;
	fmWorldId world = fmCreateWorld(&def);
	fmTetMesh mesh;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &mesh), fm_ok);
	fmBodyDef body = fmDefaultBodyDef();
	body.mesh = &mesh;
	CHECK_INT(fmCreateBody(world, &body, &s->body, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	s->world = world;
	return world;
}

TEST(a_world_stepped_on_two_threads_refuses_the_second_step)
{
	// A second thread's step while the first is held inside its substep: fm_errBusy, and the
	// first step ends as if it had been alone (its substeps, no error written).
	SharedWorld held;
	memset(&held, 0, sizeof held);
	fmWorldId world = sharedWorld(failures_, &held);
	pthread_t thread;
	CHECK_INT(pthread_create(&thread, NULL, stepWhileHeld, &held), 0);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 3), fm_ok);
	pthread_join(thread, NULL);
	CHECK_INT(held.second, fm_errBusy);
	CHECK_INT(atomic_load(&held.substeps), 3);
	CHECK_INT(fmWorld_GetStepStats(world).steps, 3);
	CHECK_INT(fmWorld_GetLastError(world)->result, fm_ok);
	fmDestroyWorld(world);

	// Two threads stepping as fast as they can: every call is a whole step or a refusal, and the
	// substeps that ran are exactly those of the steps that returned fm_ok.
	SharedWorld racing;
	memset(&racing, 0, sizeof racing);
	atomic_store(&racing.inside, 1); // no holding
	world = sharedWorld(failures_, &racing);
	pthread_t threads[2];
	for (int t = 0; t < 2; ++t)
		CHECK_INT(pthread_create(&threads[t], NULL, stepRepeatedly, &racing), 0);
	for (int t = 0; t < 2; ++t)
		pthread_join(threads[t], NULL);
	int ok = atomic_load(&racing.ok), busy = atomic_load(&racing.busy);
	printf("  racing: %d steps ran, %d refused as busy\n", ok, busy);
	CHECK_INT(atomic_load(&racing.other), 0);
	CHECK_INT(ok + busy, 400);
	CHECK(ok >= 1);
	CHECK_INT(atomic_load(&racing.substeps), ok);
	double x[3 * 27];
	CHECK_INT(fmBody_CopyPositions(racing.body, x, 27), fm_ok);
	for (int k = 0; k < 3 * 27; ++k)
		CHECK(isfinite(x[k]));
	fmDestroyWorld(world);
}
