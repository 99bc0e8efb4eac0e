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


def accelerate(mu, s0, s1, s2, have_history):
    """Next start state (N, T) of an iteration over rounds, accelerated where the iteration is
    geometric.

    Within a fixed pattern of events the round map is affine, so where its contracting part has
    one direction the iterates satisfy s2 - s1 = rho (s1 - s0) and the fixed point
    s2 + rho/(1-rho)(s2-s1) is exact (e.g. when gross slip freezes a partial-slip mechanism:
    vertical flanks, 90R). It is used only where that structure is verified and the state is
    admissible; the following round then checks closure as usual. Otherwise the plain iterate s2
    is returned.
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


def closure_gap(start, end):
    """How far a round's end state is from its start state (the largest force change, units of
    F_D): the round closes the cycle where this is at most CLOSE_TOL."""
    return jnp.max(jnp.abs(end - start))


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
    start done, `engine.run(idle=...)`, so that they do not keep the batch's loops going). A failed leg stops the iteration at once, or with
    whole_rounds at the end of its round (the Base-Cycle's pair always runs both halves).
    stop0: True where there is nothing to iterate (the start failed). loop: `loops.repeat_until`'s.

    Returns a dict: records; N, T (where the next round would start); top (the state at the
    last round's start); gap (the last round's closure, inf before one ended); closed (the last
    round closed and none of its legs failed); rounds (int32, rounds ended).
    """
    n = N0.shape[0]

    def step(c, j):
        k = j - pre_legs
        starts = (k >= 0) & (k % legs_per_round == 0)
        ends = (k >= 0) & (k % legs_per_round == legs_per_round - 1)
        N1, T1, bad, records = leg(c["records"], c["N"], c["T"], j, k, stopped(c))
        there = jnp.concatenate([N1, T1])
        top = jnp.where(starts, jnp.concatenate([c["N"], c["T"]]), c["top"])
        gap = closure_gap(top, there)
        closed = ends & (gap <= CLOSE_TOL)
        nxt = jnp.where(ends, accelerate(mu, c["prev"], top, there, k >= legs_per_round), there)
        if whole_rounds:
            failed = c["failed"] | bad
            stop = ends & (closed | failed)
        else:
            failed = bad
            stop = closed | failed
        return dict(N=nxt[:n], T=nxt[n:], top=top, prev=jnp.where(ends, top, c["prev"]),
                    gap=jnp.where(ends, gap, c["gap"]), closed=closed & ~failed,
                    failed=jnp.where(ends, False, failed) if whole_rounds else failed,
                    stop=stop, rounds=c["rounds"] + ends.astype(jnp.int32), records=records)

    if round_budget is None:
        stopped = lambda c: c["stop"]  # noqa: E731
    else:
        stopped = lambda c: c["stop"] | (c["rounds"] >= round_budget)  # noqa: E731
    no = jnp.array(False)
    init = dict(N=N0, T=T0, top=jnp.concatenate([N0, T0]), prev=jnp.zeros(2 * n),
                gap=jnp.asarray(jnp.inf), closed=no, failed=no, stop=jnp.asarray(stop0),
                rounds=jnp.array(0, jnp.int32), records=records)
    return repeat_until(step, init, pre_legs + legs_per_round * max_rounds, loop, stopped)


__all__ = ["CLOSE_TOL", "accelerate", "closure_gap", "iterate_to_periodic"]
