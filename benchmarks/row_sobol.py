"""Does the row optimiser optimise? (issue 61, item 3). A derivative-free search on the same
objective as `benchmarks/row_optimisation.py`: scrambled Sobol points (scipy.stats.qmc, seed 0)
over the unit box of the four shape variables, as many as ten times the gradient optimiser's
row evaluations (its grid and its descent: results/row_optimisation.json, rounded up to a power of
two; a gradient counts as one evaluation), each the worst A*/F over the descent's scenarios (`row_values`: every engine order of the
example disk, mu 0.3/0.5/0.7, 4 forces over 2-20 N, F_D +/- 20 %, both histories, nominal kn and
kt; infeasible where the no-liftoff margins fail or a peak has no valid number), as the
optimiser's own objective, the smooth maximum (the hard one recorded too). Compared: the best
feasible point against the gradient optimum's value, and the wall times. The JSON is
written every 64 points, so that a stopped run keeps what it measured.

Run from the repository root (after row_optimisation.py):
    PYTHONPATH=$PWD python benchmarks/row_sobol.py [--points N]
-> benchmarks/results/row_sobol.json
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
from scipy.stats import qmc  # noqa: E402

from jaxdamp.modal_file import load_modal_family  # noqa: E402
from jaxdamp_optimize import VARIABLES, design_space, make_problem  # noqa: E402
from jaxdamp_optimize.response_objective import complete_shape  # noqa: E402
from jaxdamp_optimize.robust_objective import RobustSpec  # noqa: E402
from jaxdamp_optimize.row_objective import RowTask, row_values  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
CHUNK = 64


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=0,
                    help="Sobol points (default: ten times the optimiser's evaluations)")
    a = ap.parse_args()
    gradient = json.loads((OUT / "row_optimisation.json").read_text())
    # A gradient (row_gradient) counts as one evaluation, as a value does: generous to the search
    evaluations = (int(gradient["grid_evaluations"]) + int(gradient["descent_evaluations"])
                   + int(gradient.get("gradient_evaluations", 0)))
    n = a.points or int(2 ** np.ceil(np.log2(10 * evaluations)))
    family = load_modal_family("example")
    orders = list(range(family.n_blades // 2 + 1))
    problem = make_problem(design_space(gradient["free"]), mus=tuple(gradient["mus"]))
    spec = RobustSpec(n_forces=int(gradient["spec"]["n_forces"]))
    task = RowTask(family, tuple(orders), float(gradient["h_l_mm"]))
    Z = qmc.Sobol(d=problem.space.dim, scramble=True, seed=0).random(n)
    V = np.stack([complete_shape(problem, z) for z in Z])
    doc = {"machine": machine("2-core VM"), "points": n, "optimiser_evaluations": evaluations,
           "free": list(problem.space.free), "variables": list(VARIABLES), "mus": list(problem.mus),
           "spec": spec._asdict(), "optimiser": {
               "objective_mm_per_n": gradient["descent_objective_mm_per_n"],
               "seconds": sum(v for k, v in gradient["stages_seconds"].items()
                              if not k.startswith("certify")),
               "shape": gradient["designs"][0]["shape"]}}
    smooth, hard, feasible = np.full(n, np.inf), np.full(n, np.inf), np.zeros(n, bool)
    t0 = time.perf_counter()
    for i in range(0, n, CHUNK):
        got = row_values(V[i:i + CHUNK], problem, spec, task)
        smooth[i:i + CHUNK], hard[i:i + CHUNK], feasible[i:i + CHUNK] = got
        done = min(i + CHUNK, n)
        best = int(np.argmin(np.where(feasible[:done], smooth[:done], np.inf)))
        doc.update(evaluated=done, seconds=time.perf_counter() - t0,
                   load_average_1min=loadavg()[0], feasible=int(feasible[:done].sum()),
                   best={"objective_mm_per_n": float(smooth[best]), "index": best,
                         "hard_maximum_mm_per_n": float(hard[best]),
                         "shape": V[best].tolist()} if feasible[best] else None,
                   smooth_mm_per_n=[float(h) if f else None
                                    for h, f in zip(smooth[:done], feasible[:done])],
                   hard_mm_per_n=[float(h) if f else None
                                  for h, f in zip(hard[:done], feasible[:done])])
        if doc["best"] is not None:
            doc["optimiser_over_best"] = doc["optimiser"]["objective_mm_per_n"] / doc["best"][
                "objective_mm_per_n"]
            doc["time_ratio"] = doc["seconds"] / doc["optimiser"]["seconds"]
        (OUT / "row_sobol.json").write_text(json.dumps(doc, indent=1) + "\n")
        print(f"{done}/{n} points, {doc['seconds']:.0f} s, best "
              f"{doc['best'] and doc['best']['objective_mm_per_n']:.4g}", flush=True)


if __name__ == "__main__":
    main()
