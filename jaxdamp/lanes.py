"""Every tract of a cycle in one loop, and a batch's cycles run by a pool of lanes.

`periodic.iterate_to_periodic` runs legs (periods), each a loop over its tracts (`engine.run`):
two nested loops. Under `vmap` a nested loop runs, for every leg, as many tract steps as the
batch's longest leg, and every lane runs as many legs as the batch's slowest lane. Here the legs
of one path's runs (an ellipse's periods) run as one loop whose step is one tract: where a lane's
run ends, the same step closes the leg (`periodic.after_leg`: the closure, the extrapolation) and
starts the next run. The same runs (the machine's init, step and finish, `engine.machine`), the
same iteration, the same numbers.

One loop per cycle is what lets a batch share its lanes (`iterate_lanes`): under `vmap` a batch
of N cycles runs on W < N lanes, and a lane whose cycle has ended takes the next cycle of the
batch in the same step, so that the batch pays its cycles' tracts shared over W lanes, not N
lanes times its slowest cycle's tracts.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from .engine import empty_tracts
from .loops import looped_together, tree_where, zeros_of
from .periodic import after_leg, start_of_iteration, stopped_by
from .runtime import small_loops
from .status import RESULTS


def _end_set(rows, ran):
    """(state (P,), known): the states of the last active tract among the first `ran` rows (the
    run's; later rows are an earlier run's), as `engine.end_set`."""
    index = jnp.arange(rows["active"].shape[0])
    last = jnp.max(jnp.where(rows["active"] & (index < ran), index, -1))
    return rows["state"][jnp.maximum(last, 0)], last >= 0


def _where_leading(mask, new, old):
    """new where mask, else old, row by row of the leading axis of every leaf (mask: that axis's
    length; `loops.tree_where` takes one condition for the whole tree)."""
    return jax.tree_util.tree_map(
        lambda x, y: jnp.where(mask.reshape((-1,) + (1,) * (x.ndim - 1)), x, y), new, old)


class Legs:
    """The iteration over legs that are runs of one tract machine (`engine.machine`: one path to
    one end), as one loop over tracts: `periodic.iterate_to_periodic`'s iteration, one lane.

    machine_of(data, k) -> (TractMachine, p_start): the machine of the lane's leg j (k = j -
    pre_legs, a traced int) and where its run starts, from the lane's data, a dict with N0, T0
    (the first leg's start), mu, pre_state, pre_known (the set the first leg starts in: each
    later leg starts in the set the previous one ended in) and stop0 (nothing to iterate), and
    what machine_of reads. The legs' machines may differ in their constants (the path, its end)
    but not in their carry. rows: one step's output shapes (`engine.tract_rows`)."""

    def __init__(self, machine_of, rows: dict, *, legs_per_round: int, pre_legs: int,
                 max_rounds: int, max_tracts: int):
        self.machine_of, self.rows = machine_of, rows
        self.legs_per_round, self.pre_legs = legs_per_round, pre_legs
        self.legs = pre_legs + legs_per_round * max_rounds
        self.max_tracts = max_tracts
        self.stopped = stopped_by()

    def _machine(self, c, data):
        """The machine of the lane's current leg."""
        return self.machine_of(data, c["j"] - self.pre_legs)[0]

    def _start_run(self, data, N, T, k, previous, idle=None):
        state, known = previous
        start_set = (jnp.where(known, state, data["pre_state"]), known | data["pre_known"])
        m, p_start = self.machine_of(data, k)
        return m.init(N, T, p_start, start_set, idle)

    def init(self, data) -> dict:
        """The lane's carry before its first tract."""
        N0, T0, stop0 = data["N0"], data["T0"], jnp.asarray(data["stop0"])
        nothing = (jnp.zeros_like(data["pre_state"]), jnp.array(False))
        # A lane with nothing to iterate starts done: under vmap it runs the loop's body while
        # others go on, and a run not done would ask for second looks.
        return dict(it=start_of_iteration(N0, T0, None, stop0), j=jnp.array(0, jnp.int32),
                    i=jnp.array(0, jnp.int32),
                    run=self._start_run(data, N0, T0, jnp.array(-self.pre_legs, jnp.int32),
                                        nothing, stop0),
                    rows=zeros_of(self.rows, self.max_tracts))

    def going(self, c) -> jnp.ndarray:
        """The lane's iteration goes on (not closed, failed or out of legs)."""
        return ~self.stopped(c["it"]) & (c["j"] < self.legs)

    def step(self, c, data) -> dict:
        """One tract; where it ends the run, the leg's end and the next run's start. A lane that
        is not going is left as it is (its row is written nowhere)."""
        return self.close(self.advance(c, data), data)

    def advance(self, c, data) -> dict:
        """`step`'s tract: the run's step and its row (a lane that is not going left as it is)."""
        c, at, out = self.advance_row(c, data)
        rows = jax.tree_util.tree_map(lambda a, o: a.at[at].set(o, mode="drop"), c["rows"], out)
        return dict(c, rows=rows)

    def advance_row(self, c, data):
        """(carry, at, row): `advance` with its row not yet written, at tract `at` (past the rows,
        max_tracts, where the lane is not going)."""
        go = self.going(c)
        run, out = self._machine(c, data).step(c["run"], None)
        at = jnp.where(go, c["i"], self.max_tracts)
        return (dict(c, run=tree_where(go, run, c["run"]), i=jnp.where(go, c["i"] + 1, c["i"])),
                at, out)

    def ends(self, c) -> jnp.ndarray:
        """After `advance`: the lane's run has ended (its leg closes in `close`)."""
        return self.going(c) & (c["run"]["done"] | (c["i"] >= self.max_tracts))

    def close(self, c, data) -> dict:
        """`step`'s end of a run, after `advance`: where the run ended, its leg's end
        (`periodic.after_leg`) and the next run's start; elsewhere the carry as it is."""
        over = self.ends(c)
        arc = self._machine(c, data).finish(c["run"], c["rows"])
        it = after_leg(c["it"], arc.N_end, arc.T_end, arc.status != RESULTS.ok, None, c["j"],
                       data["mu"], legs_per_round=self.legs_per_round, pre_legs=self.pre_legs)
        j = c["j"] + 1
        on = over & ~self.stopped(it) & (j < self.legs)
        fresh = self._start_run(data, it["N"], it["T"], j - self.pre_legs,
                                _end_set(c["rows"], c["i"]))
        return dict(it=tree_where(over, it, c["it"]), j=jnp.where(over, j, c["j"]),
                    i=jnp.where(on, 0, c["i"]), run=tree_where(on, fresh, c["run"]),
                    rows=c["rows"])

    def result(self, c, data):
        """(end, arc): the iteration's end carry (`iterate_to_periodic`'s, records None) and the
        last leg's tracts (zeros where no leg ran)."""
        # The last leg's rows are the first i; the rest are earlier legs'.
        kept = _where_leading(jnp.arange(self.max_tracts) < c["i"], c["rows"],
                              jax.tree_util.tree_map(jnp.zeros_like, c["rows"]))
        arc = self._machine(c, data).finish(c["run"], kept)
        n_pads, n_basis = data["N0"].shape[0], self.rows["dN"].shape[0]
        arc = tree_where(c["j"] > 0, arc, empty_tracts(n_pads, n_basis, self.max_tracts))
        return c["it"], arc


# Lanes a pooled batch runs on: a batched step costs a fixed part and a part per lane, and a pool
# of N / 16 lanes, at least 64, keeps both small on the 2-core CPU (256 cycles, 2026-12-01: 64
# lanes 1.1-2.6x faster than plain vmap and within a tenth of the best of 16, 32 and 128; 4096:
# 128 to 1024 lanes alike; docs/motions.md, "Cost"). Smaller batches run every cycle on its own
# lane (`_lockstep`); so does every batch on an accelerator, whose steps' fixed part is larger
# and part per lane smaller (no accelerator was lent to measure the pool there).
POOL_WIDTH = 64
POOL_SHARE = 16


def pool_width(n: int) -> int | None:
    """The lanes a batch of n cycles runs on, or None: every cycle its own lane (`_lockstep`)."""
    if jax.default_backend() != "cpu":
        return None
    width = max(POOL_WIDTH, n // POOL_SHARE)
    return width if n >= 2 * width else None


def _lane_loop(lane, data):
    """lane.result after lane.step from lane.init until lane.going is False, one lane."""
    c = jax.lax.while_loop(lane.going, lambda c: lane.step(c, data),
                           looped_together(lane.init(data), data))
    return lane.result(c, data)


def iterate_lanes(lane, data, width: int | None = None, alone=None):
    """`lane.result` of one lane's loop from its data (a pytree of arrays). lane: `Legs`, or any
    object with init(data) -> carry (a dict), going(carry), step(carry, data) -> carry (a carry
    that is not going left as it is) and result(carry, data); a carry's "rows", if any, are
    left to the next cycle on its lane (its own are read up to its own count, as `Legs` does).
    A lane may step in two parts, as `Legs` does (advance, ends, close: `_batched_step`).

    Under vmap over N cycles the batch runs on a pool of `width` lanes (default `pool_width(N)`;
    every cycle its own lane, `_lockstep`, where that is None or N < 2 width): each step steps
    every lane; a lane whose cycle has ended leaves its carry at the cycle's place and takes the
    next cycle; the results come from the carries left. Every cycle runs its own steps, so the
    numbers are those of its own loop (to the last bits: XLA's code for W lanes is not that for
    N). Values and forward mode only: reverse mode cannot pass a while loop, nor custom_vmap.
    alone(data): the same result another way for a cycle not in a batch (unbatched), if given.
    """

    @jax.custom_batching.custom_vmap
    def run(data):
        return _lane_loop(lane, data) if alone is None else alone(data)

    @run.def_vmap
    def rule(axis_size, in_batched, data):
        W = pool_width(axis_size) if width is None else width
        batched = jax.tree_util.tree_map(
            lambda x, b: x if b else jnp.broadcast_to(x, (axis_size,) + jnp.shape(x)),
            data, in_batched[0])
        if W is None or axis_size < 2 * W:
            out = _lockstep(lane, batched)
        else:
            out = _pool(lane, batched, axis_size, W)
        return out, jax.tree_util.tree_map(lambda _: True, out)

    return run(data)


def _batched_step(lane):
    """step(carry, data) of a batch of lanes (leading lane axis): lane.step on every lane; with a
    lane that steps in two parts (`Legs.advance`, then `Legs.close` where `Legs.ends`), the
    second only in the steps where a lane's run ended (most steps of a batch whose lanes run
    together: a lax.cond of the batch, not of a lane)."""
    if not hasattr(lane, "advance"):
        return jax.vmap(lane.step)
    close, ends = jax.vmap(lane.close), jax.vmap(lane.ends)
    if hasattr(lane, "advance_row") and small_loops():  # `Legs`' rows without a scatter
        def advance(c, data):
            c, at, out = jax.vmap(lane.advance_row)(c, data)
            return dict(c, rows=_write_rows(c["rows"], at, out))
    else:
        advance = jax.vmap(lane.advance)

    def step(c, data):
        c = advance(c, data)
        return jax.lax.cond(jnp.any(ends(c)), close, lambda c, data: c, c, data)

    return step


def _write_rows(rows, at, out):
    """rows (lanes, tracts, ...) with each lane's row out written at its tract at (past the
    tracts: nowhere), by a select over the tracts instead of `Legs.advance`'s scatter, so that
    the batch's loop can be compiled as one kernel (under `runtime.SMALL_LOOP_FLAG` only: without
    it the select cost batches of 16 5-12 % at their fastest). A pool keeps the scatter: the
    select over its rows cost 1.5x on pools of 256 (2026-12-02)."""
    hit = jnp.arange(jax.tree_util.tree_leaves(rows)[0].shape[1])[None, :] == at[:, None]
    return jax.tree_util.tree_map(
        lambda a, o: jnp.where(hit.reshape(hit.shape + (1,) * (a.ndim - 2)), o[:, None], a),
        rows, out)


def _lockstep(lane, data):
    """lane.result of every cycle of `data` (leading axis), each on its own lane: the batch's
    loop runs until no lane is going (plain vmap's loop, with `_batched_step`: batches of 16
    random elliptic cycles 1.3x faster than plain vmap, bit-identical; 2026-12-02)."""
    step, going = _batched_step(lane), jax.vmap(lane.going)
    c = jax.lax.while_loop(lambda c: jnp.any(going(c)), lambda c: step(c, data),
                           looped_together(jax.vmap(lane.init)(data), data))
    return jax.vmap(lane.result)(c, data)


def _pool(lane, data, n: int, W: int):
    """lane.result of every cycle of `data` (n along the leading axis), the cycles run on W lanes:
    each step steps every lane (`Legs.step` leaves a lane that is not going as it is); a lane
    whose cycle has ended stores its carry at the cycle's place and starts the next cycle (all
    but its rows, which a fresh lane ignores: `Legs.result` keeps the first i)."""
    def take(idx):  # the cycles' data at lanes' indices (n: none, any row will do)
        return jax.tree_util.tree_map(lambda x: x[jnp.minimum(idx, n - 1)], data)

    # Both parts of the step in every step: in a pool some lane's run ends in most steps (the
    # batch-level cond of `_batched_step` measured a wash or slower here, 2026-12-02).
    init, step, going = jax.vmap(lane.init), jax.vmap(lane.step), jax.vmap(lane.going)
    idx0 = jnp.arange(W)
    lanes0 = init(take(idx0))
    # Every cycle's final carry, filled as lanes end (in place of the cycle).
    store0 = jax.tree_util.tree_map(lambda x: jnp.zeros((n,) + x.shape[1:], x.dtype), lanes0)

    def body(s):
        lanes, idx, nxt, store = s
        lanes = step(lanes, take(idx))
        ended = (idx < n) & ~going(lanes)
        dest = jnp.where(ended, idx, n)  # n: dropped
        store = jax.tree_util.tree_map(lambda a, x: a.at[dest].set(x, mode="drop"), store, lanes)
        # The ended lanes take the next cycles, in lane order.
        fresh_idx = nxt + jnp.cumsum(ended) - 1
        idx = jnp.where(ended, jnp.where(fresh_idx < n, fresh_idx, n), idx)
        fresh = init(take(idx))
        kept = {k: v for k, v in lanes.items() if k == "rows"}
        small = {k: v for k, v in lanes.items() if k != "rows"}
        small = _where_leading(ended & (idx < n), {k: fresh[k] for k in small}, small)
        return dict(small, **kept), idx, nxt + jnp.sum(ended), store

    # A cycle with nothing to iterate ends before its first step: the first step stores it.
    _, _, _, store = jax.lax.while_loop(lambda s: jnp.any(s[1] < n), body,
                                        (lanes0, idx0, jnp.array(W), store0))
    return jax.vmap(lane.result)(store, data)


__all__ = ["Legs", "POOL_WIDTH", "POOL_SHARE", "pool_width", "iterate_lanes"]
