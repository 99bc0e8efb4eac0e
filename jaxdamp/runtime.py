"""XLA compiler options chosen by measurement: per program for the batched ones (`batch_jit`), and
for a whole process that compiles for a first call rather than for speed (`compile_for_latency`).

On CPU, recent XLA hands small reductions (over the 3 contacts, the 8 candidate stick/slip sets)
to YNNPACK library calls; for arrays of (designs, 8, 3) each call costs more than the loop XLA
emits itself. Turning that fusion off made the batched first stage 1.22x faster on one 8192-design
chunk (the same program compiled both ways in one process) and evaluate_designs 1.19x across
worker processes; HBM-AFT's batch and single-design calls were unchanged
(benchmarks/results/cpu_runtime_options.json; results change in the last bits only, as any change
of reduction order does).

The options are passed per compiled program (`batch_jit`), so importing jaxdamp changes nothing
and an XLA that does not know them costs nothing: they are probed once and dropped if rejected.
`compile_for_latency` changes the process's XLA_FLAGS and is called explicitly: by the CLI and the
test suite, never by the library.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import jax
import numpy as np

# Measured (issue 15): keep XLA's own loop emitter for reductions instead of YNNPACK calls.
CPU_BATCH_OPTIONS = {"xla_cpu_experimental_ynn_fusion_type": ""}


# Measured (issue 60): XLA's older loop emitters (not the fusion emitters) for the row's derivative
# program (`response.row_gradient_program`): on the 2-core VM (2026-11-29) the example row's
# elliptic batch traced and compiled in 34 s instead of 38 s, its straight one in 20 s instead of
# 23 s, and both ran as fast. Not for every program: the values' row programs compiled a little
# faster and their elliptic batch ran 15 % slower (0.46 s against 0.40 s a call).
LOOP_EMITTERS = {"xla_cpu_use_fusion_emitters": False}


@functools.cache
def batch_compiler_options(extra: tuple = ()) -> dict:
    """CPU_BATCH_OPTIONS and the options `extra` ((name, value) pairs, a program's own), where the
    default backend is a CPU whose XLA accepts them, else {}; an XLA that rejects `extra` gets
    CPU_BATCH_OPTIONS alone. Resolved at the first batched call (asking for the backend starts
    it)."""
    if jax.default_backend() != "cpu":
        return {}
    options = {**CPU_BATCH_OPTIONS, **dict(extra)}
    try:
        jax.jit(lambda x: x + 1.0, compiler_options=options).lower(1.0).compile()
    except Exception:  # noqa: BLE001 - an older or newer XLA without the option: use its defaults
        return batch_compiler_options() if extra else {}
    return options


# Measured (issue 32): XLA options that make XLA compile about twice as fast and run slower, for
# processes whose first call is mostly XLA compilation (one design, a program run once or a few
# times).
# Either one alone saved little (the cycle's program: 3.8 s default, 3.8 s at level 0, 3.4 s
# without the fusion emitters, 1.5-2.2 s with both); its run took 0.3-0.5 ms either way, the
# response's 9 -> 50 ms, the band's 0.3 -> 2.6 s (docs/performance.md, "Compiling for a first call").
LATENCY_OPTIONS = {"xla_backend_optimization_level": 0, "xla_cpu_use_fusion_emitters": False}
# Measured (issue 60): a blade row's command (`response --modes`), whose programs are long and run
# a few times, between the two: the older loop emitters and LLVM level 1. The example row (13
# engine orders, 2 forces) with an empty cache on the 2-core VM (2026-12-01, three fresh caches
# each): first call 13.6-14.9 s optimised, 6.9-7.2 s so, 7.5-8.0 s with the loop emitters
# alone, 5.0 s at LATENCY_OPTIONS (level 0); a repeat 2.0-2.4 s, 2.0-2.1, 2.0-2.1 and 2.3 s;
# the row's call in a warm process 0.18 s optimised, 0.22 s so.
ROW_LATENCY_OPTIONS = {"xla_backend_optimization_level": 1, "xla_cpu_use_fusion_emitters": False}
# Measured (issue 60): XLA's CPU backend compiles a while loop as one kernel (no runtime between
# its operations, no hand-offs between threads) where the loop holds no scatter, sort, dot or
# custom call and touches fewer bytes than a threshold (1 kB by default). Under this process flag
# (XLA reads XLA_FLAGS once, when the backend starts; `small_loops` says whether it is set) a
# batch of up to 32 path cycles (`lanes._lockstep`, `stages.SMALL_LANES`) is written so that its
# loop qualifies, and is one kernel up to 16 lanes of a wedge. On the 2-core VM (2026-12-02,
# `benchmarks/cpu_executor.py`): one 60sym cycle about 1.8x and a batch of 16 1.5x faster,
# compiled 1-1.4 s slower; HBM-AFT's batches 1.8x faster too; pools of 256 unchanged; the same
# cycles (to the last bit or so). Not set by jaxdamp: it is process-wide and changes every
# program's loops.
SMALL_LOOP_FLAG = "--xla_backend_extra_options=xla_cpu_small_while_loop_byte_threshold=4194304"


def small_loops() -> bool:
    """Whether this process's XLA_FLAGS raise XLA's small-while-loop threshold (as
    `SMALL_LOOP_FLAG` does): only then are small batches' loops written without scatters and
    sorts (`lanes._write_rows`, `stages.SMALL_LANES`), which without the flag cost their batches
    of 16 5-12 % at their fastest (2026-12-02). Read when a program is traced."""
    return "xla_cpu_small_while_loop_byte_threshold" in os.environ.get("XLA_FLAGS", "")


# Accelerator plugins for jaxlib: where one is installed the default backend may not be the CPU,
# and the latency options were measured on the CPU only.
_ACCELERATOR_PLUGINS = ("jax_plugins", "jax_cuda12_plugin", "jax_cuda13_plugin", "jax_rocm7_plugin",
                        "libtpu")


def compile_for_latency(options: dict = LATENCY_OPTIONS) -> bool:
    """Ask XLA to compile this process's programs fast rather than optimise them (`options`, by
    default `LATENCY_OPTIONS`, added to the XLA_FLAGS environment variable; a program's own
    compiler_options can ask for them too). XLA reads that variable once, at the process's first
    compilation, so this is for a process's start (the CLI calls it before any computation, for
    the commands whose first call is mostly compilation), and it is process-wide. A flag the
    user set in XLA_FLAGS is kept; nothing is changed where JAX_PLATFORMS names another platform
    than the CPU or an accelerator plugin is installed. Returns whether XLA_FLAGS changed."""
    platforms = os.environ.get("JAX_PLATFORMS", "").strip().lower()
    if platforms not in ("", "cpu"):
        return False
    if not platforms and any(importlib.util.find_spec(name) is not None
                             for name in _ACCELERATOR_PLUGINS):
        return False
    flags = os.environ.get("XLA_FLAGS", "")
    missing = [f"--{name}={str(value).lower()}" for name, value in options.items()
               if f"--{name}=" not in flags]
    if not missing:
        return False
    os.environ["XLA_FLAGS"] = " ".join([flags.strip(), *missing]).strip()
    return True


def side_by_side(*calls) -> list:
    """[call() for call in calls], the first on the calling thread and the others each in a thread
    of their own. For independent computations whose first run is mostly XLA compiling programs of
    their own: XLA releases Python's lock while it compiles, so the programs compile on separate
    cores (two of them took 12.7 s instead of 18.9 s on 2 cores). The first exception is raised;
    neither it nor an interrupt (Ctrl-C) waits for the other threads, which finish on their own
    (the CLI's process ends at once)."""
    pool = ThreadPoolExecutor(max_workers=max(len(calls) - 1, 1))
    try:
        others = [pool.submit(call) for call in calls[1:]]
        first = calls[0]()
        return [first] + [job.result() for job in others]
    finally:
        pool.shutdown(wait=False, cancel_futures=True)


def cpu_cores() -> int:
    """The CPU cores this process may run on (its affinity where the system tells it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def thread_map(fn, items, threads: int) -> list:
    """[fn(x) for x in items] on up to `threads` threads, in order; the first exception is raised.
    For calls of one compiled program on parts of a batch: XLA releases Python's lock while a
    program runs, so on the CPU the parts run on separate cores."""
    items = list(items)
    threads = min(int(threads), len(items))
    if threads <= 1:
        return [fn(x) for x in items]
    with ThreadPoolExecutor(max_workers=threads) as pool:
        return list(pool.map(fn, items))


def map_in_parts(run, items, cpu_chunk: int, min_step: int = 1):
    """run(part) over a non-empty 1-D array `items` in parts of one shape, the outputs (pytrees of
    arrays with the part's leading axis) trimmed to the real entries and concatenated, as NumPy.
    On the CPU the parts are cpu_chunk long and run on the cores' threads (`thread_map`): one
    compiled program for every batch, and a vmapped while loop waits on the slowest lane of a
    smaller batch. Elsewhere one part, padded to `padded_size(n, min_step, 8)`. A part is padded
    by repeating its first entry (the band's amplitude chunks, the curves' cycle chunks)."""
    items = np.asarray(items)
    step = part_size(items.size, cpu_chunk, min_step)

    def one(part):
        out = run(np.concatenate([part, np.full(step - part.size, part[0], part.dtype)]))
        return jax.tree_util.tree_map(lambda x: np.asarray(x)[: part.size], out)

    done = thread_map(one, [items[k:k + step] for k in range(0, items.size, step)], cpu_cores())
    return jax.tree_util.tree_map(lambda *x: np.concatenate(x), *done)


def part_size(n: int, cpu_chunk: int, min_step: int = 1) -> int:
    """The length of every part `map_in_parts` runs a batch of n items in."""
    return cpu_chunk if jax.default_backend() == "cpu" else padded_size(n, min_step, 8)


def compile_ahead(program, args: tuple, runner=None) -> threading.Thread | None:
    """Start compiling program for the shapes and dtypes of args (their values are not used) on a
    thread of its own, and return at once: a later run_program(program, args2, runner) with inputs
    of those shapes and dtypes then finds it compiled, or waits for this compilation where it is
    still under way (JAX compiles a jitted program once for all the threads that ask). For a
    program whose inputs wait on another program's results (the band's amplitude grid on the
    Base-Cycle's psi_BC): both compile side by side, XLA releasing Python's lock while it compiles.
    runner: as run_program's; one with a `compile_ahead(program, args)` method (the CLI's saved
    programs) compiles through it, one without compiles nothing ahead (None is returned). Returns
    the compiling thread (join() waits for it). An error there is dropped: the later call compiles
    again and raises it."""
    if runner is None:
        def ahead():
            program.lower(*args).compile()
    elif hasattr(runner, "compile_ahead"):
        def ahead():
            runner.compile_ahead(program, args)
    else:
        return None

    def quietly():
        try:
            ahead()
        except Exception:  # noqa: BLE001 - the later call raises it where it is handled
            pass

    thread = threading.Thread(target=quietly, name="compile_ahead")
    thread.start()
    return thread


def run_program(program, args: tuple, runner=None):
    """program(*args), or runner(program, args) where a runner is given: the one protocol of the
    library's `runner=` arguments (the CLI passes its saved-program cache, `jaxdamp.cli.exported`),
    for a jitted program of arrays."""
    return program(*args) if runner is None else runner(program, args)


def padded_size(n: int, min_step: int, steps_per_octave: int = 1) -> int:
    """The one padding rule of every batched call: n rounded up to a multiple of
    max(min_step, 2^floor(log2 n) / steps_per_octave). With steps_per_octave = 1 that is the next
    power of two (at least min_step); with 8, at most an eighth of the work is padding. Either way
    a new count of elements rarely compiles a new program."""
    n = max(int(n), 1)
    step = max(int(min_step), (1 << (n.bit_length() - 1)) // int(steps_per_octave))
    return -(-n // step) * step


def options_jit(fun, cpu_options: tuple = (), **kwargs):
    """jax.jit(fun, **kwargs) compiled with `batch_compiler_options(cpu_options)`, built now (call it
    at first use: the options probe JAX's backend)."""
    options = batch_compiler_options(cpu_options)
    return jax.jit(fun, **kwargs, **({"compiler_options": options} if options else {}))


class _BatchJit:
    """jax.jit(fun, **kwargs) built at the first call with `batch_compiler_options(cpu_options)`:
    building it at import would start JAX's backend as a side effect."""

    def __init__(self, fun, kwargs, cpu_options: tuple = ()):
        functools.update_wrapper(self, fun)
        self._fun, self._kwargs, self._jitted = fun, kwargs, None
        self.cpu_options = cpu_options

    def _get(self):
        if self._jitted is None:
            self._jitted = options_jit(self._fun, self.cpu_options, **self._kwargs)
        return self._jitted

    def __call__(self, *args, **kwargs):
        return self._get()(*args, **kwargs)

    def __getattr__(self, name):
        # The jitted function's own attributes (lower, trace, _cache_size, ...), built on demand.
        if name in ("_fun", "_kwargs", "_jitted"):
            raise AttributeError(name)
        return getattr(self._get(), name)


def batch_jit(fun=None, *, cpu_options: dict | None = None, **kwargs):
    """`jax.jit` for batched programs, compiled with `batch_compiler_options()` and the program's own
    `cpu_options` (XLA CPU options, e.g. `LOOP_EMITTERS`). Use as batch_jit(fun,
    static_argnames=...) or as a decorator, @batch_jit or @batch_jit(static_argnames=...)."""
    extra = tuple(sorted((cpu_options or {}).items()))
    if fun is None:
        return lambda f: _BatchJit(f, kwargs, extra)
    return _BatchJit(fun, kwargs, extra)


__all__ = ["padded_size", "CPU_BATCH_OPTIONS", "LOOP_EMITTERS", "LATENCY_OPTIONS", "ROW_LATENCY_OPTIONS",
           "SMALL_LOOP_FLAG", "small_loops",
           "batch_compiler_options",
           "options_jit", "batch_jit", "compile_for_latency", "side_by_side", "cpu_cores", "thread_map", "map_in_parts",
           "part_size", "compile_ahead", "run_program"]
