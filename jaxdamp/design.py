"""One design type: a damper shape with its friction coefficient, contacts and load.

`Design` is a pytree. Every leaf is data (a traced array under jit/vmap/grad); nothing in it is a
static argument, so changing any value never recompiles. What does select a compiled program is the
pytree's structure, fixed here in one place:

- `shape.x_d` is None (the triangle's centroid) or a number;
- kn and kt are always carried per contact, shape (3,) for (R1, L1, L2) (`prepared` broadcasts a
  shared scalar), so shared and per-contact stiffness run the same program;
- a batch of designs is a Design whose leaves have a leading batch axis (`jaxdamp.stack_designs`).

Derivatives of any output with respect to a Design are again a Design (d/d theta_L is
`d.shape.theta_l`, per degree; d/d kn is `d.contacts.kn`, per N/mm and per contact).
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ._validate import require_x64
from .geometry import WEDGE_REFUSED, DamperShape, validate_shape
from .params import (Contacts, LoadCase, prepare_inputs, validate_contacts, validate_load,
                     validate_mu)


class Design(NamedTuple):
    """shape (DamperShape), mu (friction coefficient), contacts (kn, kt in N/mm), load (F_D in N,
    q* in mm, r sin beta in mm)."""

    shape: DamperShape
    mu: jnp.ndarray | float
    contacts: Contacts = Contacts()
    load: LoadCase = LoadCase()

    @property
    def size(self) -> int:
        """Number of designs: the leading axis of mu in a batch, 1 for a single design."""
        return int(np.shape(self.mu)[0]) if np.ndim(self.mu) else 1

    def prepared(self) -> "Design":
        """Validated (ValueError naming the parameter and range; float64 required) and converted
        to float arrays with kn, kt per contact: the form every compiled kernel takes."""
        return Design(*prepare_inputs(*self))


def _batch_leaf(name: str, value, n: int | None, per_pad: int | None):
    """One leaf of a batched Design as a float numpy array: a shared scalar, or (n,) per design;
    kn, kt (per_pad = the pad count) also (n, per_pad). n None: the batch's length is not known
    yet (a (per_pad,) stiffness is then not refused)."""
    if value is None:
        raise ValueError(f"{name} is None: give a number, or one per design (n,)")
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be numbers; got {type(value).__name__}") from None
    allowed = "a scalar or one per design (n,)" + (f" or (n, {per_pad}) per pad" if per_pad else "")
    if a.ndim > (2 if per_pad else 1) or (a.ndim == 2 and a.shape[1] != per_pad):
        raise ValueError(f"{name} in a batch must be {allowed}; got shape {a.shape}")
    if per_pad and a.ndim == 1 and a.shape[0] == per_pad and n is not None and n != per_pad:
        raise ValueError(f"{name}: shape ({per_pad},) in a batch of {n}: a batch's stiffness is "
                         f"one per design ({n},) or one per pad per design ({n}, {per_pad}), told "
                         f"apart by shape (jaxdamp.stack_designs broadcasts a shared per-pad "
                         f"Contacts)")
    return a


def check_batch(designs) -> Design:
    """The one input boundary of every batched entry point (`evaluate_designs`, `base_cycles`,
    `batch_jacobian`): a batched Design checked and converted before anything is traced.

    Every leaf is a shared scalar or has the batch's leading axis (n,); kn and kt may also be
    (n, 3), one per pad per design. A per-pad array is told from a batch axis by its shape, never
    by its length: (n,) is one value per design. Scalars are broadcast, no axis is ever cut, and
    every value is checked against `params.RANGES` (ValueError naming the parameter and range;
    TypeError for a leaf that is not numbers; Float64Required in float32). Returns the Design
    with float64 numpy leaves, (n,) each and (n, 3) for kn, kt: the form the batched kernels take.
    The wedge is refused (the batch computes the curved-flat Base-Cycle)."""
    require_x64()
    if not isinstance(designs, Design):
        raise ValueError("designs must be a batched Design (see jaxdamp.stack_designs); got "
                         f"{type(designs).__name__}")
    shape, mu, contacts, load = designs
    for field, value, kind in (("shape", shape, DamperShape), ("contacts", contacts, Contacts),
                               ("load", load, LoadCase)):
        if not isinstance(value, kind):
            raise TypeError(f"designs.{field} must be a {kind.__name__}; got {type(value).__name__}")
    if shape.br2_over_hr is not None:  # refused first, in one line naming the wedge's functions
        raise ValueError(WEDGE_REFUSED)
    names = [(f, v, None) for f, v in zip(DamperShape._fields[:4], shape[:4])]
    if shape.x_d is not None:
        names.append(("x_d", shape.x_d, None))
    names += [("mu", mu, None), ("kn", contacts.kn, 3), ("kt", contacts.kt, 3)]
    names += [(f, v, None) for f, v in zip(LoadCase._fields, load)]
    arrays = {name: _batch_leaf(name, v, None, pads) for name, v, pads in names}
    # The batch length from the leaves that have no per-pad form first: a stiffness of shape (3,)
    # is then refused as per-pad-in-a-batch (by shape), not reported as a third length.
    lengths = {name: a.shape[0] for name, a in arrays.items()
               if a.ndim >= 1 and name not in ("kn", "kt")}
    lengths = lengths or {name: a.shape[0] for name, a in arrays.items() if a.ndim >= 1}
    if not lengths:
        raise ValueError("designs: no leaf has a batch axis; a single design goes to the "
                         "single-design functions (base_cycle, cycle_numbers, "
                         "five_numbers_jacobian), a batch is built by jaxdamp.stack_designs")
    n = next(iter(lengths.values()))
    for name in ("kn", "kt"):  # per-pad shapes need n
        _batch_leaf(name, arrays[name], n, 3)
    lengths = {name: a.shape[0] for name, a in arrays.items() if a.ndim >= 1}
    if len(set(lengths.values())) > 1:
        raise ValueError("designs: the leaves' batch lengths differ (no axis is cut): "
                         + ", ".join(f"{k}={v}" for k, v in lengths.items()))
    if n < 1:
        raise ValueError("designs: a batch needs at least one design")
    rows = {name: np.broadcast_to(a if a.ndim != 1 or name not in ("kn", "kt") else a[:, None],
                                  (n, 3) if name in ("kn", "kt") else (n,)).copy()
            for name, a in arrays.items()}
    out = Design(DamperShape(*(rows[f] for f in DamperShape._fields[:4]), rows.get("x_d")),
                 rows["mu"], Contacts(rows["kn"], rows["kt"]),
                 LoadCase(*(rows[f] for f in LoadCase._fields)))
    validate_shape(out.shape)
    validate_mu(out.mu)
    validate_contacts(out.contacts)
    validate_load(out.load)
    return out


def check_design(shape_or_design, mu=None, contacts=None, load=None, *,
                 wedge_ok: bool = False) -> Design:
    """The one input boundary of every single-design entry point, public: a Design, or (shape,
    mu, contacts, load) (contacts, load None: the defaults), checked before anything is traced
    (types, None, one design's shapes, per-pad lengths, `params.RANGES`; ValueError or TypeError
    in one line naming the parameter, a batch told which functions take one; Float64Required in
    float32) and converted to the form every kernel takes (float arrays, kn and kt per pad).
    wedge_ok: the caller computes a wedge; otherwise a wedge is refused. Many designs:
    `check_batch`."""
    return Design(*prepare_inputs(*as_design(shape_or_design, mu, contacts, load),
                                  wedge_ok=wedge_ok))


def as_design(shape_or_design, mu=None, contacts: Contacts = Contacts(),
              load: LoadCase = LoadCase()) -> Design:
    """A Design from either a Design or the (shape, mu, contacts, load) arguments. contacts or
    load None means the default (`Contacts()`, `LoadCase()`), as everywhere in jaxdamp."""
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    if isinstance(shape_or_design, Design):
        if mu is not None:
            raise ValueError("give either a Design or (shape, mu, contacts, load), not both")
        return shape_or_design
    if mu is None:
        raise ValueError("mu is required: the friction coefficient, in (0, 5]")
    return Design(shape_or_design, mu, contacts, load)


__all__ = ["Design", "check_design", "check_batch", "as_design"]
