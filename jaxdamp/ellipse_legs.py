"""The legs of an elliptic cycle as tract runs: assembly's straight move, its half period, the
periods.

An elliptic cycle (`jaxdamp.ellipse`) iterates periods of the path to a periodic state
(`periodic.iterate_to_periodic`); from assembly two legs come first: the straight move from
X = 0 to X(pi) and the half period from tau = pi. Every leg is a run of the tract engine on an
`Ellipse` (the move on one of zero width, `MOVE_TAU`), so that a cycle's program holds one tract
machine. `leg_machine` gives the legs to `lanes.Legs` (one loop over a lane's tracts: a batch's
values); `periods` runs them as nested loops (one cycle's values, the recording pass and the
replay behind the derivatives).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from .engine import empty_tape, empty_tracts, end_set, machine
from .engine import run as run_tracts
from .paths import Ellipse
from .periodic import iterate_to_periodic
from .status import RESULTS

# Assembly's straight move, from X = 0 to X(pi) = -s_a X_r, runs as the iteration's first leg on
# an ellipse of zero width: X = 2 s_a X_r cos tau (X_i's motion zeroed) from tau = pi/2 to 2 pi/3,
# the same straight path (its events in closed form on the same line), so that a cycle's program
# holds one tract machine, not a line's and an ellipse's: vmapped cycles compiled in 4.1-5.5 s
# instead of 6.2-8.4 s, derivatives of one cycle 17 % faster, batches as fast, the 590 committed
# cases unchanged (docs/motions.md, "Cost", 2026-12-02). 2 s_a, not s_a to tau = pi: the move
# then ends where the path still moves (cos falls at sin(2 pi/3) of its largest rate), not at a
# turning point, where an event's tau is ill-conditioned and a remainder of TRAVEL_TOL in tau is
# far less in travel.
MOVE_TAU = (0.5 * np.pi, 2.0 * np.pi / 3.0)


def leg_runs(pre_legs: int):
    """run(pads, s_a, k) -> (pads, path, start, end): leg k's tract run (k = j - pre_legs, a
    traced int): a period, tau 0 to 2 pi; with pre_legs 2 (from assembly) the straight move to
    X(pi) (`MOVE_TAU`, k = -2) and the half period from tau = pi (k = -1) before them."""
    if pre_legs not in (0, 2):
        raise ValueError(f"pre_legs must be 0 or 2 (from assembly); got {pre_legs}")

    def run(pads, s_a, k):
        if not pre_legs:
            return pads, Ellipse(s_a), jnp.zeros(()), 2.0 * jnp.pi
        move = k == -2
        straight = jnp.asarray([1.0, 0.0])[:, None]  # X_i's motion zeroed
        pads = pads._replace(nw=jnp.where(move, straight * pads.nw, pads.nw),
                             tw=jnp.where(move, straight * pads.tw, pads.tw))
        start = jnp.where(move, MOVE_TAU[0], jnp.where(k == -1, jnp.pi, 0.0))
        return (pads, Ellipse(jnp.where(move, 2.0 * s_a, s_a)), start,
                jnp.where(move, MOVE_TAU[1], 2.0 * jnp.pi))

    return run


def leg_machine(max_tracts: int, pre_legs: int):
    """machine_of(data, k): the tract machine of a lane's leg k (`lanes.Legs`) and its start,
    from the lane's pads and path size (`leg_runs`)."""
    leg_run = leg_runs(pre_legs)

    def machine_of(data, k):
        pads, path, start, end = leg_run(data["pads"], data["s_a"], k)
        return machine(pads, path, end, max_tracts=max_tracts, loop="while"), start

    return machine_of


def periods(data, *, pre_legs: int, max_tracts: int, max_periods: int, loop: str,
             record: bool = False, recorded=None):
    """(end, arc, legs' tape): the periods of one cycle from its data (`elliptic_impl`'s: pads,
    s_a, N0, T0, mu, pre_state, pre_known, stop0) by `periodic.iterate_to_periodic`, a run of
    tracts per leg (`leg_runs`: assembly's move and half period first); end: the iteration's,
    arc: the last leg's tracts. record: each run's choices into the tape; recorded: a tape of
    every leg to replay."""
    n_pads = data["pads"].a.shape[0]
    pre_set = (data["pre_state"], data["pre_known"])
    leg_run = leg_runs(pre_legs)

    def leg(records, N, T, j, k, idle):
        before, legs = records
        rows = jax.tree_util.tree_map(lambda x: x[j], recorded)  # None: no replay
        # Each leg starts in the set the previous one ended in (the first: data's pre_state).
        state, known = end_set(before)
        pads, path, start, end = leg_run(data["pads"], data["s_a"], k)
        arc = run_tracts(pads, path, N, T, start, end, max_tracts=max_tracts,
                         loop=loop, record=record, replay=rows, idle=idle,
                         start_set=(jnp.where(known, state, pre_set[0]), known | pre_set[1]))
        if record:
            arc, rows = arc
            legs = jax.tree_util.tree_map(lambda x, r: x.at[j].set(r), legs, rows)
        return arc.N_end, arc.T_end, arc.status != RESULTS.ok, (arc, legs)

    no_tape = empty_tape(n_pads, max_tracts, pre_legs + max_periods) if record else None
    end = iterate_to_periodic(leg, data["N0"], data["T0"], data["mu"],
                              (empty_tracts(n_pads, 2, max_tracts), no_tape),
                              legs_per_round=1, pre_legs=pre_legs, max_rounds=max_periods,
                              loop=loop, stop0=data["stop0"])
    arc, legs_tape = end["records"]
    return end, arc, legs_tape


__all__ = ["MOVE_TAU", "leg_runs", "leg_machine", "periods"]
