"""Shared by the benchmarks: the machine a run is recorded on, and the one timer.

Every timing is a call of `fn(*args)` waited for with `jax.block_until_ready` (`call_time`);
`warm_times` times warm calls (one call first, so compilation is not timed); `median_time` and
`best_time` reduce them; `interleaved_times` / `interleaved_ms` time several programs round-robin,
so that the load of a shared machine hits all alike; `spread` is the median, min and max of a list
of times."""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

import jax
import numpy as np


# Both sides of every comparison run with the CPU option jaxdamp's batched programs compile with
# (jaxdamp.runtime.CPU_BATCH_OPTIONS, measured in results/cpu_runtime_options.json), set for the
# whole process: the baselines' programs compile with the same options as the direct method's.
MEASURED_XLA_FLAGS = "--xla_cpu_experimental_ynn_fusion_type="


def use_measured_xla_flags() -> str:
    """Add MEASURED_XLA_FLAGS to XLA_FLAGS for this process, before JAX starts its backend.
    XLA aborts on a flag it does not know, so a subprocess checks it first. Returns XLA_FLAGS as
    the run uses it (recorded by `machine`)."""
    import subprocess
    import sys

    # Call it first thing in a benchmark (the scripts do, before any JAX computation): XLA reads
    # XLA_FLAGS once, when the backend starts.
    flags = os.environ.get("XLA_FLAGS", "")
    if MEASURED_XLA_FLAGS.split("=")[0] in flags:
        return flags
    env = dict(os.environ, XLA_FLAGS=f"{flags} {MEASURED_XLA_FLAGS}".strip(), JAX_PLATFORMS="cpu")
    probe = subprocess.run([sys.executable, "-c", "import jax; jax.devices()"], env=env,
                           capture_output=True)
    if probe.returncode == 0:
        os.environ["XLA_FLAGS"] = env["XLA_FLAGS"]
    return os.environ.get("XLA_FLAGS", "")


def loadavg() -> list[float]:
    """1-, 5- and 15-minute load averages."""
    try:
        return [float(x) for x in Path("/proc/loadavg").read_text().split()[:3]]
    except OSError:
        return list(os.getloadavg())


def random_shapes(n, seed=0, angles=(35.0, 90.0), br=(-0.3, 0.4), mu=(0.1, 0.9)):
    """(DamperShape, mu) of n random designs: uniform angles (deg), b_R/h_R and mu; 2b_L/h_L 0.8."""
    import jaxdamp as jd

    rng = np.random.default_rng(seed)
    shape = jd.DamperShape(rng.uniform(*angles, n), rng.uniform(*angles, n), rng.uniform(*br, n),
                           np.full(n, 0.8))
    return shape, rng.uniform(*mu, n)


def machine(note: str | None = None) -> dict:
    """The machine a run is recorded on (CPU, devices, versions, float64, load at the start)."""
    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    info = {"cpu": cpu, "cores": os.cpu_count(), "platform": platform.platform(),
            "python": platform.python_version(), "jax": jax.__version__,
            "devices": [str(d) for d in jax.devices()],
            "device_kinds": sorted({d.device_kind for d in jax.devices()}),
            "float64": bool(jax.config.jax_enable_x64),
            "load_average_1min_at_start": loadavg()[0], "xla_flags": os.environ.get("XLA_FLAGS", "")}
    if note:
        info["note"] = note
    return info


def call_time(fn, *args):
    """(wall time in s, output) of one call of fn(*args), waited for: a first call's time
    includes its tracing and compilation."""
    t = time.perf_counter()
    out = jax.block_until_ready(fn(*args))
    return time.perf_counter() - t, out


def warm_times(fn, *args, repeats=7, budget_s=0.0, max_repeats=None):
    """(times in s, last output) of warm calls: one call first so compilation is not timed, then
    `repeats` timed calls, and more (up to max_repeats) while their total stays under budget_s."""
    out = jax.block_until_ready(fn(*args))
    times = []
    limit = max(repeats, max_repeats or repeats)
    while len(times) < repeats or (sum(times) < budget_s and len(times) < limit):
        dt, out = call_time(fn, *args)
        times.append(dt)
    return times, out


def median_time(fn, *args, repeats=7):
    """Median wall time (s) of warm calls: one call first so compilation is not timed."""
    return float(np.median(warm_times(fn, *args, repeats=repeats)[0]))


def best_time(fn, *args, repeats=7):
    """Shortest wall time (s) of warm calls: one call first so compilation is not timed."""
    return float(min(warm_times(fn, *args, repeats=repeats)[0]))


def spread(times) -> dict:
    """Median, min and max (s) of a list of times, and how many."""
    t = np.asarray(times, float)
    return {"median_s": float(np.median(t)), "min_s": float(t.min()), "max_s": float(t.max()),
            "repeats": int(t.size)}


def interleaved_times(programs: dict, *args, repeats=60, calls=None, warm=True, each_round=None):
    """({name: times in s}, {name: last output}) of the programs timed round-robin, so that machine
    load hits all alike: `repeats` rounds, in each of which every program is called calls[name]
    times in a row (default 1). warm: call each program once first (not timed); each_round: called
    at the start of every round (e.g. to record the load)."""
    outs = {k: jax.block_until_ready(f(*args)) for k, f in programs.items()} if warm else {}
    times = {k: [] for k in programs}
    for _ in range(repeats):
        if each_round is not None:
            each_round()
        for k, f in programs.items():
            for _ in range((calls or {}).get(k, 1)):
                dt, outs[k] = call_time(f, *args)
                times[k].append(dt)
    return times, outs


def interleaved_ms(programs: dict, *args, repeats=60) -> dict:
    """Warm medians (ms), timing the programs round-robin so that machine load hits all alike."""
    times, _ = interleaved_times(programs, *args, repeats=repeats)
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}


def time_below(times, errors, target, first_label="first setting already below target (upper bound)"):
    """(time, how) at which the error falls below target and stays below, settings ordered from
    cheap to accurate: interpolated log-log between the two settings around the last crossing;
    the first setting's time (an upper bound, how=first_label) when every error is below; None
    when the last setting is still above ("not reached")."""
    errs = np.array([max(e, 1e-300) for e in errors])
    times = np.array(times, float)
    above = np.nonzero(errs > target)[0]
    if above.size == 0:
        return float(times[0]), first_label
    i = int(above[-1])
    if i == len(errs) - 1:
        return None, "not reached"
    e0, e1, t0, t1 = np.log(errs[i]), np.log(errs[i + 1]), np.log(times[i]), np.log(times[i + 1])
    frac = (np.log(target) - e0) / (e1 - e0)
    return float(np.exp(t0 + frac * (t1 - t0))), "interpolated"
