"""cffi builder of femto's extension module ``femto._femto`` (API mode: compiled against the C
headers, so every struct's layout comes from the C compiler, not from a copy in Python).

The declarations cffi reads are femto's public headers themselves, run through the C
preprocessor with the system headers stubbed out and the inline math helpers removed: a new
function or field in include/femto/ reaches Python without being written twice.
"""
import os
import re
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
INCLUDE = os.path.join(ROOT, "include")
CLI = os.path.join(ROOT, "cli")

# The scene shim: scene files are read by the same parser as the `femto` tool (cli/scene.c),
# and a frame is stepped the way `femto run` steps it (attachments moved first).
SHIM_DECLARATIONS = """
typedef struct fpyScene fpyScene;
int fpy_scene_load(const char* path, const char* text, size_t size, fpyScene** scene,
                   char* messages, size_t capacity);
void fpy_scene_free(fpyScene* scene);
fmWorldId fpy_scene_world(const fpyScene* scene);
int fpy_scene_body_count(const fpyScene* scene);
fmBodyId fpy_scene_body(const fpyScene* scene, int index);
int fpy_scene_collider_count(const fpyScene* scene);
fmColliderId fpy_scene_collider(const fpyScene* scene, int index);
double fpy_scene_dt(const fpyScene* scene);
int fpy_scene_substeps(const fpyScene* scene);
int fpy_scene_frames(const fpyScene* scene);
const char* fpy_scene_description(const fpyScene* scene);
fmResult fpy_scene_step(fpyScene* scene);
"""

SHIM_SOURCE = r"""
#include <femto/femto.h>
#include "scene.h"
#include "attachments.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct fpyScene
{
	cliScene scene;
	cliSimulation sim;
} fpyScene;

/* cliSimulation_Create writes its reasons on standard error: they are caught there for the
   exception (descriptor 2 is borrowed for the call; cffi releases the GIL around C calls, so
   femto.Scene holds a lock over the load: no two loads borrow it at once). */
static bool fpyCreateCaught(fpyScene* s, char* messages, size_t capacity)
{
	FILE* caught = tmpfile();
	int saved = caught != NULL ? dup(2) : -1;
	if (saved < 0)
	{
		if (caught != NULL)
			fclose(caught);
		return cliSimulation_Create(&s->scene, cli_stepCheckWarnings, &s->sim);
	}
	fflush(stderr);
	dup2(fileno(caught), 2);
	bool ok = cliSimulation_Create(&s->scene, cli_stepCheckWarnings, &s->sim);
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
	size_t used = strlen(messages);
	rewind(caught);
	size_t got = fread(messages + used, 1, capacity - 1 - used, caught);
	messages[used + got] = '\0';
	fclose(caught);
	return ok;
}

int fpy_scene_load(const char* path, const char* text, size_t size, fpyScene** scene,
                   char* messages, size_t capacity)
{
	*scene = NULL;
	messages[0] = '\0';
	fpyScene* s = calloc(1, sizeof *s);
	if (s == NULL)
		return 0;
	FILE* out = fmemopen(messages, capacity, "w");
	if (out != NULL)
		setvbuf(out, NULL, _IONBF, 0);
	bool ok = path == NULL ? (cliScene_MakeHouse(&s->scene), true)
	                       : cliScene_LoadText(path, text, size, out, &s->scene);
	if (out != NULL)
		fclose(out);
	messages[capacity - 1] = '\0';
	if (!ok)
	{
		free(s);
		return 0;
	}
	if (!fpyCreateCaught(s, messages, capacity))
	{
		cliScene_Free(&s->scene);
		free(s);
		return 0;
	}
	if (!cliAttachments_Create(&s->scene, &s->sim))
	{
		cliSimulation_Destroy(&s->sim);
		cliScene_Free(&s->scene);
		free(s);
		return 0;
	}
	*scene = s;
	return 1;
}

void fpy_scene_free(fpyScene* s)
{
	if (s == NULL)
		return;
	cliSimulation_Destroy(&s->sim);
	cliScene_Free(&s->scene);
	free(s);
}

fmWorldId fpy_scene_world(const fpyScene* s) { return s->sim.world; }
int fpy_scene_body_count(const fpyScene* s) { return s->sim.bodyCount; }
fmBodyId fpy_scene_body(const fpyScene* s, int i) { return s->sim.bodies[i]; }
int fpy_scene_collider_count(const fpyScene* s) { return s->sim.colliderCount; }
fmColliderId fpy_scene_collider(const fpyScene* s, int i) { return s->sim.colliders[i]; }
double fpy_scene_dt(const fpyScene* s) { return s->scene.dt; }
int fpy_scene_substeps(const fpyScene* s) { return s->scene.substeps; }
int fpy_scene_frames(const fpyScene* s) { return s->scene.frames; }
const char* fpy_scene_description(const fpyScene* s) { return s->scene.description; }

fmResult fpy_scene_step(fpyScene* s)
{
	double frame = cliScene_FrameTime(&s->scene);
	if (s->sim.attachedCount > 0 && !cliAttachments_Update(&s->sim, s->sim.time + frame))
		return fm_errParameter;
	s->sim.time += frame;
	return fmWorld_Step(s->sim.world, frame, s->scene.substeps);
}
"""


def _preprocessed_header():
    """femto.h as cffi reads it: preprocessed with empty system headers, inline helpers cut."""
    with tempfile.TemporaryDirectory() as stub:
        for name in ("stddef.h", "stdint.h", "stdbool.h", "math.h", "stdio.h"):
            open(os.path.join(stub, name), "w").close()
        cc = os.environ.get("CC", "cc")
        text = subprocess.run(
            [cc, "-E", "-P", "-nostdinc", "-I" + stub, "-I" + INCLUDE, "-DFM_API=",
             "-D__attribute__(x)=", os.path.join(INCLUDE, "femto", "femto.h")],
            check=True, capture_output=True, text=True).stdout
    return _without_inline_functions(text)


def _without_inline_functions(text):
    out, i = [], 0
    for match in re.finditer(r"static inline[^;{]*\{", text):
        if match.start() < i:
            continue
        out.append(text[i:match.start()])
        depth, j = 1, match.end()
        while depth > 0:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    out.append(text[i:])
    return "".join(out)


def _integer_constants():
    """The headers' integer #defines (FM_MAX_*), for Python."""
    names = []
    for header in ("base.h", "types.h", "mesh.h", "femto.h"):
        with open(os.path.join(INCLUDE, "femto", header)) as f:
            for line in f:
                m = re.match(r"#define (FM_[A-Z0-9_]+) (\(?[0-9][0-9 <()]*\)?)\s*$", line)
                if m:
                    names.append(m.group(1))
    return "".join("#define %s ...\n" % n for n in names)


def make_builder(library_dirs, libraries, extra_objects, runtime_dirs):
    import cffi
    ffibuilder = cffi.FFI()
    ffibuilder.cdef(_preprocessed_header() + _integer_constants() + SHIM_DECLARATIONS)
    ffibuilder.set_source(
        "femto._femto", SHIM_SOURCE,
        include_dirs=[INCLUDE, CLI],
        library_dirs=library_dirs,
        libraries=libraries,
        extra_objects=extra_objects,
        runtime_library_dirs=runtime_dirs,
        extra_compile_args=["-std=c11", "-D_POSIX_C_SOURCE=200809L"])
    return ffibuilder
