"""Issue 24: job 2 (the k(psi_a) curve of a design, 64 amplitudes 0.05..3 psi_BC, 60sym-like
designs of benchmarks/jobs_layered.py) by the piecewise closed form (`jaxdamp.sequence.
sequence_curves`) against the per-amplitude cycles (`amplitude_curves`, two-stage), both warm,
median of repeats; the curves must agree (max error, statuses). HBM-AFT is not rerun here: its
time at 1e-4 for 128 designs is read from results/jobs_layered.json (same machine kind, an earlier
run; flagged) and scaled linearly in the number of designs for 1000.

    python benchmarks/bench_sequence.py     # writes results/sequence_curves.json
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", False)

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import loadavg, machine, use_measured_xla_flags, warm_times  # noqa: E402

use_measured_xla_flags()

import jaxdamp as jd  # noqa: E402
import jobs_layered as jl  # noqa: E402
from jaxdamp.curves import broadcast_designs, flat_cycles  # noqa: E402
from jaxdamp import sequence as sq  # noqa: E402
from jaxdamp import stiffness_curve  # noqa: E402
from jaxdamp.sequence import sequence_curves  # noqa: E402  (return_curve: the pieces too)

OUT = Path(__file__).parent / "results"


def timed(fn, repeats=3):
    """(median warm time in s, output), by bench_common's timer."""
    ts, out = warm_times(fn, repeats=repeats)
    return float(np.median(ts)), out


def run(n, hbm_128):
    shapes, mu = jl.designs(n)
    pbc = np.asarray(jax.jit(jl.psi_bc_kernel)(shapes, mu))
    psi = pbc[:, None] * np.asarray(jl.AMP_FRACTIONS)[None, :]
    cyc = lambda: jd.amplitude_curves(shapes, mu, psi, jl.CONTACTS, jl.LOAD)  # noqa: E731
    seq = lambda: sequence_curves(shapes, mu, psi, jl.CONTACTS, jl.LOAD)  # noqa: E731
    t_cyc, a = timed(cyc)
    t_seq, b = timed(seq)
    scale = np.max(np.maximum(np.abs(np.asarray(a.k_re)), np.abs(np.asarray(a.k_im))), axis=1,
                   keepdims=True)
    err = np.maximum(np.abs(np.asarray(a.k_re - b.k_re)), np.abs(np.asarray(a.k_im - b.k_im))) / scale
    below = psi < pbc[:, None] * (1 + 1e-9)
    _, cur = sequence_curves(shapes, mu, psi, jl.CONTACTS, jl.LOAD, return_curve=True)
    g = np.where(below, psi, np.max(np.where(below, psi, 0.0), axis=1, keepdims=True))
    designs = broadcast_designs((shapes, mu, jl.CONTACTS, jl.LOAD), n, np)
    t_build, _ = timed(lambda: stiffness_curve(designs, grid=g).start)
    hbm = hbm_128 * n / 128
    return {"designs": n, "amplitudes": int(psi.shape[1]),
            "time_per_amplitude_cycles_s": t_cyc, "time_sequence_s": t_seq,
            "time_stiffness_curve_build_s": t_build,
            "speedup_sequence_vs_cycles": t_cyc / t_seq,
            "curve_points_per_s_sequence": psi.size / t_seq,
            "curve_points_per_s_cycles": psi.size / t_cyc,
            "max_error_sequence_vs_cycles": float(err.max()),
            "status_mismatches": int(np.sum(np.asarray(a.status) != np.asarray(b.status))),
            "amplitudes_below_psi_bc_per_curve": float(below.sum(axis=1).mean()),
            "cycles_per_curve_sequence_mean": float(np.mean(cur.cycles)),
            "cycles_per_curve_sequence_max": int(np.max(cur.cycles)),
            "note_cycles": ("probes (each an exact cycle plus its forward-mode derivative in "
                            "psi_a) on the amplitudes below psi_BC; both paths take the stretched "
                            "Base-Cycle above psi_BC; the per-amplitude path runs one cycle per "
                            "amplitude below psi_BC"),
            "hbm_time_at_1e-4_s": hbm,
            "hbm_time_how": ("results/jobs_layered.json (128 designs, earlier run)" +
                             ("" if n == 128 else ", scaled linearly to this many designs")),
            "ratio_vs_hbm_sequence": hbm / t_seq, "ratio_vs_hbm_cycles": hbm / t_cyc,
            "loadavg": loadavg()[0]}


def probe_cost(n=1000, m=5):
    """Probes (cycle + forward-mode derivative in psi_a) against plain cycles per second, on the
    same n x m (design, amplitude) pairs below psi_BC."""
    shapes, mu = jl.designs(n)
    pbc = np.asarray(jax.jit(jl.psi_bc_kernel)(shapes, mu))
    designs = broadcast_designs((shapes, mu, jl.CONTACTS, jl.LOAD), n, np)
    d = np.repeat(np.arange(n), m)
    psi = jnp.asarray((pbc[:, None] * np.linspace(0.05, 1.0, m)[None]).reshape(-1))
    sub = jax.tree_util.tree_map(lambda x: np.asarray(x)[d], designs)
    z = jnp.zeros((d.size, 3))
    t_probe, _ = timed(lambda: sq._probes(*sub, psi, z, z, "gross_slip", 8, 12).corners)
    t_cycle, _ = timed(lambda: flat_cycles(*sub, psi, "gross_slip", 8, 12).k_re)
    return {"evaluations": int(d.size), "probes_per_s": d.size / t_probe,
            "cycles_per_s": d.size / t_cycle, "probe_over_cycle": t_probe / t_cycle}


def main():
    prev = json.loads((OUT / "jobs_layered.json").read_text())["curve"]
    hbm = prev["hbm_time_at_target_s"]
    res = {"machine": machine(), "job": "2, whole curve (jobs_layered.job_curve's designs and grid)",
           "hbm_reference": {"time_at_1e-4_s_128_designs": hbm, "machine": prev["machine"]},
           "runs": []}
    for n in (128, 1000):
        r = run(n, hbm)
        print(r, flush=True)
        res["runs"].append(r)
    res["probe_cost"] = probe_cost()
    print(res["probe_cost"], flush=True)
    res["target_1000x_met"] = any(r["ratio_vs_hbm_sequence"] >= 1000 for r in res["runs"])
    (OUT / "sequence_curves.json").write_text(json.dumps(res, indent=1) + "\n")


if __name__ == "__main__":
    main()
