"""The whole lumped ring with N explicit dampers, integrated in time: the independent check of the
cyclic reduction (`jaxdamp.response.modes.nodal_scene`) and of the damper's first-harmonic
stiffness on its path.

The ring is `lumped_disk`'s (2N degrees of freedom: each blade's root rotation theta_j in rad and
tip displacement x_j in mm; its full mass and stiffness matrices, no cyclic reduction) under the
travelling engine-order tip force F_j(t) = F cos(omega t + j 2 pi e / N), N. One damper sits
between each pair of neighbours, all identical: damper j (between blade j and j+1, modulo N) sees
the relative platform motion

    X_j(t) = theta_{j+1}(t) d_L - theta_j(t) d_R      (u mm, v mm, theta mrad; theta_j in mrad)

with d_L, d_R the left-hand and right-hand platform's motion at D per mrad of the blade's rotation
(the paper's Fig. 4, `conventions.platform_directions`): two scalar coordinates per damper, driven
the way `ellipse_march` drives its two components (each pad's platform motion is u1 nw_1 + u2 nw_2
with u = travel_mm(theta in mrad)). Each damper is the quasi-static, massless contact model of
`timemarch` (three Jenkins contacts, Newton with return mapping; no tracts, no harmonic balance).
Its modal forces on the two coordinates (M_1 on theta_{j+1}, M_2 on theta_j, N mm: the work of the
contact forces per rad of each blade's rotation, `motion.motion_moment_coefficients`) act on the
blades' roots.

Damping: viscous C = (eta / omega) K, exactly the loss factor eta of the whole stiffness on the
first harmonic at the forcing frequency (as in `time_integration`).

Scheme: classical RK4 on the 4N states, fixed step (steps_per_period per forcing period), in
`jax.lax.scan`. At an RK stage each damper's forces are the return-mapped response from its
committed contact state at the step start (not committed); the state is committed at the step end.

History: F_D is applied with the platforms at rest (`timemarch.assemble`, every damper alike).
From rest (x0 = v0 = 0) the vibration then grows under the forcing. A start elsewhere (x0, v0:
e.g. near the expected steady state, to shorten the transient) first moves each damper's
platforms quasi-statically along a straight line from rest to their starting positions
(n_premove steps), then integrates: assembly, a straight move, then the vibration at full size,
as the reduction's cycles from assembly (`amplitude_cycle(initial="assembly")`,
`elliptic_cycle`) assume.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int, check_range
from ..conventions import MRAD_PER_RAD, platform_directions
from ..motion import Motion, motion_moment_coefficients, pad_motion
from ..params import prepare_inputs
from ..status import RESULTS, number_repr, status_repr
from .lumped_disk import LumpedDisk, full_matrices
from .timemarch import MAX_NEWTON, NEWTON_TOL, assemble, march_model, newton, respond

__all__ = ["RingResponse", "ring_response", "travelling_force", "linear_ring_response"]


class RingResponse(NamedTuple):
    """The ring after n_periods forcing periods (displacements in mm, moments in N mm).

    amplitude_mm: (N,) first-harmonic tip amplitude of each blade over the last period.
    phase_rad: (N,) its phase (x_j ~ amplitude cos(omega t + phase)).
    spread: (max - min) / mean of amplitude_mm over the blades.
    change: the largest relative change of a blade's first harmonic between the last two periods
        (a steady-state indicator).
    history_mm: (n_periods, N) complex first harmonic of each tip per period (x_j ~
        Re(history e^{i omega t})), mm: its convergence shows the transient.
    tip_mm: (steps_per_period, N) tip displacements over the last period.
    damper_moment: (steps_per_period, N, 2) each damper's modal forces (M_1 on theta_{j+1},
        M_2 on theta_j) over the last period, N mm; zeros without dampers.
    newton_failures: steps whose Newton iterations missed the tolerance (any damper).
    status: ok, liftoff (a pad opened), or not_converged (Newton failures).
    root_mrad: (steps_per_period, N) each blade's root rotation over the last period, mrad (with
        damper_moment: the dampers' first-harmonic stiffness as the ring has it).
    """

    amplitude_mm: jnp.ndarray
    phase_rad: jnp.ndarray
    spread: jnp.ndarray
    change: jnp.ndarray
    history_mm: jnp.ndarray
    tip_mm: jnp.ndarray
    damper_moment: jnp.ndarray
    newton_failures: jnp.ndarray
    status: jnp.ndarray
    root_mrad: jnp.ndarray

    def __repr__(self) -> str:
        a = np.asarray(self.amplitude_mm)
        return (f"RingResponse(status={status_repr(self.status)}, {a.size} blades, tip amplitude "
                f"{number_repr(a.mean(), 'mm')} mean, spread {float(self.spread):.2e}, "
                f"change {float(self.change):.2e})")


def travelling_force(n_blades: int, engine_order: int, force_n=1.0) -> np.ndarray:
    """(N,) complex tip-force amplitudes of the engine-order excitation, F_j = F e^{i j 2 pi e/N}
    (F_j(t) = Re(F_j e^{i omega t}), N)."""
    j = np.arange(n_blades)
    return float(force_n) * np.exp(1j * 2.0 * np.pi * int(engine_order) * j / n_blades)


def linear_ring_response(disk: LumpedDisk, engine_order: int, force_n, frequency_hz) -> np.ndarray:
    """(2N,) complex steady response of the ring without dampers (theta_j rad, x_j mm interleaved)
    to the engine-order tip force: the full complex solve (K (1 + i eta) - omega^2 M) y = F."""
    M, K = full_matrices(disk)
    omega = 2.0 * np.pi * float(frequency_hz)
    f = np.zeros(2 * disk.n_blades, complex)
    f[1::2] = travelling_force(disk.n_blades, engine_order, force_n)
    return np.linalg.solve(K * (1.0 + 1j * float(disk.eta)) - omega ** 2 * M, f)


class _Dampers(NamedTuple):
    """The ring's dampers' constant data (one model, shared)."""

    m0: object  # MarchModel from zero forces (the assembly's), nw / tw replaced per step
    nw: jnp.ndarray  # (2, 3) each pad's platform normal motion per mm of u1, u2
    tw: jnp.ndarray  # (2, 3)
    fn: jnp.ndarray  # (2, 3) modal force of each coordinate per unit normal force (units of F_D)
    ft: jnp.ndarray  # (2, 3)


def _damper_forces(d: _Dampers, u, q, p, max_newton):
    """Return-mapped forces of every damper at platform coordinates u (N, 2) (mm of travel) from
    committed positions q (N, 3) and slips p (N, 3): (q, p, M (N, 2) N mm, newton ok, closed)."""

    def one(u_j, q_j, p_j):
        here = d.m0._replace(nw=u_j @ d.nw, tw=u_j @ d.tw)

        def residual(x):
            r = respond(here, x, 1.0, p_j)
            return r.R, r.J

        qn, res, _ = newton(residual, q_j, max_newton)
        r = respond(here, qn, 1.0, p_j)
        M = d.fn @ r.N + d.ft @ r.T
        return qn, r.p, M, res <= NEWTON_TOL, jnp.all(r.closed)

    return jax.vmap(one)(u, q, p)


@partial(jax.jit, static_argnames=("n_periods", "steps_per_period", "n_load", "n_premove",
                                   "with_dampers", "max_newton"))
def _integrate(shape, mu, contacts, load, left, right, mass, stiffness, eta, force, omega, y0, v0,
               n_periods: int, steps_per_period: int, n_load: int, n_premove: int,
               with_dampers: bool, max_newton: int):
    n = force.shape[0]
    travel = load.q_star / MRAD_PER_RAD  # mm of travel per mrad
    m, _ = march_model(shape, mu, contacts, load, left)
    nw1, tw1 = pad_motion(shape, left, load.q_star)
    nw2, tw2 = pad_motion(shape, right, load.q_star)
    fn1, ft1 = motion_moment_coefficients(nw1, tw1, load)
    fn2, ft2 = motion_moment_coefficients(nw2, tw2, load)
    m0, s, ok0 = assemble(m, n_load, max_newton)
    d = _Dampers(m0, jnp.stack([nw1, nw2]), jnp.stack([tw1, tw2]), jnp.stack([fn1, fn2]),
                 jnp.stack([ft1, ft2]))
    inv_mass = 1.0 / mass
    damping = eta / omega * stiffness
    dt = 2.0 * jnp.pi / omega / steps_per_period

    def coords(y):
        theta = y[0::2] * MRAD_PER_RAD  # mrad
        return travel * jnp.stack([jnp.roll(theta, -1), theta], -1)  # (N, 2): blade j+1, blade j

    def root_moments(M):
        # M[:, 0] acts on blade j+1's rotation, M[:, 1] on blade j's (both per rad).
        return jnp.roll(M[:, 0], 1) + M[:, 1]

    def dampers(y, q, p):
        if not with_dampers:
            return q, p, jnp.zeros((n, 2)), jnp.ones(n, bool), jnp.ones(n, bool)
        return _damper_forces(d, coords(y), q, p, max_newton)

    def accel(t, y, v, M):
        f = jnp.zeros(2 * n).at[1::2].set(jnp.real(force * jnp.exp(1j * omega * t)))
        f = f.at[0::2].add(-root_moments(M))
        return inv_mass * (f - damping @ v - stiffness @ y)

    q = jnp.broadcast_to(s.q, (n, 3))
    p = jnp.broadcast_to(s.p, (n, 3))
    ok, closed_all = ok0, jnp.array(True)
    if with_dampers:
        # Quasi-static straight move of every damper from rest to the start (module docstring).
        def move(c, lam):
            q, p, ok, cl = c
            q, p, _, good, closed = _damper_forces(d, lam * coords(y0), q, p, max_newton)
            return (q, p, ok & jnp.all(good), cl & jnp.all(closed)), None

        lams = jnp.arange(1, n_premove + 1, dtype=float) / n_premove
        (q, p, ok, closed_all), _ = jax.lax.scan(move, (q, p, ok, closed_all), lams)
    _, _, M_start, _, _ = dampers(y0, q, p)

    def rk4(carry, k):
        y, v, q, p, M, fails, cl = carry
        t = k * dt
        a1 = accel(t, y, v, M)
        y2, v2 = y + 0.5 * dt * v, v + 0.5 * dt * a1
        _, _, M2, g2, c2 = dampers(y2, q, p)
        a2 = accel(t + 0.5 * dt, y2, v2, M2)
        y3, v3 = y + 0.5 * dt * v2, v + 0.5 * dt * a2
        _, _, M3, g3, c3 = dampers(y3, q, p)
        a3 = accel(t + 0.5 * dt, y3, v3, M3)
        y4, v4 = y + dt * v3, v + dt * a3
        _, _, M4, g4, c4 = dampers(y4, q, p)
        a4 = accel(t + dt, y4, v4, M4)
        yn = y + dt / 6.0 * (v + 2 * v2 + 2 * v3 + v4)
        vn = v + dt / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)
        qn, pn, Mn, gn, cn = dampers(yn, q, p)
        bad = ~(jnp.all(g2) & jnp.all(g3) & jnp.all(g4) & jnp.all(gn))
        cl = cl & jnp.all(c2) & jnp.all(c3) & jnp.all(c4) & jnp.all(cn)
        return (yn, vn, qn, pn, Mn, fails + bad, cl), (yn[1::2], Mn, yn[0::2])

    tau = 2.0 * jnp.pi * jnp.arange(1, steps_per_period + 1) / steps_per_period
    e = jnp.exp(-1j * tau)

    def period(carry, i):
        ks = i * steps_per_period + jnp.arange(steps_per_period, dtype=float)
        carry, (xs, Ms, ths) = jax.lax.scan(rk4, carry, ks)
        # x_j(tau_k) sampled at t = (i steps + k + 1) dt, i.e. omega t = tau_k mod 2 pi.
        first = 2.0 / steps_per_period * (e @ xs)
        return carry, (first, xs, Ms, ths)

    init = (y0, v0, q, p, M_start, jnp.where(ok, 0, 1), closed_all)
    carry, (firsts, xs, Ms, ths) = jax.lax.scan(period, init, jnp.arange(n_periods, dtype=float))
    fails, closed_all = carry[5], carry[6]
    amp = jnp.abs(firsts[-1])
    change = jnp.max(jnp.abs(firsts[-1] - firsts[-2]) / jnp.maximum(amp, 1e-300))
    spread = (jnp.max(amp) - jnp.min(amp)) / jnp.mean(amp)
    status = RESULTS.first({RESULTS.liftoff: ~closed_all, RESULTS.not_converged: fails != 0})
    return RingResponse(amp, jnp.angle(firsts[-1]), spread, change, firsts, xs[-1],
                        Ms[-1], fails, status, ths[-1] * MRAD_PER_RAD)


def ring_response(shape, mu, contacts, load, disk: LumpedDisk, engine_order: int, force_n,
                  frequency_hz, *, h_c_mm: float, h_l_mm: float, x0=None, v0=None,
                  n_periods: int = 200, steps_per_period: int = 128, n_load: int = 16,
                  n_premove: int = 32, dampers: bool = True, force_phase_rad: float = 0.0,
                  max_newton: int = MAX_NEWTON) -> RingResponse:
    """The ring's response after n_periods periods of the engine-order tip force F (N) at
    frequency_hz (module docstring). Damper: shape, mu, contacts, load as `jaxdamp.base_cycle`
    (checked), q* from the load; h_c_mm the blades' rotation centre below D, h_l_mm the damper's
    left flank (its size). x0, v0: (2N,) start (theta_j rad, x_j mm interleaved; velocities per
    s), default rest. dampers=False: the bare ring (linear). force_phase_rad: the force's phase
    at t = 0 (F_j(t) = F cos(omega t + j 2 pi e / N + phase)), so that a start x0, v0 on a steady
    solution can be taken at any point of its period (e.g. where the damper's path is at X(pi),
    as the reduction's history from assembly has it)."""
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    if not isinstance(disk, LumpedDisk):
        raise ValueError(f"disk must be a LumpedDisk; got {type(disk).__name__}")
    n = check_int("n_blades", disk.n_blades, 2)
    e = check_int("engine_order", engine_order, 0)
    check_range("force_n", force_n, 0.0, np.inf, hi_open=True, unit="N")
    check_range("frequency_hz", frequency_hz, 0.0, np.inf, lo_open=True, hi_open=True, unit="Hz")
    check_range("h_c_mm", h_c_mm, -np.inf, np.inf, lo_open=True, hi_open=True, unit="mm")
    check_range("h_l_mm", h_l_mm, 0.0, 1e4, lo_open=True, unit="mm")
    check_range("force_phase_rad", force_phase_rad, -np.inf, np.inf, lo_open=True, hi_open=True,
                unit="rad")
    q_star = float(np.asarray(load.q_star))
    mass, stiffness = full_matrices(disk)
    left, right = platform_directions(q_star, h_c_mm)
    per_mrad = np.array([1.0, 1.0, MRAD_PER_RAD]) / MRAD_PER_RAD  # (mm, mm, rad) per rad -> per mrad
    # Damper j's coordinates: u1 along blade j+1's left platform, u2 along minus blade j's right.
    along_left = Motion(jnp.asarray(left * per_mrad), jnp.asarray(float(h_l_mm)))
    along_right = Motion(jnp.asarray(-right * per_mrad), jnp.asarray(float(h_l_mm)))
    y0 = np.zeros(2 * n) if x0 is None else np.asarray(x0, float)
    v0 = np.zeros(2 * n) if v0 is None else np.asarray(v0, float)
    for name, v in (("x0", y0), ("v0", v0)):
        if v.shape != (2 * n,) or not np.all(np.isfinite(v)):
            raise ValueError(f"{name} must be {2 * n} finite numbers (theta_j rad, x_j mm); got "
                             f"shape {v.shape}")
    return _integrate(shape, mu, contacts, load, along_left, along_right, jnp.asarray(np.diag(mass)),
                      jnp.asarray(stiffness), jnp.asarray(float(disk.eta)),
                      jnp.asarray(travelling_force(n, e, force_n)
                                  * np.exp(1j * float(force_phase_rad))),
                      jnp.asarray(2.0 * np.pi * float(frequency_hz)), jnp.asarray(y0),
                      jnp.asarray(v0), check_int("n_periods", n_periods, 2),
                      check_int("steps_per_period", steps_per_period, 4),
                      check_int("n_load", n_load, 1), check_int("n_premove", n_premove, 1),
                      bool(dampers), check_int("max_newton", max_newton, 1))
