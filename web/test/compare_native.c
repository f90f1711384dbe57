// The native side of the Node.js comparison (docs/web.md, scripts/check-web.sh): runs a scene of
// web/femto_web.c through the script that web/test/compare_node.cjs runs on the WebAssembly
// build, and prints the final positions' bit patterns (one vertex a line: body, vertex, x y z as
// 16 hex digits), which the Node side compares with its own.
//
//   compare_native SCENE FRAMES DETERMINISTIC INTEGRATOR [--plain]
//
// --plain: no jump or drag, and the positions as `femto run --export-node` writes them (1-based
// index, %.17g), to compare the glue's scene with the tool's (scripts/check-web.sh). Run from the
// repository's root: the glue's files (fw_file_path) are read from there.
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int fw_file_count(void);
const char* fw_file_path(int k);
int fw_set_file(const char* path, const char* text, int size);
int fw_load_scene(int index, int deterministic);
void fw_set_integrator(int integrator);
int fw_step(void);
void fw_jump(void);
int fw_drag_start(int b, double x, double y, double z);
void fw_drag_move(double x, double y, double z);
void fw_drag_end(void);
int fw_body_count(void);
int fw_vertex_count(int b);
const double* fw_positions_double(int b);
const char* fw_error(void);

// The files the glue reads (fw_file_path), read from disk and given to it (fw_set_file), as
// give_files.cjs gives them to the WebAssembly build; false with a message when one is not read.
static bool giveFiles(void)
{
	for (int k = 0; k < fw_file_count(); ++k)
	{
		const char* path = fw_file_path(k);
		FILE* file = fopen(path, "rb");
		long size = -1;
		if (file != NULL && fseek(file, 0, SEEK_END) == 0)
			size = ftell(file);
		char* text = size >= 0 && fseek(file, 0, SEEK_SET) == 0 ? malloc((size_t)size + 1) : NULL;
		bool read = text != NULL && fread(text, 1, (size_t)size, file) == (size_t)size;
		if (file != NULL)
			fclose(file);
		int r = read ? fw_set_file(path, text, (int)size) : -1;
		free(text);
		if (r != 0)
		{
			fprintf(stderr, "compare_native: %s: %s\n", path, read ? fw_error() : "cannot read it");
			return false;
		}
	}
	return true;
}

// The script, as compare_node.cjs's: a jump at 1/3 of the frames, body 0 grabbed at vertex 5 and
// pulled 0.2 m up from where it is from 1/2 to 2/3 (without @p input: frames only).
static int run(int frames, bool input)
{
	for (int f = 0; f < frames; ++f)
	{
		if (input && f == frames / 3)
			fw_jump();
		if (input && f == frames / 2)
		{
			const double* x = fw_positions_double(0);
			fw_drag_start(0, x[15], x[16], x[17]);
			fw_drag_move(x[15], x[16] + 0.2, x[17]);
		}
		if (input && f == 2 * frames / 3)
			fw_drag_end();
		int r = fw_step();
		if (r != 0)
		{
			fprintf(stderr, "compare_native: frame %d: %s\n", f, fw_error());
			return r;
		}
	}
	return 0;
}

int main(int argc, char** argv)
{
	bool plain = argc == 6 && strcmp(argv[5], "--plain") == 0;
	if (argc != 5 && !plain)
	{
		fprintf(stderr, "usage: compare_native SCENE FRAMES DETERMINISTIC INTEGRATOR [--plain]\n");
		return 2;
	}
	if (!giveFiles())
		return 1;
	int r = fw_load_scene(atoi(argv[1]), atoi(argv[3]));
	if (r != 0)
	{
		fprintf(stderr, "compare_native: %s\n", fw_error());
		return 1;
	}
	fw_set_integrator(atoi(argv[4]));
	struct timespec t0, t1;
	timespec_get(&t0, TIME_UTC);
	if (run(atoi(argv[2]), !plain) != 0)
		return 1;
	timespec_get(&t1, TIME_UTC);
	double ms = 1e3 * (double)(t1.tv_sec - t0.tv_sec) + 1e-6 * (double)(t1.tv_nsec - t0.tv_nsec);
	fprintf(stderr, "compare_native: %.3f ms a frame\n", ms / atoi(argv[2]));
	for (int b = 0; b < fw_body_count(); ++b)
	{
		const double* x = fw_positions_double(b);
		for (int i = 0; i < fw_vertex_count(b); ++i)
		{
			if (plain)
			{
				printf("%d %.17g %.17g %.17g\n", i + 1, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
				continue;
			}
			uint64_t bits[3];
			memcpy(bits, x + 3 * i, sizeof bits);
			printf("%d %d %016" PRIx64 " %016" PRIx64 " %016" PRIx64 "\n", b, i, bits[0], bits[1],
			       bits[2]);
		}
	}
	return 0;
}
