"""The iteration to a periodic cycle: one driver for every path kind and history.

A cycle is iterated in rounds of legs: a (forward, backward) pair of halves in phase and on a
straight path, one period on an ellipse, a pair of moves to gross slip for the path Base-Cycle.
Legs before the first round (a history's preliminary moves) run first. At the end of each round
the state at its start (`top`) is compared with the state it reached (closure within CLOSE_TOL,
units of F_D), and the next round starts from the reached state, extrapolated to the fixed point
where the iteration is geometric (`accelerate`). The caller's `leg` runs one leg and keeps its own
records (halves, periods, spans); the caller's kernel turns what ended into its status.
"""

from __future__ import annotations

import jax.numpy as jnp

from .loops import repeat_until
from .tract import LIMIT_TOL

CLOSE_TOL = 1e-9  # periodicity: the forces at a round's start repeat within this (units of F_D)


MODES = 2  # the most contracting modes a round map may have for `accelerate` to use them
RATIO_LIMIT = 0.95  # a mode contracting slower than this is left to the plain iteration
# The misfit (units of F_D) under which the affine model of the last rounds is taken, whatever
# the differences' size: near the fixed point of a smooth, not affine, round map (an ellipse's
# event times) the misfit falls as the differences squared, and a jump whose model misses by
# this much lands well within CLOSE_TOL of the fixed point.
MISFIT_TOL = 1e-11


def _contracting(c):
    """Whether every root of lambda^m = c_{m-1} lambda^{m-1} + ... + c_0 (the round map's ratios
    on the differences' span) lies within RATIO_LIMIT: Jury's test, m = 1 or 2."""
    r = RATIO_LIMIT
    if c.shape[0] == 1:
        return jnp.abs(c[0]) < r
    a0, a1 = -c[0] / r ** 2, -c[1] / r  # mu^2 + a1 mu + a0 with lambda = r mu
    return (jnp.abs(a0) < 1.0) & (jnp.abs(a1) < 1.0 + a0)


def _det(A):
    """Determinant of a 1x1 or 2x2 matrix in closed form (batched LAPACK calls on matrices this
    small cost more than the rest of the step under vmap)."""
    return A[0, 0] if A.shape[0] == 1 else A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]


def _dot(x, y):
    """x @ y for a small matrix x and a vector or small matrix y, as products and a sum: under
    vmap XLA on CPU runs each tiny dot as a kernel of its own (`linalg.rowdot`)."""
    return jnp.sum(x * y[None, :] if y.ndim == 1 else x[:, :, None] * y[None], axis=1)


def _solve(A, b):
    """A^-1 b for a 1x1 or 2x2 A with a nonzero determinant, by Cramer's rule."""
    if A.shape[0] == 1:
        return b / A[0, 0]
    adj = jnp.array([[A[1, 1], -A[0, 1]], [-A[1, 0], A[0, 0]]])
    return _dot(adj, b) / _det(A)


def _extrapolated(starts, there, m):
    """(fixed point, found) from the last 2m round starts and `there`, the end of the last
    round, where each of the last m differences d_j between successive states is the same
    combination sum_i c_i d_(j-m+i) of the m before it (the round map, affine, keeps their span)
    with contracting ratios. m predictions by the same ratios, not one: with three pads the
    differences live in three dimensions (equilibrium), where one difference in the span of two
    others is a single condition that a transient can meet by chance, and a jump from a
    transient lands, where stuck pads leave a family of periodic cycles, on another member."""
    states = jnp.concatenate([starts[-2 * m:], there[None]])
    diffs = states[1:] - states[:-1]  # 2m differences
    D = jnp.concatenate([diffs[j:j + m].T for j in range(m)])  # (m * 2P, m)
    target = jnp.concatenate([diffs[m + j] for j in range(m)])
    gram = _dot(D.T, D)
    # Columns far from parallel (for m = 1, nonzero); a singular Gram is replaced, not solved.
    scale = jnp.prod(jnp.diag(gram))
    solvable = (scale > 1e-60) & (_det(gram) > 1e-10 * scale)
    c = _solve(jnp.where(solvable, gram, jnp.eye(m)), _dot(D.T, target))
    off = target - _dot(D, c)
    # Squared norms: no square root, whose derivative at zero is NaN.
    spanned = jnp.sum(off * off) <= 1e-12 * jnp.sum(target * target) + MISFIT_TOL ** 2
    ok = solvable & spanned & _contracting(c)
    # On the last m differences (Dl): A Dl = Dl H (H: shift, last column c), d_last = (A - I) e
    # with e = Dl y, (H - I) y = c, and the fixed point is the last start less e.
    last = diffs[m - 1:2 * m - 1].T
    # A select, not `.at[].set` (a scatter: a loop holding one is not compiled as one kernel,
    # `runtime.SMALL_LOOP_FLAG`).
    H = jnp.where(jnp.arange(m) == m - 1, c[:, None], jnp.eye(m, k=-1)) - jnp.eye(m)
    # det(H - I) = +-(1 - sum c): nonzero where every ratio is below one (contracting).
    y = _solve(jnp.where(ok, H, -jnp.eye(m)), c)
    return starts[-1] - _dot(last, jnp.where(ok, y, 0.0)), ok


def accelerate(mu, starts, there, plain):
    """Next start state (N, T) of an iteration over rounds, accelerated where the iteration is
    geometric.

    starts: (2 MODES, 2P) the last round starts, the latest (`top`) last, of which the last
    `plain` are successive iterates of the round map (traced int: rounds since the iteration
    started or was last accelerated); there: where the last round ended. Within a fixed pattern
    of events the round map is affine; where its contracting part has m <= MODES modes (ratios
    below RATIO_LIMIT), every m + 1 successive differences are linearly dependent with the same
    coefficients, and the fixed point follows exactly (minimal polynomial extrapolation; m = 1
    is Aitken's s2 + rho/(1-rho)(s2-s1), e.g. when gross slip freezes a partial-slip mechanism:
    vertical flanks, 90R; m = 2 where two pads' slips settle together, or slip dies out towards
    shakedown). It is used only where that structure is verified (the fewest modes first) and
    the state is admissible; the following round then checks closure as usual. Otherwise the
    plain iterate `there` is returned. Returns (next start, whether it was accelerated).
    """
    guess, ok = there, jnp.array(False)
    for m in range(MODES, 0, -1):  # the fewest modes win: tried last
        g, found = _extrapolated(starts, there, m)
        found = found & (plain >= 2 * m)
        guess, ok = jnp.where(found, g, guess), ok | found
    n_pads = there.shape[0] // 2
    N, T = guess[:n_pads], guess[n_pads:]
    admissible = jnp.all(N > 0.0) & jnp.all(jnp.abs(T) <= mu * N + LIMIT_TOL)
    ok = ok & admissible
    return jnp.where(ok, guess, there), ok


def closure_gap(start, end):
    """How far a round's end state is from its start state (the largest force change, units of
    F_D): the round closes the cycle where this is at most CLOSE_TOL."""
    return jnp.max(jnp.abs(end - start))


def start_of_iteration(N0, T0, records, stop0) -> dict:
    """The iteration's carry before its first leg (`iterate_to_periodic`'s returns)."""
    n = N0.shape[0]
    no = jnp.array(False)
    top0 = jnp.concatenate([N0, T0])
    return dict(N=N0, T=T0, top=top0, starts=jnp.broadcast_to(top0, (2 * MODES, 2 * n)),
                plain=jnp.array(0, jnp.int32), gap=jnp.asarray(jnp.inf), closed=no, failed=no,
                stop=jnp.asarray(stop0), rounds=jnp.array(0, jnp.int32), records=records)


def after_leg(c: dict, N1, T1, bad, records, j, mu, *, legs_per_round: int, pre_legs: int,
              whole_rounds: bool = False) -> dict:
    """The iteration's carry after leg j (k = j - pre_legs within the rounds) ran from (c["N"],
    c["T"]) to (N1, T1): the round's closure at its last leg, the next start (extrapolated where
    the iteration is geometric, `accelerate`), whether to stop; bad: the leg failed; records:
    the caller's, kept."""
    n = N1.shape[0]
    k = j - pre_legs
    starts_round = (k >= 0) & (k % legs_per_round == 0)
    ends = (k >= 0) & (k % legs_per_round == legs_per_round - 1)
    there = jnp.concatenate([N1, T1])
    top = jnp.where(starts_round, jnp.concatenate([c["N"], c["T"]]), c["top"])
    gap = closure_gap(top, there)
    closed = ends & (gap <= CLOSE_TOL)
    starts = jnp.where(starts_round, jnp.concatenate([c["starts"][1:], top[None]]), c["starts"])
    plain = jnp.where(starts_round, jnp.minimum(c["plain"] + 1, 2 * MODES), c["plain"])
    guess, jumped = accelerate(mu, starts, there, plain)
    nxt = jnp.where(ends, guess, there)
    if whole_rounds:
        failed = c["failed"] | bad
        stop = ends & (closed | failed)
    else:
        failed = bad
        stop = closed | failed
    # After a jump the next round starts a new sequence of iterates.
    return dict(N=nxt[:n], T=nxt[n:], top=top, starts=starts,
                plain=jnp.where(ends & jumped, 0, plain),
                gap=jnp.where(ends, gap, c["gap"]), closed=closed & ~failed,
                failed=jnp.where(ends, False, failed) if whole_rounds else failed,
                stop=stop, rounds=c["rounds"] + ends.astype(jnp.int32), records=records)


def stopped_by(round_budget=None):
    """stopped(carry): the iteration has stopped (closed, failed, or round_budget rounds ran)."""
    if round_budget is None:
        return lambda c: c["stop"]
    return lambda c: c["stop"] | (c["rounds"] >= round_budget)


def iterate_to_periodic(leg, N0, T0, mu, records, *, legs_per_round: int, pre_legs: int,
                        max_rounds: int, loop: str, stop0, whole_rounds: bool = False,
                        round_budget=None) -> dict:
    """Run legs from (N0, T0) until a round closes (its end state repeats its start state within
    CLOSE_TOL), a leg fails, or max_rounds rounds (at most round_budget, which may be traced) have
    run.

    leg(records, N, T, j, k, idle) -> (N_end, T_end, bad, records): runs leg j from (N, T), where
    k = j - pre_legs is its index within the rounds (negative for a preliminary leg; the round's
    first leg where k % legs_per_round == 0), and returns the caller's records updated (a pytree)
    and bad, whether the leg failed. idle: the iteration has stopped, and what the leg returns is
    dropped (it runs only as a lane of a batch whose other lanes go on: its tract runs should
    start done, `engine.run(idle=...)`, so that they do not keep the batch's loops going). A
    failed leg stops the iteration at once, or with
    whole_rounds at the end of its round (the Base-Cycle's pair always runs both halves).
    stop0: True where there is nothing to iterate (the start failed). loop: `loops.repeat_until`'s.
    The legs of one path's tract runs also run as one loop over their tracts
    (`lanes.Legs`: the same iteration, `after_leg`).

    Returns a dict: records; N, T (where the next round would start); top (the state at the
    last round's start); gap (the last round's closure, inf before one ended); closed (the last
    round closed and none of its legs failed); rounds (int32, rounds ended).
    """
    stopped = stopped_by(round_budget)

    def step(c, j):
        N1, T1, bad, records = leg(c["records"], c["N"], c["T"], j, j - pre_legs, stopped(c))
        return after_leg(c, N1, T1, bad, records, j, mu, legs_per_round=legs_per_round,
                         pre_legs=pre_legs, whole_rounds=whole_rounds)

    init = start_of_iteration(N0, T0, records, stop0)
    return repeat_until(step, init, pre_legs + legs_per_round * max_rounds, loop, stopped)


__all__ = ["CLOSE_TOL", "MODES", "accelerate", "closure_gap", "start_of_iteration", "after_leg",
           "stopped_by", "iterate_to_periodic"]
