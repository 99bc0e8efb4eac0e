"""The state choice of a tract, and its replay.

At a tract's start every pad's state for the tract must be chosen (stick, slip, open, closing):
`choose` tries every candidate set (per pad a strong or weak choice, the closing pad's slip
direction) and keeps the consistent one with the most pads strong; `propose` tries one set, the
previous tract's with the pads whose events ended it changed, by the same rules (the engine's
first look: one solve instead of 16 or 32); `choose_closed` is the
paper's in-phase model (three closed pads, 8 sets in closed form). A run records what it chose
(`Tape`) and a replay takes those sets again (`replayed_choice`: one solve per tract), which is
what the derivatives differentiate (`loops.values_by_replay`). The engine's step (`engine.run`)
calls these; the contact laws are in `jaxdamp.engine`'s module docstring.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from .linalg import rowdot, solve3
from .tract import (CANDIDATE_SETS, LIMIT_TOL, OPEN, RATE_TOL, SLIP, STICK, Mechanics,
                    candidate_rates)

# Tolerance of the second-order check of a state set on an ellipse (units of F_D; of s_a for
# slips): see `choose`.
LOOKAHEAD_TOL = 1e-13


class Pads(NamedTuple):
    """Everything a tract needs that does not change along a path (a pytree of arrays).

    P pads, B basis directions of the path (1 for a line, 2 for an ellipse: X_r, X_i)."""

    a: jnp.ndarray  # (P, 3) generalised outward normals about D
    c: jnp.ndarray  # (P, 3) generalised up-flank tangents
    kn: jnp.ndarray  # (P,) normal stiffness / F_D, 1/mm
    kt: jnp.ndarray  # (P,) tangential stiffness / F_D, 1/mm
    mu: jnp.ndarray  # () or (P,)
    nw: jnp.ndarray  # (B, P) platform motion along each pad's normal per mm of s along basis b
    tw: jnp.ndarray  # (B, P) along its tangent


class Rates(NamedTuple):
    """Rates of every candidate state set per unit motion along each basis direction."""

    dN: jnp.ndarray  # (C, B, P); an open pad's is the rate of its virtual force kn * (-gap)
    dT: jnp.ndarray  # (C, B, P)
    dslip: jnp.ndarray  # (C, B, P) sliding of the damper relative to the platform, along t
    ok: jnp.ndarray  # (C,) the tract's 3x3 system is regular


def candidate_table(n_pads: int):
    """weak (S, P) bool, S = 2^P: per pad a strong (stick, closed) or weak (slip at its limit;
    open at N = 0) choice (numpy: the table is static)."""
    return np.array([[(c >> i) & 1 for i in range(n_pads)] for c in range(2 ** n_pads)], bool)


def _rates(pads: Pads, closed, slipping, signs) -> Rates:
    """Rates of C state sets at once: closed, slipping (C, P) bool, signs (C, P) (T = s mu N).

    Written as explicit products and sums over the pads and the 3 components (no einsum): under
    vmap a tiny contraction becomes a batched dot_general, which XLA on CPU runs as a loop of small
    matrix products, while products and sums fuse (`linalg.rowdot`)."""
    K, (wn, wt, wx), (stick, slip, mu) = set_stiffness(pads, closed, slipping, signs)
    a, c = pads.a, pads.c
    n_pads, n_basis = a.shape[0], pads.nw.shape[0]
    rhs = jnp.stack([sum((wn[:, i, None] * pads.nw[b, i]) * a[i][None]
                         + (wt[:, i, None] * pads.tw[b, i] - wx[:, i, None] * pads.nw[b, i])
                         * c[i][None] for i in range(n_pads))
                     for b in range(n_basis)], axis=1)  # (C, B, 3)
    dq, ok = solve3(K[:, None], rhs)  # (C, B, 3): one 3x3 system, B right-hand sides
    gn = jnp.stack([rowdot(dq, a[i]) for i in range(n_pads)], -1) - pads.nw[None]
    gt = jnp.stack([rowdot(dq, c[i]) for i in range(n_pads)], -1) - pads.tw[None]
    per = lambda x: x[:, None]  # noqa: E731  (C or 1, P) -> (C or 1, 1, P) against (C, B, P)
    kn, kt = pads.kn[None], pads.kt[None]
    dN = per(kn) * gn
    dT = per(stick) * (-per(kt) * gt) + per(slip * signs * mu) * dN
    dslip = per(slip) * (gt + dT / per(kt))
    return Rates(dN, dT, dslip, jnp.all(ok, axis=1))


def set_stiffness(pads: Pads, closed, slipping, signs):
    """(K (C, 3, 3), pad weights (wn, wt, wx), (stick, slip, mu)) of C state sets: the damper's
    incremental stiffness sum_closed kn a a^T + sum_stick kt c c^T - sum_slip s mu kn c a^T."""
    f = lambda b: b.astype(float)  # noqa: E731
    kn, kt = pads.kn[None], pads.kt[None]  # (1, P) against the (C, P) table
    mu = jnp.broadcast_to(pads.mu, pads.kn.shape)[None]
    stick = f(closed & ~slipping)
    slip = f(closed & slipping)
    wn, wt, wx = f(closed) * kn, stick * kt, slip * signs * mu * kn
    a, c = pads.a, pads.c
    outer = lambda u, v: (u[:, None] * v[None, :])[None]  # noqa: E731  (1, 3, 3)
    K = sum(wn[:, i, None, None] * outer(a[i], a[i]) + wt[:, i, None, None] * outer(c[i], c[i])
            - wx[:, i, None, None] * outer(c[i], a[i]) for i in range(a.shape[0]))
    return K, (wn, wt, wx), (stick, slip, mu)


def _along(weights, x):
    """sum_b weights[b] x[:, b] for rates x (C, B, P): the rates along a direction of motion."""
    return sum(weights[b] * x[:, b] for b in range(x.shape[1]))


def _pad_classes(pads: Pads, N, T):
    """(mu, zero, gap, limit, inside, t_sign) per pad at the forces (N, T): at N = 0, open (a gap:
    an open pad's virtual N < 0), on the friction limit, inside the cone; the sign of T."""
    mu = jnp.broadcast_to(pads.mu, N.shape)
    zero = jnp.abs(N) <= LIMIT_TOL
    gap = N < -LIMIT_TOL
    limit = ~zero & ~gap & (jnp.abs(T) >= mu * N - LIMIT_TOL)
    inside = ~zero & ~gap & ~limit
    return mu, zero, gap, limit, inside, jnp.where(T >= 0.0, 1.0, -1.0)


def _judged(pads: Pads, N, T, heading, ahead, closed, slipping, signs, r: Rates, classes):
    """(first, second) (C,) bool for C state sets (closed, slipping, signs (C, P)) with rates r
    (classes: `_pad_classes` of (N, T), which the caller has already):
    consistent to first order along `heading` (a stick pad on its limit stays in the cone, a
    slipping pad slides against its friction force, a pad at N = 0 closes or opens as its state
    says; and the set's system is regular), and still so at `ahead` basis increments on (the
    second-order check; all True where ahead is None)."""
    mu, zero, _, limit, _, t_sign = classes
    zero2, limit2, mu2 = zero[None], limit[None], mu[None]
    dN, dT, dslip = (_along(heading, x) for x in (r.dN, r.dT, r.dslip))
    tol = RATE_TOL * jnp.max(jnp.maximum(pads.kn, pads.kt))
    stick = closed & ~slipping
    ok_pad = jnp.where(stick & limit2, t_sign[None] * dT - mu2 * dN <= tol, True)
    ok_pad &= jnp.where(slipping, signs * dslip <= RATE_TOL, True)
    ok_pad &= jnp.where(stick & zero2, (dN >= -tol) & (jnp.abs(dT) - mu2 * dN <= tol), True)
    ok_pad &= jnp.where(slipping & zero2, dN >= -tol, True)
    ok_pad &= jnp.where(~closed & zero2, dN <= tol, True)
    first = r.ok & jnp.all(ok_pad, axis=1)
    if ahead is None:
        return first, jnp.ones_like(first)
    N1, T1, slid = (N[None] + _along(ahead, r.dN), T[None] + _along(ahead, r.dT),
                    _along(ahead, r.dslip))
    stays = jnp.where(stick & (limit2 | zero2), jnp.abs(T1) <= mu2 * N1 + LOOKAHEAD_TOL, True)
    stays &= jnp.where(slipping, signs * slid <= LOOKAHEAD_TOL * jnp.max(jnp.abs(ahead)), True)
    stays &= jnp.where(~closed & zero2, N1 <= LOOKAHEAD_TOL, True)
    stays &= jnp.where(closed & zero2, N1 >= -LOOKAHEAD_TOL, True)
    return first, jnp.all(stays, axis=1)


class Choice(NamedTuple):
    closed: jnp.ndarray  # (P,) bool
    slipping: jnp.ndarray  # (P,) bool
    signs: jnp.ndarray  # (P,) friction direction of a slipping pad
    dN: jnp.ndarray  # (B, P) rates per unit motion along each basis direction
    dT: jnp.ndarray
    dslip: jnp.ndarray
    consistent: jnp.ndarray  # () bool: the set is consistent (`choose`: the best candidate's)


def choose(pads: Pads, N, T, heading, ahead=None) -> Choice:
    """The state set of a tract starting at (N, T) with the platforms moving along `heading` (B,)
    (basis weights of the path's direction of motion, scaled to unit pad speed).

    Pads inside the friction cone stick; a pad on its limit sticks (if its stick increment stays
    inside the cone) or slips against its friction force; a pad with a gap stays open; a pad at
    N = 0 opens (if its gap grows) or closes, in stick or slipping. Among the sets consistent to
    first order, those still consistent at `ahead` (B,) basis increments on (an ellipse's
    second-order check: a rate can be zero at a tract's start without changing sign), if any;
    then the one with the most pads strong (stick, closed), closing pads preferably in stick."""
    n_pads = N.shape[0]
    classes = _pad_classes(pads, N, T)
    _, zero, gap, limit, inside, t_sign = classes
    zero2, gap2, limit2, inside2 = zero[None], gap[None], limit[None], inside[None]

    # Every weak/strong choice per pad, pads at N = 0 that close in stick; then the sets in which
    # the first pad at N = 0 closes slipping up, and slipping down (the other pads' choices as
    # before; every closing pad slips the same way). Until 2026-11-26 every set was tried with
    # both slip directions (3 x 2^P sets): 28 600 flops per lane of a batched choice on three pads
    # against 18 000 now (XLA's count), with the same cycles on the 230 cases of
    # benchmarks/pads_vs_marcher.py and the 360 of ellipse_vs_marcher.py; only a second pad at
    # N = 0 at the same instant (a tie of two events) has fewer sets. Choosing the direction from
    # the stuck set's trial increment (return mapping) would need 2^(P-1) sets fewer, but two
    # rounds of solves: 13 500 flops, and 20 % more to compile in a first CLI call (measured).
    weak1 = jnp.asarray(candidate_table(n_pads))
    z = jnp.argmax(zero)  # pad 0 where none is at N = 0: its closing sets are then disallowed
    pad = np.arange(n_pads)
    column = jnp.clip(pad - (pad > z), 0, n_pads - 2)  # each pad's column among the others
    weak2 = jnp.where(pad[None] == z, False, jnp.asarray(candidate_table(n_pads - 1))[:, column])
    weak = jnp.concatenate([weak1, weak2, weak2])
    n1, n2 = weak1.shape[0], weak2.shape[0]
    direction = np.repeat([0.0, 1.0, -1.0], [n1, n2, n2])[:, None]
    closing = ~weak & zero2 & (direction != 0.0)
    closed = ~(weak & (zero2 | gap2))
    slipping = (weak & limit2) | closing
    signs = jnp.where(closing, direction, t_sign[None])
    r = _rates(pads, closed, slipping, signs)
    first = np.arange(weak.shape[0]) < n1
    allowed = (~jnp.any(weak & inside2, axis=1) & ~jnp.any(~weak & gap2, axis=1)
               & (first | zero[z]))
    good, second = _judged(pads, N, T, heading, ahead, closed, slipping, signs, r, classes)
    good = allowed & good
    if ahead is not None:
        second = good & second
        good = jnp.where(jnp.any(second), second, good)
    score = jnp.where(good, 10 + 4 * jnp.sum(~weak, axis=1) + first, 0)
    best = jnp.argmax(score)
    return Choice(closed[best], slipping[best], signs[best], r.dN[best], r.dT[best],
                  r.dslip[best], good[best])


def propose(pads: Pads, N, T, heading, ahead, last) -> Choice:
    """`run`'s first look: the previous tract's state set with the pads whose events ended it
    changed (slips, opens, or sticks where it closed or its slip reversed; unchanged where the
    path's end ended it), its rates (one 3x3 solve) and whether it is consistent by `choose`'s
    rules, to first and second order. last: (state (P,), kind (P,), known): the previous tract's
    states, the kind of event that ended it per pad (`run`'s kinds; -1 for none; more than one
    pad where events tie) and whether there was one (a run's first tract may have none: then
    it is not consistent). Where it is consistent it is
    `choose`'s choice (checked on every tract of the cases of benchmarks/pads_vs_marcher.py and
    ellipse_vs_marcher.py); where not, `run` chooses among every set (`stages.second_look`)."""
    state, kind, known = last
    classes = _pad_classes(pads, N, T)
    t_sign = classes[5]
    state = jnp.where((kind == 0) | (kind == 1), SLIP, state)
    state = jnp.where(kind == 2, OPEN, state)
    state = jnp.where(kind >= 3, STICK, state)
    # Closing slipping is not proposed here (`propose_again` does).
    return _proposed(pads, N, T, heading, ahead, state != OPEN, state == SLIP, t_sign,
                     jnp.zeros_like(kind, bool), known, classes)


def _proposed(pads: Pads, N, T, heading, ahead, closed, slipping, signs, closing, allowed,
              classes) -> Choice:
    """One proposed state set (closed, slipping, signs (P,)), its rates (one 3x3 solve) and
    whether it is consistent: allowed, a set `choose` tries (an open pad at N = 0 or with a gap,
    a slipping one on its limit with T's sign or closing, a stuck one closed) and consistent by
    its rules to first and second order."""
    _, zero, gap, limit, _, _ = classes
    allowed &= jnp.all(jnp.where(closed, jnp.where(slipping, limit | closing, ~gap), zero | gap))
    r = _rates(pads, closed[None], slipping[None], signs[None])
    good, second = _judged(pads, N, T, heading, ahead, closed[None], slipping[None],
                           signs[None], r, classes)
    return Choice(closed, slipping, signs, r.dN[0], r.dT[0], r.dslip[0],
                  allowed & good[0] & second[0])


def propose_again(pads: Pads, N, T, heading, ahead, first: Choice, known) -> Choice:
    """`run`'s second look before the choice among every set, where `propose`'s set (first)
    failed `choose`'s rules: that set with its failing pads changed (a stuck pad on its limit
    that leaves the cone slips; a stuck pad at N = 0, closing, whose |T| grows past mu N slips,
    with the sign of T's growth; a slipping pad whose slip turns sticks), its rates (one 3x3
    solve) and whether it is consistent by `choose`'s rules, as `propose` (and as there, where
    it is consistent it is `choose`'s choice: checked on the cases of pads_vs_marcher.py and
    ellipse_vs_marcher.py). Not consistent where no pad changed or a pad at N = 0 would open.
    known: the first set was a previous tract's (`propose`'s last[2])."""
    classes = _pad_classes(pads, N, T)
    mu, zero, _, limit, _, t_sign = classes
    dN, dT, dslip = (_along(heading, x[None])[0] for x in (first.dN, first.dT, first.dslip))
    tol = RATE_TOL * jnp.max(jnp.maximum(pads.kn, pads.kt))
    out = t_sign * dT - mu * dN > tol  # leaves the cone (a pad on its limit)
    grows = jnp.abs(dT) - mu * dN > tol  # |T| grows past mu N (a pad closing at N = 0)
    turns = first.signs * dslip > RATE_TOL  # slides along its friction force
    if ahead is not None:  # `_judged`'s second-order check
        N1 = N + _along(ahead, first.dN[None])[0]
        T1 = T + _along(ahead, first.dT[None])[0]
        beyond = jnp.abs(T1) > mu * N1 + LOOKAHEAD_TOL
        out, grows = out | beyond, grows | beyond
        turns |= (first.signs * _along(ahead, first.dslip[None])[0]
                  > LOOKAHEAD_TOL * jnp.max(jnp.abs(ahead)))
    stick = first.closed & ~first.slipping
    leaves, closing = stick & limit & out, stick & zero & grows
    sticks = first.slipping & ~zero & turns
    opens = stick & zero & (dN < -tol)  # `choose`'s to find
    slipping = (first.slipping & ~sticks) | leaves | closing
    signs = jnp.where(closing, jnp.where(dT >= 0.0, 1.0, -1.0), t_sign)
    return _proposed(pads, N, T, heading, ahead, first.closed, slipping, signs, closing,
                     known & jnp.any(leaves | closing | sticks) & ~jnp.any(opens), classes)


def choose_closed(closed: Mechanics, N, T, heading) -> Choice:
    """`choose` for three pads that may not open, on a `Line`: the paper's in-phase model, where a
    normal force reaching zero is liftoff. Only the 8 stick/slip sets remain, and their rates come
    in closed form from the all-stick reduction (`tract.candidate_rates`, Woodbury: measured faster
    than a 3x3 solve per set, benchmarks/bench_core.py). `closed` is `tract.make_mechanics` of
    the pads with the line's direction folded in (`tract.along`: rates per unit s)."""
    mu = jnp.broadcast_to(closed.mu, N.shape)
    limit = jnp.abs(T) >= mu * N - LIMIT_TOL
    signs = jnp.where(T >= 0.0, 1.0, -1.0)
    slipping = jnp.asarray(CANDIDATE_SETS)  # (8, 3)
    r = candidate_rates(closed, signs, 1.0)  # (8, 3) per unit s
    # `choose`'s tolerances on rates at unit pad speed (heading), applied to the rates per unit s
    h = heading[0]
    tol = RATE_TOL * jnp.max(jnp.maximum(closed.kn, closed.kt)) / h
    limit2, signs2, mu2 = limit[None], signs[None], mu[None]
    ok_pad = jnp.where(~slipping & limit2, signs2 * r.dT - mu2 * r.dN <= tol, True)
    ok_pad &= jnp.where(slipping, signs2 * r.dslip <= RATE_TOL / h, True)
    good = ~jnp.any(slipping & ~limit2, axis=1) & r.ok & jnp.all(ok_pad, axis=1)
    best = jnp.argmax(jnp.where(good, 10 + jnp.sum(~slipping, axis=1), 0))
    basis = lambda x: x[best][None]  # noqa: E731  (P,) -> (B = 1, P)
    return Choice(jnp.ones(3, bool), slipping[best], signs, basis(r.dN), basis(r.dT),
                  basis(r.dslip), good[best])


class Tape(NamedTuple):
    """What a run chose, tract by tract (leading tract axis): the state set of each tract, which a
    replay of the run (`run(replay=...)`) takes instead of choosing again. A replay computes the
    same tracts (the same events, closed form) with one 3x3 solve per tract instead of a choice
    among every candidate set: the program that forward and reverse mode differentiate
    (`loops.values_by_replay`)."""

    state: jnp.ndarray  # (nt, P) STICK / SLIP / OPEN
    signs: jnp.ndarray  # (nt, P) friction direction of each slipping pad
    chosen: jnp.ndarray  # (nt,) bool: the choice was consistent
    # (nt,) int: the event that ended the tract, kind * P + pad (`run`'s kinds), or -1 where the
    # path's end or gross slip did
    event: jnp.ndarray


def one_set(pads: Pads, closed, slipping, signs):
    """(K, ok, (wn, wt, wx), (stick, slip, mu)) of one state set in matrix form: `set_stiffness`'s
    K, guarded like `linalg.solve3` (ok: |det| above 1e-12 of the product of its row norms); a
    replay's (`replayed_choice`, `assemble(replay=...)`)."""
    f = lambda b: b.astype(float)  # noqa: E731
    mu = jnp.broadcast_to(pads.mu, pads.kn.shape)
    stick, slip = f(closed & ~slipping), f(closed & slipping)
    wn, wt, wx = f(closed) * pads.kn, stick * pads.kt, slip * signs * mu * pads.kn
    a, c = pads.a, pads.c
    K = a.T @ (wn[:, None] * a) + c.T @ (wt[:, None] * c) - c.T @ (wx[:, None] * a)
    det = jnp.linalg.det(K)
    ok = det * det > 1e-24 * jnp.prod(jnp.sum(K * K, axis=1))
    return jnp.where(ok, K, jnp.eye(3)), ok, (wn, wt, wx), (stick, slip, mu)


def replayed_choice(pads: Pads, row: Tape) -> Choice:
    """A replayed tract's state set (`Tape` row) and its rates: `_rates` of one set in matrix
    form. `_rates` writes every product out for the batched throughput of many candidate sets on
    a CPU; for one set that is 675 operations in the tract's program, which reverse mode then
    transposes, against about 40 here (the derivatives' compile: measured in docs/motions.md)."""
    closed, slipping = row.state != OPEN, row.state == SLIP
    K, ok, (wn, wt, wx), (stick, slip, mu) = one_set(pads, closed, slipping, row.signs)
    a, c = pads.a, pads.c
    per = lambda v: v[None]  # noqa: E731  (P,) against the (B, P) motions and rates
    rhs = (per(wn) * pads.nw) @ a + (per(wt) * pads.tw - per(wx) * pads.nw) @ c  # (B, 3)
    dq = jnp.linalg.solve(K, rhs.T).T  # (B, 3)
    gn, gt = dq @ a.T - pads.nw, dq @ c.T - pads.tw  # (B, P)
    dN = per(pads.kn) * gn
    dT = per(stick) * (-per(pads.kt) * gt) + per(slip * row.signs * mu) * dN
    dslip = per(slip) * (gt + dT / per(pads.kt))
    zero = lambda x: jnp.where(ok, x, 0.0)  # noqa: E731
    return Choice(closed, slipping, row.signs, zero(dN), zero(dT), zero(dslip), row.chosen & ok)


def empty_tape(n_pads: int, max_tracts: int, n_runs: int) -> Tape:
    """A Tape of zeros for n_runs runs (leading run axis; the records of an iteration's legs)."""
    return Tape(jnp.zeros((n_runs, max_tracts, n_pads), int),
                jnp.zeros((n_runs, max_tracts, n_pads)), jnp.zeros((n_runs, max_tracts), bool),
                jnp.full((n_runs, max_tracts), -1))


__all__ = ["LOOKAHEAD_TOL", "Pads", "Rates", "Choice", "Tape", "candidate_table", "choose", "propose",
           "propose_again",
           "choose_closed", "set_stiffness", "one_set",
           "replayed_choice", "empty_tape"]
