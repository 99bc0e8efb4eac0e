"""The damper's section with its pads, D, R, L, the contact forces, friction cones and the
full-slip lines of action at cycle start and mid-cycle (the paper's Fig. 7)."""

from __future__ import annotations

import numpy as np

from ..geometry import CONTACT_NAMES
from .labels import point_label
from .style import CONTACT_COLORS, as_numpy, axes_row, finish_figure, legend_below, shape_name

__all__ = ["section_lines_of_action", "plot_section"]


def _line_intersection(p1, d1, p2, d2):
    m = np.array([d1, -d2]).T
    if abs(np.linalg.det(m)) < 1e-12:
        return None
    s = np.linalg.solve(m, p2 - p1)
    return p1 + s[0] * d1


def section_lines_of_action(shape, mu, end="start"):
    """Points and directions of the full-slip lines of action (numpy), for plots and checks.

    Returns a dict: R1 point and force, the left resultant's application point on L1-L2 and force,
    and their intersection (which lies on F_D's line of action, the vertical through D).
    """
    from ..summary import section_data

    geo, st = section_data(shape, mu)
    s = st.start if end == "start" else st.mid
    n, t, p = as_numpy(geo.normals), as_numpy(geo.tangents), as_numpy(geo.points)
    N, T = as_numpy(s.N), as_numpy(s.T)
    F = -N[:, None] * n + T[:, None] * t
    F_L = F[1] + F[2]
    frac = float(s.resultant_pos_pct) / 100.0
    P_L = p[1] + frac * (p[2] - p[1])
    X = _line_intersection(p[0], F[0], P_L, F_L)
    return dict(points=p, normals=n, tangents=t, N=N, T=T, F=F, F_L=F_L, P_L=P_L, X=X,
                pos_pct=float(s.resultant_pos_pct), liftoff=bool(float(s.min_normal) <= 0.0),
                D=as_numpy(geo.D), geo=geo)


def _draw_section(ax, shape, mu, end, scale):
    d = section_lines_of_action(shape, mu, end)
    geo = d["geo"]
    A, B, V, D, R, L = (as_numpy(geo.A), as_numpy(geo.B), as_numpy(geo.V), as_numpy(geo.D), as_numpy(geo.R), as_numpy(geo.L))
    tri = np.array([A, B, V, A])
    ax.fill(tri[:, 0], tri[:, 1], color="0.92", zorder=0)
    ax.plot(tri[:, 0], tri[:, 1], color="0.3", lw=1.5, zorder=1)
    ax.plot([L[0], R[0]], [L[1], R[1]], color="0.55", lw=0.8, ls="-.", zorder=1,
            label="reference line L–R")
    p, n, t, F = d["points"], d["normals"], d["tangents"], d["F"]
    h_l = float(geo.h_l)
    for i, name in enumerate(CONTACT_NAMES):
        c = CONTACT_COLORS[name]
        pad = np.array([p[i] - 0.05 * h_l * t[i], p[i] + 0.05 * h_l * t[i]])
        ax.plot(pad[:, 0], pad[:, 1], color="k", lw=5, solid_capstyle="butt", zorder=3)
        for sgn in (1.0, -1.0):  # friction cone boundaries, drawn outside the damper
            cone = n[i] - sgn * mu * t[i]
            end_pt = p[i] + 0.55 * cone / np.linalg.norm(cone)
            ax.plot([p[i][0], end_pt[0]], [p[i][1], end_pt[1]], color=c, lw=0.8, ls="--", zorder=2)
        tail = p[i] - scale * F[i]
        ax.annotate("", xy=p[i], xytext=tail, zorder=4,
                    arrowprops=dict(arrowstyle="-|>", color=c, lw=2.0, mutation_scale=14))
        point_label(ax, name, p[i], prefer=n[i] + 0.6 * t[i], color=c, fontsize=11, fontweight="bold")
    # F_D = 1 at D, upward; its line of action is the vertical through D.
    ax.annotate("", xy=D + [0, scale], xytext=D, zorder=4,
                arrowprops=dict(arrowstyle="-|>", color="k", lw=2.0, mutation_scale=14))
    ax.plot([D[0]], [D[1]], "ko", ms=5, zorder=5)
    point_label(ax, "D", D, prefer=(1.0, -1.0), fontsize=11)
    point_label(ax, "$F_D$", D + [0, 0.6 * scale], prefer=(1.0, 0.0), fontsize=11)
    for P, lab, pref in ((R, "R", (1.0, -1.0)), (L, "L", (-1.0, -1.0))):
        ax.plot([P[0]], [P[1]], "o", color="0.4", ms=4, zorder=5)
        point_label(ax, lab, P, prefer=pref, fontsize=10, color="0.3")
    # Lines of action (dotted): R1 force, left resultant, F_D; they meet at X.
    X = d["X"]
    ax.plot([d["P_L"][0]], [d["P_L"][1]], "s", color="tab:purple", ms=6, zorder=5,
            label=f"left resultant at {d['pos_pct']:.1f} % of L1→L2")
    if X is not None:
        ax.plot([p[0][0], X[0]], [p[0][1], X[1]], color=CONTACT_COLORS["R1"], ls=":", lw=1.6,
                label="line of action of $F_{R1}$")
        ax.plot([d["P_L"][0], X[0]], [d["P_L"][1], X[1]], color="tab:purple", ls=":", lw=1.6,
                label="line of action of $F_L$")
        ax.plot([D[0], X[0]], [D[1], X[1]], color="k", ls=":", lw=1.0)
        ax.plot([X[0]], [X[1]], "x", color="k", ms=8, mew=2, label="intersection (on $F_D$ line)")
    what = "cycle start (point 0)" if end == "start" else "mid-cycle"
    title = f"{shape_name(shape)}, μ = {mu:g}\n{what}, full-slip statics"
    if d["liftoff"]:
        lifted = ", ".join(c for c, v in zip(CONTACT_NAMES, d["N"]) if v <= 0.0)
        title += f"\nLIFTOFF: resultant outside L1–L2, N ≤ 0 at {lifted}"
    ax.set_title(title, color="firebrick" if d["liftoff"] else "k", fontsize=11)
    return d


def plot_section(shape, mu, ax=None, end="both", force_scale=0.35):
    """The section (H = 1) with pads R1, L1, L2, points D, R, L, the full-slip contact forces (scaled
    by force_scale, F_D = 1), friction-cone boundaries (dashed) and lines of action (dotted) that
    meet on the line of action of F_D (the paper's Fig. 7).

    end: "start" (cycle start), "mid" (mid-cycle) or "both" (two panels; ax then a pair of Axes).
    """
    ends = ("start", "mid") if end == "both" else (end,)
    if any(e not in ("start", "mid") for e in ends):
        raise ValueError(f"end must be 'start', 'mid' or 'both'; got {end!r}")
    fig, axes = axes_row(ax, len(ends), size=(6.0, 6.3))
    lims = []
    for a, e in zip(axes, ends):
        d = _draw_section(a, shape, float(mu), e, force_scale)
        pts = [d["points"], as_numpy(d["geo"].B)[None], as_numpy(d["geo"].A)[None], as_numpy(d["geo"].V)[None]]
        if d["X"] is not None:
            pts.append(d["X"][None])
        lims.append(np.concatenate(pts))
        a.set_aspect("equal")
        a.set_xlabel("circumferential position c / H (–)")
        a.set_ylabel("radial position r / H (–)")
        a.grid(alpha=0.25)
        legend_below(a)
    allp = np.concatenate(lims)
    lo, hi = allp.min(0) - 0.45, allp.max(0) + 0.45
    lo[1], hi[1] = min(allp[:, 1].min() - 0.2, -0.2), max(hi[1], 1.45)
    for a in axes:
        a.set_xlim(lo[0], hi[0])
        a.set_ylim(lo[1], min(hi[1], 4.0))
    return finish_figure(fig)
