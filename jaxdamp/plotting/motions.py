"""The damper against the interblade phase angle: damping relative to in-phase and the pads' open
fractions, for several dampers (the paper's curved-flat damper against a wedge)."""

from __future__ import annotations

import numpy as np

VALID = ("ok", "shakedown")
DAMPER_STYLES = ("-", "--", ":", "-.")


def plot_ibpa_claim(curves, title=None):
    """A Figure of 2 rows x one column per mu: k_Im / k_Im(phi = 0) (top) and the fraction of the
    period each pad is open (bottom) against the interblade phase angle phi >= 0 (deg).

    curves: a list of {"damper", "pads", "mu", "amplitude_mrad", "rows"}, each row {"ibpa_deg",
    "status", "k_im_over_in_phase", "open_fraction" (one per pad)} (`benchmarks/ibpa_sweep.py`,
    the study's "platform_claim"). One line style per damper, one colour per amplitude (top) or
    pad (bottom; pads that never open are left out, and a damper none of whose pads opens gets a
    note); phase angles without a valid cycle are marked x at zero."""
    import matplotlib.pyplot as plt

    mus = sorted({c["mu"] for c in curves})
    amplitudes = sorted({c["amplitude_mrad"] for c in curves})
    dampers = list(dict.fromkeys(c["damper"] for c in curves))
    style = {d: DAMPER_STYLES[i % len(DAMPER_STYLES)] for i, d in enumerate(dampers)}
    fig, axes = plt.subplots(2, len(mus), figsize=(4.4 * len(mus), 7), sharex=True,
                             squeeze=False, layout="constrained")
    for j, mu in enumerate(mus):
        never_open = set(dampers)
        for c in (c for c in curves if c["mu"] == mu):
            rows = [r for r in c["rows"] if r["ibpa_deg"] >= 0.0]
            phi = [r["ibpa_deg"] for r in rows]
            ok = [r["status"] in VALID for r in rows]
            ratio = [r["k_im_over_in_phase"] if good and r["k_im_over_in_phase"] is not None
                     else np.nan for r, good in zip(rows, ok)]
            level = amplitudes.index(c["amplitude_mrad"])
            axes[0, j].plot(phi, ratio, style[c["damper"]], marker="o", ms=3, color=f"C{level}",
                            label=f"{c['damper']}, a = {c['amplitude_mrad']:g} mrad")
            bad = [p for p, good in zip(phi, ok) if not good]
            if bad:
                axes[0, j].plot(bad, [0.0] * len(bad), "x", color="k", ms=8)
            for p, name in enumerate(c["pads"]):
                opened = [r["open_fraction"][p] if good else np.nan for r, good in zip(rows, ok)]
                if np.nanmax(opened, initial=0.0) > 0.0:
                    never_open.discard(c["damper"])
                    axes[1, j].plot(phi, opened, style[c["damper"]], marker=".", color=f"C{p + 2}",
                                    alpha=0.45 if level < len(amplitudes) - 1 else 1.0,
                                    label=f"{c['damper']} {name}, a = {c['amplitude_mrad']:g} mrad")
        if never_open:
            axes[1, j].text(0.02, 0.97, "no pad opens: " + ", ".join(sorted(never_open)),
                            transform=axes[1, j].transAxes, va="top", fontsize=8)
        axes[0, j].set_title(f"μ = {mu:g}")
        axes[1, j].set_xlabel("interblade phase angle φ, deg")
        if axes[1, j].get_lines():
            axes[1, j].legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, 0.9),
                              framealpha=0.9)
    axes[0, 0].set_ylabel("k_Im / k_Im(in-phase)")
    axes[1, 0].set_ylabel("fraction of the period a pad is open")
    for ax in axes.ravel():
        ax.grid(True, alpha=0.3)
        ax.set_xticks(range(0, 181, 30))
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(title or "Against the interblade phase angle (x: no valid cycle)")
    return fig


__all__ = ["plot_ibpa_claim"]
