"""What the Python bindings cost on top of libfemto (docs/performance.md, "Python").

    .venv/bin/python python/bench/overhead.py [frames]

1. The bouncy house, frame by frame as a game steps it from Python (World.step, then the
   positions copied into a reused numpy array): each frame's wall time around the Python call
   against the library's own time for the step (fmProfile.step, measured inside fmWorld_Step).
   The difference is what the bindings add: argument conversion, the id checks, the copy.
2. One call's cost through the three ways to reach a C library from Python: cffi's API mode
   (the compiled extension femto uses), cffi's ABI mode (libffi over the same declarations)
   and ctypes, on fmBody_GetVertexCount (a 16-byte struct by value in, an int out).
"""
import ctypes
import os
import statistics
import sys
import time
import timeit

import numpy as np

import femto
from femto._femto import ffi, lib

frames = int(sys.argv[1]) if len(sys.argv) > 1 else 600
scene = femto.Scene.house()
world, house = scene.world, scene.bodies[0]
frame_time, substeps = scene.frame_time, scene.substeps
out = np.empty((house.vertex_count, 3))
walls, steps, copies = [], [], []
for frame in range(frames):
    begin = time.perf_counter()
    world.step(frame_time, substeps)
    middle = time.perf_counter()
    house.positions(out=out)
    end = time.perf_counter()
    walls.append((middle - begin) * 1e3)
    steps.append(world.profile["step"])
    copies.append((end - middle) * 1e3)
    if frame % 100 == 99:
        house.apply_impulse((0.0, 8.0, 0.0))  # keep it moving: frames in motion, not at rest

added = [w - s for w, s in zip(walls, steps)]
median_step = statistics.median(steps)
print("house (%d vertices, %d tets, explicit, %d substeps a frame), %d frames:"
      % (house.vertex_count, house.tet_count, substeps, frames))
print("  library step   median %.4f ms  p95 %.4f ms" % (median_step, np.percentile(steps, 95)))
print("  Python step    median %.4f ms  p95 %.4f ms" % (statistics.median(walls),
                                                       np.percentile(walls, 95)))
print("  added by the bindings: median %.1f us (%.2f%% of the step), p95 %.1f us"
      % (1e3 * statistics.median(added), 100 * statistics.median(added) / median_step,
         1e3 * np.percentile(added, 95)))
print("  positions copied into a numpy array: median %.1f us (%.2f%% of the step)"
      % (1e3 * statistics.median(copies), 100 * statistics.median(copies) / median_step))

# One call three ways.
body_id = house._id
library = os.path.join(os.path.dirname(femto.__file__),
                       [f for f in os.listdir(os.path.dirname(femto.__file__))
                        if f.startswith("libfemto.so")][0])


class BodyId(ctypes.Structure):
    _fields_ = [("index1", ctypes.c_int32), ("generation", ctypes.c_uint32),
                ("world0", ctypes.c_int32), ("worldGeneration", ctypes.c_uint32)]


c = ctypes.CDLL(library)
c.fmBody_GetVertexCount.argtypes = [BodyId]
c.fmBody_GetVertexCount.restype = ctypes.c_int
c_id = BodyId(body_id.index1, body_id.generation, body_id.world0, body_id.worldGeneration)

import cffi  # noqa: E402

abi = cffi.FFI()
abi.cdef("typedef struct { int32_t index1; uint32_t generation; int32_t world0; "
         "uint32_t worldGeneration; } fmBodyId; int fmBody_GetVertexCount(fmBodyId);")
abi_lib = abi.dlopen(library)
abi_id = abi.new("fmBodyId*", {"index1": body_id.index1, "generation": body_id.generation,
                               "world0": body_id.world0,
                               "worldGeneration": body_id.worldGeneration})[0]
ways = {
    "cffi API mode (femto)": lambda: lib.fmBody_GetVertexCount(body_id),
    "cffi ABI mode": lambda: abi_lib.fmBody_GetVertexCount(abi_id),
    "ctypes": lambda: c.fmBody_GetVertexCount(c_id),
    "femto.Body.vertex_count": lambda: house.vertex_count,
}
assert len({f() for f in ways.values()}) == 1
print("one call, fmBody_GetVertexCount (median of 7 runs of 200,000):")
for name, fn in ways.items():
    per = statistics.median(timeit.repeat(fn, number=200000, repeat=7)) / 200000
    print("  %-26s %6.0f ns" % (name, per * 1e9))
