"""Materials: a constitutive model with Young's modulus and Poisson ratio, or Lame constants."""
from __future__ import annotations

from typing import Dict, Optional, Sequence, Union
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


# Python's names of fmPlasticity's fields (docs/materials.md, "Plasticity").
_PLASTICITY = {"yield_stress": "yieldStress", "hardening": "hardening",
               "creep_rate": "creepRate", "max_plastic_strain": "maxPlasticStrain"}
_FRACTURE = {"strength": "strength", "length": "length", "min_volume": "minVolume"}


class Material:
    """An elastic material (fmMaterial), checked when made.

    ``Material("neohookean", youngs_modulus=1e5, poisson_ratio=0.3)`` or
    ``Material("stvk", lam=20000, mu=5000)``; models: linear, corotated, stvk, neohookean,
    mooneyrivlin (with ``c01``), neohookean-isochoric, fibre-neohookean (with
    ``fibre_stiffness`` and ``fibre``), and through ``Material.orthotropic`` orthotropic-linear
    and orthotropic-stvk (the names ``femto run`` takes). ``plasticity={"yield_stress": Pa,
    "hardening": Pa, "creep_rate": 1/s, "max_plastic_strain": ...}`` makes an isotropic
    large-strain model flow (von Mises; the body's ``stats()`` gives ``plastic_work``).
    ``nodal_pressure=True`` puts the volume term on vertex patches (linear, neohookean,
    mooneyrivlin, neohookean-isochoric): no locking near a Poisson ratio of 0.5
    (docs/materials.md, "Nearly incompressible bodies"). ``fracture={"strength": Pa,
    "length": m, "min_volume": m^3}`` lets the body tear along its tet faces (the body's
    ``fracture()``, ``damage()``, ``pieces()``; docs/materials.md, "Fracture").
    """

    def __init__(self, model: Union[str, int] = "stvk", youngs_modulus: Optional[float] = None,
                 poisson_ratio: Optional[float] = None, lam: Optional[float] = None,
                 mu: Optional[float] = None, c01: float = 0.0, fibre_stiffness: float = 0.0,
                 fibre: Optional[Sequence[float]] = None,
                 sheet: Optional[Sequence[float]] = None,
                 plasticity: Optional[Dict[str, float]] = None,
                 nodal_pressure: bool = False,
                 fracture: Optional[Dict[str, float]] = None) -> None:
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
        self._c.fibreStiffness = float(fibre_stiffness)
        for key, value in (plasticity or {}).items():
            field = _PLASTICITY.get(key)
            if field is None:
                raise TypeError("plasticity: unknown key %r (expected one of %s)"
                                % (key, ", ".join(sorted(_PLASTICITY))))
            setattr(self._c.plasticity, field, float(value))
        self._c.nodalPressure = bool(nodal_pressure)
        for key, value in (fracture or {}).items():
            field = _FRACTURE.get(key)
            if field is None:
                raise TypeError("fracture: unknown key %r (expected one of %s)"
                                % (key, ", ".join(sorted(_FRACTURE))))
            setattr(self._c.fracture, field, float(value))
        self._finish(fibre, sheet)

    @classmethod
    def orthotropic(cls, model: str = "orthotropic-linear", E: Sequence[float] = (1e6, 1e6, 1e6),
                    nu: Sequence[float] = (0.3, 0.3, 0.3),
                    G: Sequence[float] = (3.8e5, 3.8e5, 3.8e5),
                    fibre: Optional[Sequence[float]] = None,
                    sheet: Optional[Sequence[float]] = None) -> "Material":
        """An orthotropic material (fmMakeOrthotropicMaterial): ``model`` orthotropic-linear or
        orthotropic-stvk, Young's moduli ``E`` = (E1, E2, E3), Poisson ratios ``nu`` = (nu12,
        nu13, nu23), shear moduli ``G`` = (G12, G13, G23) in Pa, axis 1 along ``fibre`` and axis 2
        toward ``sheet`` (default x and y; docs/materials.md, "Anisotropy")."""
        constants = ffi.new("fmOrthotropy*")
        for k in range(3):
            constants.E[k] = float(E[k])
            constants.nu[k] = float(nu[k])
            constants.G[k] = float(G[k])
        self = cls.__new__(cls)
        self._c = ffi.new("fmMaterial*", lib.fmMakeOrthotropicMaterial(_model(model), constants[0]))
        self._finish(fibre, sheet)
        return self

    def _finish(self, fibre, sheet) -> None:
        for name, value in (("fibre", fibre), ("sheet", sheet)):
            if value is not None:
                x, y, z = (float(v) for v in value)
                setattr(self._c, name, (x, y, z))
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
