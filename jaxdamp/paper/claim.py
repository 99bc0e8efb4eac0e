"""The paper's claim on platform motions, computed: the curved-flat damper against a wedge of the
same base angles over the interblade phase angle (the study's data and its report section).

The paper (its ref [16], Appendix 2) argues without numbers that under out-of-phase vibration, or
in-phase vibration with a non-zero interblade phase angle, a wedge damper suffers edge contacts and
liftoff while the asymmetric-contact (curved-flat) damper is self-aligning.
"""

from __future__ import annotations

import numpy as np

from ..ellipse import interblade_sweep
from ..geometry import family_shape, pad_names
from ..status import RESULTS

# The report names a shape in every heading (its contents list reads as a list of shapes' results).
PLATFORM_CLAIM_SECTION = "60sym (curved-flat) against its wedge on every platform motion"

CLAIM_PHIS_DEG = (0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0)
CLAIM_AMPLITUDES_MRAD = (2.0, 10.0)
CLAIM_H_C_MM, CLAIM_H_L_MM = 20.0, 10.0  # blades' rotation centre below D; the damper's size
CLAIM_WEDGE_BR2 = 0.8  # the wedge's right pad spacing 2b/h_R, as 60sym's left flank's 2b_L/h_L


def platform_claim(mus, contacts, load, progress=None, runner=None) -> dict:
    """The paper's claim (its ref [16], Appendix 2: under a non-zero interblade phase angle a wedge
    suffers edge contacts and liftoff, the curved-flat damper stays seated), computed: 60sym and
    the wedge of the same base angles (R1, R2 | L1, L2, 2b/h = 0.8 on both flanks) on the paper's
    Fig. 4 kinematics at CLAIM_PHIS_DEG, both amplitudes and every mu, from assembly (one
    `interblade_sweep` program per damper). Rows carry the status, k_Im, k_Im / k_Im(phi = 0) and
    the open and slip fraction per pad. runner: as `interblade_sweep`'s."""
    curved = family_shape("60sym")
    dampers = {"60sym": curved,
               "wedge": curved._replace(br_over_hr=0.0, br2_over_hr=CLAIM_WEDGE_BR2)}
    curves = []
    for name, shape in dampers.items():
        for mu in mus:
            for a in CLAIM_AMPLITUDES_MRAD:
                r = interblade_sweep(shape, float(mu), a, CLAIM_PHIS_DEG, CLAIM_H_C_MM,
                                     CLAIM_H_L_MM, contacts, load, runner=runner)
                status = [RESULTS.name_of(v) for v in np.asarray(r.status)]
                k_im = np.asarray(r.k_im)
                ref = k_im[0] if status[0] == "ok" and k_im[0] > 0.0 else None
                rows = [{"ibpa_deg": phi, "status": st, "k_im": float(k),
                         "k_im_over_in_phase": None if ref is None or st not in ("ok", "shakedown")
                         else float(k / ref),
                         "open_fraction": [float(v) for v in o],
                         "slip_fraction": [float(v) for v in f]}
                        for phi, st, k, o, f in zip(CLAIM_PHIS_DEG, status, k_im,
                                                    np.asarray(r.open_fraction),
                                                    np.asarray(r.slip_fraction))]
                curves.append({"damper": name, "pads": list(pad_names(shape)), "mu": float(mu),
                               "amplitude_mrad": a, "rows": rows})
        if progress is not None:
            progress.update(1)
    return {"h_c_mm": CLAIM_H_C_MM, "h_l_mm": CLAIM_H_L_MM, "initial": "assembly",
            "wedge_br2_over_hr": CLAIM_WEDGE_BR2, "curves": curves}


def claim_section(doc, claim, figures, fmt):
    """The paper's claim on interblade phase angles (its ref [16]), computed: per damper, mu and
    amplitude, k_Im / k_Im(in-phase) and the largest open fraction of any pad at each phi. fmt:
    the report's number format (`report.fmt`, passed in: report imports this module)."""
    if not claim:
        return
    doc.h(1, PLATFORM_CLAIM_SECTION)
    doc.p("The paper (its ref [16], Appendix 2) argues without numbers that under out-of-phase "
          "vibration, or in-phase vibration with a non-zero interblade phase angle, a wedge damper "
          "suffers edge contacts and liftoff while the asymmetric-contact (curved-flat) damper "
          "stays seated. Computed here on the paper's Fig. 4 kinematics (each platform turns about "
          f"its blade's centre, h_C = {claim['h_c_mm']:g} mm below D; damper size h_L = "
          f"{claim['h_l_mm']:g} mm; amplitude a of the left-hand blade's platform rotation; from "
          "assembly) for 60sym and the wedge of the same base angles (two flat pads on each "
          f"flank, 2b/h = {claim['wedge_br2_over_hr']:g}). Each cell: k_Im / k_Im(φ = 0) and, "
          "after the slash, the largest fraction of the period any pad is open (a status where "
          "there is no valid cycle).")
    phis = [r["ibpa_deg"] for r in claim["curves"][0]["rows"]]
    rows = []
    for c in claim["curves"]:
        cells = []
        for r in c["rows"]:
            if r["status"] not in ("ok", "shakedown"):
                cells.append(r["status"])
                continue
            cells.append(f"{fmt(r['k_im_over_in_phase'], 2)} / {fmt(max(r['open_fraction']), 2)}")
        rows.append([c["damper"], f"{c['mu']:g}", f"{c['amplitude_mrad']:g}"] + cells)
    doc.table(["damper", "μ", "a (mrad)"] + [f"φ = {p:g}°" for p in phis], rows)
    lines = []
    for damper in dict.fromkeys(c["damper"] for c in claim["curves"]):
        opened = [(max(r["open_fraction"]), c["mu"], c["amplitude_mrad"], r["ibpa_deg"])
                  for c in claim["curves"] if c["damper"] == damper for r in c["rows"]
                  if r["status"] in ("ok", "shakedown")]
        failed = sum(r["status"] not in ("ok", "shakedown") for c in claim["curves"]
                     if c["damper"] == damper for r in c["rows"])
        worst = max(opened) if opened else None
        if worst is None or worst[0] == 0.0:
            lines.append(f"{damper}: no pad opens at any phase angle, amplitude or μ"
                         + (f" ({failed} without a valid cycle)" if failed else "") + ".")
        else:
            share = sum(o[0] > 0.0 for o in opened)
            lines.append(f"{damper}: a pad opens in {share} of {len(opened)} valid cycles, for up "
                         f"to {fmt(100 * worst[0], 2)} % of the period (μ = {worst[1]:g}, "
                         f"a = {worst[2]:g} mrad, φ = {worst[3]:g}°)"
                         + (f"; {failed} without a valid cycle" if failed else "") + ".")
    doc.items(lines)
    for f in figures:
        if f.get("section") == PLATFORM_CLAIM_SECTION:
            doc.figure(f["file"], f["caption"])


__all__ = ["PLATFORM_CLAIM_SECTION", "CLAIM_PHIS_DEG", "CLAIM_AMPLITUDES_MRAD", "CLAIM_H_C_MM",
           "CLAIM_H_L_MM", "CLAIM_WEDGE_BR2", "platform_claim", "claim_section"]
