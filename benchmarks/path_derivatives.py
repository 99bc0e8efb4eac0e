"""Derivatives of a path cycle's k_Im: how long they take to compile, and whether they are right.

The elliptic kernel's derivatives replay the value pass's choices (`loops.values_by_replay`).
With respect to x = (theta_l, theta_r, b_R/h_R, mu, kn, kt, F_D, h_L) (a wedge: b_R2/h_R2 too is
not varied), on the elliptic path of phi = 90 deg and the straight one of phi = 180 deg (an
ellipse of zero width), for the curved-flat damper (60sym) and a wedge (60/60, 2b/h 0.8), from
assembly and from gross slip:

- compile time (lower + compile, warm process) of `jax.jacfwd` and `jax.grad` of one design's
  k_Im, and of `jax.vmap(jax.grad)` over 64 designs (60sym, elliptic path, assembly); there also
  the same three with XLA's latency options (`runtime.LATENCY_OPTIONS`, `*_latency_s`) and the
  public `path_gradient`'s first call per mode (every output, the Design and the Motion);
- agreement with float64 central differences (step 1e-6 of each variable's size) on random
  designs around each base (each variable scaled by 1 + 0.05 N(0, 1), mu in 0.3-0.7, amplitude
  1-10 mrad): a case counts where the central difference is smooth (the two one-sided
  differences agree within 1e-4: no switch of the sequence within the step) and the cycle is ok.

Run: python benchmarks/path_derivatives.py [--cases N] -> benchmarks/results/path_derivatives.json
"""

from __future__ import annotations

import json
import time
import warnings
from pathlib import Path

import jax
import numpy as np

from bench_common import machine

RESULTS = Path(__file__).parent / "results"
NAMES = ("theta_l", "theta_r", "br_over_hr", "mu", "kn", "kt", "F_D", "h_l")


def main(cases: int = 16, out: Path = RESULTS / "path_derivatives.json") -> dict:
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    import jaxdamp as jd

    warnings.simplefilter("ignore", jd.SmallRotationWarning)
    dampers = {"60sym": jd.family_shape("60sym"),
               "wedge": jd.DamperShape(60.0, 60.0, 0.0, 0.8, None, 0.8)}
    load0 = jd.LoadCase()

    def cycle_of(shape, motion, initial):
        """cycle(x, amplitude): the steady cycle at the variables x (NAMES), and x's base."""
        # The kernel's inputs as arrays (the unchecked form; the checked one is elliptic_cycle).
        sh = jd.DamperShape(*(None if v is None else jnp.asarray(float(v)) for v in shape))
        load = jd.LoadCase(*(jnp.asarray(float(v)) for v in load0))

        def cycle(x, amplitude):
            s = sh._replace(theta_l=x[0], theta_r=x[1], br_over_hr=x[2])
            return jd.elliptic_kernel(s, x[3], jd.Contacts(x[4], x[5]), load._replace(F_D=x[6]),
                                      amplitude, motion._replace(h_l=x[7]), initial=initial)

        x0 = np.array([float(sh.theta_l), float(sh.theta_r), float(sh.br_over_hr), 0.5,
                       17900.0, 3580.0, float(load.F_D), 10.0])
        return cycle, x0

    def compile_s(f, *args, options=None):
        """Seconds to lower and compile jax.jit(f) for args (XLA's default options, or `options`)."""
        t0 = time.perf_counter()
        lowered = jax.jit(f).lower(*args)
        lowered.compile(compiler_options=options) if options else lowered.compile()
        return time.perf_counter() - t0

    from jaxdamp.runtime import LATENCY_OPTIONS

    rng = np.random.default_rng(0)
    rows, compiles = [], []
    for damper, shape in dampers.items():
        for phi in (90.0, 180.0):
            motion = jd.interblade_motion(phi, 20.0, 100.0, 10.0)
            motion = motion._replace(quadrature=(jnp.zeros(3) if motion.quadrature is None
                                                 else motion.quadrature))
            for initial in ("assembly", "gross_slip"):
                cycle, x0 = cycle_of(shape, motion, initial)
                k_im = lambda x, a, cycle=cycle: cycle(x, a).k_im  # noqa: E731
                a0 = jnp.asarray(2.0)
                entry = dict(damper=damper, phi_deg=phi, initial=initial,
                             jacfwd_s=compile_s(jax.jacfwd(k_im), x0, a0),
                             grad_s=compile_s(jax.grad(k_im), x0, a0))
                if damper == "60sym" and phi == 90.0 and initial == "assembly":
                    X = np.tile(x0, (64, 1))
                    A = jnp.full(64, 2.0)
                    entry["vmap64_grad_s"] = compile_s(jax.vmap(jax.grad(k_im)), X, A)
                    # The same three programs with XLA's latency options (path_gradient's), and
                    # the public path_gradient's first call (trace, lower, compile, run) per mode.
                    latency = dict(LATENCY_OPTIONS)
                    entry["jacfwd_latency_s"] = compile_s(jax.jacfwd(k_im), x0, a0, options=latency)
                    entry["grad_latency_s"] = compile_s(jax.grad(k_im), x0, a0, options=latency)
                    entry["vmap64_grad_latency_s"] = compile_s(jax.vmap(jax.grad(k_im)), X, A,
                                                               options=latency)
                    for mode in ("fwd", "rev"):
                        t0 = time.perf_counter()
                        g = jd.path_gradient(shape, 0.5, 2.0, motion, jd.Contacts(17900.0, 3580.0),
                                             initial=initial, mode=mode)
                        g.values.k_im.block_until_ready()
                        entry[f"path_gradient_{mode}_first_call_s"] = time.perf_counter() - t0
                compiles.append(entry)
                print(json.dumps(entry), flush=True)
                # Random designs: one program for the derivatives, one for the values.
                X = x0[None] * (1 + 0.05 * rng.standard_normal((cases, 8)))
                X[:, 3] = rng.uniform(0.3, 0.7, cases)
                A = rng.uniform(1.0, 10.0, cases)
                grads = np.asarray(jax.jit(jax.vmap(jax.grad(k_im)))(X, A))
                fwd = np.asarray(jax.jit(jax.vmap(jax.jacfwd(k_im)))(X, A))
                value = jax.jit(jax.vmap(cycle))
                h = 1e-6 * np.maximum(np.abs(x0), 1.0)
                for i in range(cases):
                    steps = X[i][None] + np.diag(h)
                    back = X[i][None] - np.diag(h)
                    up = value(steps, np.full(8, A[i]))
                    down = value(back, np.full(8, A[i]))
                    mid = value(X[i][None], np.full(1, A[i]))
                    ok = (jd.RESULTS.name_of(int(mid.status[0])) == "ok"
                          and np.all(np.asarray(up.status) == 0)
                          and np.all(np.asarray(down.status) == 0))
                    k_mid = float(mid.k_im[0])
                    forward = (np.asarray(up.k_im) - k_mid) / h
                    backward = (k_mid - np.asarray(down.k_im)) / h
                    central = 0.5 * (forward + backward)
                    scale = max(np.max(np.abs(central)), 1e-300)
                    smooth = bool(np.all(np.abs(forward - backward) <= 1e-4 * scale))
                    err = float(np.max(np.abs(grads[i] - central)) / scale)
                    rows.append(dict(damper=damper, phi_deg=phi, initial=initial,
                                     amplitude_mrad=float(A[i]), ok=bool(ok), smooth=smooth,
                                     grad_error=err,
                                     jacfwd_grad_difference=float(
                                         np.max(np.abs(fwd[i] - grads[i])) / scale)))
    checked = [r for r in rows if r["ok"] and r["smooth"]]
    doc = dict(machine=machine(), variables=list(NAMES), compile=compiles,
               summary=dict(cases=len(rows), checked=len(checked),
                            max_grad_error=max((r["grad_error"] for r in checked), default=None),
                            within_1e_6=sum(r["grad_error"] <= 1e-6 for r in checked),
                            max_jacfwd_grad_difference=max(
                                (r["jacfwd_grad_difference"] for r in checked), default=None)),
               cases=rows)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(doc, indent=1))
    return doc


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=16, help="random designs per case kind")
    args = parser.parse_args()
    doc = main(args.cases)
    print(json.dumps(doc["summary"], indent=1))
