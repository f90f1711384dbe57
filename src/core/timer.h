// A monotonic wall clock for the step profile (timer.c).
#pragma once

// Seconds since an arbitrary fixed point, monotonic where the platform has such a clock.
double fmSeconds(void);
