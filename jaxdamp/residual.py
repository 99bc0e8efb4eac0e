"""The damper in series with a flexibility: the platforms' residual flexibility of a bladed disk's
modes left out of the reduction (`jaxdamp.response.modes`), as the mode sees the damper.

Core (pure JAX, values only): the row's peaks (`response.stiffness.with_residual`) and the band
of a path (`band.band_kernel(..., residual=)`, each admissible state's cycle in series) use it.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from .loops import batched_together
from .status import RESULTS

__all__ = ["RESIDUAL_RTOL", "RESIDUAL_ITERATIONS", "through_residual"]

RESIDUAL_RTOL = 1e-12  # relative error of the damper's amplitude at which the series converged
RESIDUAL_ITERATIONS = 200  # the map contracts by |c k / (1 + c k)| per step or faster: 0.25 for
# a damper a third as stiff as the support (c k = 1/3, the example disk's nodal diameter 0), 0.75 at
# c k = 3


def through_residual(cycle, psi, c):
    """(k_re, k_im, status, psi_d) of the damper in series with the path's residual flexibility c
    (mrad per N mm, `modes` docstring) at the free-platform path amplitude psi (mrad, an array):
    psi_d = psi / |1 + c k(psi_d)| is the damper's own amplitude, k(psi_d) / (1 + c k(psi_d))
    what the mode sees. cycle(psi_d) -> (k_re, k_im, status) arrays of psi's shape.

    Fixed-point iteration on psi_d from psi: the map increases with psi_d and contracts by about
    |c k / (1 + c k)| |d ln k / d ln psi| < 1 (k falls no faster than 1 / psi). It stops where the
    step, over one minus the contraction the last two steps show, is below RESIDUAL_RTOL of psi
    (the distance left to the fixed point); with c = 0 after one evaluation, with k(psi) itself.
    not_converged where RESIDUAL_ITERATIONS do not get there. Values only (a while loop: no
    reverse-mode derivative)."""
    psi = jnp.asarray(psi, float)
    c = jnp.asarray(c, float)

    def body(state):
        i, p, step, _, _, _, _ = state
        k_re, k_im, status = cycle(p)
        p_new = psi / jnp.abs(1.0 + c * (k_re + 1j * k_im))
        new_step = jnp.abs(p_new - p)
        rate = jnp.where(step > 0, new_step / jnp.where(step > 0, step, 1.0), 0.0)
        done = new_step <= RESIDUAL_RTOL * psi * (1.0 - jnp.minimum(rate, 0.99))
        return (i + 1, jnp.where(done, p, p_new), jnp.where(done, step, new_step), k_re, k_im,
                status, done)

    def more(state):
        return (state[0] < RESIDUAL_ITERATIONS) & ~jnp.all(state[6])

    zeros = jnp.zeros_like(psi)
    _, p, _, k_re, k_im, status, done = jax.lax.while_loop(
        more, body, batched_together((jnp.array(0), psi, zeros, zeros, zeros,
                                      jnp.zeros(psi.shape, jnp.int32), jnp.zeros(psi.shape, bool))))
    k = (k_re + 1j * k_im) / (1.0 + c * (k_re + 1j * k_im))
    return jnp.real(k), jnp.imag(k), RESULTS.first({RESULTS.not_converged: ~done}, status), p
