"""Closed-form first-harmonic integrals of a piecewise-linear moment loop (no sampling).

With psi = psi_c + psi_a cos(tau) and x = cos(tau), a half-cycle that starts at an extreme and
travels cum (mm) is at x = branch (1 - cum / a_dv), a_dv = psi_a in mm of travel: branch = +1 for
the forward half (tau in [0, pi]), -1 for the backward one (tau in [pi, 2 pi]). On a segment where
M = alpha + beta x, int M cos(tau) dtau = alpha [sin tau] + beta/2 [tau + sin tau cos tau] and
int M sin(tau) dtau = -int M dx. Used by the Base-Cycle (`harmonics`) and by the cycles at a
prescribed amplitude (`amplitude`); the sign convention is `conventions.stiffness_from_fourier`'s.
"""

from __future__ import annotations

import jax.numpy as jnp


def unit_circle(x):
    """tau = arccos(x) and sin(tau) >= 0, with gradients guarded at |x| = 1 (double where).

    Breakpoints within 1e-12 of an extreme are put on it: sqrt(1 - x^2) would turn their last-bit
    rounding into ~1e-8 changes of sin(tau), while moving a breakpoint of the continuous M(tau) by
    ~1e-6 rad changes the integrals by ~1e-12 relative."""
    inside = jnp.abs(x) < 1.0 - 1e-12
    xs = jnp.where(inside, x, 0.0)
    tau = jnp.where(inside, jnp.arccos(xs), jnp.where(x > 0, 0.0, jnp.pi))
    sin = jnp.where(inside, jnp.sqrt(jnp.where(inside, 1.0 - xs * xs, 1.0)), 0.0)
    return tau, sin


def half_fourier(dv, M0, dM, a_dv, branch, *, ends_at_extreme=False):
    """(int M cos tau dtau, int M sin tau dtau) over one half of a piecewise-linear loop.

    dv: segment lengths (mm of travel), M0: moment at each segment start (N mm), dM: its rate
    (N mm per mm), a_dv: the amplitude in mm of travel, branch: +1 forward, -1 backward.
    ends_at_extreme: the last segment ends exactly at the far extreme (a gross-slip stretch that
    completes the half), so rounding of the cumulative travel cannot leave it short."""
    cum = jnp.cumsum(dv) - dv
    x1 = jnp.clip(branch * (1.0 - cum / a_dv), -1.0, 1.0)
    x2 = jnp.clip(branch * (1.0 - (cum + dv) / a_dv), -1.0, 1.0)
    if ends_at_extreme:
        x2 = x2.at[-1].set(-branch * 1.0)
    beta = -branch * a_dv * dM  # dM/dx along the segment
    alpha = M0 - beta * x1
    t1, s1 = unit_circle(x1)
    t2, s2 = unit_circle(x2)
    if branch < 0:
        t1, s1, t2, s2 = 2 * jnp.pi - t1, -s1, 2 * jnp.pi - t2, -s2
    f_cos = alpha * (s2 - s1) + 0.5 * beta * ((t2 + s2 * x2) - (t1 + s1 * x1))
    f_sin = alpha * (x1 - x2) + 0.5 * beta * (x1 * x1 - x2 * x2)
    return jnp.sum(f_cos), jnp.sum(f_sin)


__all__ = ["unit_circle", "half_fourier"]
