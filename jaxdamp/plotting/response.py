"""Figures of the blade forced response: FRFs with and without the damper, the designer's diagram,
and the single-harmonic error against H = 3, 5 and time integration. Each function takes numbers
already computed (numpy arrays / result tuples) and returns a matplotlib Figure; no backend is
chosen here."""

from __future__ import annotations

import numpy as np


def _frf_line(ax, curve, **kw):
    """One FRF as a single polyline: the low branch up to the peak, then the high branch back."""
    a = np.asarray(curve.amplitude_mm)
    lo, hi = np.asarray(curve.has_low), np.asarray(curve.has_high)
    f = np.concatenate([np.asarray(curve.f_low_hz)[lo], np.asarray(curve.f_high_hz)[hi][::-1]])
    amp = np.concatenate([a[lo], a[hi][::-1]])
    return ax.plot(f, amp, **kw)


def _finish(fig, ax, xlabel, ylabel, title):
    """Labels, a log grid, the legend and the title of a one-panel response figure."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    return fig


def frf_figure(curves, forces_n, free_curves=None, stuck_curves=None, *, title=None):
    """FRFs (first-harmonic tip amplitude, mm, against frequency, Hz) at several forces: with the
    damper (solid), without it (free, dashed) and with it stuck (dotted), log amplitude axis.

    curves, free_curves, stuck_curves: lists of `response.FRF` (one per force)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, (c, force) in enumerate(zip(curves, forces_n)):
        col = colors[i % len(colors)]
        _frf_line(ax, c, color=col, lw=1.8, label=f"F = {force:g} N, damper")
        if free_curves is not None:
            _frf_line(ax, free_curves[i], color=col, lw=0.9, ls="--",
                      label="free (no damper)" if i == 0 else None)
        if stuck_curves is not None:
            _frf_line(ax, stuck_curves[i], color=col, lw=0.9, ls=":",
                      label="damper stuck" if i == 0 else None)
    ax.set_yscale("log")
    return _finish(fig, ax, "frequency, Hz", "tip amplitude A (first harmonic), mm",
                   title or "Forced response, amplitude-layered (first harmonic)")


def _index(curve, i):
    return type(curve)(*(np.asarray(v)[i] for v in curve))


def response_figure(res, forces_n, *, title=None):
    """FRFs of a `response.ResponseCurves` (tip amplitude, mm, log, against frequency, Hz): one
    colour per force; with the damper solid, free (no damper) dashed, damper stuck dash-dotted,
    each limit across its own resonance; the peak reduction A*_free / A*_damped written at each
    damped peak. The line styles are explained once, in a legend of their own."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, ax = plt.subplots(figsize=(8, 5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    peaks = res.peaks
    for i, force in enumerate(forces_n):
        col = colors[i % len(colors)]
        valid = int(np.asarray(peaks.status)[i]) in (0, 5)  # RESULTS.ok, shakedown
        _frf_line(ax, _index(res.free, i), color=col, lw=1.1, ls="--", alpha=0.8)
        _frf_line(ax, _index(res.stuck, i), color=col, lw=1.1, ls="-.", alpha=0.8)
        if not valid:
            continue
        _frf_line(ax, _index(res.damper, i), color=col, lw=2.0)
        a_peak = float(np.asarray(peaks.peak_amplitude_mm)[i])
        f_peak = float(np.asarray(peaks.peak_frequency_hz)[i])
        a_free = float(np.max(np.asarray(res.free.amplitude_mm)[i]))
        ax.plot([f_peak], [a_peak], "o", color=col, ms=4)
        ax.annotate(f"A*free/A* = {a_free / a_peak:.3g}", (f_peak, a_peak), xytext=(6, -12),
                    textcoords="offset points", fontsize=8, color=col)
    ax.set_yscale("log")
    forces_legend = ax.legend([Line2D([], [], color=colors[i % len(colors)], lw=2.0)
                               for i in range(len(forces_n))],
                              [f"F = {f:g} N" for f in forces_n], fontsize=8, loc="upper left")
    ax.add_artist(forces_legend)
    ax.legend([Line2D([], [], color="k", lw=2.0), Line2D([], [], color="k", lw=1.1, ls="--"),
               Line2D([], [], color="k", lw=1.1, ls="-.")],
              ["with the damper", "free (no damper)", "damper stuck"], fontsize=8,
              loc="upper right")
    ax.set_xlabel("frequency, Hz")
    ax.set_ylabel("tip amplitude A (first harmonic), mm")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title(title or "Forced response, amplitude-layered (first harmonic)")
    fig.tight_layout()
    return fig


def designer_diagram_figure(dd, *, title=None):
    """The designer's diagram (`response.DesignerDiagram`): peak A* against F (log-log) and
    against F_D at fixed F, each with the mu band, the curve per mu, and the free/stuck limits."""
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, x, per_mu, band, free, stuck, xlabel in (
            (a1, dd.force_n, dd.peak_vs_force_mm, dd.band_force_mm, dd.free_vs_force_mm,
             dd.stuck_vs_force_mm, "modal force F, N"),
            (a2, dd.fd_n, dd.peak_vs_fd_mm, dd.band_fd_mm, dd.free_vs_fd_mm, dd.stuck_vs_fd_mm,
             "damper load F_D, N")):
        ax.fill_between(x, band[0], band[1], color="C0", alpha=0.25,
                        label=f"mu {dd.mu.min():g} ... {dd.mu.max():g}")
        for m, row in zip(dd.mu, per_mu):
            ax.plot(x, row, color="C0", lw=0.7, alpha=0.7)
        ax.plot(x, free, "k--", lw=1.2, label="free and stuck limits (F / eta k_b)")
        ax.plot(x, stuck, "k:", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("peak tip amplitude A*, mm")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    a1.set_title("peak response against excitation")
    a2.set_title(f"peak response against F_D at F = {dd.force_at_fd_n:g} N")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def harmonic_error_figure(forces_n, single, references, *, title=None):
    """Relative error of the single-harmonic peak, (A_1 - A_ref) / A_ref, against each reference.

    single: (n_force,) H = 1 peak amplitudes (mm); references: dict label -> (n_force,) peak
    amplitudes (mm) of H = 3, H = 5, time integration, ... (NaN where not computed)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    single = np.asarray(single, float)
    for i, (label, ref) in enumerate(references.items()):
        ref = np.asarray(ref, float)
        err = np.abs(single - ref) / ref
        ax.plot(forces_n, err, "o-", color=f"C{i}", label=f"|H=1 - {label}| / {label}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    return _finish(fig, ax, "modal force F, N", "relative error of the single-harmonic peak",
                   title or "Where one harmonic is not enough")




def row_figure(row, *, band=None, title=None):
    """The blade row at a glance (`jaxdamp.row_response`): peak tip amplitude (mm, log axis)
    against nodal diameter (left) and against engine order (right), with the damper (solid, one
    line per force) and without it (dashed), the worst engine order of each force circled.
    band: a `jaxdamp.row_band` of the same row, shaded between its lowest and highest peak.
    Points whose status is not valid are left out."""
    import matplotlib.pyplot as plt

    from ..status import RESULTS

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    eo = np.asarray(row.engine_order)
    nd = np.asarray(row.nodal_diameter)
    amp = np.asarray(row.peaks.peak_amplitude_mm)
    valid = np.asarray(RESULTS.valid(row.status))
    free = np.asarray(row.free_peak_mm)
    for ax, x, label in ((axes[0], nd, "nodal diameter"), (axes[1], eo, "engine order")):
        order = np.argsort(x, kind="stable")
        for j, force in enumerate(np.asarray(row.force_n)):
            c = colors[j % len(colors)]
            ok = order[valid[order, j]]
            ax.plot(x[ok], amp[ok, j], "o-", color=c, ms=4, label=f"F = {force:g} N, damper")
            ax.plot(x[order], free[order, j], "--", color=c, lw=1, alpha=0.7,
                    label=f"F = {force:g} N, no damper")
            w = int(np.asarray(row.worst)[j])
            if w >= 0:
                ax.plot(x[w], amp[w, j], "o", ms=11, mfc="none", mec=c)
            if band is not None:
                held = order[np.asarray(RESULTS.valid(band.status[order, j]))]
                ax.fill_between(x[held], band.peak_min_mm[held, j], band.peak_max_mm[held, j],
                                color=c, alpha=0.18, lw=0,
                                label=f"F = {force:g} N, every contact history")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("peak tip amplitude A*, mm")
    axes[1].legend(fontsize=7, loc="best")
    fig.suptitle(title or f"Peak response across the row ({row.initial} history"
                 + ("; shaded: the band over every history" if band is not None else "")
                 + "; circled: the worst engine order)", fontsize=10)
    fig.tight_layout()
    return fig


def row_diagram_figure(dd, *, title=None):
    """The row's designer's diagram (`jaxdamp.row_diagram`): the worst A*/F over the engine
    orders against the force (left) and against F_D over its nominal value at one force (right),
    each point labelled with its engine order; points beyond the small-rotation model (status
    large_rotation) crossed, points without a valid peak left out."""
    import matplotlib.pyplot as plt

    from ..status import RESULTS

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, x, worst, orders, status, xlabel in (
            (axes[0], dd.force_n, dd.worst_vs_force_mm_per_n, dd.engine_order_vs_force,
             dd.status_vs_force, "force per blade F, N"),
            (axes[1], dd.fd_factor, dd.worst_vs_fd_mm_per_n, dd.engine_order_vs_fd,
             dd.status_vs_fd, "F_D / F_D,nominal (the damper's mass at the design speed)")):
        x, worst, orders = np.asarray(x), np.asarray(worst), np.asarray(orders)
        beyond = np.asarray(status) == RESULTS.large_rotation
        ax.plot(x, worst, "o-", ms=4, color="C0", label="worst over the row, within the model")
        ax.plot(x[beyond], worst[beyond], "x", ms=8, color="C3",
                label="a peak of the row turns the platforms beyond 50 mrad")
        for xi, w, e in zip(x, worst, orders):
            if e >= 0 and np.isfinite(w):
                ax.annotate(str(int(e)), (xi, w), textcoords="offset points", xytext=(0, 5),
                            fontsize=7, ha="center")
        ax.set_xscale("log")
        ax.set_xlabel(xlabel)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("worst A*/F over the row, mm/N (label: engine order)")
    axes[0].legend(fontsize=8)
    axes[1].axvline(1.0, color="0.6", lw=0.8)
    axes[1].set_title(f"at F = {dd.force_at_fd_n:g} N", fontsize=9)
    fig.suptitle(title or "The row's designer's diagram", fontsize=10)
    fig.tight_layout()
    return fig


__all__ = ["frf_figure", "response_figure", "designer_diagram_figure", "harmonic_error_figure",
           "row_figure", "row_diagram_figure"]
