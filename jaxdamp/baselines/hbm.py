"""HBM-AFT, the way friction-damper codes (tmdsimpy, NLvib, pyHarm) evaluate a friction element.

For a prescribed harmonic relative platform motion psi(tau) = psi_a cos(tau), the alternating
frequency-time (AFT) step marches the hysteretic contact law in the time domain at Nt samples per
period for a few periods (here with the incremental return-mapping solver of `jaxdamp.baselines.timemarch`,
the damper's quasi-static equilibrium being solved at every sample), and takes the first harmonic of
the platform moment from the last period by FFT. It returns k_Re and k_Im at that amplitude; unlike
the direct method it cannot give psi_BC or psi_fs by itself (that needs a search over amplitudes).

Conventions as in `jaxdamp.harmonics`: M ~ psi_a (k_Re cos tau - k_Im sin tau), k_Im > 0, psi in
mrad, k in N mm/mrad. The march starts at state 0 (the cycle-start full slip, the top of the motion,
tau = 0), so the first half-period is the direct method's forward half.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int, check_range
from ..conventions import stiffness_from_rfft, travel_mm
from ..geometry import DamperShape
from ..status import RESULTS
from ..params import Contacts, LoadCase, prepare_inputs
from .timemarch import MAX_NEWTON, initial_state, march, march_model

PERIODIC_TOL = 1e-9  # change of the moment between the last two periods, relative to max |M|


class HBMResult(NamedTuple):
    """HBM-AFT at one amplitude psi_a (mrad): first-harmonic k_Re, k_Im (N mm/mrad), the work per
    cycle (N mm), the periodicity reached, Newton failures and a `jaxdamp.RESULTS` status."""

    k_re: jnp.ndarray  # N mm/mrad
    k_im: jnp.ndarray
    work: jnp.ndarray  # N mm per cycle, pi psi_a^2 k_Im
    periodicity: jnp.ndarray  # max |M(last period) - M(previous)| / max |M|
    newton_failures: jnp.ndarray
    # RESULTS code: liftoff, else not_converged (not periodic to PERIODIC_TOL, or Newton failed at
    # a sample), else ok
    status: jnp.ndarray


def first_harmonic(M, psi_a_mrad):
    """(k_Re, k_Im) in N mm/mrad from one period of moment samples M (..., Nt) in N mm at
    tau_k = 2 pi k / Nt, k = 0..Nt-1, by FFT; psi_a_mrad: the amplitude (mrad).
    Unchecked, traceable (jit, vmap, grad)."""
    return stiffness_from_rfft(jnp.fft.rfft(M, axis=-1)[..., 1], M.shape[-1], psi_a_mrad)


@partial(jax.jit, static_argnames=("n_time", "n_periods", "max_newton"))
def hbm_aft_kernel(shape, mu, contacts, load, psi_a_mrad, n_time: int, n_periods: int = 3,
             max_newton: int = MAX_NEWTON) -> HBMResult:
    m, lift0 = march_model(shape, mu, contacts, load)
    amp = travel_mm(psi_a_mrad, m.q_star)
    tau = 2.0 * jnp.pi / n_time * jnp.arange(1, n_time * n_periods + 1, dtype=float)
    _, smp = march(m, initial_state(m), amp * (jnp.cos(tau) - 1.0), max_newton)
    M = smp.M.reshape(n_periods, n_time)
    # The last sample of each period is at tau = 0 (mod 2 pi): rotate it to the front.
    last = jnp.roll(M[-1], 1)
    prev = jnp.roll(M[-2], 1) if n_periods > 1 else jnp.zeros_like(last)
    k_re, k_im = first_harmonic(last, psi_a_mrad)
    periodicity = jnp.max(jnp.abs(last - prev)) / jnp.maximum(jnp.max(jnp.abs(last)), 1e-300)
    liftoff = lift0 | jnp.any(smp.code == 3)
    fails = jnp.sum(~smp.newton_ok)
    converged = ~liftoff & (fails == 0) & (periodicity <= PERIODIC_TOL)
    work = jnp.pi * psi_a_mrad ** 2 * k_im * 1e-3
    return HBMResult(k_re, k_im, work, periodicity, fails, RESULTS.first({RESULTS.liftoff: liftoff, RESULTS.not_converged: ~converged}))


def hbm_aft(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
            load: LoadCase = LoadCase(), *, n_time: int = 256, n_periods: int = 3,
            max_newton: int = MAX_NEWTON) -> HBMResult:
    """k_Re, k_Im (N mm/mrad) at platform rotation amplitude psi_a (mrad) by HBM-AFT: march
    n_periods periods of psi_a cos(tau) at n_time samples per period, first harmonic of the last
    period by FFT. Non-periodicity, Newton failures and liftoff are flags."""
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, np.inf, lo_open=True, unit="mrad")
    return hbm_aft_kernel(shape, mu, contacts, load, jnp.asarray(psi_a_mrad, float),
                    n_time=check_int("n_time", n_time, 4), n_periods=check_int("n_periods", n_periods, 1),
                    max_newton=check_int("max_newton", max_newton, 1))


__all__ = ["hbm_aft", "HBMResult", "first_harmonic"]
