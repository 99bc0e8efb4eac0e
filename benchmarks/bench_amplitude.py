"""Benchmark (not a test): exact k(psi_a) curves, 1000 designs x 64 amplitudes in one batched call
(`jaxdamp.curves.amplitude_curves`), in steady cycles per second, against Base-Cycles per second
(`jaxdamp.cycle.base_cycles`) on the same designs. Warm medians; compile times separately.

    PYTHONPATH=. python benchmarks/bench_amplitude.py [--designs 1000] [--amplitudes 64]

Writes benchmarks/results/amplitude.json (with the machine it ran on).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from bench_common import use_measured_xla_flags, random_shapes, call_time, machine, median_time  # noqa: E402

use_measured_xla_flags()  # before JAX starts: both sides of every comparison get it
from jaxdamp import RESULTS, amplitude_curves  # noqa: E402

OUT = Path(__file__).parent / "results"


def designs(n, seed=0):
    return random_shapes(n, seed, angles=(45, 85), br=(-0.1, 0.2), mu=(0.2, 0.8))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=1000)
    ap.add_argument("--amplitudes", type=int, default=64)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    info = machine()
    shape, mu = designs(a.designs)
    psi = np.geomspace(0.05, 20.0, a.amplitudes)
    contacts = jd.Contacts()
    out = {"machine": info, "designs": a.designs, "amplitudes": a.amplitudes,
           "psi_a_mrad": [float(psi[0]), float(psi[-1])], "curves": {}}
    n_cycles = a.designs * a.amplitudes
    for initial in ("gross_slip", "assembly"):
        first, cv = call_time(lambda: amplitude_curves(shape, mu, psi, contacts, initial=initial))
        warm = median_time(lambda: amplitude_curves(shape, mu, psi, contacts, initial=initial),
                           repeats=a.repeats)
        status = np.asarray(cv.status)
        out["curves"][initial] = {
            "first_call_s": first, "warm_s": warm, "cycles_per_s": n_cycles / warm,
            "status_counts": {RESULTS(c).name: int(np.sum(status == c)) for c in np.unique(status)},
            "max_cycles": int(np.max(cv.cycles))}
        print(initial, out["curves"][initial], flush=True)
    first, _ = call_time(jd.base_cycles, shape, mu, contacts)
    warm = median_time(lambda: jd.base_cycles(shape, mu, contacts), repeats=a.repeats)
    out["base_cycles"] = {"first_call_s": first, "warm_s": warm, "base_cycles_per_s": a.designs / warm}
    out["ratio_base_cycles_per_s_over_cycles_per_s"] = {
        k: out["base_cycles"]["base_cycles_per_s"] / v["cycles_per_s"] for k, v in out["curves"].items()}
    print(out["base_cycles"], out["ratio_base_cycles_per_s_over_cycles_per_s"])
    try:
        import os
        out["machine"]["load_average_1min_at_end"] = os.getloadavg()[0]
    except OSError:
        pass
    OUT.mkdir(exist_ok=True)
    (OUT / "amplitude.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
