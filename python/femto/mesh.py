"""Tetrahedral meshes: read from TetGen, Gmsh, VTK, VTU or Medit files, made as boxes, or given
as arrays; written back to any of those."""
from __future__ import annotations

from typing import Any, Dict, Optional, Sequence, Tuple, Union
import os

import numpy as np

from ._defs import vec3
from ._errors import check
from ._femto import ffi, lib


class TetMesh:
    """A tetrahedral mesh owned by the C library (freed with the object).

    ``vertices`` (n, 3) float64 and ``tets`` (m, 4) int32 are copies (zero-based).
    """

    def __init__(self) -> None:
        self._c = ffi.gc(ffi.new("fmTetMesh*"), lib.fmFreeTetMesh)

    @classmethod
    def load(cls, path: Union[str, os.PathLike], ele_path: Optional[Union[str, os.PathLike]] = None) -> "TetMesh":
        """Read a mesh: a TetGen .node (its .ele beside it, or ele_path), .msh, .vtk, .vtu,
        .mesh. Raises FemtoError naming the file, line and what was expected."""
        mesh, diag = cls(), ffi.new("fmDiagnostic*")
        path = os.fspath(path)
        if path.endswith(".node") or ele_path is not None:
            ele = os.fspath(ele_path) if ele_path is not None else path[:-5] + ".ele"
            check(lib.fmLoadTetGen(path.encode(), ele.encode(), mesh._c, diag), diag)
        else:
            check(lib.fmLoadMesh(path.encode(), mesh._c, diag), diag)
        return mesh

    @classmethod
    def box(cls, counts: Tuple[int, int, int], lower: Sequence[float],
            upper: Sequence[float]) -> "TetMesh":
        """A box [lower, upper] of counts = (nx, ny, nz) cubes, 6 tets each."""
        nx, ny, nz = (int(c) for c in counts)
        mesh = cls()
        code = lib.fmMakeBoxMesh(nx, ny, nz, vec3(lower, "lower"), vec3(upper, "upper"),
                                 mesh._c)
        check(code, what="box %s from %s to %s" % ((nx, ny, nz), tuple(lower), tuple(upper)))
        return mesh

    @classmethod
    def from_arrays(cls, vertices: Any, tets: Any) -> "TetMesh":
        """A mesh of vertices (n, 3) and tets (m, 4, zero-based), checked as a file would be."""
        v = np.ascontiguousarray(vertices, dtype=np.float64)
        t = np.ascontiguousarray(tets, dtype=np.int64)
        if v.ndim != 2 or v.shape[1] != 3 or t.ndim != 2 or t.shape[1] != 4:
            raise ValueError("expected vertices (n, 3) and tets (m, 4), got %s and %s"
                             % (v.shape, t.shape))
        node = ["%d 3 0 0" % len(v)] + ["%d %.17g %.17g %.17g" % (i, *p) for i, p in enumerate(v)]
        ele = ["%d 4 0" % len(t)] + ["%d %d %d %d %d" % (i, *e) for i, e in enumerate(t)]
        node_text, ele_text = ("\n".join(node) + "\n").encode(), ("\n".join(ele) + "\n").encode()
        mesh, diag = cls(), ffi.new("fmDiagnostic*")
        check(lib.fmLoadTetGenFromMemory(node_text, len(node_text), b"vertices", ele_text,
                                         len(ele_text), b"tets", mesh._c, diag), diag)
        return mesh

    @property
    def vertex_count(self) -> int:
        return self._c.nodeCount

    @property
    def tet_count(self) -> int:
        return self._c.tetCount

    @property
    def vertices(self) -> np.ndarray:
        """(n, 3) float64 copy of the rest positions."""
        n = self._c.nodeCount
        return np.frombuffer(ffi.buffer(self._c.positions, 24 * n), np.float64).reshape(n, 3).copy()

    @property
    def tets(self) -> np.ndarray:
        """(m, 4) int32 copy of the tets' vertices, zero-based."""
        m = self._c.tetCount
        return np.frombuffer(ffi.buffer(self._c.tets, 16 * m), np.int32).reshape(m, 4).copy()

    def transform(self, scale: float = 1.0, center: bool = False, swap_yz: bool = False,
                  translate: Sequence[float] = (0.0, 0.0, 0.0)) -> "TetMesh":
        """Scale, centre, swap y and z, then translate the rest shape (as scenes do)."""
        t = ffi.new("fmMeshTransform*", lib.fmDefaultMeshTransform())
        t.scale, t.center, t.swapYZ = float(scale), bool(center), bool(swap_yz)
        t.translate = vec3(translate, "translate")
        lib.fmTetMesh_Transform(self._c, t)
        return self

    def info(self) -> Dict[str, Any]:
        """Counts, volumes, dihedral angles and quality (fmMeshInfo) as a dict."""
        from ._defs import as_struct_dict
        info = ffi.new("fmMeshInfo*")
        check(lib.fmTetMesh_GetInfo(self._c, info), what="mesh info")
        return as_struct_dict(info[0])

    def write(self, path: Union[str, os.PathLike], positions: Optional[Any] = None) -> None:
        """Write the mesh (the format from the extension; TetGen writes .node and .ele),
        optionally with deformed positions (n, 3)."""
        diag = ffi.new("fmDiagnostic*")
        p = ffi.NULL
        if positions is not None:
            pos = np.ascontiguousarray(positions, dtype=np.float64)
            if pos.shape != (self.vertex_count, 3):
                raise ValueError("positions: expected (%d, 3), got %s"
                                 % (self.vertex_count, pos.shape))
            p = ffi.from_buffer("double[]", pos)
        check(lib.fmWriteMesh(os.fspath(path).encode(), self._c, p, diag), diag)

    def __repr__(self):
        return "TetMesh(%d vertices, %d tets)" % (self.vertex_count, self.tet_count)


