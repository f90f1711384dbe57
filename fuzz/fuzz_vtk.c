// libFuzzer entry for the VTK legacy .vtk reader (fuzz_inputs.h).
#include "fuzz_inputs.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	fmFuzzVtk(data, size);
	return 0;
}
