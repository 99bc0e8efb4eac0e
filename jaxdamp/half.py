"""The tract engine: one half of a cycle, from a reversal, tract by tract with exact events.

Every cycle the library computes is made of such halves: the Base-Cycle's run to gross slip
(`travel=None`) and the travel-limited halves of a cycle at a prescribed amplitude, its assembly
and its sequence curve (`travel` in mm). Within a tract the contact states are fixed and the forces
are affine in the travel (`tract.choose_states`); a tract ends at the nearest event
(`tract.next_event`: a stick contact reaching its friction limit, a normal force reaching zero) or,
for a travel-limited half, where its travel is spent:

    tract length = min(next stick/slip or liftoff event, remaining travel)

A travel-limited half that reaches gross slip before its travel ends finishes with a constant-force
stretch (one more tract with zero force rates, `stretch`). A half to gross slip stops there and
keeps the gross-slip sliding rates (`gross_dslip`); it fails where no event ever comes.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from .loops import bounded_loop, zeros_of
from .status import from_flags, number_repr, ok_status, status_repr
from .tract import (BACKSLIDE, LIMIT_TOL, OPEN, RATE_TOL, SLIP, STICK, Mechanics, choose_states,
                    next_event)

TRAVEL_TOL = 1e-12  # travel (fraction of a half's) below which a half has ended; slip below it is none
NO_EVENT_LIMIT = 1e5  # mm: a half to gross slip with no event nearer than this fails (no gross slip)


class Half(NamedTuple):
    """One half of a cycle from a reversal. Arrays with a leading tract axis (max_tracts)."""

    dv: jnp.ndarray  # tract lengths, mm of relative platform travel (>= 0)
    N0: jnp.ndarray  # (nt, 3) forces at the tract start, units of F_D
    T0: jnp.ndarray
    dN: jnp.ndarray  # (nt, 3) rates per mm of travel (zero in a constant-force stretch)
    dT: jnp.ndarray
    dslip: jnp.ndarray  # (nt, 3) sliding rate of each contact, mm per mm of travel
    state: jnp.ndarray  # (nt, 3) STICK / SLIP / BACKSLIDE / OPEN
    active: jnp.ndarray  # (nt,) bool, the tract exists
    # (nt,) bool: a travel-limited half's constant-force gross-slip stretch (never in a half to
    # gross slip, which stops there)
    stretch: jnp.ndarray
    # (nt,) mm of travel by which the tract's end beat the nearest competing end (the next contact
    # event after the one taken, or the nearest event when the travel ended it); NO_EVENT-based
    # when there is none. Within one sequence it is affine in the amplitude; where it reaches zero
    # a new event enters and the sequence changes (`jaxdamp.sequence`).
    slack: jnp.ndarray
    N_end: jnp.ndarray  # (3,) forces at the end of the half
    T_end: jnp.ndarray
    span: jnp.ndarray  # mm, total travel of the half (to gross slip, or the travel given)
    gross_slip: jnp.ndarray  # bool: reached gross slip (before the end of the travel, if limited)
    gross_dslip: jnp.ndarray  # (3,) sliding rates in the gross-slip state (zero if none reached)
    # RESULTS code (int32): ok, liftoff (a normal force reached zero) or singular (no consistent
    # state set, no event before gross slip, or the tracts ran out); the two exclude each other.
    status: jnp.ndarray

    def __repr__(self) -> str:
        return (f"Half(status={status_repr(self.status)}, span={number_repr(self.span, 'mm')}, "
                f"tracts={number_repr(jnp.sum(self.active), fmt='.0f')}, "
                f"gross_slip={number_repr(self.gross_slip, fmt='.0f')})")


def half_rows() -> dict:
    """Shapes and dtypes of one recorded tract (dtypes resolved when traced: float64 if x64); they
    spare `bounded_loop` tracing the step once more to find them."""
    f, v = jax.ShapeDtypeStruct((), float), jax.ShapeDtypeStruct((3,), float)
    b = jax.ShapeDtypeStruct((), bool)
    return dict(dv=f, N0=v, T0=v, dN=v, dT=v, dslip=v, state=jax.ShapeDtypeStruct((3,), int),
                active=b, stretch=b, slack=f)


def empty_half(max_tracts: int) -> Half:
    """A Half of zeros (the initial value of an iteration over halves)."""
    z3, b = jnp.zeros(3), jnp.array(False)
    return Half(**zeros_of(half_rows(), max_tracts), N_end=z3, T_end=z3, span=jnp.zeros(()),
                gross_slip=b, gross_dslip=z3, status=ok_status())


def run_half(mech: Mechanics, N, T, direction, travel=None, *, max_tracts: int,
             loop: str = "scan") -> Half:
    """Tracts from a reversal at (N, T) (units of F_D) with the platforms moving in `direction`
    (+1 when dv increases, -1 when it decreases), until gross slip (travel=None) or over `travel`
    mm of relative platform motion.

    loop="scan" runs max_tracts masked steps (reverse-mode differentiable); loop="while" stops when
    the half is done (the same numbers; values and forward mode only). Unchecked, traceable.
    """
    limited = travel is not None  # Python-static: which kind of half this program is
    scale = jnp.max(jnp.maximum(mech.kn, mech.kt))
    start_sign = jnp.where(T >= 0.0, 1.0, -1.0)
    lift0 = jnp.min(N) <= LIMIT_TOL
    init = dict(N=N, T=T, done=lift0, gross=jnp.array(False), liftoff=lift0,
                failed=jnp.array(False), gross_dslip=jnp.zeros(3),
                # Back-slide (Appendix A): a contact still sliding on the limit line it had at the
                # reversal.
                line=jnp.abs(T) >= mech.mu * N - LIMIT_TOL)
    if limited:
        init["rem"] = jnp.asarray(travel, float)

    def step(carry, _):
        N, T = carry["N"], carry["T"]
        choice = choose_states(mech, N, T, direction)
        r = choice.rates
        frozen = jnp.max(jnp.abs(jnp.concatenate([r.dN, r.dT]))) <= RATE_TOL * scale
        gross = choice.consistent & frozen
        ev = next_event(mech, N, T, choice)
        if limited:
            rem = carry["rem"]
            # Rounding leaves ~1e-17 mm of travel after a tract that ends on the extreme: no tract.
            live = ~carry["done"] & (rem > TRAVEL_TOL * travel)
            failed_now = ~choice.consistent
            advance = live & ~failed_now
            # The travel budget is one more event; a tie with a contact event ends the half by
            # travel (the next half starts at a reversal, where `choose_states` sees the contact on
            # its limit). At gross slip the rest of the travel is a constant-force stretch.
            by_travel = gross | (rem <= ev.length)
            lam = jnp.where(advance, jnp.where(by_travel, rem, ev.length), 0.0)
            dN, dT = jnp.where(gross, 0.0, r.dN), jnp.where(gross, 0.0, r.dT)
            slack = jnp.where(by_travel, ev.length, ev.runner_up) - lam
        else:
            live = ~carry["done"]
            failed_now = ~choice.consistent | (~gross & (ev.length >= NO_EVENT_LIMIT))
            advance = live & ~gross & ~failed_now  # gross slip ends the half: no tract
            by_travel = jnp.array(False)
            lam = jnp.where(advance, ev.length, 0.0)
            dN, dT = r.dN, r.dT
            slack = ev.runner_up - lam
        N1 = N + lam * dN
        T1 = T + lam * dT
        # Snap to the limit line: slipping contacts stay on it, the event contact lands on it.
        T1 = jnp.where(choice.slipping, choice.signs * mech.mu * N1, T1)
        at_event = advance & ~by_travel
        hit = jnp.arange(3) == ev.contact
        T1 = jnp.where(at_event & ~ev.opens & hit, ev.side * mech.mu * N1, T1)
        N1 = jnp.where(at_event & ev.opens & hit, 0.0, N1)
        lifted = advance & ((at_event & ev.opens) | (jnp.min(N1) <= LIMIT_TOL))
        line = carry["line"] & choice.slipping & (choice.signs == start_sign)
        back = jnp.where(advance, line, carry["line"] & choice.slipping)
        state = jnp.where(choice.slipping, jnp.where(back, BACKSLIDE, SLIP), STICK)
        state = jnp.where(N <= LIMIT_TOL, OPEN, state)
        out = dict(dv=lam, N0=N, T0=T, dN=dN, dT=dT, dslip=r.dslip, state=state, active=advance,
                   stretch=advance & gross, slack=jnp.where(advance, slack, 0.0))
        new = dict(N=jnp.where(advance, N1, N), T=jnp.where(advance, T1, T),
                   done=carry["done"] | (live & (gross | failed_now)) | lifted
                   | (advance & by_travel),
                   gross=carry["gross"] | (live & gross),
                   liftoff=carry["liftoff"] | lifted,
                   failed=carry["failed"] | (live & failed_now),
                   gross_dslip=jnp.where(live & gross, r.dslip, carry["gross_dslip"]),
                   line=jnp.where(advance, line, carry["line"]))
        if limited:
            new["done"] = new["done"] | ~live
            new["rem"] = jnp.where(advance, jnp.where(by_travel, 0.0, rem - lam), rem)
        return new, out

    end, tr = bounded_loop(step, init, max_tracts, loop, half_rows())
    return Half(**tr, N_end=end["N"], T_end=end["T"], span=jnp.sum(tr["dv"]),
                gross_slip=end["gross"], gross_dslip=end["gross_dslip"],
                status=from_flags(end["liftoff"], end["failed"] | ~end["done"]))


def accelerate(mu, s0, s1, s2, have_history):
    """Next start state (N, T) of an iteration over pairs of halves, accelerated where the iteration
    is geometric.

    Within a fixed pattern of events the pair map is affine, so where its contracting part has one
    direction the iterates satisfy s2 - s1 = rho (s1 - s0) and the fixed point
    s2 + rho/(1-rho)(s2-s1) is exact (e.g. when gross slip freezes a partial-slip mechanism: vertical
    flanks, 90R). It is used only where that structure is verified and the state is admissible; the
    following pair then checks closure as usual. Otherwise the plain iterate s2 is returned.
    """
    d1, d2 = s1 - s0, s2 - s1
    n1 = jnp.dot(d1, d1)
    ok = have_history & (n1 > 1e-30)
    rho = jnp.where(ok, jnp.dot(d2, d1) / jnp.where(ok, n1, 1.0), 0.0)
    off = d2 - rho * d1
    # Squared norms: no square root, whose derivative at zero is NaN.
    collinear = jnp.dot(off, off) <= 1e-12 * jnp.dot(d2, d2) + 1e-30
    ok = ok & collinear & (rho > -0.95) & (rho < 0.95)
    step = jnp.where(ok, rho / jnp.where(ok, 1.0 - rho, 1.0), 0.0)
    guess = s2 + step * d2
    n_pads = s2.shape[0] // 2
    N, T = guess[:n_pads], guess[n_pads:]
    admissible = jnp.all(N > 0.0) & jnp.all(jnp.abs(T) <= mu * N + LIMIT_TOL)
    return jnp.where(ok & admissible, guess, s2)


__all__ = ["Half", "run_half", "empty_half", "half_rows", "accelerate", "TRAVEL_TOL",
           "NO_EVENT_LIMIT"]
