"""The platform paths a tract engine run follows: a straight `Line` and an `Ellipse`.

A path gives the engine its basis functions phi(p) (forces within a tract are affine in them),
the direction of motion at p, and the first point after p0 where an affine function of phi falls
through zero, in closed form: linear on a line, a root of c + alpha cos tau + beta sin tau on an
ellipse. Both are pytrees (NamedTuple) so that jit and vmap see through them.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp

from .linalg import combine
from .tract import LIMIT_TOL, NO_EVENT

TAU_TOL = 1e-12  # rad: an event nearer than this to the tract's start is the start itself
# rad ahead of a tract's start where a state set's second-order behaviour is checked on an
# ellipse (`engine.choose`)
LOOKAHEAD = 1e-4


class Line(NamedTuple):
    """A straight path: p is mm of travel s along the basis direction (B = 1), from 0."""

    def basis(self, p):
        return p[None]

    def step(self, p0, dp):
        """phi(p0 + dp) - phi(p0): dp itself (no rounding of p0 + dp - p0)."""
        return dp[None]

    def heading(self, pads, p):
        return jnp.ones(1) / _pad_speed(pads, jnp.ones(1))

    def ahead(self, p):
        return None

    def first_descent(self, f0, A, p0, rate_tol):
        """Travel to where f0 + A (s - s0) falls through zero (f0 > 0); A (..., B). A rate within
        rate_tol of zero is rounding of a constant, not a fall."""
        rate = A[..., 0]
        falls = (rate < -rate_tol) & (f0 > LIMIT_TOL)
        return jnp.where(falls, f0 / jnp.where(falls, -rate, 1.0), NO_EVENT)

    def reversal(self, A, p0):
        return jnp.full(A.shape[:-1], NO_EVENT)


class Ellipse(NamedTuple):
    """X(tau) = s_a (X_r cos tau - X_i sin tau): p is tau (rad), basis s_a (cos tau, -sin tau)."""

    s_a: jnp.ndarray  # mm of s: the path's size

    def basis(self, p):
        return self.s_a * jnp.stack([jnp.cos(p), -jnp.sin(p)])

    def heading(self, pads, p):
        """Basis weights of the direction of motion at tau, at unit pad speed (at a turning point
        of a degenerate ellipse, the direction just after it)."""
        v = jnp.stack([-jnp.sin(p), -jnp.cos(p)])
        unit = jnp.maximum(_pad_speed(pads, jnp.array([1.0, 0.0])),
                           _pad_speed(pads, jnp.array([0.0, 1.0])))
        turning = _pad_speed(pads, v) <= 1e-9 * unit
        v = jnp.where(turning, jnp.stack([-jnp.sin(p + 1e-6), -jnp.cos(p + 1e-6)]), v)
        speed = _pad_speed(pads, v)
        return v / jnp.where(speed > 0.0, speed, 1.0)

    def step(self, p0, dp):
        return self.basis(p0 + dp) - self.basis(p0)

    def ahead(self, p):
        return self.basis(p + LOOKAHEAD) - self.basis(p)

    def first_descent(self, f0, A, p0, rate_tol):
        """rad from tau0 to the first zero after tau0 where f = f0 + A.(phi(tau) - phi(tau0))
        falls; a dip of LIMIT_TOL or less is a touch, not a crossing (a pad that reaches its
        limit exactly at a turning point, where rounding would split the double root). rate_tol:
        unused (the depth test is the ellipse's)."""
        return _sinusoid_descent(*sinusoid(f0, A[..., 0], A[..., 1], self.s_a, p0), p0,
                                 LIMIT_TOL)

    def reversal(self, A, p0):
        """rad to where the slip rate s A.phi'(tau) turns from sliding against friction (<= 0)
        to along it; A (..., B) = s dslip."""
        # s p'(tau) = s_a (-A_0 sin tau - A_1 cos tau): it turns positive where
        # f = s_a (A_1 cos tau + A_0 sin tau) falls through zero.
        return _sinusoid_descent(0.0, self.s_a * A[..., 1], self.s_a * A[..., 0], p0, 0.0)


def sinusoid(f0, A, B, s_a, tau0):
    """(c, alpha, beta) of f(tau) = f0 + s_a [A (cos tau - cos tau0) - B (sin tau - sin tau0)] =
    c + alpha cos tau + beta sin tau: a force on an `Ellipse` tract with rates A, B along X_r, X_i
    (its events, and the closed-form harmonics of `jaxdamp.ellipse`)."""
    alpha, beta = s_a * A, -s_a * B
    return f0 - alpha * jnp.cos(tau0) - beta * jnp.sin(tau0), alpha, beta


def _pad_speed(pads, v):
    """Largest platform speed at a pad for basis weights v (B,) (pads: an `engine.Pads`)."""
    return jnp.max(jnp.abs(jnp.concatenate([combine(v, pads.nw), combine(v, pads.tw)])))


def _sinusoid_descent(c, alpha, beta, tau0, depth_tol):
    """rad from tau0 to the first zero of f = c + alpha cos tau + beta sin tau after tau0 where f
    falls (NO_EVENT where it never does, or dips by depth_tol or less). Guarded for gradients.

    With f = c + rho cos(tau - phase), f falls through zero where tau - phase = arccos(-c / rho),
    i.e. where cos(tau - phase) = -c / rho and sin(tau - phase) = +sqrt(rho^2 - c^2) / rho. Turned
    to angles from tau0 (A + iB = (alpha + i beta) e^{-i tau0}), that is one arctan2 of
    (Y A - c B, -c A - Y B) with Y = sqrt(rho^2 - c^2): one square root and one arctan2 per
    event instead of two square roots, an arctan2 and an arccos (10 % of an elliptic cycle,
    measured batched)."""
    rho2 = alpha * alpha + beta * beta
    reach = c + depth_tol  # rho - c > depth_tol, without a square root
    has = (rho2 > 1e-300) & (c * c < rho2) & ((reach <= 0.0) | (reach * reach < rho2))
    cos0, sin0 = jnp.cos(tau0), jnp.sin(tau0)
    A = alpha * cos0 + beta * sin0
    B = beta * cos0 - alpha * sin0
    Y = jnp.sqrt(jnp.where(has, rho2 - c * c, 1.0))
    t = jnp.mod(jnp.arctan2(jnp.where(has, Y * A - c * B, 0.0),
                            jnp.where(has, -c * A - Y * B, 1.0)), 2.0 * jnp.pi)
    t = jnp.where(t <= TAU_TOL, t + 2.0 * jnp.pi, t)  # a touch at tau0 itself is not an event
    return jnp.where(has, t, NO_EVENT)


__all__ = ["Line", "Ellipse", "sinusoid", "TAU_TOL", "LOOKAHEAD"]
