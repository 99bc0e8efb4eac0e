"""The steady cycle on an elliptic platform path: any interblade phase angle, exactly.

With a non-zero interblade phase angle other than 180 degrees the right platform's motion relative
to the left one runs an ellipse, X(tau) = a Re(X_hat e^{i tau}) = a (X_r cos tau - X_i sin tau)
(MODEL.md, "Any in-plane motion"). Within a tract the contact states are fixed, so the forces are
affine in the platform motion, here in (cos tau, sin tau):

    F(tau) = F(tau0) + s_a [R_r (cos tau - cos tau0) - R_i (sin tau - sin tau0)]

with R_r, R_i the tract's rates for a unit motion along X_r and X_i and s_a = a q*/1e3 mm the
path's size in the solvers' units. The tracts run on the tract engine (`jaxdamp.engine`, an
`Ellipse` path): every event is a root of c + alpha cos tau + beta sin tau = 0, in closed form (a
stick pad reaching its friction limit, a slipping pad whose slip rate reverses, a pad opening, an
open pad closing, the end of the period). Any pad set: the paper's curved-flat damper (R1 | L1, L2)
or a wedge (R1, R2 | L1, L2, `DamperShape.br2_over_hr`). Pads that open and close are states of
the cycle (`open_fraction`); a damper that no set of closed pads can hold is `unseated`.

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

import functools

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_int, check_range, check_scalar, check_values
from .amplitude import explicit_start
from .conventions import (CENTRIFUGAL_LOAD, MRAD_PER_RAD, interblade_direction, travel_mm,
                          warn_small_rotation)
from .engine import TRAVEL_TOL, Pads, Tracts, assemble, end_set, to_gross_slip, tract_rows
from .geometry import DamperShape, is_wedge, pad_names
from .ellipse_legs import leg_machine, periods
from .lanes import Legs, iterate_lanes
from .linalg import combine
from .loops import check_loop, values_by_replay
from .paths import sinusoid
from .motion import (Motion, as_ellipse, motion_moment_coefficients, pad_motion, path_parts,
                     validate_motion)
from .params import Contacts, LoadCase, above_validated_range, prepare_inputs
from .runtime import run_program
from .statics import contact_columns
from .status import RESULTS, number_repr, status_repr
from .tract import OPEN, SLIP, STICK

MAX_TRACTS = 32  # per period: each pad may stick and slip twice per turn of the ellipse
MAX_PERIODS = 16  # periods run until the forces at tau = 0 repeat
INITIAL_STATES = ("assembly", "gross_slip")

__all__ = ["EllipticCycle", "elliptic_cycle", "elliptic_kernel", "interblade_sweep", "sweep_program", "path_pads", "period_fourier",
           "GrossSlipAmplitude", "gross_slip_amplitude_kernel", "along_line",
           "MAX_TRACTS", "MAX_PERIODS", "INITIAL_STATES"]


def path_pads(shape, mu, contacts, load, parts) -> Pads:
    """The tract engine's constants (`engine.Pads`) of one design, curved-flat or wedge, for the
    straight motions `parts` (one basis direction each: X_r, or X_r and X_i of an ellipse).
    Unchecked, traceable."""
    a, c, _ = contact_columns(shape)
    n_pads = a.shape[0]
    per_pad = lambda k: jnp.broadcast_to(jnp.asarray(k, float), (n_pads,)) / load.F_D  # noqa: E731
    motions = [pad_motion(shape, m, load.q_star) for m in parts]
    return Pads(a, c, per_pad(contacts.kn), per_pad(contacts.kt), jnp.asarray(mu, float),
                jnp.stack([m[0] for m in motions]), jnp.stack([m[1] for m in motions]))


def along_line(pads: Pads, sign) -> Pads:
    """The pads on the straight line along sign * X_r (the first basis direction)."""
    return pads._replace(nw=sign * pads.nw[:1], tw=sign * pads.tw[:1])


def _integrals(t0, t1):
    """int over [t0, t1] of cos, sin, cos^2, sin^2 and sin cos."""
    s2 = jnp.sin(2.0 * t1) - jnp.sin(2.0 * t0)
    return dict(c=jnp.sin(t1) - jnp.sin(t0), s=jnp.cos(t0) - jnp.cos(t1),
                cc=0.5 * (t1 - t0) + 0.25 * s2, ss=0.5 * (t1 - t0) - 0.25 * s2,
                cs=0.5 * (jnp.sin(t1) ** 2 - jnp.sin(t0) ** 2))


def _force_pieces(arc: Tracts, s_a):
    """Each tract's N and T as sinusoids c + a cos tau + b sin tau: ((cN, aN, bN), (cT, aT, bT)),
    (nt, P) each. An open pad's N is its virtual gap force: it carries no force on the
    platforms, so it is zero here."""
    t0 = arc.p0

    def pieces(f0, rates):  # rates (nt, 2, P): along X_r, X_i
        return sinusoid(f0, rates[:, 0], rates[:, 1], s_a, t0[:, None])

    closed = arc.state != OPEN  # (nt, P)
    return (pieces(jnp.where(closed, arc.N0, 0.0), jnp.where(closed[:, None], arc.dN, 0.0)),
            pieces(arc.T0, arc.dT))


def period_fourier(arc: Tracts, s_a, coefficients):
    """int F e^{-i tau} dtau over a period's tracts of the force F = sum of N fn + T ft,
    coefficients = (fn, ft) per unit normal / tangential force of each pad (units of F_D); s_a:
    the path's size, mm. Unchecked, traceable."""
    return _fourier(arc, _force_pieces(arc, s_a), _integrals(arc.p0, arc.p0 + arc.dp),
                    coefficients)


def _fourier(arc: Tracts, pieces, I, coefficients):
    """`period_fourier` from the tracts' force sinusoids (`_force_pieces`) and their integrals."""
    (cN, aN, bN), (cT, aT, bT) = pieces
    fn, ft = coefficients
    # Sums over the pads, not six tiny dots (XLA's own kernels on CPU: 2-5 % of a batch of 16).
    c = combine(fn, cN.T) + combine(ft, cT.T)
    a = combine(fn, aN.T) + combine(ft, aT.T)
    b = combine(fn, bN.T) + combine(ft, bT.T)
    cos_part = c * I["c"] + a * I["cc"] + b * I["cs"]
    sin_part = c * I["s"] + a * I["cs"] + b * I["ss"]
    return jnp.sum(jnp.where(arc.active, cos_part - 1j * sin_part, 0.0))


def _arc_numbers(arc: Tracts, s_a, coefficients_r, coefficients_i, F_D):
    """(int M_r e^{-i tau}, int M_i e^{-i tau}, energy per pad in N mm) over a period's tracts."""
    t0, t1 = arc.p0, arc.p0 + arc.dp
    I = _integrals(t0, t1)
    act = arc.active
    pieces = _force_pieces(arc, s_a)
    _, (cT, aT, bT) = pieces

    # Energy: -F_D int T p' dtau, p' = gamma sin + delta cos.
    gamma, delta = -s_a * arc.dslip[:, 0], -s_a * arc.dslip[:, 1]
    col = lambda key: I[key][:, None]  # noqa: E731
    tp = (cT * gamma * col("s") + cT * delta * col("c") + aT * gamma * col("cs")
          + aT * delta * col("cc") + bT * gamma * col("ss") + bT * delta * col("cs"))
    energy = -F_D * jnp.sum(jnp.where(act[:, None], tp, 0.0), axis=0)
    return (_fourier(arc, pieces, I, coefficients_r), _fourier(arc, pieces, I, coefficients_i),
            energy)


class EllipticCycle(NamedTuple):
    """The steady cycle on an elliptic platform path (a pytree). k in N mm/mrad per mrad of the
    path's amplitude a, energy in N mm per cycle, fractions of the period per pad (in
    `geometry.pad_names` order: R1, L1, L2, or R1, R2, L1, L2 for a wedge)."""

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    motion: Motion
    amplitude: jnp.ndarray  # a, mrad
    period: Tracts  # the last period run, tau (p) from 0 to 2 pi
    k_re: jnp.ndarray
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (P,) N mm per cycle dissipated at each pad (sum of int T d(slip))
    work: jnp.ndarray  # pi a^2 k_Im / 1e3: the work per cycle of the modal forces, N mm
    slip_fraction: jnp.ndarray  # (P,) of the period each pad slips
    open_fraction: jnp.ndarray  # (P,) of the period each pad is open (N = 0, springs released)
    closure: jnp.ndarray  # max force change over the last period (units of F_D)
    periods: jnp.ndarray  # periods run (int32)
    # RESULTS code: ok, shakedown, unseated, singular, not_converged, unreachable, ill_conditioned
    status: jnp.ndarray

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
    `amplitude_kernel`'s, but "auto" differentiates a replay of the value pass's choices
    (`loops.values_by_replay`: one 3x3 solve per tract instead of a choice among every set) and
    "forward" replays them in while loops (forward mode only: the periods and tracts the cycle
    took, not max_periods of max_tracts)."""
    impl = functools.partial(elliptic_impl, initial=initial, max_tracts=max_tracts,
                             max_periods=max_periods)
    args = (shape, mu, contacts, load, amplitude, motion, N_init, T_init)
    check_loop(loop)
    if loop in ("auto", "forward"):
        return values_by_replay(impl, *args, replay_loop="scan" if loop == "auto" else "while")
    return impl(*args, loop=loop)


def elliptic_impl(shape, mu, contacts, load, amplitude, motion, N_init, T_init, *, initial,
                   max_tracts, max_periods, loop, record=False, tape=None):
    """The cycle (loop "scan" or "while"); record: (cycle, tape), the tape of every run's choices;
    tape: replay those choices (`engine.run(replay=...)`; loop "scan" or "while" as for values)."""

    def recorded(part):  # what the value pass recorded for this part of the cycle (a replay)
        return None if tape is None else tape[part]

    along_r, along_i = path_parts(motion)
    pads = path_pads(shape, mu, contacts, load, (along_r, along_i))
    n_pads = pads.kn.shape[0]
    a_ok = jnp.asarray(amplitude, float) > 0.0  # a Python number too (~ of a bool is an int)
    a = jnp.where(a_ok, amplitude, 1.0)
    s_a = travel_mm(a, load.q_star)
    two_pi = 2.0 * jnp.pi
    unreachable = jnp.array(False)
    no_runs = jnp.zeros(2, jnp.int32)
    assembly_tape = None
    if initial in ("assembly", "gross_slip"):
        got = assemble(pads, CENTRIFUGAL_LOAD, record, recorded("assembly"))
        Na, Ta, ok0 = got[:3]
        assembly_tape = got[3] if record else None
        Na = jnp.where(ok0, Na, jnp.ones(n_pads))  # keep the masked runs finite
        Ta = jnp.where(ok0, Ta, 0.0)
    # Assembly's move and half period from tau = pi run as the periods' loop's first legs: one
    # compiled tract run in the program (the half period's joining cut one cycle's compile from
    # 6.5-7.3 to 4.9-5.9 s; the move's, on an ellipse of zero width: `ellipse_legs.MOVE_TAU`).
    pre_legs = 2 if initial == "assembly" else 0
    stuck = (jnp.full(n_pads, STICK), jnp.array(True))  # a run's first proposal: every pad stuck
    if initial == "assembly":
        N0, T0 = Na, Ta
        pre = no_runs
        # The move starts stuck; the ellipse's first tract proposes the move's last set, slipping
        # pads slipping (60sym's batch of 16 1.12x faster than proposed stuck, random batches
        # alike; 2026-12-02): each leg starts in the set the previous one ended in.
        pre_set = stuck
        pre_tape = None
    elif initial == "gross_slip":
        # Along +X_r to gross slip: the forces there hold to X(0) = a X_r (any a).
        got = to_gross_slip(along_line(pads, 1.0), Na, Ta, ok0, max_tracts=max_tracts,
                            loop=loop, record=record, replay=recorded("pre"), start_set=stuck)
        up, reached = got[:2]
        pre_tape = got[2] if record else None
        unreachable = ok0 & ~reached
        ok0 = ok0 & reached
        N0, T0 = up.N_end, up.T_end
        pre = no_runs
        pre_set = end_set(up)
    elif initial == "explicit":
        N0, T0 = jnp.asarray(N_init, float), jnp.asarray(T_init, float)
        ok0 = jnp.min(N0) > 0.0
        pre = no_runs
        pre_set = (stuck[0], jnp.array(False))
        pre_tape = None
    else:
        raise ValueError(f"initial must be one of assembly, gross_slip, explicit; got {initial!r}")
    bad0 = ~ok0 | jnp.any(pre != RESULTS.ok)
    N0 = jnp.where(bad0, jnp.ones(n_pads), N0)  # keep the masked iteration finite
    T0 = jnp.where(bad0, 0.0, T0)

    # Rounds of one period; the period map is affine within one pattern of events: where the
    # iterates converge along one or two directions, the extrapolated fixed point is exact
    # (`periodic.accelerate`).
    data = dict(pads=pads, s_a=s_a, N0=N0, T0=T0, mu=pads.mu, pre_state=pre_set[0],
                pre_known=jnp.asarray(pre_set[1]), stop0=bad0 | ~a_ok)
    run_periods = functools.partial(periods, pre_legs=pre_legs, max_tracts=max_tracts,
                                    max_periods=max_periods)
    if loop == "while" and not record and tape is None:
        # Values: a batch's cycles on a pool of lanes, each cycle's periods one loop over their
        # tracts (`lanes.iterate_lanes`); one cycle alone by the nested loops (periods of runs),
        # measured 10-40 % faster alone (docs/motions.md, "Cost").
        lane = Legs(leg_machine(max_tracts, pre_legs), tract_rows(n_pads, 2), legs_per_round=1,
                    pre_legs=pre_legs, max_rounds=max_periods, max_tracts=max_tracts)

        def alone(d):
            end, arc, _ = run_periods(d, loop="while")
            return dict(end, records=None), arc  # as `Legs.result`

        end, arc = iterate_lanes(lane, data, alone=alone)
        legs_tape = None
    else:
        end, arc, legs_tape = run_periods(data, loop=loop, record=record, recorded=recorded("legs"))
    coef_r = motion_moment_coefficients(pads.nw[0], pads.tw[0], load)
    coef_i = motion_moment_coefficients(pads.nw[1], pads.tw[1], load)
    m_r, m_i, energy = _arc_numbers(arc, s_a, coef_r, coef_i, load.F_D)
    k = (m_r - 1j * m_i) / (jnp.pi * a)
    work = jnp.pi * a * a * jnp.imag(k) / 1e3
    share = lambda state: jnp.sum(jnp.where(arc.active[:, None] & (arc.state == state),  # noqa: E731
                                            arc.dp[:, None], 0.0), axis=0) / two_pi
    runs = jnp.concatenate([pre, arc.status[None]])
    # An explicit start with a pad at N <= 0 is refused as liftoff (explicit states are closed).
    liftoff = ~ok0 & ~unreachable & (initial == "explicit")
    # No consistent state set at assembly (open pads included): nothing holds the damper.
    unseated = jnp.any(runs == RESULTS.unseated) | (~ok0 & ~unreachable & (initial != "explicit"))
    failed = jnp.any(runs == RESULTS.singular) | ~a_ok
    # Elastic (shakedown) where the pads' sliding over the period is rounding: bounded by
    # sum dtau s_a (|dslip_r| + |dslip_i|) against the path's length 2 pi s_a (the straight
    # engine's rule, TRAVEL_TOL of the travel).
    slid = jnp.sum(jnp.where(arc.active[:, None], arc.dp[:, None]
                             * (jnp.abs(arc.dslip[:, 0]) + jnp.abs(arc.dslip[:, 1])), 0.0))
    status = RESULTS.first({
        RESULTS.ill_conditioned: above_validated_range(pads.kn * load.F_D, pads.kt * load.F_D),
        RESULTS.unreachable: unreachable, RESULTS.liftoff: liftoff, RESULTS.unseated: unseated,
        RESULTS.singular: failed, RESULTS.not_converged: ~end["closed"],
        RESULTS.shakedown: slid <= TRAVEL_TOL * two_pi})
    valid = RESULTS.valid(status)
    zero = lambda v: jnp.where(valid, v, jnp.zeros_like(v))  # noqa: E731
    cycle = EllipticCycle(shape, pads.mu, contacts, load, motion, jnp.asarray(amplitude, float),
                          arc, zero(jnp.real(k)), zero(jnp.imag(k)), zero(energy), zero(work),
                          zero(share(SLIP)), zero(share(OPEN)), end["gap"], end["rounds"], status)
    if not record:
        return cycle
    return cycle, dict(assembly=assembly_tape, pre=pre_tape, legs=legs_tape)


class GrossSlipAmplitude(NamedTuple):
    """Where a straight move from assembly reaches gross slip (a pytree; unpacks as a pair)."""

    amplitude_mrad: jnp.ndarray  # of the path's parameter
    status: jnp.ndarray  # ok, unseated or unreachable

    def __repr__(self) -> str:
        return (f"GrossSlipAmplitude(status={status_repr(self.status)}, "
                f"amplitude_mrad={number_repr(self.amplitude_mrad, 'mrad')})")


def gross_slip_amplitude_kernel(shape, mu, contacts, load, motion: Motion,
                                max_tracts: int = MAX_TRACTS, loop: str = "while"):
    """(a_gs, status): the amplitude (mrad of the path's parameter) of a straight move from
    assembly along +X_r (the path's real part) at which every pad that can slip does (the gross-
    slip history's move), and its RESULTS code: unseated where no set of pads holds the damper
    at assembly, unreachable where the move never reaches gross slip. An amplitude scale of the
    path's cycles for any pad set (a wedge's response: its full-slip statics are indeterminate).
    Unchecked, traceable."""
    pads = path_pads(shape, mu, contacts, load, (Motion(motion.direction, motion.h_l),))
    Na, Ta, ok0 = assemble(pads, CENTRIFUGAL_LOAD)
    up, reached = to_gross_slip(pads, Na, Ta, ok0, max_tracts=max_tracts, loop=loop)
    travel = jnp.sum(jnp.where(up.active, up.dp, 0.0))
    status = RESULTS.first({RESULTS.unreachable: ok0 & ~reached, RESULTS.unseated: ~ok0})
    return GrossSlipAmplitude(travel * MRAD_PER_RAD / load.q_star, status)


@functools.cache
def _program(initial: str, max_tracts: int, max_periods: int):
    """elliptic_cycle's one compiled program: the kernel with its static options bound."""

    def program(shape, mu, contacts, load, amplitude, motion, N_init, T_init):
        return elliptic_kernel(shape, mu, contacts, load, amplitude, motion, N_init, T_init,
                               initial=initial, max_tracts=max_tracts, max_periods=max_periods)

    return jax.jit(program)


def elliptic_cycle(shape: DamperShape, mu, amplitude_mrad, motion: Motion,
                   contacts: Contacts = Contacts(), load: LoadCase = LoadCase(), *,
                   initial="assembly", max_tracts: int = MAX_TRACTS,
                   max_periods: int = MAX_PERIODS) -> EllipticCycle:
    """The steady cycle on an elliptic platform path (`interblade_motion` at a phase angle other
    than 0 or 180 degrees, or `general_motion` of a complex X_hat) at amplitude a (mrad).

    initial: "assembly" (F_D applied at X = 0, a straight move to X(pi) = -a X_r, then the path
    from tau = pi), "gross_slip" (from assembly a straight move along +X_r until every pad that
    can slip does, then the path from X(0) = a X_r) or an explicit (N, T) pair at tau = 0 (units
    of F_D, in equilibrium with F_D, one per pad: 3, or 4 for a wedge, every pad closed).
    shape: the curved-flat damper, or a wedge (`DamperShape.br2_over_hr`), which also runs here on
    a straight path (as an ellipse of zero width; the straight-path solvers take the curved-flat
    damper only).
    Returns an EllipticCycle; its status says whether its numbers are valid (ok, shakedown) or
    not (unseated: no set of closed pads holds the damper; unreachable; singular;
    not_converged). Pads that open and close are part of a valid cycle (`open_fraction`).
    Inputs are checked here (ValueError naming the parameter and its range); `elliptic_kernel`
    is the unchecked form for jit / vmap / jvp.
    """
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=True)
    amplitude_mrad = check_scalar("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True,
                                  unit="mrad")
    warn_small_rotation(amplitude_mrad, "psi_a", stacklevel=3)
    motion = validate_motion(motion, load)
    wedge = is_wedge(shape)
    n_pads = len(pad_names(shape))
    if motion.quadrature is None:
        if not wedge:
            raise ValueError("motion must be elliptic for elliptic_cycle (a straight path: use "
                             "amplitude_cycle(..., motion=...))")
        motion = as_ellipse(motion)
    check_int("max_tracts", max_tracts, 1)
    check_int("max_periods", max_periods, 1)
    N_init = T_init = None
    if isinstance(initial, str):
        if initial not in INITIAL_STATES:
            raise ValueError(f"initial must be assembly, gross_slip or an (N, T) pair of "
                             f"({n_pads},) arrays (one per pad); got {initial!r}")
        mode = initial
    else:
        N_init, T_init = explicit_start(initial, shape, mu, pad_names(shape), INITIAL_STATES)
        mode = "explicit"
    return _program(mode, max_tracts, max_periods)(
        shape, mu, contacts, load, jnp.asarray(float(amplitude_mrad)), motion, N_init, T_init)



@functools.cache
def sweep_program(initial: str):
    """The jitted steady cycle at each motion of a batch, f(shape, mu, contacts, load, amplitude,
    motion) -> EllipticCycle with a leading motion axis (one program per initial state; a runner
    can save it: its option is its closure's constant)."""
    def program(shape, mu, contacts, load, amplitude, motion):
        return jax.vmap(lambda m: elliptic_kernel(shape, mu, contacts, load, amplitude, m,
                                                  initial=initial))(motion)

    return jax.jit(program)


def interblade_sweep(shape: DamperShape, mu, amplitude_mrad, phis_deg, h_c_mm, h_l_mm,
                     contacts: Contacts = Contacts(), load: LoadCase = LoadCase(), *,
                     initial="assembly", runner=None) -> EllipticCycle:
    """The steady cycle at every interblade phase angle of phis_deg (deg, each in [-360, 360]) on
    the paper's Fig. 4 kinematics (`interblade_motion`: rotation centres h_c_mm below D, damper
    size h_l_mm), at amplitude_mrad of the left-hand blade's platform rotation: one vmapped
    program, an EllipticCycle whose leaves have a leading phase-angle axis. Any pad set (the
    curved-flat damper or a wedge); straight paths (0, 180 deg) run as ellipses of zero width,
    which give the straight-path solver's numbers (tests/test_engine.py). initial: "assembly" or
    "gross_slip". Inputs are checked here (ValueError naming the parameter and its range).
    runner(program, args) -> outputs runs `sweep_program` instead of a plain call (the CLI passes
    its saved-program cache)."""
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=True)
    amplitude_mrad = check_scalar("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True,
                                  unit="mrad")
    check_range("phis_deg", phis_deg, -360.0, 360.0, unit="deg")  # text too, in one line
    phis = np.atleast_1d(np.asarray(phis_deg, float))
    if phis.ndim != 1 or phis.size == 0:
        raise ValueError(f"phis_deg must be one or more angles in [-360, 360] deg; got {phis_deg!r}")
    h_c_mm = float(check_values("h_c", h_c_mm, max_ndim=0))
    h_l_mm = float(check_values("h_l", h_l_mm, max_ndim=0))
    if initial not in INITIAL_STATES:
        raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)}; got {initial!r}")
    warn_small_rotation(amplitude_mrad, "psi_a", stacklevel=3)
    x = np.array([interblade_direction(p, float(h_c_mm), float(load.q_star)) for p in phis])
    motion = Motion(jnp.asarray(x.real), jnp.full(phis.size, float(h_l_mm)), jnp.asarray(x.imag))
    args = (shape, mu, contacts, load, jnp.asarray(float(amplitude_mrad)), motion)
    program = sweep_program(initial)
    return run_program(program, args, runner)


