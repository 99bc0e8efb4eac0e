"""Issue 24, part 2: the band over admissible histories by the tract-sequence structure.

    python benchmarks/band_sequence.py            # results/band_sequence.json
    python benchmarks/band_sequence.py --quick    # 2 shapes x 1 mu
    python benchmarks/band_sequence.py --starts 1 --steps 4   # other options: results/band_sequence_starts1_steps4.json

Test set: the paper's five shapes (90L, 74L, 60sym, 74R, 90R) x mu 0.3, 0.5, 0.7 x six amplitudes
(0.2, 0.4, 0.6, 0.8, 1.0, 1.3) psi_BC of the design, plus 45sym at mu 0.5 (outside the paper's
family, recorded apart). For each case:

- the reference: k of 10^4 admissible initial states drawn uniformly in the vertices' bounding
  box (rejection, numpy's generator, independent of the band's own sampling), and where the set
  is unbounded (a self-locking wedge) 10^4 more in a box 9 times that size, each run as a plain
  cycle (`amplitude_kernel`, vmap);
- `amplitude_bands` with the defaults (vertices + 64 samples, 2 starts x 6 trust-region steps on
  the sequence's exact second-order model) and with refine=False (the samples only), each over
  the six amplitudes in one call;
- "narrower": how far each bound falls inside the reference extremes, relative to the case's k
  scale (positive: narrower; the target is never narrower, beyond rounding 1e-9);
- "confirmed": every bound's attaining state re-run as a plain cycle gives the bound (1e-9).

Timing (warm, medians of 5, `block_until_ready` through device_get): per design and amplitude on a
grid of 24 amplitudes (the response band's grid), and `peak_band` (24 amplitudes + the peak
solves at 3 forces) in process. The CLI's `jaxdamp response --band` is timed as a subprocess twice
(the second call with the persistent caches warm).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.band import admissible_polytope, polytope_vertices, recession_rays  # noqa: E402
from jaxdamp.cli import configure_runtime  # noqa: E402
from bench_common import loadavg, machine, use_measured_xla_flags, warm_times  # noqa: E402

use_measured_xla_flags()
configure_runtime()

OUT = Path(__file__).parent / "results"
CONTACTS = jd.Contacts(jd.REFERENCE_KN, jd.REFERENCE_KT)
LOAD = jd.LoadCase()
FRACTIONS = np.array([0.2, 0.4, 0.6, 0.8, 1.0, 1.3])
N_REF = 10_000
SIGNS = np.array([1.0, -1.0, 1.0, -1.0])
OPTIONS: dict = {}  # amplitude_bands options (--starts N, --steps N on the command line)


@jax.jit
def _reference_k(shape, mu, psi, T):
    P, n0, _, _ = admissible_polytope(shape, mu)

    def one(p, t):
        ac = jd.amplitude_kernel(shape, mu, CONTACTS, LOAD, p, P @ t + n0, t, initial="explicit")
        return ac.k_re, ac.k_im, ac.status
    return jax.vmap(lambda p: jax.vmap(lambda t: one(p, t))(T))(psi)


def uniform_states(shape, mu, n, seed=1, enlarge=0.0):
    """n admissible states uniform in the vertices' bounding box (enlarged by `enlarge` times its
    size on every side: where the set is unbounded, the far, self-locked states)."""
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    V, ok = (np.asarray(v) for v in polytope_vertices(G, h))
    V = V[ok]
    lo, hi = V.min(0), V.max(0)
    size = np.max(hi - lo)
    lo, hi = lo - enlarge * size, hi + enlarge * size
    rng = np.random.default_rng(seed)
    out, got = [], 0
    while got < n:
        X = rng.uniform(lo, hi, (20 * n, 3))
        X = X[np.all(X @ G.T + h >= 0, axis=1)]
        out.append(X)
        got += len(X)
    return np.concatenate(out)[:n]


def reference(shape, mu, psi):
    T = uniform_states(shape, mu, N_REF)
    _, ok = (np.asarray(v) for v in recession_rays(admissible_polytope(shape, mu)[2]))
    if ok.any():  # unbounded: as many again in a box 9 times the size (4 on every side)
        T = np.concatenate([T, uniform_states(shape, mu, N_REF, seed=2, enlarge=4.0)])
    kr, ki, st = (np.asarray(v) for v in _reference_k(shape, mu, jnp.asarray(psi), jnp.asarray(T)))
    v = np.asarray(jd.RESULTS.valid(st))
    ref = np.stack([np.where(v, kr, np.inf).min(1), np.where(v, kr, -np.inf).max(1),
                    np.where(v, ki, np.inf).min(1), np.where(v, ki, -np.inf).max(1)], 1)
    return ref, v.sum(axis=1)


def narrower(bands, ref, n_ref_valid):
    """(amplitudes, 4) relative shortfall of the band against the reference (0 where neither has a
    valid state; +inf where the reference has one and the band none)."""
    b = np.array([x.bounds for x in bands])
    have = np.array([x.status == jd.RESULTS.ok for x in bands])
    finite = n_ref_valid[:, None] > 0
    scale = np.max(np.where(finite, np.abs(np.where(np.isfinite(ref), ref, 0.0)), 0.0)) or 1.0
    out = np.where(finite, SIGNS * (b - np.where(np.isfinite(ref), ref, 0.0)) / scale, 0.0)
    return np.where(finite & ~have[:, None], np.inf, out)


def timed(fn, repeats=5):
    """(median, [min, max]) of warm calls (s), by bench_common's timer."""
    ts, _ = warm_times(fn, repeats=repeats)
    return float(np.median(ts)), [float(min(ts)), float(max(ts))]


def main(quick: bool):
    t_start = time.perf_counter()
    shapes = ["74L", "90R"] if quick else ["90L", "74L", "60sym", "74R", "90R"]
    mus = [0.5] if quick else [0.3, 0.5, 0.7]
    cases = [(s, m) for s in shapes for m in mus] + ([] if quick else [("45sym", 0.5)])
    rows = []
    for name, mu in cases:
        shape = jd.family_shape(name)
        fn = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS, LOAD))
        if int(fn.status) != jd.RESULTS.ok:  # 74L at mu 0.7 lifts off: no psi_BC to scale by
            rows.append({"shape": name, "mu": mu, "skipped": jd.RESULTS.name_of(fn.status)})
            continue
        psi_bc = float(fn.psi_bc)
        psi = FRACTIONS * psi_bc
        ref, nv = reference(shape, mu, psi)
        row = {"shape": name, "mu": mu, "psi_bc_mrad": psi_bc, "psi_a_mrad": psi.tolist(),
               "reference_valid_states": nv.tolist(), "reference_bounds": np.where(
                   np.isfinite(ref), ref, np.nan).tolist()}
        for label, kw in (("sequence", OPTIONS), ("samples_only", {"refine": False})):
            bands = jd.amplitude_band(shape, mu, psi, CONTACTS, LOAD, **kw)
            nar = narrower(bands, ref, nv)
            row[label] = {
                "bounds": [b.bounds.tolist() for b in bands],
                "status": [jd.RESULTS.name_of(b.status) for b in bands],
                "max_narrower_rel": float(np.max(nar)),
                "narrower_bounds_beyond_1e-9": int(np.sum(nar > 1e-9)),
                "all_confirmed": bool(all(bool(np.all(b.confirmed)) for b in bands
                                          if b.status == jd.RESULTS.ok)),
                "refined_bounds": int(sum(int(np.sum(b.refined)) for b in bands))}
        rows.append(row)
        print(f"{name} mu {mu}: narrower sequence {row['sequence']['max_narrower_rel']:.2e} "
              f"({row['sequence']['narrower_bounds_beyond_1e-9']} bounds), samples only "
              f"{row['samples_only']['max_narrower_rel']:.2e} "
              f"({row['samples_only']['narrower_bounds_beyond_1e-9']})", flush=True)

    # timing: the response band's grid (24 amplitudes), one design
    shape, mu = jd.family_shape("74L"), 0.3
    psi_bc = float(jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS, LOAD)).psi_bc)
    grid = np.geomspace(0.05 * psi_bc, 3.0 * psi_bc, 24)
    timing = {}
    for label, kw in (("sequence", OPTIONS), ("samples_only", {"refine": False})):
        med, spread = timed(lambda: jd.amplitude_band(shape, mu, grid, CONTACTS, LOAD, **kw))
        timing[label] = {"grid_24_s": med, "min_max_s": spread, "per_amplitude_ms": 1e3 * med / 24}
    forces = jnp.asarray([5.0, 20.0, 50.0])
    med, spread = timed(lambda: jd.peak_band(shape, mu, CONTACTS, LOAD, jd.BladeMode(), forces), 3)
    timing["peak_band_in_process_s"] = {"median": med, "min_max": spread}
    cli = []
    for _ in range(2):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "jaxdamp.cli", "response", "--shape", "74L", "--mu",
                        "0.3", "--band", "--json"], check=True, capture_output=True)
        cli.append(time.perf_counter() - t0)
    timing["cli_response_band_s"] = {"first_call": cli[0], "repeat_call": cli[1],
                                     "command": "jaxdamp response --shape 74L --mu 0.3 --band --json"}
    paper = [r for r in rows if r["shape"] != "45sym" and "skipped" not in r]
    res = {"machine": machine(), "loadavg_end": loadavg(), "quick": quick, "options": OPTIONS,
           "reference_states": N_REF, "amplitude_fractions_of_psi_bc": FRACTIONS.tolist(),
           "cases": rows, "timing": timing,
           "summary": {
               "paper_shapes_max_narrower_rel_sequence": max(r["sequence"]["max_narrower_rel"]
                                                             for r in paper),
               "paper_shapes_narrower_bounds_sequence": sum(
                   r["sequence"]["narrower_bounds_beyond_1e-9"] for r in paper),
               "paper_shapes_narrower_bounds_samples_only": sum(
                   r["samples_only"]["narrower_bounds_beyond_1e-9"] for r in paper),
               "bounds_checked": 4 * len(FRACTIONS) * len(paper),
               "all_confirmed": all(r["sequence"]["all_confirmed"] for r in rows if "skipped" not in r),
               "target_ms_per_amplitude": 10.0,
               "per_amplitude_ms": timing["sequence"]["per_amplitude_ms"],
               "target_response_band_s": 5.0,
               "cli_repeat_s": timing["cli_response_band_s"]["repeat_call"]},
           "wall_s": time.perf_counter() - t_start}
    OUT.mkdir(exist_ok=True)
    name = "band_sequence_quick.json" if quick else "band_sequence.json"
    if OPTIONS:
        name = name.replace(".json", "_" + "_".join(f"{k}{v}" for k, v in OPTIONS.items()) + ".json")
    (OUT / name).write_text(json.dumps(res, indent=1))
    print(json.dumps(res["summary"], indent=1))


if __name__ == "__main__":
    for flag in ("--starts", "--steps", "--n-samples"):
        if flag in sys.argv:
            OPTIONS[flag[2:].replace("-", "_")] = int(sys.argv[sys.argv.index(flag) + 1])
    main("--quick" in sys.argv)
