// Test runner: `femto_tests SUITE` runs the tests registered from tests/test_SUITE.c;
// `femto_tests` alone runs everything. Exit code = number of failed tests (capped), or 77 when
// none failed and a part of one was skipped (TEST_SKIP; a failure under CI=true).
#include "test.h"

#include "core/timer.h"

#include <femto/femto.h>
#include <stdlib.h>

#define MAX_TESTS 1024

typedef struct TestEntry
{
	char suite[64];
	const char* name;
	fmTestFcn* fcn;
} TestEntry;

static TestEntry s_tests[MAX_TESTS];
static int s_testCount;
static unsigned long long s_rng = 0x9E3779B97F4A7C15ull;

void fmRegisterTest(const char* file, const char* name, fmTestFcn* fcn)
{
	if (s_testCount >= MAX_TESTS)
	{
		fprintf(stderr, "too many tests\n");
		exit(2);
	}
	const char* base = strrchr(file, '/');
	base = base ? base + 1 : file;
	if (strncmp(base, "test_", 5) == 0)
		base += 5;
	TestEntry* e = &s_tests[s_testCount++];
	snprintf(e->suite, sizeof e->suite, "%s", base);
	char* dot = strrchr(e->suite, '.');
	if (dot)
		*dot = 0;
	e->name = name;
	e->fcn = fcn;
}

void fmTestSeed(unsigned long long seed)
{
	s_rng = seed ? seed : 0x9E3779B97F4A7C15ull;
}

// Each test's random numbers come from its own name (FNV-1a), so that adding a test elsewhere
// never changes another test's inputs.
static unsigned long long fmTestNameSeed(const char* suite, const char* name)
{
	unsigned long long h = 0xcbf29ce484222325ull;
	for (const char* p = suite; *p; ++p)
		h = (h ^ (unsigned char)*p) * 0x100000001b3ull;
	h = (h ^ '.') * 0x100000001b3ull;
	for (const char* p = name; *p; ++p)
		h = (h ^ (unsigned char)*p) * 0x100000001b3ull;
	return h;
}

double fmTestRandom(double lo, double hi)
{
	s_rng ^= s_rng >> 12;
	s_rng ^= s_rng << 25;
	s_rng ^= s_rng >> 27;
	unsigned long long r = s_rng * 2685821657736338717ull;
	return lo + (hi - lo) * (double)(r >> 11) * (1.0 / 9007199254740992.0);
}

static int s_skipCount;

void fmTestSkipped(int* failures, const char* file, int line, const char* reason)
{
	const char* ci = getenv("CI");
	if (ci != NULL && strcmp(ci, "true") == 0)
	{
		fprintf(stderr, "  %s:%d: CI=true and not tested: %s\n", file, line, reason);
		++*failures;
		return;
	}
	printf("  SKIPPED (%s:%d): %s\n", file, line, reason);
	++s_skipCount;
}

int fmTestCount(int full, int quick)
{
	const char* q = getenv("FEMTO_TEST_QUICK");
	return q != NULL && strcmp(q, "1") == 0 ? quick : full;
}

bool fmTestHaveProgram(const char* name)
{
	char command[160];
	snprintf(command, sizeof command, "command -v '%s' >/dev/null 2>&1", name);
	return system(command) == 0;
}

static int s_assertCount;
static int countingAssert(const char* condition, const char* file, int line)
{
	fprintf(stderr, "  femto assert: %s at %s:%d\n", condition, file, line);
	++s_assertCount;
	return 0;
}

// Whether test @p name matches @p pattern: the same name, or a prefix ending in '*'.
static bool nameMatches(const char* pattern, const char* name)
{
	size_t n = strlen(pattern);
	return n > 0 && pattern[n - 1] == '*' ? strncmp(pattern, name, n - 1) == 0
	                                      : strcmp(pattern, name) == 0;
}

// Whether the selection after the suite (argv[2...]) takes test @p name: "name" (or "prefix*")
// takes those alone, "-name" (or "-prefix*") every test of the suite but those.
static bool selected(int argc, char** argv, const char* name)
{
	bool any = false, taken = false;
	for (int k = 2; k < argc; ++k)
	{
		if (argv[k][0] == '-' && nameMatches(argv[k] + 1, name))
			return false;
		if (argv[k][0] != '-')
		{
			any = true;
			taken = taken || nameMatches(argv[k], name);
		}
	}
	return !any || taken;
}

int main(int argc, char** argv)
{
	const char* suite = argc > 1 ? argv[1] : NULL;
	fmSetAssertFcn(countingAssert);
	int run = 0, failed = 0;
	for (int i = 0; i < s_testCount; ++i)
	{
		TestEntry* e = &s_tests[i];
		if (suite && strcmp(suite, e->suite) != 0)
			continue;
		if (!selected(argc, argv, e->name))
			continue;
		int failures = 0;
		int asserts = s_assertCount;
		fmTestSeed(fmTestNameSeed(e->suite, e->name));
		double began = fmSeconds();
		e->fcn(&failures);
		double seconds = fmSeconds() - began;
		if (s_assertCount != asserts)
			++failures;
		++run;
		if (failures)
			++failed;
		printf("%s %s.%s (%.1f s)\n", failures ? "FAIL" : "ok  ", e->suite, e->name, seconds);
		fflush(stdout);
	}
	if (run == 0)
	{
		fprintf(stderr, "no test matches '%s'\n", suite ? suite : "");
		return 2;
	}
	printf("%d passed, %d failed\n", run - failed, failed);
	if (failed == 0 && s_skipCount > 0)
	{
		printf("%d parts skipped: the suite reports itself skipped (exit 77), not passed\n",
		       s_skipCount);
		return 77;
	}
	return failed > 100 ? 100 : failed;
}
