"""Robust design over the example blade row (`jaxdamp_optimize.row_objective.optimize_row`): the
worst peak A*/F over every engine order of the example disk (24 blades, nodal diameters 0 ... 12,
h_L = 10 mm), mu 0.3, 0.5, 0.7 in the descent, F_D +/- 20 %, forces 2 ... 20 N, the history band
(gross slip and assembly), the nominal kn and kt in the descent, four free variables; timed by
stage; then the optimum, 60sym and the in-phase robust optimum re-evaluated at every engine order
under each history and their band (mu 0.3/0.5/0.7 x kn and kt 0.5/1/2 x F_D 0.8/1/1.2, 4 forces).

Writes benchmarks/results/row_optimisation.json and its figure, docs/row_optimisation_example.png.
From the repository root:
    PYTHONPATH=$PWD python benchmarks/row_optimisation.py [--grid-points 3] [--steps 6]
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

from jaxdamp.modal_file import load_modal_family  # noqa: E402
from jaxdamp_optimize import VARIABLES, design_space, make_problem  # noqa: E402
from jaxdamp_optimize.robust_objective import RobustSpec  # noqa: E402
from jaxdamp_optimize.robust_plot import plot_row  # noqa: E402
from jaxdamp_optimize.row_objective import optimize_row  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--grid-points", type=int, default=3)
    ap.add_argument("--steps", type=int, default=6)
    ap.add_argument("--n-forces", type=int, default=4)
    ap.add_argument("--free", default=",".join(VARIABLES))
    ap.add_argument("--mu-set", default="0.3,0.5,0.7")
    ap.add_argument("--direction", default="lbfgs")
    a = ap.parse_args()
    info = machine("2-core VM")
    family = load_modal_family("example")
    orders = list(range(family.n_blades // 2 + 1))
    free = a.free.split(",")
    assert all(f in VARIABLES for f in free)
    problem = make_problem(design_space(free), mus=tuple(float(m) for m in a.mu_set.split(",")))
    spec = RobustSpec(n_forces=a.n_forces)
    stamps = [time.perf_counter()]
    res = optimize_row(family, orders, 10.0, problem, spec, grid_points=a.grid_points,
                       steps=a.steps, direction=a.direction, progress=lambda n: (stamps.append(time.perf_counter()),
                                                          print(f"stage at {stamps[-1] - stamps[0]:.0f} s",
                                                                flush=True)))
    stages = np.diff(stamps)
    names = (["grid (incl. compile)"] + [f"descent start {i}" for i in range(len(stages) - 3)]
             + ["certify optimum", "certify references"])
    designs = [res.best] + list(res.references)
    for d in designs:
        print(d.name, d.shape, d.feasible, d.worst, d.worst_engine_order, d.reason)
    doc = {"machine": info, "load_average_1min_at_end": loadavg()[0],
           "modes": "example (jaxdamp/data/example_disk_modes.npz)", "engine_orders": orders,
           "h_l_mm": 10.0, "spec": res.spec._asdict(), "corners": res.corners,
           "mus": list(problem.mus), "free": list(problem.space.free),
           "grid_points": a.grid_points, "seconds_total": float(stamps[-1] - stamps[0]),
           "stages_seconds": dict(zip(names, map(float, stages))),
           "grid_evaluations": res.grid_evaluations, "descent_evaluations": res.descent_evaluations,
           "gradient_evaluations": res.gradient_evaluations, "direction": a.direction,
           "steps": a.steps, "accepted_steps": len(res.history),
           "descent_objective_mm_per_n": res.objective_value, "descent_history": res.history,
           "designs": [d._asdict() for d in designs]}
    OUT.mkdir(exist_ok=True)
    (OUT / "row_optimisation.json").write_text(json.dumps(doc, indent=1))
    ax = plot_row(designs)
    ax.figure.savefig(OUT.parent.parent / "docs" / "row_optimisation_example.png", dpi=120,
                      bbox_inches="tight")
    plt.close(ax.figure)
    print(json.dumps({k: doc[k] for k in ("seconds_total", "stages_seconds")}))


if __name__ == "__main__":
    main()
