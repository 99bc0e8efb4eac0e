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

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .linalg import combine, rowdot, solve3
from .loops import bounded_loop, zeros_of
from .paths import Line
from .stages import second_look
from .status import RESULTS
from .tract import (CANDIDATE_SETS, LIMIT_TOL, NO_EVENT, OPEN, RATE_TOL, SLIP, STICK,
                    Mechanics, candidate_rates, make_mechanics)

TRAVEL_TOL = 1e-12  # path left (fraction of a run's) below which a run has ended; slip below it is none
NO_EVENT_LIMIT = 1e5  # mm: a run to gross slip with no event nearer than this fails (no gross slip)
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
    K, (wn, wt, wx), (stick, slip, mu) = _stiffness(pads, closed, slipping, signs)
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


def _stiffness(pads: Pads, closed, slipping, signs):
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


class Choice(NamedTuple):
    closed: jnp.ndarray  # (P,) bool
    slipping: jnp.ndarray  # (P,) bool
    signs: jnp.ndarray  # (P,) friction direction of a slipping pad
    dN: jnp.ndarray  # (B, P) rates per unit motion along each basis direction
    dT: jnp.ndarray
    dslip: jnp.ndarray
    consistent: jnp.ndarray  # () bool: some candidate set is consistent


def choose(pads: Pads, N, T, heading, ahead=None, seated: bool = False,
           reduced: tuple[Mechanics, ...] | None = None) -> Choice:
    """The state set of a tract starting at (N, T) with the platforms moving along `heading` (B,)
    (basis weights of the path's direction of motion, scaled to unit pad speed).

    Pads inside the friction cone stick; a pad on its limit sticks (if its stick increment stays
    inside the cone) or slips against its friction force; a pad with a gap stays open; a pad at
    N = 0 opens (if its gap grows) or closes, in stick or slipping. Among the sets consistent to
    first order, those still consistent at `ahead` (B,) basis increments on (an ellipse's
    second-order check: a rate can be zero at a tract's start without changing sign), if any;
    then the one with the most pads strong (stick, closed), closing pads preferably in stick.

    seated=True: only the 2^P sets of closed pads (stick or slip) are tried, and the choice is
    consistent only where no pad is open or at N = 0. There the sets with an open or closing pad
    are not allowed anyway, so the choice is `choose`'s, at half the candidate sets (`run`'s first
    look; the lanes it leaves inconsistent choose again among every set). reduced (three pads,
    seated): `seated_reduction(pads)`, whose closed-form rates (`tract.candidate_rates`) replace
    the sets' 3x3 solves."""
    n_pads = N.shape[0]
    mu = jnp.broadcast_to(pads.mu, N.shape)
    zero = jnp.abs(N) <= LIMIT_TOL
    gap = N < -LIMIT_TOL
    limit = ~zero & ~gap & (jnp.abs(T) >= mu * N - LIMIT_TOL)
    inside = ~zero & ~gap & ~limit
    t_sign = jnp.where(T >= 0.0, 1.0, -1.0)
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
    weak = weak1 if seated else jnp.concatenate([weak1, weak2, weak2])
    n1, n2 = weak1.shape[0], 0 if seated else weak2.shape[0]
    direction = np.repeat([0.0, 1.0, -1.0], [n1, n2, n2])[:, None]
    closing = ~weak & zero2 & (direction != 0.0)
    closed = ~(weak & (zero2 | gap2))
    slipping = (weak & limit2) | closing
    signs = jnp.where(closing, direction, t_sign[None])
    if reduced is None:
        r = _rates(pads, closed, slipping, signs)
    else:  # the same sets (weak: slipping, every pad closed) in closed form, per basis direction
        per = [candidate_rates(m, t_sign, 1.0) for m in reduced]
        r = Rates(*(jnp.stack([getattr(x, f) for x in per], axis=1) for f in ("dN", "dT", "dslip")),
                  functools.reduce(jnp.logical_and, [x.ok for x in per]))
    first = np.arange(weak.shape[0]) < n1
    allowed = (~jnp.any(weak & inside2, axis=1) & ~jnp.any(~weak & gap2, axis=1)
               & (first | zero[z]))
    dN, dT, dslip = (_along(heading, x) for x in (r.dN, r.dT, r.dslip))
    scale = jnp.max(jnp.maximum(pads.kn, pads.kt))
    tol = RATE_TOL * scale
    mu2 = mu[None]
    stick = closed & ~slipping
    # Seated, the conditions of pads at N = 0 are moot (such a choice is not consistent).
    at_zero = not seated
    ok_pad = jnp.where(stick & limit2, t_sign[None] * dT - mu2 * dN <= tol, True)
    ok_pad &= jnp.where(slipping, signs * dslip <= RATE_TOL, True)
    if at_zero:
        ok_pad &= jnp.where(stick & zero2, (dN >= -tol) & (jnp.abs(dT) - mu2 * dN <= tol), True)
        ok_pad &= jnp.where(slipping & zero2, dN >= -tol, True)
        ok_pad &= jnp.where(~closed & zero2, dN <= tol, True)
    good = allowed & r.ok & jnp.all(ok_pad, axis=1)
    if ahead is not None:
        N1, T1, slid = (N[None] + _along(ahead, r.dN), T[None] + _along(ahead, r.dT),
                        _along(ahead, r.dslip))
        stays = jnp.where(stick & (limit2 | zero2), jnp.abs(T1) <= mu2 * N1 + LOOKAHEAD_TOL, True)
        stays &= jnp.where(slipping, signs * slid <= LOOKAHEAD_TOL * jnp.max(jnp.abs(ahead)),
                           True)
        if at_zero:
            stays &= jnp.where(~closed & zero2, N1 <= LOOKAHEAD_TOL, True)
            stays &= jnp.where(closed & zero2, N1 >= -LOOKAHEAD_TOL, True)
        second = good & jnp.all(stays, axis=1)
        good = jnp.where(jnp.any(second), second, good)
    score = jnp.where(good, 10 + 4 * jnp.sum(~weak, axis=1) + first, 0)
    best = jnp.argmax(score)
    consistent = good[best] & ~jnp.any(zero | gap) if seated else good[best]
    return Choice(closed[best], slipping[best], signs[best], r.dN[best], r.dT[best],
                  r.dslip[best], consistent)


def _choose_seated(pads: Pads, N, T, heading, ahead, reduced) -> Choice:
    """`run`'s first look: `choose` among the closed sets."""
    return choose(pads, N, T, heading, ahead, seated=True, reduced=reduced)


def _choose_all(pads: Pads, N, T, heading, ahead, reduced) -> Choice:
    """`run`'s second look: `choose` among every set (`reduced` is the first look's)."""
    return choose(pads, N, T, heading, ahead)


def seated_reduction(pads: Pads) -> tuple[Mechanics, ...]:
    """The all-stick reduction of three pads (`tract.make_mechanics`) per basis direction of the
    path: what `choose(seated=True, reduced=...)` needs, computed once per run."""
    return tuple(make_mechanics(pads.a, pads.c, pads.nw[b], pads.tw[b], pads.kn, pads.kt, pads.mu)
                 for b in range(pads.nw.shape[0]))


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


def assemble(pads: Pads, load_vector):
    """(N, T, ok): the pad forces after F_D is applied from zero with the platforms held.

    Every contact law is positively homogeneous and the forces start at zero, so the response is
    proportional to the load and one state set holds throughout: per pad stick, slip either way
    or open (4^P candidates), the consistent one that keeps the most pads stuck and closed.
    load_vector: the generalised load on the damper per unit F_D (3,). An open pad's N is its
    virtual force kn * (-gap) <= 0."""
    n_pads = pads.kn.shape[0]
    codes = jnp.asarray(np.array([[(c // 4 ** i) % 4 for i in range(n_pads)]
                                  for c in range(4 ** n_pads)]))
    closed, slipping = codes != 3, (codes == 1) | (codes == 2)
    signs = jnp.where(codes == 2, -1.0, 1.0)
    K, _, (_, _, mu) = _stiffness(pads, closed, slipping, signs)
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


def _rows(n_pads: int, n_basis: int) -> dict:
    f = jax.ShapeDtypeStruct((), float)
    v = jax.ShapeDtypeStruct((n_pads,), float)
    m = jax.ShapeDtypeStruct((n_basis, n_pads), float)
    b = jax.ShapeDtypeStruct((), bool)
    return dict(p0=f, dp=f, N0=v, T0=v, dN=m, dT=m, dslip=m,
                state=jax.ShapeDtypeStruct((n_pads,), int), active=b, stretch=b, slack=f)


def run(pads: Pads, path, N, T, p_start, p_end=None, *, max_tracts: int,
        loop: str = "scan", closed: Mechanics | None = None) -> Tracts:
    """Tracts along `path` (`Line` or `Ellipse`) from p_start to p_end, from the pad forces (N, T)
    (units of F_D; an open pad's N is kn * (-gap)). p_end None (a Line only): until gross slip,
    where no force changes any more. On a line with an end, gross slip before the end is followed
    by a constant-force stretch to it.

    closed (three pads on a Line): their all-stick reduction with the line's direction folded in
    (`tract.along(tract.make_mechanics(...), direction)`); the pads may not open, and a normal
    force reaching zero ends the run as liftoff (the paper's in-phase model; `choose_closed`).
    loop: as `loops.bounded_loop`. Unchecked, traceable."""
    to_gross = p_end is None
    on_line = isinstance(path, Line)
    n_pads, n_basis = N.shape[0], pads.nw.shape[0]
    pads_open = closed is None
    if not pads_open and not (on_line and n_pads == 3):
        raise ValueError("closed is the three-pad model on a Line")
    scale = jnp.max(jnp.maximum(pads.kn, pads.kt))
    rate_tol = RATE_TOL * scale
    mu = jnp.broadcast_to(pads.mu, N.shape)
    p_start = jnp.asarray(p_start, float)
    span = None if to_gross else jnp.abs(jnp.asarray(p_end, float) - p_start)
    # A line's direction of motion is the same all along it.
    line_heading = path.heading(pads, p_start) if on_line else None
    # Values: each tract's state choice tries the closed sets first (three pads: in closed form
    # from their all-stick reduction, computed once per run), and the lanes of a batch that have a
    # pad open or at N = 0 choose again among every set (`stages.second_look`). The derivatives'
    # masked scan chooses among every set (reverse mode cannot pass second_look).
    reduced = seated_reduction(pads) if pads_open and n_pads == 3 and loop == "while" else None
    chooser = (second_look(_choose_seated, _choose_all, lambda ch: ~ch.consistent)
               if loop == "while" else _choose_all)
    # Pads that may not open: one at N = 0 at the start has lifted off.
    lift0 = jnp.array(False) if pads_open else jnp.min(N) <= LIMIT_TOL
    init = dict(N=N, T=T, p=p_start, done=lift0, gross=jnp.array(False),
                failed=jnp.array(False), unseated=jnp.array(False), liftoff=lift0,
                gross_dslip=jnp.zeros((n_basis, n_pads)))

    def step(carry, _):
        N, T, p0 = carry["N"], carry["T"], carry["p"]
        heading = line_heading if on_line else path.heading(pads, p0)
        if pads_open:
            ch = chooser(pads, N, T, heading, path.ahead(p0), reduced)
        else:
            ch = choose_closed(closed, N, T, heading)
        stick = ch.closed & ~ch.slipping
        dN_h, dT_h = combine(heading, ch.dN), combine(heading, ch.dT)
        # Gross slip: no closed pad's force changes any more, and no open pad's gap closes.
        frozen = jnp.max(jnp.where(ch.closed, jnp.maximum(jnp.abs(dN_h), jnp.abs(dT_h)),
                                   jnp.maximum(dN_h, 0.0))) <= rate_tol
        gross = ch.consistent & frozen

        def event(f0, A, where):  # a quantity that must stay >= 0 falls through zero
            return jnp.where(where, path.first_descent(f0, A, p0, rate_tol), NO_EVENT)

        tr = lambda x: jnp.swapaxes(x, 0, 1)  # noqa: E731  (B, P) -> (P, B)
        mu_b = mu[None]  # against the (B, P) rates
        kinds = [event(mu * N - T, tr(mu_b * ch.dN - ch.dT), stick),  # 0: slips up
                 event(mu * N + T, tr(mu_b * ch.dN + ch.dT), stick),  # 1: slips down
                 event(N, tr(ch.dN), ch.closed)]  # 2: opens (closed given: lifts off)
        if pads_open:
            kinds += [event(-N, tr(-ch.dN), ~ch.closed),  # 3: closes
                      jnp.where(ch.slipping, path.reversal(tr(ch.signs[None] * ch.dslip), p0),
                                NO_EVENT)]  # 4: slip reverses
        cand = jnp.stack(kinds).reshape(-1)  # (kinds * P,)
        flat = jnp.argmin(cand)
        kind, pad = flat // n_pads, flat % n_pads
        d_event = cand[flat]
        runner_up = jnp.min(jnp.where(jnp.arange(cand.shape[0]) == flat, NO_EVENT, cand))
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
                   slack=jnp.where(advance, slack, 0.0))
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
        return new, out

    end, tr = bounded_loop(step, init, max_tracts, loop, _rows(n_pads, n_basis))
    failed = end["failed"] | ~end["done"]
    status = RESULTS.first({RESULTS.liftoff: end["liftoff"], RESULTS.unseated: failed & end["unseated"],
                            RESULTS.singular: failed})
    return Tracts(**tr, N_end=end["N"], T_end=end["T"], p_end=end["p"], gross_slip=end["gross"],
                  gross_dslip=end["gross_dslip"], status=status)


def empty_tracts(n_pads: int, n_basis: int, max_tracts: int) -> Tracts:
    """A Tracts of zeros (the initial value of an iteration over runs)."""
    zp = jnp.zeros(n_pads)
    return Tracts(**zeros_of(_rows(n_pads, n_basis), max_tracts), N_end=zp, T_end=zp,
                  p_end=jnp.zeros(()), gross_slip=jnp.array(False),
                  gross_dslip=jnp.zeros((n_basis, n_pads)), status=jnp.zeros((), jnp.int32))


def to_gross_slip(pads: Pads, N, T, start_ok, *, max_tracts: int, loop: str = "scan",
                  closed: Mechanics | None = None):
    """(run, reached): the one move to gross slip, a straight run along the pads' one direction
    (B = 1) from (N, T) until every pad that can slip does (`run` with no end: the gross-slip
    history's move from assembly); reached: it got there (ok, gross slip; a pad that opens or
    lifts off first leaves no gross-slip state). Where start_ok is False the start is masked
    (N = 1, T = 0), which keeps the masked run finite. closed: as `run`'s."""
    N = jnp.where(start_ok, N, jnp.ones_like(N))
    T = jnp.where(start_ok, T, 0.0)
    up = run(pads, Line(), N, T, 0.0, None, max_tracts=max_tracts, loop=loop, closed=closed)
    return up, (up.status == RESULTS.ok) & up.gross_slip


__all__ = ["Pads", "Rates", "Choice", "Tracts", "candidate_table", "choose", "choose_closed",
           "seated_reduction",
           "assemble", "run", "to_gross_slip", "empty_tracts", "TRAVEL_TOL", "NO_EVENT", "NO_EVENT_LIMIT"]
