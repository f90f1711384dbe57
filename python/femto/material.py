"""Materials: a constitutive model with Young's modulus and Poisson ratio, or Lame constants."""
from __future__ import annotations

from typing import Optional, Union
from ._errors import check
from ._femto import ffi, lib


def _model(name):
    if isinstance(name, int):
        return name
    model = ffi.new("fmMaterialModel*")
    if not lib.fmMaterialModelFromName(name.encode(), model):
        known = ", ".join(ffi.string(lib.fmMaterialModelName(m)).decode()
                          for m in range(lib.fm_materialModelCount)
                          if m not in (lib.fm_stretchEnergy, lib.fm_invariantEnergy))
        raise ValueError("unknown material model %r: expected one of %s" % (name, known))
    return model[0]


class Material:
    """An elastic material (fmMaterial), checked when made.

    ``Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3)`` or
    ``Material("stvk", lam=20000, mu=5000)``; models: linear, corotated, stvk, neohookean,
    mooneyrivlin (with ``c01``), neohookean-isochoric (the names ``femto run`` takes).
    """

    def __init__(self, model: Union[str, int] = "stvk", youngs_modulus: Optional[float] = None,
                 poisson_ratio: Optional[float] = None, lam: Optional[float] = None,
                 mu: Optional[float] = None, c01: float = 0.0) -> None:
        by_young = youngs_modulus is not None or poisson_ratio is not None
        by_lame = lam is not None or mu is not None
        if by_young == by_lame:
            raise TypeError("give youngs_modulus and poisson_ratio, or lam and mu")
        kind = _model(model)
        if by_young:
            if youngs_modulus is None or poisson_ratio is None:
                raise TypeError("youngs_modulus and poisson_ratio go together")
            made = lib.fmMakeMaterial(kind, float(youngs_modulus), float(poisson_ratio))
        else:
            if lam is None or mu is None:
                raise TypeError("lam and mu go together")
            made = lib.fmMakeMaterialLame(kind, float(lam), float(mu))
        self._c = ffi.new("fmMaterial*", made)
        self._c.c01 = float(c01)
        diag = ffi.new("fmDiagnostic*")
        check(lib.fmMaterial_Validate(self._c, diag), diag)

    @property
    def model(self) -> str:
        """The model's name."""
        return ffi.string(lib.fmMaterialModelName(self._c.model)).decode()

    @property
    def lam(self) -> float:
        """First Lame constant (Pa)."""
        return getattr(self._c, "lambda")

    @property
    def mu(self) -> float:
        """Shear modulus (Pa)."""
        return self._c.mu

    def __repr__(self):
        return "Material(%r, lam=%g, mu=%g)" % (self.model, self.lam, self.mu)
