// Fuzz the TetGen .face reader.
#include <femto/femto.h>

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	int* triangles = NULL;
	int count = 0;
	for (int first = 0; first < 2; ++first)
		if (fmLoadTetGenFaceFromMemory((const char*)data, size, "fuzz.face", 100, first, &triangles,
									   &count, NULL) == fm_ok)
			fmFree(triangles);
	return 0;
}
