"""Benchmark (not a test): `jaxdamp.fit_loops` on three measured-like moment loops of 500 samples
each (60sym; mu = 0.4, kn = 25000 N/mm, kt = 4000 N/mm; 2.5 periods sampled at random times, noise
0.5 % of the moment range, offsets in both channels). Times the first call (compile included) and
the warm median of the whole fit (both stages, covariance, identifiability), records the recovered
parameters against the truth with their 95 % intervals, and compares the solver: optimistix's
Levenberg-Marquardt against optax's L-BFGS on the same plain least-squares problem
(`jaxdamp.fit.fit_problem`), from the same generic start.

    PYTHONPATH=. python benchmarks/fit_loops.py [--repeats 5]

Writes benchmarks/results/fit_loops.json (with the machine it ran on).
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from bench_common import call_time, machine, median_time  # noqa: E402
from jaxdamp import sample_loop  # noqa: E402
from jaxdamp.blocks import fit_problem

OUT = Path(__file__).parent / "results"
# What the L-BFGS comparison gave when it was run (2026-11-24, 2 shared cores, load average 5-10):
# it had not finished after 18 minutes (two compiled programs, values and forward-mode gradient,
# and a zoom line search of eager steps), where Levenberg-Marquardt's whole fit took 46-93 s cold and
# under half a second warm. Levenberg-Marquardt is the solver; rerun without --no-optax to measure.
NO_OPTAX_NOTE = ("optax L-BFGS on the same problem had not finished after 18 min on this machine "
                 "(2026-11-24, load 5-10); see the comment in benchmarks/fit_loops.py")
SHAPE = jd.family_shape("60sym")
TRUE = {"mu": 0.4, "kn": 25000.0, "kt": 4000.0}
AMPS = (0.8, 1.5, 3.0)
OFFSETS = (30.0, -50.0, 10.0)


def loops(seed=1, n=500):
    rng = np.random.default_rng(seed)
    out = []
    for a, off in zip(AMPS, OFFSETS):
        t = np.sort(rng.uniform(0.0, 2.5, n))
        psi, m = sample_loop(SHAPE, TRUE["mu"], a, jd.Contacts(TRUE["kn"], TRUE["kt"]), t=t)
        out.append((psi + 0.2, m + off + rng.normal(0.0, 0.005 * np.ptp(m), n)))
    return out


def optax_lbfgs(prob, max_steps=100, tol=1e-10):
    """optax L-BFGS (zoom line search) on 0.5 sum r^2 of the plain problem: (theta, loss, steps).
    The gradient J^T r takes J by forward mode (6 columns), as Levenberg-Marquardt does: reverse
    mode through the masked cycle iteration compiles for minutes."""
    import optax

    jnp = jax.numpy
    loss = jax.jit(lambda th: 0.5 * jnp.sum(prob.residuals(th, 0.0) ** 2))

    @jax.jit
    def value_and_grad(th):
        r = prob.residuals(th, 0.0)
        J = jax.jacfwd(lambda x: prob.residuals(x, 0.0))(th)
        return 0.5 * jnp.sum(r ** 2), J.T @ r

    opt = optax.lbfgs()
    theta = jnp.asarray(prob.theta0)
    state = opt.init(theta)
    prev = np.inf
    for k in range(max_steps):
        v, g = value_and_grad(theta)
        upd, state = opt.update(g, state, theta, value=v, grad=g, value_fn=loss)
        theta = optax.apply_updates(theta, upd)
        if abs(prev - float(v)) <= tol * max(abs(float(v)), 1e-30):
            break
        prev = float(v)
    return np.asarray(theta), float(loss(theta)), k + 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-optax", action="store_true", help="skip the L-BFGS comparison (minutes)")
    a = ap.parse_args()
    info = machine()
    data = loops()
    first, fit = call_time(jd.fit_loops, data, SHAPE)
    warm = median_time(lambda: jd.fit_loops(data, SHAPE), repeats=a.repeats)
    params = {}
    for i, name in enumerate(fit.names):
        truth = TRUE.get(name, OFFSETS[i - 3] if name.startswith("offset_") else None)
        params[name] = {"truth": truth, "value": float(fit.value[i]), "se": float(fit.se[i]),
                        "lo95": float(fit.lo[i]), "hi95": float(fit.hi[i]),
                        "truth_inside": bool(fit.lo[i] <= truth <= fit.hi[i])}
    print(f"first call {first:.2f} s, warm {warm:.3f} s, steps {fit.steps}", flush=True)
    for k, v in params.items():
        print(k, v, flush=True)

    # the solver, measured: LM (plain stage only) against optax L-BFGS on the same problem
    prob = fit_problem(data, SHAPE)
    plain = lambda: jd.fit_loops(data, SHAPE, robust=False)  # noqa: E731
    plain()
    lm_warm = median_time(plain, repeats=a.repeats)
    lm = plain()
    lm_loss = lm.history[-1][2]  # optimistix's 0.5 sum r^2 at its last accepted step
    solver = {"levenberg_marquardt_optimistix": {"warm_s": lm_warm, "steps": lm.steps[0], "loss": lm_loss,
                                                 "mu": float(lm.mu), "kn": float(lm.kn[0]), "kt": float(lm.kt[0])}}
    if not a.no_optax:
        solver["lbfgs_optax"] = lbfgs_entry(prob)
    else:
        solver["lbfgs_optax"] = {"skipped": "--no-optax", "note": NO_OPTAX_NOTE}
    print(solver, flush=True)
    finish(info, first, warm, fit, params, solver)


def lbfgs_entry(prob):
    ox_first, _ = call_time(optax_lbfgs, prob)
    ox_warm, (th, ox_loss, ox_steps) = call_time(optax_lbfgs, prob)
    ox_vals = {"mu": float(np.exp(th[0])), "kn": float(1e4 * np.exp(th[1])), "kt": float(1e4 * np.exp(th[2]))}
    return {"first_s": ox_first, "warm_s": ox_warm, "steps": ox_steps, "loss": ox_loss, **ox_vals}


def finish(info, first, warm, fit, params, solver):
    try:
        info["load_average_1min_at_end"] = os.getloadavg()[0]
    except OSError:
        pass
    out = {"machine": info, "problem": {"shape": "60sym", "truth": TRUE, "psi_a_mrad": AMPS,
                                        "offsets_nmm": OFFSETS, "samples_per_loop": 500,
                                        "periods_per_loop": 2.5, "noise": "0.5 % of the moment range"},
           "fit": {"first_call_s": first, "warm_s": warm, "target_warm_s": 10.0,
                   "steps": fit.steps, "status": jd.RESULTS.name_of(fit.status),
                   "sigma_nmm": fit.sigma, "parameters": params},
           "solver_comparison_plain_least_squares": solver}
    OUT.mkdir(exist_ok=True)
    (OUT / "fit_loops.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
