// Tiny test framework: TEST(name) registers itself (constructor); CHECK macros print both values.
#pragma once

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

typedef void fmTestFcn(int* failures);

void fmRegisterTest(const char* file, const char* name, fmTestFcn* fcn);

// A part of a test that cannot run here (a tool such as gmsh or ccx is missing): said with the
// reason. Under CI=true it is a failure (every test must run there); elsewhere the suite exits
// with 77, which ctest reports as "Skipped" (SKIP_RETURN_CODE), never as passed.
void fmTestSkipped(int* failures, const char* file, int line, const char* reason);
#define TEST_SKIP(reason) fmTestSkipped(failures_, __FILE__, __LINE__, reason)

// The size of a slow test's loop: @p full, or @p quick where FEMTO_TEST_QUICK=1 (the
// sanitizer and ThreadSanitizer runs set it; the Release suite runs the full count). A quick
// count must still test the same thing (the test's own checks hold at both).
int fmTestCount(int full, int quick);

// Whether a program is on PATH (command -v).
bool fmTestHaveProgram(const char* name);

#define TEST(name)                                                                                 \
	static void test_##name(int* failures_);                                                       \
	__attribute__((constructor)) static void register_##name(void)                                 \
	{                                                                                              \
		fmRegisterTest(__FILE__, #name, test_##name);                                              \
	}                                                                                              \
	static void test_##name(int* failures_)

#define FAIL_AT(...)                                                                               \
	do                                                                                             \
	{                                                                                              \
		fprintf(stderr, "  %s:%d: ", __FILE__, __LINE__);                                          \
		fprintf(stderr, __VA_ARGS__);                                                              \
		fprintf(stderr, "\n");                                                                     \
		++*failures_;                                                                              \
	} while (0)

#define CHECK(cond)                                                                                \
	do                                                                                             \
	{                                                                                              \
		if (!(cond))                                                                               \
			FAIL_AT("CHECK(%s) failed", #cond);                                                    \
	} while (0)

#define CHECK_INT(a, b)                                                                            \
	do                                                                                             \
	{                                                                                              \
		long long a_ = (long long)(a), b_ = (long long)(b);                                        \
		if (a_ != b_)                                                                              \
			FAIL_AT("%s == %s failed: %lld vs %lld", #a, #b, a_, b_);                              \
	} while (0)

// |a - b| <= tol
#define CHECK_NEAR(a, b, tol)                                                                      \
	do                                                                                             \
	{                                                                                              \
		double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);                             \
		if (!(fabs(a_ - b_) <= t_))                                                                \
			FAIL_AT("%s ~ %s failed: %.17g vs %.17g (diff %.3g, tol %.3g)", #a, #b, a_, b_,        \
			        fabs(a_ - b_), t_);                                                            \
	} while (0)

// |a - b| <= tol * max(|a|, |b|, floor)
#define CHECK_REL(a, b, tol, floor)                                                                \
	do                                                                                             \
	{                                                                                              \
		double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);                             \
		double s_ = fmax(fmax(fabs(a_), fabs(b_)), (double)(floor));                               \
		if (!(fabs(a_ - b_) <= t_ * s_))                                                           \
			FAIL_AT("%s ~ %s failed: %.17g vs %.17g (rel diff %.3g, tol %.3g)", #a, #b, a_, b_,    \
			        fabs(a_ - b_) / s_, t_);                                                       \
	} while (0)

#define CHECK_STR_CONTAINS(haystack, needle)                                                       \
	do                                                                                             \
	{                                                                                              \
		const char* h_ = (haystack);                                                               \
		const char* n_ = (needle);                                                                 \
		if (h_ == NULL || strstr(h_, n_) == NULL)                                                  \
			FAIL_AT("\"%s\" does not contain \"%s\"", h_ ? h_ : "(null)", n_);                     \
	} while (0)

// Deterministic random numbers for tests (xorshift64*), in [lo, hi).
double fmTestRandom(double lo, double hi);
void fmTestSeed(unsigned long long seed);
