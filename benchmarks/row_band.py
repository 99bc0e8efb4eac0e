"""The committed robust row optimum, 60sym and the in-phase robust optimum re-evaluated at every
engine order of the example disk under the band over every admissible contact history
(`jaxdamp.row_band`), beside the gross-slip and assembly histories (`jaxdamp.row_response`): the
worst A*/F (mm/N) per engine order over mu 0.3, 0.5, 0.7 (the descent's set; nominal kn, kt and
F_D) and four forces 2 ... 20 N, and what each costs.

Writes benchmarks/results/row_band.json and its figure, docs/row_band_example.png.
From the repository root:
    PYTHONPATH=$PWD python benchmarks/row_band.py [--samples 64]
"""

from __future__ import annotations

import argparse
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

import jaxdamp as jd  # noqa: E402
from jaxdamp.modal_file import load_modal_family  # noqa: E402
from jaxdamp_optimize.design import shape_of_vector  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
H_L_MM = 10.0
MUS = (0.3, 0.5, 0.7)
FORCES = np.geomspace(2.0, 20.0, 4)


def designs() -> dict:
    """The three designs of results/row_optimisation.json, by name, as shape vectors."""
    doc = json.loads((OUT / "row_optimisation.json").read_text())
    return {d["name"]: d for d in doc["designs"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=64)
    a = ap.parse_args()
    info = machine("2-core VM")
    family = load_modal_family("example")
    orders = list(range(family.n_blades // 2 + 1))
    out, seconds = [], {"row_response": [], "row_band": []}
    for name, d in designs().items():
        shape = shape_of_vector(np.asarray(d["shape"], float))
        worst = {h: np.full(len(orders), -np.inf) for h in ("gross_slip", "assembly", "band_max",
                                                            "band_min")}
        statuses = []
        for mu in MUS:
            kw = dict(modes=family, engine_orders=orders, force_n=FORCES, h_l_mm=H_L_MM)
            for h in ("gross_slip", "assembly"):
                t = time.perf_counter()
                row = jd.row_response(shape, mu, initial=h, **kw)
                seconds["row_response"].append(time.perf_counter() - t)
                ok = np.asarray(jd.RESULTS.valid(row.status))
                # a gross-slip history that does not exist on a path is no failure (`certify_row`)
                statuses += [int(s) for s in np.asarray(row.status)[~ok]
                             if not (h == "gross_slip" and s == jd.RESULTS.unreachable)]
                mag = np.where(ok, row.peaks.peak_amplitude_mm / FORCES[None, :], -np.inf)
                worst[h] = np.maximum(worst[h], mag.max(axis=1))
            t = time.perf_counter()
            band = jd.row_band(shape, mu, n_samples=a.samples, **kw)
            seconds["row_band"].append(time.perf_counter() - t)
            ok = np.asarray(jd.RESULTS.valid(band.status))
            statuses += [int(s) for s in band.status[~ok]]
            worst["band_max"] = np.maximum(worst["band_max"], np.where(
                ok, band.peak_max_mm / FORCES[None, :], -np.inf).max(axis=1))
            worst["band_min"] = np.maximum(worst["band_min"], np.where(
                ok, band.peak_min_mm / FORCES[None, :], -np.inf).max(axis=1))
            print(f"{name} mu {mu}: band worst {worst['band_max'].max():.4f} mm/N", flush=True)
        histories = np.maximum(worst["gross_slip"], worst["assembly"])
        out.append({"name": name, "shape": d["shape"], "engine_order": orders,
                    "worst_mm_per_n": {k: v.tolist() for k, v in worst.items()},
                    "worst_of_both_histories_mm_per_n": histories.tolist(),
                    "band_over_histories": (worst["band_max"] / histories).tolist(),
                    "worst_band_mm_per_n": float(worst["band_max"].max()),
                    "worst_band_engine_order": int(orders[int(np.argmax(worst["band_max"]))]),
                    "worst_histories_mm_per_n": float(histories.max()),
                    "certified_worst_band_mm_per_n": d["worst"],
                    "invalid_statuses": sorted(set(statuses))})
    doc = {"machine": info, "load_average_1min_at_end": loadavg()[0],
           "modes": "example (jaxdamp/data/example_disk_modes.npz)", "h_l_mm": H_L_MM,
           "mus": list(MUS), "contacts": "nominal kn, kt", "fd_n": 1000.0,
           "force_n": FORCES.tolist(), "band_samples": a.samples,
           "seconds_first_call": {k: v[0] for k, v in seconds.items()},
           "seconds_median_repeat": {k: float(np.median(v[1:])) for k, v in seconds.items()},
           "designs": out}
    OUT.mkdir(exist_ok=True)
    (OUT / "row_band.json").write_text(json.dumps(doc, indent=1))

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for c, d in zip(colors, out):
        w = d["worst_mm_per_n"]
        ax.fill_between(orders, w["band_min"], w["band_max"], color=c, alpha=0.18, lw=0)
        ax.plot(orders, w["band_max"], "-", color=c, label=f"{d['name']}: every history (band)")
        ax.plot(orders, w["assembly"], "o--", color=c, ms=3, lw=1, label=f"{d['name']}: assembly")
        ax.plot(orders, w["gross_slip"], "x:", color=c, ms=4, lw=1,
                label=f"{d['name']}: gross slip")
    ax.set_xlabel("engine order (= nodal diameter)")
    ax.set_ylabel("worst A*/F over mu and forces, mm/N")
    ax.set_title("Example disk (24 blades): the designs over every contact history", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6.5, ncol=1, loc="upper left")
    fig.tight_layout()
    fig.savefig(OUT.parent.parent / "docs" / "row_band_example.png", dpi=120)
    for d in out:
        print(d["name"], "band", round(d["worst_band_mm_per_n"], 4), "EO", d["worst_band_engine_order"],
              "histories", round(d["worst_histories_mm_per_n"], 4), d["invalid_statuses"])


if __name__ == "__main__":
    main()
