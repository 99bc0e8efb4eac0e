"""Blade peak response: amplitude-layered (first harmonic) against coupled HBM-AFT (H = 1, 3, 5)
and time integration, 60sym at mu = 0.5 with the default BladeMode; timings of each.

Writes benchmarks/results/response_baselines.json and its figure, docs/response_baselines.png. Run
from the repository root:
    PYTHONPATH=$PWD python benchmarks/response_baselines.py
"""

from __future__ import annotations

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

from bench_common import call_time, machine, median_time  # noqa: E402
from jaxdamp import family_shape  # noqa: E402
from jaxdamp.baselines.coupled_hbm import coupled_hbm, solve_at_frequency  # noqa: E402
from jaxdamp.baselines.time_integration import start_on_harmonics, steady_state  # noqa: E402
from jaxdamp import BladeMode, damper_stiffness, frf, peak_response
from jaxdamp.blocks import frf_amplitude_grid

OUT = Path(__file__).resolve().parent / "results"
FORCES = (2.0, 5.0, 10.0, 20.0, 50.0)
MU = 0.5


def main():
    info = machine()
    shape, mode = family_shape("60sym"), BladeMode()
    peak = jax.jit(lambda f: peak_response(damper_stiffness(shape, MU, method="interpolated"), mode, f))
    curve = jax.jit(lambda f, top: frf(damper_stiffness(shape, MU, method="interpolated"), mode, f,
                                       frf_amplitude_grid(top)))
    t_peak = median_time(peak, jnp.asarray(20.0), repeats=5)
    t_frf = median_time(curve, jnp.asarray(20.0), jnp.asarray(2.6), repeats=5)
    rows = []
    for force in FORCES:
        lay = peak(jnp.asarray(force))
        row = {"force_n": force, "layered_mm": float(lay.peak_amplitude_mm),
               "layered_hz": float(lay.peak_frequency_hz), "psi_a_mrad": float(lay.psi_a_mrad)}
        for H in ((1,), (1, 3), (1, 3, 5)):
            seconds, path = call_time(lambda: coupled_hbm(shape, MU, mode=mode, force_n=force, harmonics=H))
            key = f"H{max(H)}"
            row[key + "_mm"] = float(path.peak_amplitude_mm)
            row[key + "_hz"] = float(path.peak_frequency_hz)
            row[key + "_max_displacement_mm"] = float(path.peak_max_displacement_mm)
            row[key + "_status"] = int(path.status)
            row[key + "_seconds"] = seconds
            if H == (1, 3, 5):
                path5 = path
        # Time integration at the H = 5 peak frequency and +-0.3 half-widths around it; the peak
        # of the first-harmonic amplitude from the parabola through the three.
        _, k_im = damper_stiffness(shape, MU, method="interpolated").k_of_psi(mode.r * lay.peak_amplitude_mm)
        half = float((mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_im) / (2 * mode.k_b)) * mode.f0_hz
        f5 = row["H5_hz"]
        freqs = [f5 - 0.3 * half, f5, f5 + 0.3 * half]
        amps, hbm5, changes, t_ti = [], [], [], []
        for f in freqs:
            y, res = solve_at_frequency(shape, MU, None, None, mode, force, f, path5.peak_coefficients)
            x0, v0, ph = start_on_harmonics(y, (1, 3, 5), f)
            seconds, ti = call_time(lambda: steady_state(shape, MU, mode=mode, force_n=force,
                                                         frequency_hz=f, x0=x0, v0=v0, phase0=ph,
                                                         n_periods=400))
            t_ti.append(seconds)
            amps.append(float(ti.amplitude_mm))
            hbm5.append(float(np.hypot(y[0], y[1])))
            changes.append(float(ti.change))
        c2, c1, c0 = np.polyfit(np.asarray(freqs) - f5, amps, 2)
        row["TI_mm"] = float(c0 - c1 * c1 / (4 * c2)) if c2 < 0 else max(amps)
        row["TI_at_H5_frequencies_mm"] = amps
        row["H5_at_same_frequencies_mm"] = hbm5
        row["TI_last_period_change"] = changes
        row["TI_seconds_per_frequency"] = float(np.median(t_ti))
        rows.append(row)
        print(json.dumps(row))
    result = {"machine": info, "shape": "60sym", "mu": MU, "mode": BladeMode()._asdict(),
              "layered_peak_seconds": t_peak, "layered_frf_seconds_200_amplitudes": t_frf,
              "rows": rows}
    OUT.mkdir(exist_ok=True)
    (OUT / "response_baselines.json").write_text(json.dumps(result, indent=1))
    figure(result)


def figure(result):
    """The single-harmonic error chart from the results (rows whose continuation failed are left
    out). Time integration's peak is taken as its amplitude at the H = 5 peak frequency: the
    three-point parabola (TI_mm) is too coarse where the FRF is skewed."""
    import matplotlib

    matplotlib.use("Agg")
    from jaxdamp.plotting.response import harmonic_error_figure

    rows = [r for r in result["rows"] if r["H1_status"] == r["H3_status"] == r["H5_status"] == 0]
    fig = harmonic_error_figure([r["force_n"] for r in rows], [r["H1_mm"] for r in rows],
                                {"H=3": [r["H3_mm"] for r in rows],
                                 "H=5": [r["H5_mm"] for r in rows],
                                 "time integration": [r["TI_at_H5_frequencies_mm"][1] for r in rows]})
    fig.savefig(OUT.parent.parent / "docs" / "response_baselines.png", dpi=120)


if __name__ == "__main__":
    import sys

    if "--figure-only" in sys.argv:
        figure(json.loads((OUT / "response_baselines.json").read_text()))
    else:
        main()
