"""Contact and load parameters as pytrees."""

from __future__ import annotations

from typing import NamedTuple

import math

import jax
import jax.numpy as jnp
import numpy as np

# The one table of the inputs' ranges and its check live in _validate (below geometry, which checks
# the shape with them); they are public here.
from ._validate import RANGE_CHECKS, RANGES, check_param, require_x64
from .geometry import DamperShape, validate_shape

# The paper's reference contact pair: the least-squares fit of `jaxdamp calibrate` to Tables B3.1
# and B4.1 (every number within 0.7 %, docs/paper_comparison.md). MODEL.md's first quick fit was
# kn = 17.9 N/um, kt = 3.6 N/um.
REFERENCE_KN = 20246.3  # N/mm
REFERENCE_KT = 3492.1  # N/mm


# The validated stiffness range (docs/model.md, tests/test_conditioning.py): kn/F_D and kt/F_D per
# mm of travel, and kt/kn. Above it the linear solves lose their digits, so a cycle there is
# `ill_conditioned` whatever its residuals say. Below it the numbers stay exact but psi_BC exceeds
# the small-rotation limit (SMALL_ROTATION_MRAD), which is what warns there.
VALIDATED_STIFFNESS_OVER_FD_PER_MM = (0.1, 1e6)
VALIDATED_KT_OVER_KN = (1e-4, 1e4)


def above_validated_range(kn_over_fd, kt_over_fd):
    """True (traceable) where a contact's stiffness over F_D exceeds the validated range, or its
    kt/kn ratio leaves it (arguments per mm, any shape; a hair of slack keeps the bounds inside)."""
    hi = VALIDATED_STIFFNESS_OVER_FD_PER_MM[1] * (1.0 + 1e-9)
    lo_ratio, hi_ratio = VALIDATED_KT_OVER_KN[0] * (1.0 - 1e-9), VALIDATED_KT_OVER_KN[1] * (1.0 + 1e-9)
    ratio = kt_over_fd / kn_over_fd
    return jnp.any((kn_over_fd > hi) | (kt_over_fd > hi) | (ratio < lo_ratio) | (ratio > hi_ratio))


def _limit(v: float) -> str:
    """A validated-range limit as the docs write it: a power of ten as 1e-4, 1e6; else %g."""
    e = math.log10(v)
    return f"1e{round(e)}" if abs(e - round(e)) < 1e-12 else f"{v:g}"


def _where(values: list[tuple[str, str]], unit: str = "") -> str:
    """'5e-05' when all three contacts share the (formatted) value, '5e-05 at R1, L1' when those
    contacts share it, else '5e-05 at R1, 6e-05 at L2' (unit after each value)."""
    if len({v for _, v in values}) == 1:
        names = [n for n, _ in values]
        return values[0][1] + unit + ("" if len(names) == 3 else " at " + ", ".join(names))
    return ", ".join(f"{v}{unit} at {n}" for n, v in values)


def validated_range_violations(contacts: "Contacts", load: "LoadCase") -> list[str]:
    """The limits of the validated stiffness range that the contacts leave for this load, one line
    of text each (host-side, numpy; for checked, concrete inputs): kn/F_D or kt/F_D above
    VALIDATED_STIFFNESS_OVER_FD_PER_MM[1] per mm, kt/kn outside VALIDATED_KT_OVER_KN. These are
    exactly the conditions of `above_validated_range` (same slack), the ones that make every cycle
    `ill_conditioned`; an empty list where the inputs are inside (then an ill_conditioned status
    comes from the solves' residuals). Below the range nothing is listed: the numbers stay exact
    there (the small-rotation limit warns instead). Contacts named R1, L1, L2 where they differ."""
    check_contacts_and_load(contacts, load)
    validate_contacts(contacts)
    validate_load(load)
    names = ("R1", "L1", "L2")
    fd = float(np.asarray(load.F_D, float))
    kn = np.broadcast_to(np.asarray(contacts.kn, float), (3,)) / fd
    kt = np.broadcast_to(np.asarray(contacts.kt, float), (3,)) / fd
    hi = VALIDATED_STIFFNESS_OVER_FD_PER_MM[1]
    lo_r, hi_r = VALIDATED_KT_OVER_KN
    slack = 1e-9
    out = []
    for label, k in (("kn/F_D", kn), ("kt/F_D", kt)):
        bad = [(n, f"{v:.3g}") for n, v in zip(names, k) if v > hi * (1.0 + slack)]
        if bad:
            out.append(f"{label} = {_where(bad, ' per mm')} above the validated range (at most "
                       f"{_limit(hi)} per mm)")
    ratio = kt / kn
    rng = f"[{_limit(lo_r)}, {_limit(hi_r)}]"
    for side, test in (("below", lambda r: r < lo_r * (1.0 - slack)),
                       ("above", lambda r: r > hi_r * (1.0 + slack))):
        bad = [(n, f"{v:.3g}") for n, v in zip(names, ratio) if test(v)]
        if bad:
            out.append(f"kt/kn = {_where(bad)} {side} the validated range {rng}")
    return out


class Contacts(NamedTuple):
    """Jenkins contact stiffness in N/mm: scalars (shared) or arrays ordered (R1, L1, L2)."""

    kn: jnp.ndarray | float = REFERENCE_KN
    kt: jnp.ndarray | float = REFERENCE_KT

    def per_contact(self) -> tuple[jnp.ndarray, jnp.ndarray]:
        """(kn, kt) as arrays of shape (3,): a scalar is shared by R1, L1 and L2."""
        return _three(self.kn), _three(self.kt)


def _three(k) -> jnp.ndarray:
    k = jnp.asarray(k, dtype=float)
    return jnp.broadcast_to(k, (3,)) if k.ndim == 0 else k


class LoadCase(NamedTuple):
    """Centrifugal force F_D (N), virtual blade pitch q* (mm), and the pitch term r*sin(beta) (mm)."""

    F_D: jnp.ndarray | float = 1000.0
    q_star: jnp.ndarray | float = 100.0
    r_sin_beta: jnp.ndarray | float = 0.0


def validate_mu(mu, name="mu"):
    """name: how the error names the coefficient (mu, mu_max, mu_set, ...)."""
    return check_param("mu", mu, name)


def validate_contacts(contacts: Contacts) -> Contacts:
    check_param("kn", contacts.kn)
    check_param("kt", contacts.kt)
    return contacts


def validate_load(load: LoadCase) -> LoadCase:
    check_param("F_D", load.F_D)
    check_param("q_star", load.q_star)
    check_param("r_sin_beta", load.r_sin_beta)
    return load


# The scalar inputs in fast_ok's order (their ranges from RANGES).
_FAST_NAMES = ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "mu", "F_D", "q_star", "r_sin_beta")


def fast_ok(shape, mu, contacts: Contacts, load: LoadCase) -> bool:
    """True when every input is a plain Python number (kn, kt may also be numpy (3,) arrays) inside
    its range: plain comparisons, no array work. Anything else goes through the full checks."""
    vals = (shape.theta_l, shape.theta_r, shape.br_over_hr, shape.bl2_over_hl, mu, *load)
    if shape.x_d is not None or shape.br2_over_hr is not None:  # a wedge: the full checks refuse
        return False  # it where the caller computes the curved-flat damper only
    for v, name in zip(vals, _FAST_NAMES):
        lo, hi, lo_open, hi_open, _ = RANGES[name]
        if type(v) not in (float, int) or not ((v > lo) if lo_open else (v >= lo)) \
                or not ((v < hi) if hi_open else (v <= hi)) or v == math.inf:
            return False
    for k in contacts:
        if type(k) in (float, int):
            if not 0.0 < k < math.inf:
                return False
        elif not (isinstance(k, np.ndarray) and k.shape == (3,) and bool(np.all(k > 0.0))
                  and bool(np.all(np.isfinite(k)))):
            return False
    RANGE_CHECKS.update(_FAST_NAMES + ("kn", "kt"))
    return True


_PART_TYPES = {"shape": DamperShape, "contacts": Contacts, "load": LoadCase}

# What a single-design function says to a batch: the batched functions and the transform.
ONE_DESIGN_HINT = ("this function takes one design; for many use jaxdamp.evaluate_designs, "
                   "base_cycles or batch_jacobian (a batch from jaxdamp.stack_designs), or jax.vmap "
                   "over the *_kernel form")


def check_one_value(name: str, v, n_pads: int | None = None) -> None:
    """One input of one design: a real number, or (n_pads,) where n_pads is given (per pad);
    tracers pass. ValueError / TypeError in one line naming it."""
    if isinstance(v, jax.core.Tracer):
        return
    if v is None:
        raise ValueError(f"{name} is None: give a number in its range (params.RANGES)")
    if isinstance(v, (str, bytes, bool)) or getattr(v, "dtype", None) == bool:
        raise TypeError(f"{name} must be a real number; got {v!r}")
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real number; got {type(v).__name__}") from None
    if a.ndim > int(n_pads is not None) or (a.ndim == 1 and a.shape[0] != n_pads):
        pads = f", or one per pad ({n_pads} for this damper)" if n_pads else ""
        raise ValueError(f"{name}: one value{pads}; got shape {a.shape}: {ONE_DESIGN_HINT}")


def check_types(**parts) -> None:
    """shape=, contacts=, load= (any of them) are a DamperShape, Contacts and LoadCase: a
    TypeError in one line naming the argument, before any field is read."""
    for name, value in parts.items():
        kind = _PART_TYPES[name]
        if not isinstance(value, kind):
            raise TypeError(f"{name} must be a jaxdamp.{kind.__name__}; got {type(value).__name__}")


def check_one_shape(shape) -> None:
    """A DamperShape of one design: every field one real number (x_d and br2_over_hr may be
    None). Ranges are `validate_shape`'s."""
    check_types(shape=shape)
    for f, v in zip(DamperShape._fields, shape):
        if not (f in ("x_d", "br2_over_hr") and v is None):
            check_one_value(f, v, None)


def check_shape_and_mu(shape, mu, name: str = "mu", n_pads: int | None = None) -> None:
    """One curved-flat damper's shape and friction coefficient (named `name`; one number, or one
    per pad where n_pads is given), types, shapes and ranges: the statics' inputs."""
    check_one_shape(shape)
    check_one_value(name, mu, n_pads)
    validate_shape(shape)
    validate_mu(mu, name)


def check_one_design(shape, mu, contacts, load, *, mu_per_pad: bool = True) -> None:
    """The types, None and shapes of one design's inputs (concrete leaves; tracers pass): a
    DamperShape, Contacts and LoadCase; every shape and load field one number (x_d and
    br2_over_hr may be None); mu one number or, with mu_per_pad, one per pad; kn, kt one number
    or one per pad. TypeError or ValueError in one line naming the parameter; a batch gets
    ONE_DESIGN_HINT."""
    check_one_shape(shape)
    n_pads = 3 if shape.br2_over_hr is None else 4
    check_one_value("mu", mu, n_pads if mu_per_pad else None)
    check_contacts_and_load(contacts, load, n_pads)


def check_contacts_and_load(contacts, load, n_pads: int = 3) -> None:
    """A Contacts of one value or one per pad (n_pads) each, a LoadCase of one number per field:
    `check_one_design`'s part for the functions that take no shape or mu (a nominal design)."""
    check_types(contacts=contacts, load=load)
    check_one_value("kn", contacts.kn, n_pads)
    check_one_value("kt", contacts.kt, n_pads)
    for f, v in zip(LoadCase._fields, load):
        check_one_value(f, v, None)


def prepare_inputs(shape, mu, contacts: Contacts, load: LoadCase, *, wedge_ok: bool = False):
    """Validate a solver's inputs (ValueError naming the parameter and its range; Float64Required
    in float32) and convert them to float arrays with kn, kt per contact, so that every entry point
    compiles the same program. Plain numbers take a one-comparison fast path. wedge_ok: the
    solver computes a wedge (`DamperShape.br2_over_hr`); the others refuse one."""
    require_x64()
    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    check_types(shape=shape, contacts=contacts, load=load)  # before fast_ok reads any field
    wedge = shape.br2_over_hr is not None
    if wedge or not fast_ok(shape, mu, contacts, load):
        check_one_design(shape, mu, contacts, load)
        validate_shape(shape, wedge_ok=wedge_ok)
        validate_mu(mu)
        validate_contacts(contacts)
        validate_load(load)
    n_pads = 4 if wedge else 3
    for name, k in zip(("kn", "kt"), contacts):
        if np.ndim(k) not in (0,) and np.shape(k) != (n_pads,):
            raise ValueError(f"{name}: one value, or one per pad ({n_pads} for this damper); "
                             f"got shape {np.shape(k)}")
    shape = DamperShape(*(None if v is None else _float_array(v) for v in shape))
    # A shared stiffness runs as equal ones per pad: one compiled program for both forms.
    contacts = Contacts(*(_per_contact(_float_array(k), n_pads) for k in contacts))
    load = LoadCase(*(_float_array(v) for v in load))
    return shape, _float_array(mu), contacts, load


def _float_array(v):
    """Concrete host values stay numpy arrays (jit takes them without a per-leaf device dispatch,
    which dominated a single call's Python overhead); JAX arrays and tracers stay JAX's."""
    if isinstance(v, float):
        return np.float64(v)
    if isinstance(v, jax.Array):
        return v if v.dtype == jnp.result_type(float) else jnp.asarray(v, float)
    return np.asarray(v, dtype=float)


def _per_contact(k, n_pads: int = 3):
    if np.ndim(k) == 0:
        return (np.full(n_pads, k) if isinstance(k, (np.ndarray, np.generic))
                else jnp.broadcast_to(k, (n_pads,)))
    return k


__all__ = ["REFERENCE_KN", "REFERENCE_KT", "VALIDATED_STIFFNESS_OVER_FD_PER_MM",
           "VALIDATED_KT_OVER_KN", "above_validated_range", "validated_range_violations", "Contacts",
           "LoadCase", "RANGES", "RANGE_CHECKS", "check_param", "validate_mu", "validate_contacts",
           "validate_load", "fast_ok", "ONE_DESIGN_HINT", "check_one_value", "check_types",
           "check_one_shape", "check_shape_and_mu", "check_one_design", "check_contacts_and_load", "prepare_inputs"]
