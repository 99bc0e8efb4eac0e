"""The tract engine for any pad set on any platform path, with pads that open and close.

A run goes tract by tract along a platform path from given pad forces. Within a tract every pad's
state is fixed (stick, slip, open), so the damper's incremental equilibrium is linear and every
force is affine in the path's basis functions phi(p):

    F(p) = F(p0) + sum_b R_b (phi_b(p) - phi_b(p0))

with R_b the rates for a unit motion along basis direction b (one 3x3 solve per direction).
Two paths (`jaxdamp.paths`: `Line`, `Ellipse`):

- a straight line, phi(s) = s (mm of travel along one direction): every event is linear in s;
- an ellipse, X(tau) = s_a (X_r cos tau - X_i sin tau), phi(tau) = s_a (cos tau, -sin tau):
  every event is a root of c + alpha cos tau + beta sin tau = 0, in closed form.

Pads (any number P, `Pads`): the curved-flat damper R1 | L1, L2 or the wedge R1, R2 | L1, L2.
A pad is closed (N > 0, a normal spring kn and a tangential spring kt in series with a Coulomb
slider) or open: N = 0 and its springs released. An open pad's normal gap is carried in its N as
the virtual force kn * (-gap) < 0, affine along the path like every other force; it closes (in
stick, with a fresh tangential anchor: T = 0) where that reaches zero. Events: a stick pad reaching
its friction limit, a slipping pad whose slip rate reverses (an ellipse only: on a line it is
constant in a tract), a closed pad's N reaching zero (it opens), an open pad's gap closing, and the
end of the path. The state set of each tract is the consistent one (`choose`) that keeps the most
pads in stick and closed; none consistent means no set of pads holds the damper: it is unseated.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .choice import (LOOKAHEAD_TOL, Choice, Pads, Rates, Tape, candidate_table, choose,
                     choose_closed, empty_tape, one_set, propose, propose_again, replayed_choice,
                     set_stiffness)
from .linalg import combine, rowdot, solve3
from .loops import bounded_loop, zeros_of
from .paths import Line
from .stages import CHUNK, second_look
from .status import RESULTS
from .tract import LIMIT_TOL, NO_EVENT, OPEN, RATE_TOL, SLIP, STICK, Mechanics

TRAVEL_TOL = 1e-12  # path left (fraction of a run's) below which a run has ended; slip below it is none
TIE_TOL = 1e-9  # events nearer than this (of the larger of the tract's length and 1) are tied
NO_EVENT_LIMIT = 1e5  # mm: a run to gross slip with no event nearer than this fails (no gross slip)


def assemble(pads: Pads, load_vector, record: bool = False, replay=None):
    """(N, T, ok): the pad forces after F_D is applied from zero with the platforms held.

    Every contact law is positively homogeneous and the forces start at zero, so the response is
    proportional to the load and one state set holds throughout: per pad stick, slip either way
    or open (4^P candidates), the consistent one that keeps the most pads stuck and closed.
    load_vector: the generalised load on the damper per unit F_D (3,). An open pad's N is its
    virtual force kn * (-gap) <= 0. record: (N, T, ok, choice), the set chosen; replay: a
    choice recorded so, whose set alone is solved (`loops.values_by_replay`)."""
    n_pads = pads.kn.shape[0]
    codes = jnp.asarray(np.array([[(c // 4 ** i) % 4 for i in range(n_pads)]
                                  for c in range(4 ** n_pads)]))
    closed, slipping = codes != 3, (codes == 1) | (codes == 2)
    signs = jnp.where(codes == 2, -1.0, 1.0)
    if replay is not None:
        best, good = replay
        K, ok, _, (_, _, mu) = one_set(pads, closed[best], slipping[best], signs[best])
        q = jnp.linalg.solve(K, jnp.asarray(load_vector, float))
        N = pads.kn * (pads.a @ q)
        gt = pads.c @ q
        T = jnp.where(slipping[best], signs[best] * mu * N, jnp.where(closed[best], -pads.kt * gt, 0.0))
        return N, T, good & ok
    K, _, (_, _, mu) = set_stiffness(pads, closed, slipping, signs)
    q, ok = solve3(K, jnp.broadcast_to(jnp.asarray(load_vector, float), (codes.shape[0], 3)))
    kn, kt = pads.kn[None], pads.kt[None]
    N = kn * jnp.stack([rowdot(q, a_i) for a_i in pads.a], -1)
    gt = jnp.stack([rowdot(q, c_i) for c_i in pads.c], -1)
    T = jnp.where(slipping, signs * mu * N, jnp.where(closed, -kt * gt, 0.0))
    slid = gt + T / kt  # slip of the damper relative to the platform, along t
    tol = LIMIT_TOL
    good = (ok & jnp.all(jnp.where(closed & ~slipping, jnp.abs(T) <= mu * N + tol, True), axis=1)
            & jnp.all(jnp.where(slipping, signs * slid <= tol, True), axis=1)
            & jnp.all(jnp.where(closed, N >= -tol, N <= tol), axis=1))
    score = jnp.where(good, 10 + jnp.sum(codes == 0, axis=1) + 4 * jnp.sum(closed, axis=1), 0)
    best = jnp.argmax(score)
    if record:
        return N[best], T[best], good[best], (best, good[best])
    return N[best], T[best], good[best]


class Tracts(NamedTuple):
    """The tracts of a run (leading tract axis). The forces of tract k at p are
    N0 + dN . (phi(p) - phi(p0)), likewise T and the slip; state per pad."""

    p0: jnp.ndarray  # (nt,) where the tract starts (mm of travel, or rad)
    dp: jnp.ndarray  # (nt,) its length
    N0: jnp.ndarray  # (nt, P) forces at its start, units of F_D (open pads: kn * (-gap))
    T0: jnp.ndarray
    dN: jnp.ndarray  # (nt, B, P) (a closed pad's: zero in a constant-force stretch)
    dT: jnp.ndarray
    dslip: jnp.ndarray
    state: jnp.ndarray  # (nt, P) STICK / SLIP / OPEN
    active: jnp.ndarray  # (nt,) bool
    # (nt,) bool: on a line with an end, the constant-force stretch once gross slip is reached
    # (a run to gross slip stops there instead)
    stretch: jnp.ndarray
    # (nt,) path length by which the tract's end beat the nearest competing end (the next event
    # after the one taken, or the nearest event when the path's end ended it); NO_EVENT-based
    # when there is none. On a line, within one sequence of events it is affine in the amplitude;
    # where it reaches zero a new event enters (`jaxdamp.sequence`).
    slack: jnp.ndarray
    N_end: jnp.ndarray  # (P,) forces at the run's end
    T_end: jnp.ndarray
    p_end: jnp.ndarray  # where the run ended
    gross_slip: jnp.ndarray  # bool: reached gross slip (on a line: no force changes any more)
    gross_dslip: jnp.ndarray  # (B, P) sliding rates in the gross-slip state (zero if none reached)
    # RESULTS code: ok; liftoff (pads that may not open: a normal force reached zero); unseated
    # (no consistent state set with a pad open or at N = 0: the closed pads cannot hold the
    # damper); singular (no consistent set otherwise, no event before gross slip, or the tracts
    # ran out)
    status: jnp.ndarray


def tract_rows(n_pads: int, n_basis: int, record: bool = False) -> dict:
    """The shapes and dtypes of one tract's row (a run's step output; `Tracts`' leading-axis
    fields), as `loops.bounded_loop` takes them."""
    f = jax.ShapeDtypeStruct((), float)
    v = jax.ShapeDtypeStruct((n_pads,), float)
    m = jax.ShapeDtypeStruct((n_basis, n_pads), float)
    b = jax.ShapeDtypeStruct((), bool)
    tape = (dict(tape_signs=v, tape_chosen=b, tape_event=jax.ShapeDtypeStruct((), int))
            if record else {})
    return dict(p0=f, dp=f, N0=v, T0=v, dN=m, dT=m, dslip=m,
                state=jax.ShapeDtypeStruct((n_pads,), int), active=b, stretch=b, slack=f, **tape)


class TractMachine(NamedTuple):
    """A run's pieces, for drivers that step runs themselves (`jaxdamp.lanes`): `run` is
    init, then `step` until carry["done"] (at most max_tracts times, each giving one tract's
    row), then `finish`.

    init(N, T, p_start, start_set=None, idle=None) -> carry; step(carry, row) -> (carry, out),
    row a replayed `Tape` row or None; finish(carry, rows) -> Tracts (and the `Tape` where the
    machine records), rows the stacked outputs of the steps (zeros for steps not run)."""

    init: callable
    step: callable
    finish: callable


def machine(pads: Pads, path, p_end=None, *, max_tracts: int, loop: str = "scan",
            closed: Mechanics | None = None, record: bool = False,
            replay: bool = False) -> TractMachine:
    """`run`'s init, step and finish for one design's pads on `path` to p_end (a `TractMachine`);
    the options are `run`'s (replay: whether rows of a `Tape` are given to the steps)."""
    to_gross = p_end is None
    on_line = isinstance(path, Line)
    n_pads, n_basis = pads.a.shape[0], pads.nw.shape[0]
    pads_open = closed is None
    if not pads_open and not (on_line and n_pads == 3):
        raise ValueError("closed is the three-pad model on a Line")
    scale = jnp.max(jnp.maximum(pads.kn, pads.kt))
    rate_tol = RATE_TOL * scale
    mu = jnp.broadcast_to(pads.mu, (n_pads,))
    # A line's direction of motion is the same all along it.
    line_heading = path.heading(pads, 0.0) if on_line else None
    # Values: each tract's state choice first proposes the previous tract's set with the pads
    # whose events ended it changed (`propose`: one solve, verified by `choose`'s rules), and
    # the lanes of a batch whose proposal fails choose among every set (`stages.second_look`);
    # on random shapes one tract in eight or fewer. A masked scan (reverse mode cannot pass
    # second_look) chooses among every set, and a replay takes the recorded sets (`Tape`: one
    # solve and one event root per tract, what derivatives replay). A recording run (the value
    # pass inside a derivative program, `loops.values_by_replay`) chooses among every set at
    # once: the same sets (the first look's contract), one choice in the program instead of
    # two: the example row's elliptic derivative program traced and compiled in 34 s instead of
    # 47 s, and ran as fast (docs/motions.md, 2026-11-29). A replay runs as `loop` says: a
    # masked scan (reverse mode passes) or a while loop that stops where the recorded run ended
    # (forward mode only).
    if replay and not pads_open:
        raise ValueError("replay: a run of pads that may open (closed=None)")
    proposes = pads_open and loop == "while" and not record and not replay

    def proposed(pads, N, T, heading, ahead, last, done):
        # A finished lane asks for no second look (its choice is not used).
        ch = propose(pads, N, T, heading, ahead, last)
        return ch._replace(consistent=ch.consistent | done)

    def every_set(pads, N, T, heading, ahead, last, done):
        return choose(pads, N, T, heading, ahead)

    # The choice among every set costs twice as much per lane with four pads (32 sets against
    # 16): on pools of wedge cycles chunks of 2 lanes were 10-15 % faster than 4 (1 as 2), where
    # the curved-flat damper's were 2-5 % slower (2026-12-01, docs/motions.md, "Cost").
    chunk = CHUNK if n_pads == 3 else CHUNK // 2
    def proposed_again(first, pads, N, T, heading, ahead, last, done):
        ch = propose_again(pads, N, T, heading, ahead, first, last[2])
        return ch._replace(consistent=ch.consistent | done)

    # A wedge's proposals miss more often, a closing pad most (it closes slipping where proposed
    # stuck: about 40 % of the misses at 10 mrad), so its batches try a second proposal before
    # choosing among 32 sets: wedge batches 1.06-1.35x; for the curved-flat damper pools of 256
    # ran 0.86-0.95x and programs compiled 1-4 s slower (docs/motions.md, "Cost", 2026-12-02).
    chooser = (second_look(proposed, every_set, lambda ch: ~ch.consistent, chunk,
                           retry=proposed_again if n_pads == 4 else None)
               if proposes else every_set)

    def init(N, T, p_start, start_set=None, idle=None):
        # Pads that may not open: one at N = 0 at the start has lifted off.
        lift0 = jnp.array(False) if pads_open else jnp.min(N) <= LIMIT_TOL
        done0 = lift0 if idle is None else lift0 | idle
        p_start = jnp.asarray(p_start, float)
        carry = dict(N=N, T=T, p=p_start, done=done0, gross=jnp.array(False),
                     failed=jnp.array(False), unseated=jnp.array(False), liftoff=lift0,
                     gross_dslip=jnp.zeros((n_basis, n_pads)))
        if not to_gross:
            carry["span"] = jnp.abs(jnp.asarray(p_end, float) - p_start)
        if proposes:
            # The previous tract's states and the kinds of event that ended it per pad
            # (`propose`): none before a run's first tract unless the caller knows the set it
            # starts in.
            state0, known0 = ((jnp.zeros(n_pads, int), False) if start_set is None
                              else start_set)
            carry["last"] = (jnp.asarray(state0), jnp.full(n_pads, -1), jnp.asarray(known0))
        return carry

    def step(carry, row):
        N, T, p0 = carry["N"], carry["T"], carry["p"]
        heading = line_heading if on_line else path.heading(pads, p0)
        if replay:
            ch = replayed_choice(pads, row)
        elif pads_open:
            ch = chooser(pads, N, T, heading, path.ahead(p0), carry.get("last"), carry["done"])
        else:
            ch = choose_closed(closed, N, T, heading)
        dN_h, dT_h = combine(heading, ch.dN), combine(heading, ch.dT)
        # Gross slip: no closed pad's force changes any more, and no open pad's gap closes.
        frozen = jnp.max(jnp.where(ch.closed, jnp.maximum(jnp.abs(dN_h), jnp.abs(dT_h)),
                                   jnp.maximum(dN_h, 0.0))) <= rate_tol
        gross = ch.consistent & frozen
        stick = ch.closed & ~ch.slipping

        tr = lambda x: jnp.swapaxes(x, 0, 1)  # noqa: E731  (B, P) -> (P, B)
        mu_b = mu[None]  # against the (B, P) rates
        # Each kind of event: a quantity that must stay >= 0 (f0 now, rates A along the basis)
        # falls through zero, where the pads are in the state that can have it.
        kinds = [(mu * N - T, tr(mu_b * ch.dN - ch.dT), stick),  # 0: slips up
                 (mu * N + T, tr(mu_b * ch.dN + ch.dT), stick),  # 1: slips down
                 (N, tr(ch.dN), ch.closed)]  # 2: opens (closed given: lifts off)
        if pads_open:
            kinds += [(-N, tr(-ch.dN), ~ch.closed),  # 3: closes
                      (N, tr(ch.signs[None] * ch.dslip), ch.slipping)]  # 4: slip reverses

        def when(f0, A, kind):  # path length to the event (closed form)
            if kind == 4:
                return path.reversal(A, p0)
            return path.first_descent(f0, A, p0, rate_tol)

        if not replay:
            cand = jnp.stack([jnp.where(w, when(f0, A, i), NO_EVENT)
                              for i, (f0, A, w) in enumerate(kinds)]).reshape(-1)  # (kinds * P,)
            flat = jnp.argmin(cand)
            d_event = cand[flat]
            runner_up = jnp.min(jnp.where(jnp.arange(cand.shape[0]) == flat, NO_EVENT, cand))
        else:
            # The event the value pass took (none: the path's end or gross slip ended the
            # tract): its root alone. No runner-up is known: a replay's slack is zero (the
            # value pass's is the one returned).
            flat = jnp.maximum(row.event, 0)
            f0, A = (jnp.concatenate([k[i] for k in kinds])[flat] for i in (0, 1))
            root = when(f0, A, 0)
            if pads_open:
                root = jnp.where(flat // n_pads == 4, when(f0, A, 4), root)
            d_event = jnp.where(row.event >= 0, root, NO_EVENT)
            runner_up = d_event
        kind, pad = flat // n_pads, flat % n_pads
        # On a line, gross slip before the end: the rest is a constant-force stretch.
        stretch = on_line and not to_gross
        if to_gross:
            live = ~carry["done"]
            failed_now = ~ch.consistent | (~gross & (d_event >= NO_EVENT_LIMIT))
            advance = live & ~gross & ~failed_now
            by_end = jnp.array(False)
            dp = jnp.where(advance, d_event, 0.0)
            slack = runner_up - dp
        else:
            span = carry["span"]
            d_end = p_end - p0
            # Rounding leaves ~1e-17 of the path after a tract that ends at its end: no tract.
            live = ~carry["done"] & (d_end > TRAVEL_TOL * span)
            failed_now = ~ch.consistent
            advance = live & ~failed_now
            # A tie with an event ends the tract by the path's end (the next run starts there,
            # where `choose` sees the pad on its limit). Ties are structural (a steady cycle's
            # half ends where the next began, a pad on its limit), so rounding must not decide
            # them: an event within TRAVEL_TOL of the path's end is a tie.
            by_end = (d_end <= d_event + TRAVEL_TOL * span) | (stretch & gross)
            dp = jnp.where(advance, jnp.where(by_end, d_end, d_event), 0.0)
            slack = jnp.maximum(jnp.where(by_end, d_event, runner_up) - dp, 0.0)
        if stretch:
            # Closed pads hold their forces; an open pad's gap keeps growing (its virtual N).
            frozen_pad = gross & ch.closed[None]
            dN, dT = jnp.where(frozen_pad, 0.0, ch.dN), jnp.where(frozen_pad, 0.0, ch.dT)
        else:
            dN, dT = ch.dN, ch.dT
        p1 = p0 + dp
        dphi = path.step(p0, dp)
        N1 = N + combine(dphi, dN)
        T1 = T + combine(dphi, dT)
        # Snap: slipping pads stay on their limit line, open pads carry no T, the event pad lands
        # on its limit, opens or closes.
        T1 = jnp.where(ch.slipping, ch.signs * mu * N1, T1)
        T1 = jnp.where(ch.closed, T1, 0.0)
        at_event = advance & ~by_end
        hit = at_event & (jnp.arange(n_pads) == pad)
        T1 = jnp.where(hit & (kind == 0), mu * N1, T1)
        T1 = jnp.where(hit & (kind == 1), -mu * N1, T1)
        N1 = jnp.where(hit & ((kind == 2) | (kind == 3)), 0.0, N1)
        T1 = jnp.where(hit & ((kind == 2) | (kind == 3)), 0.0, T1)
        lifted = (jnp.array(False) if pads_open
                  else advance & ((at_event & (kind == 2)) | (jnp.min(N1) <= LIMIT_TOL)))
        state = jnp.where(ch.closed, jnp.where(ch.slipping, SLIP, STICK), OPEN)
        out = dict(p0=p0, dp=dp, N0=N, T0=T, dN=dN, dT=dT, dslip=ch.dslip, state=state,
                   active=advance, stretch=advance & gross if stretch else jnp.array(False),
                   slack=jnp.where(advance & (not replay), slack, 0.0))
        if record:
            out.update(tape_signs=ch.signs, tape_chosen=ch.consistent,
                       tape_event=jnp.where(at_event, flat, -1))
        new = dict(N=jnp.where(advance, N1, N), T=jnp.where(advance, T1, T),
                   p=jnp.where(advance, jnp.where(by_end, p_end if not to_gross else p1, p1), p0),
                   done=(carry["done"] | ~live | (live & failed_now) | (advance & by_end)
                         | (to_gross & live & gross) | lifted),
                   gross=carry["gross"] | (live & gross),
                   failed=carry["failed"] | (live & failed_now),
                   # No consistent set with a pad open or at N = 0: the closed pads cannot hold
                   # the damper (a failure of the design, not of the solve).
                   unseated=carry["unseated"] | (live & ~ch.consistent
                                                 & jnp.any(N <= LIMIT_TOL)),
                   liftoff=carry["liftoff"] | lifted,
                   gross_dslip=jnp.where(live & gross, ch.dslip, carry["gross_dslip"]))
        if not to_gross:
            new["span"] = carry["span"]
        if proposes:
            # Per pad, the first kind of event at the tract's end (the one taken, and those tied
            # with it or with the path's end: the same event of symmetric pads, a slip reversing
            # at the end of a period), or -1: what the next tract's first look changes.
            tied = (cand <= dp + TIE_TOL * jnp.maximum(dp, 1.0)).reshape(-1, n_pads)
            changes = jnp.where(jnp.any(tied, axis=0), jnp.argmax(tied, axis=0), -1)
            state0, _, known = carry["last"]
            new["last"] = (jnp.where(advance, state, state0),
                           jnp.where(advance, changes, carry["last"][1]), known | advance)
        return new, out

    def finish(end, tr):
        tr = dict(tr)
        failed = end["failed"] | ~end["done"]
        status = RESULTS.first({RESULTS.liftoff: end["liftoff"],
                                RESULTS.unseated: failed & end["unseated"],
                                RESULTS.singular: failed})
        tape = (Tape(tr["state"], tr.pop("tape_signs"), tr.pop("tape_chosen"),
                     tr.pop("tape_event")) if record else None)
        tracts = Tracts(**tr, N_end=end["N"], T_end=end["T"], p_end=end["p"],
                        gross_slip=end["gross"], gross_dslip=end["gross_dslip"], status=status)
        return (tracts, tape) if record else tracts

    return TractMachine(init, step, finish)


def run(pads: Pads, path, N, T, p_start, p_end=None, *, max_tracts: int,
        loop: str = "scan", closed: Mechanics | None = None, record: bool = False,
        replay: Tape | None = None, start_set=None, idle=None):
    """Tracts along `path` (`Line` or `Ellipse`) from p_start to p_end, from the pad forces (N, T)
    (units of F_D; an open pad's N is kn * (-gap)). p_end None (a Line only): until gross slip,
    where no force changes any more. On a line with an end, gross slip before the end is followed
    by a constant-force stretch to it.

    closed (three pads on a Line): their all-stick reduction with the line's direction folded in
    (`tract.along(tract.make_mechanics(...), direction)`); the pads may not open, and a normal
    force reaching zero ends the run as liftoff (the paper's in-phase model; `choose_closed`).
    loop: as `loops.bounded_loop`. record: return (Tracts, Tape), what the run chose; replay (a
    `Tape` of max_tracts rows, pads that may open): take its state sets instead of choosing.
    start_set: (state (P,), known ()): the states of the tract before the run's start (the last
    tract of the previous period), which the run's first tract proposes first (`propose`).
    idle: a bool; where True the run does nothing (no tracts, status ok: a batch's lane whose
    iteration has stopped, `periodic.iterate_to_periodic`). Unchecked, traceable."""
    n_pads, n_basis = N.shape[0], pads.nw.shape[0]
    m = machine(pads, path, p_end, max_tracts=max_tracts, loop=loop, closed=closed,
                record=record, replay=replay is not None)
    init = m.init(N, T, p_start, start_set, idle)
    end, tr = bounded_loop(m.step, init, max_tracts, loop, tract_rows(n_pads, n_basis, record),
                           replay, like=(pads, path, p_start, p_end))
    return m.finish(end, tr)


def end_set(tracts: Tracts):
    """(state (P,), known): the states of a run's last tract, which the next run starts in
    (`run(start_set=...)`); known False where the run had none."""
    last = jnp.max(jnp.where(tracts.active, jnp.arange(tracts.active.shape[0]), -1))
    return tracts.state[jnp.maximum(last, 0)], last >= 0


def empty_tracts(n_pads: int, n_basis: int, max_tracts: int) -> Tracts:
    """A Tracts of zeros (the initial value of an iteration over runs)."""
    zp = jnp.zeros(n_pads)
    return Tracts(**zeros_of(tract_rows(n_pads, n_basis), max_tracts), N_end=zp, T_end=zp,
                  p_end=jnp.zeros(()), gross_slip=jnp.array(False),
                  gross_dslip=jnp.zeros((n_basis, n_pads)), status=jnp.zeros((), jnp.int32))


def to_gross_slip(pads: Pads, N, T, start_ok, *, max_tracts: int, loop: str = "scan",
                  closed: Mechanics | None = None, record: bool = False,
                  replay: Tape | None = None, start_set=None):
    """(run, reached): the one move to gross slip, a straight run along the pads' one direction
    (B = 1) from (N, T) until every pad that can slip does (`run` with no end: the gross-slip
    history's move from assembly); reached: it got there (ok, gross slip; a pad that opens or
    lifts off first leaves no gross-slip state). Where start_ok is False the start is masked
    (N = 1, T = 0), which keeps the masked run finite. closed, replay, start_set: as `run`'s;
    record: the run's `Tape` comes third."""
    N = jnp.where(start_ok, N, jnp.ones_like(N))
    T = jnp.where(start_ok, T, 0.0)
    up = run(pads, Line(), N, T, 0.0, None, max_tracts=max_tracts, loop=loop, closed=closed,
             record=record, replay=replay, start_set=start_set)
    up, tape = up if record else (up, None)
    reached = (up.status == RESULTS.ok) & up.gross_slip
    return (up, reached, tape) if record else (up, reached)


__all__ = ["Pads", "Rates", "Choice", "Tracts", "Tape", "TractMachine", "machine", "tract_rows", "candidate_table", "choose", "choose_closed",
           "propose", "LOOKAHEAD_TOL", "assemble", "run", "to_gross_slip", "end_set", "empty_tracts", "empty_tape", "TRAVEL_TOL", "NO_EVENT", "NO_EVENT_LIMIT"]
