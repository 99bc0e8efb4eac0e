"""The robust designs' magnification A*/F against the force, the uncertainty band shaded."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_robust", "plot_row"]


def plot_robust(designs, ax=None, limit_mm_per_n=None):
    """A*/F (mm/N) against the modal force (N) of each `CertifiedDesign`: the band over the dense
    uncertainty grid shaded, its upper edge drawn, the Monte Carlo worst marked. Returns the axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.6))
    for i, d in enumerate(designs):
        if not d.feasible:
            continue
        c = f"C{i}"
        f = np.asarray(d.force_n)
        lo, hi = (np.asarray(b) for b in d.band_mm_per_n)
        ax.fill_between(f, lo, hi, color=c, alpha=0.18, lw=0)
        ax.plot(f, hi, color=c, lw=1.8,
                label=f"{d.name}: worst {d.worst_dense:.3f} (grid), {d.worst_mc:.3f} (MC) mm/N")
    if limit_mm_per_n is not None:
        ax.axhline(limit_mm_per_n, color="k", ls="--", lw=1, label="peak limit")
    ax.set_xscale("log")
    ax.set_xlabel("modal force F (N)")
    ax.set_ylabel("dynamic magnification A*/F (mm/N)")
    ax.set_title("band over mu, F_D, kn, kt (shaded); line: its upper edge")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return ax


def _curve(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], float)


def plot_row(designs, ax=None):
    """Worst A*/F (mm/N) per engine order of each `RowCertified`: the history band's upper edge
    (solid), gross slip (dashed) and assembly (dotted) underneath. Returns the axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.6))
    for i, d in enumerate(designs):
        c = f"C{i}"
        e = np.asarray(d.engine_order)
        band = _curve(d.worst_band)
        label = (f"{d.name}: worst {d.worst:.3f} mm/N at EO {d.worst_engine_order}" if d.feasible
                 else f"{d.name}: not certified ({d.reason})")
        ax.plot(e, band, "o-", color=c, lw=1.8, ms=4, label=label)
        for h, ls in (("gross_slip", "--"), ("assembly", ":")):
            ax.plot(e, _curve(d.worst_by_history[h]), ls, color=c, lw=1.0)
    ax.set_xlabel("engine order")
    ax.set_ylabel("worst A*/F over the uncertainty grid (mm/N)")
    ax.set_title("row: band of histories (solid), gross slip (dashed), assembly (dotted)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax
