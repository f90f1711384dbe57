"""Worlds, bodies and colliders: femto's C API with numpy arrays and exceptions."""
from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _defs
from ._defs import fill, finite, float_rows, out_rows, tuple3, vec3
from ._errors import FemtoError, check, error_from_diagnostic, invalid_id
from ._femto import ffi, lib
from .material import Material
from .mesh import TetMesh

Vec3 = Sequence[float]  # any 3 numbers: a tuple, a list, a numpy array
ArrayLike = Any  # what numpy.asarray takes

DRAW_FLAGS = {
    "surfaces": lib.fm_drawSurfaces, "stress": lib.fm_drawStress,
    "tet_edges": lib.fm_drawTetEdges, "inverted_tets": lib.fm_drawInvertedTets,
    "pins": lib.fm_drawPins, "targets": lib.fm_drawTargets, "floor": lib.fm_drawFloor,
    "contacts": lib.fm_drawContacts, "colliders": lib.fm_drawColliders, "all": lib.fm_drawAll,
}

# Contacts as a numpy structured array (fmWorld_GetContacts), one row a touching vertex.
CONTACT_DTYPE = np.dtype([("body", np.int32), ("vertex", np.int32), ("other_body", np.int32),
                          ("collider", np.int32), ("point", np.float64, 3),
                          ("normal", np.float64, 3), ("depth", np.float64),
                          ("impulse", np.float64)])


def _filter(filter):
    f = lib.fmDefaultFilter()
    if filter is not None:
        f.categoryBits, f.maskBits = int(filter[0]), int(filter[1])
    return f


class World:
    """A femto world (fmWorldId). Keywords are fmWorldDef's fields in snake_case:

    ``World(gravity=(0, -9.8, 0), integrator="implicit", floor={"height": -3,
    "friction": "coulomb"}, contact={"friction": 0.5}, worker_count=2)``.
    Destroyed by ``close()``, ``with``, or when collected.
    """

    def __init__(self, **fields: Any) -> None:
        d = ffi.new("fmWorldDef*", lib.fmDefaultWorldDef())
        if "floor" in fields and fields["floor"] in (None, False):
            fields["floor"] = {"enabled": False}
        if "simd" in fields and isinstance(fields["simd"], str):
            level = ffi.new("fmSimdLevel*")
            if not lib.fmSimdLevelFromName(fields["simd"].encode(), level):
                raise ValueError("simd: unknown level %r" % fields["simd"])
            fields["simd"] = level[0]
        fill(d[0], fields, "fmWorldDef")
        diag = ffi.new("fmDiagnostic*")
        check(lib.fmWorldDef_Validate(d, diag), diag)
        self._id = lib.fmCreateWorld(d)
        if self._id.index1 == 0:
            raise FemtoError(lib.fm_errLimit, "no world could be created (too many worlds, or "
                             "out of memory for its capacity)")
        self._owned = True
        self._bodies = {}

    @classmethod
    def _borrow(cls, world_id):
        world = cls.__new__(cls)
        world._id, world._owned, world._bodies = world_id, False, {}
        return world

    def close(self) -> None:
        """Destroy the world and everything in it (a second close does nothing)."""
        if getattr(self, "_owned", False) and lib.fmWorld_IsValid(self._id):
            lib.fmDestroyWorld(self._id)
        self._owned = False

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    @property
    def valid(self) -> bool:
        return bool(lib.fmWorld_IsValid(self._id))

    def _live(self):
        if not lib.fmWorld_IsValid(self._id):
            raise invalid_id("the world")
        return self._id

    def last_error(self, code: int) -> FemtoError:
        """The world's last error as a FemtoError (for a failed code)."""
        diag = lib.fmWorld_GetLastError(self._live())
        return error_from_diagnostic(code, diag)

    def _check(self, code):
        if code != lib.fm_ok:
            raise self.last_error(code)

    # -- stepping ---------------------------------------------------------------------------
    def step(self, time_step: float, substeps: int = 1) -> None:
        """Advance time_step seconds (a frame) in substeps equal substeps. A step that goes
        numerically bad or does not converge (when that is an error) raises FemtoError with
        the world's advice."""
        self._check(lib.fmWorld_Step(self._live(), finite(time_step, "time_step"),
                                     int(substeps)))

    def advance(self, clock: "FixedStep", elapsed: float) -> int:
        """The game loop's fixed step: add elapsed seconds of real time to clock (a FixedStep)
        and step the whole frames it holds (at most clock.max_frames); returns how many. Then
        clock.alpha is where the picture stands between the last two frames."""
        frames = ffi.new("int*")
        code = lib.fmWorld_Advance(self._live(), clock._c, finite(elapsed, "elapsed"), frames)
        self._check(code)
        return frames[0]

    @property
    def stats(self) -> Dict[str, Any]:
        """The last step's statistics (fmStepStats) as a dict."""
        return _defs.as_struct_dict(lib.fmWorld_GetStepStats(self._live()))

    @property
    def profile(self) -> Dict[str, float]:
        """The last step's times in milliseconds (fmProfile) as a dict."""
        return _defs.as_struct_dict(lib.fmWorld_GetProfile(self._live()))

    def estimate_explicit_step(self) -> float:
        """The largest stable explicit substep (s) the world's bodies allow."""
        return lib.fmWorld_EstimateExplicitStep(self._live())

    # -- settings ---------------------------------------------------------------------------
    def set_gravity(self, gravity: Vec3) -> None:
        self._check(lib.fmWorld_SetGravity(self._live(), vec3(gravity, "gravity")))

    def set_floor(self, **fields: Any) -> None:
        """Replace the floor: fmFloorDef's fields (enabled, height, friction, ...)."""
        d = ffi.new("fmFloorDef*", lib.fmDefaultFloorDef())
        fill(d[0], fields, "fmFloorDef")
        self._check(lib.fmWorld_SetFloor(self._live(), d))

    def set_integrator(self, integrator: Union[str, int]) -> None:
        lib.fmWorld_SetIntegrator(self._live(), _defs.ENUMS["integrator"][integrator]
                                  if isinstance(integrator, str) else int(integrator))

    # -- snapshots --------------------------------------------------------------------------
    def save_snapshot(self) -> bytes:
        """The whole state as bytes (restore_snapshot takes it back; same build and world)."""
        size = lib.fmWorld_GetSnapshotSize(self._live())
        buffer = ffi.new("char[]", size)
        written = ffi.new("size_t*")
        self._check(lib.fmWorld_SaveSnapshot(self._id, buffer, size, written))
        return ffi.buffer(buffer, written[0])[:]

    def restore_snapshot(self, data: bytes) -> None:
        """Put the world back to a saved state; a corrupted or foreign snapshot raises."""
        data = bytes(data)
        self._check(lib.fmWorld_RestoreSnapshot(self._live(), data, len(data)))

    # -- bodies and colliders ---------------------------------------------------------------
    def add_body(self, mesh: TetMesh, material: Optional[Material] = None,
                 region_materials: Optional[Sequence[Material]] = None,
                 region_ids: Optional[Sequence[int]] = None, **fields: Any) -> "Body":
        """A soft body of mesh (a TetMesh, copied). Keywords are fmBodyDef's fields in
        snake_case (density, particle_mass, mass_mode, damping, smoothing, friction,
        self_collision, ...); material is a Material (default: the seeds' StVK)."""
        if not isinstance(mesh, TetMesh):
            raise TypeError("mesh: expected a femto.TetMesh, got %s" % type(mesh).__name__)
        d = ffi.new("fmBodyDef*", lib.fmDefaultBodyDef())
        d.mesh = mesh._c
        keep = []
        if material is not None:
            if not isinstance(material, Material):
                raise TypeError("material: expected a femto.Material")
            d.material = material._c[0]
        if region_materials is not None or region_ids is not None:
            if region_materials is None or region_ids is None:
                raise TypeError("region_materials and region_ids go together")
            materials = ffi.new("fmMaterial[]", [m._c[0] for m in region_materials])
            ids = ffi.new("int[]", [int(i) for i in region_ids])
            if len(materials) != len(ids):
                raise ValueError("region_materials and region_ids differ in length")
            d.regionMaterials, d.regionIds, d.regionCount = materials, ids, len(ids)
            keep += [materials, ids]
        fill(d[0], fields, "fmBodyDef")
        body_id, diag = ffi.new("fmBodyId*"), ffi.new("fmDiagnostic*")
        check(lib.fmCreateBody(self._live(), d, body_id, diag), diag)
        return self._body(body_id[0])

    def _body(self, body_id):
        key = (body_id.index1, body_id.generation)
        body = self._bodies.get(key)
        if body is None:
            body = self._bodies[key] = Body(self, body_id)
        return body

    def body_from_id(self, body_id: Any) -> Optional["Body"]:
        """The Body of an fmBodyId (from a contact, a ray hit or an event); None for the null id."""
        return None if body_id.index1 == 0 else self._body(body_id)

    def add_collider(self, shape: str, **fields: Any) -> "Collider":
        """A kinematic collider: shape "plane", "sphere", "box", "capsule" or "mesh" and
        fmColliderDef's fields (center, radius, half_extents, rotation, a, b, normal, offset,
        friction, restitution, stick, velocity, angular_velocity). A mesh takes vertices (n, 3)
        and triangles (m, 3)."""
        d = ffi.new("fmColliderDef*", lib.fmDefaultColliderDef())
        vertices = fields.pop("vertices", None)
        triangles = fields.pop("triangles", None)
        keep = []
        if vertices is not None:
            v = np.ascontiguousarray(vertices, dtype=np.float64)
            t = _defs.int_array(triangles, "triangles")
            if v.ndim != 2 or v.shape[1] != 3 or t.ndim != 2 or t.shape[1] != 3:
                raise ValueError("vertices (n, 3) and triangles (m, 3) expected")
            keep += [v, t]
            d.vertices = ffi.cast("const fmVec3*", ffi.from_buffer(v))
            d.triangles = ffi.cast("const int*", ffi.from_buffer(t))
            d.vertexCount, d.triangleCount = len(v), len(t)
        fields["shape"] = shape
        fill(d[0], fields, "fmColliderDef")
        collider_id, diag = ffi.new("fmColliderId*"), ffi.new("fmDiagnostic*")
        check(lib.fmCreateCollider(self._live(), d, collider_id, diag), diag)
        return Collider(self, collider_id[0])

    @property
    def floor_collider(self) -> Optional["Collider"]:
        """The floor as a Collider (its contact force), or None without a floor."""
        c = lib.fmWorld_GetFloorCollider(self._live())
        return None if c.index1 == 0 else Collider(self, c)

    # -- queries ----------------------------------------------------------------------------
    def contacts(self) -> np.ndarray:
        """The last substep's contacts as a numpy structured array (CONTACT_DTYPE): body and
        other_body are body slots (Body.slot), collider the collider's (0: none)."""
        count = lib.fmWorld_GetContacts(self._live(), ffi.NULL, 0)
        points = ffi.new("fmContactPoint[]", max(count, 1))
        count = lib.fmWorld_GetContacts(self._id, points, count)
        out = np.zeros(count, CONTACT_DTYPE)
        for i in range(count):
            c = points[i]
            out[i] = (c.body.index1, c.vertex, c.otherBody.index1, c.collider.index1,
                      tuple3(c.point), tuple3(c.normal), c.depth, c.impulse)
        return out

    def contact_events(self) -> List[Dict[str, Any]]:
        """Pairs that began or stopped touching in the last step: a list of dicts."""
        count = lib.fmWorld_GetContactEvents(self._live(), ffi.NULL, 0)
        events = ffi.new("fmContactEvent[]", max(count, 1))
        count = lib.fmWorld_GetContactEvents(self._id, events, count)
        return [{"begin": bool(e.begin), "body": self.body_from_id(e.body),
                 "other_body": self.body_from_id(e.otherBody),
                 "collider": None if e.collider.index1 == 0 else Collider(self, e.collider)}
                for e in events[0:count]]

    def sleep_events(self) -> List[Tuple["Body", bool]]:
        """Bodies that fell asleep or woke in the last step: a list of (Body, asleep)."""
        count = lib.fmWorld_GetSleepEvents(self._live(), ffi.NULL, 0)
        events = ffi.new("fmSleepEvent[]", max(count, 1))
        count = lib.fmWorld_GetSleepEvents(self._id, events, count)
        return [(self.body_from_id(e.body), bool(e.asleep)) for e in events[0:count]]

    def _hit(self, hit):
        return {"body": self.body_from_id(hit.body),
                "collider": None if hit.collider.index1 == 0 else Collider(self, hit.collider),
                "triangle": hit.triangle, "vertex": hit.vertex, "point": tuple3(hit.point),
                "normal": tuple3(hit.normal), "fraction": hit.fraction}

    def cast_ray(self, origin: Vec3, translation: Vec3,
                 filter: Optional[Tuple[int, int]] = None) -> Optional[Dict[str, Any]]:
        """The first body or collider along origin + t translation, t in [0, 1]: a dict
        (body, collider, triangle, vertex, point, normal, fraction) or None."""
        hit = ffi.new("fmRayHit*")
        if not lib.fmWorld_CastRay(self._live(), vec3(origin, "origin"),
                                   vec3(translation, "translation"), _filter(filter), hit):
            return None
        return self._hit(hit)

    def grab_ray(self, origin: Vec3, translation: Vec3,
                 filter: Optional[Tuple[int, int]] = None,
                 **grab: float) -> Optional[Dict[str, Any]]:
        """Cast a ray and grab the body it hits where it hits (a mouse pick): the hit or None.
        Keywords are fmGrabDef's (radius, stiffness, damping_ratio, max_force)."""
        d = ffi.new("fmGrabDef*", lib.fmDefaultGrabDef())
        fill(d[0], grab, "fmGrabDef")
        hit = ffi.new("fmRayHit*")
        if not lib.fmWorld_GrabRay(self._live(), vec3(origin, "origin"),
                                   vec3(translation, "translation"), _filter(filter), d, hit):
            return None
        return self._hit(hit)

    def overlap_sphere(self, center: Vec3, radius: float,
                       filter: Optional[Tuple[int, int]] = None) -> List[Dict[str, Any]]:
        """Bodies and colliders a sphere touches: a list of dicts (body, collider, vertex,
        point, distance)."""
        c, r = vec3(center, "center"), finite(radius, "radius")
        count = lib.fmWorld_OverlapSphere(self._live(), c, r, _filter(filter), ffi.NULL, 0)
        found = ffi.new("fmOverlap[]", max(count, 1))
        count = lib.fmWorld_OverlapSphere(self._id, c, r, _filter(filter), found, count)
        return [{"body": self.body_from_id(o.body),
                 "collider": None if o.collider.index1 == 0 else Collider(self, o.collider),
                 "vertex": o.vertex, "point": tuple3(o.point), "distance": o.distance}
                for o in found[0:count]]

    def audit_contact(self) -> Dict[str, Any]:
        """Crossings, vertices inside other bodies and inverted tets now (fmContactAudit)."""
        audit = ffi.new("fmContactAudit*")
        self._check(lib.fmWorld_AuditContact(self._live(), audit))
        out = {}
        for name in ("bodies", "crossings", "selfCrossings", "verticesInside", "deepest",
                     "invertedTets"):
            out[_defs._snake(name)] = getattr(audit, name)
        return out

    def draw(self, flags: Union[str, int, Sequence[str]] = "all") -> Dict[str, list]:
        """The debug draw's arrays (fmWorld_Draw): a dict with "triangles" (a list of dicts of
        numpy arrays: positions, normals, colors or None, indices, vertices, color, body),
        "lines" and "points" (lists of (array, color)) and "planes" ((point, normal, color))."""
        if isinstance(flags, str):
            flags = DRAW_FLAGS[flags]
        elif not isinstance(flags, int):
            flags = sum(DRAW_FLAGS[f] for f in flags)
        return _draw(self, self._live(), flags)


def _floats(pointer, count):
    return np.frombuffer(ffi.buffer(pointer, 4 * count), np.float32).copy()


def _draw(world, world_id, flags):
    out = {"triangles": [], "lines": [], "points": [], "planes": []}
    kinds = {name: field.type for name, field in ffi.typeof("fmDebugDraw").fields}

    @ffi.callback(kinds["drawTriangles"])
    def triangles(t, context):
        n, m = t.vertexCount, t.triangleCount
        out["triangles"].append({
            "body": world.body_from_id(t.body),
            "positions": _floats(t.positions, 3 * n).reshape(n, 3),
            "normals": _floats(t.normals, 3 * n).reshape(n, 3),
            "colors": None if t.colors == ffi.NULL else _floats(t.colors, 3 * n).reshape(n, 3),
            "indices": np.frombuffer(ffi.buffer(t.indices, 12 * m), np.int32).reshape(m, 3).copy(),
            "vertices": None if t.vertices == ffi.NULL else
            np.frombuffer(ffi.buffer(t.vertices, 4 * n), np.int32).copy(),
            "color": t.color})

    @ffi.callback(kinds["drawLines"])
    def lines(points, count, color, context):
        out["lines"].append((_floats(points, 6 * count).reshape(count, 2, 3), color))

    @ffi.callback(kinds["drawPoints"])
    def points(p, count, size, color, context):
        out["points"].append((_floats(p, 3 * count).reshape(count, 3), color))

    @ffi.callback(kinds["drawPlane"])
    def plane(point, normal, color, context):
        out["planes"].append((tuple3(point), tuple3(normal), color))

    d = ffi.new("fmDebugDraw*", lib.fmDefaultDebugDraw())
    d.drawTriangles, d.drawLines, d.drawPoints, d.drawPlane = triangles, lines, points, plane
    d.flags = flags
    code = lib.fmWorld_Draw(world_id, d)
    if code != lib.fm_ok:
        raise world.last_error(code)
    return out


class Body:
    """A soft body of a World. Arrays are copied out into numpy arrays: pass ``out=`` to reuse
    one (float64 or float32, shape (n, 3)); no Python loop runs over vertices."""

    def __init__(self, world, body_id):
        self.world = world
        self._id = body_id

    @property
    def slot(self) -> int:
        """The body's slot number (what contacts() reports)."""
        return self._id.index1

    @property
    def valid(self) -> bool:
        return bool(lib.fmBody_IsValid(self._id))

    def _live(self):
        if not lib.fmBody_IsValid(self._id):
            raise invalid_id("the body")
        return self._id

    def destroy(self) -> None:
        """Remove the body from its world."""
        lib.fmDestroyBody(self._live())
        self.world._bodies.pop((self._id.index1, self._id.generation), None)

    def __repr__(self):
        if not self.valid:
            return "Body(destroyed)"
        return "Body(slot %d, %d vertices, %d tets)" % (self.slot, self.vertex_count,
                                                         self.tet_count)

    @property
    def vertex_count(self) -> int:
        return lib.fmBody_GetVertexCount(self._live())

    @property
    def tet_count(self) -> int:
        return lib.fmBody_GetTetCount(self._live())

    def fracture(self) -> int:
        """Tear where the material's fracture criterion holds now (fmBody_Fracture; the world's
        step does it after every frame): the faces broken. The vertex count grows."""
        broken = lib.fmBody_Fracture(self._live())
        if broken < 0:
            self.world._check(lib.fm_errOutOfMemory)
        return broken

    def damage(self) -> np.ndarray:
        """Each tet's largest traction over strength on its unbroken faces (1 tears)."""
        out = np.zeros(self.tet_count)
        lib.fmBody_ComputeDamage(self._live(), ffi.from_buffer("double[]", out))
        return out

    def pieces(self) -> np.ndarray:
        """Each tet's piece (numbered by first appearance); a whole body is all zeros."""
        out = np.zeros(self.tet_count, dtype=np.intc)
        lib.fmBody_GetPieces(self._live(), ffi.from_buffer("int[]", out))
        return out

    @property
    def broken_face_count(self) -> int:
        """Faces broken since the body was made."""
        return lib.fmBody_GetBrokenFaceCount(self._live())

    def _copy_rows(self, double_fn, float_fn, out, what):
        n = self.vertex_count
        out = out_rows(out, n, what)
        fn, kind = (double_fn, "double[]") if out.dtype == np.float64 else (float_fn, "float[]")
        self.world._check(fn(self._id, ffi.from_buffer(kind, out), n))
        return out

    def positions(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """The vertices' positions (n, 3), in out when given."""
        return self._copy_rows(lib.fmBody_CopyPositions, lib.fmBody_CopyPositionsFloat, out,
                               "positions")

    def velocities(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """The vertices' velocities (n, 3), in out when given."""
        return self._copy_rows(lib.fmBody_CopyVelocities, lib.fmBody_CopyVelocitiesFloat, out,
                               "velocities")

    def interpolated_positions(self, alpha: float,
                               out: Optional[np.ndarray] = None) -> np.ndarray:
        """Positions alpha of the way through the last frame World.advance stepped (float32,
        (n, 3), in out when given): for drawing between frames."""
        n = self.vertex_count
        out = out if out is not None else np.empty((n, 3), np.float32)
        out = out_rows(out, n, "positions")
        if out.dtype != np.float32:
            raise TypeError("positions: expected float32 (what a vertex buffer holds)")
        self.world._check(lib.fmBody_CopyInterpolatedPositionsFloat(
            self._id, finite(alpha, "alpha"), ffi.from_buffer("float[]", out), n))
        return out

    def set_positions(self, positions: ArrayLike) -> None:
        """Overwrite every vertex's position ((n, 3) finite numbers)."""
        a = float_rows(positions, self.vertex_count, "positions")
        lib.fmBody_SetPositions(self._id, ffi.from_buffer("double[]", a))

    def set_velocities(self, velocities: ArrayLike) -> None:
        """Overwrite every vertex's velocity ((n, 3) finite numbers)."""
        a = float_rows(velocities, self.vertex_count, "velocities")
        lib.fmBody_SetVelocities(self._id, ffi.from_buffer("double[]", a))

    @property
    def masses(self) -> np.ndarray:
        """Each vertex's lumped mass (kg), a copy."""
        n = self.vertex_count
        return np.frombuffer(ffi.buffer(lib.fmBody_GetMasses(self._live()), 8 * n),
                             np.float64).copy()

    @property
    def tets(self) -> np.ndarray:
        """(m, 4) int32: the tets' vertices (zero-based)."""
        m = self.tet_count
        return np.frombuffer(ffi.buffer(lib.fmBody_GetTets(self._live()), 16 * m),
                             np.int32).reshape(m, 4).copy()

    @property
    def surface(self) -> np.ndarray:
        """(k, 3) int32: the boundary triangles, counter-clockwise seen from outside."""
        count = ffi.new("int*")
        p = lib.fmBody_GetSurface(self._live(), count)
        return np.frombuffer(ffi.buffer(p, 12 * count[0]), np.int32).reshape(-1, 3).copy()

    def apply_impulse(self, delta_velocity: Vec3) -> None:
        """Add delta_velocity (m/s) to every vertex (the seeds' space bar)."""
        lib.fmBody_ApplyImpulse(self._live(), vec3(delta_velocity, "delta_velocity"))

    def apply_vertex_impulse(self, vertex: int, delta_velocity: Vec3) -> None:
        self._vertex(vertex)
        lib.fmBody_ApplyVertexImpulse(self._id, int(vertex),
                                      vec3(delta_velocity, "delta_velocity"))

    def _vertex(self, vertex):
        n = self.vertex_count
        if not 0 <= int(vertex) < n:
            raise IndexError("vertex %d: expected 0 to %d" % (vertex, n - 1))

    def pin_box(self, lower: Vec3, upper: Vec3, axes: int = 7) -> int:
        """Pin the vertices inside [lower, upper] on axes (bits x=1, y=2, z=4); how many."""
        return lib.fmBody_PinBoxAxes(self._live(), vec3(lower, "lower"), vec3(upper, "upper"),
                                     int(axes))

    def set_pinned(self, vertex: int, pinned: bool = True) -> None:
        self._vertex(vertex)
        lib.fmBody_SetPinned(self._id, int(vertex), bool(pinned))

    def is_pinned(self, vertex: int) -> bool:
        self._vertex(vertex)
        return bool(lib.fmBody_IsPinned(self._id, int(vertex)))

    @property
    def awake(self) -> bool:
        return bool(lib.fmBody_IsAwake(self._live()))

    @awake.setter
    def awake(self, value: bool) -> None:
        lib.fmBody_SetAwake(self._live(), bool(value))

    def set_targets(self, vertices: ArrayLike, positions: ArrayLike, stiffness: float) -> None:
        """Pull vertices toward positions ((k, 3)) with springs of stiffness (N/m) over the next
        step; an empty set clears them."""
        v = _defs.int_array(vertices, "vertices").reshape(-1)
        p = float_rows(positions, len(v), "positions")
        self.world._check(lib.fmBody_SetTargets(
            self._live(), ffi.cast("const int*", ffi.from_buffer(v)),
            ffi.cast("const fmVec3*", ffi.from_buffer(p)), len(v), finite(stiffness, "stiffness")))

    def attach_to_collider(self, vertices: ArrayLike, collider: "Collider", **attach: float) -> None:
        """Glue vertices to a collider (two-way: the glue's pull is part of the collider's
        contact force); keywords are fmAttachDef's (stiffness, damping_ratio, max_force)."""
        v = _defs.int_array(vertices, "vertices").reshape(-1)
        d = ffi.new("fmAttachDef*", lib.fmDefaultAttachDef())
        fill(d[0], attach, "fmAttachDef")
        self.world._check(lib.fmBody_AttachToCollider(
            self._live(), ffi.cast("const int*", ffi.from_buffer(v)), len(v), collider._live(), d))

    def weld(self, vertices: ArrayLike, other: "Body", other_vertices: ArrayLike,
             **attach: float) -> None:
        """Weld vertices[k] of this body to other_vertices[k] of other (or of this body: a
        seam); keywords are fmAttachDef's."""
        v = _defs.int_array(vertices, "vertices").reshape(-1)
        o = _defs.int_array(other_vertices, "other_vertices").reshape(-1)
        if len(o) != len(v):
            raise ValueError(f"vertices and other_vertices differ in length ({len(v)}, {len(o)})")
        d = ffi.new("fmAttachDef*", lib.fmDefaultAttachDef())
        fill(d[0], attach, "fmAttachDef")
        self.world._check(lib.fmBody_Weld(
            self._live(), ffi.cast("const int*", ffi.from_buffer(v)), other._live(),
            ffi.cast("const int*", ffi.from_buffer(o)), len(v), d))

    @property
    def attachment_count(self) -> int:
        """Glued vertices and weld ends of the body."""
        return int(lib.fmBody_GetAttachmentCount(self._live()))

    def clear_attachments(self) -> None:
        """Remove the body's glue and welds (both ends)."""
        lib.fmBody_ClearAttachments(self._live())

    def grab(self, point: Vec3, **grab: float) -> None:
        """Grab the body at point (a mouse drag); keywords are fmGrabDef's fields."""
        d = ffi.new("fmGrabDef*", lib.fmDefaultGrabDef())
        fill(d[0], grab, "fmGrabDef")
        self.world._check(lib.fmBody_Grab(self._live(), vec3(point, "point"), d))

    def move_grab(self, target: Vec3) -> None:
        """Move the grab's target; the patch follows over the next step."""
        self.world._check(lib.fmBody_MoveGrab(self._live(), vec3(target, "target")))

    def release_grab(self) -> None:
        lib.fmBody_ReleaseGrab(self._live())

    @property
    def grab_state(self) -> Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float]]]:
        """(point, target) while grabbed, else None."""
        point, target = ffi.new("fmVec3*"), ffi.new("fmVec3*")
        if not lib.fmBody_GetGrab(self._live(), point, target):
            return None
        return tuple3(point[0]), tuple3(target[0])

    def set_render_mesh(self, vertices: ArrayLike, triangles: ArrayLike) -> None:
        """Skin a triangle mesh (vertices (n, 3) at rest, triangles (m, 3)) to the body."""
        v = float_rows(vertices, len(vertices), "vertices")
        t = _defs.int_array(triangles, "triangles")
        if t.ndim != 2 or t.shape[1] != 3:
            raise ValueError("triangles: expected shape (m, 3), got %s" % (t.shape,))
        diag = ffi.new("fmDiagnostic*")
        check(lib.fmBody_SetRenderMesh(self._live(), ffi.from_buffer("double[]", v), len(v),
                                       ffi.cast("const int*", ffi.from_buffer(t)), len(t), diag),
              diag)

    def clear_render_mesh(self) -> None:
        lib.fmBody_ClearRenderMesh(self._live())

    @property
    def render_triangles(self) -> np.ndarray:
        count = ffi.new("int*")
        p = lib.fmBody_GetRenderTriangles(self._live(), count)
        if p == ffi.NULL:
            return np.zeros((0, 3), np.int32)
        return np.frombuffer(ffi.buffer(p, 12 * count[0]), np.int32).reshape(-1, 3).copy()

    def render_positions(self, out: Optional[np.ndarray] = None,
                         normals: Optional[np.ndarray] = None) -> np.ndarray:
        """The render mesh's deformed positions (and normals into normals when given)."""
        n = lib.fmBody_GetRenderVertexCount(self._live())
        if n <= 0:
            raise FemtoError(lib.fm_errParameter, "the body has no render mesh "
                             "(set_render_mesh)")
        out = out_rows(out, n, "render positions")
        if normals is not None:
            normals = out_rows(normals, n, "render normals")
            if normals.dtype != out.dtype:
                raise TypeError("render normals: expected the positions' dtype")
        kind = "double[]" if out.dtype == np.float64 else "float[]"
        fn = (lib.fmBody_CopyRenderPositions if out.dtype == np.float64
              else lib.fmBody_CopyRenderPositionsFloat)
        nrm = ffi.NULL if normals is None else ffi.from_buffer(kind, normals)
        self.world._check(fn(self._id, ffi.from_buffer(kind, out), nrm, n))
        return out

    def add_nodal_force(self, lower: Vec3, upper: Vec3, force: Vec3) -> int:
        """A force (N) shared by the vertices in [lower, upper]; how many took it."""
        return lib.fmBody_AddNodalForce(self._live(), vec3(lower, "lower"),
                                        vec3(upper, "upper"), vec3(force, "force"))

    def add_pressure(self, lower: Vec3, upper: Vec3, pressure: float,
                     follower: bool = False) -> int:
        """A pressure (Pa) on the surface triangles in [lower, upper]; how many took it."""
        return lib.fmBody_AddPressure(self._live(), vec3(lower, "lower"), vec3(upper, "upper"),
                                      finite(pressure, "pressure"), bool(follower))

    def clear_loads(self) -> None:
        lib.fmBody_ClearLoads(self._live())

    def elastic_forces(self, out: Optional[np.ndarray] = None) -> Tuple[float, np.ndarray]:
        """(energy, forces): the elastic energy (J) and each vertex's elastic force (n, 3)."""
        out = out_rows(out, self.vertex_count, "forces")
        if out.dtype != np.float64:
            raise TypeError("forces: expected float64")
        energy = lib.fmBody_ComputeElasticForces(self._live(), ffi.from_buffer("double[]", out))
        return energy, out

    @property
    def stats(self) -> Dict[str, Any]:
        """Energies, centre of mass, lowest y, inverted tets (fmBodyStats) as a dict."""
        return _defs.as_struct_dict(lib.fmBody_GetStats(self._live()))

    def set_material(self, material: Material) -> None:
        diag = ffi.new("fmDiagnostic*")
        check(lib.fmBody_SetMaterial(self._live(), material._c, diag), diag)

    def solve_static(self, tolerance: float = 1e-8, max_iterations: int = 100) -> float:
        """Solve for equilibrium under the loads and pins; returns the residual reached."""
        residual, diag = ffi.new("double*"), ffi.new("fmDiagnostic*")
        check(lib.fmBody_SolveStatic(self._live(), finite(tolerance, "tolerance"),
                                     int(max_iterations), residual, diag), diag)
        return residual[0]


class FixedStep:
    """A game loop's clock (fmFixedStep): frame_time (s), substeps, max_frames; after each
    World.advance, accumulator (s) and alpha (in [0, 1))."""

    def __init__(self, frame_time: float = 1.0 / 60.0, substeps: int = 1,
                 max_frames: int = 4) -> None:
        self._c = ffi.new("fmFixedStep*", lib.fmDefaultFixedStep())
        self._c.frameTime = float(frame_time)
        self._c.substeps = int(substeps)
        self._c.maxFrames = int(max_frames)

    frame_time = property(lambda self: self._c.frameTime)
    substeps = property(lambda self: self._c.substeps)
    max_frames = property(lambda self: self._c.maxFrames)
    accumulator = property(lambda self: self._c.accumulator)
    alpha = property(lambda self: self._c.alpha)


class Collider:
    """A kinematic collider of a World: move it, read what the bodies push on it."""

    def __init__(self, world, collider_id):
        self.world = world
        self._id = collider_id

    @property
    def slot(self) -> int:
        return self._id.index1

    @property
    def valid(self) -> bool:
        return bool(lib.fmCollider_IsValid(self._id))

    def _live(self):
        if not lib.fmCollider_IsValid(self._id):
            raise invalid_id("the collider")
        return self._id

    def destroy(self) -> None:
        lib.fmDestroyCollider(self._live())

    def set_transform(self, position: Vec3, rotation: Vec3 = (0.0, 0.0, 0.0)) -> None:
        """Place the collider (rotation as axis-angle, rad) for the next step."""
        lib.fmCollider_SetTransform(self._live(), vec3(position, "position"),
                                    vec3(rotation, "rotation"))

    def set_velocity(self, velocity: Vec3, angular_velocity: Vec3 = (0.0, 0.0, 0.0)) -> None:
        lib.fmCollider_SetVelocity(self._live(), vec3(velocity, "velocity"),
                                   vec3(angular_velocity, "angular_velocity"))

    def set_mesh_vertices(self, vertices: ArrayLike) -> None:
        """A mesh collider's new vertices ((n, 3), m, in its own frame, as many as at creation),
        reached at the end of the next step; their velocity over it pushes and drags the bodies
        (docs/contact.md, "Moving mesh colliders")."""
        v = np.ascontiguousarray(vertices, dtype=np.float64)
        v = float_rows(v, len(v) if v.ndim == 2 else -1, "vertices")
        self.world._check(lib.fmCollider_SetMeshVertices(
            self._live(), ffi.cast("const fmVec3*", ffi.from_buffer(v)), len(v)))

    @property
    def position(self) -> Tuple[float, float, float]:
        return tuple3(lib.fmCollider_GetPosition(self._live()))

    def contact_force(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]:
        """(force, torque): what the soft bodies pushed on it, averaged over the last step."""
        force, torque = ffi.new("fmVec3*"), ffi.new("fmVec3*")
        lib.fmCollider_GetContactForce(self._live(), force, torque)
        return tuple3(force[0]), tuple3(torque[0])


