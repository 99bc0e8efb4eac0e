"""Figures in the paper's spirit (matplotlib). Every function returns its Figure.

- `plot_equilibrium_tracks`: force Base-Cycles in the force polygon with F_D = 1 (Fig. 10b).
- `plot_moment_cycles`: moment Base-Cycles (Fig. 13).
- `plot_stretched_cycles`: stretched cycles with their first-harmonic ellipses (Fig. 14).
- `plot_complex_stiffness`: k_Re and k_Im versus psi_a with psi_fs and psi_BC marked (Fig. 15, App. B).
- `plot_energy`: dissipated energy per contact (work shape factors, Appendix B/C).
- `plot_family_comparison`: the five numbers and w_M of the family, side by side (Table 11).

The section (Fig. 7) is drawn by `section.py`; the shared look lives in `style.py`, the label
placement in `labels.py`. Importing this module chooses no matplotlib backend: the CLI picks Agg, notebooks and scripts keep
whatever matplotlib chose for them.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..geometry import CONTACT_NAMES
from ..status import RESULTS
from .labels import mark_coincident_lines, point_label
from .style import (CONTACT_COLORS, PSI_LABEL, as_cycles, as_numpy, axes_row, cycle_panel,
                    finish_figure, legend_below, mu_color, shape_name)


# ---------------------------------------------------------------- Fig. 10b: equilibrium tracks
def _merge_labels(points, labels, tol=1e-9, near=0.0):
    """Merge labels of coincident consecutive points ('A≡B') and of points closer than `near`
    ('D,E', so that labels do not overprint); returns (points, labels)."""
    out_p, out_l = [points[0]], [labels[0]]
    for p, lab in zip(points[1:], labels[1:]):
        gap = np.linalg.norm(p - out_p[-1])
        if gap <= tol:
            out_l[-1] = f"{out_l[-1]}≡{lab}"
        elif gap <= near:
            out_l[-1] = f"{out_l[-1]},{lab}"
        else:
            out_p.append(p)
            out_l.append(lab)
    return out_p, out_l


def force_track(bc):
    """Force-polygon points of the cycle with F_D = 1 drawn from (0, 0) to (0, 1).

    Returns (track, secondary, labels): the tip of F_R1 (= tail of F_L = -F_L) and the tail of F_L1
    (= -F_L1, with F_L = F_L2 + F_L1 ending at the origin) at every tract end, and point names.
    """
    from ..summary import force_points, point_names, section_data

    # the study's compiled program (op by op the geometry compiled ~18 small programs per process)
    geo = section_data(bc.shape, bc.mu)[0]
    n, t = as_numpy(geo.normals), as_numpy(geo.tangents)
    N, T = force_points(bc)
    F = -N[..., None] * n + T[..., None] * t  # (points, contact, xy)
    track = -(F[:, 1] + F[:, 2])
    secondary = -F[:, 1]
    labels = point_names(len(track))
    return track, secondary, labels


def plot_equilibrium_tracks(cycles, axes=None, show_secondary=True):
    """Force Base-Cycles (equilibrium tracks) in the force polygon, F_D = 1 (Fig. 10b), one panel
    per cycle: the path of the tip of F_R1 / tail of F_L (solid) and of the tail of F_L1 (thin dashed,
    the secondary loop), with the friction-cone boundaries of the left contacts (through the origin)
    and of R1 (through the tip of F_D). Cycles that lift off get a labelled empty panel."""
    from ..summary import section_data

    cycles = as_cycles(cycles)
    created = axes is None
    fig, axes = axes_row(axes, len(cycles), size=(5.2, 6.0))
    fig._jaxdamp_shared_legend = created and len(cycles) > 1
    for k, (ax, bc) in enumerate(zip(axes, cycles)):
        if cycle_panel(ax, bc, "", "circumferential force component (units of $F_D$)",
                        "radial force component (units of $F_D$)"):
            continue
        mu = float(bc.mu)
        geo = section_data(bc.shape, mu)[0]
        n, t = as_numpy(geo.normals), as_numpy(geo.tangents)
        track, sec, labels = force_track(bc)
        apex_r = np.array([0.0, 1.0])
        ax.annotate("", xy=apex_r, xytext=(0, 0),
                    arrowprops=dict(arrowstyle="-|>", color="k", lw=1.8, mutation_scale=14))
        point_label(ax, "$F_D$", (0.0, 0.5), prefer=(1.0, 0.0), fontsize=11)
        reach = 1.3 * max(np.abs(track).max(), 1.0)
        for sgn in (1.0, -1.0):
            dl = n[1] + sgn * mu * t[1]
            dl = reach * dl / np.linalg.norm(dl)
            ax.plot([0, dl[0]], [0, dl[1]], color="tab:purple", lw=0.8, ls="--",
                    label="left friction angle (L1, L2)" if sgn > 0 else None)
            dr = -n[0] + sgn * mu * t[0]
            dr = reach * dr / np.linalg.norm(dr)
            ax.plot([0, dr[0]], [1, 1 + dr[1]], color="tab:olive", lw=1.0, ls="-.",
                    label="R1 friction angle" if sgn > 0 else None)
        # F_R1 and F_L at point 0 (as in Fig. 9a), faint.
        ax.annotate("", xy=track[0], xytext=apex_r,
                    arrowprops=dict(arrowstyle="-|>", color="0.6", lw=1.0))
        ax.annotate("", xy=(0, 0), xytext=track[0], arrowprops=dict(arrowstyle="-|>", color="0.6", lw=1.0))
        ax.plot(track[:, 0], track[:, 1], "-o", color="tab:blue", lw=2.2, ms=4,
                label="equilibrium track (tip of $F_{R1}$)")
        if show_secondary:
            ax.plot(sec[:, 0], sec[:, 1], "--", color="tab:red", lw=1.0,
                    label="secondary loop (tail of $F_{L1}$)")
        span = np.ptp(track, axis=0).max() + 1e-12
        pts, labs = _merge_labels(list(track), labels, near=0.03 * span)
        if len(pts) > 1 and np.linalg.norm(pts[-1] - pts[0]) < 1e-9:
            pts, labs = pts[:-1], labs[:-1]
            labs[0] = labs[0] if "≡" in labs[0] else f"{labels[-1]}≡0"
        centre = track.mean(0)
        for p, lab in zip(pts, labs):
            point_label(ax, lab, p, prefer=p - centre, fontsize=10, color="navy")
        allp = np.vstack([track, sec, [[0, 0], [0, 1]]])
        lo, hi = allp.min(0), allp.max(0)
        half = 0.5 * (hi - lo).max() * 1.15
        mid = 0.5 * (lo + hi)
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(alpha=0.25)
        legend_below(ax, fontsize=7.5)
        if not RESULTS.valid(bc.status):
            ax.text(0.02, 0.02, RESULTS.name_of(bc.status).upper().replace("_", " "),
                    transform=ax.transAxes, color="firebrick")
    return finish_figure(fig)


# ---------------------------------------------------------------- Fig. 13: moment Base-Cycles
def _psi_dv_axis(ax, q_star):
    """Secondary x axis: relative platform displacement (µm) for the given q*."""
    sec = ax.secondary_xaxis("top", functions=(lambda p: p * q_star, lambda v: v / q_star))
    sec.set_xlabel(f"relative platform displacement Δv − Δv_c (µm), q* = {q_star:g} mm")
    return sec


def _label_vertices(ax, psi, M, labels, color):
    span_x = np.ptp(psi) + 1e-12
    span_y = np.ptp(M) + 1e-12
    cx, cy = psi.mean(), M.mean()
    pts = np.column_stack([psi / span_x, M / span_y])
    merged, labs = _merge_labels(list(pts), list(labels), near=0.025)
    if len(merged) > 1 and np.linalg.norm(merged[-1] - merged[0]) < 1e-9:
        # The closing vertex repeats point 0 ("F≡0" when the last tract ends exactly there).
        labs[0] = labs[-1] if "≡" in labs[-1] else labs[0]
        merged, labs = merged[:-1], labs[:-1]
    for (x, y), lab in zip(merged, labs):
        x, y = x * span_x, y * span_y
        point_label(ax, lab, (x, y), prefer=((x - cx) / span_x, (y - cy) / span_y), fontsize=9, color=color)


def _style(bc, k, labels):
    """(legend label, colour) of cycle k: by mu by default, by position when labels are given."""
    if labels is not None:
        return str(labels[k]), f"C{k % 10}"
    mu = float(bc.mu)
    return f"μ = {mu:g}", mu_color(mu, k)


def plot_moment_cycles(cycles, ax=None, label_points=True, labels=None):
    """Moment Base-Cycles M_P (N mm) versus platform rotation psi_P - psi_c (mrad), one curve per
    cycle (the paper's Fig. 13); the top axis gives the relative platform displacement (µm).
    labels: optional legend label per cycle (default: its mu)."""
    from ..summary import moment_polyline

    cycles = as_cycles(cycles)
    fig, (ax,) = axes_row(ax, 1, size=(7.5, 5.4))
    skipped = []
    q = None
    for k, bc in enumerate(cycles):
        name, c = _style(bc, k, labels)
        if RESULTS.stopped(bc.status):
            skipped.append(name)
            continue
        q = float(bc.load.q_star)
        psi, M, names = moment_polyline(bc)
        flag = "" if RESULTS.valid(bc.status) else f" ({RESULTS.name_of(bc.status)})"
        ax.plot(psi, M, "-o", color=c, lw=2, ms=3.5, label=f"{name}: ψ_BC = {psi.max():.3f} mrad{flag}")
        if label_points:
            _label_vertices(ax, psi, M, names, c)
    for name in skipped:
        ax.plot([], [], " ", label=f"{name}: LIFTOFF, no cycle")
    names = sorted({shape_name(bc.shape) for bc in cycles})
    ax.set_title(f"{', '.join(names)}: moment Base-Cycles")
    ax.set_xlabel(PSI_LABEL)
    ax.set_ylabel("platform moment M_P (N mm)")
    ax.axhline(0, color="0.7", lw=0.6)
    ax.axvline(0, color="0.7", lw=0.6)
    ax.grid(alpha=0.25)
    ax.legend(loc="best", fontsize=9)
    mark_coincident_lines(ax)
    if q is not None:
        _psi_dv_axis(ax, q)
    return finish_figure(fig)


# ---------------------------------------------------------------- Fig. 14: stretched cycles
def default_amplitudes(bc):
    """psi_BC and three stretched amplitudes, 1.2, 1.6 and 2.4 psi_BC (3, 4, 6 mrad for 60sym at 0.7)."""
    from ..harmonics import base_cycle_amplitude

    psi_bc = float(base_cycle_amplitude(bc))

    def nice(v):
        step = 0.5 if v > 2.0 else 0.1 if v > 0.5 else 0.01
        return round(round(v / step) * step, 2)

    return [psi_bc] + [nice(f * psi_bc) for f in (1.2, 1.6, 2.4)]


def plot_stretched_cycles(bc, psi_a_mrad=None, ax=None):
    """The moment Base-Cycle and stretched cycles at larger amplitudes (solid) with their
    first-harmonic ellipses M = M_0 + psi_a (k_Re cos tau - k_Im sin tau) versus psi_a cos tau
    (dotted), as in the paper's Fig. 14. k from `complex_stiffness`; M_0 is the cycle's mean moment."""
    from ..summary import moment_polyline, sample_cycle, stiffness_at

    fig, (ax,) = axes_row(ax, 1, size=(7.5, 6.6))
    if cycle_panel(ax, bc, ": stretched cycles and first harmonics",
                    PSI_LABEL, "platform moment M_P (N mm)"):
        return fig
    amps = default_amplitudes(bc) if psi_a_mrad is None else [float(a) for a in np.atleast_1d(psi_a_mrad)]
    k_re, k_im = stiffness_at(bc, amps)
    cmap = plt.get_cmap("viridis")
    tau = np.linspace(0, 2 * np.pi, 361)
    for j, a in enumerate(amps):
        c = cmap(j / max(len(amps) - 1, 1) * 0.85)
        psi, M, labels = moment_polyline(bc, a)
        a = float(psi.max())
        _, m_s = sample_cycle(psi, M, a)
        m0 = float(np.mean(m_s))
        base = "Base-Cycle, " if j == 0 and psi_a_mrad is None else ""
        ax.plot(psi, M, "-", color=c, lw=2.2,
                label=f"{base}ψ_a = {a:.2f} mrad: k_Re = {k_re[j]:.0f}, k_Im = {k_im[j]:.0f} N mm/mrad")
        ell = m0 + a * (k_re[j] * np.cos(tau) - k_im[j] * np.sin(tau))
        ax.plot(a * np.cos(tau), ell, ":", color=c, lw=1.8)
        if j == len(amps) - 1:
            _label_vertices(ax, psi, M, labels, c)
    ax.plot([], [], ":", color="0.3", label="first-harmonic (Fourier) ellipses")
    ax.grid(alpha=0.25)
    legend_below(ax, ncol=1, fontsize=8.5)
    _psi_dv_axis(ax, float(bc.load.q_star))
    return finish_figure(fig)


# ---------------------------------------------------------------- Fig. 15: complex stiffness
def _stiffness_curves(ax, cycles, summaries, labels, legend_entries):
    for k, (bc, s) in enumerate(zip(cycles, summaries)):
        name, c = _style(bc, k, labels)
        if RESULTS.stopped(s.status):
            if legend_entries:
                ax.plot([], [], " ", label=f"{name}: LIFTOFF, no cycle")
            continue
        nb = s.numbers
        ax.plot(s.psi, s.k_re, "-", color=c, lw=2, label=(
            f"{name}: k_Re (ψ_fs = {nb['psi_fs_mrad']:.2f}, ψ_BC = {nb['psi_bc_mrad']:.2f} mrad)"
            if legend_entries else None))
        ax.plot(s.psi, s.k_im, "--", color=c, lw=2, label=f"{name}: k_Im" if legend_entries else None)
        ax.plot([nb["psi_fs_mrad"]], [nb["k_re_fs"]], "o", color=c, ms=7, mec="k", zorder=4)
        ax.plot([nb["psi_bc_mrad"]] * 2, [nb["k_re_bc"], nb["k_im_bc"]], "s", color=c, ms=7, mec="k",
                zorder=4)
    ax.set_xlabel("platform rotation amplitude ψ_P,a (mrad)")
    ax.set_ylabel("rotational stiffness k_Re, k_Im (N mm/mrad)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.25)


def plot_complex_stiffness(cycles, psi_max=20.0, ax=None, summaries=None, labels=None, zoom=None):
    """k_Re (solid) and k_Im (dashed) versus psi_a over 0..psi_max mrad, one colour per cycle, with
    psi_fs (circle) and psi_BC (square) marked; the microslip range between them is the paper's
    linear interpolation (Fig. 15, Appendix B). `summaries`: optional precomputed CycleSummary list;
    labels: optional legend label per cycle (default: its mu).

    zoom: add a second panel over 0..1.6 max(psi_BC), where psi_fs and psi_BC lie (for shapes such as
    90R whose psi_BC is a small fraction of psi_max the markers would otherwise bunch at the left
    edge). Default: True when this function creates the figure, False when `ax` is given.
    """
    from ..summary import analyse_cycle, psi_grid

    cycles = as_cycles(cycles)
    zoom = (ax is None) if zoom is None else bool(zoom)
    fig, axes = axes_row(ax, 2 if zoom else 1, size=(7.0, 5.4))
    if summaries is None:
        summaries = [analyse_cycle(bc, psi_grid(psi_max)) for bc in cycles]
    ax = axes[0]
    _stiffness_curves(ax, cycles, summaries, labels, True)
    ax.plot([], [], "o", color="w", mec="k", label="ψ_fs (end of full stick)")
    ax.plot([], [], "s", color="w", mec="k", label="ψ_BC (Base-Cycle)")
    names = sorted({shape_name(bc.shape) for bc in cycles})
    ax.set_title(f"{', '.join(names)}: complex stiffness of the platform")
    ax.set_xlim(0, psi_max)
    ax.legend(loc="upper right", fontsize=8, ncol=1)
    valid = [s.numbers["psi_bc_mrad"] for s in summaries if not RESULTS.stopped(s.status)]
    if zoom:
        z = axes[1]
        z_max = 1.6 * max(valid) if valid else psi_max
        # The same grid length as the full panel: the jit-compiled analysis is reused.
        fine = [s if RESULTS.stopped(s.status) else analyse_cycle(bc, psi_grid(z_max, len(s.psi)))
                for bc, s in zip(cycles, summaries)]
        _stiffness_curves(z, cycles, fine, labels, False)
        z.set_xlim(0, z_max)
        z.set_title(f"zoom on 0 – {z_max:.2f} mrad (ψ_fs, ψ_BC)")
    return finish_figure(fig)


# ---------------------------------------------------------------- energy and family comparison
def _mu_keys(results):
    keys = []
    for per_mu in results.values():
        for m in per_mu:
            if m not in keys:
                keys.append(m)
    return keys


# A stacked bar below this fraction of the panel's highest is labelled 0 (it is drawn empty).
ZERO_BAR = 1e-3


def plot_energy(results, energies=None):
    """Dissipated energy per contact for every shape (bars) and friction coefficient (panels).

    results: {shape: {mu_key: entry}} as in study.json (work shape factors w_R1, w_L1, w_L2, w_M).
    Top row: work shape factors stacked per contact, with w_M (= their sum) as a black diamond and
    the contact shares in %. energies: optional {shape: {mu_key: {"R1", "L1", "L2", "M"}}} in N mm per
    Base-Cycle, drawn in a second row: each shape's Base-Cycle, so each at its own psi_BC amplitude.
    A shape whose bar is (next to) empty gets a "0" label.
    """
    mus = _mu_keys(results)
    shapes = list(results)
    rows = 2 if energies else 1
    fig, axes = plt.subplots(rows, len(mus), figsize=(4.8 * len(mus), 4.3 * rows), squeeze=False,
                             layout="constrained")
    x = np.arange(len(shapes))
    for j, mu in enumerate(mus):
        for r in range(rows):
            ax = axes[r][j]
            bottom = np.zeros(len(shapes))
            for c in CONTACT_NAMES:
                vals = []
                for s in shapes:
                    e = results[s].get(mu)
                    ok = e is not None and not e.get("liftoff") and e.get(f"w_{c}") is not None
                    if r == 0:
                        vals.append(max(e[f"w_{c}"], 0.0) if ok else 0.0)
                    else:
                        vals.append(max(energies[s][mu][c], 0.0) if ok else 0.0)
                vals = np.array(vals)
                ax.bar(x, vals, 0.6, bottom=bottom, color=CONTACT_COLORS[c], label=c, edgecolor="k", lw=0.5)
                if r == 0:
                    for xi, b, v in zip(x, bottom, vals):
                        tot = sum(max(results[shapes[xi]][mu].get(f"w_{cc}") or 0.0, 0.0)
                                  for cc in CONTACT_NAMES) if mu in results[shapes[xi]] else 0.0
                        if v > 0.06 * max(tot, 1e-12) and tot > 0:
                            ax.text(xi, b + v / 2, f"{100 * v / tot:.0f}%", ha="center", va="center",
                                    fontsize=7.5)
                bottom += vals
            tops = []
            for xi, s in enumerate(shapes):
                e = results[s].get(mu)
                if e is None or e.get("liftoff"):
                    ax.text(xi, 0.02, "LIFTOFF", rotation=90, ha="center", va="bottom", color="firebrick",
                            fontsize=9, transform=ax.get_xaxis_transform())
                    continue
                if bottom[xi] <= ZERO_BAR * max(bottom.max(), 1e-300):
                    # a cycle that dissipates (next to) nothing (90R: the mechanism freezes): an
                    # empty bar is a number, 0, not a missing one
                    ax.text(xi, 0.02, "0" if bottom[xi] == 0.0 else "≈0", ha="center", va="bottom",
                            fontsize=10, fontweight="bold", transform=ax.get_xaxis_transform())
                tops.append((xi, e["w_M"] if r == 0 else energies[s][mu]["M"]))
            if tops:
                xs, ys = zip(*tops)
                ax.plot(xs, ys, "D", color="k", ms=6, label="w_M" if r == 0 else "∮M dψ")
            ax.set_xticks(x, shapes)
            ax.set_xlabel("shape")
            ax.grid(axis="y", alpha=0.25)
            if r == 0:
                ax.set_title(f"μ = {mu}: work shape factors (full slip)")
                ax.set_ylabel("work shape factor w (–)")
            else:
                ax.set_title(f"μ = {mu}: energy per Base-Cycle\n(each shape at its own ψ_BC)")
                ax.set_ylabel("dissipated energy (N mm per cycle)")
            ax.legend(fontsize=8, loc="upper right")
    return fig


FAMILY_PANELS = (("k_re_fs", "k_Re,fs = k_Re,init (N mm/mrad)", "higher is better"),
                 ("psi_bc_mrad", "ψ_BC (mrad)", "lower is better"),
                 ("k_re_bc", "k_Re,BC (N mm/mrad)", "higher is better"),
                 ("w_M", "w_M (–)", "higher is better"),
                 ("psi_fs_mrad", "ψ_fs (mrad)", "not scored"),
                 ("k_im_bc", "k_Im,BC (N mm/mrad)", "not scored"))


def plot_family_comparison(results, paper=None):
    """The five numbers and w_M of every shape, one bar per friction coefficient (Table 11 as a
    figure). results: {shape: {mu_key: entry}} as in study.json. Liftoff cases are marked, not drawn.
    paper: optional {shape: {mu_key: {key: value}}} drawn as black ticks (the paper's tables)."""
    mus = _mu_keys(results)
    shapes = list(results)
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.8), layout="constrained")
    x = np.arange(len(shapes))
    width = 0.8 / max(len(mus), 1)
    for ax, (key, label, note) in zip(axes.ravel(), FAMILY_PANELS):
        for j, mu in enumerate(mus):
            xs = x - 0.4 + width * (j + 0.5)
            for xi, s in zip(xs, shapes):
                e = results[s].get(mu)
                if e is None:
                    continue
                if e.get("liftoff") or e.get(key) is None:
                    ax.text(xi, 0.02, "liftoff", rotation=90, ha="center", va="bottom", fontsize=8,
                            color="firebrick", transform=ax.get_xaxis_transform())
                    continue
                ax.bar(xi, e[key], width, color=mu_color(float(mu), j), edgecolor="k", lw=0.4)
                ref = (paper or {}).get(s, {}).get(mu, {}).get(key)
                if ref is not None:
                    ax.plot([xi - width / 2, xi + width / 2], [ref, ref], color="k", lw=2)
        ax.set_xticks(x, shapes)
        ax.set_xlabel("shape")
        ax.set_ylabel(label)
        ax.set_title(f"{label.split(' (')[0]}  ({note})", fontsize=10)
        ax.grid(axis="y", alpha=0.25)
    handles = [plt.Rectangle((0, 0), 1, 1, color=mu_color(float(m), j)) for j, m in enumerate(mus)]
    labels = [f"μ = {m}" for m in mus]
    if paper:
        handles.append(plt.Line2D([], [], color="k", lw=2))
        labels.append("paper (Tables B3.1-B5.1)")
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=10)
    fig.suptitle("Shapes compared: the five numbers and w_M", fontsize=13)
    return fig


__all__ = ["force_track", "plot_equilibrium_tracks", "plot_moment_cycles", "default_amplitudes",
           "plot_stretched_cycles", "plot_complex_stiffness", "ZERO_BAR", "plot_energy",
           "FAMILY_PANELS", "plot_family_comparison"]
