"""The damper in series with a flexibility: the platforms' residual flexibility of a bladed disk's
modes left out of the reduction (`jaxdamp.response.modes`), as the mode sees the damper.

Core (pure JAX, values only): the curve as the mode sees it at given amplitudes
(`response.stiffness.with_residual`: the damped FRFs) uses it. The row's peaks and its band over
contact histories do not: they are searched in the damper's own amplitude, where the series is
explicit (`response.peaks.series_peaks`, `response.row_band`), one cycle per evaluation.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from .loops import batched_together
from .status import RESULTS

__all__ = ["RESIDUAL_RTOL", "RESIDUAL_ITERATIONS", "RESIDUAL_PATIENCE", "through_residual"]

RESIDUAL_RTOL = 1e-12  # relative error of the damper's amplitude at which the series converged
RESIDUAL_ITERATIONS = 16  # the map contracts by |c k / (1 + c k)| per step or faster (0.25 for
# a damper a third as stiff as the support, c k = 1/3, the example disk's nodal diameter 0; 0.75 at
# c k = 3), and secant steps get to RESIDUAL_RTOL in far fewer evaluations: admissible states'
# cycles on the example disk (60sym, mu 0.5, nodal diameters 0/3/6/12, 0.3-300 mrad) converge in
# 2-6. Where k jumps with the amplitude (h has no root) no count gets there (18 of 88 states at
# 30 mrad of nodal diameter 6), and under vmap every lane pays for the bound: 50 (was the bound)
# made a band in series (then solved this way per state) cost ten times a free one
RESIDUAL_PATIENCE = 8  # consecutive evaluations without a valid cycle after which an amplitude
# stops iterating (a cycle that does not settle has no trustworthy k to iterate on)


def through_residual(cycle, psi, c):
    """(k_re, k_im, status, psi_d) of the damper in series with the path's residual flexibility c
    (mrad per N mm, `modes` docstring) at the free-platform path amplitude psi (mrad, an array):
    psi_d = psi / |1 + c k(psi_d)| is the damper's own amplitude, k(psi_d) / (1 + c k(psi_d))
    what the mode sees. cycle(psi_d) -> (k_re, k_im, status) arrays of psi's shape.

    The root of h(p) = F(p) - p, F(p) = psi / |1 + c k(p)|, from p = psi: the map F increases
    with p and contracts by about |c k / (1 + c k)| |d ln k / d ln psi| < 1 (k falls no faster
    than 1 / psi), so its fixed-point steps converge; secant steps on h (from the second
    evaluation on) converge faster, and a secant step that leaves (0, psi] falls back to the
    fixed-point step F(p). It stops where |h|, over one minus F's slope the last two evaluations
    show, is below RESIDUAL_RTOL of psi (the distance left to the root); with c = 0 after one
    evaluation, with k(psi) itself. not_converged where RESIDUAL_ITERATIONS do not get there, or
    where RESIDUAL_PATIENCE evaluations in a row give no valid cycle (or no finite step): such an
    amplitude stops there with that cycle's status. Values only (a while loop: no reverse-mode
    derivative). Each evaluation is a steady cycle at every amplitude of psi still iterating:
    secant steps need far fewer of them than fixed-point steps (about 20 at the example disk's
    contraction, to 1e-12)."""
    psi = jnp.asarray(psi, float)
    c = jnp.asarray(c, float)

    def body(state):
        i, p_prev, h_prev, p, _, _, _, _, bad = state
        k_re, k_im, status = cycle(p)
        f = psi / jnp.abs(1.0 + c * (k_re + 1j * k_im))
        h = f - p
        dp, dh = p - p_prev, h - h_prev
        ok = (i > 0) & (dh != 0) & (dp != 0)
        slope = jnp.where(ok, 1.0 + dh / jnp.where(ok, dp, 1.0), 0.0)  # F' by the secant
        done = jnp.abs(h) <= RESIDUAL_RTOL * psi * (1.0 - jnp.clip(slope, 0.0, 0.99))
        secant = p - h * dp / jnp.where(ok, dh, 1.0)
        inside = ok & jnp.isfinite(secant) & (secant > 0) & (secant <= psi)
        p_new = jnp.where(inside, secant, f)
        bad = jnp.where(RESULTS.valid(status) & jnp.isfinite(h), 0, bad + 1)
        stop = done | (bad >= RESIDUAL_PATIENCE)
        return (i + 1, jnp.where(stop, p_prev, p), jnp.where(stop, h_prev, h),
                jnp.where(stop, p, p_new), k_re, k_im, status, done, bad)

    def more(state):
        return (state[0] < RESIDUAL_ITERATIONS) & ~jnp.all(state[7]
                                                          | (state[8] >= RESIDUAL_PATIENCE))

    zeros = jnp.zeros_like(psi)
    _, _, _, p, k_re, k_im, status, done, _ = jax.lax.while_loop(
        more, body, batched_together((jnp.array(0), zeros, zeros, psi, zeros, zeros,
                                      jnp.zeros(psi.shape, jnp.int32), jnp.zeros(psi.shape, bool),
                                      jnp.zeros(psi.shape, jnp.int32))))
    k = (k_re + 1j * k_im) / (1.0 + c * (k_re + 1j * k_im))
    return jnp.real(k), jnp.imag(k), RESULTS.first({RESULTS.not_converged: ~done}, status), p
