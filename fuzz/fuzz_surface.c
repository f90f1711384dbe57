// libFuzzer entry for the surface readers of `femto mesh` (cli/surface_read.c): any bytes, read
// as STL, OFF and PLY, must give a surface or an error, never a crash, leak or undefined
// behaviour.
#include "surface_read.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const cliSurfaceFormat formats[3] = {cli_surfaceStl, cli_surfaceOff, cli_surfacePly};
	for (int f = 0; f < 3; ++f)
	{
		cliSurface surface;
		// Quiet: the messages are still composed (their formatting is fuzzed too).
		if (cliReadSurface("fuzz", (const char*)data, size, formats[f], NULL, &surface))
			cliSurface_Free(&surface);
	}
	return 0;
}
