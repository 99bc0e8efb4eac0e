"""Coupled HBM-AFT of the one-DOF blade with the damper's Jenkins contacts (a standard technique).

The blade mode of `jaxdamp.response` (tip displacement x in mm, modal stiffness k_b, frequency f0,
loss factor eta, platform rotation psi = r x in mrad) carries the damper's modal force
1e-3 r M(t), with M the platform moment (N mm) of the quasi-static contact model. The periodic
motion is x(tau) = sum_h a_h cos(h tau) + b_h sin(h tau), tau = omega t, over the odd harmonics H
(1; 1, 3; 1, 3, 5). Per harmonic, with X_h = a_h - i b_h and hysteretic structural damping
(the loss factor acts on every harmonic, as in the layered model's D):

    [k_b (1 - h^2 Omega^2) + i eta k_b] X_h + F_d,h = F delta_h1,   Omega = omega / omega0.

AFT: sample x at n_time points per period, march the damper's incremental return-mapping model
(`jaxdamp.timemarch`, Newton at every sample) for n_periods periods starting at the sample where
x is largest, in the cycle-start full-slip state (state 0: the top of the motion, the forward half
first, as in `jaxdamp.hbm`), and FFT the last period. The mean moment (a static preload) and even
harmonics are left out. Newton at each point with pseudo-arclength continuation across the
resonance (a bounded `lax.scan`, so a batch of force levels can be vmapped); the peak of the
first-harmonic amplitude is located on the branch by bisection on the arclength.

For checks, the damper may instead be a describing function k(psi_a) (a `DamperStiffness`): then
F_d,1 = 1e-3 r^2 (k_Re + i k_Im)(r |X_1|) X_1, the layered model's physics exactly.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..response import BladeMode, DamperStiffness, damper_stiffness, peak_response
from ..status import RESULTS
from .timemarch import initial_state, march, march_model

N_TIME = 256
N_PERIODS = 3
N_NEWTON = 10
NEWTON_TOL = 1e-9  # residual relative to F


class HBMPath(NamedTuple):
    """A continuation path and its peak (first-harmonic amplitude in mm, frequency in Hz)."""

    frequency_hz: jnp.ndarray  # (n_steps + 1,)
    amplitude_mm: jnp.ndarray  # (n_steps + 1,) first-harmonic amplitude |X_1|
    coefficients: jnp.ndarray  # (n_steps + 1, 2H): a_1, b_1, a_3, b_3, ...
    residual: jnp.ndarray  # (n_steps + 1,) max |R| / F after the corrector
    peak_amplitude_mm: jnp.ndarray
    peak_frequency_hz: jnp.ndarray
    peak_coefficients: jnp.ndarray
    peak_max_displacement_mm: jnp.ndarray  # max |x(t)| at the peak (all harmonics)
    status: jnp.ndarray


def synthesize(y, harmonics, n_time, phase=0.0):
    """x (n_time,) at tau_k = phase + 2 pi k / n_time (phase in rad) from the coefficients
    y = (a_1, b_1, a_3, b_3, ...), in the coefficients' unit (mm for the tip motion)."""
    tau = phase + 2.0 * jnp.pi * jnp.arange(n_time) / n_time
    h = jnp.asarray(harmonics, float)
    a, b = y[0::2], y[1::2]
    return (jnp.cos(jnp.outer(tau, h)) @ a) + (jnp.sin(jnp.outer(tau, h)) @ b)


def project(f, harmonics, phase=0.0):
    """Coefficients (c_h, s_h) of f(tau) = sum c_h cos(h tau) + s_h sin(h tau) from samples at
    tau_k = phase + 2 pi k / n."""
    n = f.shape[-1]
    idx = np.asarray(harmonics)
    F = jnp.fft.rfft(f)[idx] * jnp.exp(-1j * jnp.asarray(idx, float) * phase)
    c = 2.0 * jnp.real(F) / n
    s = -2.0 * jnp.imag(F) / n
    return jnp.stack([c, s], axis=-1).reshape(-1)


def first_harmonic_phase(y):
    """The phase where the first harmonic a_1 cos + b_1 sin peaks (0 when it vanishes)."""
    a1, b1 = y[0], y[1]
    ok = a1 * a1 + b1 * b1 > 0
    return jnp.where(ok, jnp.arctan2(jnp.where(ok, b1, 0.0), jnp.where(ok, a1, 1.0)), 0.0)


def aft_modal_force(model, mode: BladeMode, y, harmonics, n_time=N_TIME, n_periods=N_PERIODS):
    """Harmonic coefficients of the damper's modal force 1e-3 r M(t) (N) and whether every
    sample's Newton converged without liftoff, by AFT on the contact model.

    The time grid is rotated so that a sample sits on the first harmonic's crest: a fixed grid
    misses the motion's extremes by up to (pi/n)^2/2 of the amplitude, which shifts the hysteresis
    loop's reversal points and costs ~1e-4 relative on k(psi_a) near psi_BC at n = 256."""
    phase = first_harmonic_phase(y)
    x = synthesize(y, harmonics, n_time, phase)
    k0 = jnp.argmax(x)
    j = jnp.arange(n_time * n_periods)
    order = (k0 + 1 + j) % n_time
    dv = model.q_star * mode.r * (x[order] - x[k0]) / 1e3  # mm of relative platform travel
    _, smp = march(model, initial_state(model), dv)
    last = smp.M[-n_time:]
    M = last[(jnp.arange(n_time) - k0 - 1) % n_time]
    ok = jnp.all(smp.newton_ok) & ~jnp.any(smp.code == 3)
    return project(1e-3 * mode.r * M, harmonics, phase), ok


def describing_modal_force(damper: DamperStiffness, mode: BladeMode, y):
    """First-harmonic modal force (N) of a damper given as k(psi_a) (other harmonics: zero), at
    the tip-motion coefficients y = (a_1, b_1, ...) in mm."""
    a1, b1 = y[0], y[1]
    amp2 = a1 * a1 + b1 * b1
    pos = amp2 > 0
    amp = jnp.where(pos, jnp.sqrt(jnp.where(pos, amp2, 1.0)), 0.0)
    k_re, k_im = damper.k_of_psi(mode.r * amp)
    g = 1e-3 * mode.r ** 2
    X = a1 - 1j * b1
    Fd = g * (k_re + 1j * k_im) * X
    out = jnp.zeros_like(y)
    return out.at[0].set(jnp.real(Fd)).at[1].set(-jnp.imag(Fd)), jnp.array(True)


def residual(force_fn, mode: BladeMode, harmonics, force_n, y, omega_ratio):
    """Harmonic balance residual (N), length 2H."""
    h = jnp.repeat(jnp.asarray(harmonics, float), 2)
    stiff = mode.k_b * (1.0 - (h * omega_ratio) ** 2)
    # i eta k_b X with X = a - i b is eta k_b b + i eta k_b a: (c, s) += (eta k_b b, -eta k_b a).
    swap = jnp.stack([y[1::2], -y[0::2]], axis=-1).reshape(-1)
    fd, _ = force_fn(y)
    rhs = jnp.zeros_like(y).at[0].set(force_n)
    return stiff * y + mode.eta * mode.k_b * swap + fd - rhs


MAX_UPDATE = 0.25  # largest Newton update (normalised units): keeps iterates near the branch


def _newton_update(res, z, zp, t):
    """One damped Newton update of [res(z); t.(z - zp)] = 0, frozen once converged."""
    r = res(z)
    J = jax.jacfwd(res)(z)
    dz = jnp.linalg.solve(jnp.vstack([J, t[None]]), jnp.concatenate([r, jnp.array([t @ (z - zp)])]))
    size = jnp.linalg.norm(dz)
    dz = dz * jnp.minimum(1.0, MAX_UPDATE / jnp.where(size > 0, size, 1.0))
    done = jnp.max(jnp.abs(r)) <= 0.01 * NEWTON_TOL
    ok = jnp.all(jnp.isfinite(dz))
    return jnp.where(done | ~ok, z, z - dz)


def _continuation(res, z0, t0, ds, n_steps, n_newton):
    """Pseudo-arclength continuation of res(z) = 0 (n equations, n + 1 unknowns) from z0 along t0.

    Bounded scans throughout (fixed Newton iterations, masked once converged)."""
    n = z0.shape[0]
    e = jnp.zeros(n).at[-1].set(1.0)

    def tangent(z, t_prev):
        J = jax.jacfwd(res)(z)
        t = jnp.linalg.solve(jnp.vstack([J, t_prev[None]]), e)
        return t / jnp.linalg.norm(t)

    def correct(zp, t):
        z, _ = jax.lax.scan(lambda z, _: (_newton_update(res, z, zp, t), None), zp, None,
                            length=n_newton)
        return z

    def step(carry, _):
        z, t = carry
        t = tangent(z, t)

        # A corrector that failed (a fold of the damper law, a contact opening) is retried from
        # the same point with a third of the step, then a ninth (one compiled corrector).
        def attempt(z1, shrink):
            bad = ~(jnp.max(jnp.abs(res(z1))) <= NEWTON_TOL)
            return jax.lax.cond(bad, lambda: correct(z + ds / shrink * t, t), lambda: z1), None

        z1, _ = jax.lax.scan(attempt, z + ds * t, jnp.array([1.0, 3.0, 9.0]))
        return (z1, t), (z1, t)

    _, (zs, ts) = jax.lax.scan(step, (z0, t0), None, length=n_steps)
    return jnp.vstack([z0[None], zs]), jnp.vstack([t0[None], ts])


def _solve_fixed(res_y, y0, n_newton):
    def it(y, _):
        r = res_y(y)
        J = jax.jacfwd(res_y)(y)
        return y - jnp.linalg.solve(J, r), None

    y, _ = jax.lax.scan(it, y0, None, length=n_newton)
    return y


def continuation_path(force_fn, mode: BladeMode, harmonics, force_n, amp_scale_mm, omega_peak,
                      omega_halfwidth, *, ds=0.08, n_steps=160, n_newton=N_NEWTON,
                      n_bisect=40):
    """The FRF branch across the resonance and its peak (pure JAX, traceable; see module doc).

    z = (y / amp_scale, (Omega - omega_peak) / omega_halfwidth): amplitudes and frequency on
    comparable scales (amp_scale_mm in mm, omega in rad/s). Starts 5 half-widths below omega_peak
    from the linear stuck guess. force_n: the modal force amplitude (N)."""
    nh = 2 * len(harmonics)
    f = jnp.asarray(force_n, float)

    def res_z(z):
        y = z[:-1] * amp_scale_mm
        om = omega_peak + z[-1] * omega_halfwidth
        return residual(force_fn, mode, harmonics, f, y, om) / f

    om0 = omega_peak - 5.0 * omega_halfwidth
    y_lin = jnp.zeros(nh).at[0].set(f / (mode.k_b * (1 - om0 ** 2)))
    z0 = jnp.concatenate([_solve_fixed(lambda v: res_z(jnp.append(v, -5.0)), y_lin / amp_scale_mm,
                                       2 * n_newton), jnp.array([-5.0])])
    t0 = jnp.zeros(nh + 1).at[-1].set(1.0)
    zs, ts = _continuation(res_z, z0, t0, ds, n_steps, n_newton)
    amp = jnp.hypot(zs[:, 0], zs[:, 1]) * amp_scale_mm
    resid = jax.vmap(lambda z: jnp.max(jnp.abs(res_z(z))))(zs)

    # Peak: bisection on the arclength sigma from the point before the largest sample, on the
    # sign of d|X_1|/ds = grad|X_1| . t along the branch.
    k = jnp.clip(jnp.argmax(amp), 1, n_steps - 1)
    zk, tk = zs[k - 1], ts[k]
    e = jnp.zeros(nh + 1).at[-1].set(1.0)

    def at(sigma):
        zp = zk + sigma * tk

        z, _ = jax.lax.scan(lambda z, _: (_newton_update(res_z, z, zp, tk), None), zp, None,
                            length=n_newton)
        J = jax.jacfwd(res_z)(z)
        t = jnp.linalg.solve(jnp.vstack([J, tk[None]]), e)
        slope = (z[0] * t[0] + z[1] * t[1])
        return z, slope

    def bis(carry, _):
        lo, hi = carry
        mid = 0.5 * (lo + hi)
        _, s = at(mid)
        return (jnp.where(s > 0, mid, lo), jnp.where(s > 0, hi, mid)), None

    (lo, hi), _ = jax.lax.scan(bis, (jnp.asarray(0.0), jnp.asarray(2.0 * ds)), None,
                               length=n_bisect)
    zpk, _ = at(0.5 * (lo + hi))
    ypk = zpk[:-1] * amp_scale_mm
    om_pk = omega_peak + zpk[-1] * omega_halfwidth
    _, ok = force_fn(ypk)
    x = synthesize(ypk, harmonics, 4 * N_TIME)
    converged = (jnp.max(jnp.abs(res_z(zpk))) <= NEWTON_TOL) & (jnp.max(resid) <= NEWTON_TOL)
    status = RESULTS.first({RESULTS.liftoff: ~ok, RESULTS.not_converged: ~converged})
    ys = zs[:, :-1] * amp_scale_mm
    fr = mode.f0_hz * (omega_peak + zs[:, -1] * omega_halfwidth)
    return HBMPath(fr, amp, ys, resid, jnp.hypot(ypk[0], ypk[1]), mode.f0_hz * om_pk, ypk,
                   jnp.max(jnp.abs(x)), status)


def _scales(damper, mode, force_n):
    """Peak amplitude, frequency ratio and half-width from the amplitude-layered solution."""
    p = peak_response(damper, mode, force_n)
    a = p.peak_amplitude_mm
    _, k_im = damper.k_of_psi(mode.r * a)
    width = (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_im) / (2.0 * mode.k_b)
    return a, p.peak_frequency_hz / mode.f0_hz, width


@partial(jax.jit, static_argnames=("harmonics", "n_time", "n_periods", "n_steps"))
def _coupled(shape, mu, contacts, load, mode, force_n, harmonics, n_time, n_periods, n_steps):
    model, lift0 = march_model(shape, mu, contacts, load)
    # Only scales for the continuation (frequency window, amplitude) come from the layered model.
    d = damper_stiffness(shape, mu, contacts, load, method="interpolated")
    scale, om, width = _scales(d, mode, force_n)

    def force_fn(y):
        return aft_modal_force(model, mode, y, harmonics, n_time, n_periods)

    path = continuation_path(force_fn, mode, harmonics, force_n, scale, om, width,
                             n_steps=n_steps)
    return path._replace(status=RESULTS.first({RESULTS.liftoff: lift0}, path.status))


def coupled_hbm(shape, mu, contacts=None, load=None, mode: BladeMode = BladeMode(), force_n=20.0,
                *, harmonics=(1, 3, 5), n_time: int = N_TIME, n_periods: int = N_PERIODS,
                n_steps: int = 160) -> HBMPath:
    """Coupled HBM-AFT of the blade with the damper's contacts across the resonance at force F (N).

    harmonics: odd harmonics of the motion, e.g. (1,), (1, 3), (1, 3, 5). Compiled once per
    (harmonics, n_time, n_periods, n_steps); force_n may be traced (vmap over force levels).
    """
    from ..response import prepare_scene

    shape, mu, contacts, load, mode = prepare_scene(shape, mu, contacts, load, mode)
    return _coupled(shape, mu, contacts, load, mode, jnp.asarray(force_n, float),
                    tuple(int(h) for h in harmonics), n_time, n_periods, n_steps)


def describing_function_hbm(damper: DamperStiffness, mode: BladeMode, force_n, *,
                            n_steps: int = 160) -> HBMPath:
    """H = 1 continuation with the damper as the describing function k(psi_a) (the layered
    model's physics through the HBM solver: a check of the continuation and peak search).
    force_n: the modal force amplitude (N); amplitudes in the path are tip amplitudes (mm)."""
    scale, om, width = _scales(damper, mode, force_n)
    return continuation_path(lambda y: describing_modal_force(damper, mode, y), mode, (1,),
                             force_n, scale, om, width, n_steps=n_steps)


@partial(jax.jit, static_argnames=("harmonics", "n_time", "n_periods", "n_newton"))
def _fixed(shape, mu, contacts, load, mode, force_n, omega_ratio, y0, harmonics, n_time,
           n_periods, n_newton):
    model, _ = march_model(shape, mu, contacts, load)

    def res_y(y):
        return residual(lambda v: aft_modal_force(model, mode, v, harmonics, n_time, n_periods),
                        mode, harmonics, force_n, y, omega_ratio) / force_n

    y = _solve_fixed(res_y, y0, n_newton)
    return y, jnp.max(jnp.abs(res_y(y)))


def solve_at_frequency(shape, mu, contacts, load, mode: BladeMode, force_n, frequency_hz, y0,
                       *, harmonics=(1, 3, 5), n_time: int = N_TIME, n_periods: int = N_PERIODS,
                       n_newton: int = 2 * N_NEWTON):
    """HBM-AFT coefficients at one frequency (Newton from y0, e.g. a continuation point);
    returns (y, max |R| / F). Compiled once per (harmonics, n_time, n_periods, n_newton)."""
    from ..params import Contacts, LoadCase, prepare_inputs

    contacts = Contacts() if contacts is None else contacts
    load = LoadCase() if load is None else load
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    mode = BladeMode(*(jnp.asarray(v, float) for v in mode))
    return _fixed(shape, mu, contacts, load, mode, jnp.asarray(force_n, float),
                  jnp.asarray(frequency_hz, float) / mode.f0_hz, jnp.asarray(y0, float),
                  tuple(int(h) for h in harmonics), n_time, n_periods, n_newton)


__all__ = ["HBMPath", "coupled_hbm", "describing_function_hbm", "continuation_path",
           "aft_modal_force", "first_harmonic_phase", "describing_modal_force", "residual", "synthesize",
           "project",
           "solve_at_frequency"]
