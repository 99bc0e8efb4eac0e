"""A regularised (tanh) friction law in the same damper, evaluated the HBM-AFT way, to show its bias.

Time-integration friction codes often replace the Coulomb slider by a smooth law. Here each
contact's slider obeys T = -mu N tanh(p' / eps_v) (p' = slip rate per radian of the harmonic
motion), in series with the tangential spring kt, so a contact creeps a little even below the cone
and never quite reaches it while sliding. With eps_v = eps * (platform amplitude in mm) the law
tends to Coulomb's as eps -> 0; for finite eps it is rate dependent and biased. The march uses
backward Euler in time (the phase tau) at Nt samples per period with a local, safeguarded Newton
solve per contact and the consistent tangent in the damper's Newton iterations; k_Re, k_Im come
from the FFT of the last period, as in `jaxdamp.hbm`.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int, check_range
from ..conventions import CENTRIFUGAL_LOAD, MRAD_PER_RAD, travel_mm
from ..geometry import DamperShape
from ..status import RESULTS
from .hbm import PERIODIC_TOL, HBMResult, first_harmonic
from ..params import Contacts, LoadCase, prepare_inputs
from .timemarch import NEWTON_TOL, MarchModel, march_model, moment_of, newton

LOCAL_ITERS = 80  # bound on the safeguarded Newton iterations of the per-contact slip equation
MAX_NEWTON_REG = 20


def local_tanh(T_tr, muN, c):
    """Solve muN tanh(z) + c z = T_tr for z (monotone in z), Newton safeguarded by bisection."""
    lo = (T_tr - muN) / c
    hi = (T_tr + muN) / c
    z0 = jnp.clip(T_tr / (muN + c), lo, hi)
    tol = 1e-14 * (muN + jnp.abs(T_tr))

    def g_of(z):
        return muN * jnp.tanh(z) + c * z - T_tr

    def cond(st):
        z, _, _, it = st
        return (it < LOCAL_ITERS) & jnp.any(jnp.abs(g_of(z)) > tol)

    def body(st):
        z, lo, hi, it = st
        g = g_of(z)
        lo = jnp.where(g < 0, z, lo)
        hi = jnp.where(g > 0, z, hi)
        dg = muN / jnp.cosh(jnp.clip(z, -300.0, 300.0)) ** 2 + c
        zn = z - g / dg
        zn = jnp.where((zn > lo) & (zn < hi), zn, 0.5 * (lo + hi))
        return jnp.where(jnp.abs(g) > tol, zn, z), lo, hi, it + 1

    z, _, _, _ = jax.lax.while_loop(cond, body, (z0, lo, hi, jnp.array(0)))
    return z


class RegResponse(NamedTuple):
    N: jnp.ndarray
    T: jnp.ndarray
    p: jnp.ndarray
    R: jnp.ndarray
    J: jnp.ndarray


def respond_tanh(m: MarchModel, q, dv, p_old, c_reg):
    """Contact forces with the tanh slider (backward Euler over one time step) and the tangent.

    c_reg = kt * eps_v * dtau per contact (units of F_D, kt normalised by F_D).
    """
    gn = m.a @ q - m.nw * dv
    gt = m.c @ q - m.tw * dv
    N_tr = m.N_ref + m.kn * gn
    closed = N_tr > 0.0
    N = jnp.where(closed, N_tr, 0.0)
    muN = jnp.maximum(m.mu * N, 1e-300)
    T_tr = m.T_ref - m.kt * (gt - p_old)
    z = local_tanh(T_tr, muN, c_reg)
    th = jnp.tanh(z)
    T = jnp.where(closed, muN * th, 0.0)
    p = gt - (m.T_ref - T) / m.kt
    # Implicit derivative of T(T_tr, N): (1 + c / (muN sech^2)) dT = dT_tr + (c th / (N sech^2)) dN.
    sech2 = jnp.maximum(1.0 - th * th, 1e-300)
    denom = 1.0 + c_reg / (muN * sech2)
    dT_dTtr = 1.0 / denom
    dT_dN = c_reg * th / (jnp.maximum(N, 1e-300) * sech2) / denom
    dN = jnp.where(closed, m.kn, 0.0)[:, None] * m.a
    dT = jnp.where(closed[:, None], (-m.kt * dT_dTtr)[:, None] * m.c + dT_dN[:, None] * dN, 0.0)
    R = -m.a.T @ N + m.c.T @ T + CENTRIFUGAL_LOAD
    J = -m.a.T @ dN + m.c.T @ dT
    return RegResponse(N, T, p, R, J)


@partial(jax.jit, static_argnames=("n_time", "n_periods", "max_newton"))
def regularized_aft_kernel(shape, mu, contacts, load, psi_a_mrad, eps, n_time: int, n_periods: int = 3,
                     max_newton: int = MAX_NEWTON_REG) -> HBMResult:
    m, lift0 = march_model(shape, mu, contacts, load)
    amp = travel_mm(psi_a_mrad, m.q_star)
    dtau = 2.0 * jnp.pi / n_time
    c_reg = m.kt * eps * amp * dtau
    tau = dtau * jnp.arange(1, n_time * n_periods + 1, dtype=float)
    path = amp * (jnp.cos(tau) - 1.0)

    def step(carry, dv_new):
        q, dv, p = carry

        def residual(qq):
            r = respond_tanh(m, qq, dv_new, p, c_reg)
            return r.R, r.J

        q, res, _ = newton(residual, q, max_newton)
        r = respond_tanh(m, q, dv_new, p, c_reg)
        out = (moment_of(m, r.N, r.T), res <= NEWTON_TOL, jnp.min(r.N))
        return (q, dv_new, r.p), out

    init = (jnp.zeros(3), jnp.zeros(()), jnp.zeros(3))
    _, (M, conv, n_min) = jax.lax.scan(step, init, path)
    M = M.reshape(n_periods, n_time)
    last = jnp.roll(M[-1], 1)
    prev = jnp.roll(M[-2], 1) if n_periods > 1 else jnp.zeros_like(last)
    k_re, k_im = first_harmonic(last, psi_a_mrad)
    periodicity = jnp.max(jnp.abs(last - prev)) / jnp.maximum(jnp.max(jnp.abs(last)), 1e-300)
    liftoff = lift0 | jnp.any(n_min <= 0.0)
    fails = jnp.sum(~conv)
    converged = ~liftoff & (fails == 0) & (periodicity <= PERIODIC_TOL)
    return HBMResult(k_re, k_im, jnp.pi * psi_a_mrad ** 2 * k_im / MRAD_PER_RAD, periodicity,
                     fails, RESULTS.first({RESULTS.liftoff: liftoff,
                                                RESULTS.not_converged: ~converged}))


def regularized_aft(shape: DamperShape, mu, psi_a_mrad, eps, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, n_time: int = 1024, n_periods: int = 3,
                    max_newton: int = MAX_NEWTON_REG) -> HBMResult:
    """k_Re, k_Im (N mm/mrad) at amplitude psi_a (mrad) with the tanh-regularised slider of
    relative width eps (> 0, dimensionless; eps -> 0 recovers Coulomb), by HBM-AFT."""
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, np.inf, lo_open=True, unit="mrad")
    check_range("eps", eps, 0.0, np.inf, lo_open=True)
    return regularized_aft_kernel(shape, mu, contacts, load,
                            jnp.asarray(psi_a_mrad, float), jnp.asarray(eps, float),
                            n_time=check_int("n_time", n_time, 4), n_periods=check_int("n_periods", n_periods, 1),
                            max_newton=check_int("max_newton", max_newton, 1))


__all__ = ["regularized_aft"]
