"""Input checks that raise a one-line ValueError naming the parameter and its valid range.

Checks run only on concrete values: inside jit/vmap/grad the inputs are tracers and the solver
reports problems through status flags instead.
"""

from __future__ import annotations

import numpy as np
from jax.core import Tracer


def is_concrete(value) -> bool:
    if value is None:
        return False
    leaves = value if isinstance(value, (tuple, list)) else (value,)
    return not any(isinstance(v, Tracer) for v in leaves)


def check_range(name, value, lo, hi, *, lo_open=False, hi_open=False, unit=""):
    """Check lo <(=) value <(=) hi elementwise, and finiteness."""
    if not is_concrete(value):
        return
    arr = np.asarray(value, dtype=float)
    left = "(" if lo_open else "["
    right = ")" if hi_open else "]"
    suffix = f" {unit}" if unit else ""
    rng = f"{left}{lo:g}, {hi:g}{right}{suffix}"
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be a finite number in {rng}; got {value!r}")
    bad_lo = arr <= lo if lo_open else arr < lo
    bad_hi = arr >= hi if hi_open else arr > hi
    if np.any(bad_lo | bad_hi):
        shown = arr if arr.ndim == 0 else arr[bad_lo | bad_hi][0]
        raise ValueError(f"{name} must be in {rng}; got {float(shown):g}")


def check_positive(name, value, unit=""):
    check_range(name, value, 0.0, np.inf, lo_open=True, hi_open=False, unit=unit)


def check_int(name, value, lo):
    """An integer count >= lo (static arguments such as step or iteration counts)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise ValueError(f"{name} must be an integer in [{lo}, inf); got {value!r}")
    return int(value)
