"""Does the ring from rest overshoot? A diagnostic beside `ring_check.py` (docs/blade_example.md,
"The contact history"): on its microslip cases (six blades, 60sym, mu = 0.5), the ring from rest
again at the frequency of the run nearest its peak, and whether blade 0's first-harmonic envelope
grows monotonically. An overshoot would leave the pads in the state of a larger excursion than
the steady one; none is there.

Run: python benchmarks/ring_history.py (after ring_check.py) -> results/ring_history.json.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.baselines.lumped_disk import LumpedDisk  # noqa: E402
from jaxdamp.baselines.ring import ring_response  # noqa: E402

from bench_common import machine  # noqa: E402
from ring_check import H_C_MM, H_L_MM, MU, N_SMALL, SHAPE  # noqa: E402

RESULTS = Path(__file__).parent / "results"


def main() -> dict:
    started = time.perf_counter()
    checked = json.loads((RESULTS / "ring_check.json").read_text())
    disk = LumpedDisk(n_blades=N_SMALL)
    rows = []
    for row in checked["rows"]:
        if row["regime"] != "microslip":
            continue
        e, freq = row["engine_order"], row["damper_in_ring"]["frequency_hz"]
        t = time.perf_counter()
        ring = ring_response(SHAPE, MU, jd.Contacts(), jd.LoadCase(), disk, e, row["force_n"],
                             freq, h_c_mm=H_C_MM, h_l_mm=H_L_MM, n_periods=checked["periods"],
                             steps_per_period=checked["steps_per_period"])
        envelope = np.abs(np.asarray(ring.history_mm)[:, 0])
        rises = np.diff(envelope)
        out = dict(nodal_diameter=e, force_n=row["force_n"], frequency_hz=freq,
                   final_mm=float(envelope[-1]), max_mm=float(envelope.max()),
                   max_at_period=int(np.argmax(envelope)),
                   overshoot=float(envelope.max() / envelope[-1] - 1.0),
                   largest_fall_per_period=float(max(0.0, -rises.min()) / envelope[-1]),
                   seconds=time.perf_counter() - t)
        rows.append(out)
        print(f"ND {e}: final {out['final_mm']:.6g} mm, max {out['max_mm']:.6g} at period "
              f"{out['max_at_period']}, overshoot {out['overshoot']:.1e}", flush=True)
    doc = dict(machine=machine(), seconds=time.perf_counter() - started, rows=rows)
    (RESULTS / "ring_history.json").write_text(json.dumps(doc, indent=1))
    return doc


if __name__ == "__main__":
    main()
