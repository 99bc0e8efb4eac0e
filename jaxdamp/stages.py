"""Two stages inside one program: a fast computation for every lane of a batch, the full one only
for the lanes it could not finish.

Under `vmap` every lane of a loop pays for the slowest lane and for every branch any lane takes: a
`lax.cond` on a batched predicate runs both branches for every lane. `second_look` keeps the rare
work out of the batch's common path at the level where the batch is known: its batching rule
(`jax.custom_batching.custom_vmap`) runs the fast computation on every lane, then the full one on
the lanes whose fast result says "look again", gathered in chunks of a few lanes (a while loop
that does not run at all where no lane needs it). Unbatched, it is the fast computation and, where
needed, the full one (`lax.cond`). The host-driven form of the same idea for batches of designs is
`batch.two_stage`.

The fast computation must give the full one's result wherever it does not ask for a second look
(the caller's contract; tested per use). Forward mode passes (the JVP of the rule); reverse mode
does not (custom_vmap has no transpose): kernels use it on their values path only, and
their derivatives replay the value pass's choices (`loops.values_by_replay`)."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from .runtime import small_loops

# Lanes the second stage runs at once. With the engine's proposed set first (a tract in eight
# or fewer asks for a second look), 8 and 32 measured alike on 256 lanes: 32 was 7 % faster on
# 60sym and 14 % slower on random shapes (docs/motions.md, "Cost", 2026-11-30). On a pool of 64
# lanes (`lanes.iterate_lanes`, 2026-12-01), where the lanes' cycles are out of step and a few
# lanes ask in most steps, 4 was 2-12 % faster than 8 on 256-cycle batches, 16 and 32 slower.
CHUNK = 4
# The lanes of a wider batch that `second_look`'s retry runs on, the flagged ones first (a pool's
# 64 lanes: about ten ask in a step; docs/motions.md, "Cost").
RETRY_LANES = 16
# Under `runtime.SMALL_LOOP_FLAG`, batches of at most this many lanes find their flagged lanes
# and write their results without a sort or a scatter (`_flagged_first`, `_put`), so that a small
# batch's loop can be compiled as one kernel; wider ones (pools of 64 lanes) keep the sort and
# the scatter: with the flag, a pool's second look as one kernel made curved-flat pools of 256
# 15 % slower (2026-12-02, docs/motions.md "Cost"). The same lanes and results either way.
SMALL_LANES = 32


def second_look(fast, full, again, chunk: int = CHUNK, retry=None):
    """f(*args): fast(*args), or full(*args) where again(fast(*args)) is True (a () bool).

    fast and full: functions of the same arguments (pytrees of arrays, None allowed) returning
    pytrees of one structure, shape and dtype. Under vmap, full runs only on the lanes that need
    it, `chunk` lanes at a time. retry(out, *args), if given: a cheaper second try from the fast
    result, run under vmap in a batch in which some lane asks (one batched call, not chunks: on
    every lane, or on the first RETRY_LANES flagged ones of a wider batch), kept where it does
    not ask again; full then runs where it does. Unbatched it is
    not used (full directly). Under vmap the flagged lanes' arguments and full's results travel
    as float64 rows (`_packed`): their values must be exact in float64 (bools, ints below 2^53;
    float64 enabled, as every public entry point requires)."""

    @jax.custom_batching.custom_vmap
    def f(*args):
        out = fast(*args)
        return jax.lax.cond(again(out), lambda: full(*args), lambda: out)

    @f.def_vmap
    def rule(axis_size, in_batched, *args):
        axes = jax.tree_util.tree_map(lambda b: 0 if b else None, list(in_batched))
        out = jax.vmap(fast, in_axes=tuple(axes))(*args)
        flags = jax.vmap(again)(out)
        count = jnp.sum(flags)
        size = -(-axis_size // chunk) * chunk
        leaves, tree = jax.tree_util.tree_flatten(list(args))
        lane_axis = jax.tree_util.tree_leaves(list(in_batched))
        batched = [x for x, b in zip(leaves, lane_axis) if b]

        def on_lanes(fn, packed, idx, *first):
            """fn(*first, *args) under vmap on the lanes idx, their arguments taken from the
            packed rows (`_packed(batched)`); first: arguments already on those lanes."""
            rows, unpack_args = packed
            taken = iter(unpack_args(rows[idx]))
            sub = jax.tree_util.tree_unflatten(
                tree, [next(taken) if b else x for x, b in zip(leaves, lane_axis)])
            return jax.vmap(fn, in_axes=(0,) * len(first) + tuple(axes))(*first, *sub)

        small = axis_size <= SMALL_LANES and small_loops()
        put = _put if small else _scatter

        def flagged_first(n):
            # The flagged lanes first, in lane order; past them lane 0 (small) or the others.
            if small:
                return _flagged_first(flags, n)
            order = jnp.argsort(~flags, stable=True)
            return jnp.concatenate([order, jnp.zeros(max(n - axis_size, 0), order.dtype)])[:n]

        if retry is not None and axis_size > RETRY_LANES:
            def retried(out):
                # The first RETRY_LANES flagged lanes only (gathered packed, as `look_again`'s
                # chunks); the rest go to `full`. Wedge pools of 256 (64 lanes, about ten
                # flagged in a step) 1.13-1.17x against the retry on every lane, bit-identical;
                # for the curved-flat damper it still cost more than it saved (2026-12-02).
                idx = flagged_first(RETRY_LANES)
                alt = on_lanes(retry, _packed(batched), idx,
                               jax.tree_util.tree_map(lambda o: o[idx], out))
                use = (jnp.arange(RETRY_LANES) < count) & ~jax.vmap(again)(alt)
                return put(out, jnp.where(use, idx, axis_size), alt)
        elif retry is not None:
            def retried(out):
                alt = jax.vmap(retry, in_axes=(0,) + tuple(axes))(out, *args)
                use = flags & ~jax.vmap(again)(alt)
                return jax.tree_util.tree_map(
                    lambda a, o: jnp.where(use.reshape((-1,) + (1,) * (a.ndim - 1)), a, o),
                    alt, out)

        if retry is not None:
            out = jax.lax.cond(count > 0, retried, lambda out: out, out)
            flags = jax.vmap(again)(out)
            count = jnp.sum(flags)

        def look_again(out):
            # The flagged lanes first, padded to whole chunks.
            order = flagged_first(size)
            # A chunk's lanes are gathered, and its results written, as one row each of one
            # packed array (`_packed`): one gather and one write a chunk, not one per leaf
            # (some twenty): elliptic batches of 16 1.00-1.10x, pools of 256 0.99-1.05x,
            # bit-identical (2026-12-02, docs/motions.md "Cost").
            packed_args = _packed(batched)
            packed_out, unpack_out = _packed(jax.tree_util.tree_leaves(out))
            out_tree = jax.tree_util.tree_structure(out)

            def body(carry):
                k, packed_out = carry
                idx = jax.lax.dynamic_slice(order, (k * chunk,), (chunk,))
                redo = on_lanes(full, packed_args, idx)
                # Slots past the flagged lanes write nowhere (index axis_size, dropped).
                dest = jnp.where(k * chunk + jnp.arange(chunk) < count, idx, axis_size)
                redo_rows, _ = _packed(jax.tree_util.tree_leaves(redo))
                return k + 1, put(packed_out, dest, redo_rows)

            packed_out = jax.lax.while_loop(lambda c: c[0] * chunk < count, body,
                                            (jnp.array(0), packed_out))[1]
            return jax.tree_util.tree_unflatten(out_tree, unpack_out(packed_out))

        # Most steps of a small batch flag no lane: the sort is skipped with the loop (a batch
        # of 16 elliptic cycles 17 % faster, 2026-12-01).
        out = jax.lax.cond(count > 0, look_again, lambda out: out, out)
        return out, jax.tree_util.tree_map(lambda _: True, out)

    return f


def _flagged_first(flags, n: int):
    """The indices of the first n flagged lanes in lane order (lane 0 past the last one), without
    a sort: the k-th flagged lane is the number of lanes whose running count of flags is below
    k + 1."""
    seen = jnp.cumsum(flags)
    k = jnp.arange(n)
    return jnp.where(k < seen[-1], jnp.sum(seen[None, :] < k[:, None] + 1, axis=1), 0)


def _put(tree, dest, rows):
    """tree with rows[j] at dest[j] along the leading axis of every leaf (dest past it: nowhere;
    the others distinct), by a select instead of a scatter."""
    def put(a, r):
        match = jnp.arange(a.shape[0])[:, None] == dest[None, :]
        hit = jnp.any(match, axis=1).reshape((-1,) + (1,) * (a.ndim - 1))
        return jnp.where(hit, r[jnp.argmax(match, axis=1)], a)
    return jax.tree_util.tree_map(put, tree, rows)


def _scatter(tree, dest, rows):
    """`_put` by a scatter (dest past the leading axis: dropped)."""
    return jax.tree_util.tree_map(lambda a, r: a.at[dest].set(r, mode="drop"), tree, rows)


def _packed(leaves):
    """(rows, unpack): arrays with a leading lane axis as one float64 array (lanes, width), each
    lane's leaves side by side, and unpack(rows') -> the leaves again (their shapes after the
    lane axis, their dtypes) for rows' of any leading length. Bools and small ints are exact in
    float64."""
    n = leaves[0].shape[0]
    sizes = [int(np.prod(x.shape[1:], dtype=int)) for x in leaves]
    rows = jnp.concatenate([x.reshape(n, -1).astype(jnp.float64) for x in leaves], axis=1)
    ends = np.cumsum(sizes)

    def unpack(r):
        return [r[:, e - w:e].reshape((r.shape[0],) + x.shape[1:]).astype(x.dtype)
                for x, w, e in zip(leaves, sizes, ends)]

    return rows, unpack


__all__ = ["CHUNK", "second_look"]
