"""Shared test helpers: finite-difference JVPs for gradient checks."""

import numpy as np


def fd_jvp(f, x, v, h=1e-6):
    """Central finite-difference directional derivative of f at x along v (float64)."""
    x = np.asarray(x, float)
    v = np.asarray(v, float)
    return (np.asarray(f(x + h * v)) - np.asarray(f(x - h * v))) / (2 * h)
