// The machine's memory bandwidth for the benchmark's bound, and how its threads scale on work
// that needs no memory (bandwidth.c).
#pragma once

/// Bytes per second a STREAM-style triad reaches on 1 thread (@p one) and on @p threads threads
/// (@p many), each the median of 5 passes over 192 MiB (one set of arrays, allocated and touched
/// once); both 0 when memory is short.
void cliTriadBandwidths(int threads, double* one, double* many);

/// How much more work @p threads threads do than one in the same time when each has its own,
/// in registers (independent multiply-add chains, about 30 ms a thread): threads for a machine
/// whose cores are all its own, less where a host shares them. The median of 5 passes; 0 when
/// a thread cannot be started. The reference for "two workers at least 1.8x one where the work
/// is compute-bound", as the triad's ratio is for memory-bound work.
double cliComputeScaling(int threads);
