"""The modal file: one mode family of a tuned bladed disk per nodal diameter, as NPZ or JSON
(docs/blade.md), read into a checked `jaxdamp.ModalFamily` and written back.

Fields (one row per nodal diameter; the names of `ModalFamily`): n_blades, nodal_diameter,
frequency_hz, loss_factor, modal_force, response_displacement, left_platform, right_platform,
optionally platform_residual (the platforms' residual flexibility, (n, 6, 6)), name and
unit_system. Complex fields are complex arrays in NPZ, and {"re": [...],
"im": [...]} objects in JSON (a real list is taken as real). unit_system says in which consistent
units the modes are mass-normalised: "mm-N-s-t" (the default: mm, N, s, tonne) or "SI" (m, N, s,
kg), converted here to mm-N-s-t: lengths per unit modal coordinate times sqrt(1000), rotations
divided by sqrt(1000), modal forces times sqrt(1000) (a unit modal coordinate is sqrt(1000) times
larger in SI); the residual flexibility's entries by s_i s_j with s = (sqrt(1000), sqrt(1000),
1 / sqrt(1000)) per platform (m/N -> mm/N, rad/(N m) -> rad/(N mm)). Rotations are in rad in
both.

Anything else is refused with one line naming the field (ValueError).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .paper.files import atomic_file
from .response.modes import FAMILY_FIELDS, OPTIONAL_FIELDS, ModalFamily, validate_family

__all__ = ["UNIT_SYSTEMS", "EXAMPLE", "EXAMPLE_PATH", "load_modal_family", "save_modal_family",
           "family_from_mapping"]

# The example file shipped with the package (a lumped 24-blade disk's first bending family,
# `jaxdamp.baselines.lumped_disk`): `load_modal_family("example")`, `--modes example`.
EXAMPLE = "example"
EXAMPLE_PATH = Path(__file__).resolve().parent / "data" / "example_disk_modes.npz"

UNIT_SYSTEMS = ("mm-N-s-t", "SI")
_ROOT = np.sqrt(1000.0)
# Per field, how a unit modal coordinate's change from SI to mm-N-s-t scales it.
_SI_SCALE = {"modal_force": _ROOT, "response_displacement": _ROOT}
_SI_PLATFORM = np.array([_ROOT, _ROOT, 1.0 / _ROOT])  # (u, v lengths; theta a rotation)


def family_from_mapping(data) -> ModalFamily:
    """A checked ModalFamily from a mapping of the file's fields (as `np.load` or `json.load` give
    them): unit conversion, then `validate_family`."""
    keys = set(data.keys())
    known = set(FAMILY_FIELDS) | set(OPTIONAL_FIELDS) | {"n_blades", "name", "unit_system"}
    missing = [k for k in ["n_blades", *FAMILY_FIELDS] if k not in keys]
    if missing:
        raise ValueError(f"modes file must have the field {missing[0]} (fields: n_blades, "
                         f"{', '.join(FAMILY_FIELDS)}; docs/blade.md)")
    extra = sorted(keys - known)
    if extra:
        raise ValueError(f"modes file has an unknown field {extra[0]!r} (fields: n_blades, "
                         f"{', '.join(FAMILY_FIELDS)}, {', '.join(OPTIONAL_FIELDS)}, name, "
                         f"unit_system)")
    units = str(np.asarray(data["unit_system"])) if "unit_system" in keys else UNIT_SYSTEMS[0]
    if units not in UNIT_SYSTEMS:
        raise ValueError(f"unit_system must be one of {', '.join(UNIT_SYSTEMS)}; got {units!r}")
    n_blades = np.asarray(data["n_blades"])
    if n_blades.shape != () or n_blades.dtype.kind not in "iu" and not (
            n_blades.dtype.kind == "f" and float(n_blades) == round(float(n_blades))):
        raise ValueError(f"n_blades must be an integer in [2, inf); got {data['n_blades']!r}")
    fields = {name: _array(name, data[name]) for name in [*FAMILY_FIELDS, *OPTIONAL_FIELDS]
              if name in keys}
    if units == "SI":
        for name, scale in _SI_SCALE.items():
            fields[name] = fields[name] * scale
        for name in ("left_platform", "right_platform"):
            fields[name] = fields[name] * _SI_PLATFORM
        if "platform_residual" in fields:
            both = np.tile(_SI_PLATFORM, 2)
            fields["platform_residual"] = fields["platform_residual"] * np.outer(both, both)
    name = str(np.asarray(data["name"])) if "name" in keys else ""
    return validate_family(ModalFamily(int(n_blades), name=name, **fields))


def _array(name, value):
    if isinstance(value, dict):
        if set(value) != {"re", "im"}:
            raise ValueError(f"{name} must be a list, or an object with re and im lists; got keys "
                             f"{sorted(value)}")
        try:
            return np.asarray(value["re"], float) + 1j * np.asarray(value["im"], float)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must hold numbers in its re and im lists") from None
    try:
        return np.asarray(value, complex if np.iscomplexobj(np.asarray(value)) else float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of numbers; got {value!r}"[:200]) from None


def load_modal_family(path) -> ModalFamily:
    """Read a modal file (.npz or .json, module docstring) into a checked ModalFamily; "example"
    reads the example disk shipped with the package (EXAMPLE_PATH). ValueError (one line) for a
    missing file, an unknown suffix or a field it cannot use."""
    path = EXAMPLE_PATH if str(path) == EXAMPLE else Path(path)
    if not path.is_file():
        raise ValueError(f"modes must be an existing .npz or .json file; got {str(path)!r}")
    if path.suffix == ".npz":
        try:
            with np.load(path, allow_pickle=False) as data:
                return family_from_mapping({k: data[k] for k in data.files})
        except (OSError, EOFError) as e:
            raise ValueError(f"modes file {str(path)!r} is not a readable .npz ({e})") from None
    if path.suffix == ".json":
        try:
            data = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as e:
            raise ValueError(f"modes file {str(path)!r} is not readable JSON ({e})") from None
        if not isinstance(data, dict):
            raise ValueError("modes file must hold a JSON object with the fields of docs/blade.md")
        return family_from_mapping(data)
    raise ValueError(f"modes must be a .npz or .json file; got suffix {path.suffix!r}")


def save_modal_family(family: ModalFamily, path) -> Path:
    """Write a ModalFamily as .npz or .json (mm-N-s-t units), atomically."""
    family = validate_family(family)
    path = Path(path)
    fields = {name: np.asarray(getattr(family, name)) for name in FAMILY_FIELDS}
    if np.any(family.platform_residual != 0):
        fields["platform_residual"] = np.asarray(family.platform_residual)
    if path.suffix == ".npz":
        with atomic_file(path, "wb") as f:
            np.savez(f, n_blades=np.int64(family.n_blades), name=np.str_(family.name),
                     unit_system=np.str_(UNIT_SYSTEMS[0]), **fields)
    elif path.suffix == ".json":
        def plain(v):
            v = np.asarray(v)
            if np.iscomplexobj(v):
                return {"re": v.real.tolist(), "im": v.imag.tolist()}
            return v.tolist()
        doc = {"n_blades": family.n_blades, "name": family.name, "unit_system": UNIT_SYSTEMS[0],
               **{k: plain(v) for k, v in fields.items()}}
        with atomic_file(path, "w") as f:
            json.dump(doc, f, indent=1)
    else:
        raise ValueError(f"path must end in .npz or .json; got {str(path)!r}")
    return path
