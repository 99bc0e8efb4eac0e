"""Shared by the benchmarks: the machine a run is recorded on, and warm median timing."""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

import jax
import numpy as np


def machine() -> dict:
    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = None
    return {"cpu": cpu, "cores": os.cpu_count(), "platform": platform.platform(),
            "python": platform.python_version(), "jax": jax.__version__,
            "devices": [str(d) for d in jax.devices()], "load_average_1min_at_start": load}


def median_time(fn, *args, repeats=7):
    """Median wall time (s) of warm calls: one call first so compilation is not timed."""
    jax.block_until_ready(fn(*args))
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def interleaved_ms(programs: dict, *args, repeats=60) -> dict:
    """Warm medians (ms), timing the programs round-robin so that machine load hits all alike."""
    for f in programs.values():
        jax.block_until_ready(f(*args))
    times = {k: [] for k in programs}
    for _ in range(repeats):
        for k, f in programs.items():
            t = time.perf_counter()
            jax.block_until_ready(f(*args))
            times[k].append(time.perf_counter() - t)
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}
