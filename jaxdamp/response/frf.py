"""Frequency response functions in closed form: for each amplitude A the first-harmonic equation
|D(omega, A)| A = F is quadratic in omega^2 (the package docstring gives D)."""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from .._validate import check_int, check_range, check_values, traced
from ..status import number_repr, status_repr
from .scene import BladeMode, validate_mode
from .stiffness import DamperStiffness, check_damper, stuck_damper

__all__ = ["FRF", "FRF_POINTS", "dynamic_stiffness", "frf", "frf_amplitude_grid",
           "response_amplitude_linear", "linear_frf"]


FRF_POINTS = 200  # amplitudes per FRF


class FRF(NamedTuple):
    """First-harmonic response curve at force F, layered by amplitude (arrays over the A grid).

    At each A the equation |D| A = F has up to two frequencies: the low branch (below the peak
    frequency) and the high branch. Missing branches are masked (has_low / has_high False, value
    0), never NaN. status: the damper curve's RESULTS code (its numbers mean nothing unless valid).
    """

    amplitude_mm: jnp.ndarray
    f_low_hz: jnp.ndarray
    f_high_hz: jnp.ndarray
    has_low: jnp.ndarray
    has_high: jnp.ndarray
    status: jnp.ndarray

    def __repr__(self):
        return (f"FRF(amplitude {number_repr(self.amplitude_mm, 'mm')}, low branch "
                f"{number_repr(self.f_low_hz, 'Hz')}, high branch {number_repr(self.f_high_hz, 'Hz')}, "
                f"status {status_repr(self.status)})")


def dynamic_stiffness(mode: BladeMode, k_of_psi, amplitude_mm):
    """Damper-modified modal stiffness terms at amplitude A: (real part less the inertia, imaginary)."""
    a = jnp.asarray(amplitude_mm, float)
    k_re, k_im = k_of_psi(mode.r * a)
    g = 1e-3 * mode.r ** 2
    return mode.k_b + g * k_re, mode.eta * mode.k_b + g * k_im


def frf(damper: DamperStiffness, mode: BladeMode, force_n, amplitude_mm) -> FRF:
    """Frequencies (Hz) at which the first-harmonic amplitude is A, for each A of amplitude_mm.

    k_b (1 - W) + K_re = +/- sqrt((F/A)^2 - K_im'^2) with W = (omega/omega0)^2 and
    K_im' = eta k_b + 1e-3 r^2 k_Im: W = (k_b + K_re -/+ s) / k_b, s = sqrt(...).
    Unchecked, traceable (jit, vmap, grad): a building block of the compiled response programs; the
    checked path is `response_curves` (or `prepare_scene` for the mode). Concrete inputs are
    checked (the mode, a force > 0 N, amplitudes > 0 mm, 1-D).
    """
    check_damper(damper)
    if not traced(mode, force_n, amplitude_mm):
        validate_mode(mode)
        check_values("force_n", force_n, max_ndim=0)
        check_range("amplitude_mm", amplitude_mm, 0.0, np.inf, lo_open=True, hi_open=True,
                    unit="mm")
        if np.ndim(amplitude_mm) > 1 or np.size(amplitude_mm) == 0:
            raise ValueError(f"amplitude_mm must be one amplitude or a non-empty 1-D grid (mm); "
                             f"got shape {np.shape(amplitude_mm)}")
    a = jnp.asarray(amplitude_mm, float)
    re, im = dynamic_stiffness(mode, damper.k_of_psi, a)
    pos = a > 0
    fa = jnp.asarray(force_n, float) / jnp.where(pos, a, 1.0)
    disc = fa ** 2 - im ** 2
    real = pos & (disc >= 0)
    s = jnp.where(real, jnp.sqrt(jnp.where(real, disc, 1.0)), 0.0)
    w_hi = (re + s) / mode.k_b
    w_lo = (re - s) / mode.k_b
    has_hi = real & (w_hi > 0)
    has_lo = real & (w_lo > 0)
    f_hi = jnp.where(has_hi, mode.f0_hz * jnp.sqrt(jnp.where(has_hi, w_hi, 1.0)), 0.0)
    f_lo = jnp.where(has_lo, mode.f0_hz * jnp.sqrt(jnp.where(has_lo, w_lo, 1.0)), 0.0)
    return FRF(a, f_lo, f_hi, has_lo, has_hi, damper.status)


def frf_amplitude_grid(top_mm, n: int = FRF_POINTS, low: float = 1e-2):
    """Amplitudes (mm) for an FRF up to the peak top_mm: log-spaced from low * top, then dense
    towards the top where the two branches meet (1 - A/top from 1e-2 down to 1e-7).
    Unchecked, traceable (jit, vmap, grad)."""
    top = jnp.asarray(top_mm, float)
    m = n // 2
    base = top * jnp.geomspace(low, 0.99, n - m)
    near = top * (1.0 - jnp.geomspace(1e-2, 1e-7, m))
    return jnp.concatenate([base, near])


def response_amplitude_linear(mode: BladeMode, k_re, k_im, force_n, frequency_hz):
    """|A| = F / |D| for a damper frozen at (k_re, k_im) (a linear spring): the free and stuck
    limits' FRFs as a function of frequency."""
    w = (jnp.asarray(frequency_hz, float) / mode.f0_hz) ** 2
    g = 1e-3 * mode.r ** 2
    re = mode.k_b * (1.0 - w) + g * k_re
    im = mode.eta * mode.k_b + g * k_im
    return force_n / jnp.sqrt(re ** 2 + im ** 2)


def linear_frf(mode: BladeMode, k_re, force_n, n: int = FRF_POINTS) -> FRF:
    """The FRF of the blade with a damper frozen as a real spring k_re (N mm/mrad; 0: free, k_Re,fs:
    stuck) across its own resonance: amplitudes up to its own peak F / (eta k_b), at
    f0 sqrt(1 + 1e-3 r^2 k_re / k_b). Without structural damping (eta = 0) the peak is unbounded:
    the grid then stops at 1e3 F / k_b. Unchecked, traceable (jit, vmap, grad), as `frf`; concrete
    inputs are checked (the mode, k_re >= 0, a force > 0 N, n >= 2 points)."""
    if not traced(mode, k_re, force_n):
        validate_mode(mode)
        check_range("k_re", k_re, 0.0, np.inf, hi_open=True, unit="N mm/mrad")
        check_values("force_n", force_n, max_ndim=0)
        check_int("n", n, 2)
    damped = mode.eta * mode.k_b > 0
    force = jnp.asarray(force_n, float)
    top = jnp.where(damped, force / jnp.where(damped, mode.eta * mode.k_b, 1.0),
                    1e3 * force / mode.k_b)
    return frf(stuck_damper(k_re), mode, force, frf_amplitude_grid(top, n))

