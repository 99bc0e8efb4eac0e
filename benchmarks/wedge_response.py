"""The paper's claim in the blade's forced response: the curved-flat damper (60sym) against a wedge
of the same base angles, peak tip response against the interblade phase angle.

`jaxdamp.path_response_curves` for both dampers (the 60/60 wedge with two flat pads on each flank
at +-0.4 h from its midpoint, 2b/h = 0.8, as in benchmarks/ibpa_sweep.py), mu 0.5, contacts
17900 / 3580 N/mm, the paper's Fig. 4 kinematics (rotation centres h_C = 20 mm below D, q* = 100
mm, damper size h_L = 10 mm), history assembly, at phi = 0, 45, 90, 135, 180 deg and two modal
forces, on one illustrative blade mode (f0 500 Hz, k_b 500 N/mm, eta 0.001, r = 1 mrad of the
left-hand blade's platform rotation per mm of tip). Per case: the peak A* (mm), its frequency,
psi_a, the free blade's peak F / (eta k_b) over A* (the peak reduction) and the status.

Run: python benchmarks/wedge_response.py -> benchmarks/results/wedge_response.json and its figure,
docs/wedge_response.png.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax
import numpy as np

from bench_common import machine

RESULTS = Path(__file__).parent / "results"
PHIS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0)
FORCES_N = (5.0, 20.0)
MU = 0.5
H_C_MM, H_L_MM, Q_STAR_MM = 20.0, 10.0, 100.0


def main() -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd

    contacts = jd.Contacts(17900.0, 3580.0)
    mode = jd.BladeMode(500.0, 500.0, 0.001, 1.0)
    dampers = {"curved-flat 60sym": jd.family_shape("60sym"),
               "wedge 60/60": jd.DamperShape(60.0, 60.0, 0.0, 0.8, br2_over_hr=0.8)}
    free = np.asarray(FORCES_N) / (mode.eta * mode.k_b)
    rows, started = [], time.perf_counter()
    for name, shape in dampers.items():
        for phi in PHIS_DEG:
            t0 = time.perf_counter()
            motion = jd.interblade_motion(phi, H_C_MM, Q_STAR_MM, H_L_MM)
            res = jd.path_response_curves(shape, MU, contacts, mode=mode, motion=motion,
                                          force_n=FORCES_N)
            p = jax.device_get(res.peaks)
            for i, force in enumerate(FORCES_N):
                ok = bool(jd.RESULTS.valid(p.status[i]))
                a = float(p.peak_amplitude_mm[i])
                rows.append(dict(damper=name, ibpa_deg=phi, force_n=force,
                                 status=jd.RESULTS.name_of(p.status[i]),
                                 peak_amplitude_mm=a if ok else None,
                                 peak_frequency_hz=float(p.peak_frequency_hz[i]) if ok else None,
                                 psi_a_mrad=float(p.psi_a_mrad[i]) if ok else None,
                                 peak_reduction=float(free[i] / a) if ok and a > 0 else None))
            print(f"{name:18} phi {phi:5.0f}: " + "  ".join(
                f"F {r['force_n']:g} N A* {r['peak_amplitude_mm']} ({r['status']})"
                for r in rows[-len(FORCES_N):]) + f"  [{time.perf_counter() - t0:.1f} s]",
                flush=True)
    out = dict(machine=machine(), mu=MU, contacts_n_per_mm=[17900.0, 3580.0],
               mode=dict(f0_hz=500.0, k_b_n_per_mm=500.0, eta=0.001, r_mrad_per_mm=1.0),
               kinematics=dict(h_c_mm=H_C_MM, h_l_mm=H_L_MM, q_star_mm=Q_STAR_MM),
               initial="assembly", forces_n=list(FORCES_N), free_peak_mm=[float(v) for v in free],
               rows=rows, wall_time_s=time.perf_counter() - started)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "wedge_response.json").write_text(json.dumps(out, indent=1))
    plot(out)
    return out


def plot(out: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(out["forces_n"]), figsize=(10, 3.8), sharex=True)
    for ax, force in zip(np.atleast_1d(axes), out["forces_n"]):
        for name, style in (("curved-flat 60sym", "o-"), ("wedge 60/60", "s--")):
            pts = [(r["ibpa_deg"], r["peak_reduction"]) for r in out["rows"]
                   if r["damper"] == name and r["force_n"] == force
                   and r["peak_reduction"] is not None]
            if pts:
                ax.plot(*zip(*pts), style, label=name)
        ax.set_title(f"modal force {force:g} N")
        ax.set_xlabel("interblade phase angle (deg)")
        ax.set_xticks(PHIS_DEG)
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("peak reduction A*_free / A*")
    np.atleast_1d(axes)[0].legend()
    fig.tight_layout()
    fig.savefig(RESULTS.parent.parent / "docs" / "wedge_response.png", dpi=120)  # docs/motions.md


if __name__ == "__main__":
    main()
