// libFuzzer entry for the TetGen .node/.ele readers (input format in fuzz_inputs.h).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzTetGen(data, size);
	return 0;
}
