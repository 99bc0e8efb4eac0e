"""Shared test helpers (equinox style): pytree comparison and finite-difference JVPs."""

import jax
import numpy as np


def tree_allclose(a, b, rtol=1e-12, atol=0.0):
    """True when two pytrees have the same structure and all leaves agree."""
    la, ta = jax.tree_util.tree_flatten(a)
    lb, tb = jax.tree_util.tree_flatten(b)
    if ta != tb:
        return False
    return all(np.allclose(np.asarray(x), np.asarray(y), rtol=rtol, atol=atol) for x, y in zip(la, lb))


def fd_jvp(f, x, v, h=1e-6):
    """Central finite-difference directional derivative of f at x along v (float64)."""
    x = np.asarray(x, float)
    v = np.asarray(v, float)
    return (np.asarray(f(x + h * v)) - np.asarray(f(x - h * v))) / (2 * h)
