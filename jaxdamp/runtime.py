"""XLA compiler options for jaxdamp's batched programs, chosen by measurement.

On CPU, recent XLA hands small reductions (over the 3 contacts, the 8 candidate stick/slip sets)
to YNNPACK library calls; for arrays of (designs, 8, 3) each call costs more than the loop XLA
emits itself. Turning that fusion off made the batched first stage 1.22x faster on one 8192-design
chunk (the same program compiled both ways in one process) and evaluate_designs 1.19x across
worker processes; HBM-AFT's batch and single-design calls were unchanged
(benchmarks/results/cpu_runtime_options.json; results change in the last bits only, as any change
of reduction order does).

The options are passed per compiled program (`batch_jit`), so importing jaxdamp changes nothing
and an XLA that does not know them costs nothing: they are probed once and dropped if rejected.
"""

from __future__ import annotations

import functools

import jax

# Measured (issue 15): keep XLA's own loop emitter for reductions instead of YNNPACK calls.
CPU_BATCH_OPTIONS = {"xla_cpu_experimental_ynn_fusion_type": ""}


@functools.cache
def batch_compiler_options() -> dict:
    """CPU_BATCH_OPTIONS where the default backend is a CPU whose XLA accepts them, else {}.
    Resolved at the first batched call (asking for the backend starts it)."""
    if jax.default_backend() != "cpu":
        return {}
    try:
        jax.jit(lambda x: x + 1.0, compiler_options=CPU_BATCH_OPTIONS).lower(1.0).compile()
    except Exception:  # noqa: BLE001 - an older or newer XLA without the option: use its defaults
        return {}
    return dict(CPU_BATCH_OPTIONS)


def padded_size(n: int, min_step: int, steps_per_octave: int = 1) -> int:
    """The one padding rule of every batched call: n rounded up to a multiple of
    max(min_step, 2^floor(log2 n) / steps_per_octave). With steps_per_octave = 1 that is the next
    power of two (at least min_step); with 8, at most an eighth of the work is padding. Either way
    a new count of elements rarely compiles a new program."""
    n = max(int(n), 1)
    step = max(int(min_step), (1 << (n.bit_length() - 1)) // int(steps_per_octave))
    return -(-n // step) * step


class _BatchJit:
    """jax.jit(fun, **kwargs) built at the first call with `batch_compiler_options()`: building it
    at import would start JAX's backend as a side effect."""

    def __init__(self, fun, kwargs):
        functools.update_wrapper(self, fun)
        self._fun, self._kwargs, self._jitted = fun, kwargs, None

    def _get(self):
        if self._jitted is None:
            options = batch_compiler_options()
            self._jitted = jax.jit(self._fun, **self._kwargs,
                                   **({"compiler_options": options} if options else {}))
        return self._jitted

    def __call__(self, *args, **kwargs):
        return self._get()(*args, **kwargs)

    def __getattr__(self, name):
        # The jitted function's own attributes (lower, trace, _cache_size, ...), built on demand.
        if name in ("_fun", "_kwargs", "_jitted"):
            raise AttributeError(name)
        return getattr(self._get(), name)


def batch_jit(fun=None, **kwargs):
    """`jax.jit` for batched programs, compiled with `batch_compiler_options()`. Use as
    batch_jit(fun, static_argnames=...) or as a decorator, @batch_jit or
    @batch_jit(static_argnames=...)."""
    if fun is None:
        return lambda f: _BatchJit(f, kwargs)
    return _BatchJit(fun, kwargs)


__all__ = ["padded_size", "CPU_BATCH_OPTIONS", "batch_compiler_options", "batch_jit"]
