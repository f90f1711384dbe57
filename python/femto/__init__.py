"""femto: real-time finite-element soft bodies (Python bindings of libfemto).

    import femto
    world = femto.World(integrator="implicit")
    body = world.add_body(femto.TetMesh.load("data/house2.node").transform(scale=0.4,
                          center=True, swap_yz=True), femto.Material("stvk", lam=2e4, mu=5e3))
    for frame in range(100):
        world.step(1 / 30)
    print(body.positions().mean(axis=0))

Errors raise femto.FemtoError carrying the C library's diagnostic (file, line, message).
docs/python.md has the whole tour.
"""
from ._errors import FemtoError
from ._femto import ffi as _ffi, lib as _lib
from .material import Material
from .mesh import TetMesh
from .scene import Scene
from .world import CONTACT_DTYPE, DRAW_FLAGS, Body, Collider, FixedStep, World

__all__ = ["FemtoError", "Material", "TetMesh", "Scene", "World", "Body", "Collider",
           "FixedStep", "CONTACT_DTYPE", "DRAW_FLAGS", "version", "allocated_bytes"]


def version() -> tuple:
    """libfemto's version as (major, minor, patch)."""
    v = _lib.fmGetVersion()
    return (v.major, v.minor, v.patch)


def allocated_bytes() -> int:
    """Bytes libfemto holds now (its allocator's count)."""
    return _lib.fmGetAllocatedBytes()
