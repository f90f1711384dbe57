// Replays every committed fuzz input through the fuzzers' own actions: the seed corpora
// (fuzz/corpus/<target>/) and the crashes the fuzzers found (tests/data/fuzz/<target>_*).
// Under the ASan/UBSan build each replay is checked for memory errors and undefined behaviour;
// the suite also fails if an input cannot be read or the directories are empty.
#define _POSIX_C_SOURCE 200809L
#include "fuzz_inputs.h"
#include "test.h"

#include <dirent.h>
#include <stdlib.h>

typedef void fmFuzzFcn(const uint8_t* data, size_t size);

static int replayFile(const char* path, fmFuzzFcn* fcn)
{
	FILE* file = fopen(path, "rb");
	if (file == NULL)
		return 0;
	size_t capacity = 1 << 20;
	uint8_t* data = malloc(capacity);
	size_t size = fread(data, 1, capacity, file);
	fclose(file);
	fcn(data, size);
	free(data);
	return 1;
}

// Replay the files in @p dir whose names start with @p prefix; returns how many.
static int replayDirectory(int* failures_, const char* dir, const char* prefix, fmFuzzFcn* fcn)
{
	DIR* d = opendir(dir);
	CHECK(d != NULL);
	if (d == NULL)
		return 0;
	int count = 0;
	struct dirent* entry;
	while ((entry = readdir(d)) != NULL)
	{
		if (entry->d_name[0] == '.' || strncmp(entry->d_name, prefix, strlen(prefix)) != 0)
			continue;
		char path[1024];
		snprintf(path, sizeof path, "%s/%s", dir, entry->d_name);
		int ok = replayFile(path, fcn);
		CHECK(ok);
		count += ok;
	}
	closedir(d);
	return count;
}

TEST(tetgen_corpus_and_crashes_replay_cleanly)
{
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/tetgen", "", fmFuzzTetGen) >= 5);
	CHECK(replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "tetgen_", fmFuzzTetGen) >= 1);
}

TEST(face_corpus_replays_cleanly)
{
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/face", "", fmFuzzFace) >= 2);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "face_", fmFuzzFace);
}

TEST(obj_corpus_replays_cleanly)
{
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/obj", "", fmFuzzObj) >= 5);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "obj_", fmFuzzObj);
}

// The mesh format readers' seeds (tests/data/mesh/ files and hand-written ones) and crashes.
TEST(mesh_format_corpora_replay_cleanly)
{
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/gmsh", "", fmFuzzGmsh) >= 4);
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/vtk", "", fmFuzzVtk) >= 3);
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/vtu", "", fmFuzzVtu) >= 3);
	CHECK(replayDirectory(failures_, FEMTO_FUZZ_DIR "/corpus/medit", "", fmFuzzMedit) >= 2);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "gmsh_", fmFuzzGmsh);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "vtk_", fmFuzzVtk);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "vtu_", fmFuzzVtu);
	replayDirectory(failures_, FEMTO_TEST_DATA "/fuzz", "medit_", fmFuzzMedit);
}
