"""Figure: k_Re and k_Im against psi_a from the exact steady cycles (jaxdamp.amplitude), from both
named initial states, with the band over all admissible initial states shaded and the paper's
linear microslip interpolation dashed. matplotlib is imported here; no backend is chosen."""

from __future__ import annotations

import numpy as np


def amplitude_stiffness_data(shape, mu, contacts=None, load=None, psi_a_mrad=None, band_points=0,
                             band_kwargs=None) -> dict:
    """The numbers the figure draws (numpy arrays; k in N mm/mrad, psi in mrad): exact k from
    gross_slip and assembly on psi_a_mrad (default: 96 points up to 2.5 psi_BC), the paper's
    interpolation, psi_fs and psi_BC, and the band at `band_points` amplitudes (0: none)."""
    import jaxdamp as jd
    from jaxdamp.sequence import amplitude_curves
    from jaxdamp.band import amplitude_band
    from jaxdamp.status import RESULTS

    contacts = jd.Contacts() if contacts is None else contacts
    load = jd.LoadCase() if load is None else load
    bc = jd.base_cycle(shape, mu, contacts, load)
    nums = jd.five_numbers(bc)
    psi_bc = float(nums.psi_bc)
    if psi_a_mrad is None:
        psi_a_mrad = np.linspace(0.02, 2.5, 96) * max(psi_bc, 1e-3)
    psi = np.asarray(psi_a_mrad, float)
    out = {"psi_a_mrad": psi, "psi_fs": float(nums.psi_fs), "psi_bc": psi_bc}
    for initial in ("gross_slip", "assembly"):
        cv = amplitude_curves(shape, mu, psi, contacts, load, initial=initial)
        ok = np.asarray(RESULTS.valid(cv.status))[0]
        out[initial] = (np.where(ok, np.asarray(cv.k_re)[0], np.nan),
                        np.where(ok, np.asarray(cv.k_im)[0], np.nan))
    k_re, k_im = jd.complex_stiffness(bc, psi, method="interpolated")
    out["interpolated"] = (np.asarray(k_re), np.asarray(k_im))
    if band_points:
        grid = np.linspace(psi[0], psi[-1], band_points)
        bands = [amplitude_band(shape, mu, float(p), contacts, load, **(band_kwargs or {}))
                 for p in grid]
        # NaN (a gap in the shading) where no history gives a valid cycle
        out["band"] = (grid, np.array([b.bounds if b.status == RESULTS.ok else np.full(4, np.nan)
                                       for b in bands]))
    return out


def plot_amplitude_stiffness(shape, mu, contacts=None, load=None, psi_a_mrad=None, band_points=9,
                             ax=None, data=None, title=None, band_kwargs=None):
    """Two panels, k_Re and k_Im against psi_a: exact from gross_slip (solid) and assembly
    (dash-dot), the band (shaded), the paper's interpolation (dashed), psi_fs and psi_BC (dotted
    verticals). Returns the figure. `data` from `amplitude_stiffness_data` skips the computation."""
    import matplotlib.pyplot as plt

    d = data if data is not None else amplitude_stiffness_data(
        shape, mu, contacts, load, psi_a_mrad, band_points, band_kwargs)
    if ax is None:
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    else:
        fig = np.atleast_1d(ax)[0].figure
    ax = np.atleast_1d(ax)
    psi = d["psi_a_mrad"]
    for j, (axis, label) in enumerate(zip(ax, ("k_Re", "k_Im"))):
        if "band" in d:
            grid, b = d["band"]
            axis.fill_between(grid, b[:, 2 * j], b[:, 2 * j + 1], color="0.8",
                              label="band (all admissible states)")
        axis.plot(psi, d["gross_slip"][j], "C0-", label="exact, from gross slip")
        axis.plot(psi, d["assembly"][j], "C1-.", label="exact, from assembly")
        axis.plot(psi, d["interpolated"][j], "k--", lw=1, label="paper's interpolation")
        # Labels inside the axes on an opaque box (the dotted line passes behind), each at the
        # first height clear of every curve at its psi (k_Re is highest at psi_fs: a label at the
        # top sat on it), and apart from each other when psi_fs and psi_BC coincide (a mechanism
        # that goes straight to gross slip).
        axis.autoscale_view()
        taken = []
        for x, name in ((d["psi_fs"], "ψ_fs"), (d["psi_bc"], "ψ_BC")):
            axis.axvline(x, color="0.5", ls=":", lw=1)
            y = _clear_height(axis, psi, [d[k][j] for k in ("gross_slip", "assembly", "interpolated")],
                              x, taken)
            taken.append((x, y))
            axis.annotate(name, (x, y), xycoords=("data", "axes fraction"), ha="center",
                          va="center", fontsize=8, zorder=5,
                          bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none"))
        axis.set_xlabel("ψ_a (mrad)")
        axis.set_ylabel(f"{label} (N mm/mrad)")
        axis.grid(alpha=0.3)
    ax[-1].legend(fontsize=8, loc="best")
    if title:
        fig.suptitle(title)
    return fig


# Heights (axes fractions) tried for the psi_fs / psi_BC labels, top first; a label needs CLEARANCE
# (axes fraction) from every curve at its psi and from the other label's height where both are close.
LABEL_HEIGHTS = (0.95, 0.84, 0.5, 0.16, 0.05, 0.3, 0.7)
CLEARANCE = 0.07


def _clear_height(axis, psi, curves, x, taken) -> float:
    """The first LABEL_HEIGHTS entry clear of the curves (at x) and of labels already placed near x."""
    y0, y1 = axis.get_ylim()
    (x0, x1) = axis.get_xlim()
    at = [(np.interp(x, psi, c) - y0) / (y1 - y0) for c in curves if np.isfinite(np.interp(x, psi, c))]
    near = [h for xt, h in taken if abs(xt - x) < 0.08 * (x1 - x0)]
    for h in LABEL_HEIGHTS:
        if all(abs(h - a) > CLEARANCE for a in at) and all(abs(h - t) > CLEARANCE for t in near):
            return h
    return LABEL_HEIGHTS[len(taken) % len(LABEL_HEIGHTS)]


__all__ = ["amplitude_stiffness_data", "plot_amplitude_stiffness"]
