"""Certify like a designer would (issue 61, item 4): the row robust optimum of
results/row_optimisation.json, 60sym and the in-phase robust optimum re-evaluated on a dense grid
that includes the interior: mu at 5 levels over 0.3-0.7, kn x kt at 3 x 3 factors 0.5/1/2 (the
off-diagonal pairs included), F_D at 3 levels (0.8/1/1.2 x nominal, applied explicitly), 6 forces
over 2-20 N, from gross slip and from assembly separately, at every engine order of the example
disk with its residual flexibility (`jaxdamp_optimize.row_objective.certify_row`; 135 scenarios,
540 rows per design). Per design: the worst A*/F per engine order and history, where it binds,
and the 95th percentile and median over every (scenario, force, engine order) of each
history's peaks (the interior a designer also cares about). The band over every history is not
in it: in series with the residual flexibility a row's band costs about six times its free
platform one (docs/blade.md).

Writes results/row_certify_dense.json after each design. From the repository root:
    PYTHONPATH=$PWD python benchmarks/row_certify_dense.py
"""

from __future__ import annotations

import itertools
import json
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402
from bench_common import loadavg, machine  # noqa: E402

from jaxdamp import RESULTS, Contacts, LoadCase  # noqa: E402
from jaxdamp.modal_file import load_modal_family  # noqa: E402
from jaxdamp_optimize import design_space, make_problem  # noqa: E402
from jaxdamp_optimize.robust_objective import RobustSpec  # noqa: E402
from jaxdamp_optimize.row_objective import (HISTORY_NAMES, RowTask, row_magnification,  # noqa: E402
                                            row_reference_shapes)

OUT = Path(__file__).resolve().parent / "results"
N_MU, N_K, N_FD, N_FORCES = 5, 3, 3, 6


def percentiles(values) -> dict:
    v = np.asarray(values, float)
    return {"q50": float(np.percentile(v, 50)), "q95": float(np.percentile(v, 95)),
            "max": float(v.max())}


def main():
    opt = json.loads((OUT / "row_optimisation.json").read_text())
    family = load_modal_family("example")
    orders = list(range(family.n_blades // 2 + 1))
    problem = make_problem(design_space(opt["free"]), mus=tuple(opt["mus"]))
    spec = RobustSpec(n_forces=N_FORCES)
    task = RowTask(family, tuple(orders), float(opt["h_l_mm"]))
    designs = {"row robust optimum": opt["designs"][0]["shape"], **row_reference_shapes()}
    mus = np.linspace(min(problem.mus), max(problem.mus), N_MU)
    factors = np.geomspace(1 / spec.kn_factor, spec.kn_factor, N_K)
    fds = problem.load[0] * np.linspace(1 - spec.fd_spread, 1 + spec.fd_spread, N_FD)
    forces = np.geomspace(*spec.force_range_n, N_FORCES)
    grid = list(itertools.product(mus, factors, factors, fds))
    doc = {"machine": machine("2-core VM"), "modes": "example (with its platform residual)",
           "engine_orders": orders, "h_l_mm": task.h_l_mm, "mu": mus.tolist(),
           "kn_factors": factors.tolist(), "kt_factors": factors.tolist(), "fd_n": fds.tolist(),
           "force_n": forces.tolist(), "scenarios": len(grid), "designs": {}}
    for name, shape in designs.items():
        t0 = time.perf_counter()
        v = np.asarray(shape, float)
        worst = {h: np.full(len(orders), -np.inf) for h in HISTORY_NAMES}
        peaks = {h: [] for h in HISTORY_NAMES}
        failed, binding, top = {}, None, -np.inf
        for mu, fn, ft, f_d in grid:
            load = LoadCase(f_d, *problem.load[1:])
            contacts = Contacts(problem.kn * fn, problem.kt * ft)
            for h in HISTORY_NAMES:
                mag, status = row_magnification(v, task, mu, contacts, load, forces, h)
                valid = np.asarray(RESULTS.valid(status))
                for s in np.asarray(status)[~valid]:
                    key = RESULTS.name_of(int(s))
                    failed[f"{h}: {key}"] = failed.get(f"{h}: {key}", 0) + 1
                scored = np.where(valid, mag, -np.inf)
                worst[h] = np.maximum(worst[h], scored.max(axis=1))
                peaks[h].extend(mag[valid].ravel().tolist())
                if scored.max() > top:
                    top = float(scored.max())
                    e, j = np.unravel_index(int(np.argmax(scored)), scored.shape)
                    binding = {"engine_order": orders[e], "mu": float(mu), "kn_factor": float(fn),
                               "kt_factor": float(ft), "fd_n": float(f_d),
                               "force_n": float(forces[j]), "history": h}
        doc["designs"][name] = {
            "shape": list(map(float, v)),
            "worst_by_history": {h: worst[h].tolist() for h in HISTORY_NAMES},
            "worst": top, "binding": binding,
            "peaks_by_history": {h: percentiles(peaks[h]) for h in HISTORY_NAMES},
            "peaks_both_histories": percentiles(peaks["gross_slip"] + peaks["assembly"]),
            "no_valid_peak": failed, "seconds": time.perf_counter() - t0,
            "load_average_1min_at_end": loadavg()[0]}
        (OUT / "row_certify_dense.json").write_text(json.dumps(doc, indent=1) + "\n")
        print(name, f"{top:.4f}", binding, doc["designs"][name]["peaks_both_histories"],
              failed, f"{doc['designs'][name]['seconds']:.0f} s", flush=True)


if __name__ == "__main__":
    main()
