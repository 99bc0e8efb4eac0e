"""The tract engine on any pad set, with pads that open and close, against the time marcher.

Random cases (seeded): half curved-flat dampers (R1 | L1, L2), half wedges (R1, R2 | L1, L2);
base angles 45-80 deg, pad spacings 2b/h 0.5-0.9 on each flat flank (b_R/h_R in [-0.2, 0.3] for
the curved pad), mu 0.3-0.7, interblade phase angles uniform in [-180, 180] deg (0 and 180 are
straight paths, run as ellipses of zero width), rotation centres h_C 10-40 mm, damper size
h_L 8-14 mm, amplitudes 1-25 mrad (the large ones open pads), from assembly. Each case is run by
`jaxdamp.elliptic_cycle` (the engine's events in closed form) and by
`jaxdamp.baselines.march_ellipse` (Newton with return mapping and gaps at every step, no event
logic) at 4000 and 16000 steps of tau per period (STEPS), six periods after the history. The
record keeps both results, k's error relative to max(|k_Re|, |k_Im|) and the largest difference
of the open and slip fractions per pad (the marcher's are fractions of its samples: a step is
1/n_steps) at each step count; the tolerances are judged at the finest (its error falls with the
step where the two disagree: the marcher's). Cases where either method reports a problem are
kept and counted, not dropped.

Run: python benchmarks/pads_vs_marcher.py [n_cases] -> benchmarks/results/pads_vs_marcher.json
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
STEPS = (4000, 16000)
K_TOL = 1e-4  # of max(|k_Re|, |k_Im|): the tolerance
FRACTION_TOL = 2.0 / STEPS[-1]  # two of the finest marcher's steps


def main(n_cases: int = 230) -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd
    from jaxdamp.baselines import march_ellipse

    rng = np.random.default_rng(3434)
    contacts = jd.Contacts(17900.0, 3580.0)
    cases, started = [], time.perf_counter()
    for i in range(n_cases):
        wedge = i % 2 == 1
        tl, tr, bl2 = (float(v) for v in rng.uniform([45.0, 45.0, 0.5], [80.0, 80.0, 0.9]))
        if wedge:
            shape = jd.DamperShape(tl, tr, 0.0, bl2, None, float(rng.uniform(0.5, 0.9)))
        else:
            shape = jd.DamperShape(tl, tr, float(rng.uniform(-0.2, 0.3)), bl2)
        mu = float(rng.uniform(0.3, 0.7))
        phi = float(rng.uniform(-180.0, 180.0))
        h_c, h_l, psi = (float(v) for v in rng.uniform([10.0, 8.0, 1.0], [40.0, 14.0, 25.0]))
        motion = jd.interblade_motion(phi, h_c, 100.0, h_l)
        row = dict(damper="wedge" if wedge else "curved-flat", pads=list(jd.blocks.pad_names(shape)),
                   theta_l=tl, theta_r=tr, br_over_hr=None if wedge else float(shape.br_over_hr),
                   br2_over_hr=float(shape.br2_over_hr) if wedge else None, bl2_over_hl=bl2,
                   mu=mu, ibpa_deg=phi, h_c_mm=h_c, h_l_mm=h_l, amplitude_mrad=psi)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            ec = jax.block_until_ready(jd.elliptic_cycle(shape, mu, psi, motion, contacts))
            row["engine_s"] = time.perf_counter() - t0
        row.update(status=jd.RESULTS.name_of(ec.status), k_re=float(ec.k_re), k_im=float(ec.k_im),
                   periods=int(ec.periods),
                   open_fraction=[float(v) for v in np.asarray(ec.open_fraction)],
                   slip_fraction=[float(v) for v in np.asarray(ec.slip_fraction)])
        scale = max(abs(row["k_re"]), abs(row["k_im"]), 1e-300)
        for n in STEPS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                t0 = time.perf_counter()
                tm = jax.block_until_ready(march_ellipse(shape, mu, psi, motion, contacts,
                                                         n_steps=n, periods=6))
                seconds = time.perf_counter() - t0
            row[f"march_{n}"] = dict(
                seconds=seconds, status=jd.RESULTS.name_of(tm.status), k_re=float(tm.k_re),
                k_im=float(tm.k_im), closure=float(tm.closure),
                newton_failures=int(tm.newton_failures),
                open_fraction=[float(v) for v in np.asarray(tm.open_fraction)],
                slip_fraction=[float(v) for v in np.asarray(tm.slip_fraction)],
                k_error=max(abs(float(tm.k_re) - row["k_re"]),
                            abs(float(tm.k_im) - row["k_im"])) / scale,
                open_fraction_error=float(np.max(np.abs(np.asarray(tm.open_fraction)
                                                        - np.asarray(ec.open_fraction)))),
                slip_fraction_error=float(np.max(np.abs(np.asarray(tm.slip_fraction)
                                                        - np.asarray(ec.slip_fraction)))))
        cases.append(row)
        if (i + 1) % 20 == 0:
            print(f"{i + 1}/{n_cases} cases, {time.perf_counter() - started:.0f} s", flush=True)
    fine = f"march_{STEPS[-1]}"
    compared = [c for c in cases if c["status"] in ("ok", "shakedown")
                and c[fine]["status"] == "ok" and c[fine]["closure"] < 1e-9]

    def tally(key):
        out = {}
        for c in cases:
            out[key(c)] = out.get(key(c), 0) + 1
        return out

    summary = dict(
        cases=len(cases), engine_status=tally(lambda c: c["status"]),
        march_status=tally(lambda c: c[fine]["status"]), compared=len(compared),
        compared_wedges=sum(c["damper"] == "wedge" for c in compared),
        compared_with_opening_pads=sum(max(c["open_fraction"]) > 0.0 for c in compared),
        k_tol=K_TOL, fraction_tol=FRACTION_TOL, steps=list(STEPS),
        engine_s_median=float(np.median([c["engine_s"] for c in cases[2:]])))
    for n in STEPS:
        key = f"march_{n}"
        summary[key] = dict(
            k_error_max=max(c[key]["k_error"] for c in compared),
            k_error_median=float(np.median([c[key]["k_error"] for c in compared])),
            open_fraction_error_max=max(c[key]["open_fraction_error"] for c in compared),
            slip_fraction_error_max=max(c[key]["slip_fraction_error"] for c in compared),
            seconds_median=float(np.median([c[key]["seconds"] for c in cases[2:]])))
    summary["within_tolerances"] = sum(c[fine]["k_error"] <= K_TOL
                                       and c[fine]["open_fraction_error"] <= FRACTION_TOL
                                       for c in compared)
    summary["seconds"] = time.perf_counter() - started
    out = dict(machine=machine(), summary=summary, cases=cases)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "pads_vs_marcher.json").write_text(json.dumps(out, indent=1))
    print(json.dumps(summary, indent=1))
    return out


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 230)
