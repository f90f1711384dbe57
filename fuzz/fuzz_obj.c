// libFuzzer entry for the Wavefront OBJ reader (fmLoadObjFromMemory; action in fuzz_inputs.c).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzObj(data, size);
	return 0;
}
