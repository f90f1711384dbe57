"""Scenes: JSON scene files read by the same parser as `femto run`, stepped frame by frame."""
from __future__ import annotations

from typing import Union
import os
import threading

from ._errors import FemtoError
from ._femto import ffi, lib
from .world import Collider, World

_MESSAGES = 8192
# A scene's load borrows standard error to catch the tool's messages: one load at a time.
_LOAD_LOCK = threading.Lock()


class Scene:
    """A scene file made into a world (``Scene.load("scenes/stack.json")``, or
    ``Scene.house()``, the seeds' bouncy house). ``step()`` advances one frame as `femto run`
    does (attachments moved first); ``world``, ``bodies`` and ``colliders`` reach the rest."""

    def __init__(self, handle):
        self._handle = handle
        self.world = World._borrow(lib.fpy_scene_world(handle))
        self.bodies = [self.world.body_from_id(lib.fpy_scene_body(handle, i))
                       for i in range(lib.fpy_scene_body_count(handle))]
        self.colliders = [Collider(self.world, lib.fpy_scene_collider(handle, i))
                          for i in range(lib.fpy_scene_collider_count(handle))]

    @classmethod
    def load(cls, path: Union[str, os.PathLike]) -> "Scene":
        """Read and make a scene; a bad file raises FemtoError with every message the tool
        gives (file, line, what was expected)."""
        path = os.fspath(path)
        try:
            with open(path, "rb") as f:
                text = f.read()
        except OSError as e:
            raise FemtoError(lib.fm_errIo, "cannot read the scene: %s" % e.strerror,
                             path) from None
        return cls._make(path.encode(), text)

    @classmethod
    def house(cls) -> "Scene":
        """The built-in bouncy house (`femto run` with no scene)."""
        return cls._make(ffi.NULL, b"")

    @classmethod
    def _make(cls, name, text):
        handle = ffi.new("fpyScene**")
        messages = ffi.new("char[]", _MESSAGES)
        with _LOAD_LOCK:
            made = lib.fpy_scene_load(name, text, len(text), handle, messages, _MESSAGES)
        if not made:
            said = ffi.string(messages).decode(errors="replace").strip()
            where = name.decode() if name != ffi.NULL else "builtin:house"
            raise FemtoError(lib.fm_errParameter, said or "the scene could not be made", where)
        return cls(ffi.gc(handle[0], lib.fpy_scene_free))

    def _live(self):
        if self._handle is None:
            raise FemtoError(lib.fm_errInvalidId, "the scene is closed")
        return self._handle

    @property
    def dt(self) -> float:
        """Seconds of one substep."""
        return lib.fpy_scene_dt(self._live())

    @property
    def substeps(self) -> int:
        return lib.fpy_scene_substeps(self._live())

    @property
    def frame_time(self) -> float:
        return self.dt * self.substeps

    @property
    def frames(self) -> int:
        """The scene's frame count (0 when it gives none)."""
        return lib.fpy_scene_frames(self._live())

    @property
    def description(self) -> str:
        return ffi.string(lib.fpy_scene_description(self._live())).decode(errors="replace")

    def step(self, frames: int = 1) -> None:
        """Advance frames frames; a failed step raises FemtoError with the world's advice."""
        for _ in range(int(frames)):
            code = lib.fpy_scene_step(self._live())
            if code != lib.fm_ok:
                raise self.world.last_error(code)

    def close(self) -> None:
        """Destroy the scene's world (the bodies and colliders go with it)."""
        if self._handle is not None:
            ffi.release(self._handle)
            self._handle = None
