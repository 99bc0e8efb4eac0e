"""The paper's damper (60sym, curved-flat) on the out-of-phase path against the in-phase one.

For mu 0.3, 0.5, 0.7 and the blades' rotation centre h_C = 20 and 60 mm below D (damper size
h_L = 10 mm, q* = 100 mm), k_Re and k_Im of the steady cycle from assembly against the amplitude
of the left-hand blade's platform rotation, by the direct method on the straight out-of-phase
path (jaxdamp.interblade_motion(180, ...)), with the in-phase curve (phi = 0) beside it. Each
curve's status per amplitude is kept (a pad that opens is liftoff: reported, not hidden).

Run: python benchmarks/out_of_phase.py -> benchmarks/results/out_of_phase.json and its figure,
docs/out_of_phase_60sym.png (docs/motions.md).
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
MUS = (0.3, 0.5, 0.7)
H_C_MM = (20.0, 60.0)
H_L_MM = 10.0
AMPLITUDES_MRAD = np.geomspace(0.2, 40.0, 25)


def main() -> dict:
    jax.config.update("jax_enable_x64", True)
    import jaxdamp as jd

    shape, contacts = jd.family_shape("60sym"), jd.Contacts(17900.0, 3580.0)
    paths = {"in_phase": None}
    paths.update({f"out_of_phase_hc{h:g}": jd.interblade_motion(180, h, 100.0, H_L_MM) for h in H_C_MM})
    curves, started = [], time.perf_counter()
    for mu in MUS:
        for name, motion in paths.items():
            rows = []
            for psi in AMPLITUDES_MRAD:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", jd.SmallRotationWarning)
                    ac = jd.amplitude_cycle(shape, mu, float(psi), contacts, initial="assembly",
                                            motion=motion)
                rows.append(dict(psi_a_mrad=float(psi), k_re=float(ac.k_re), k_im=float(ac.k_im),
                                 status=jd.RESULTS.name_of(ac.status),
                                 energy_nmm=[float(e) for e in np.asarray(ac.energy)]))
            curves.append(dict(mu=mu, path=name, direction=None if motion is None else
                               [float(v) for v in motion.direction], rows=rows))
    doc = dict(machine=machine(), seconds=time.perf_counter() - started, shape="60sym",
               kn_n_per_mm=17900.0, kt_n_per_mm=3580.0, h_l_mm=H_L_MM, q_star_mm=100.0,
               initial="assembly", curves=curves)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "out_of_phase.json").write_text(json.dumps(doc, indent=1))
    plot(doc)
    return doc


def plot(doc: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(MUS), figsize=(12, 6.5), sharex=True, constrained_layout=True)
    styles = {"in_phase": dict(color="k", ls="-"), "out_of_phase_hc20": dict(color="C0", ls="--"),
              "out_of_phase_hc60": dict(color="C3", ls="-.")}
    labels = {"in_phase": "in-phase (phi = 0)", "out_of_phase_hc20": "out-of-phase, h_C = 20 mm",
              "out_of_phase_hc60": "out-of-phase, h_C = 60 mm"}
    for j, mu in enumerate(MUS):
        for c in (c for c in doc["curves"] if c["mu"] == mu):
            ok = [r for r in c["rows"] if r["status"] in ("ok", "shakedown")]
            psi = [r["psi_a_mrad"] for r in ok]
            for i, key in enumerate(("k_re", "k_im")):
                axes[i, j].plot(psi, [r[key] for r in ok], label=labels[c["path"]], **styles[c["path"]])
        axes[0, j].set_title(f"60sym, mu = {mu:g}, from assembly")
        axes[1, j].set_xlabel("amplitude of the left blade's platform rotation, mrad")
    for i, key in enumerate(("k_Re", "k_Im")):
        for ax in axes[i]:
            ax.set_xscale("log")
            ax.grid(True, alpha=0.3)
        axes[i, 0].set_ylabel(f"{key}, N mm/mrad")
    axes[0, 0].legend(fontsize=8)
    fig.savefig(RESULTS.parent.parent / "docs" / "out_of_phase_60sym.png", dpi=110)  # docs/motions.md


if __name__ == "__main__":
    d = main()
    print(f"{len(d['curves'])} curves in {d['seconds']:.1f} s")
