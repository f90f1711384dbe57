// libFuzzer entry for the JSON scene parser of the femto tool (cli/scene.c): any bytes must give
// a scene or an error message, never a crash, leak or undefined behaviour.
#include "scene.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	cliScene scene;
	// Quiet: a fuzzer that prints every rejection drowns its own reports (the messages are
	// still composed, so their formatting code is fuzzed too).
	if (cliScene_LoadText("fuzz.json", (const char*)data, size, NULL, &scene))
		cliScene_Free(&scene);
	return 0;
}
