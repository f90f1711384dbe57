"""Filling femto's definition structs from Python keywords (snake_case names of the fields)."""
import math

import numpy as np

from ._femto import ffi, lib

# Enum fields accept these names (or the C constant's integer value).
ENUMS = {
    "integrator": {"explicit": lib.fm_explicit, "implicit": lib.fm_implicit},
    "implicitSolver": {"newton": lib.fm_solverNewton, "vbd": lib.fm_solverVbd},
    "friction@fmFloorDef": {"stick": lib.fm_floorStick, "coulomb": lib.fm_floorCoulomb},
    "massMode": {"density": lib.fm_massFromDensity, "particle": lib.fm_massPerParticle},
    "shape": {"plane": lib.fm_shapePlane, "sphere": lib.fm_shapeSphere, "box": lib.fm_shapeBox,
              "capsule": lib.fm_shapeCapsule, "mesh": lib.fm_shapeMesh},
}


def camel(name):
    head, *rest = name.split("_")
    return head + "".join(word[:1].upper() + word[1:] for word in rest)


def vec3(value, what="a 3-vector"):
    """An fmVec3 from any 3 numbers (a tuple, a list, a numpy array)."""
    x, y, z = (float(v) for v in _three(value, what))
    return ffi.new("fmVec3*", {"x": x, "y": y, "z": z})[0]


def _three(value, what):
    try:
        items = list(value)
    except TypeError:
        raise TypeError("%s: expected 3 numbers, got %r" % (what, value)) from None
    if len(items) != 3:
        raise ValueError("%s: expected 3 numbers, got %d" % (what, len(items)))
    return items


def tuple3(v):
    return (v.x, v.y, v.z)


def _enum_value(field, struct_type, value):
    if isinstance(value, str):
        table = ENUMS.get("%s@%s" % (field, struct_type)) or ENUMS.get(field)
        if table is None or value not in table:
            names = ", ".join(sorted(table)) if table else "an integer"
            raise ValueError("%s: unknown %r: expected one of %s" % (field, value, names))
        return table[value]
    return int(value)


def fill(struct, values, struct_type):
    """Set struct's fields (a cdata struct) from a dict of snake_case names; nested structs
    take dicts; fmVec3 fields take 3 numbers; enum fields take their names."""
    fields = dict(ffi.typeof(struct).fields)
    struct_type = struct_type.replace("struct ", "")
    for key, value in values.items():
        field = camel(key)
        if field not in fields or field == "internalValue":
            known = ", ".join(sorted(_snake(f) for f in fields if f != "internalValue"))
            raise TypeError("%s has no field %r (known: %s)" % (struct_type, key, known))
        kind = fields[field].type
        if kind.kind == "struct" and kind.cname.endswith("fmVec3"):
            setattr(struct, field, vec3(value, key))
        elif kind.kind == "struct":
            if not isinstance(value, dict):
                raise TypeError("%s: expected a dict of %s's fields" % (key, kind.cname))
            fill(getattr(struct, field), value, kind.cname)
        elif kind.kind == "enum":
            setattr(struct, field, _enum_value(field, struct_type, value))
        elif kind.kind == "primitive":
            setattr(struct, field, _primitive(kind.cname, key, value))
        else:
            raise TypeError("%s.%s is set through its own argument" % (struct_type, key))


def _primitive(cname, key, value):
    if cname in ("_Bool", "bool"):
        return bool(value)
    if cname in ("double", "float"):
        return float(value)
    if isinstance(value, float) and not value.is_integer():
        raise TypeError("%s: expected an integer, got %r" % (key, value))
    return int(value)


def _snake(name):
    return "".join("_" + c.lower() if c.isupper() else c for c in name)


def as_struct_dict(struct):
    """A dict of a result struct's fields (snake_case), fmVec3 as tuples."""
    out = {}
    for name, field in ffi.typeof(struct).fields:
        value = getattr(struct, name)
        if field.type.kind == "struct" and field.type.cname.endswith("fmVec3"):
            value = tuple3(value)
        elif field.type.kind == "struct":
            value = as_struct_dict(value)
        out[_snake(name)] = value
    return out


def float_rows(array, rows, what, dtype=np.float64):
    """array as a C-contiguous (rows, 3) array of dtype, checked finite (a copy if needed)."""
    a = np.ascontiguousarray(array, dtype=dtype)
    if a.shape != (rows, 3):
        raise ValueError("%s: expected shape (%d, 3), got %s" % (what, rows, a.shape))
    if not np.all(np.isfinite(a)):
        raise ValueError("%s: expected finite numbers" % what)
    return a


def out_rows(out, rows, what, columns=3):
    """The caller's output array, checked: C-contiguous float64 or float32 of (rows, columns)."""
    if out is None:
        return np.empty((rows, columns), dtype=np.float64)
    if not isinstance(out, np.ndarray) or out.dtype not in (np.float64, np.float32):
        raise TypeError("%s: expected a numpy float64 or float32 array" % what)
    if out.shape != (rows, columns) or not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError("%s: expected a writeable C-contiguous array of shape (%d, %d), got %s"
                         % (what, rows, columns, out.shape))
    return out


def finite(value, what):
    value = float(value)
    if not math.isfinite(value):
        raise ValueError("%s: expected a finite number, got %r" % (what, value))
    return value


def int_array(values, what):
    """values as a C-contiguous int32 array: integers only (a float array is a TypeError, not
    truncated), each within int32."""
    a = np.asarray(values)
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise TypeError("%s: expected integers, got %s" % (what, a.dtype))
    if a.size and (a.min() < np.iinfo(np.int32).min or a.max() > np.iinfo(np.int32).max):
        raise ValueError("%s: an index beyond 32 bits" % what)
    return np.ascontiguousarray(a, dtype=np.int32)
