"""The periodic Base-Cycle by the direct piecewise-linear method.

A half-cycle is a bounded `lax.scan` over tracts with masking (so reverse-mode AD works); the
periodic cycle is a bounded scan over (forward, backward) pairs until the end state repeats.
"""

from __future__ import annotations

import string
from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .design import Design, as_design
from .geometry import CONTACT_NAMES, DamperShape
from .status import RESULTS, from_flags, number_repr, ok_status, status_repr
from .params import Contacts, LoadCase, above_validated_range
from .conventions import CENTRIFUGAL_LOAD, PLATFORM_MOTION, START_FRICTION_SIGNS
from .statics import contact_columns, full_slip_state, statics_singular
from .linalg import vecmat
from .tract import (BACKSLIDE, STATE_NAMES, LIMIT_TOL, OPEN, RATE_TOL, SLIP, STICK, Mechanics, choose_states,
                    make_mechanics, next_event)

MAX_TRACTS = 6  # per half-cycle; the paper's cases need at most 4, random designs at most 5
MAX_PAIRS = 4  # forward+backward iterations: 1 usually; frozen mechanisms need 3 with Aitken
CLOSE_TOL = 1e-9  # end-state repeat tolerance on forces (units of F_D)
# Equilibrium residual (forces in units of F_D; rates relative to the largest rate) above which a
# cycle is reported ill-conditioned. A well-posed cycle has residuals of 1e-15; stiffness pairs far
# outside the validated range (docs/model.md) give 5e-8 (kn = 1e12 N/mm) to 1 (kn = 1e30 N/mm).
EQUILIBRIUM_TOL = 1e-8


class HalfCycle(NamedTuple):
    """One half-cycle from a reversal to gross slip. Arrays with a leading tract axis (MAX_TRACTS)."""

    dv: jnp.ndarray  # tract lengths, mm of relative platform travel (>= 0)
    N0: jnp.ndarray  # (nt, 3) forces at the tract start, units of F_D
    T0: jnp.ndarray
    dN: jnp.ndarray  # (nt, 3) rates per mm of travel
    dT: jnp.ndarray
    dslip: jnp.ndarray  # (nt, 3) sliding rate of each contact, mm per mm of travel
    state: jnp.ndarray  # (nt, 3) STICK / SLIP / BACKSLIDE / OPEN
    active: jnp.ndarray  # (nt,) bool, tract exists
    gross_dslip: jnp.ndarray  # (3,) sliding rates in the final gross-slip state
    N_end: jnp.ndarray
    T_end: jnp.ndarray
    span: jnp.ndarray  # mm, total travel to gross slip
    gross_slip: jnp.ndarray  # bool: reached gross slip
    # RESULTS code (int32): ok, liftoff (a normal force reached zero) or singular (no consistent
    # state set / singular system / ran out of tracts); the two problems exclude each other.
    status: jnp.ndarray

    def __repr__(self) -> str:
        return (f"HalfCycle(status={status_repr(self.status)}, span={number_repr(self.span, 'mm')}, "
                f"tracts={number_repr(jnp.sum(self.active), fmt='.0f')}, "
                f"gross_slip={number_repr(self.gross_slip, fmt='.0f')})")


def mechanics(shape: DamperShape, mu, contacts: Contacts, load: LoadCase) -> Mechanics:
    a, c, geo = contact_columns(shape)
    nw = geo.normals[:, 1] * PLATFORM_MOTION
    tw = geo.tangents[:, 1] * PLATFORM_MOTION
    kn, kt = contacts.per_contact()
    return make_mechanics(a, c, nw, tw, kn / load.F_D, kt / load.F_D, mu)


def half_cycle(mech: Mechanics, N, T, direction, max_tracts: int = MAX_TRACTS,
               loop: str = "scan") -> HalfCycle:
    """Run tracts from a reversal at (N, T) until gross slip (zero incremental stiffness).

    loop="scan" runs max_tracts masked steps (reverse-mode differentiable); loop="while" stops at
    gross slip (same numbers, fewer steps; values and forward mode only)."""
    scale = jnp.max(jnp.maximum(mech.kn, mech.kt))
    start_sign = jnp.where(T >= 0.0, 1.0, -1.0)
    # Back-slide (Appendix A): a contact still sliding on the limit line it had at the reversal.
    on_start_line = jnp.abs(T) >= mech.mu * N - LIMIT_TOL
    init = dict(N=N, T=T, done=jnp.array(False), gross=jnp.array(False),
                liftoff=jnp.min(N) <= LIMIT_TOL, failed=jnp.array(False), gross_dslip=jnp.zeros(3),
                line=on_start_line)
    init["done"] = init["liftoff"]

    def step(carry, _):
        N, T = carry["N"], carry["T"]
        choice = choose_states(mech, N, T, direction)
        r = choice.rates
        frozen = jnp.max(jnp.abs(jnp.concatenate([r.dN, r.dT]))) <= RATE_TOL * scale
        gross = choice.consistent & frozen
        ev = next_event(mech, N, T, choice)
        failed_now = ~choice.consistent | (~gross & (ev.length >= 1e5))
        live = ~carry["done"]
        advance = live & ~gross & ~failed_now
        lam = jnp.where(advance, ev.length, 0.0)
        N1 = N + lam * r.dN
        T1 = T + lam * r.dT
        # Snap to the limit line: slipping contacts stay on it, the event contact lands on it.
        T1 = jnp.where(choice.slipping, choice.signs * mech.mu * N1, T1)
        on_cone = advance & ~ev.opens
        hit = jnp.arange(3) == ev.contact
        T1 = jnp.where(on_cone & hit, ev.side * mech.mu * N1, T1)
        N1 = jnp.where(advance & ev.opens & hit, 0.0, N1)
        lifted = advance & (ev.opens | (jnp.min(N1) <= LIMIT_TOL))
        line = carry["line"] & choice.slipping & (choice.signs == start_sign)
        back = jnp.where(advance, line, carry["line"] & choice.slipping)
        state = jnp.where(choice.slipping, jnp.where(back, BACKSLIDE, SLIP), STICK)
        state = jnp.where(N <= LIMIT_TOL, OPEN, state)
        out = dict(dv=lam, N0=N, T0=T, dN=r.dN, dT=r.dT, dslip=r.dslip, state=state, active=advance)
        new = dict(
            N=jnp.where(advance, N1, N), T=jnp.where(advance, T1, T),
            done=carry["done"] | gross | failed_now | lifted,
            gross=carry["gross"] | (live & gross),
            liftoff=carry["liftoff"] | lifted,
            failed=carry["failed"] | (live & failed_now),
            gross_dslip=jnp.where(live & gross, r.dslip, carry["gross_dslip"]),
            line=jnp.where(advance, line, carry["line"]),
        )
        return new, out

    end, tr = bounded_loop(step, init, max_tracts, loop, tract_rows())
    exhausted = ~end["done"]
    return HalfCycle(tr["dv"], tr["N0"], tr["T0"], tr["dN"], tr["dT"], tr["dslip"], tr["state"],
                     tr["active"], end["gross_dslip"], end["N"], end["T"], jnp.sum(tr["dv"]),
                     end["gross"], from_flags(end["liftoff"], end["failed"] | exhausted))


def tract_rows(**extra) -> dict:
    """Shapes and dtypes of one tract's recorded row (a half's step output); extra: more fields."""
    f, v = jax.ShapeDtypeStruct((), float), jax.ShapeDtypeStruct((3,), float)
    return dict(dv=f, N0=v, T0=v, dN=v, dT=v, dslip=v, state=jax.ShapeDtypeStruct((3,), int),
                active=jax.ShapeDtypeStruct((), bool), **extra)


def zeros_of(rows: dict, length: int) -> dict:
    """Arrays of zeros for `length` rows of the given shapes and dtypes."""
    return {k: jnp.zeros((length,) + r.shape, r.dtype) for k, r in rows.items()}


def bounded_loop(step, init, length: int, loop: str, rows: dict):
    """(final carry, stacked outputs) of up to `length` calls of step(carry, None) -> (carry, out).

    "scan": always `length` steps (masked by the step itself; reverse mode passes). "while": stops
    once carry["done"] is True; the rows of the steps not run are zeros (the step's outputs for
    finished steps must be inactive rows, e.g. zero travel). rows: the shapes and dtypes of one
    step's outputs (a dict, as `tract_rows`), which spares tracing the step once more to find them
    (tracing is most of a CLI call's cost)."""
    if loop == "scan":
        return jax.lax.scan(step, init, None, length=length)
    if loop != "while":
        raise ValueError(f"loop must be scan or while; got {loop!r}")
    rows = zeros_of(rows, length)

    def cond(c):
        i, carry, _ = c
        return (i < length) & ~carry["done"]

    def body(c):
        i, carry, acc = c
        carry, out = step(carry, None)
        return i + 1, carry, jax.tree_util.tree_map(lambda a, o: a.at[i].set(o), acc, out)

    _, end, acc = jax.lax.while_loop(cond, body, (jnp.array(0), init, rows))
    return end, acc


def repeat_until(run, init, length: int, loop: str, stopped):
    """The carry after up to `length` calls carry = run(carry, k), k = 0, 1, ..., that end once
    stopped(carry) is True. "while" stops there; "scan" makes every call and keeps the stopped
    carry (masked, not lax.cond: the scan form is the derivative program of loop="auto", and JAX
    cannot transpose a cond that vmap has turned into a select inside a custom JVP rule)."""
    if loop == "while":
        return jax.lax.while_loop(lambda c: (c[0] < length) & ~stopped(c[1]),
                                  lambda c: (c[0] + 1, run(c[1], c[0])), (jnp.array(0), init))[1]

    def step(carry, k):
        new = run(carry, k)
        return jax.tree_util.tree_map(lambda old, x: jnp.where(stopped(carry), old, x), carry,
                                      new), None

    return jax.lax.scan(step, init, jnp.arange(length))[0]


LOOPS = ("auto", "scan", "while")


def check_loop(loop: str) -> None:
    if loop not in LOOPS:
        raise ValueError(f"loop must be one of {', '.join(LOOPS)}; got {loop!r}")


def values_by_while(impl, *args):
    """impl(*args, loop) for loop="auto": the values of loop="while" (loops that stop when done),
    the derivatives of loop="scan" through a custom JVP rule (the masked scan's own JVP, whose
    transpose gives reverse mode, which cannot pass a while loop)."""
    @jax.custom_jvp
    def run(*a):
        return impl(*a, "while")

    @run.defjvp
    def run_jvp(primals, tangents):
        return jax.jvp(lambda *a: impl(*a, "scan"), primals, tangents)

    return run(*args)


class BaseCycle(NamedTuple):
    """The periodic Base-Cycle and its inputs (a pytree: jit, vmap and grad see through it).

    forward is the half that starts at state 0 (full slip, left platform having moved down) and
    runs with dv decreasing; backward returns with dv increasing.
    """

    shape: DamperShape
    mu: jnp.ndarray
    contacts: Contacts
    load: LoadCase
    forward: HalfCycle
    backward: HalfCycle
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
    check_loop(loop)

    def impl(shape, mu, contacts, load, loop):
        return _cycle_impl(shape, mu, contacts, load, max_tracts, max_pairs, loop)

    if loop == "auto":
        return values_by_while(impl, shape, mu, contacts, load)
    return impl(shape, mu, contacts, load, loop)


def _cycle_impl(shape, mu, contacts, load, max_tracts, max_pairs, loop):
    mech = mechanics(shape, mu, contacts, load)
    start = full_slip_state(shape, mech.mu, START_FRICTION_SIGNS)
    # Unsolvable statics are `singular` (as `full_slip_statics` says); either way no cycle runs.
    singular0 = statics_singular(shape, mech.mu)
    liftoff0 = (start.min_normal <= 0.0) | singular0
    N0 = jnp.where(liftoff0, jnp.ones(3), start.N)  # keep the masked solve finite
    T0 = START_FRICTION_SIGNS * mech.mu * N0

    def run_pair(carry, k):
        N, T, conv, stop, fwd_s, bwd_s, nhalf, prev = carry
        fwd = half_cycle(mech, N, T, -1.0, max_tracts, loop)
        bwd = half_cycle(mech, fwd.N_end, fwd.T_end, 1.0, max_tracts, loop)
        bad = (fwd.status != RESULTS.ok) | (bwd.status != RESULTS.ok)
        closed = (jnp.max(jnp.abs(bwd.N_end - N)) + jnp.max(jnp.abs(bwd.T_end - T))) <= CLOSE_TOL
        here = jnp.concatenate([N, T])
        nxt = _aitken(mech, prev, here, jnp.concatenate([bwd.N_end, bwd.T_end]), k > 0)
        return (nxt[:3], nxt[3:], closed & ~bad, closed | bad, fwd, bwd, 2 * (k + 1), here)

    empty = _empty_half(max_tracts)
    init = (N0, T0, jnp.array(False), liftoff0, empty, empty, jnp.array(0), jnp.zeros(6))
    # Once the cycle has closed (or failed) the remaining pairs change nothing.
    _, _, conv, _, fwd, bwd, nhalf, _ = repeat_until(run_pair, init, max_pairs, loop,
                                                     lambda c: c[3])
    halves = jnp.stack([fwd.status, bwd.status])
    liftoff = (liftoff0 & ~singular0) | jnp.any(halves == RESULTS.liftoff)
    failed = singular0 | (~liftoff0 & jnp.any(halves == RESULTS.singular))
    converged = conv & ~liftoff
    residual = jnp.maximum(equilibrium_residual(mech, fwd), equilibrium_residual(mech, bwd))
    # A Base-Cycle of zero span means the contacts behave as rigid to working precision (their
    # stiffness over F_D is numerically infinite): its numbers are meaningless too.
    rigid = ~liftoff & (jnp.maximum(fwd.span, bwd.span) <= 0.0)
    ill = ~liftoff0 & ((residual > EQUILIBRIUM_TOL) | rigid)
    ill = ill | above_validated_range(mech.kn, mech.kt)
    # A failed half-cycle comes before liftoff: a half that continues from an unfinished one may
    # lift off spuriously (so the two-stage batch reruns `singular`, and keeps `liftoff`).
    status = RESULTS.promote(ok_status(), ill, RESULTS.ill_conditioned)
    status = RESULTS.promote(status, failed, RESULTS.singular)
    status = RESULTS.promote(status, liftoff, RESULTS.liftoff)
    status = RESULTS.promote(status, ~converged, RESULTS.not_converged)
    return BaseCycle(shape, mech.mu, contacts, load, fwd, bwd, nhalf, status)


def _empty_half(max_tracts: int) -> HalfCycle:
    """A HalfCycle of zeros (the pair iteration's initial value)."""
    z3, f, b = jnp.zeros(3), jnp.zeros(()), jnp.array(False)
    return HalfCycle(**zeros_of(tract_rows(), max_tracts), gross_dslip=z3, N_end=z3, T_end=z3,
                     span=f, gross_slip=b, status=ok_status())


def equilibrium_residual(mech: Mechanics, half: HalfCycle):
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


def _aitken(mech: Mechanics, s0, s1, s2, have_history):
    """Next start state of the cycle iteration, accelerated where the iteration is geometric.

    When gross slip freezes a partial-slip mechanism (vertical flanks, 90R), the end state of a pair
    of half-cycles is an affine function of its start state on a line of admissible states, so the
    iterates s0, s1, s2 satisfy s2 - s1 = rho (s1 - s0) and the fixed point s2 + rho/(1-rho)(s2-s1)
    is exact. It is used only where that structure is verified and the state is admissible; the
    following pair then checks closure as usual. Otherwise the plain iterate s2 is returned.
    """
    d1, d2 = s1 - s0, s2 - s1
    n1 = jnp.dot(d1, d1)
    ok = have_history & (n1 > 1e-30)
    rho = jnp.where(ok, jnp.dot(d2, d1) / jnp.where(ok, n1, 1.0), 0.0)
    collinear = jnp.linalg.norm(d2 - rho * d1) <= 1e-6 * jnp.sqrt(jnp.dot(d2, d2)) + 1e-15
    ok = ok & collinear & (rho > -0.95) & (rho < 0.95)
    step = jnp.where(ok, rho / jnp.where(ok, 1.0 - rho, 1.0), 0.0)
    guess = s2 + step * d2
    N, T = guess[:3], guess[3:]
    admissible = jnp.all(N > 0.0) & jnp.all(jnp.abs(T) <= mech.mu * N + LIMIT_TOL)
    return jnp.where(ok & admissible, guess, s2)


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
    design = as_design(shape, mu, contacts, load)
    # one design: mu is one number or one per contact (3); any other length broke deep in the
    # kernel as a JAX broadcasting TypeError
    if not isinstance(design.mu, jax.core.Tracer) and np.ndim(design.mu) > 0 \
            and np.shape(design.mu) != (3,):
        raise ValueError(f"mu must be one number or one per contact (3 values) in (0, 5]; "
                         f"got shape {np.shape(design.mu)}")
    return base_cycle_kernel(*design.prepared(), max_tracts=max_tracts, max_pairs=max_pairs)


def _letters():
    return ["0"] + list(string.ascii_uppercase[: 26])


def transitions_chart(bc: BaseCycle) -> list[dict]:
    """The paper's Table 2 form: one row per tract with its contacts in stick / slip / back-slide.

    Rows carry the tract name (0-A, A-B, ...), dv_mm, and a state per contact. A constant-force
    gross-slip stretch that completes the shorter half is a row with every contact in slip
    ('C-C′' at mid-cycle or 'F-0' at the end, as in the paper).
    """
    names = _letters()
    rows, k = [], 0
    longest = max(float(bc.forward.span), float(bc.backward.span))
    for label, half in (("forward", bc.forward), ("backward", bc.backward)):
        active = np.asarray(half.active)
        states = np.asarray(half.state)
        dvs = np.asarray(half.dv)
        for i in np.nonzero(active)[0]:
            rows.append(dict(half=label, tract=f"{names[k]}-{names[k + 1]}", dv_mm=float(dvs[i]),
                             **{c: STATE_NAMES[int(s)] for c, s in zip(CONTACT_NAMES, states[i])}))
            k += 1
        stretch = longest - float(half.span)
        if stretch > 1e-12 * max(longest, 1e-300):
            end = names[k]
            tail = "0" if label == "backward" else f"{end}\u2032"  # the paper's C′
            rows.append(dict(half=label, tract=f"{end}-{tail}", dv_mm=stretch, stretch=True,
                             **{c: "slip" for c in CONTACT_NAMES}))
            if label == "forward":
                names[k] = f"{end}\u2032"
    return rows


__all__ = ["MAX_TRACTS", "MAX_PAIRS", "CLOSE_TOL", "EQUILIBRIUM_TOL", "HalfCycle", "mechanics",
           "half_cycle", "tract_rows", "zeros_of", "bounded_loop", "repeat_until", "LOOPS",
           "check_loop", "values_by_while", "BaseCycle", "base_cycle_kernel",
           "equilibrium_residual", "base_cycle", "transitions_chart"]
