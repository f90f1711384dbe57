// libFuzzer entry for the VTK XML .vtu reader (fuzz_inputs.h).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzVtu(data, size);
	return 0;
}
