"""Issue 24, step 3: the piecewise closed-form curves (`jaxdamp.sequence`) against the per-amplitude
cycles (`amplitude_curves` / `amplitude_kernel`, the reference method), status for status.

Sets: the five paper shapes at mu 0.3, 0.5, 0.7 from both histories; random designs (angles
35-90 deg, b_R/h -0.3..0.4, mu 0.1-0.9, liftoff designs included) from both histories; explicit
initial states (random admissible states of the paper shapes at mu 0.5). 200 amplitudes from 0.02
to 3 psi_BC (designs whose Base-Cycle fails: 0.02..3 mrad). Error: max over a curve's covered
amplitudes of max(|dk_Re|, |dk_Im|) / max over the curve of max(|k_Re|, |k_Im|) (the reference's).
Uncovered amplitudes (gaps the models did not resolve) are counted: `amplitude_curves(method=
"sequence")` computes them by plain cycles.

    python benchmarks/sequence_check.py [--designs 500] [--quick]   # results/sequence_check.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from jaxdamp import amplitude_kernel, stiffness_curve
from jaxdamp.blocks import admissible_polytope, curve_at, polytope_vertices

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import machine  # noqa: E402

OUT = Path(__file__).parent / "results"
N_AMP = 200
TOL = 1e-9


def stack(shapes, mu):
    shape = jax.tree_util.tree_map(lambda *x: np.array(x, float), *shapes)
    return shape, np.asarray(mu, float)


def psi_bc_of(shape, mu):
    s = jd.evaluate_designs(jd.stack_designs(shape, mu))
    pbc = np.asarray(s.psi_bc, float)
    return np.where(np.isfinite(pbc) & (pbc > 0), pbc, 1.0)


@jax.jit
def _explicit_ref(shape, mu, psi, N0, T0):
    def one(s, m, p, n, t):
        ac = amplitude_kernel(s, m, jd.Contacts(), jd.LoadCase(), p, n, t, initial="explicit")
        return ac.k_re, ac.k_im, ac.status
    return jax.vmap(one)(shape, mu, psi, N0, T0)


def reference(shape, mu, grid, initial, N0=None, T0=None):
    if initial != "explicit":
        r = jd.amplitude_curves(shape, mu, grid, initial=initial)
        return np.asarray(r.k_re), np.asarray(r.k_im), np.asarray(r.status)
    n, m = grid.shape
    rep = lambda x: np.repeat(np.asarray(x), m, axis=0)  # noqa: E731
    sh = jax.tree_util.tree_map(rep, shape)
    out = _explicit_ref(sh, rep(mu), grid.reshape(-1), rep(N0), rep(T0))
    return tuple(np.asarray(x).reshape(n, m) for x in out)


def compare(label, shape, mu, initial, N0=None, T0=None, names=None, free=True):
    n = len(mu)
    pbc = psi_bc_of(shape, mu)
    grid = np.linspace(0.02, 3.0, N_AMP)[None] * pbc[:, None]
    designs = (shape, mu, jax.tree_util.tree_map(lambda x: np.full(n, x), jd.Contacts()),
               jax.tree_util.tree_map(lambda x: np.full(n, x), jd.LoadCase()))
    t = time.perf_counter()
    cur_g = stiffness_curve(designs, grid=grid, initial=initial, N_init=N0, T_init=T0)
    t_build_grid = time.perf_counter() - t
    t = time.perf_counter()
    cur = (stiffness_curve(designs, grid[:, 0], grid[:, -1], initial=initial, N_init=N0, T_init=T0)
           if free else cur_g)
    t_build = time.perf_counter() - t
    pt = curve_at(cur, jnp.asarray(grid))
    pt_g = curve_at(cur_g, jnp.asarray(grid))
    k_re, k_im, st = reference(shape, mu, grid, initial, N0, T0)
    cov = np.asarray(pt.covered)
    scale = np.maximum(np.max(np.maximum(np.abs(k_re), np.abs(k_im)), axis=1, keepdims=True), 1e-300)
    err = np.maximum(np.abs(np.asarray(pt.k_re) - k_re), np.abs(np.asarray(pt.k_im) - k_im)) / scale
    err = np.where(cov, err, 0.0)
    mism = cov & (np.asarray(pt.status) != st)
    per = err.max(axis=1)
    row = dict(set=label, initial=initial, free_curve=("on [psi_lo, psi_hi], probes anywhere"
                                                      if free else "the grid curve"), designs=n, amplitudes=N_AMP,
               max_error=float(err.max()), median_curve_error=float(np.median(per)),
               curves_over_tol=int(np.sum(per > TOL)), status_mismatches=int(mism.sum()),
               uncovered_points=int((~cov).sum()), curves_with_uncovered=int(np.sum(~cov.all(axis=1))),
               cycles_per_curve_mean=float(np.mean(cur.cycles)),
               cycles_per_curve_max=int(np.max(cur.cycles)),
               pieces_per_curve_mean=float(np.mean(np.sum(np.isfinite(np.asarray(cur.start)), axis=1) + 1)),
               build_s=t_build,
               reference_statuses={jd.RESULTS.name_of(int(c)): int(k)
                                   for c, k in zip(*np.unique(st, return_counts=True))})
    if names is not None:
        row["per_design"] = [dict(design=nm, max_error=float(e), cycles=int(c),
                                  uncovered=int((~cv).sum()))
                             for nm, e, c, cv in zip(names, per, np.asarray(cur.cycles), cov)]
    cov_g = np.asarray(pt_g.covered)
    err_g = np.maximum(np.abs(np.asarray(pt_g.k_re) - k_re), np.abs(np.asarray(pt_g.k_im) - k_im)) / scale
    err_g = np.where(cov_g, err_g, 0.0)
    row["on_grid"] = dict(max_error=float(err_g.max()), curves_over_tol=int(np.sum(err_g.max(axis=1) > TOL)),
                          status_mismatches=int((cov_g & (np.asarray(pt_g.status) != st)).sum()),
                          uncovered_points=int((~cov_g).sum()),
                          cycles_per_curve_mean=float(np.mean(cur_g.cycles)),
                          cycles_per_curve_max=int(np.max(cur_g.cycles)), build_s=t_build_grid)
    print({k: v for k, v in row.items() if k != "per_design"}, flush=True)
    return row


def random_designs(n, seed=1):
    rng = np.random.default_rng(seed)
    shape = jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n), rng.uniform(-0.3, 0.4, n),
                           np.full(n, 0.8))
    return shape, rng.uniform(0.1, 0.9, n)


def explicit_states(shape1, mu, k, rng):
    P, n0, G, h = admissible_polytope(shape1, mu)
    V, ok = polytope_vertices(G, h)
    V = np.asarray(V)[np.asarray(ok)]
    w = rng.dirichlet(np.full(len(V), 0.3), k)
    T = w @ V
    N = T @ np.asarray(P).T + np.asarray(n0)
    return N, T


def main(argv=None):
    p = argparse.ArgumentParser()
    p.add_argument("--designs", type=int, default=500)
    p.add_argument("--states", type=int, default=8, help="explicit states per paper shape")
    p.add_argument("--out", default=str(OUT / "sequence_check.json"))
    a = p.parse_args(argv)
    res = {"machine": machine(), "tolerance": TOL, "amplitudes": "200, 0.02..3 psi_BC",
           "reference": "amplitude_curves (gross_slip, assembly) / amplitude_kernel (explicit)",
           "sets": []}
    names = [f"{s} mu {m}" for s in jd.FAMILY for m in (0.3, 0.5, 0.7)]
    shape, mu = stack([jd.family_shape(s) for s in jd.FAMILY for _ in range(3)],
                      [m for _ in jd.FAMILY for m in (0.3, 0.5, 0.7)])
    for initial in ("gross_slip", "assembly"):
        res["sets"].append(compare("paper shapes", shape, mu, initial, names=names))
    rng = np.random.default_rng(7)
    Ns, Ts, shs = [], [], []
    for s in jd.FAMILY:
        N, T = explicit_states(jd.family_shape(s), 0.5, a.states, rng)
        Ns.append(N)
        Ts.append(T)
        shs += [jd.family_shape(s)] * a.states
    shape_e, mu_e = stack(shs, [0.5] * len(shs))
    res["sets"].append(compare("paper shapes, mu 0.5, random admissible states", shape_e, mu_e,
                               "explicit", np.concatenate(Ns), np.concatenate(Ts)))
    if a.designs:
        shape_r, mu_r = random_designs(a.designs)
        for initial in ("gross_slip", "assembly"):
            res["sets"].append(compare(f"{a.designs} random designs", shape_r, mu_r, initial,
                                       free=False))
    res["all_within_tolerance"] = all(r["max_error"] <= TOL and r["status_mismatches"] == 0
                                      for r in res["sets"])
    res["all_within_tolerance_on_grid"] = all(
        r["on_grid"]["max_error"] <= TOL and r["on_grid"]["status_mismatches"] == 0
        and r["on_grid"]["uncovered_points"] == 0 for r in res["sets"])
    Path(a.out).write_text(json.dumps(res, indent=1) + "\n")
    print("all within tolerance:", res["all_within_tolerance"])


if __name__ == "__main__":
    main()
