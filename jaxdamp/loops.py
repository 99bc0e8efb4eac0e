"""Bounded loops that reverse-mode AD can pass: the tracts of a half, the halves of a cycle.

Every iteration of the direct method is bounded (a half has at most so many tracts, a cycle at
most so many pairs of halves), so it runs either as a masked `lax.scan` over every slot (reverse
mode passes) or as a `lax.while_loop` that stops when done (values and forward mode only);
`values_by_while` takes the values of the one and the derivatives of the other.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def zeros_of(rows: dict, length: int) -> dict:
    """Arrays of zeros for `length` rows of the given shapes and dtypes."""
    return {k: jnp.zeros((length,) + r.shape, r.dtype) for k, r in rows.items()}


def tree_where(mask, new, old):
    """new where mask, else old, leaf by leaf (two pytrees of one structure): a loop's carry
    kept, or a half-cycle's record taken, under a traced condition."""
    return jax.tree_util.tree_map(lambda x, y: jnp.where(mask, x, y), new, old)


def _tie(leaves, refs):
    """The leaves unchanged, each tied by select(p, x, x) to a probe that reads every leaf and
    ref (XLA folds the select and drops the probe)."""
    probe = jnp.array(True)
    for x in leaves + refs:
        probe = probe & jnp.all(x == x)
    return [jnp.where(probe, x, x) for x in leaves]


def batched_together(carry, like=None):
    """The carry unchanged, each leaf tied to all the others and to the leaves of `like` (the
    loop's inputs: select(p, x, x), which XLA folds away): under vmap, where one of them is
    batched every leaf of the carry is.

    Why: JAX's batching rule for a loop finds which carries vmap batches by a fixpoint, batching
    the body once per pass and once more for a batched predicate, and a loop nested in the body
    repeats this within every pass. A carry batched from the start takes one pass, so the
    kernels' nested loops are batched once per level instead of once per pass (three for a
    tract run, tests/test_loops.py). `like`: a carry that starts from values the batch shares
    (a row's design, batched over its paths) would otherwise start unbatched."""
    leaves, tree = jax.tree_util.tree_flatten(carry)
    refs = jax.tree_util.tree_leaves(like)
    if len(leaves) + len(refs) < 2:
        return carry
    return jax.tree_util.tree_unflatten(tree, _tie(leaves, refs))


@jax.custom_jvp
def _differentiated_together(carry, like):
    return batched_together(carry, like)


@_differentiated_together.defjvp
def _differentiated_together_jvp(primals, tangents):
    # Every inexact leaf's tangent is returned as an array (zeros where the carry's is zero), tied
    # to the tangents of `like`, so that under jvp the loop carries a tangent for every float from
    # its first pass, and under vmap (jacfwd) those tangents are batched from it too. The tie
    # reads the tangents (a comparison): forward mode only, as the while loops it serves.
    carry, like = primals
    dcarry, dlike = tangents
    leaves, tree = jax.tree_util.tree_flatten(dcarry)
    inexact = [jnp.issubdtype(t.dtype, jnp.inexact) for t in leaves]
    refs = [t for t in jax.tree_util.tree_leaves(dlike) if jnp.issubdtype(t.dtype, jnp.inexact)]
    tied = iter(_tie([t for t, f in zip(leaves, inexact) if f], refs))
    dout = [next(tied) if f else t for t, f in zip(leaves, inexact)]
    return batched_together(carry, like), jax.tree_util.tree_unflatten(tree, dout)


def looped_together(carry, like=None):
    """`batched_together` for a `lax.while_loop`'s carry, and under jvp a tangent for every float
    of the carry from the start, tied to the tangents of `like`: JAX's JVP rule for a loop finds
    which carries have tangents by a fixpoint as its batching rule does (one tracing of the body's
    JVP per pass, a loop nested in the body repeating it within every pass), and vmap over those
    tangents (jacfwd) batches them by its own."""
    like = jax.tree_util.tree_map(jnp.asarray, like)
    return _differentiated_together(carry, like)


def bounded_loop(step, init, length: int, loop: str, rows: dict, xs=None, like=None):
    """(final carry, stacked outputs) of up to `length` calls of step(carry, x) -> (carry, out),
    x the row of `xs` (a pytree with a leading axis of `length`; None: x is None).

    "scan": always `length` steps (masked by the step itself; reverse mode passes). "while": stops
    once carry["done"] is True; the rows of the steps not run are zeros (the step's outputs for
    finished steps must be inactive rows, e.g. zero travel). rows: the shapes and dtypes of one
    step's outputs (a dict, as `engine._rows` builds for a tract), which spares tracing the step once more to find them
    (tracing is most of a CLI call's cost). like: the inputs the carry should be batched with
    (`batched_together`)."""
    if loop == "scan":
        return jax.lax.scan(step, batched_together(init, like), xs, length=length)
    if loop != "while":
        raise ValueError(f"loop must be scan or while; got {loop!r}")
    rows = zeros_of(rows, length)

    def cond(c):
        i, carry, _ = c
        return (i < length) & ~carry["done"]

    def body(c):
        i, carry, acc = c
        carry, out = step(carry, None if xs is None else
                          jax.tree_util.tree_map(lambda x: x[i], xs))
        return i + 1, carry, jax.tree_util.tree_map(lambda a, o: a.at[i].set(o), acc, out)

    _, end, acc = jax.lax.while_loop(cond, body, looped_together((jnp.array(0), init, rows), like))
    return end, acc


def repeat_until(run, init, length: int, loop: str, stopped):
    """The carry after up to `length` calls carry = run(carry, k), k = 0, 1, ..., that end once
    stopped(carry) is True. "while" stops there; "scan" makes every call and keeps the stopped
    carry (masked, not lax.cond: the scan form is the derivative program of loop="auto", and JAX
    cannot transpose a cond that vmap has turned into a select inside a custom JVP rule)."""
    if loop == "while":
        return jax.lax.while_loop(lambda c: (c[0] < length) & ~stopped(c[1]),
                                  lambda c: (c[0] + 1, run(c[1], c[0])),
                                  looped_together((jnp.array(0), init)))[1]

    def step(carry, k):
        new = run(carry, k)
        return tree_where(stopped(carry), carry, new), None

    return jax.lax.scan(step, batched_together(init), jnp.arange(length))[0]


# A kernel's loop option: "scan" (masked; every mode), "while" (stops when done; values and
# forward mode), "auto" (the values of "while", the derivatives of a masked scan: every mode),
# "forward" (the values of "while", forward-mode derivatives by loops that stop when done, so
# that a derivative costs the iterations the cycle took, not the bound's; reverse mode raises).
LOOPS = ("auto", "scan", "while", "forward")


def check_loop(loop: str) -> None:
    if loop not in LOOPS:
        raise ValueError(f"loop must be one of {', '.join(LOOPS)}; got {loop!r}")


def values_by_while(impl, *args):
    """impl(*args, loop) for loop="auto": the values of loop="while" (loops that stop when done),
    the derivatives of loop="scan" through a custom JVP rule (the masked scan's own JVP, whose
    transpose gives reverse mode, which cannot pass a while loop)."""
    @jax.custom_jvp
    def run(*a):
        return impl(*a, "while")

    @run.defjvp
    def run_jvp(primals, tangents):
        return jax.jvp(lambda *a: impl(*a, "scan"), primals, tangents)

    return run(*args)


def values_by_replay(impl, *args, replay_loop: str = "scan"):
    """impl(*args, loop=...) for loop="auto", where impl(..., record=True) also returns the tape of
    its runs' choices and impl(..., tape=tape) replays them: the values of loop="while", the
    derivatives of the replay (one state set per tract, no choice among candidates: as a masked
    scan 19x faster to run batched than the masked scan that chooses, its gradient about a third
    faster to compile; docs/motions.md, "Derivatives"). replay_loop: "scan" (every mode), or
    "while" (loop="forward": the replay stops where the recorded cycle ended; forward mode only).
    The replay follows the same sequence of events, so within it its derivatives are the cycle's;
    at a switch they are the one-sided derivatives of the sequence the value pass took."""
    @jax.custom_jvp
    def run(*a):
        return impl(*a, loop="while")

    @run.defjvp
    def run_jvp(primals, tangents):
        out, tape = impl(*primals, loop="while", record=True)
        _, dout = jax.jvp(lambda *a: impl(*a, loop=replay_loop, tape=tape), primals, tangents)
        return out, dout

    return run(*args)


def run_by_loop(impl, args: tuple, loop: str):
    """impl(*args, loop) for a kernel's `loop` option, checked: "scan" and "while" as given, "auto"
    through `values_by_while`, "forward" as "while" (forward mode passes a while loop)."""
    check_loop(loop)
    if loop == "auto":
        return values_by_while(impl, *args)
    return impl(*args, "while" if loop == "forward" else loop)


__all__ = ["LOOPS", "zeros_of", "batched_together", "looped_together", "bounded_loop",
           "repeat_until", "check_loop", "values_by_while", "values_by_replay", "run_by_loop"]
