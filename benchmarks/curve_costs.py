"""Issue 24, job 2 (the k(psi_a) curve, 64 amplitudes 0.05..3 psi_BC, benchmarks/jobs_layered.py's
60sym-like designs): which part of the curve costs what, against the 1000x target over HBM-AFT.

    python benchmarks/curve_costs.py     # writes results/curve_costs.json

Parts, each timed warm (median of 5, `block_until_ready`), one batched call over all designs:
- psi_BC: the Base-Cycle and its five numbers (`jobs_layered.psi_bc_kernel`), which fixes the grid;
- above psi_BC: the stretched Base-Cycle's closed form at the 43 amplitudes above psi_BC
  (`curves.stretched_curves`);
- below psi_BC: one exact cycle per amplitude at the 21 amplitudes below (`curves.flat_cycles`,
  what `amplitude_curves` runs there);
- the probes the sequence curve would need instead (5.2 per curve measured in
  results/sequence_curves.json), priced at this run's probe cost (`sequence.probe_kernel`);
- the whole `amplitude_curves` call, for reference.
The 1000x budget is HBM-AFT's time at 1e-4 (results/jobs_layered.json, 128 designs, same kind of
machine, an earlier run; scaled linearly in the number of designs) over 1000.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import loadavg, machine, median_time, use_measured_xla_flags  # noqa: E402

use_measured_xla_flags()

import jaxdamp as jd  # noqa: E402
import jobs_layered as jl  # noqa: E402
from jaxdamp.curves import broadcast_designs, flat_cycles, stretched_curves  # noqa: E402
from jaxdamp import sequence as sq  # noqa: E402

OUT = Path(__file__).parent / "results"


def timed(fn, repeats=5):
    """Median warm time (s), by bench_common's timer."""
    return median_time(fn, repeats=repeats)


@jax.jit
def _probes(shapes, mu, contacts, load, psi):
    return jax.vmap(lambda s, m, c, ld, p: sq.probe_kernel(s, m, c, ld, p).k_re)(
        shapes, mu, contacts, load, psi)


def run(n, hbm_128, probes_per_curve):
    shapes, mu = jl.designs(n)
    psi_bc_fn = jax.jit(jl.psi_bc_kernel)
    pbc = np.asarray(psi_bc_fn(shapes, mu))
    psi = pbc[:, None] * np.asarray(jl.AMP_FRACTIONS)[None, :]
    below = psi < pbc[:, None] * (1 - 1e-12)
    n_below = int(below.sum())
    designs = broadcast_designs((shapes, mu, jl.CONTACTS, jl.LOAD), n, np)
    flat_idx = np.nonzero(below.reshape(-1))[0]
    d_of = flat_idx // psi.shape[1]
    sub = jax.tree_util.tree_map(lambda x: jnp.asarray(np.asarray(x)[d_of]), designs)
    psi_below = jnp.asarray(psi.reshape(-1)[flat_idx])
    n_probe = int(round(probes_per_curve * n))
    p_idx = np.arange(n_probe) % n
    sub_p = jax.tree_util.tree_map(lambda x: jnp.asarray(np.asarray(x)[p_idx]), designs)
    psi_p = jnp.asarray(pbc[p_idx] * 0.5)
    parts = {
        "psi_bc_s": timed(lambda: psi_bc_fn(shapes, mu)),
        "above_psi_bc_closed_form_s": timed(lambda: stretched_curves(*designs, jnp.asarray(psi))[0]),
        "below_psi_bc_cycles_s": timed(lambda: flat_cycles(*sub, psi_below, "gross_slip", 8, 12).k_re),
        "sequence_probes_instead_s": timed(lambda: _probes(*sub_p, psi_p)),
        "amplitude_curves_total_s": timed(lambda: jd.amplitude_curves(shapes, mu, psi, jl.CONTACTS,
                                                                      jl.LOAD).k_re),
    }
    hbm = hbm_128 * n / 128
    return {"designs": n, "amplitudes": psi.shape[1], "amplitudes_below_psi_bc": n_below,
            "probes": n_probe, **parts, "hbm_aft_time_at_1e-4_s": hbm,
            "budget_for_1000x_s": hbm / 1000,
            "ratio_vs_hbm_amplitude_curves": hbm / parts["amplitude_curves_total_s"],
            "ratio_vs_hbm_if_below_psi_bc_were_free": hbm / (parts["psi_bc_s"]
                                                             + parts["above_psi_bc_closed_form_s"]),
            "loadavg": loadavg()}


def main():
    jobs = json.loads((OUT / "jobs_layered.json").read_text())
    hbm_128 = jobs["curve"]["hbm_time_at_target_s"]
    seq = json.loads((OUT / "sequence_curves.json").read_text())
    probes_per_curve = seq["runs"][0]["cycles_per_curve_sequence_mean"]
    res = {"machine": machine(), "job": "2, whole curve (jobs_layered.job_curve's designs and grid)",
           "hbm_reference": {"time_at_1e-4_s_128_designs": hbm_128,
                             "machine": jobs["curve"]["machine"]},
           "probes_per_curve_from": "results/sequence_curves.json", "runs": []}
    for n in (128, 1000):
        r = run(n, hbm_128, probes_per_curve)
        res["runs"].append(r)
        print(json.dumps(r, indent=1), flush=True)
    (OUT / "curve_costs.json").write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
