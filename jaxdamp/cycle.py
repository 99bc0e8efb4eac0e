"""The periodic Base-Cycle by the direct piecewise-linear method.

Each half-cycle runs from a reversal to gross slip on the tract engine (`jaxdamp.half.run_half`);
the periodic cycle is a bounded loop over (forward, backward) pairs until the end state repeats
(`loops.repeat_until`: a masked scan for reverse mode, a while loop for values).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ._validate import check_int
from .design import Design, as_design
from .geometry import WEDGE_REFUSED, DamperShape, is_wedge
from .status import RESULTS, number_repr, status_repr
from .params import Contacts, LoadCase, above_validated_range
from .conventions import CENTRIFUGAL_LOAD, START_FRICTION_SIGNS
from .statics import contact_columns, full_slip_state, statics_singular
from .linalg import vecmat
from .half import Half, empty_half, run_half
from .periodic import CLOSE_TOL, closure_gap, iterate_to_periodic
from .loops import run_by_loop, tree_where
from .motion import pad_motion
from .tract import Mechanics, make_mechanics

MAX_TRACTS = 6  # per half-cycle; the paper's cases need at most 4, random designs at most 5
MAX_PAIRS = 4  # forward+backward iterations: 1 usually; frozen mechanisms need 3 with Aitken
# Equilibrium residual (forces in units of F_D; rates relative to the largest rate) above which a
# cycle is reported ill-conditioned. A well-posed cycle has residuals of 1e-15; stiffness pairs far
# outside the validated range (docs/model.md) give 5e-8 (kn = 1e12 N/mm) to 1 (kn = 1e30 N/mm).
EQUILIBRIUM_TOL = 1e-8


def mechanics(shape: DamperShape, mu, contacts: Contacts, load: LoadCase, motion=None) -> Mechanics:
    """The tract engine's constants of one design on a platform path: in-phase (motion None,
    per mm of dv) or a straight `jaxdamp.Motion` (per mm of its path parameter a q*/1e3).
    The in-phase engine's three pads only: a wedge (a static field) is refused in one line here,
    at trace time, rather than failing inside the engine's contractions."""
    if is_wedge(shape):
        raise ValueError(WEDGE_REFUSED)
    a, c, _ = contact_columns(shape)
    nw, tw = pad_motion(shape, motion, load.q_star)
    kn, kt = contacts.per_contact()
    return make_mechanics(a, c, nw, tw, kn / load.F_D, kt / load.F_D, mu)


class BaseCycle(NamedTuple):
    """The periodic Base-Cycle and its inputs (a pytree: jit, vmap and grad see through it).

    forward is the half that starts at state 0 (full slip, left platform having moved down) and
    runs with dv decreasing; backward returns with dv increasing.
    """

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    forward: Half
    backward: Half
    half_cycles: jnp.ndarray
    # RESULTS code: ok, ill_conditioned, singular, liftoff or not_converged (the first that applies)
    status: jnp.ndarray

    def __repr__(self) -> str:
        f, b = self.forward, self.backward
        return (f"BaseCycle(status={status_repr(self.status)}, mu={number_repr(self.mu)}, "
                f"span forward={number_repr(f.span, 'mm')}, backward={number_repr(b.span, 'mm')}, "
                f"half_cycles={number_repr(self.half_cycles, fmt='.0f')}; the numbers: "
                "jaxdamp.five_numbers(bc), the tracts: jaxdamp.transitions_chart(bc))")


@partial(jax.jit, static_argnames=("max_tracts", "max_pairs", "loop"))
def base_cycle_kernel(shape, mu, contacts, load, max_tracts=MAX_TRACTS, max_pairs=MAX_PAIRS,
                      loop="auto"):
    """The jit-compiled Base-Cycle without input checks: for use inside your own jit/vmap/grad
    (inputs as float arrays; kn, kt per contact (3,) or shared). `base_cycle` is the checked form.

    loop: how the bounded iterations (tracts of a half-cycle, pairs of halves) run; the numbers are
    the same. "scan" runs every slot, masked, which reverse-mode AD needs; "while" stops each loop
    when it is done (values and forward mode only); "auto" (default) computes values with "while"
    and derivatives (jvp, jacfwd, grad, vjp) with "scan", through a custom JVP rule.
    """
    def impl(shape, mu, contacts, load, loop):
        return _cycle_impl(shape, mu, contacts, load, max_tracts, max_pairs, loop)

    return run_by_loop(impl, (shape, mu, contacts, load), loop)


def _cycle_impl(shape, mu, contacts, load, max_tracts, max_pairs, loop):
    mech = mechanics(shape, mu, contacts, load)
    start = full_slip_state(shape, mech.mu, START_FRICTION_SIGNS)
    # Unsolvable statics are `singular` (as `full_slip_statics` says); either way no cycle runs.
    singular0 = statics_singular(shape, mech.mu)
    liftoff0 = (start.min_normal <= 0.0) | singular0
    N0 = jnp.where(liftoff0, jnp.ones(3), start.N)  # keep the masked solve finite
    T0 = START_FRICTION_SIGNS * mech.mu * N0

    empty = empty_half(max_tracts)
    if max_pairs == 1:
        fwd, bwd, conv, nhalf = _one_pair(mech, N0, T0, liftoff0, empty, max_tracts, loop)
    else:
        fwd, bwd, conv, nhalf = _pairs(mech, N0, T0, liftoff0, empty, max_tracts, max_pairs, loop)
    halves = jnp.stack([fwd.status, bwd.status])
    # A pair runs both halves: a backward half that continues from a failed forward one may lift
    # off spuriously, so its liftoff counts only after a forward half that finished (the two-stage
    # batch reruns `singular` and keeps `liftoff`).
    liftoff = ((liftoff0 & ~singular0) | (fwd.status == RESULTS.liftoff)
               | ((bwd.status == RESULTS.liftoff) & (fwd.status != RESULTS.singular)))
    failed = singular0 | (~liftoff0 & jnp.any(halves == RESULTS.singular))
    converged = conv & ~liftoff
    residual = jnp.maximum(equilibrium_residual(mech, fwd), equilibrium_residual(mech, bwd))
    # A Base-Cycle of zero span means the contacts behave as rigid to working precision (their
    # stiffness over F_D is numerically infinite): its numbers are meaningless too.
    rigid = ~liftoff & (jnp.maximum(fwd.span, bwd.span) <= 0.0)
    ill = ~liftoff0 & ((residual > EQUILIBRIUM_TOL) | rigid)
    ill = ill | above_validated_range(mech.kn, mech.kt)
    status = RESULTS.first({RESULTS.ill_conditioned: ill, RESULTS.liftoff: liftoff,
                            RESULTS.singular: failed, RESULTS.not_converged: ~converged})
    return BaseCycle(shape, mech.mu, contacts, load, fwd, bwd, nhalf, status)


def _pairs(mech, N0, T0, liftoff0, empty, max_tracts, max_pairs, loop):
    """(forward half, backward half, converged, half-cycles run) of the iteration to the periodic
    cycle from (N0, T0), up to max_pairs pairs (none where liftoff0): `periodic.iterate_to_periodic`
    with rounds of two halves."""
    # One loop over half-cycles (forward, backward, forward, ...), so that the program holds one
    # compiled half instead of a pair's two (as the amplitude kernel does): the reverse-mode
    # program of the five numbers traced in 6 s instead of 10 and compiled in 11 s instead of
    # 14 (the value program's compile stayed at 3.4 s; docs/performance-history.md). A pair
    # always runs both halves (whole_rounds), and the cycle stops after a backward half that
    # closed it or after a pair with a failed half.
    def leg(records, N, T, j, k, idle):
        forward = j % 2 == 0
        half = run_half(mech, N, T, jnp.where(forward, -1.0, 1.0), max_tracts=max_tracts,
                        loop=loop, idle=idle)
        records = dict(fwd=tree_where(forward, half, records["fwd"]),
                       bwd=tree_where(~forward, half, records["bwd"]), nhalf=j + 1)
        return half.N_end, half.T_end, half.status != RESULTS.ok, records

    end = iterate_to_periodic(leg, N0, T0, mech.mu, dict(fwd=empty, bwd=empty, nhalf=jnp.array(0)),
                              legs_per_round=2, pre_legs=0, max_rounds=max_pairs, loop=loop,
                              stop0=liftoff0, whole_rounds=True)
    r = end["records"]
    return r["fwd"], r["bwd"], end["closed"], r["nhalf"]


def _one_pair(mech, N0, T0, liftoff0, empty, max_tracts, loop):
    """`_pairs` with max_pairs 1 (the batch's first stage, `batch.first_stage_summary`), the pair
    written out: no loop over halves, so the directions are constants and no half record is
    selected per half. The loop's form cost that stage a fifth more work per design (XLA's flops
    27 248 -> 33 094) and its Base-Cycles/s as much (docs/performance-history.md); the same numbers."""
    fwd = run_half(mech, N0, T0, -1.0, max_tracts=max_tracts, loop=loop)
    bwd = run_half(mech, fwd.N_end, fwd.T_end, 1.0, max_tracts=max_tracts, loop=loop)
    bad = (fwd.status != RESULTS.ok) | (bwd.status != RESULTS.ok)
    closed = closure_gap(jnp.concatenate([N0, T0]), jnp.concatenate([bwd.N_end, bwd.T_end])) <= CLOSE_TOL
    ran = ~liftoff0
    return (tree_where(ran, fwd, empty), tree_where(ran, bwd, empty), ran & closed & ~bad,
            jnp.where(ran, 2, 0).astype(int))


def equilibrium_residual(mech: Mechanics, half: Half):
    """Largest equilibrium residual of a half-cycle: of the forces at every tract start and at its
    end (units of F_D), and of every tract's force rates (relative to the largest rate). The damper
    is rigid and massless, so sum_i (-N_i a_i + T_i c_i) + F_D e_y = 0 and the rates balance; a
    residual above rounding means the linear solves lost their digits (ill-conditioning)."""
    def imbalance(N, T, load):
        return jnp.abs(-vecmat(N, mech.a) + vecmat(T, mech.c) + load)

    active = half.active[:, None]
    forces = jnp.max(jnp.where(active, imbalance(half.N0, half.T0, CENTRIFUGAL_LOAD[None]), 0.0))
    end = jnp.max(imbalance(half.N_end, half.T_end, CENTRIFUGAL_LOAD))
    rates = jnp.where(active, imbalance(half.dN, half.dT, 0.0), 0.0)
    scale = jnp.max(jnp.where(active, jnp.maximum(jnp.abs(half.dN), jnp.abs(half.dT)), 0.0))
    rate_res = jnp.max(rates) / jnp.where(scale > 0.0, scale, 1.0)
    return jnp.maximum(jnp.maximum(forces, end), rate_res)


def base_cycle(shape: DamperShape | Design, mu=None, contacts: Contacts = Contacts(),
               load: LoadCase = LoadCase(), *, max_tracts: int = MAX_TRACTS,
               max_pairs: int = MAX_PAIRS) -> BaseCycle:
    """The damper's periodic Base-Cycle by the direct piecewise-linear method (jit-compiled).

    shape: a DamperShape (then mu is required) or a whole Design.
    mu: friction coefficient (> 0). contacts: kn, kt in N/mm. load: F_D (N), q* (mm), r sin(beta) (mm).
    Liftoff, non-convergence, singular and ill-conditioned cycles are reported in the result's
    `status` (jaxdamp.RESULTS), never as NaN.
    Works under jax.vmap / jax.grad / jax.jacfwd (validation is skipped for traced inputs).
    """
    check_int("max_tracts", max_tracts, 1)
    check_int("max_pairs", max_pairs, 1)
    design = as_design(shape, mu, contacts, load)
    return base_cycle_kernel(*design.prepared(), max_tracts=max_tracts, max_pairs=max_pairs)


def check_base_cycle(bc) -> BaseCycle:
    """bc as it is, or a TypeError in one line naming it: for the public functions that read a
    Base-Cycle (a number given there failed deep inside with an AttributeError on a tracer)."""
    if not isinstance(bc, BaseCycle):
        raise TypeError(f"bc must be a jaxdamp.BaseCycle (from base_cycle); got {type(bc).__name__}")
    return bc


__all__ = ["MAX_TRACTS", "MAX_PAIRS", "CLOSE_TOL", "EQUILIBRIUM_TOL", "mechanics",
           "BaseCycle", "base_cycle_kernel", "check_base_cycle",
           "equilibrium_residual", "base_cycle"]
