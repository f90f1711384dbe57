// The machine's memory bandwidth for the benchmark's bound (bandwidth.c).
#pragma once

// Bytes per second a STREAM-style triad reaches on @p threads threads (median of 5 passes over
// 192 MiB); 0 when memory is short.
double cliTriadBandwidth(int threads);
