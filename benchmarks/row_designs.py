"""Committed damper designs across the example disk's blade row (issue 35): 60sym, the in-phase
robust optimum (gross-slip history), the robust optimum with the history band where it was run,
and the in-phase response optimum, each re-evaluated at every nodal diameter of the example disk
(`--modes example`, 24 blades) from the assembly history, at three forces.

The robust optima were found for the one-mode illustrative blade on the in-phase path; this asks
how they do on a blade row whose every engine order has its own mode and platform path. Writes
benchmarks/results/row_designs.json and its figure, docs/row_designs_example.png. From the repository root:
    PYTHONPATH=$PWD python benchmarks/row_designs.py
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from bench_common import loadavg, machine  # noqa: E402

from jaxdamp import RESULTS, DamperShape, row_response  # noqa: E402
from jaxdamp.modal_file import load_modal_family  # noqa: E402

RESULTS_DIR = Path(__file__).resolve().parent / "results"
FORCES_N = (1.0, 3.0, 10.0)
H_L_MM = 10.0  # the damper's size (its left flank), as docs/blade.md's example
MU = 0.5


def designs() -> dict:
    """name -> DamperShape, from the committed optimisation results."""
    out = {"60sym": DamperShape(60.0, 60.0, 0.14, 0.8)}
    robust = json.loads((RESULTS_DIR / "robust_optimisation.json").read_text())
    out["robust optimum (gross slip)"] = DamperShape(*robust["designs"][0]["shape"])
    band = RESULTS_DIR / "robust_optimisation_band.json"
    if band.exists():
        out["robust optimum (history band)"] = DamperShape(
            *json.loads(band.read_text())["designs"][0]["shape"])
    resp = json.loads((RESULTS_DIR / "response_optimisation.json").read_text())
    out["response optimum"] = DamperShape(*resp["runs"][0]["designs"][0]["shape"])
    return out


def main():
    info = machine("shared machine: 2 cores, other jobs running alongside")
    family = load_modal_family("example")
    orders = list(range(family.n_blades // 2 + 1))
    rows = {}
    for name, shape in designs().items():
        t = time.perf_counter()
        res = row_response(shape, MU, modes=family, engine_orders=orders, force_n=FORCES_N,
                           h_l_mm=H_L_MM)
        seconds = time.perf_counter() - t
        amp = np.asarray(res.peaks.peak_amplitude_mm)
        valid = np.asarray(RESULTS.valid(res.status))
        per_n = np.where(valid, amp / np.asarray(res.tip_force_n), np.nan)  # mm per N of tip force
        worst = np.nanmax(per_n, axis=0) if valid.any() else None
        rows[name] = {
            "shape": list(map(float, shape[:4])), "seconds": seconds,
            "nodal_diameter": res.nodal_diameter.tolist(),
            "peak_mm": [[float(v) if ok else None for v, ok in zip(r, vr)]
                        for r, vr in zip(amp, valid)],
            "peak_per_tip_force_mm_per_n": [[float(v) if np.isfinite(v) else None for v in r]
                                            for r in per_n],
            "free_peak_mm": np.asarray(res.free_peak_mm).tolist(),
            "status": [[RESULTS.name_of(s) for s in r] for r in res.status],
            "worst_mm_per_n": None if worst is None else [float(v) for v in worst],
            "worst_engine_order": [int(res.engine_order[w]) if w >= 0 else None
                                   for w in res.worst]}
        print(f"{name:32s} worst A*/F per force {rows[name]['worst_mm_per_n']} at EO "
              f"{rows[name]['worst_engine_order']}  ({seconds:.1f} s)")
    doc = {"machine": info, "load_average_1min_at_end": loadavg()[0], "family": family.name,
           "forces_n": list(FORCES_N), "mu": MU, "h_l_mm": H_L_MM, "history": "assembly",
           "designs": rows}
    RESULTS_DIR.mkdir(exist_ok=True)
    (RESULTS_DIR / "row_designs.json").write_text(json.dumps(doc, indent=1))

    fig, axes = plt.subplots(1, len(FORCES_N), figsize=(4.2 * len(FORCES_N), 4), sharey=True)
    for j, (ax, force) in enumerate(zip(axes, FORCES_N)):
        for name, r in rows.items():
            y = [p[j] if p[j] is not None else np.nan for p in r["peak_mm"]]
            ax.plot(r["nodal_diameter"], y, "o-", ms=3, label=name)
        free = [p[j] for p in next(iter(rows.values()))["free_peak_mm"]]
        ax.plot(next(iter(rows.values()))["nodal_diameter"], free, "k--", lw=1, label="no damper")
        ax.set_yscale("log")
        ax.set_xlabel("nodal diameter")
        ax.set_title(f"F = {force:g} N per blade", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("peak tip amplitude A*, mm")
    axes[-1].legend(fontsize=7)
    fig.suptitle(f"Designs across the example disk's row (mu = {MU}, assembly history)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(RESULTS_DIR.parent.parent / "docs" / "row_designs_example.png", dpi=120)


if __name__ == "__main__":
    main()
