// A main() for fuzz targets built without libFuzzer: runs the target once on every file named
// on the command line. CTest uses it to replay the committed corpora and found crashes in the
// normal and sanitizer builds (the fuzzers themselves need clang). Exit 0 only when every input
// was read (at least one); CTest judges the replay by its exit status, which a sanitizer's report
// (LeakSanitizer's at exit included) makes non-zero.
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv)
{
	if (argc < 2)
	{
		fprintf(stderr, "usage: %s INPUT...\n", argv[0]);
		return 2;
	}
	for (int i = 1; i < argc; ++i)
	{
		FILE* file = fopen(argv[i], "rb");
		if (file == NULL)
		{
			fprintf(stderr, "%s: cannot open\n", argv[i]);
			return 1;
		}
		size_t capacity = 1 << 20;
		uint8_t* data = malloc(capacity);
		if (data == NULL)
		{
			fclose(file);
			fprintf(stderr, "%s: out of memory\n", argv[i]);
			return 1;
		}
		size_t size = fread(data, 1, capacity, file);
		int readError = ferror(file);
		fclose(file);
		if (readError)
		{
			free(data);
			fprintf(stderr, "%s: read error\n", argv[i]);
			return 1;
		}
		LLVMFuzzerTestOneInput(data, size);
		free(data);
	}
	printf("replayed %d inputs\n", argc - 1);
	return 0;
}
