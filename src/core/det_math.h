// Elementary functions with the same bits on every target (det_math.c): written with +, -, *, /
// and sqrt only, which IEEE 754 rounds correctly everywhere, so their results do not depend on
// the C library's log or exp (glibc, musl, Apple's libm, MSVC's CRT and Emscripten's differ in
// the last bit of some results). Accuracy, measured in tests/test_determinism.c against glibc
// over the whole range: log and exp within 1 ulp; pow(x, y) within 2 (1 + |y ln x|) ulp (the
// rounding of y ln x; the velocity filters keep |y ln x| below 1).
//
// The hot path calls fmMathLog and fmMathPow: the C library's functions normally, femto's own
// on a thread whose det_math mode is on (fmWorldDef.crossPlatformDeterminism; fp_env.h sets the
// mode on entry to every public call and in every task).
#pragma once

#include <math.h>
#include <stdbool.h>

// Natural logarithm: -inf at +-0, NaN below 0 and for NaN, +inf at +inf; denormals handled.
double fmDetLog(double x);

// e^x: +inf above 709.78, 0 below -745.13 (denormal results in between), NaN for NaN.
double fmDetExp(double x);

// x^y for x >= 0 (a NaN for x < 0, unlike C's pow with an integer y): e^(y ln x), with
// x^0 = 1^y = 1, 0^y = 0 for y > 0 and +inf for y < 0.
double fmDetPow(double x, double y);

// sin x and cos x together, for |x| <= 1e6 (collider rotations: angles of a step or a pose);
// NaN beyond. Within 2 ulp of the correctly rounded values over that range.
void fmDetSinCos(double x, double* sine, double* cosine);

// The angle of the point (x, y) from the positive x axis, in [-pi, pi], as C's atan2 for finite
// arguments (NaN for a NaN). Within 2 ulp of the correctly rounded value (mesh collider
// pseudo-normals).
double fmDetAtan2(double y, double x);

// fmin and fmax with the same bits on every target: the C libraries disagree on the sign of
// fmax(-0.0, +0.0) (glibc's x86-64 fmax returns its first argument, musl, AArch64 and
// Emscripten +0). Here the minimum of -0 and +0 is -0 and the maximum +0 in either order; a
// NaN argument gives the other, as C's. Inline: the common case is one compare-and-select
// (minsd/maxsd, no branch on the data); the rare ones (equal arguments, a NaN second argument)
// take a branch that is predictably not taken.
static inline double fmMin(double a, double b)
{
	if (a == b || b != b)
		return b != b ? a : (signbit(a) ? a : b);
	return a < b ? a : b; // a NaN first argument gives b
}

static inline double fmMax(double a, double b)
{
	if (a == b || b != b)
		return b != b ? a : (signbit(a) ? b : a);
	return a > b ? a : b; // a NaN first argument gives b
}

// The calling thread's det_math mode (off when a thread starts); set by fp_env.c.
extern _Thread_local bool fmDetMathMode;

static inline void fmDetMath_Enable(bool enabled)
{
	fmDetMathMode = enabled;
}

static inline bool fmDetMath_Enabled(void)
{
	return fmDetMathMode;
}

// The hot path's log and pow: femto's own in det_math mode, the C library's otherwise (inline:
// the option off costs one test of a thread-local flag a call).
static inline double fmMathLog(double x)
{
	return fmDetMathMode ? fmDetLog(x) : log(x);
}

static inline double fmMathPow(double x, double y)
{
	return fmDetMathMode ? fmDetPow(x, y) : pow(x, y);
}
