// job_system: femto stepping on the engine's own threads. A game engine has a job system; femto
// does not start threads of its own when the world def gives it two callbacks (as Box2D v3):
// enqueueTask splits a loop over items into ranges that run in parallel, finishTask waits for
// them. Here a tiny pool of POSIX threads stands in for the engine's. Checks that the house
// lands on exactly the same bits as a serial run (femto's results do not depend on threads).
// Usage: job_system MESH.node MESH.ele
#include <femto/femto.h>

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WORKERS 4

// One loop femto asked for: ranges handed out in order to whichever worker asks next.
typedef struct Job
{
	fmTaskCallback* task;
	void* taskContext;
	int itemCount, rangeSize, rangeCount;
	int nextRange, doneRanges;
	struct Job* next; // the pool's list of jobs with ranges left
} Job;

typedef struct Pool
{
	pthread_t threads[WORKERS];
	pthread_mutex_t lock;
	pthread_cond_t work, finished;
	Job* jobs;
	bool stop;
} Pool;

typedef struct Worker
{
	Pool* pool;
	int index; // the worker index femto gets: distinct per thread, below fmWorldDef.workerCount
} Worker;

static void* workerMain(void* argument)
{
	Worker* w = argument;
	Pool* pool = w->pool;
	pthread_mutex_lock(&pool->lock);
	for (;;)
	{
		Job* job = pool->jobs;
		while (job != NULL && job->nextRange == job->rangeCount)
			job = job->next;
		if (job == NULL)
		{
			if (pool->stop)
				break;
			pthread_cond_wait(&pool->work, &pool->lock);
			continue;
		}
		int range = job->nextRange++;
		pthread_mutex_unlock(&pool->lock);
		int start = range * job->rangeSize;
		int end = start + job->rangeSize < job->itemCount ? start + job->rangeSize : job->itemCount;
		job->task(start, end, w->index, job->taskContext);
		pthread_mutex_lock(&pool->lock);
		if (++job->doneRanges == job->rangeCount)
			pthread_cond_broadcast(&pool->finished);
	}
	pthread_mutex_unlock(&pool->lock);
	return NULL;
}

static void* enqueueTask(fmTaskCallback* task, int itemCount, int minRange, void* taskContext,
                         void* userContext)
{
	Pool* pool = userContext;
	int ranges = (itemCount + minRange - 1) / (minRange > 0 ? minRange : 1);
	ranges = ranges < WORKERS ? ranges : WORKERS;
	if (ranges <= 1)
	{
		task(0, itemCount, 0, taskContext); // not worth a thread: run it here, return NULL
		return NULL;
	}
	Job* job = calloc(1, sizeof *job);
	job->task = task;
	job->taskContext = taskContext;
	job->itemCount = itemCount;
	job->rangeCount = ranges;
	job->rangeSize = (itemCount + ranges - 1) / ranges;
	pthread_mutex_lock(&pool->lock);
	job->next = pool->jobs;
	pool->jobs = job;
	pthread_cond_broadcast(&pool->work);
	pthread_mutex_unlock(&pool->lock);
	return job;
}

static void finishTask(void* userTask, void* userContext)
{
	Pool* pool = userContext;
	Job* job = userTask;
	pthread_mutex_lock(&pool->lock);
	while (job->doneRanges < job->rangeCount)
		pthread_cond_wait(&pool->finished, &pool->lock);
	for (Job** link = &pool->jobs; *link != NULL; link = &(*link)->next)
		if (*link == job)
		{
			*link = job->next;
			break;
		}
	pthread_mutex_unlock(&pool->lock);
	free(job);
}

// Drop the house for one second; its positions into @p x (3 per vertex). With @p pool the world
// runs on it, else serially.
static int dropHouse(const fmTetMesh* mesh, Pool* pool, double* x)
{
	fmWorldDef worldDef = fmDefaultWorldDef();
	if (pool != NULL)
	{
		worldDef.workerCount = WORKERS;
		worldDef.enqueueTask = enqueueTask;
		worldDef.finishTask = finishTask;
		worldDef.userTaskContext = pool;
	}
	fmWorldId world = fmCreateWorld(&worldDef);
	fmBodyDef bodyDef = fmDefaultBodyDef();
	bodyDef.mesh = mesh;
	fmBodyId body;
	if (fmCreateBody(world, &bodyDef, &body, NULL) != fm_ok)
		return 1;
	for (int frame = 0; frame < 33; ++frame) // 33 frames of 10 x 3 ms
		if (fmWorld_Step(world, 0.03, 10) != fm_ok)
			return 1;
	fmResult r = fmBody_CopyPositions(body, x, mesh->nodeCount);
	fmDestroyWorld(world);
	return r == fm_ok ? 0 : 1;
}

int main(int argc, char** argv)
{
	if (argc < 3)
	{
		fprintf(stderr, "usage: %s MESH.node MESH.ele\n", argv[0]);
		return 2;
	}
	fmTetMesh mesh;
	if (fmLoadTetGen(argv[1], argv[2], &mesh, NULL) != fm_ok)
		return 1;
	fmMeshTransform placement = fmDefaultMeshTransform();
	placement.scale = 0.4;
	placement.center = true;
	placement.swapYZ = true;
	fmTetMesh_Transform(&mesh, &placement);

	Pool pool;
	memset(&pool, 0, sizeof pool);
	pthread_mutex_init(&pool.lock, NULL);
	pthread_cond_init(&pool.work, NULL);
	pthread_cond_init(&pool.finished, NULL);
	Worker workers[WORKERS];
	for (int i = 0; i < WORKERS; ++i)
	{
		workers[i].pool = &pool;
		workers[i].index = i;
		pthread_create(&pool.threads[i], NULL, workerMain, &workers[i]);
	}
	double* serial = malloc(sizeof(double) * 3 * (size_t)mesh.nodeCount);
	double* parallel = malloc(sizeof(double) * 3 * (size_t)mesh.nodeCount);
	int failed = dropHouse(&mesh, NULL, serial) || dropHouse(&mesh, &pool, parallel);
	pthread_mutex_lock(&pool.lock);
	pool.stop = true;
	pthread_cond_broadcast(&pool.work);
	pthread_mutex_unlock(&pool.lock);
	for (int i = 0; i < WORKERS; ++i)
		pthread_join(pool.threads[i], NULL);
	bool same =
	    !failed && memcmp(serial, parallel, sizeof(double) * 3 * (size_t)mesh.nodeCount) == 0;
	printf("%d workers on the engine's pool: %s as the serial run\n", WORKERS,
	       same ? "the same bits" : "DIFFERENT positions");
	free(serial);
	free(parallel);
	fmFreeTetMesh(&mesh);
	return same ? 0 : 1;
}
