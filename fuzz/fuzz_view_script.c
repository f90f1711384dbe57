// libFuzzer entry for the viewer's script reader (viewer/script.c, `femto view --script`): any
// bytes give a script or a located error, never a crash, a hang or an unbounded allocation.
#define _POSIX_C_SOURCE 200809L
#include "script.h"

#include <stdint.h>
#include <stdio.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	if (size == 0)
		return 0;
	FILE* in = fmemopen((void*)data, size, "r");
	if (in == NULL)
		return 0;
	fvScript script;
	char error[512];
	if (fvScript_Read(in, "fuzz.txt", &script, error, sizeof error))
		fvScript_Free(&script);
	fclose(in);
	return 0;
}
