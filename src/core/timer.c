// The profile's clock (timer.h): CLOCK_MONOTONIC on POSIX systems, C11's timespec_get
// (realtime) elsewhere.
#if !defined(_WIN32) && !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 200809L
#endif
#include "core/timer.h"

#include <time.h>

double fmSeconds(void)
{
	struct timespec now;
#if defined(CLOCK_MONOTONIC)
	clock_gettime(CLOCK_MONOTONIC, &now);
#else
	timespec_get(&now, TIME_UTC);
#endif
	return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}
