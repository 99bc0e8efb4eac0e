"""Independent time integration of the one-DOF blade with the damper's contacts, to steady state.

    m x'' + c x' + k_b x + 1e-3 r M(t) = F cos(omega t),   m = k_b / omega0^2,

x the tip displacement (mm), M the platform moment (N mm) of the quasi-static contact model of
`jaxdamp.timemarch` driven by the relative platform motion dv = q* r (x - x_start) / 1e3 (mm),
starting in the cycle-start full-slip state (state 0) at the top of the motion.

Structural damping: equivalent viscous at the forcing frequency, c = eta k_b / omega. A loss
factor is a frequency-domain idea (its time-domain kernel is not causal); at one forcing frequency
this c gives exactly the hysteretic force on the first harmonic, and eta / h on harmonic h. The
harmonic-balance baseline applies eta to every harmonic, a difference of order eta (1 - 1/h)
k_b |X_h| on harmonics that are themselves small.

Scheme: classical RK4 on (x, x'), fixed step (steps_per_period per forcing period). The damper has
no inertia but has memory: at an RK stage its moment is the return-mapped response from the
committed contact state of the step start (`timemarch.step` at the stage's dv, not committed); the
state is committed at the step end. Nothing is shared with the harmonic-balance solvers.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ..response import BladeMode
from ..status import RESULTS
from .timemarch import initial_state, march_model, step


class TimeResponse(NamedTuple):
    """Steady-state response at one forcing frequency (Hz); displacements in mm.

    amplitude_mm: first-harmonic amplitude of x over the last period; max_displacement_mm:
    max |x - mean| over it; change: relative change of the first-harmonic amplitude between the
    last two periods (a steady-state indicator); history_mm: first-harmonic amplitude per period.
    """

    amplitude_mm: jnp.ndarray
    max_displacement_mm: jnp.ndarray
    change: jnp.ndarray
    history_mm: jnp.ndarray
    status: jnp.ndarray


@partial(jax.jit, static_argnames=("n_periods", "steps_per_period"))
def _integrate(shape, mu, contacts, load, mode, force_n, frequency_hz, x0, v0, phase0, n_periods,
               steps_per_period):
    model, lift0 = march_model(shape, mu, contacts, load)
    omega0 = 2.0 * jnp.pi * mode.f0_hz
    omega = 2.0 * jnp.pi * frequency_hz
    mass = mode.k_b / omega0 ** 2  # N s^2 / mm
    c = mode.eta * mode.k_b / omega
    dt = 2.0 * jnp.pi / omega / steps_per_period
    g = 1e-3 * mode.r

    def dv_of(x):
        return model.q_star * mode.r * (x - x0) / 1e3

    def accel(t, x, v, M):
        return (force_n * jnp.cos(omega * t + phase0) - c * v - mode.k_b * x - g * M) / mass

    def moment_at(s, x):
        _, smp = step(model, s, dv_of(x))
        return smp.M, smp.newton_ok & ~jnp.any(smp.code == 3)

    def rk4(carry, k):
        x, v, s, M, ok = carry
        t = k * dt
        a1 = accel(t, x, v, M)
        x2, v2 = x + 0.5 * dt * v, v + 0.5 * dt * a1
        M2, ok2 = moment_at(s, x2)
        a2 = accel(t + 0.5 * dt, x2, v2, M2)
        x3, v3 = x + 0.5 * dt * v2, v + 0.5 * dt * a2
        M3, ok3 = moment_at(s, x3)
        a3 = accel(t + 0.5 * dt, x3, v3, M3)
        x4, v4 = x + dt * v3, v + dt * a3
        M4, ok4 = moment_at(s, x4)
        a4 = accel(t + dt, x4, v4, M4)
        xn = x + dt / 6.0 * (v + 2 * v2 + 2 * v3 + v4)
        vn = v + dt / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)
        sn, smp = step(model, s, dv_of(xn))
        okn = ok & ok2 & ok3 & ok4 & smp.newton_ok & ~jnp.any(smp.code == 3)
        return (xn, vn, sn, smp.M, okn), xn

    s0 = initial_state(model)
    M0 = jnp.sum(s0.N * model.fn + s0.T * model.ft)
    tau = 2.0 * jnp.pi * jnp.arange(1, steps_per_period + 1) / steps_per_period

    def period(carry, p):
        ks = p * steps_per_period + jnp.arange(steps_per_period, dtype=float)
        carry, xs = jax.lax.scan(rk4, carry, ks)
        a = 2.0 / steps_per_period * jnp.sum(xs * jnp.cos(tau))
        b = 2.0 / steps_per_period * jnp.sum(xs * jnp.sin(tau))
        return carry, (jnp.hypot(a, b), jnp.max(jnp.abs(xs - jnp.mean(xs))))

    init = (jnp.asarray(x0, float), jnp.asarray(v0, float), s0, M0, jnp.array(True))
    (_, _, _, _, ok), (amps, maxes) = jax.lax.scan(period, init, jnp.arange(n_periods, dtype=float))
    change = jnp.abs(amps[-1] - amps[-2]) / jnp.maximum(amps[-1], 1e-300)
    status = RESULTS.first({RESULTS.liftoff: lift0 | ~ok})
    return TimeResponse(amps[-1], maxes[-1], change, amps, status)


def steady_state(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode(),
                 force_n=20.0, frequency_hz=500.0, *, x0=0.0, v0=0.0, phase0=0.0, n_periods: int = 300,
                 steps_per_period: int = 256) -> TimeResponse:
    """Integrate n_periods forcing periods of F cos(omega t + phase0) from (x0 mm, v0 mm/s) at
    t = 0 with the damper in state 0,
    and report the last period (see module doc). A start on the expected steady motion (x0 at its
    crest, e.g. from a harmonic-balance solution) shortens the transient; the steady state does
    not depend on it where it is unique."""
    from ..response import prepare_scene

    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    return _integrate(shape, mu, contacts, load, mode, jnp.asarray(force_n, float),
                      jnp.asarray(frequency_hz, float), jnp.asarray(x0, float),
                      jnp.asarray(v0, float), jnp.asarray(phase0, float), n_periods,
                      steps_per_period)


def start_on_harmonics(y, harmonics, frequency_hz):
    """(x0, v0, phase0) on the crest of the periodic motion x(tau) = sum a_h cos + b_h sin of a
    harmonic-balance solution (the forcing F cos(tau)), to start `steady_state` near it: x0 in the
    coefficients' unit (mm), v0 in mm/s at frequency_hz (Hz), phase0 in rad."""
    import numpy as np

    y = np.asarray(y, float)
    h = np.asarray(harmonics, float)
    tau = 2 * np.pi * np.arange(4096) / 4096
    x = np.cos(np.outer(tau, h)) @ y[0::2] + np.sin(np.outer(tau, h)) @ y[1::2]
    k = int(np.argmax(x))
    v = (-np.sin(h * tau[k]) * h) @ y[0::2] + (np.cos(h * tau[k]) * h) @ y[1::2]
    return float(x[k]), float(v * 2 * np.pi * float(frequency_hz)), float(tau[k])


__all__ = ["TimeResponse", "steady_state", "start_on_harmonics"]
