"""Benchmark (not a test): the obvious composition of public functions against the compiled entry
point, after the first call (issue 32).

A user who loops over scenarios writes `peak_response(damper_stiffness(shape, mu, ...), mode,
forces)`; `design_peaks(shape, mu, ..., force_n=forces)` is the compiled entry point for the same
numbers. Both run here on the same scenarios (60sym, mu from 0.3 to 0.7, forces 2, 5 and 20 N, the
exact damper curve from a gross-slip history), each warmed up once, then timed over the whole loop.
The numbers of both paths are compared too.

    PYTHONPATH=. python benchmarks/composition.py [--scenarios 16]

Writes benchmarks/results/composition.json (with the machine it ran on).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from bench_common import call_time, machine  # noqa: E402

OUT = Path(__file__).parent / "results"
FORCES = np.array([2.0, 5.0, 20.0])


def composed(shape, mu):
    return jd.peak_response(jd.damper_stiffness(shape, mu), jd.BladeMode(), FORCES)


def entry_point(shape, mu):
    return jd.design_peaks(shape, mu, force_n=FORCES)


def timed_loop(fn, shape, mus):
    """(s, outputs) of the whole loop over the scenarios, each call waited for."""
    return call_time(lambda: [jax.block_until_ready(fn(shape, m)) for m in mus])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", type=int, default=16)
    args = ap.parse_args()
    shape = jd.family_shape("60sym")
    mus = np.linspace(0.3, 0.7, args.scenarios)
    result = {}
    for name, fn in (("design_peaks", entry_point), ("peak_response(damper_stiffness)", composed)):
        first, _ = call_time(fn, shape, 0.5)
        loop_s, out = timed_loop(fn, shape, mus)
        result[name] = {"first_call_s": round(first, 3), "loop_s": round(loop_s, 4),
                        "per_scenario_ms": round(1e3 * loop_s / len(mus), 3),
                        "peaks_mm": [np.asarray(p.peak_amplitude_mm).tolist() for p in out]}
        print(f"{name:34s} first {first:7.2f} s, loop of {len(mus)}: {loop_s:.3f} s", flush=True)
    a, b = (np.array(result[k]["peaks_mm"]) for k in result)
    ratio = result["peak_response(damper_stiffness)"]["loop_s"] / result["design_peaks"]["loop_s"]
    doc = {"machine": machine(), "scenarios": len(mus), "forces_n": FORCES.tolist(),
           "ratio_composed_over_design_peaks": round(ratio, 3),
           "max_relative_difference_of_peaks": float(np.max(np.abs(a - b) / np.abs(b))),
           "results": result}
    print(f"ratio {ratio:.2f}, max relative difference {doc['max_relative_difference_of_peaks']:.2e}")
    (OUT / "composition.json").write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
