// The floating-point environment femto computes in (fp_env.c): round to nearest, no
// flush-to-zero, no denormals-are-zero, every exception masked. Host engines change these
// (a renderer's FTZ/DAZ, a physics engine's rounding mode), and a step run under another state
// gives other bits. Every public call that computes saves the caller's state, sets femto's and
// restores the caller's on every return path; the worker threads set it for every task.
#pragma once

#include <stdbool.h>
#include <stdint.h>

// The caller's state, kept between fmFpEnv_Enter and fmFpEnv_Leave.
typedef struct fmFpEnv
{
	uint64_t control;       // MXCSR (x86 SSE), FPCR (AArch64), or the rounding mode (fenv.h)
	bool deterministicMath; // the calling thread's det_math mode before the call
} fmFpEnv;

// Save the calling thread's floating-point state, set femto's, and set the thread's det_math
// mode (det_math.h) to @p deterministicMath: with it the hot path uses femto's own elementary
// functions instead of the C library's (fmWorldDef.crossPlatformDeterminism).
fmFpEnv fmFpEnv_Enter(bool deterministicMath);

// Restore what fmFpEnv_Enter saved.
void fmFpEnv_Leave(const fmFpEnv* saved);

// True when the calling thread's floating-point state is femto's (for tests and asserts).
bool fmFpEnv_IsFemtos(void);
