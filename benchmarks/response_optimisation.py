"""Response-based shape optimisation: minimise the worst-case peak A* over mu = 0.3 ... 0.7 at
F = 20 N (and with F_D +/- 20 %), and report 60sym and the k_Im,BC optimum on the same objective.

Writes benchmarks/results/response_optimisation.json. Run from the repository root:
    PYTHONPATH=$PWD python benchmarks/response_optimisation.py
"""

from __future__ import annotations

import json
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import jaxdamp_optimize as opt  # noqa: E402
from jaxdamp_optimize.response_objective import optimize_response  # noqa: E402
from bench_common import call_time, machine  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"


def main():
    info = machine()
    t_kim, kim = call_time(opt.optimize)  # the k_Im,BC:worst optimum (mu = 0.3, 0.5, 0.7), as shipped
    s = kim.shape
    k_im_vec = [float(s.get(n, d)) for n, d in (("theta_l", 60.0), ("theta_r", 60.0),
                                                ("br_over_hr", 0.14), ("bl2_over_hl", 0.8))]
    print("k_Im,BC optimum:", k_im_vec, float(kim.objective))
    problem = opt.make_problem(mus=(0.3, 0.4, 0.5, 0.6, 0.7))
    runs = []
    for spread in (0.0, 0.2):
        seconds, r = call_time(lambda: optimize_response(problem, force_n=20.0, fd_spread=spread,
                                                         k_im_optimum=k_im_vec))
        runs.append({"force_n": r.force_n, "fd_spread": r.fd_spread, "mus": list(r.mus),
                     "grid_evaluations": r.grid_evaluations, "descent_evaluations": r.descent_steps,
                     "seconds": seconds,
                     "designs": [d._asdict() for d in [r.best] + list(r.references)]})
        print(json.dumps(runs[-1]))
    OUT.mkdir(exist_ok=True)
    (OUT / "response_optimisation.json").write_text(json.dumps(
        {"machine": info, "k_im_optimum": k_im_vec, "k_im_optimum_seconds": t_kim, "runs": runs}, indent=1))


if __name__ == "__main__":
    main()
