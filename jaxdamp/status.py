"""One status code for every result (in the style of optimistix's `RESULTS`).

Inside jit/vmap a status is an int32 array; `RESULTS.promote(status, condition, code)` raises it to
`code` where `condition` holds and it is still ok, so the first problem found is the one reported.
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

    @staticmethod
    def promote(status, condition, code: "RESULTS"):
        """status where it already reports a problem (or `condition` is False), else `code`."""
        return jnp.where((status == RESULTS.ok) & condition, jnp.int32(code), status)

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
    def stopped(status):
        """True where the computation stopped part-way (liftoff, or a singular / failed solve), so
        that it has no numbers at all; not_converged and ill_conditioned results have numbers that
        are not to be trusted."""
        return ((status == RESULTS.liftoff) | (status == RESULTS.singular)
                | (status == RESULTS.unseated))


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


def from_flags(liftoff, failed=False, converged=True, ill_conditioned=False):
    """The status of a solver's internal liftoff / failed / converged booleans (no result stores
    them). Ill-conditioning
    comes first (it makes the other flags meaningless too), then liftoff, then a singular or failed
    solve, then non-convergence."""
    status = RESULTS.promote(ok_status(jnp.shape(liftoff)), ill_conditioned, RESULTS.ill_conditioned)
    status = RESULTS.promote(status, liftoff, RESULTS.liftoff)
    status = RESULTS.promote(status, failed, RESULTS.singular)
    return RESULTS.promote(status, ~jnp.asarray(converged), RESULTS.not_converged)


def ok_status(shape=()):
    """An array of `ok` codes (int32)."""
    return jnp.zeros(shape, jnp.int32)


def status_of(result) -> RESULTS:
    """The RESULTS code of a concrete result (its `status` field). Host-side only."""
    status = getattr(result, "status", None)
    if status is None:
        raise TypeError(f"{type(result).__name__} has no status field")
    return RESULTS(int(np.asarray(status)))


__all__ = ["RESULTS", "status_repr", "number_repr", "from_flags", "ok_status", "status_of"]
