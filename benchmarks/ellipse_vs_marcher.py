"""The direct method on elliptic platform paths against the time marcher, on random cases.

Random curved-flat designs (base angles 40-89 deg, b_R/h_R in [-0.2, 0.3], mu 0.2-0.8), interblade
phase angles in (-180, 180) deg (the ellipse), rotation centres h_C 0-80 mm, damper sizes h_L
6-16 mm and amplitudes 0.5-30 mrad, from assembly. Each case is run by `jaxdamp.elliptic_cycle`
and by `jaxdamp.baselines.march_ellipse` at 2000 and 8000 steps of tau per period (six periods
after the history); the record keeps
both k, the energies, the statuses and the errors relative to max(|k_Re|, |k_Im|) (energies
relative to pi a^2 max(|k_Re|, |k_Im|) / 1e3, the loop's energy scale). Cases where either method reports a problem are kept and
counted, not dropped.

Run: python benchmarks/ellipse_vs_marcher.py [n_cases] -> benchmarks/results/ellipse_vs_marcher.json
"""

from __future__ import annotations

import json
import sys
import time
import warnings
from pathlib import Path

import jax
import numpy as np

from bench_common import machine

RESULTS = Path(__file__).parent / "results"
STEPS = (2000, 8000)


def main(n_cases: int = 360) -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp.baselines import march_ellipse

    rng = np.random.default_rng(2026)
    contacts = jd.Contacts(17900.0, 3580.0)
    cases, started = [], time.perf_counter()
    for i in range(n_cases):
        shape = jd.DamperShape(*rng.uniform([40.0, 40.0, -0.2], [89.0, 89.0, 0.3]), 0.8)
        mu = float(rng.uniform(0.2, 0.8))
        phi = float(rng.uniform(-179.0, 179.0))
        phi = phi if abs(phi) > 1.0 else 1.0 + abs(phi)  # an ellipse, not the in-phase segment
        h_c, h_l, psi = (float(v) for v in rng.uniform([0.0, 6.0, 0.5], [80.0, 16.0, 30.0]))
        motion = jd.interblade_motion(phi, h_c, 100.0, h_l)
        row = dict(theta_l=float(shape.theta_l), theta_r=float(shape.theta_r),
                   br_over_hr=float(shape.br_over_hr), mu=mu, ibpa_deg=phi, h_c_mm=h_c,
                   h_l_mm=h_l, amplitude_mrad=psi)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ec = jd.elliptic_cycle(shape, mu, psi, motion, contacts)
        row.update(status=jd.RESULTS.name_of(ec.status), k_re=float(ec.k_re), k_im=float(ec.k_im),
                   energy_nmm=[float(v) for v in np.asarray(ec.energy)],
                   slip_fraction=[float(v) for v in np.asarray(ec.slip_fraction)])
        scale = max(abs(row["k_re"]), abs(row["k_im"]), 1e-300)
        # Energies against the loop's energy scale pi a^2 |k| / 1e3 (N mm), not the work itself,
        # which is near zero where the cycle is nearly elastic.
        work = np.pi * psi**2 * scale / 1e3
        for n in STEPS:
            tm = march_ellipse(shape, mu, psi, motion, contacts, n_steps=n, periods=6)
            row[f"march_{n}"] = dict(
                status=jd.RESULTS.name_of(tm.status), k_re=float(tm.k_re), k_im=float(tm.k_im),
                closure=float(tm.closure), newton_failures=int(tm.newton_failures),
                k_error=max(abs(float(tm.k_re) - row["k_re"]), abs(float(tm.k_im) - row["k_im"])) / scale,
                energy_error=float(np.max(np.abs(np.asarray(tm.energy) - np.asarray(ec.energy)))) / work)
        cases.append(row)
        if (i + 1) % 40 == 0:
            print(f"{i + 1}/{n_cases} cases, {time.perf_counter() - started:.0f} s", flush=True)
    both_ok = [c for c in cases if c["status"] in ("ok", "shakedown")
               and c[f"march_{STEPS[-1]}"]["status"] == "ok" and c[f"march_{STEPS[-1]}"]["closure"] < 1e-9]
    summary = {"cases": len(cases), "direct_status": {}, "compared": len(both_ok)}
    for c in cases:
        summary["direct_status"][c["status"]] = summary["direct_status"].get(c["status"], 0) + 1
    for n in STEPS:
        errs = np.array([c[f"march_{n}"]["k_error"] for c in both_ok if c["status"] == "ok"])
        eerr = np.array([c[f"march_{n}"]["energy_error"] for c in both_ok if c["status"] == "ok"])
        summary[f"march_{n}"] = dict(k_error_max=float(errs.max()), k_error_median=float(np.median(errs)),
                                     energy_error_max=float(eerr.max()),
                                     energy_error_median=float(np.median(eerr)))
    doc = dict(machine=machine(), seconds=time.perf_counter() - started, summary=summary, cases=cases)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "ellipse_vs_marcher.json").write_text(json.dumps(doc, indent=1))
    return doc


if __name__ == "__main__":
    d = main(int(sys.argv[1]) if len(sys.argv) > 1 else 360)
    print(json.dumps(d["summary"], indent=1))
