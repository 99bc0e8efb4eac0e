"""The paper's damper (60sym, curved-flat) against the interblade phase angle, from 0 to 180 deg.

For mu 0.3, 0.5, 0.7 and two amplitudes of the left-hand blade's platform rotation (2 and 10
mrad), the steady cycle from assembly on the path of the paper's Fig. 4 kinematics (rotation
centres h_C = 20 mm below D, q* = 100 mm, damper size h_L = 10 mm) at phi = 0, 15, ..., 180 deg
and at -90 deg (the ellipse run the other way): k_Re, k_Im, k_Im / k_Im(phi = 0), the fraction of
the period each pad slips, and the status (a pad that opens is `liftoff`: reported). phi = 0 and
180 are straight paths (`amplitude_cycle`), the others ellipses (`elliptic_cycle`).

Run: python benchmarks/ibpa_sweep.py -> benchmarks/results/ibpa_sweep.{json,png} and the figure as
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


def cycle(jd, shape, mu, psi, phi, contacts):
    from jaxdamp.amplitude import slip_fraction

    motion = jd.interblade_motion(phi, H_C_MM, Q_STAR_MM, H_L_MM)
    if motion.quadrature is None:
        c = jd.amplitude_cycle(shape, mu, psi, contacts, initial="assembly", motion=motion)
        fractions = slip_fraction(c)
    else:
        c = jd.elliptic_cycle(shape, mu, psi, motion, contacts)
        fractions = np.asarray(c.slip_fraction)
    return dict(ibpa_deg=phi, status=jd.RESULTS.name_of(c.status), k_re=float(c.k_re),
                k_im=float(c.k_im), energy_nmm=[float(e) for e in np.asarray(c.energy)],
                slip_fraction=[float(f) for f in fractions])


def main() -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd

    shape, contacts = jd.family_shape("60sym"), jd.Contacts(17900.0, 3580.0)
    curves, started = [], time.perf_counter()
    for mu in MUS:
        for psi in AMPLITUDES_MRAD:
            rows = [cycle(jd, shape, mu, psi, phi, contacts) for phi in PHIS_DEG]
            ref = rows[0]["k_im"]
            for r in rows:
                r["k_im_over_in_phase"] = r["k_im"] / ref if ref > 0 else None
            curves.append(dict(mu=mu, amplitude_mrad=psi, rows=rows))
    doc = dict(machine=machine(), seconds=time.perf_counter() - started, shape="60sym",
               kn_n_per_mm=17900.0, kt_n_per_mm=3580.0, h_c_mm=H_C_MM, h_l_mm=H_L_MM,
               q_star_mm=Q_STAR_MM, initial="assembly", pads=list(jd.CONTACT_NAMES), curves=curves)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "ibpa_sweep.json").write_text(json.dumps(doc, indent=1))
    plot(doc)
    return doc


def plot(doc: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(MUS), figsize=(12, 6.5), sharex=True, constrained_layout=True)
    for j, mu in enumerate(MUS):
        for c in (c for c in doc["curves"] if c["mu"] == mu):
            rows = [r for r in c["rows"] if r["ibpa_deg"] >= 0.0]
            phi = [r["ibpa_deg"] for r in rows]
            ratio = [np.nan if r["k_im_over_in_phase"] is None or r["status"] not in ("ok", "shakedown")
                     else r["k_im_over_in_phase"] for r in rows]
            axes[0, j].plot(phi, ratio, marker="o", ms=3, label=f"a = {c['amplitude_mrad']:g} mrad")
            for p, name in enumerate(doc["pads"]):
                axes[1, j].plot(phi, [r["slip_fraction"][p] for r in rows], marker=".",
                                ls=("-", "--")[AMPLITUDES_MRAD.index(c["amplitude_mrad"])],
                                color=f"C{p + 2}",
                                label=f"{name}, a = {c['amplitude_mrad']:g} mrad")
        axes[0, j].set_title(f"mu = {mu:g}")
        axes[1, j].set_xlabel("interblade phase angle, deg")
    axes[0, 0].set_ylabel("k_Im / k_Im(in-phase)")
    axes[1, 0].set_ylabel("fraction of the period slipping")
    for ax in axes.ravel():
        ax.grid(True, alpha=0.3)
        ax.set_xticks(range(0, 181, 30))
    axes[0, 0].legend(fontsize=8)
    axes[1, 2].legend(fontsize=7, ncol=2, loc="upper right", framealpha=0.9)
    fig.suptitle(f"60sym (curved-flat) against the interblade phase angle: h_C = {H_C_MM:g} mm, "
                 f"h_L = {H_L_MM:g} mm, q* = {Q_STAR_MM:g} mm, from assembly")
    fig.savefig(RESULTS / "ibpa_sweep.png", dpi=110)
    fig.savefig(RESULTS.parent.parent / "docs" / "ibpa_sweep_60sym.png", dpi=110)


if __name__ == "__main__":
    d = main()
    print(f"{sum(len(c['rows']) for c in d['curves'])} cycles in {d['seconds']:.1f} s")
    for c in d["curves"]:
        print(c["mu"], c["amplitude_mrad"], " ".join(
            f"{r['ibpa_deg']:g}:{r['k_im_over_in_phase'] if r['k_im_over_in_phase'] is None else round(r['k_im_over_in_phase'], 2)}/{r['status'][:2]}"
            for r in c["rows"]))
