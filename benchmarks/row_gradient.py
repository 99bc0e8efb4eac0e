"""The row's peaks and their derivatives: what the gradient of the row's worst peak costs.

The job (issue "Path cycles at in-phase speed", item 3): every engine order of the example disk
(`--modes example`, 13 orders, 11 on ellipses), 4 forces (2, 5, 10, 20 N), 3 mu (0.3, 0.5, 0.7),
60sym, from assembly, h_L 10 mm. Per mu, `jaxdamp.row_response` (the values program: the peak
search) and then `jaxdamp.row_gradient`'s derivative program at the roots found (dA*/d of nine
variables by the implicit function theorem). Recorded, in a fresh process:

- first calls: the values program (trace + compile + run) and the derivative program (the first
  `row_gradient` call less a warm values call);
- warm: the values and the derivative pass per mu (the median of ROUNDS calls each), and the
  whole job (3 mu) of each;
- the gradient of the smooth maximum of A*/F over the job (temperature 1 % of its largest value)
  with respect to the four shape variables, from the Jacobians, against central differences of
  the same smooth maximum computed from `row_response` alone (steps 1e-3 deg, 1e-5).

Run: python benchmarks/row_gradient.py -> benchmarks/results/row_gradient.json
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax
import numpy as np

from bench_common import machine, use_measured_xla_flags

RESULTS = Path(__file__).parent / "results"
MUS = (0.3, 0.5, 0.7)
FORCES = (2.0, 5.0, 10.0, 20.0)
H_L = 10.0
ROUNDS = 5


def smooth_max(x, width):
    """width * log sum exp(x / width): the smooth maximum of x (>= max x)."""
    top = np.max(x)
    return top + width * np.log(np.sum(np.exp((x - top) / width)))


def main(out: Path = RESULTS / "row_gradient.json") -> dict:
    flags = use_measured_xla_flags()
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp.modal_file import load_modal_family

    family = load_modal_family("example")
    shape = jd.family_shape("60sym")
    kw = dict(modes=family, engine_orders=jd.engine_orders_of("all", family.n_blades),
              force_n=FORCES, h_l_mm=H_L)
    forces = np.asarray(FORCES)

    def timed(fn):
        t = time.perf_counter()
        got = fn()
        return time.perf_counter() - t, got

    first_values, _ = timed(lambda: jd.row_response(shape, MUS[0], **kw))
    values_warm, _ = timed(lambda: jd.row_response(shape, MUS[0], **kw))
    first_gradient, _ = timed(lambda: jd.row_gradient(shape, MUS[0], **kw))
    per_mu = []
    for mu in MUS:
        # The median of ROUNDS warm calls each (one call moved by up to half on this VM).
        tv = [timed(lambda: jd.row_response(shape, mu, **kw))[0] for _ in range(ROUNDS)]
        tg = [timed(lambda: jd.row_gradient(shape, mu, **kw)) for _ in range(ROUNDS)]
        got = tg[-1][1]
        per_mu.append(dict(mu=mu, values_s=float(np.median(tv)),
                           values_and_derivatives_s=float(np.median([t for t, _ in tg])),
                           values_rounds_s=tv, values_and_derivatives_rounds_s=[t for t, _ in tg],
                           got=got))

    # The smooth maximum of A*/F over (mu, order, force) on the valid peaks, and its gradient
    # with respect to the shape from the Jacobians.
    mags = np.stack([np.asarray(p["got"].row.peaks.peak_amplitude_mm) / forces for p in per_mu])
    valid = np.stack([np.asarray(jd.RESULTS.valid(p["got"].row.status)) for p in per_mu])
    jac = np.stack([p["got"].d_peak_mm[..., :4] / forces[:, None] for p in per_mu])
    width = 0.01 * np.max(mags[valid])
    x = np.where(valid, mags, -np.inf)
    weights = np.exp((x - np.max(x)) / width)
    weights /= weights.sum()
    gradient = np.einsum("mof,mofv->v", weights, jac)

    def objective(v):
        s = shape._replace(theta_l=v[0], theta_r=v[1], br_over_hr=v[2], bl2_over_hl=v[3])
        m = np.stack([np.asarray(jd.row_response(s, mu, **kw).peaks.peak_amplitude_mm) / forces
                      for mu in MUS])
        return smooth_max(m[valid], width)

    v0 = np.array([shape.theta_l, shape.theta_r, shape.br_over_hr, shape.bl2_over_hl], float)
    steps = np.array([1e-3, 1e-3, 1e-5, 1e-5])
    central = []
    for j in range(4):
        e = np.zeros(4)
        e[j] = steps[j]
        central.append((objective(v0 + e) - objective(v0 - e)) / (2 * steps[j]))
    central = np.array(central)
    binding = np.unravel_index(np.argmax(x), x.shape)
    result = dict(
        machine=machine(f"2-core VM; XLA_FLAGS {flags!r}"),
        job=dict(shape="60sym", engine_orders=kw["engine_orders"], forces_n=list(FORCES),
                 mu=list(MUS), initial="assembly", h_l_mm=H_L),
        first_call_s=dict(values_program=first_values,
                          derivative_program=first_gradient - values_warm),
        warm_s=dict(per_mu=[{k: v for k, v in p.items() if k != "got"} for p in per_mu],
                    values_job=sum(p["values_s"] for p in per_mu),
                    values_and_derivatives_job=sum(p["values_and_derivatives_s"] for p in per_mu)),
        smooth_max=dict(width_mm_per_n=width, value_mm_per_n=smooth_max(x[valid], width),
                        binding=dict(mu=MUS[binding[0]], engine_order=int(kw["engine_orders"][binding[1]]),
                                     force_n=FORCES[binding[2]]),
                        gradient_ift=gradient.tolist(), gradient_central=central.tolist(),
                        max_relative_difference=float(np.max(np.abs(gradient - central))
                                                      / np.max(np.abs(central)))),
        valid_peaks=int(valid.sum()), peaks=int(valid.size))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: result[k] for k in ("first_call_s", "smooth_max")}, indent=1))
    print(json.dumps({k: v for k, v in result["warm_s"].items() if k != "per_mu"}, indent=1))
    return result


if __name__ == "__main__":
    main()
