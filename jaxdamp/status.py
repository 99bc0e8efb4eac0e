"""One status code for every result (in the style of optimistix's `RESULTS`).

Inside jit/vmap a status is an int32 array. Statuses combine in one documented order, `SEVERITY`
(most severe first): a computation's own conditions become a status by `RESULTS.first` (the most
severe condition that holds), and the statuses of several results (two halves, the cells of a
grid, a batch) become one by `RESULTS.combine` / `RESULTS.worst` (the most severe of them). Nothing
combines statuses by comparing their codes: code numbers are names, not ranks.
Outside JAX, `RESULTS.name_of(s)` and `RESULTS.message(s)` say what a code means, and masks come
from it (`RESULTS.valid`, `RESULTS.stopped`, `status == RESULTS.liftoff`): no public result stores a
flag beside its status.
"""

from __future__ import annotations

import enum

import jax
import jax.numpy as jnp
import numpy as np


class RESULTS(enum.IntEnum):
    """Outcome of a computation; `ok` and `shakedown` carry valid numbers, the others do not."""

    ok = 0
    liftoff = 1
    not_converged = 2
    singular = 3
    ill_conditioned = 4
    shakedown = 5
    no_root = 6
    unreachable = 7
    unseated = 8
    large_rotation = 9

    @staticmethod
    def first(conditions, status=None):
        """The status of a computation's problem conditions, {code: boolean array}: the most
        severe code (`SEVERITY`) whose condition holds, else ok (the conditions' broadcast shape).
        status: an earlier status to start from (the result combines it with the conditions)."""
        unknown = set(conditions) - set(SEVERITY)
        if unknown:
            raise ValueError(f"conditions must be keyed by problem codes {[c.name for c in SEVERITY]}; "
                             f"got {sorted(unknown)}")
        xp = _array_module(*conditions.values(), status)
        shape = np.broadcast_shapes(*(np.shape(c) for c in conditions.values()))
        out = xp.zeros(shape, xp.int32)
        for code in SEVERITY:
            if code in conditions:
                out = xp.where((out == RESULTS.ok) & conditions[code], xp.int32(code), out)
        return out if status is None else RESULTS.combine(status, out)

    @staticmethod
    def combine(*statuses):
        """The most severe (`SEVERITY`) of several statuses, elementwise (int32; broadcast)."""
        xp = _array_module(*statuses)
        rank = xp.asarray(_RANK)
        out = xp.asarray(statuses[0], xp.int32)
        for s in statuses[1:]:
            s = xp.asarray(s, xp.int32)
            out = xp.where(rank[s] > rank[out], s, out)
        return out

    @staticmethod
    def worst(status, axis=None):
        """The most severe (`SEVERITY`) status along `axis` (None: of all), int32."""
        xp = _array_module(status)
        status = xp.asarray(status, xp.int32)
        ranks = xp.asarray(_RANK)[status]
        if axis is None:
            return status.reshape(-1)[xp.argmax(ranks.reshape(-1))]
        idx = xp.expand_dims(xp.argmax(ranks, axis=axis), axis)
        return xp.squeeze(xp.take_along_axis(status, idx, axis=axis), axis)

    @staticmethod
    def name_of(status) -> str:
        return RESULTS(int(np.asarray(status))).name

    @staticmethod
    def message(status) -> str:
        return _MESSAGES[RESULTS(int(np.asarray(status)))]

    @staticmethod
    def valid(status):
        """True where the numbers mean something (ok or shakedown)."""
        return (status == RESULTS.ok) | (status == RESULTS.shakedown)

    @staticmethod
    def has_numbers(status):
        """True where a result's numbers are computed as asked: the valid ones, and those that lie
        outside the model's validity (large_rotation), which are reported with that status."""
        return RESULTS.valid(status) | (status == RESULTS.large_rotation)

    @staticmethod
    def stopped(status):
        """True where the computation stopped part-way (liftoff, or a singular / failed solve), so
        that it has no numbers at all; not_converged and ill_conditioned results have numbers that
        are not to be trusted."""
        return ((status == RESULTS.liftoff) | (status == RESULTS.singular)
                | (status == RESULTS.unseated))


# The one order in which statuses combine, most severe first. Ill-conditioning first (it makes
# every other flag meaningless too); then the problems that stop a computation with no numbers,
# the earliest in a computation's course first (a history that does not exist, a normal force at
# zero, no pad set holding the damper, a failed solve); then the numbers that are not to be
# trusted (not periodic, no root); then a number computed as asked that lies outside the model's
# validity (large_rotation: a stuck damper's peak far beyond it is still beyond it); shakedown
# last (its numbers are valid).
SEVERITY = (RESULTS.ill_conditioned, RESULTS.unreachable, RESULTS.liftoff, RESULTS.unseated,
            RESULTS.singular, RESULTS.not_converged, RESULTS.no_root, RESULTS.large_rotation,
            RESULTS.shakedown)
_RANK = np.zeros(len(RESULTS), np.int32)
for _i, _code in enumerate(SEVERITY):
    _RANK[_code] = len(SEVERITY) - _i
assert set(SEVERITY) | {RESULTS.ok} == set(RESULTS), "every problem code has its place in SEVERITY"

_MESSAGES = {
    RESULTS.ok: "ok",
    RESULTS.liftoff: "a normal force reached zero (liftoff): the damper does not work as designed",
    RESULTS.not_converged: "the cycle did not become periodic within the iteration bound",
    RESULTS.singular: "a tract's linear system is singular (no consistent stick/slip set)",
    RESULTS.ill_conditioned: ("the contact stiffness is above the validated range (docs/model.md) "
                              "or the linear solves lost their digits (equilibrium residual above "
                              "tolerance): the numbers are not trustworthy"),
    RESULTS.shakedown: "the steady cycle is elastic (shakedown): no slip, k_Im = 0",
    RESULTS.no_root: "no solution of the scalar equation in the searched range",
    RESULTS.unreachable: ("the stated contact history does not exist on this path: moving along "
                          "it opens a pad before every pad slips (no gross-slip state)"),
    RESULTS.unseated: ("no set of closed pads holds the damper in equilibrium: with pads open, "
                       "the rest cannot carry F_D (the damper is unseated)"),
    RESULTS.large_rotation: ("the platforms' rotation at the peak exceeds the small-rotation "
                             "model's limit (SMALL_ROTATION_MRAD, 50 mrad): the number lies outside "
                             "the model's validity (a smaller force or a heavier damper keeps it "
                             "inside)"),
}


def _concrete(value):
    """value as a numpy array, or None inside a trace or for a non-number (a repr must never
    force a tracer, nor raise)."""
    if isinstance(value, jax.core.Tracer):
        return None
    try:
        v = np.asarray(value)
    except Exception:  # noqa: BLE001 - a repr must not raise
        return None
    return v if v.dtype.kind in "biuf" else None


def status_repr(status) -> str:
    """A status by name: 'ok'; a few as a list ('[ok, liftoff]'); a batch as the count of each
    name ('ok: 12, liftoff: 3')."""
    s = _concrete(status)
    if s is None:
        return "<traced>"
    if s.ndim == 0:
        return RESULTS(int(s)).name
    if s.size <= 4:
        return "[" + ", ".join(RESULTS(int(c)).name for c in s.reshape(-1)) + "]"
    codes, counts = np.unique(s, return_counts=True)
    return ", ".join(f"{RESULTS(int(c)).name}: {int(n)}" for c, n in zip(codes, counts))


def number_repr(value, unit: str = "", fmt: str = ".6g") -> str:
    """A number with its unit ('0.6736 mrad'); a few as a list; an array by its shape and range."""
    v = _concrete(value)
    tail = f" {unit}" if unit else ""
    if v is None:
        return "<traced>" if isinstance(value, jax.core.Tracer) else f"<{type(value).__name__}>"
    v = v.astype(float)
    if v.ndim == 0:
        return f"{float(v):{fmt}}{tail}"
    if v.size == 0:
        return f"<empty {v.shape}>"
    if v.size <= 4:
        return "[" + ", ".join(f"{float(x):{fmt}}" for x in v.reshape(-1)) + "]" + tail
    return f"<{v.shape}: {float(np.min(v)):{fmt}} to {float(np.max(v)):{fmt}}{tail}>"


def _array_module(*values):
    """jax.numpy where any value is a JAX array (a tracer inside jit/vmap included), else NumPy:
    host-side statuses (a result's, the CLI's) combine without compiling one small XLA program per
    operation (a blade row's response compiled 30 of them, about a second of its call)."""
    leaves = jax.tree_util.tree_leaves(values)
    return jnp if any(isinstance(v, jax.Array) for v in leaves) else np


def ok_status(shape=()):
    """An array of `ok` codes (int32)."""
    return jnp.zeros(shape, jnp.int32)


def status_of(result) -> RESULTS:
    """The RESULTS code of a concrete result (its `status` field). Host-side only."""
    status = getattr(result, "status", None)
    if status is None:
        raise TypeError(f"{type(result).__name__} has no status field")
    return RESULTS(int(np.asarray(status)))


__all__ = ["RESULTS", "SEVERITY", "status_repr", "number_repr", "ok_status", "status_of"]
