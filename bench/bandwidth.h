// The machine's memory bandwidth for the benchmark's bound (bandwidth.c).
#pragma once

/// Bytes per second a STREAM-style triad reaches on 1 thread (@p one) and on @p threads threads
/// (@p many), each the median of 5 passes over 192 MiB (one set of arrays, allocated and touched
/// once); both 0 when memory is short.
void cliTriadBandwidths(int threads, double* one, double* many);
