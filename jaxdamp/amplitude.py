"""The steady cycle at a prescribed platform rotation amplitude psi_a, by the direct method.

Below psi_BC the cycle depends on the contact state the history left (MODEL.md, "Cycles at a
prescribed amplitude"). Its halves run on the Base-Cycle's tract engine (`jaxdamp.half.run_half`),
given a travel budget of 2 psi_a q*/1e3 mm, which is one more event:

    tract length = min(next stick/slip or liftoff event, remaining travel)

and a half that reaches gross slip before its travel ends finishes with a constant-force stretch
(recorded as one more tract with zero force rates). Pairs of halves (forward, backward) are repeated
until the forces at the forward extreme repeat within CLOSE_TOL (units of F_D), or the cycle is
elastic (shakedown).

Sign convention (the code's, as in `cycle.py` and `harmonics.py`): the forward half starts at the
extreme where state 0 of the Base-Cycle sits, the top of the relative platform travel dv (psi =
+psi_a about the loop centre), and runs with dv DECREASING; the backward half returns with dv
increasing. The issue text writes the same physical history with the opposite sign of psi (state 0
"at psi = -psi_a", psi = -psi_a cos tau). With psi = psi_c + psi_a cos(tau), tau = 0 at the forward
extreme, the first harmonic is M ~ psi_a (k_Re cos tau - k_Im sin tau) and k_Im > 0 for a
dissipative loop: the numbers have the sign and units of the Base-Cycle's (N mm/mrad).

Initial states (all forces normalised to F_D, tangential forces along the up-flank tangent):
- "gross_slip": the Base-Cycle's state 0 (full slip at the start of the forward half);
- "assembly": forces zero, F_D applied from zero with the platforms at mid travel (proportional
  loading: one consistent stick/slip set for the whole load increment; a contact whose all-stick
  friction demand exceeds mu slips from the start), then a quarter travel forward (psi_a q*/1e3 mm,
  dv decreasing) to the backward extreme, then a backward half to the forward extreme where the
  pair iteration starts;
- explicit (N, T): the forces at the forward extreme, in equilibrium with F_D, 0 <= N, |T| <= mu N.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_int, check_range
from .cycle import mechanics
from .engine import TRAVEL_TOL
from .half import (Half, assemble_in_phase, empty_half, gross_slip_from_assembly, run_half)
from .periodic import CLOSE_TOL, iterate_to_periodic
from .loops import run_by_loop, tree_where
from .runtime import run_program
from .geometry import CONTACT_NAMES, DamperShape
from .linalg import rowdot
from .motion import Motion, loop_moment_coefficients, validate_motion
from .fourier import half_fourier
from .params import Contacts, LoadCase, above_validated_range, prepare_inputs
from .conventions import START_FRICTION_SIGNS, psi_mrad, travel_mm, warn_small_rotation
from .statics import contact_columns, full_slip_state, statics_singular
from .status import RESULTS, number_repr, status_repr
from .tract import BACKSLIDE, SLIP

MAX_TRACTS = 8  # per half, the constant-force stretch included (Base-Cycle halves need at most 5+1)
MAX_PAIRS = 12  # (forward, backward) pairs of the iteration to a periodic cycle
ADMISSIBLE_TOL = 1e-9  # explicit states: equilibrium residual and cone tolerance (units of F_D)
INITIAL_STATES = ("gross_slip", "assembly")

__all__ = ["AmplitudeCycle", "amplitude_cycle", "amplitude_kernel",
           "gross_slip_state", "check_admissible", "explicit_start",
           "moment_loop", "slip_fraction",
           "MAX_TRACTS", "MAX_PAIRS", "CLOSE_TOL", "INITIAL_STATES", "PRELIMINARY_HALVES",
           "history_halves"]



class AmplitudeCycle(NamedTuple):
    """The steady cycle at amplitude psi_a and its inputs (a pytree).

    forward starts at the forward extreme (top of dv, where the Base-Cycle's state 0 sits) and runs
    with dv decreasing; backward returns. k in N mm/mrad, energy in N mm per cycle.
    """

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    psi_a: jnp.ndarray  # mrad
    N_start: jnp.ndarray  # (3,) forces at the forward extreme of the steady cycle (units of F_D)
    T_start: jnp.ndarray
    forward: Half
    backward: Half
    k_re: jnp.ndarray
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (3,) dissipated at R1, L1, L2 per cycle, N mm (sum T d(slip), exact)
    work: jnp.ndarray  # oint M dpsi, N mm per cycle (= pi psi_a^2 k_Im 1e-3 = sum of energy)
    closure: jnp.ndarray  # max force change over the last pair (units of F_D)
    cycles: jnp.ndarray  # pairs of halves run until the forces repeated (int32)
    status: jnp.ndarray  # RESULTS code (int32): ok, shakedown, not_converged, liftoff, singular
    # (halves, MAX_TRACTS) tract lengths (mm) of every half run, preliminary and transient halves
    # included, in order (zeros after the last): within one sequence they are affine in psi_a, and
    # where one reaches zero the sequence changes (`jaxdamp.sequence`)
    history_dv: jnp.ndarray = None
    history_slack: jnp.ndarray = None  # the same halves' tract slacks (`Half.slack`)
    # The straight platform path (`jaxdamp.Motion`), or None for the paper's in-phase motion. On a
    # path, psi_a is its amplitude a (mrad), "dv" in the halves is its parameter a q*/1e3 (mm)
    # and k is that of the modal force (`jaxdamp.motion`).
    motion: object = None

    def __repr__(self) -> str:
        return (f"AmplitudeCycle(status={status_repr(self.status)}, psi_a={number_repr(self.psi_a, 'mrad')}, "
                f"k_re={number_repr(self.k_re, 'N mm/mrad')}, k_im={number_repr(self.k_im, 'N mm/mrad')}, "
                f"cycles={number_repr(self.cycles, fmt='.0f')})")


def gross_slip_state(shape: DamperShape, mu):
    """(N, T, ok) of the Base-Cycle's state 0: full slip at the start of the forward half."""
    st = full_slip_state(shape, mu, START_FRICTION_SIGNS)
    ok = st.solvable & (st.min_normal > 0.0)
    return st.N, st.T, ok


def check_admissible(shape: DamperShape, mu, N, T, tol=ADMISSIBLE_TOL):
    """(equilibrium residual, max cone violation, min N) of an explicit state (units of F_D)."""
    a, c, _ = contact_columns(shape)
    N, T = jnp.asarray(N, float), jnp.asarray(T, float)
    residual = -a.T @ N + c.T @ T + jnp.array([0.0, 1.0, 0.0])
    return (jnp.max(jnp.abs(residual)), jnp.max(jnp.abs(T) - jnp.asarray(mu, float) * N),
            jnp.min(N))


def explicit_start(initial, shape: DamperShape, mu, pads, modes) -> tuple:
    """(N, T) as float arrays from an explicit start `initial` (an (N, T) pair of one force per
    pad, in the order of the names `pads`, units of F_D), checked: admissible (in equilibrium
    with F_D within ADMISSIBLE_TOL * 1e3, N >= 0, |T| <= mu N within ADMISSIBLE_TOL); else a
    one-line ValueError naming `initial` (modes: the named histories it could have been)."""
    arrays = f"arrays of one force per pad ({', '.join(pads)}), shape ({len(pads)},)"
    try:
        N, T = (np.asarray(v, float) for v in initial)
    except (TypeError, ValueError):
        raise ValueError(f"initial must be {', '.join(modes)} or an (N, T) pair of {arrays}, "
                         f"units of F_D; got {initial!r}") from None
    if N.shape != (len(pads),) or T.shape != (len(pads),):
        raise ValueError(f"initial (N, T) must be two {arrays}, units of F_D; got {N.shape} and "
                         f"{T.shape}")
    res, cone, n_min = (float(v) for v in check_admissible(shape, mu, N, T))
    if not np.isfinite(res) or res > ADMISSIBLE_TOL * 1e3:
        raise ValueError(f"initial (N, T) must be in equilibrium with F_D: residual must be in "
                         f"[0, {ADMISSIBLE_TOL * 1e3:g}] F_D; got {res:g}")
    if not n_min >= 0.0:
        raise ValueError(f"initial N must be in [0, inf) F_D; got min N = {n_min:g}")
    if not cone <= ADMISSIBLE_TOL:
        raise ValueError(f"initial T must satisfy |T| <= mu N: excess must be in "
                         f"[0, {ADMISSIBLE_TOL:g}] F_D; got {cone:g}")
    return N, T


def _half_moment(coefficients, half: Half):
    """(moment at each tract start, its rate) in N mm, from `loop_moment_coefficients`."""
    fn, ft = coefficients
    return (rowdot(half.N0, fn) + rowdot(half.T0, ft), rowdot(half.dN, fn) + rowdot(half.dT, ft))


def _half_energy(half: Half, F_D):
    T1 = half.T0 + half.dT * half.dv[:, None]
    return -F_D * jnp.sum(0.5 * (half.T0 + T1) * half.dslip * half.dv[:, None], axis=0)


def loop_fourier(coefficients, fwd: Half, bwd: Half, a_dv):
    """(int F cos tau dtau, int F sin tau dtau) over the loop (forward, backward halves) of the
    force F = sum of N fn + T ft, coefficients = (fn, ft) per unit normal / tangential force of
    each contact; a_dv: the amplitude in mm of travel. Unchecked, traceable."""
    return _loop_fourier(_half_moment(coefficients, fwd), _half_moment(coefficients, bwd), fwd,
                         bwd, a_dv)


def _loop_fourier(moments_fwd, moments_bwd, fwd: Half, bwd: Half, a_dv):
    """`loop_fourier` of the halves' force at each tract start and its rate (`_half_moment`)."""
    c1, s1 = half_fourier(fwd.dv, *moments_fwd, a_dv, 1.0)
    c2, s2 = half_fourier(bwd.dv, *moments_bwd, a_dv, -1.0)
    return c1 + c2, s1 + s2


def _loop_numbers(shape, load, psi_a, fwd: Half, bwd: Half, motion=None):
    """(k_Re, k_Im, energy per contact, oint M dpsi) of the loop (forward, backward)."""
    a_dv = travel_mm(psi_a, load.q_star)
    coefficients = loop_moment_coefficients(shape, load, motion)
    m0f, dmf = _half_moment(coefficients, fwd)
    m0b, dmb = _half_moment(coefficients, bwd)
    cos_part, sin_part = _loop_fourier((m0f, dmf), (m0b, dmb), fwd, bwd, a_dv)
    k_re = cos_part / (jnp.pi * psi_a)
    k_im = -sin_part / (jnp.pi * psi_a)
    # oint M dpsi (psi in rad): trapezoids on the linear segments, dpsi = -branch dv / q*.
    wf = jnp.sum((m0f + 0.5 * dmf * fwd.dv) * fwd.dv) / load.q_star
    wb = jnp.sum((m0b + 0.5 * dmb * bwd.dv) * bwd.dv) / load.q_star
    energy = _half_energy(fwd, load.F_D) + _half_energy(bwd, load.F_D)
    return k_re, k_im, energy, wb - wf


# Halves run before the (forward, backward) pairs: from assembly a quarter travel forward, then a
# backward half to the forward extreme.
PRELIMINARY_HALVES = {"assembly": 2}


def history_halves(initial: str, max_pairs: int = MAX_PAIRS) -> int:
    """The rows of `AmplitudeCycle.history_dv` (and history_slack): every half the iteration may
    run from this initial state (each row MAX_TRACTS tracts long)."""
    return PRELIMINARY_HALVES.get(initial, 0) + 2 * max_pairs


def amplitude_kernel(shape, mu, contacts, load, psi_a, N_init=None, T_init=None, *,
                     initial="gross_slip", max_tracts: int = MAX_TRACTS,
                     max_pairs: int = MAX_PAIRS, loop: str = "auto", motion=None,
                     pair_budget=None) -> AmplitudeCycle:
    """The steady cycle at psi_a (mrad): pure JAX (jit / vmap / grad), no validation.

    initial: "gross_slip", "assembly" or "explicit" (then N_init, T_init at the forward extreme,
    units of F_D). Python-static. Problems are reported in `status`, never as NaN.

    motion: None (the paper's in-phase motion) or a straight `jaxdamp.Motion`, whose amplitude
    psi_a is then in mrad of its parameter. On a path, "gross_slip" is the state at the top of the
    path after the platforms, from assembly, moved up until every pad slipped (in-phase that is
    the Base-Cycle's state 0, except where gross slip leaves some pads stuck: 90R).

    loop: how the bounded iterations (tracts of a half, halves of the iteration to a periodic
    cycle) run; the numbers are the same. "scan" always runs every slot, masked: reverse mode
    needs it, and under vmap every lane pays for MAX_PAIRS pairs. "while" stops when done (under
    vmap: when the last lane is done, usually after 1-2 pairs); values and forward mode only.
    "auto" (default) computes values with "while" and derivatives (jvp, jacfwd, grad, vjp) with
    "scan", through a custom JVP rule. "forward" is "while": forward-mode derivatives that cost
    the pairs the cycle took (reverse mode raises).

    pair_budget: at most this many pairs of halves run (an int <= max_pairs, may be traced: one
    compiled program serves every budget, as `curves.amplitude_curves`' two stages share one);
    None: max_pairs. A cycle that has not closed by then is not_converged, as at max_pairs.
    """
    def impl(*design_and_loop):
        *design, loop = design_and_loop
        return _amplitude_impl(*design, initial=initial, max_tracts=max_tracts,
                               max_pairs=max_pairs, loop=loop)

    return run_by_loop(impl, (shape, mu, contacts, load, psi_a, N_init, T_init, motion,
                              pair_budget), loop)


def _amplitude_impl(shape, mu, contacts, load, psi_a, N_init, T_init, motion, pair_budget, *,
                    initial, max_tracts, max_pairs, loop) -> AmplitudeCycle:
    mech = mechanics(shape, mu, contacts, load, motion)
    psi_ok = jnp.asarray(psi_a, float) > 0.0  # a Python number too (~ of a bool is an int)
    psi = jnp.where(psi_ok, psi_a, 1.0)  # a zero amplitude is invalid; keep everything finite
    a_dv = travel_mm(psi, load.q_star)
    travel = 2.0 * a_dv
    n_pre = PRELIMINARY_HALVES.get(initial, 0)
    unreachable = jnp.array(False)
    if initial == "gross_slip" and motion is None:
        N0, T0, ok0 = gross_slip_state(shape, mech.mu)
    elif initial == "gross_slip":
        N0, T0, ok0, reached = gross_slip_from_assembly(mech, max_tracts=max_tracts, loop=loop)
        unreachable = ok0 & ~reached
        ok0 = ok0 & reached
    elif initial == "assembly":
        N0, T0, ok0 = assemble_in_phase(mech)
    elif initial == "explicit":
        N0, T0 = jnp.asarray(N_init, float), jnp.asarray(T_init, float)
        ok0 = jnp.min(N0) > 0.0
    else:
        raise ValueError(f"initial must be one of gross_slip, assembly, explicit; got {initial!r}")
    N0 = jnp.where(ok0, N0, jnp.ones(3))  # keep the masked iteration finite
    T0 = jnp.where(ok0, T0, 0.0)

    # One loop over half-cycles (a single compiled half: the program stays small under grad):
    # n_pre preliminary halves, then (forward, backward) pairs until the forces repeat
    # (`periodic.iterate_to_periodic`).
    n_halves = history_halves(initial, max_pairs)

    def leg(r, N, T, j, k, idle):
        forward = (k % 2 == 0) | (k == -2)  # k: index within the pair iteration (< 0: preliminary)
        direction = jnp.where(forward, -1.0, 1.0)
        length = jnp.where(k == -2, a_dv, travel)
        half = run_half(mech, N, T, direction, length, max_tracts=max_tracts, loop=loop, idle=idle)
        in_pairs = k >= 0
        r = dict(fwd=tree_where(in_pairs & forward, half, r["fwd"]),
                 bwd=tree_where(in_pairs & ~forward, half, r["bwd"]),
                 liftoff=r["liftoff"] | (half.status == RESULTS.liftoff),
                 failed=r["failed"] | (half.status == RESULTS.singular),
                 hist=r["hist"].at[j].set(half.dv), slack=r["slack"].at[j].set(half.slack))
        return half.N_end, half.T_end, half.status != RESULTS.ok, r

    empty = empty_half(max_tracts)
    records = dict(fwd=empty, bwd=empty, liftoff=~ok0, failed=jnp.array(False),
                   hist=jnp.zeros((n_halves, max_tracts)), slack=jnp.zeros((n_halves, max_tracts)))
    end = iterate_to_periodic(leg, N0, T0, mech.mu, records, legs_per_round=2, pre_legs=n_pre,
                              max_rounds=max_pairs, loop=loop, stop0=~ok0 | ~psi_ok,
                              round_budget=pair_budget)
    r = end["records"]
    fwd, bwd, closed, gap, npairs, start = (r["fwd"], r["bwd"], end["closed"], end["gap"],
                                            end["rounds"], end["top"])
    pre_lift, pre_fail = r["liftoff"], r["failed"]

    k_re, k_im, energy, work = _loop_numbers(shape, load, psi, fwd, bwd, motion)
    singular0 = statics_singular(shape, mech.mu)  # no full-slip statics: as the Base-Cycle says
    halves = jnp.stack([fwd.status, bwd.status])
    liftoff = (pre_lift & ~singular0 & ~unreachable) | jnp.any(halves == RESULTS.liftoff)
    failed = singular0 | pre_fail | jnp.any(halves == RESULTS.singular)
    slid = jnp.sum(jnp.abs(fwd.dslip) * fwd.dv[:, None]) + jnp.sum(jnp.abs(bwd.dslip) * bwd.dv[:, None])
    status = RESULTS.first({RESULTS.ill_conditioned: above_validated_range(mech.kn, mech.kt),
                            RESULTS.unreachable: unreachable & ~singular0,
                            RESULTS.liftoff: liftoff, RESULTS.singular: failed | ~psi_ok,
                            RESULTS.not_converged: ~closed,
                            RESULTS.shakedown: slid <= TRAVEL_TOL * travel})
    valid = RESULTS.valid(status)
    zero = lambda v: jnp.where(valid, v, jnp.zeros_like(v))  # noqa: E731
    return AmplitudeCycle(shape, mech.mu, contacts, load, jnp.asarray(psi_a, float), start[:3],
                          start[3:], fwd, bwd, zero(k_re), zero(k_im), zero(energy), zero(work),
                          gap, npairs.astype(jnp.int32), status, r["hist"], r["slack"], motion)


@functools.cache
def _program(initial: str, max_tracts: int, max_pairs: int):
    """The kernel with its static options bound, as a function of arrays only: amplitude_cycle's
    one compiled program (a `runner` takes it as it is: the CLI saves it, `jaxdamp.cli.exported`)."""

    def program(shape, mu, contacts, load, psi_a, N_init, T_init, motion):
        return amplitude_kernel(shape, mu, contacts, load, psi_a, N_init, T_init, initial=initial,
                                max_tracts=max_tracts, max_pairs=max_pairs, motion=motion)

    return jax.jit(program)


def amplitude_cycle(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, initial="gross_slip",
                    max_tracts: int = MAX_TRACTS, max_pairs: int = MAX_PAIRS,
                    motion: Motion | None = None, runner=None) -> AmplitudeCycle:
    """The steady cycle at platform rotation amplitude psi_a_mrad > 0 (mrad), by the direct method.

    initial: "gross_slip" (the Base-Cycle's state 0 at the forward extreme), "assembly" (F_D applied
    at mid travel, then a quarter travel forward), or an explicit state (N, T): two (3,) arrays of
    contact forces (R1, L1, L2) in units of F_D at the forward extreme, in equilibrium with F_D,
    N >= 0 and |T| <= mu N. See the module docstring for the sign convention.

    motion: None for the paper's in-phase motion, or a straight platform path (`jaxdamp.Motion`:
    `interblade_motion(180, h_c_mm)` for out-of-phase vibration, `straight_motion` for any
    direction); psi_a_mrad is then the path's amplitude (mrad) and k that of its modal force
    (`jaxdamp.motion`). A pad that opens on the path is reported as liftoff.

    runner: None, or runner(program, args) -> program(*args) for a jitted program of arrays and
    its arguments (the CLI's runs it through a saved export, `jaxdamp.cli.exported`).

    Returns an AmplitudeCycle; its `status` (jaxdamp.status.RESULTS) says whether the numbers are
    valid (ok, shakedown) or not (liftoff, not_converged, singular: numbers zero). Jit-compiled;
    inputs are validated here (ValueError naming the parameter and its range); under jit / vmap /
    grad call `amplitude_kernel` directly.
    """

    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    warn_small_rotation(psi_a_mrad, "psi_a", stacklevel=3)
    check_int("max_tracts", max_tracts, 1)
    check_int("max_pairs", max_pairs, 1)
    psi = np.asarray(psi_a_mrad, float)
    if psi.ndim != 0:
        raise ValueError("psi_a_mrad must be a scalar in (0, 10000] mrad; use amplitude_curves for a grid")
    N_init = T_init = None
    if isinstance(initial, str):
        if initial not in INITIAL_STATES:
            raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)} or an (N, T) "
                             f"pair of (3,) arrays; got {initial!r}")
        mode = initial
    else:
        N_init, T_init = explicit_start(initial, shape, mu, CONTACT_NAMES, INITIAL_STATES)
        mode = "explicit"
    if motion is not None:
        motion = validate_motion(motion, load)
        if motion.quadrature is not None:
            raise ValueError("motion must be a straight path for amplitude_cycle (an elliptic one: "
                             "use jaxdamp.elliptic_cycle)")
    return run_program(_program(mode, max_tracts, max_pairs),
                       (shape, mu, contacts, load, psi, N_init, T_init, motion), runner)


def moment_loop(ac: AmplitudeCycle):
    """The (psi, M) loop of the steady cycle as vertices: psi in mrad about the loop centre
    (forward extreme = +psi_a), M in N mm; forward half then backward half (numpy arrays)."""
    psis, ms = [], []
    coefficients = loop_moment_coefficients(ac.shape, ac.load, ac.motion)
    q = float(ac.load.q_star)
    top = float(ac.psi_a)
    for half, branch in ((ac.forward, 1.0), (ac.backward, -1.0)):
        act = np.asarray(half.active)
        dv = np.asarray(half.dv)[act]
        m0, dm = (np.asarray(m)[act] for m in _half_moment(coefficients, half))
        start = top if branch > 0 else -top
        cum = np.concatenate([[0.0], np.cumsum(dv)])
        psis.extend(start - branch * psi_mrad(cum, q))
        ms.extend(np.concatenate([m0, [m0[-1] + dm[-1] * dv[-1]] if len(dv) else []]))
    return np.asarray(psis), np.asarray(ms)


def slip_fraction(ac: AmplitudeCycle) -> np.ndarray:
    """(3,) fraction of the period (of time tau, with psi = psi_a cos tau) each pad slips or
    back-slides in the steady cycle (numpy; zeros where the cycle is not valid)."""
    if not bool(RESULTS.valid(ac.status)):
        return np.zeros(3)
    a_dv = float(travel_mm(ac.psi_a, ac.load.q_star))
    out = np.zeros(3)
    for half in (ac.forward, ac.backward):
        act = np.asarray(half.active)
        dv = np.asarray(half.dv)[act]
        cum = np.concatenate([[0.0], np.cumsum(dv)])
        # Within a half tau runs over pi as cos tau runs from one extreme to the other.
        tau = np.arccos(np.clip(1.0 - cum / a_dv, -1.0, 1.0))
        sliding = np.isin(np.asarray(half.state)[act], (SLIP, BACKSLIDE))
        out += np.sum(sliding * np.diff(tau)[:, None], axis=0)
    return out / (2.0 * np.pi)


