"""The peak search's roots: every sign change of a residual on a grid of amplitudes, each
refined in its bracket, all brackets stepping at once (`peaks.peak_response`,
`peaks.series_peaks`).

g = g0 - F with g0 the residual at zero force, so that one grid serves every force. Two drivers
return the same roots: `grid_then_roots` evaluates the grid in the search's own loop (one copy of
the curve in the program: for an expensive curve, a path's steady cycles), and
`grid_apart_then_roots` evaluates it in one call first (two copies, but the grid in one batch:
faster for a cheap curve of one design). Values only, derivative-free (`peaks` differentiates the
roots by the implicit function theorem); unchecked, traceable (jit, vmap).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ..loops import batched_together, tree_where

__all__ = ["ROOT_RTOL", "GRID_CHUNK", "grid_then_roots", "grid_apart_then_roots"]

ROOT_RTOL = 1e-13  # relative step (or bracket width) at which a root has converged
# `grid_then_roots`' amplitudes per step for one curve (a caller vmapping it over many passes
# fewer: `row.ROW_SEARCH_WIDTH`)
GRID_CHUNK = 16


def _search_start(lo, hi, glo, ghi, aux_lo, aux_hi):
    """The search state of brackets [lo, hi]: (steps taken, lo, hi, g(lo), g(hi), the latest
    point, the side that moved last, done, aux at the latest point). A bracket with g(lo) = 0 is
    done at lo, an empty one at hi."""
    at_lo = glo == 0
    return (jnp.zeros(jnp.shape(lo), jnp.int32), lo, hi, glo, ghi, jnp.where(at_lo, lo, hi),
            jnp.zeros(jnp.shape(lo), jnp.int32), (hi - lo <= 0) | at_lo,
            tree_where(at_lo, aux_lo, aux_hi))


def _proposal(c):
    """Where each bracket evaluates next: the secant through its ends (the midpoint where they
    have one value)."""
    lo0, hi0, glo0, ghi0 = c[1:5]
    d = ghi0 - glo0
    ok = d != 0
    x_new = jnp.where(ok, (lo0 * ghi0 - hi0 * glo0) / jnp.where(ok, d, 1.0), 0.5 * (lo0 + hi0))
    return jnp.clip(x_new, lo0, hi0)


def _search_step(c, evaluated, steps, scheduled=True):
    """The state after each active bracket that was `scheduled` (all by default) took its step
    to `_proposal(c)`, where g gave evaluated = (residual, aux)."""
    i, lo0, hi0, glo0, ghi0, x0, side0, done0, aux0 = c
    gx, aux = evaluated
    x_new = _proposal(c)
    active = (i < steps) & ~done0 & scheduled
    right = jnp.sign(gx) == jnp.sign(ghi0)  # the root is left of x_new: x_new becomes hi
    # Illinois: halve the value kept at the end that did not move twice in a row.
    glo = jnp.where(right, jnp.where(side0 > 0, 0.5 * glo0, glo0), gx)
    ghi = jnp.where(right, gx, jnp.where(side0 < 0, 0.5 * ghi0, ghi0))
    lo, hi = jnp.where(right, lo0, x_new), jnp.where(right, x_new, hi0)
    side = jnp.where(right, 1, -1)
    tol = ROOT_RTOL * jnp.abs(x_new)
    done = (gx == 0) | (jnp.abs(x_new - x0) <= tol) | (hi - lo <= tol)
    new = (lo, hi, glo, ghi, x_new, side, done)
    old = (lo0, hi0, glo0, ghi0, x0, side0, done0)
    # the count as an int32 step: int32 + bool has no strict promotion path
    return (i + active.astype(i.dtype), *(jnp.where(active, n, o) for n, o in zip(new, old)),
            tree_where(active, aux, aux0))


def _searching(c, steps):
    return jnp.any((c[0] < steps) & ~c[7])


def _roots_in_brackets(g, start, steps):
    """The search state after every bracket of `_search_start`'s `start` converged (or took
    `steps` steps), all stepping at once, g (-> (residual, aux)) called once per step."""
    return jax.lax.while_loop(lambda c: _searching(c, steps),
                              lambda c: _search_step(c, g(_proposal(c)), steps),
                              batched_together(start))


def grid_apart_then_roots(g0, grid, force, max_roots: int, steps: int):
    """`grid_then_roots`' result with the grid evaluated in one call of g0 before the search:
    two copies of the curve in the program, but the grid in one batch, which a cheap curve of one
    design runs faster (the exact in-phase damper's peaks at three forces: 7 ms a call, against
    14-17 ms by `grid_then_roots`, 2-core VM, 2026-11-29)."""
    def g(x):
        residual, aux = g0(x)
        return residual - force, aux

    on_grid, at_grid = g0(grid)
    lo, hi, glo, ghi, found, n_roots, ends = _brackets(grid, on_grid, force, max_roots, at_grid)
    end = _roots_in_brackets(g, _search_start(lo, hi, glo, ghi, *ends), steps)
    return end[5], end[8], found, n_roots


def grid_then_roots(g0, grid, force, max_roots: int, steps: int, width: int = GRID_CHUNK):
    """(roots, aux there, found, n_roots), arrays (n_f, max_roots): `_brackets` of g = g0 - force
    on the grid, and the root in each bracket, as one loop whose every step calls g0 once on one
    array: one copy of the damper curve in the program (a grid evaluated apart, a search and the
    curve at the roots made three; the row's elliptic program 39 -> 17 thousand lines of HLO,
    its XLA compile 36-39 -> 20 s, its run 1.4 -> 0.44 s: the grid's chunks wait on fewer slow
    lanes than one batch of it).

    g0(x) -> (the residual at zero force, aux) on an array of amplitudes: aux a pytree of arrays
    of x's shape computed on the way (the curve's values and status; () for none), kept at each
    bracket's last evaluation, which is its root. force (n_f, 1). Every step evaluates `width`
    amplitudes: the first steps take the grid in chunks; the step that ends it finds the
    brackets, the first max_roots sign changes per force; then the brackets step by the Illinois
    variant of regula falsi (superlinear, the bracket is kept), the first `width` of those still
    searching at each step, at most `steps` evaluations each, a bracket stopping when its step
    or width is below ROOT_RTOL of its root. A bracket's evaluations do not depend on when it
    steps, so the roots do not depend on `width`; its cost does: most brackets are empty (a force
    has one root where the curve has no fold), and a step's cycles cost in proportion to its
    amplitudes under vmap (each waits on the step's slowest).

    Values only, and derivative-free: the damper curve's values run its fast program (loops that
    stop when done), while a Newton step would need its derivative program. `peaks`
    differentiates the roots by the implicit function theorem, never through this loop, so it may
    be a while loop (it runs until every bracket has converged). One array per step, not a
    vmapped scalar search: vmap made JAX batch the curve's nested loops once per vmap level
    (tracing the in-phase response program took 26 s of a 49 s first call)."""
    n_brackets = force.shape[0] * max_roots
    n_chunks = -(-grid.size // width)
    padded = jnp.concatenate([grid, jnp.full(n_chunks * width - grid.size, grid[-1])])
    shape = (force.shape[0], max_roots)
    aux_like = jax.eval_shape(lambda x: g0(x)[1], jax.ShapeDtypeStruct((width,), grid.dtype))

    def blank(leaf_shape):  # zeros in aux's structure, every leaf of leaf_shape
        return jax.tree_util.tree_map(lambda v: jnp.zeros(leaf_shape, v.dtype), aux_like)

    one = jnp.ones(shape)
    # Before the grid is done the search state is a placeholder of done brackets.
    idle = _search_start(one, one, -one, one, blank(shape), blank(shape))
    init = dict(k=jnp.zeros((), jnp.int32), on_grid=jnp.zeros(padded.size),
                at_grid=blank((padded.size,)), search=idle, found=jnp.zeros(shape, bool),
                n_roots=jnp.zeros(shape[0], jnp.int32))

    def body(c):
        k = c["k"]
        on_grid_step = k < n_chunks
        at = jnp.minimum(k, n_chunks - 1) * width
        # The search's slots: the first `width` brackets still searching, in order; a free slot
        # evaluates the grid's smallest amplitude (a cheap cycle) and writes nowhere.
        searching = ((c["search"][0] < steps) & ~c["search"][7]).reshape(-1)
        which = jnp.argsort(~searching, stable=True)[:width]
        which = jnp.concatenate([which, jnp.zeros(max(width - n_brackets, 0), which.dtype)])
        which = jnp.where(jnp.arange(width) < jnp.sum(searching), which, n_brackets)
        proposals = jnp.append(_proposal(c["search"]).reshape(-1), grid[0])
        x = jnp.where(on_grid_step, jax.lax.dynamic_slice(padded, (at,), (width,)),
                      proposals[which])
        gx, aux = g0(x)
        put = lambda whole, part: jnp.where(on_grid_step,  # noqa: E731
                                            jax.lax.dynamic_update_slice(whole, part, (at,)), whole)
        on_grid = put(c["on_grid"], gx)
        at_grid = jax.tree_util.tree_map(put, c["at_grid"], aux)
        # The step that ends the grid starts the search; later ones take its steps.
        lo, hi, glo, ghi, found, n_roots, (a_lo, a_hi) = _brackets(
            grid, on_grid[:grid.size], force, max_roots,
            jax.tree_util.tree_map(lambda v: v[:grid.size], at_grid))
        started = _search_start(lo, hi, glo, ghi, a_lo, a_hi)
        to_brackets = lambda v: (jnp.zeros((n_brackets,) + v.shape[1:], v.dtype)  # noqa: E731
                                 .at[which].set(v, mode="drop").reshape(shape + v.shape[1:]))
        scheduled = to_brackets(jnp.ones(width, bool))
        stepped = _search_step(c["search"], (to_brackets(gx) - force,
                                             jax.tree_util.tree_map(to_brackets, aux)), steps,
                               scheduled)
        last = k == n_chunks - 1
        search = tree_where(last, started, tree_where(on_grid_step, c["search"], stepped))
        return dict(k=k + 1, on_grid=on_grid, at_grid=at_grid, search=search,
                    found=jnp.where(last, found, c["found"]),
                    n_roots=jnp.where(last, n_roots, c["n_roots"]))

    end = jax.lax.while_loop(lambda c: (c["k"] < n_chunks) | _searching(c["search"], steps), body,
                             batched_together(init, like=(grid, force)))
    return end["search"][5], end["search"][8], end["found"], end["n_roots"]


def _brackets(grid, g0, force, max_roots: int, aux):
    """(lo, hi, g(lo), g(hi), found, n_roots, (aux at lo, aux at hi)): the first max_roots sign
    changes of g = g0 - force on the grid (g0: the residual at zero force on the grid; force
    (n_f, 1); aux: a pytree of arrays on the grid), in ascending order, each as a bracket
    (n_f, max_roots); an empty bracket where a force has fewer roots."""
    cells_n = grid.size - 1
    gg = g0[None, :] - force
    change = (jnp.sign(gg[:, :-1]) != jnp.sign(gg[:, 1:])) & (gg[:, :-1] != 0)
    n_roots = jnp.sum(change, axis=1).astype(jnp.int32)
    # The first max_roots sign changes, in ascending order (cells without a change sort last).
    cells = jnp.argsort(jnp.where(change, jnp.arange(cells_n), cells_n + 1), axis=1)[:, :max_roots]
    found = jnp.arange(max_roots, dtype=jnp.int32)[None, :] < n_roots[:, None]
    lo = grid[cells]
    hi = jnp.where(found, grid[cells + 1], lo)  # an empty bracket: nothing to refine
    glo = jnp.take_along_axis(gg, cells, axis=1)
    ghi = jnp.take_along_axis(gg, cells + 1, axis=1)
    ends = (jax.tree_util.tree_map(lambda v: v[cells], aux),
            jax.tree_util.tree_map(lambda v: jnp.where(found, v[cells + 1], v[cells]), aux))
    return lo, hi, glo, ghi, found, n_roots, ends
