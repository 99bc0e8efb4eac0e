"""Input checks that raise a one-line ValueError naming the parameter and its valid range.

Checks run only on concrete values: inside jit/vmap/grad the inputs are tracers and the solver
reports problems through status flags instead.
"""

from __future__ import annotations

from collections import Counter

import jax
import numpy as np
from jax.core import Tracer

X64_MESSAGE = ("jaxdamp needs float64 (in float32 stick/slip decisions flip and results are wrong): "
               "call jaxdamp.enable_x64() or jax.config.update('jax_enable_x64', True) before "
               "computing, or set JAX_ENABLE_X64=1")


class Float64Required(RuntimeError):
    """Raised by the public entry points when JAX runs in float32."""


def require_x64() -> None:
    """A Python-level check, once per public call (costs a config read, no device work)."""
    if not jax.config.jax_enable_x64:
        raise Float64Required(X64_MESSAGE)


def is_concrete(value) -> bool:
    if value is None:
        return False
    leaves = value if isinstance(value, (tuple, list)) else (value,)
    return not any(isinstance(v, Tracer) for v in leaves)


def range_text(lo, hi, lo_open=False, hi_open=False, unit="") -> str:
    """A range as the messages write it: '(0, 5]', '(0, inf) N/mm'."""
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}{f' {unit}' if unit else ''}"


def traced(*trees) -> bool:
    """True where any leaf of the trees is a tracer (inside jit, vmap, grad): the unchecked,
    traceable building blocks check their inputs only where this is False."""
    return any(isinstance(x, Tracer) for x in jax.tree_util.tree_leaves(trees))


def check_range(name, value, lo, hi, *, lo_open=False, hi_open=False, unit=""):
    """Check lo <(=) value <(=) hi elementwise, and finiteness (traced values pass). None, text
    or anything that is not numbers is refused like an out-of-range value: an optional input is
    checked only where it is given."""
    rng = range_text(lo, hi, lo_open, hi_open, unit)
    if value is None or isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be a finite number in {rng}; got {value!r}")
    if not is_concrete(value):
        return
    if np.asarray(value).dtype.kind in "USb":  # text or booleans, even inside a list
        raise ValueError(f"{name} must be a finite number in {rng}; got {value!r}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number in {rng}; got "
                         f"{type(value).__name__}") from None
    finite = np.isfinite(arr)
    bad = ~finite | ((arr <= lo) if lo_open else (arr < lo)) | ((arr >= hi) if hi_open else (arr > hi))
    if not bad.any():
        return
    if not finite.all():
        raise ValueError(f"{name} must be a finite number in {rng}; got {value!r}")
    shown = arr if arr.ndim == 0 else arr[bad][0]
    raise ValueError(f"{name} must be in {rng}; got {float(shown):g}")


def check_scalar(name, value, lo, hi, *, lo_open=False, hi_open=False, unit="") -> float:
    """`check_range` of one number (an array of any other shape is refused in one line): the
    value as a float (a traced value passes, as it is)."""
    check_range(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    if not is_concrete(value):
        return value
    if np.ndim(value) != 0:
        raise ValueError(f"{name} must be one number; got shape {np.shape(value)}")
    return float(value)


def check_positive(name, value, unit=""):
    """value in (0, inf): infinity is not a stiffness, force or length the solver can use."""
    check_range(name, value, 0.0, np.inf, lo_open=True, hi_open=True, unit=unit)


def check_int(name, value, lo):
    """An integer count >= lo (static arguments such as step or iteration counts)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise ValueError(f"{name} must be an integer in [{lo}, inf); got {value!r}")
    return int(value)


# The one table of the checked inputs' ranges, for Python, the CLI and fit (public as
# `params.RANGES`): name -> (lower, upper, lower bound open, upper bound open, unit). Every check of
# these inputs goes through `check_param` (the fast path of `params.prepare_inputs` reads the same
# table), so each message is one line naming the parameter and this range.
INF = np.inf
RANGES = {
    "theta_l": (0.0, 90.0, True, False, "deg"),
    "theta_r": (0.0, 90.0, True, False, "deg"),
    "br_over_hr": (-0.5, 0.5, False, False, ""),
    "bl2_over_hl": (0.0, 1.0, True, False, ""),
    "br2_over_hr": (0.0, 1.0, True, False, ""),
    "x_d": (-1e6, 1e6, False, False, ""),
    "mu": (0.0, 5.0, True, False, ""),
    "kn": (0.0, INF, True, True, "N/mm"),
    "kt": (0.0, INF, True, True, "N/mm"),
    "F_D": (0.0, INF, True, True, "N"),
    "q_star": (0.0, INF, True, True, "mm"),
    "r_sin_beta": (-1e9, 1e9, False, False, "mm"),
    "f0_hz": (0.0, INF, True, True, "Hz"),
    "k_b": (0.0, INF, True, True, "N/mm"),
    "eta": (0.0, 1.0, False, False, ""),
    "r": (0.0, 1e6, True, False, "mrad/mm"),
    "force_n": (0.0, INF, True, True, "N"),
    # Relative platform motion (jaxdamp.motion): the damper's size and the blades' rotation centre.
    "h_l": (0.0, 1e4, True, False, "mm"),
    "h_c": (-1e4, 1e4, False, False, "mm"),
    "motion_component": (-1e6, 1e6, False, False, ""),
}

# The inputs of a platform path beyond in-phase (jaxdamp.motion): commands and functions that
# take no path (the forced response, the band) check none of them.
MOTION_RANGES = frozenset({"h_l", "h_c", "motion_component"})

# How many times each parameter of RANGES has been checked in this process (by `check_param`, or
# accepted by the fast path of `params.prepare_inputs`): the tests read it to show that a command
# checks each input once. Clear it with RANGE_CHECKS.clear().
RANGE_CHECKS: Counter = Counter()


def check_param(name: str, value, label: str | None = None):
    """Check value (concrete; traced values pass) against RANGES[name]: ValueError in one line
    naming label (default name) and the range. Returns value."""
    lo, hi, lo_open, hi_open, unit = RANGES[name]
    RANGE_CHECKS[name] += 1
    check_range(label or name, value, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    return value


def check_values(name: str, value, label: str | None = None, *, max_ndim: int = 1) -> np.ndarray:
    """A concrete scalar or 1-D sequence of numbers (max_ndim) checked against RANGES[name], as a
    float numpy array: None, text, an empty sequence or a deeper array is refused in one line
    naming label (default name), like an out-of-range value."""
    label = label or name
    lo, hi, lo_open, hi_open, unit = RANGES[name]
    rng = range_text(lo, hi, lo_open, hi_open, unit)
    if value is None or isinstance(value, (str, bytes, bool)) or getattr(value, "dtype", None) == bool:
        raise ValueError(f"{label} must be a number or a 1-D sequence of numbers in {rng}; got "
                         f"{value!r}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{label} must be a number or a 1-D sequence of numbers in {rng}; got "
                         f"{type(value).__name__}") from None
    if arr.ndim > max_ndim or arr.size == 0:
        what = "a number" if max_ndim == 0 else "a number or a non-empty 1-D sequence"
        raise ValueError(f"{label} must be {what} in {rng}; got shape {arr.shape}")
    check_param(name, value, label)  # its message shows the value as given
    return arr


__all__ = ["X64_MESSAGE", "Float64Required", "require_x64", "is_concrete", "range_text", "traced", "check_range", "check_scalar",
           "check_positive", "check_int", "RANGES", "MOTION_RANGES", "RANGE_CHECKS", "check_param", "check_values"]
