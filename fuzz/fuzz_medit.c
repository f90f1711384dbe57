// libFuzzer entry for the Medit .mesh reader (fuzz_inputs.h).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzMedit(data, size);
	return 0;
}
