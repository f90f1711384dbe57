// The machine's memory bandwidth, measured in the same run as the benchmarks (bandwidth.h): a
// STREAM-style triad a[i] = b[i] + s c[i] over arrays far larger than the caches, on 1 to W
// threads, the median of several passes. 24 bytes move per element (two reads, one write).
// And the scaling of work that needs no memory at all, on the same threads.
#include "bandwidth.h"

#include "cli.h"

#include <pthread.h>
#include <stdlib.h>

#define CLI_TRIAD_ELEMENTS (1u << 23) // 3 arrays of 64 MiB

typedef struct cliTriadSlice
{
	double* a;
	const double* b;
	const double* c;
	size_t start;
	size_t end;
	int passes;
} cliTriadSlice;

static void* cliTriadRun(void* argument)
{
	cliTriadSlice* s = argument;
	for (int p = 0; p < s->passes; ++p)
		for (size_t i = s->start; i < s->end; ++i)
			s->a[i] = s->b[i] + 3.0 * s->c[i];
	return NULL;
}

static int cliCompareSeconds(const void* x, const void* y)
{
	double a = *(const double*)x, b = *(const double*)y;
	return (a > b) - (a < b);
}

// Median bytes per second of 5 triad passes over a, b, c on @p threads threads.
static double cliTriadMeasure(double* a, const double* b, const double* c, size_t n, int threads)
{
	enum
	{
		passes = 5
	};
	double seconds[passes];
	cliTriadSlice slices[64];
	pthread_t ids[64];
	for (int p = 0; p < passes; ++p)
	{
		double start = cliNow();
		for (int t = 0; t < threads; ++t)
		{
			slices[t] = (cliTriadSlice){
			    a, b, c, n * (size_t)t / (size_t)threads, n * (size_t)(t + 1) / (size_t)threads, 1};
			if (t > 0)
				pthread_create(&ids[t], NULL, cliTriadRun, &slices[t]);
		}
		cliTriadRun(&slices[0]);
		for (int t = 1; t < threads; ++t)
			pthread_join(ids[t], NULL);
		seconds[p] = cliNow() - start;
	}
	qsort(seconds, passes, sizeof seconds[0], cliCompareSeconds);
	return 24.0 * (double)n / seconds[passes / 2];
}

void cliTriadBandwidths(int threads, double* one, double* many)
{
	size_t n = CLI_TRIAD_ELEMENTS;
	*one = *many = 0.0;
	double* a = malloc(sizeof(double) * n);
	double* b = malloc(sizeof(double) * n);
	double* c = malloc(sizeof(double) * n);
	if (a != NULL && b != NULL && c != NULL && threads >= 1 && threads <= 64)
	{
		for (size_t i = 0; i < n; ++i) // touch every page before timing
		{
			a[i] = 0.0;
			b[i] = 1.0;
			c[i] = 2.0;
		}
		*one = cliTriadMeasure(a, b, c, n, 1);
		*many = threads == 1 ? *one : cliTriadMeasure(a, b, c, n, threads);
	}
	free(a);
	free(b);
	free(c);
}

// ---- compute scaling ----------------------------------------------------------------------------

#define CLI_COMPUTE_STEPS 20000000 // a thread's multiply-add steps: about 30 ms

typedef struct cliComputeSlice
{
	double result; // read into cliComputeSink, so that the work is not optimised away
} cliComputeSlice;

// Every slice's result goes here: a slice whose result nobody reads is dead code to the
// compiler, and the caller's own slice was (1 thread timed as 30 ns, the scaling printed 0.00x).
static volatile double cliComputeSink;

// Eight independent chains x <- x * a + b (a < 1: bounded, never denormal), enough to keep a
// core's floating-point units busy whatever their latency.
static void* cliComputeRun(void* argument)
{
	cliComputeSlice* s = argument;
	double x[8] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0};
	for (int k = 0; k < CLI_COMPUTE_STEPS / 8; ++k)
		for (int c = 0; c < 8; ++c)
			x[c] = x[c] * 0.999999 + 0.5;
	s->result = x[0] + x[1] + x[2] + x[3] + x[4] + x[5] + x[6] + x[7];
	return NULL;
}

// Seconds for @p threads threads to run a slice each (the caller runs the first); < 0 when a
// thread cannot be started.
static double cliComputeSeconds(int threads)
{
	cliComputeSlice slices[64];
	pthread_t ids[64];
	double start = cliNow();
	int started = 1;
	for (int t = 1; t < threads; ++t, ++started)
		if (pthread_create(&ids[t], NULL, cliComputeRun, &slices[t]) != 0)
			break;
	cliComputeRun(&slices[0]);
	for (int t = 1; t < started; ++t)
		pthread_join(ids[t], NULL);
	for (int t = 0; t < started; ++t)
		cliComputeSink = cliComputeSink + slices[t].result;
	return started == threads ? cliNow() - start : -1.0;
}

double cliComputeScaling(int threads)
{
	enum
	{
		passes = 5
	};
	if (threads < 1 || threads > 64)
		return 0.0;
	double ratio[passes];
	for (int p = 0; p < passes; ++p)
	{
		double one = cliComputeSeconds(1), many = cliComputeSeconds(threads);
		if (one < 0.0 || many <= 0.0)
			return 0.0;
		ratio[p] = threads * one / many;
	}
	qsort(ratio, passes, sizeof ratio[0], cliCompareSeconds);
	return ratio[passes / 2];
}
