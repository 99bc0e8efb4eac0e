"""The paper's claim, computed: the curved-flat damper (60sym) and a wedge of the same base angles
against the interblade phase angle, from 0 to 180 deg.

For mu 0.3, 0.5, 0.7 and two amplitudes of the left-hand blade's platform rotation (2 and 10
mrad), the steady cycle from assembly on the path of the paper's Fig. 4 kinematics (rotation
centres h_C = 20 mm below D, q* = 100 mm, damper size h_L = 10 mm) at phi = 0, 15, ..., 180 deg
and at -90 deg (the ellipse run the other way): k_Re, k_Im, k_Im / k_Im(phi = 0), the fraction of
the period each pad slips and is open, and the status. The dampers: 60sym (R1 | L1, L2) and the
wedge 60/60 with two flat pads on each flank at +-0.4 h from its midpoint (2b/h = 0.8 on both
flanks, as 60sym's left flank: R1, R2 | L1, L2). 60sym's straight paths (phi = 0, 180) run on
`amplitude_cycle`, everything else on the tract engine (`elliptic_cycle`; a wedge's straight path
as an ellipse of zero width).

Run: python benchmarks/ibpa_sweep.py -> benchmarks/results/ibpa_sweep.json and its figure,
docs/ibpa_sweep_60sym.png (docs/motions.md).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import jax
import numpy as np

from bench_common import machine

RESULTS = Path(__file__).parent / "results"
MUS = (0.3, 0.5, 0.7)
AMPLITUDES_MRAD = (2.0, 10.0)
PHIS_DEG = tuple(float(p) for p in range(0, 181, 15)) + (-90.0,)
H_C_MM, H_L_MM, Q_STAR_MM = 20.0, 10.0, 100.0


WEDGE_BR2 = 0.8  # the wedge's right pad spacing 2b/h_R, as 60sym's left flank's 2b_L/h_L


def cycle(jd, shape, mu, psi, phi, contacts):
    from jaxdamp.amplitude import slip_fraction

    motion = jd.interblade_motion(phi, H_C_MM, Q_STAR_MM, H_L_MM)
    if motion.quadrature is None and shape.br2_over_hr is None:
        c = jd.amplitude_cycle(shape, mu, psi, contacts, initial="assembly", motion=motion)
        fractions, opened = slip_fraction(c), np.zeros(3)
    else:
        c = jd.elliptic_cycle(shape, mu, psi, motion, contacts)
        fractions, opened = np.asarray(c.slip_fraction), np.asarray(c.open_fraction)
    return dict(ibpa_deg=phi, status=jd.RESULTS.name_of(c.status), k_re=float(c.k_re),
                k_im=float(c.k_im), energy_nmm=[float(e) for e in np.asarray(c.energy)],
                slip_fraction=[float(f) for f in fractions],
                open_fraction=[float(f) for f in opened])


def main() -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd

    contacts = jd.Contacts(17900.0, 3580.0)
    curved_flat = jd.family_shape("60sym")
    dampers = {"60sym": curved_flat, "wedge": curved_flat._replace(br_over_hr=0.0,
                                                                   br2_over_hr=WEDGE_BR2)}
    curves, started = [], time.perf_counter()
    for damper, shape in dampers.items():
        for mu in MUS:
            for psi in AMPLITUDES_MRAD:
                rows = [cycle(jd, shape, mu, psi, phi, contacts) for phi in PHIS_DEG]
                ref = rows[0]["k_im"]
                for r in rows:
                    r["k_im_over_in_phase"] = r["k_im"] / ref if ref > 0 else None
                curves.append(dict(damper=damper, pads=list(jd.blocks.pad_names(shape)), mu=mu,
                                   amplitude_mrad=psi, rows=rows))
    doc = dict(machine=machine(), seconds=time.perf_counter() - started,
               dampers={k: {"theta_l": float(v.theta_l), "theta_r": float(v.theta_r),
                            "br_over_hr": None if k == "wedge" else float(v.br_over_hr),
                            "br2_over_hr": v.br2_over_hr, "bl2_over_hl": float(v.bl2_over_hl)}
                        for k, v in dampers.items()},
               kn_n_per_mm=17900.0, kt_n_per_mm=3580.0, h_c_mm=H_C_MM, h_l_mm=H_L_MM,
               q_star_mm=Q_STAR_MM, initial="assembly", curves=curves)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "ibpa_sweep.json").write_text(json.dumps(doc, indent=1))
    plot(doc)
    return doc


def plot(doc: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from jaxdamp.plotting import plot_ibpa_claim

    fig = plot_ibpa_claim(doc["curves"], title=(
        "60sym (curved-flat, solid) and the 60/60 wedge (dashed) against the interblade phase "
        f"angle: h_C = {H_C_MM:g} mm, h_L = {H_L_MM:g} mm, q* = {Q_STAR_MM:g} mm, from assembly "
        "(x: no valid cycle)"))
    fig.savefig(RESULTS.parent.parent / "docs" / "ibpa_sweep_60sym.png", dpi=110)


if __name__ == "__main__":
    d = main()
    print(f"{sum(len(c['rows']) for c in d['curves'])} cycles in {d['seconds']:.1f} s")
    for c in d["curves"]:
        print(c["damper"], c["mu"], c["amplitude_mrad"], " ".join(
            f"{r['ibpa_deg']:g}:{r['k_im_over_in_phase'] if r['k_im_over_in_phase'] is None else round(r['k_im_over_in_phase'], 2)}/{r['status'][:2]}"
            for r in c["rows"]))
