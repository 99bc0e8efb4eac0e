"""Convergence of the time marcher to the direct method's steady cycles at prescribed amplitudes.

For each case (shape, mu, amplitude regime, initial state) the direct method's k_Re, k_Im
(`jaxdamp.amplitude.amplitude_cycle`) are compared with the time marcher's
(`jaxdamp.baselines.timemarch.march_amplitude`, started from the same state at the same amplitude) at several
step counts per half-cycle. Amplitudes: 0.5 psi_fs (below), (psi_fs + psi_BC)/2 (between), 1.5 psi_BC
(above), from the Base-Cycle's five numbers. Writes benchmarks/results/amplitude_vs_timemarch.json.

    PYTHONPATH=. python benchmarks/amplitude_vs_timemarch.py
"""

from __future__ import annotations

import json
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp import RESULTS, amplitude_cycle  # noqa: E402
from jaxdamp.baselines.timemarch import march_amplitude  # noqa: E402
from bench_common import call_time, machine  # noqa: E402

CONTACTS = jd.Contacts(17900.0, 3580.0)
STEPS = (1000, 4000, 16000, 64000, 256000)

SHAPES = {
    "60sym": jd.family_shape("60sym"), "74R": jd.family_shape("74R"), "90R": jd.family_shape("90R"),
    "rand_a": jd.DamperShape(55.0, 66.0, 0.10), "rand_b": jd.DamperShape(63.0, 57.0, 0.12),
    "rand_c": jd.DamperShape(50.0, 72.0, 0.06),
}
CASES = [  # (shape, mu, regime, initial)
    ("60sym", 0.3, "below", "gross_slip"), ("60sym", 0.3, "between", "gross_slip"),
    ("60sym", 0.5, "between", "gross_slip"), ("60sym", 0.5, "between", "assembly"),
    ("60sym", 0.5, "above", "assembly"), ("60sym", 0.7, "between", "gross_slip"),
    ("74R", 0.7, "below", "gross_slip"), ("74R", 0.7, "between", "gross_slip"),
    ("74R", 0.7, "between", "assembly"), ("74R", 0.7, "above", "gross_slip"),
    ("90R", 0.5, "above", "gross_slip"), ("90R", 0.5, "above", "assembly"),
    ("90R", 0.7, "far", "gross_slip"), ("90R", 0.3, "far", "assembly"),
    ("rand_a", 0.4, "between", "gross_slip"), ("rand_b", 0.6, "between", "assembly"),
    ("rand_c", 0.5, "between", "gross_slip"), ("rand_c", 0.5, "below", "assembly"),
]


def amplitude_for(shape, mu, regime):
    nums = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))
    fs, bc = float(nums.psi_fs), float(nums.psi_bc)
    return {"below": 0.5 * fs, "between": 0.5 * (fs + bc), "above": 1.5 * bc, "far": 4.0 * bc}[regime]


def main():
    info = machine()
    rows = []
    for name, mu, regime, initial in CASES:
        shape = SHAPES[name]
        psi = amplitude_for(shape, mu, regime)
        ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
        scale = max(abs(float(ac.k_re)), abs(float(ac.k_im)))
        row = dict(shape=name, mu=mu, regime=regime, initial=initial, psi_a_mrad=psi,
                   k_re=float(ac.k_re), k_im=float(ac.k_im), status=RESULTS.name_of(ac.status),
                   cycles=int(ac.cycles), march=[])
        for n in STEPS:
            seconds, tm = call_time(lambda: march_amplitude(shape, mu, psi, CONTACTS, initial=initial,
                                                            n_steps=n, max_pairs=10))
            err = max(abs(float(tm.k_re) - row["k_re"]), abs(float(tm.k_im) - row["k_im"])) / scale
            row["march"].append(dict(n_steps=n, k_re=float(tm.k_re), k_im=float(tm.k_im), rel_err=err,
                                     closure=float(np.asarray(tm.closure)[-1]),
                                     newton_failures=int(tm.newton_failures),
                                     seconds=seconds))
        rows.append(row)
        errs = " ".join(f"{m['rel_err']:.1e}" for m in row["march"])
        print(f"{name:7} mu {mu:.1f} {regime:8} {initial:10} psi {psi:7.4f}  k_re {row['k_re']:10.3f} "
              f"k_im {row['k_im']:9.3f} {row['status']:9} cyc {row['cycles']}  err@{STEPS}: {errs}",
              flush=True)
    out = Path(__file__).parent / "results" / "amplitude_vs_timemarch.json"
    out.write_text(json.dumps(dict(machine=info,
                                   contacts_N_per_mm=[17900.0, 3580.0], steps=STEPS,
                                   error="max(|dk_Re|, |dk_Im|) / max(|k_Re|, |k_Im|)", cases=rows),
                              indent=1))


if __name__ == "__main__":
    main()
