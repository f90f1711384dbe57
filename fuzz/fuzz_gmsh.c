// libFuzzer entry for the Gmsh .msh (2.2 and 4.1, ASCII and binary) reader (fuzz_inputs.h).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzGmsh(data, size);
	return 0;
}
