"""The steady cycle on an elliptic platform path: any interblade phase angle, exactly.

With a non-zero interblade phase angle other than 180 degrees the right platform's motion relative
to the left one runs an ellipse, X(tau) = a Re(X_hat e^{i tau}) = a (X_r cos tau - X_i sin tau)
(MODEL.md, "Any in-plane motion"). Within a tract the contact states are fixed, so the forces are
affine in the platform motion, here in (cos tau, sin tau):

    F(tau) = F(tau0) + s_a [R_r (cos tau - cos tau0) - R_i (sin tau - sin tau0)]

with R_r, R_i the tract's rates for a unit motion along X_r and X_i (one linear solve each, the
engine's `tract.tract_rates`) and s_a = a q*/1e3 mm the path's size in the solvers' units. Every
event is then a root of c + alpha cos tau + beta sin tau = 0, in closed form: a stick pad reaching
its friction limit, a slipping pad whose slip rate reverses (it sticks again), a normal force
reaching zero (liftoff: pads that open and close are not computed yet), or the end of the arc.
The state set of each tract is chosen as on a straight path (`tract.candidate_sets`: the most stick
of the sets consistent for the platforms' direction of motion at its start), with a second-order
check where the first order leaves a tie (`choose_on_arc`).

The cycle is run period after period from tau = 0 until the forces repeat. Histories: explicit
forces at tau = 0; assembly: F_D applied at X = 0, a straight move to X(pi) = -a X_r, then
the path from tau = pi (in-phase, X_i = 0, this is `amplitude`'s assembly exactly); gross slip:
from assembly, the platforms move straight along +X_r until every pad that can slip does (the
forces then stay as they are) and the period starts from there at X(0) = a X_r: the state the
damper is left in by a large motion along the ellipse's tau = 0 direction. On a straight path
(X_i = 0) it is `amplitude`'s gross slip on that path exactly.

Outputs: k = (M_r^ - i M_i^) / a, from the first harmonics of the modal forces M_r, M_i
conjugate to the motions along X_r and X_i (`motion.motion_moment_coefficients`): in-phase it is
the paper's k; on any path pi a^2 k_Im / 1e3 is the work per cycle, which equals the energy
dissipated at the pads, sum of int T d(slip) (both computed in closed form, tested).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_int, check_range
from .amplitude import assembly_state, check_admissible, gross_slip_on_path
from .conventions import travel_mm, warn_small_rotation
from .cycle import mechanics
from .geometry import DamperShape
from .half import TRAVEL_TOL, accelerate, run_half
from .loops import bounded_loop, repeat_until, run_by_loop, zeros_of
from .motion import Motion, motion_moment_coefficients, path_parts, validate_motion
from .params import Contacts, LoadCase, above_validated_range, prepare_inputs
from .status import RESULTS, from_flags, number_repr, ok_status, status_repr
from .tract import (CANDIDATE_SETS, LIMIT_TOL, OPEN, SLIP, STICK, candidate_rates, candidate_sets,
                    pick_set)

MAX_TRACTS = 32  # per period: each pad may stick and slip twice per turn of the ellipse
MAX_PERIODS = 16  # periods run until the forces at tau = 0 repeat
CLOSE_TOL = 1e-9  # periodicity of the forces at tau = 0 (units of F_D)
TAU_TOL = 1e-12  # rad: an event nearer than this to the tract's start is the start itself
# rad ahead of a tract's start where a state set's second-order behaviour is checked, and the
# tolerance of that check (units of F_D; of s_a for slips): see `choose_on_arc`.
LOOKAHEAD = 1e-4
LOOKAHEAD_TOL = 1e-13
NO_EVENT_TAU = 1e3  # rad: "no event in this tract" (finite: masked arithmetic stays finite)
INITIAL_STATES = ("assembly", "gross_slip")

__all__ = ["Arc", "EllipticCycle", "elliptic_cycle", "elliptic_kernel", "run_arc", "MAX_TRACTS",
           "MAX_PERIODS", "INITIAL_STATES"]


class Arc(NamedTuple):
    """Tracts of a run along the ellipse (leading tract axis). Rates per mm of s along X_r and
    X_i: the forces of tract k at tau are N0 + s_a [dN_r (cos tau - cos tau0) - dN_i (sin tau -
    sin tau0)], likewise T and the slip."""

    tau0: jnp.ndarray  # (nt,) rad, where the tract starts
    dtau: jnp.ndarray  # (nt,) rad, its length
    N0: jnp.ndarray  # (nt, 3) forces at its start, units of F_D
    T0: jnp.ndarray
    dN_r: jnp.ndarray  # (nt, 3) per mm of s along X_r
    dT_r: jnp.ndarray
    dslip_r: jnp.ndarray
    dN_i: jnp.ndarray  # (nt, 3) per mm of s along X_i
    dT_i: jnp.ndarray
    dslip_i: jnp.ndarray
    state: jnp.ndarray  # (nt, 3) STICK / SLIP / OPEN
    active: jnp.ndarray  # (nt,) bool
    N_end: jnp.ndarray  # (3,) forces at the arc's end
    T_end: jnp.ndarray
    status: jnp.ndarray  # RESULTS code: ok, liftoff or singular (no consistent set; out of tracts)


def _arc_rows() -> dict:
    f, v = jax.ShapeDtypeStruct((), float), jax.ShapeDtypeStruct((3,), float)
    return dict(tau0=f, dtau=f, N0=v, T0=v, dN_r=v, dT_r=v, dslip_r=v, dN_i=v, dT_i=v, dslip_i=v,
                state=jax.ShapeDtypeStruct((3,), int), active=jax.ShapeDtypeStruct((), bool))


def _first_descent(c, alpha, beta, tau0, depth_tol=0.0):
    """rad from tau0 to the first zero of f = c + alpha cos tau + beta sin tau after tau0 where f
    falls (NO_EVENT_TAU where f never reaches zero). Guarded for gradients (double where).

    f = c + rho cos(tau - phase) dips below zero by rho - c at most: a dip of depth_tol or less is
    a touch, not a crossing (a pad that reaches its friction limit exactly at a turning point of
    the path, where rounding would split the double root into two events 1e-8 rad apart)."""
    rho2 = alpha * alpha + beta * beta
    rho_safe = jnp.sqrt(jnp.where(rho2 > 1e-300, rho2, 1.0))
    has = (rho2 > 1e-300) & (c * c < rho2) & (rho_safe - c > depth_tol)
    rho = jnp.sqrt(jnp.where(has, rho2, 1.0))
    phase = jnp.arctan2(jnp.where(has, beta, 0.0), jnp.where(has, alpha, 1.0))
    x = jnp.where(has, -c / rho, 0.0)
    # f = c + rho cos(tau - phase) falls through zero where tau - phase = arccos(-c / rho).
    t = jnp.mod(phase + jnp.arccos(x) - tau0, 2.0 * jnp.pi)
    t = jnp.where(t <= TAU_TOL, t + 2.0 * jnp.pi, t)  # a touch at tau0 itself is not an event
    return jnp.where(has, t, NO_EVENT_TAU)


def _sinusoid(f0, A, B, s_a, tau0):
    """(c, alpha, beta) of f(tau) = f0 + s_a [A (cos tau - cos tau0) - B (sin tau - sin tau0)]."""
    alpha, beta = s_a * A, -s_a * B
    return f0 - alpha * jnp.cos(tau0) - beta * jnp.sin(tau0), alpha, beta


def choose_on_arc(heading, mech_r, mech_i, N, T, s_a, tau0):
    """(TractChoice, rates along X_r, rates along X_i) of a tract starting at tau0.

    The sets consistent to first order for the direction of motion at tau0 (`tract.candidate_sets`),
    then, where several are, the second order: on a curved path a pad's slip rate or cone rate
    can be zero at a tract's start without changing sign (two pads on one flank reverse their
    slip together; only one may stick). A set is kept only if, LOOKAHEAD rad on, its stick pads
    that start on their limit are still inside the cone and its slipping pads still slide against
    their friction; among those (or, if none is, among the first-order ones) the most stick."""
    table = candidate_sets(heading, N, T, 1.0)
    Rr = candidate_rates(mech_r, table.signs, 1.0)
    Ri = candidate_rates(mech_i, table.signs, 1.0)
    dc = jnp.cos(tau0 + LOOKAHEAD) - jnp.cos(tau0)
    ds = jnp.sin(tau0 + LOOKAHEAD) - jnp.sin(tau0)
    N1 = N[None] + s_a * (Rr.dN * dc - Ri.dN * ds)  # (8 sets, 3 pads)
    T1 = T[None] + s_a * (Rr.dT * dc - Ri.dT * ds)
    mu = jnp.broadcast_to(mech_r.mu, N.shape)[None]
    slipping = jnp.asarray(CANDIDATE_SETS)
    on_limit = (jnp.abs(T) >= mech_r.mu * N - LIMIT_TOL)[None]
    stays = jnp.where(~slipping & on_limit, jnp.abs(T1) <= mu * N1 + LOOKAHEAD_TOL, True)
    slid = s_a * (Rr.dslip * dc - Ri.dslip * ds)
    slides = jnp.where(slipping, table.signs[None] * slid <= LOOKAHEAD_TOL * s_a, True)
    second = table.good & jnp.all(stays, axis=1) & jnp.all(slides, axis=1)
    best, choice = pick_set(table, jnp.where(jnp.any(second), second, table.good))
    pick = lambda x: x[best]  # noqa: E731
    return choice, jax.tree_util.tree_map(pick, Rr), jax.tree_util.tree_map(pick, Ri)


def run_arc(mech_r, mech_i, N, T, s_a, tau_start, tau_end, *, max_tracts: int = MAX_TRACTS,
            loop: str = "scan") -> Arc:
    """Tracts from tau_start to tau_end along the ellipse, from the forces (N, T) (units of F_D).
    mech_r, mech_i: the engine's constants for unit motions along X_r and X_i (`mechanics` with
    the two real motions); s_a: the path's size, mm of s. Unchecked, traceable."""
    unit = jnp.maximum(jnp.max(jnp.abs(jnp.concatenate([mech_r.nw, mech_r.tw]))),
                       jnp.max(jnp.abs(jnp.concatenate([mech_i.nw, mech_i.tw]))))
    lift0 = jnp.min(N) <= LIMIT_TOL
    init = dict(N=N, T=T, tau=jnp.asarray(tau_start, float), done=lift0, liftoff=lift0,
                failed=jnp.array(False))

    def heading(t):
        """The engine's constants for the platforms' direction of motion at t, scaled to unit
        pad speed (at a turning point of a straight path, the direction just after it)."""
        def pad_speed(v1, v2):
            return jnp.max(jnp.abs(jnp.concatenate([v1 * mech_r.nw + v2 * mech_i.nw,
                                                    v1 * mech_r.tw + v2 * mech_i.tw])))

        v1, v2 = -jnp.sin(t), -jnp.cos(t)
        turning = pad_speed(v1, v2) <= 1e-9 * unit
        v1 = jnp.where(turning, -jnp.sin(t + 1e-6), v1)
        v2 = jnp.where(turning, -jnp.cos(t + 1e-6), v2)
        speed = pad_speed(v1, v2)
        k = unit / jnp.where(speed > 0.0, speed, 1.0)
        mix = lambda x, y: k * (v1 * x + v2 * y)  # noqa: E731
        return mech_r._replace(nw=mix(mech_r.nw, mech_i.nw), tw=mix(mech_r.tw, mech_i.tw),
                               gn0=mix(mech_r.gn0, mech_i.gn0), gt0=mix(mech_r.gt0, mech_i.gt0))

    def step(carry, _):
        N, T, tau0 = carry["N"], carry["T"], carry["tau"]
        choice, Rr, Ri = choose_on_arc(heading(tau0), mech_r, mech_i, N, T, s_a, tau0)
        ok = choice.consistent & Rr.ok & Ri.ok
        stick, mu = ~choice.slipping, mech_r.mu

        def event(f0, A, B, where):  # f: a force (units of F_D) that must stay >= 0
            return jnp.where(where, _first_descent(*_sinusoid(f0, A, B, s_a, tau0), tau0,
                                                   LIMIT_TOL), NO_EVENT_TAU)

        up = event(mu * N - T, mu * Rr.dN - Rr.dT, mu * Ri.dN - Ri.dT, stick)
        down = event(mu * N + T, mu * Rr.dN + Rr.dT, mu * Ri.dN + Ri.dT, stick)
        opens = event(N, Rr.dN, Ri.dN, True)
        # A slipping pad slides against its friction force: s p' <= 0; it sticks where s p' turns
        # positive. p'(tau) = s_a (-dslip_r sin tau - dslip_i cos tau).
        s = choice.signs
        rev = jnp.where(choice.slipping, _first_descent(0.0, s_a * s * Ri.dslip, s_a * s * Rr.dslip,
                                                        tau0), NO_EVENT_TAU)
        cand = jnp.stack([up, down, opens, rev])  # (4 kinds, 3 pads)
        flat = jnp.argmin(cand.reshape(-1))
        kind, pad = flat // 3, flat % 3
        d_event = cand.reshape(-1)[flat]
        d_end = tau_end - tau0
        live = ~carry["done"] & (d_end > TAU_TOL)
        advance = live & ok
        by_end = d_end <= d_event
        dtau = jnp.where(advance, jnp.where(by_end, d_end, d_event), 0.0)
        tau1 = tau0 + dtau
        dc, ds = jnp.cos(tau1) - jnp.cos(tau0), jnp.sin(tau1) - jnp.sin(tau0)
        N1 = N + s_a * (Rr.dN * dc - Ri.dN * ds)
        T1 = T + s_a * (Rr.dT * dc - Ri.dT * ds)
        # Snap to the limit line: slipping pads stay on it, the event pad lands on it (or opens).
        T1 = jnp.where(choice.slipping, s * mu * N1, T1)
        at_event = advance & ~by_end
        hit = jnp.arange(3) == pad
        T1 = jnp.where(at_event & (kind == 0) & hit, mu * N1, T1)
        T1 = jnp.where(at_event & (kind == 1) & hit, -mu * N1, T1)
        N1 = jnp.where(at_event & (kind == 2) & hit, 0.0, N1)
        lifted = advance & ((at_event & (kind == 2)) | (jnp.min(N1) <= LIMIT_TOL))
        state = jnp.where(choice.slipping, SLIP, STICK)
        state = jnp.where(N <= LIMIT_TOL, OPEN, state)
        out = dict(tau0=tau0, dtau=dtau, N0=N, T0=T, dN_r=Rr.dN, dT_r=Rr.dT, dslip_r=Rr.dslip,
                   dN_i=Ri.dN, dT_i=Ri.dT, dslip_i=Ri.dslip, state=state, active=advance)
        new = dict(N=jnp.where(advance, N1, N), T=jnp.where(advance, T1, T),
                   tau=jnp.where(advance, jnp.where(by_end, tau_end, tau1), tau0),
                   done=carry["done"] | ~live | (live & ~ok) | lifted | (advance & by_end),
                   liftoff=carry["liftoff"] | lifted, failed=carry["failed"] | (live & ~ok))
        return new, out

    end, tr = bounded_loop(step, init, max_tracts, loop, _arc_rows())
    return Arc(**tr, N_end=end["N"], T_end=end["T"],
               status=from_flags(end["liftoff"], end["failed"] | ~end["done"]))


def _integrals(t0, t1):
    """int over [t0, t1] of cos, sin, cos^2, sin^2 and sin cos."""
    s2 = jnp.sin(2.0 * t1) - jnp.sin(2.0 * t0)
    return dict(c=jnp.sin(t1) - jnp.sin(t0), s=jnp.cos(t0) - jnp.cos(t1),
                cc=0.5 * (t1 - t0) + 0.25 * s2, ss=0.5 * (t1 - t0) - 0.25 * s2,
                cs=0.5 * (jnp.sin(t1) ** 2 - jnp.sin(t0) ** 2))


def _arc_numbers(arc: Arc, s_a, coefficients_r, coefficients_i, F_D):
    """(int M_r e^{-i tau}, int M_i e^{-i tau}, energy per pad in N mm) over the arc's tracts."""
    t0, t1 = arc.tau0, arc.tau0 + arc.dtau
    I = _integrals(t0, t1)
    act = arc.active

    def pieces(f0, A, B):  # (nt, 3) sinusoid coefficients
        return _sinusoid(f0, A, B, s_a, t0[:, None])

    cN, aN, bN = pieces(arc.N0, arc.dN_r, arc.dN_i)
    cT, aT, bT = pieces(arc.T0, arc.dT_r, arc.dT_i)

    def fourier(coefficients):
        fn, ft = coefficients
        c = cN @ fn + cT @ ft
        a = aN @ fn + aT @ ft
        b = bN @ fn + bT @ ft
        cos_part = c * I["c"] + a * I["cc"] + b * I["cs"]
        sin_part = c * I["s"] + a * I["cs"] + b * I["ss"]
        return jnp.sum(jnp.where(act, cos_part - 1j * sin_part, 0.0))

    # Energy: -F_D int T p' dtau, p' = gamma sin + delta cos.
    gamma, delta = -s_a * arc.dslip_r, -s_a * arc.dslip_i
    col = lambda key: I[key][:, None]  # noqa: E731
    tp = (cT * gamma * col("s") + cT * delta * col("c") + aT * gamma * col("cs")
          + aT * delta * col("cc") + bT * gamma * col("ss") + bT * delta * col("cs"))
    energy = -F_D * jnp.sum(jnp.where(act[:, None], tp, 0.0), axis=0)
    return fourier(coefficients_r), fourier(coefficients_i), energy


class EllipticCycle(NamedTuple):
    """The steady cycle on an elliptic platform path (a pytree). k in N mm/mrad per mrad of the
    path's amplitude a, energy in N mm per cycle, fractions of the period per pad (R1, L1, L2)."""

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    motion: Motion
    amplitude: jnp.ndarray  # a, mrad
    period: Arc  # the last period run, tau from 0 to 2 pi
    k_re: jnp.ndarray
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (3,) N mm per cycle dissipated at R1, L1, L2 (sum of int T d(slip))
    work: jnp.ndarray  # pi a^2 k_Im / 1e3: the work per cycle of the modal forces, N mm
    slip_fraction: jnp.ndarray  # (3,) of the period each pad slips
    closure: jnp.ndarray  # max force change over the last period (units of F_D)
    periods: jnp.ndarray  # periods run (int32)
    status: jnp.ndarray  # RESULTS code: ok, shakedown, liftoff, singular, not_converged

    def __repr__(self) -> str:
        return (f"EllipticCycle(status={status_repr(self.status)}, "
                f"amplitude={number_repr(self.amplitude, 'mrad')}, "
                f"k_re={number_repr(self.k_re, 'N mm/mrad')}, k_im={number_repr(self.k_im, 'N mm/mrad')}, "
                f"periods={number_repr(self.periods, fmt='.0f')})")


def elliptic_kernel(shape, mu, contacts, load, amplitude, motion: Motion, N_init=None,
                    T_init=None, *, initial="assembly", max_tracts: int = MAX_TRACTS,
                    max_periods: int = MAX_PERIODS, loop: str = "auto") -> EllipticCycle:
    """The steady cycle on the elliptic path of `motion` (a Motion with a quadrature part) at
    amplitude a (mrad): pure JAX (jit / vmap / jvp), no validation. initial: "assembly",
    "gross_slip" (module doc) or "explicit" (N_init, T_init at tau = 0, units of F_D). loop: as
    `amplitude_kernel`'s."""
    def impl(*design_and_loop):
        *design, loop = design_and_loop
        return _elliptic_impl(*design, initial=initial, max_tracts=max_tracts,
                              max_periods=max_periods, loop=loop)

    return run_by_loop(impl, (shape, mu, contacts, load, amplitude, motion, N_init, T_init), loop)


def _elliptic_impl(shape, mu, contacts, load, amplitude, motion, N_init, T_init, *, initial,
                   max_tracts, max_periods, loop) -> EllipticCycle:
    along_r, along_i = path_parts(motion)
    mech_r = mechanics(shape, mu, contacts, load, along_r)
    mech_i = mechanics(shape, mu, contacts, load, along_i)
    a_ok = amplitude > 0.0
    a = jnp.where(a_ok, amplitude, 1.0)
    s_a = travel_mm(a, load.q_star)
    two_pi = 2.0 * jnp.pi
    unreachable = jnp.array(False)
    if initial == "assembly":
        Na, Ta, ok0 = assembly_state(shape, mech_r.mu, contacts, load)
        Na = jnp.where(ok0, Na, jnp.ones(3))
        Ta = jnp.where(ok0, Ta, 0.0)
        to_start = run_half(mech_r, Na, Ta, -1.0, s_a, max_tracts=max_tracts, loop=loop)
        half = run_arc(mech_r, mech_i, to_start.N_end, to_start.T_end, s_a, jnp.pi, two_pi,
                       max_tracts=max_tracts, loop=loop)
        N0, T0 = half.N_end, half.T_end
        pre = jnp.stack([to_start.status, half.status])
    elif initial == "gross_slip":
        # Along +X_r to gross slip: the forces there hold to X(0) = a X_r (any a).
        N0, T0, ok0, reached = gross_slip_on_path(mech_r, shape, contacts, load, max_tracts, loop)
        unreachable = ok0 & ~reached
        ok0 = ok0 & reached
        pre = jnp.zeros(2, jnp.int32)
    elif initial == "explicit":
        N0, T0 = jnp.asarray(N_init, float), jnp.asarray(T_init, float)
        ok0 = jnp.min(N0) > 0.0
        pre = jnp.zeros(2, jnp.int32)
    else:
        raise ValueError(f"initial must be one of assembly, gross_slip, explicit; got {initial!r}")
    bad0 = ~ok0 | jnp.any(pre != RESULTS.ok)
    N0 = jnp.where(bad0, jnp.ones(3), N0)  # keep the masked iteration finite
    T0 = jnp.where(bad0, 0.0, T0)

    def run_period(c, k):
        arc = run_arc(mech_r, mech_i, c["N"], c["T"], s_a, 0.0, two_pi, max_tracts=max_tracts,
                      loop=loop)
        here = jnp.concatenate([c["N"], c["T"]])
        there = jnp.concatenate([arc.N_end, arc.T_end])
        gap = jnp.max(jnp.abs(there - here))
        bad = arc.status != RESULTS.ok
        # The period map is affine within one pattern of events: where the iterates converge
        # along one direction, the extrapolated fixed point is exact (`half.accelerate`).
        nxt = accelerate(mech_r.mu, c["prev"], here, there, k >= 1)
        return dict(N=nxt[:3], T=nxt[3:], prev=here, arc=arc, gap=gap,
                    closed=(gap <= CLOSE_TOL) & ~bad, stop=(gap <= CLOSE_TOL) | bad,
                    periods=c["periods"] + 1)

    empty = Arc(**zeros_of(_arc_rows(), max_tracts), N_end=jnp.zeros(3), T_end=jnp.zeros(3),
                status=ok_status())
    init = dict(N=N0, T=T0, prev=jnp.zeros(6), arc=empty, gap=jnp.asarray(jnp.inf), closed=jnp.array(False),
                stop=bad0 | ~a_ok, periods=jnp.array(0, jnp.int32))
    end = repeat_until(run_period, init, max_periods, loop, lambda c: c["stop"])
    arc = end["arc"]
    # The mechanics hold each part's pad motion already.
    coef_r = motion_moment_coefficients(mech_r.nw, mech_r.tw, load)
    coef_i = motion_moment_coefficients(mech_i.nw, mech_i.tw, load)
    m_r, m_i, energy = _arc_numbers(arc, s_a, coef_r, coef_i, load.F_D)
    k = (m_r - 1j * m_i) / (jnp.pi * a)
    work = jnp.pi * a * a * jnp.imag(k) / 1e3
    slip_fraction = jnp.sum(jnp.where(arc.active[:, None] & (arc.state == SLIP), arc.dtau[:, None],
                                      0.0), axis=0) / two_pi
    liftoff = ((~ok0 & ~unreachable) | jnp.any(pre == RESULTS.liftoff)
               | (arc.status == RESULTS.liftoff))
    failed = jnp.any(pre == RESULTS.singular) | (arc.status == RESULTS.singular) | ~a_ok
    status = jnp.zeros((), jnp.int32)
    status = RESULTS.promote(status, above_validated_range(mech_r.kn, mech_r.kt), RESULTS.ill_conditioned)
    status = RESULTS.promote(status, unreachable, RESULTS.unreachable)
    status = RESULTS.promote(status, liftoff, RESULTS.liftoff)
    status = RESULTS.promote(status, failed, RESULTS.singular)
    status = RESULTS.promote(status, ~end["closed"], RESULTS.not_converged)
    # Elastic (shakedown) where the pads' sliding over the period is rounding: bounded by
    # sum dtau s_a (|dslip_r| + |dslip_i|) against the path's length 2 pi s_a (the straight
    # engine's rule, TRAVEL_TOL of the travel).
    slid = jnp.sum(jnp.where(arc.active[:, None], arc.dtau[:, None]
                             * (jnp.abs(arc.dslip_r) + jnp.abs(arc.dslip_i)), 0.0))
    status = RESULTS.promote(status, slid <= TRAVEL_TOL * two_pi, RESULTS.shakedown)
    valid = RESULTS.valid(status)
    zero = lambda v: jnp.where(valid, v, jnp.zeros_like(v))  # noqa: E731
    return EllipticCycle(shape, mech_r.mu, contacts, load, motion, jnp.asarray(amplitude, float),
                         arc, zero(jnp.real(k)), zero(jnp.imag(k)), zero(energy), zero(work),
                         zero(slip_fraction), end["gap"], end["periods"], status)


_kernel = jax.jit(elliptic_kernel, static_argnames=("initial", "max_tracts", "max_periods", "loop"))


def elliptic_cycle(shape: DamperShape, mu, amplitude_mrad, motion: Motion,
                   contacts: Contacts = Contacts(), load: LoadCase = LoadCase(), *,
                   initial="assembly", max_tracts: int = MAX_TRACTS,
                   max_periods: int = MAX_PERIODS) -> EllipticCycle:
    """The steady cycle on an elliptic platform path (`interblade_motion` at a phase angle other
    than 0 or 180 degrees, or `general_motion` of a complex X_hat) at amplitude a (mrad).

    initial: "assembly" (F_D applied at X = 0, a straight move to X(pi) = -a X_r, then the path
    from tau = pi), "gross_slip" (from assembly a straight move along +X_r until every pad that
    can slip does, then the path from X(0) = a X_r) or an explicit (N, T) pair at tau = 0 (units
    of F_D, in equilibrium with F_D).
    Returns an EllipticCycle; its status says whether its numbers are valid (ok, shakedown) or
    not (liftoff: a pad opened, which is not computed yet; singular; not_converged). Inputs are
    checked here (ValueError naming the parameter and its range); `elliptic_kernel` is the
    unchecked form for jit / vmap / jvp.
    """
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    warn_small_rotation(amplitude_mrad, "psi_a", stacklevel=3)
    motion = validate_motion(motion)
    if motion.quadrature is None:
        raise ValueError("motion must be elliptic for elliptic_cycle (a straight path: use "
                         "amplitude_cycle(..., motion=...))")
    check_int("max_tracts", max_tracts, 1)
    check_int("max_periods", max_periods, 1)
    N_init = T_init = None
    if isinstance(initial, str):
        if initial not in INITIAL_STATES:
            raise ValueError(f"initial must be assembly, gross_slip or an (N, T) pair of (3,) "
                             f"arrays on an elliptic path; got {initial!r}")
        mode = initial
    else:
        N_init, T_init = (np.asarray(v, float) for v in initial)
        res, cone, n_min = (float(v) for v in check_admissible(shape, mu, N_init, T_init))
        if not (res <= 1e-6 and cone <= 1e-9 and n_min >= 0.0):
            raise ValueError("initial (N, T) must be admissible: in equilibrium with F_D (residual "
                             "<= 1e-6 F_D), N >= 0 and |T| <= mu N")
        mode = "explicit"
    return _kernel(shape, mu, contacts, load, jnp.asarray(float(amplitude_mrad)), motion, N_init,
                   T_init, initial=mode, max_tracts=max_tracts, max_periods=max_periods)

