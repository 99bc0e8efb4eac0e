"""One half of an in-phase cycle, from a reversal: the tract engine on a straight path.

Every in-phase cycle the library computes is made of such halves: the Base-Cycle's run to gross
slip (`travel=None`) and the travel-limited halves of a cycle at a prescribed amplitude, its
assembly and its sequence curve (`travel` in mm). They run on the one tract engine
(`jaxdamp.engine.run` on a `Line`, three pads that may not open: a normal force reaching zero is
liftoff, the paper's model), tract by tract with exact events:

    tract length = min(next stick/slip or liftoff event, remaining travel)

A travel-limited half that reaches gross slip before its travel ends finishes with a constant-force
stretch (one more tract with zero force rates). A half to gross slip stops there and keeps the
gross-slip sliding rates (`gross_dslip`); it fails where no event ever comes. `Half` is the
engine's `Tracts` in the in-phase terms (travel dv, back-slide named).
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp

from .conventions import CENTRIFUGAL_LOAD
from .engine import Pads, Tracts, assemble, empty_tracts, to_gross_slip
from .engine import run as run_tracts
from .paths import Line
from .status import number_repr, status_repr
from .tract import BACKSLIDE, LIMIT_TOL, SLIP, Mechanics, along


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


def _as_half(tr: Tracts, state) -> Half:
    """The engine's tracts on a line (B = 1, three pads) in in-phase terms, with `state` (the
    engine's, back-slide named)."""
    one = lambda x: x[:, 0]  # noqa: E731  (nt, B = 1, 3) -> (nt, 3)
    return Half(dv=tr.dp, N0=tr.N0, T0=tr.T0, dN=one(tr.dN), dT=one(tr.dT), dslip=one(tr.dslip),
                state=state, active=tr.active, stretch=tr.stretch, slack=tr.slack,
                N_end=tr.N_end, T_end=tr.T_end, span=jnp.sum(tr.dp), gross_slip=tr.gross_slip,
                gross_dslip=tr.gross_dslip[0], status=tr.status)


def empty_half(max_tracts: int) -> Half:
    """A Half of zeros (the initial value of an iteration over halves)."""
    empty = empty_tracts(3, 1, max_tracts)
    return _as_half(empty, empty.state)


def _pads(mech: Mechanics, moving: Mechanics) -> Pads:
    """The engine's pad constants of the in-phase pads, moving as `moving` says (`tract.along`)."""
    return Pads(mech.a, mech.c, mech.kn, mech.kt, mech.mu, moving.nw[None], moving.tw[None])


def assemble_in_phase(mech: Mechanics):
    """(N, T, ok): the forces after F_D is applied from zero with the platforms held, by the
    engine's one assembly (`engine.assemble`). The in-phase model's three pads may not open: a
    state with an open pad or a normal force at zero is not ok (the cycle's liftoff). Unchecked,
    traceable."""
    N, T, consistent = assemble(_pads(mech, mech), CENTRIFUGAL_LOAD)
    return N, T, consistent & (jnp.min(N) > 0.0)


def gross_slip_from_assembly(mech: Mechanics, *, max_tracts: int, loop: str = "scan"):
    """(N, T, assembled, reached) at the end of the gross-slip history's move in phase: from
    assembly (`assemble_in_phase`) the platforms move up (dv increasing) until every pad slips
    (`engine.to_gross_slip`). assembled: F_D is held at assembly; reached: the move got to gross
    slip. Unchecked, traceable."""
    Na, Ta, assembled = assemble_in_phase(mech)
    moving = along(mech, 1.0)
    up, reached = to_gross_slip(_pads(mech, moving), Na, Ta, assembled, max_tracts=max_tracts,
                                loop=loop, closed=moving)
    return up.N_end, up.T_end, assembled, reached


def run_half(mech: Mechanics, N, T, direction, travel=None, *, max_tracts: int,
             loop: str = "scan", idle=None) -> Half:
    """Tracts from a reversal at (N, T) (units of F_D) with the platforms moving in `direction`
    (+1 when dv increases, -1 when it decreases), until gross slip (travel=None) or over `travel`
    mm of relative platform motion.

    loop="scan" runs max_tracts masked steps (reverse-mode differentiable); loop="while" stops when
    the half is done (the same numbers; values and forward mode only). idle: `engine.run`'s.
    Unchecked, traceable.
    """
    moving = along(mech, direction)
    tr = run_tracts(_pads(mech, moving), Line(), N, T, 0.0, travel, max_tracts=max_tracts, loop=loop,
                    closed=moving, idle=idle)
    # Back-slide (Appendix A): a contact still sliding on the limit line it had at the reversal,
    # tract after tract (named here: the engine's states are stick, slip and open).
    start_sign = jnp.where(T >= 0.0, 1.0, -1.0)
    on_line = jnp.abs(T) >= mech.mu * N - LIMIT_TOL
    same = (tr.state == SLIP) & (jnp.where(tr.T0 >= 0.0, 1.0, -1.0) == start_sign[None])
    back = on_line[None] & (jnp.cumsum(~same, axis=0) == 0)
    return _as_half(tr, jnp.where(back & (tr.state == SLIP), BACKSLIDE, tr.state))


__all__ = ["Half", "run_half", "empty_half", "assemble_in_phase", "gross_slip_from_assembly"]
