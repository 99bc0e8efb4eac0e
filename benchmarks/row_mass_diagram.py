"""The row's designer's diagram against the damper's mass: the worst peak A*/F over the example
row as F_D (m Omega^2 R) is scaled by s, per design (issue "Design the damper for the blade row",
items 2 and 5: can F_D do what the shape cannot?).

The quasi-static contact problem is homogeneous in F_D and the amplitude on every path (tested per
engine order and history in tests/test_optimize_row.py): A*(F; s F_D) / F = A*(F / s; F_D) / (F / s).
So the worst A*/F over forces [F_min, F_max] and an F_D spread of +/- d at s F_D is the worst over
forces [F_min / (s (1 + d)), F_max / (s (1 - d))] at the nominal F_D: one row per (mu, history) on a
wide force grid serves every s. Designs: the row optimum of results/row_optimisation.json, the
in-phase robust optimum and 60sym; mu 0.3/0.5/0.7, both histories, nominal kn and kt, forces
2 ... 20 N, F_D +/- 20 % (the row optimiser's defaults), s from 0.25 to 2. Where a window holds a
peak without numbers (e.g. liftoff; `RESULTS.has_numbers`), the design is not feasible at that
s. Also recorded: the platforms' largest rotation in each window (`RowResponse.rotation_mrad`,
which scales with the amplitude: s times its value at the nominal F_D's force F / s), and the
worst A*/F over the peaks within the small-rotation model's limit (SMALL_ROTATION_MRAD, 50 mrad)
with the share of the window's peaks beyond it.

Run: PYTHONPATH=$PWD python benchmarks/row_mass_diagram.py -> results/row_mass_diagram.json and
docs/row_mass_diagram.png
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax
import numpy as np

from bench_common import machine

RESULTS = Path(__file__).parent / "results"
DOCS = Path(__file__).resolve().parent.parent / "docs"
MUS = (0.3, 0.5, 0.7)
HISTORIES = ("gross_slip", "assembly")
F_RANGE = (2.0, 20.0)
SPREAD = 0.2
SCALES = np.geomspace(0.25, 2.0, 19)
H_L = 10.0


def main(out: Path = RESULTS / "row_mass_diagram.json") -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp.modal_file import load_modal_family
    from jaxdamp_optimize.row_objective import IN_PHASE_ROBUST_OPTIMUM

    family = load_modal_family("example")
    orders = jd.engine_orders_of("all", family.n_blades)
    optimum = json.loads((RESULTS / "row_optimisation.json").read_text())["designs"][0]["shape"]
    sixty = jd.family_shape("60sym")
    designs = {"row optimum": tuple(optimum), "in-phase robust optimum": IN_PHASE_ROBUST_OPTIMUM,
               "60sym": (sixty.theta_l, sixty.theta_r, sixty.br_over_hr, 0.8)}
    lo = F_RANGE[0] / (SCALES.max() * (1 + SPREAD))
    hi = F_RANGE[1] / (SCALES.min() * (1 - SPREAD))
    forces = np.geomspace(lo, hi, 32)
    t0 = time.perf_counter()
    doc = {"machine": machine("2-core VM"), "engine_orders": orders, "h_l_mm": H_L,
           "mu": list(MUS), "histories": list(HISTORIES), "force_range_n": list(F_RANGE),
           "fd_spread": SPREAD, "fd_factor": SCALES.tolist(), "designs": {}}
    for name, v in designs.items():
        shape = jd.DamperShape(*map(float, v), None)
        mags, rots, valid = [], [], []
        for mu in MUS:
            for h in HISTORIES:
                row = jd.row_response(shape, mu, modes=family, engine_orders=orders,
                                      force_n=forces, h_l_mm=H_L, initial=h)
                status = np.asarray(row.status)
                missing = (h == "gross_slip") & (status == jd.RESULTS.unreachable)
                mags.append(np.where(missing, -np.inf, row.peaks.peak_amplitude_mm / forces))
                rots.append(np.where(missing, 0.0, row.rotation_mrad))
                valid.append(np.asarray(jd.RESULTS.has_numbers(status)) | missing)
        mags, rots, valid = (np.stack(x) for x in (mags, rots, valid))  # (scenario, m, n_f)
        worst, where, feasible, rot_max, worst_small, beyond = [], [], [], [], [], []
        for s in SCALES:
            small = s * rots <= jd.blocks.SMALL_ROTATION_MRAD  # the rotation at s F_D
            window = (forces >= F_RANGE[0] / (s * (1 + SPREAD)) * (1 - 1e-12)) & (
                forces <= F_RANGE[1] / (s * (1 - SPREAD)) * (1 + 1e-12))
            m = np.where(window[None, None, :], mags, -np.inf)
            k = np.unravel_index(np.argmax(m), m.shape)
            worst.append(float(m[k]))
            where.append(int(orders[k[1]]))
            feasible.append(bool(np.all(valid[..., window])))
            rot_max.append(float(s * np.max(np.where(window[None, None, :], rots, 0.0))))
            inside = window[None, None, :] & small
            worst_small.append(float(np.max(np.where(inside, mags, -np.inf))))
            beyond.append(float(1.0 - inside.sum() / (window.sum() * small[..., 0].size)))
        doc["designs"][name] = dict(shape=list(map(float, v)), worst_mm_per_n=worst,
                                    worst_engine_order=where, feasible=feasible,
                                    rotation_max_mrad=rot_max,
                                    worst_within_small_rotation_mm_per_n=worst_small,
                                    share_beyond_small_rotation=beyond)
        print(name, [f"{s:.2f}:{w:.3f}({e}){'' if f else '!'}" for s, w, e, f in
                     zip(SCALES, worst, where, feasible)], flush=True)
    doc["seconds"] = time.perf_counter() - t0
    out.write_text(json.dumps(doc, indent=1) + "\n")
    plot(doc, DOCS / "row_mass_diagram.png")
    return doc


def plot(doc: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0), constrained_layout=True)
    s = np.asarray(doc["fd_factor"])
    for name, d in doc["designs"].items():
        w = np.asarray(d["worst_mm_per_n"])
        ok = np.asarray(d["feasible"])
        line, = ax.plot(s, np.where(ok, w, np.nan), "o-", ms=3, label=name)
        ax.plot(s[~ok], w[~ok], "x", color=line.get_color())
        ax.plot(s, d["worst_within_small_rotation_mm_per_n"], "--", color=line.get_color(), lw=1,
                label=f"{name}: peaks turning the platforms <= 50 mrad only")
    ax.axvline(1.0, color="0.6", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("F_D / F_D,nominal (the damper's mass at the design speed)")
    ax.set_ylabel("worst A*/F over the row (mm/N)")
    ax.set_title("example row: every engine order, mu 0.3/0.5/0.7, both histories,\n"
                 f"forces {doc['force_range_n'][0]:g}-{doc['force_range_n'][1]:g} N, "
                 f"F_D +/-{100 * doc['fd_spread']:.0f} % (x: a peak not valid)", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
