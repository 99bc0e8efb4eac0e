"""Is the whole ring's peak from rest inside the reduction's band over every contact history?
(`benchmarks/ring_check.py`: in microslip the ring from rest peaks 0.6-4.8 % below the reduction's
assembly history; history-free, within 0.8 %.) `jaxdamp.row_band` on the same six-blade lumped
disk with its residual flexibility, 60sym mu 0.5, h_L = 10 mm, at each row's force, against the
ring's peaks committed in results/ring_check.json; and the same for the row robust optimum on the
24-blade example disk (results/ring_check_optimum.json, where present), with the gross-slip
history's peak beside the assembly one.

Writes benchmarks/results/ring_band.json. From the repository root:
    PYTHONPATH=$PWD python benchmarks/ring_band.py [--samples 16] [--optimum-samples 64]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402
from bench_common import loadavg, machine  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.baselines.lumped_disk import LumpedDisk, modal_family  # noqa: E402
from jaxdamp_optimize.design import shape_of_vector  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"


def band_rows(ring: dict, samples: int) -> list:
    """The band at each of a ring check's cases, beside the ring's peak and both histories."""
    disk = LumpedDisk(**ring["disk"])
    d = ring["damper"]
    family = jd.blocks.validate_family(modal_family(disk, d["q_star_mm"], d["h_c_mm"], residual=True))
    shape = (shape_of_vector(np.asarray(d["shape_vector"], float)) if d.get("shape_vector")
             else jd.family_shape(d["shape"]))
    rows = []
    for r in ring["rows"]:
        t = time.perf_counter()
        kw = dict(modes=family, engine_orders=[r["engine_order"]], force_n=[r["force_n"]],
                  h_l_mm=d["h_l_mm"])
        band = jd.row_band(shape, d["mu"], n_samples=samples, **kw)
        gross_slip = jd.row_response(shape, d["mu"], initial="gross_slip", **kw)
        lo, hi = float(band.peak_min_mm[0, 0]), float(band.peak_max_mm[0, 0])
        peak = r["ring"]["peak_mm"]
        rows.append({"regime": r["regime"], "engine_order": r["engine_order"],
                     "force_n": r["force_n"], "ring_from_rest_mm": peak,
                     "reduction_assembly_mm": r["reduction"]["peak_mm"],
                     "reduction_gross_slip_mm": float(gross_slip.peaks.peak_amplitude_mm[0, 0]),
                     "band_min_mm": lo, "band_max_mm": hi,
                     "band_status": jd.RESULTS.name_of(band.status[0, 0]),
                     "ring_inside_band": bool(lo <= peak <= hi),
                     "seconds": time.perf_counter() - t})
        print(rows[-1], flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=16, help="sampled states, six-blade cases")
    ap.add_argument("--optimum-samples", type=int, default=64,
                    help="sampled states for the row optimum's 24-blade cases (two cases: more "
                         "states cost little there)")
    a = ap.parse_args()
    info = machine("shared machine: 2 cores")
    started = time.perf_counter()
    rows = band_rows(json.loads((OUT / "ring_check.json").read_text()), a.samples)
    doc = {"machine": info, "band_samples": a.samples,
           "ring": "results/ring_check.json (six blades, 60sym mu 0.5, the ring from rest)",
           "rows": rows}
    optimum = OUT / "ring_check_optimum.json"
    if optimum.exists():
        ring = json.loads(optimum.read_text())
        doc["optimum"] = {"ring": "results/ring_check_optimum.json (the example's 24 blades, "
                                  f"{ring['damper']['shape']} mu {ring['damper']['mu']}, the ring "
                                  "from rest)",
                          "band_samples": a.optimum_samples,
                          "rows": band_rows(ring, a.optimum_samples)}
    doc["seconds"] = time.perf_counter() - started
    doc["load_average_1min_at_end"] = loadavg()[0]
    OUT.mkdir(exist_ok=True)
    (OUT / "ring_band.json").write_text(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
