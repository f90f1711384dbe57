// A fuzz target that leaks what it allocates: the control of the replay tests. Under
// LeakSanitizer its replay must fail (tests/CMakeLists.txt registers it WILL_FAIL), which shows
// that a leak in a real target's replay fails too: the replays are judged by their exit status.
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static void* volatile s_lastLeak;

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	uint8_t* copy = malloc(size + 1);
	if (copy != NULL)
		memcpy(copy, data, size);
	s_lastLeak = copy;
	s_lastLeak = NULL;
	return 0;
}
