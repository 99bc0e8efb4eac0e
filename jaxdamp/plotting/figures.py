"""Figures in the paper's spirit (matplotlib). Every function returns its Figure.

- `plot_section`: the section with pads, D, R, L, contact forces, friction cones and the full-slip
  lines of action at cycle start and mid-cycle (Fig. 7).
- `plot_equilibrium_tracks`: force Base-Cycles in the force polygon with F_D = 1 (Fig. 10b).
- `plot_moment_cycles`: moment Base-Cycles (Fig. 13).
- `plot_stretched_cycles`: stretched cycles with their first-harmonic ellipses (Fig. 14).
- `plot_complex_stiffness`: k_Re and k_Im versus psi_a with psi_fs and psi_BC marked (Fig. 15, App. B).
- `plot_energy`: dissipated energy per contact (work shape factors, Appendix B/C).
- `plot_family_comparison`: the five numbers and w_M of the family, side by side (Table 11).

Importing this module chooses no matplotlib backend: the CLI picks Agg, notebooks and scripts keep
whatever matplotlib chose for them.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from ..geometry import CONTACT_NAMES

# psi_c: the centre of the rotation cycle (psi_P runs between psi_c - psi_a and psi_c + psi_a).
PSI_LABEL = "platform rotation about the cycle centre ψ_c: ψ_P − ψ_c (mrad)"
MU_COLORS = {0.7: "tab:blue", 0.5: "tab:orange", 0.3: "tab:green"}
CONTACT_COLORS = {"R1": "tab:red", "L1": "tab:blue", "L2": "tab:cyan"}


def mu_color(mu, k=0):
    """Colour of a friction coefficient, consistent across figures."""
    return MU_COLORS.get(round(float(mu), 6), f"C{3 + k % 7}")


def _np(x):
    return np.asarray(x, dtype=float)


def _as_cycles(cycles):
    """A BaseCycle, a sequence of them, or a mapping label -> BaseCycle, as a list."""
    if isinstance(cycles, Mapping):
        return list(cycles.values())
    if hasattr(cycles, "forward"):
        return [cycles]
    return list(cycles)


def _axes_row(axes, n, size=(5.0, 4.6)):
    if axes is None:
        fig, axes = plt.subplots(1, n, figsize=(size[0] * n, size[1]), squeeze=False,
                                 layout="constrained")
        return fig, list(axes[0])
    axes = list(np.atleast_1d(axes).ravel())
    if len(axes) != n:
        raise ValueError(f"need {n} axes, got {len(axes)}")
    return axes[0].figure, axes


def _finish(fig):
    if fig.get_layout_engine() is None:
        fig.tight_layout()
    return fig


def _legend_below(ax, ncol=2, fontsize=8):
    """Legend under the axes; on a figure this function created, one shared legend at the bottom."""
    fig = ax.figure
    if getattr(fig, "_jaxdamp_shared_legend", False):
        if not getattr(fig, "_jaxdamp_legend_done", False):
            fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=4,
                       fontsize=fontsize + 1)
            fig._jaxdamp_legend_done = True
        return
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=ncol, fontsize=fontsize,
              framealpha=0.9)


# Markers of a curve that lies on another one (mark_coincident_lines): thin, so that the curve
# underneath stays visible through them.
COINCIDENT_MARKERS = ("x", "+", "1", "2", "3", "4")
# A vertex closer than this to another curve (in fractions of the axes' width and height) lies on it.
COINCIDENT_TOL = 2e-3


def _axes_points(ax, line):
    """The line's vertices in axes fractions (0..1 across the current limits), NaN rows dropped."""
    x, y = (np.asarray(v, float) for v in line.get_data())
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    pts = np.stack([(x - x0) / (x1 - x0), (y - y0) / (y1 - y0)], -1)
    return pts[np.all(np.isfinite(pts), -1)]


def lies_on(points, polyline, tol=COINCIDENT_TOL) -> bool:
    """Every point within tol of the polyline (a curve drawn on another one, in axes fractions)."""
    if len(points) == 0 or len(polyline) < 2:
        return False
    a, b = polyline[:-1], polyline[1:]
    d = b - a
    t = np.clip(np.einsum("psk,sk->ps", points[:, None, :] - a[None], d)
                / np.maximum(np.einsum("sk,sk->s", d, d), 1e-300), 0.0, 1.0)
    nearest = a[None] + t[..., None] * d[None]
    return bool(np.all(np.min(np.linalg.norm(points[:, None, :] - nearest, axis=-1), axis=1) <= tol))


def hidden_lines(ax):
    """(hidden, covering) pairs of visible lines: a line every vertex of which lies on a line drawn
    above it (later, or at a higher zorder), with the same line style and marker: it cannot be seen.
    Curves in data coordinates only (not axhline/axvline guides, whose x or y is in axes units)."""
    lines = [ln for ln in ax.get_lines() if ln.get_visible() and len(ln.get_xdata()) >= 2
             and ln.get_transform() == ax.transData]
    order = {id(ln): (ln.get_zorder(), k) for k, ln in enumerate(lines)}
    pairs = []
    for ln in lines:
        pts = _axes_points(ax, ln)
        for other in lines:
            if other is ln or order[id(other)] < order[id(ln)]:
                continue
            same_look = (ln.get_linestyle(), ln.get_marker()) == (other.get_linestyle(), other.get_marker())
            if same_look and lies_on(pts, _axes_points(ax, other)):
                pairs.append((ln, other))
                break
    return pairs


def mark_coincident_lines(ax) -> list[tuple[str, str]]:
    """A curve that lies on a later one (90R's moment cycle at mu = 0.7 runs along the mu = 0.5 one)
    is brought to the front, dashed, with a distinct marker, and its legend label says on which
    curve it lies. Returns the (hidden, covering) labels."""
    out = []
    legend = ax.get_legend()
    entries = {} if legend is None else {t.get_text(): (t, h) for t, h in
                                         zip(legend.get_texts(), legend.legend_handles)}
    for k, (ln, over) in enumerate(hidden_lines(ax)):
        name, under = ln.get_label(), over.get_label()
        style = dict(zorder=over.get_zorder() + 0.1, linestyle=(0, (4, 2)),
                     marker=COINCIDENT_MARKERS[k % len(COINCIDENT_MARKERS)],
                     markersize=max(ln.get_markersize(), 8.0), markeredgewidth=1.6)
        ln.set(**style)
        if not name.startswith("_") and not under.startswith("_"):
            ln.set_label(f"{name} (dashed: on {under.split(':')[0]})")
            if name in entries:  # the legend drawn already: its entry in place (keeps its layout)
                text, handle = entries[name]
                text.set_text(ln.get_label())
                if handle is not None and hasattr(handle, "set_marker"):
                    handle.set(**{k: v for k, v in style.items() if k != "zorder"})
        out.append((name, under))
    return out


def _liftoff_panel(ax, text):
    ax.set_xticks([])
    ax.set_yticks([])
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, fontsize=12,
            color="firebrick", bbox=dict(boxstyle="round", fc="mistyrose", ec="firebrick"))


def _cycle_panel(ax, bc, title_suffix, xlabel, ylabel) -> bool:
    """Title ("shape, μ" + suffix) and axis labels of a panel showing one cycle; a cycle that lifted
    off gets the labelled empty panel instead, and True is returned."""
    mu = float(bc.mu)
    ax.set_title(f"{_shape_name(bc.shape)}, μ = {mu:g}{title_suffix}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if bool(bc.liftoff):
        _liftoff_panel(ax, f"μ = {mu:g}: LIFTOFF\nno Base-Cycle")
        return True
    return False


def _shape_name(shape):
    from ..geometry import paper_tables

    for name, s in paper_tables()["shapes"].items():
        if (np.isclose(float(shape.theta_l), s["theta_l"]) and np.isclose(float(shape.theta_r), s["theta_r"])
                and np.isclose(float(shape.br_over_hr), s["br_over_hr"])
                and np.isclose(float(shape.bl2_over_hl), s["bl2_over_hl"]) and shape.x_d is None):
            return name
    return (f"θL = {float(shape.theta_l):g}°, θR = {float(shape.theta_r):g}°, "
            f"b_R/h_R = {float(shape.br_over_hr):g}")


# ---------------------------------------------------------------- labels that avoid what is drawn
class _AutoLabel(matplotlib.text.Annotation):
    """A point label that picks its offset when drawn, once the layout is final.

    Candidate offsets (points) run around the anchor, the preferred direction first; the first one
    whose text box stays inside the axes and meets no line, arrow, legend or other text of the axes
    is kept (else the least crowded one, on an opaque white box so that the text stays readable).
    """

    _RADII = (9.0, 15.0, 23.0, 32.0)

    def __init__(self, text, xy, prefer=(0.0, 1.0), **kw):
        kw.setdefault("ha", "center")
        kw.setdefault("va", "center")
        super().__init__(text, xy, xytext=(0.0, 0.0), textcoords="offset points", **kw)
        d = np.asarray(prefer, float)
        a0 = float(np.arctan2(d[1], d[0])) if np.hypot(*d) > 0 else np.pi / 2
        turns = [0.0] + [s * k * np.pi / 8 for k in range(1, 9) for s in (1.0, -1.0)][:-1]
        self._candidates = [(r * np.cos(a0 + t), r * np.sin(a0 + t)) for r in self._RADII for t in turns]
        self.set_in_layout(False)
        self.set_zorder(6)

    @staticmethod
    def _obstacles(renderer, ax):
        """What a label must avoid in ax, in pixels, computed once per draw of the axes (the cache key
        changes with the renderer, the axes' place and the number of artists)."""
        key = (id(renderer), tuple(ax.bbox.bounds), len(ax.lines), len(ax.texts), len(ax.patches))
        cached = getattr(ax, "_jaxdamp_label_obstacles", None)
        if cached is not None and cached[0] == key:
            return cached[1]
        lines = []
        for ln in ax.get_lines():
            if not ln.get_visible() or len(ln.get_xdata()) == 0:
                continue
            xy = ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
            marker = ln.get_marker() not in (None, "None", "", " ")
            drawn = ln.get_linestyle() not in ("None", "", " ") and len(xy) > 1
            r = 0.5 * ln.get_markersize() * renderer.points_to_pixels(1.0)
            lines.append((xy, marker, r, matplotlib.path.Path(xy) if drawn else None))
        arrows = [p.get_transform().transform_path(p.get_path())
                  for p in ax.patches + [t.arrow_patch for t in ax.texts
                                         if isinstance(t, matplotlib.text.Annotation) and t.arrow_patch is not None]
                  if isinstance(p, matplotlib.patches.FancyArrowPatch)]
        fixed = [t.get_window_extent(renderer) for t in ax.texts
                 if not isinstance(t, _AutoLabel) and t.get_visible() and t.get_text().strip()]
        leg = ax.get_legend()
        if leg is not None:
            fixed.append(leg.get_window_extent(renderer))
        out = (lines, arrows, fixed)
        ax._jaxdamp_label_obstacles = (key, out)
        return out

    @staticmethod
    def _cost(bb, ax, obstacles, labels):
        if not (ax.bbox.x0 <= bb.x0 and bb.x1 <= ax.bbox.x1 and ax.bbox.y0 <= bb.y0 and bb.y1 <= ax.bbox.y1):
            return 100.0
        lines, arrows, fixed = obstacles
        cost = 10.0 * sum(bb.overlaps(o) for o in fixed) + 10.0 * sum(bb.overlaps(o) for o in labels)
        for xy, marker, r, path in lines:
            if marker and bb.padded(r).count_contains(xy) > 0:
                cost += 3.0
            elif path is not None and path.intersects_bbox(bb, filled=False):
                cost += 1.0
        cost += 5.0 * sum(bool(a.intersects_bbox(bb, filled=False)) for a in arrows)
        return cost

    def _extent(self, renderer):
        """The label's box where it was last placed with this renderer (else where it is now)."""
        placed = getattr(self, "_jaxdamp_placed", None)
        if placed is not None and placed[0] == id(renderer):
            return placed[1]
        return self.get_window_extent(renderer)

    def draw(self, renderer):
        ax = self.axes
        if ax is not None and self.get_visible():
            obstacles = self._obstacles(renderer, ax)
            labels = [t._extent(renderer) for t in ax.texts
                      if isinstance(t, _AutoLabel) and t is not self and t.get_visible()]
            # The text's box at the anchor, shifted per candidate (one text layout, not one each).
            self.xyann = (0.0, 0.0)
            bb0 = self.get_window_extent(renderer)
            px = renderer.points_to_pixels(1.0)
            best, best_cost = None, None
            for off in self._candidates:
                c = self._cost(bb0.translated(off[0] * px, off[1] * px), ax, obstacles, labels)
                if c == 0.0:
                    best, best_cost = off, c
                    break
                if best_cost is None or c < best_cost:
                    best, best_cost = off, c
            self.xyann = best
            if best_cost:
                self.set_bbox(dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.85))
            self._jaxdamp_placed = (id(renderer), bb0.translated(best[0] * px, best[1] * px))
        super().draw(renderer)


def _label(ax, text, xy, prefer=(0.0, 1.0), **kw):
    """A point label at xy (data) that moves to a free spot next to it when drawn (`_AutoLabel`)."""
    lab = _AutoLabel(text, xy, prefer=prefer, **kw)
    ax._add_text(lab)
    return lab


# ---------------------------------------------------------------- Fig. 7: section and lines of action
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
    n, t, p = _np(geo.normals), _np(geo.tangents), _np(geo.points)
    N, T = _np(s.N), _np(s.T)
    F = -N[:, None] * n + T[:, None] * t
    F_L = F[1] + F[2]
    frac = float(s.resultant_pos_pct) / 100.0
    P_L = p[1] + frac * (p[2] - p[1])
    X = _line_intersection(p[0], F[0], P_L, F_L)
    return dict(points=p, normals=n, tangents=t, N=N, T=T, F=F, F_L=F_L, P_L=P_L, X=X,
                pos_pct=float(s.resultant_pos_pct), liftoff=bool(float(s.min_normal) <= 0.0),
                D=_np(geo.D), geo=geo)


def _draw_section(ax, shape, mu, end, scale):
    d = section_lines_of_action(shape, mu, end)
    geo = d["geo"]
    A, B, V, D, R, L = (_np(geo.A), _np(geo.B), _np(geo.V), _np(geo.D), _np(geo.R), _np(geo.L))
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
        _label(ax, name, p[i], prefer=n[i] + 0.6 * t[i], color=c, fontsize=11, fontweight="bold")
    # F_D = 1 at D, upward; its line of action is the vertical through D.
    ax.annotate("", xy=D + [0, scale], xytext=D, zorder=4,
                arrowprops=dict(arrowstyle="-|>", color="k", lw=2.0, mutation_scale=14))
    ax.plot([D[0]], [D[1]], "ko", ms=5, zorder=5)
    _label(ax, "D", D, prefer=(1.0, -1.0), fontsize=11)
    _label(ax, "$F_D$", D + [0, 0.6 * scale], prefer=(1.0, 0.0), fontsize=11)
    for P, lab, pref in ((R, "R", (1.0, -1.0)), (L, "L", (-1.0, -1.0))):
        ax.plot([P[0]], [P[1]], "o", color="0.4", ms=4, zorder=5)
        _label(ax, lab, P, prefer=pref, fontsize=10, color="0.3")
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
    title = f"{_shape_name(shape)}, μ = {mu:g}\n{what}, full-slip statics"
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
    fig, axes = _axes_row(ax, len(ends), size=(6.0, 6.3))
    lims = []
    for a, e in zip(axes, ends):
        d = _draw_section(a, shape, float(mu), e, force_scale)
        pts = [d["points"], _np(d["geo"].B)[None], _np(d["geo"].A)[None], _np(d["geo"].V)[None]]
        if d["X"] is not None:
            pts.append(d["X"][None])
        lims.append(np.concatenate(pts))
        a.set_aspect("equal")
        a.set_xlabel("circumferential position c / H (–)")
        a.set_ylabel("radial position r / H (–)")
        a.grid(alpha=0.25)
        _legend_below(a)
    allp = np.concatenate(lims)
    lo, hi = allp.min(0) - 0.45, allp.max(0) + 0.45
    lo[1], hi[1] = min(allp[:, 1].min() - 0.2, -0.2), max(hi[1], 1.45)
    for a in axes:
        a.set_xlim(lo[0], hi[0])
        a.set_ylim(lo[1], min(hi[1], 4.0))
    return _finish(fig)


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
    from ..geometry import section_geometry
    from ..summary import force_points, point_names

    geo = section_geometry(bc.shape)
    n, t = _np(geo.normals), _np(geo.tangents)
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
    from ..geometry import section_geometry

    cycles = _as_cycles(cycles)
    created = axes is None
    fig, axes = _axes_row(axes, len(cycles), size=(5.2, 6.0))
    fig._jaxdamp_shared_legend = created and len(cycles) > 1
    for k, (ax, bc) in enumerate(zip(axes, cycles)):
        if _cycle_panel(ax, bc, "", "circumferential force component (units of $F_D$)",
                        "radial force component (units of $F_D$)"):
            continue
        mu = float(bc.mu)
        geo = section_geometry(bc.shape)
        n, t = _np(geo.normals), _np(geo.tangents)
        track, sec, labels = force_track(bc)
        apex_r = np.array([0.0, 1.0])
        ax.annotate("", xy=apex_r, xytext=(0, 0),
                    arrowprops=dict(arrowstyle="-|>", color="k", lw=1.8, mutation_scale=14))
        _label(ax, "$F_D$", (0.0, 0.5), prefer=(1.0, 0.0), fontsize=11)
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
            _label(ax, lab, p, prefer=p - centre, fontsize=10, color="navy")
        allp = np.vstack([track, sec, [[0, 0], [0, 1]]])
        lo, hi = allp.min(0), allp.max(0)
        half = 0.5 * (hi - lo).max() * 1.15
        mid = 0.5 * (lo + hi)
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(alpha=0.25)
        _legend_below(ax, fontsize=7.5)
        if not bool(bc.converged):
            ax.text(0.02, 0.02, "NOT CONVERGED", transform=ax.transAxes, color="firebrick")
    return _finish(fig)


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
        _label(ax, lab, (x, y), prefer=((x - cx) / span_x, (y - cy) / span_y), fontsize=9, color=color)


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

    cycles = _as_cycles(cycles)
    fig, (ax,) = _axes_row(ax, 1, size=(7.5, 5.4))
    skipped = []
    q = None
    for k, bc in enumerate(cycles):
        name, c = _style(bc, k, labels)
        if bool(bc.liftoff):
            skipped.append(name)
            continue
        q = float(bc.load.q_star)
        psi, M, names = moment_polyline(bc)
        flag = "" if bool(bc.converged) else " (not converged)"
        ax.plot(psi, M, "-o", color=c, lw=2, ms=3.5, label=f"{name}: ψ_BC = {psi.max():.3f} mrad{flag}")
        if label_points:
            _label_vertices(ax, psi, M, names, c)
    for name in skipped:
        ax.plot([], [], " ", label=f"{name}: LIFTOFF, no cycle")
    names = sorted({_shape_name(bc.shape) for bc in cycles})
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
    return _finish(fig)


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

    fig, (ax,) = _axes_row(ax, 1, size=(7.5, 6.6))
    if _cycle_panel(ax, bc, ": stretched cycles and first harmonics",
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
    _legend_below(ax, ncol=1, fontsize=8.5)
    _psi_dv_axis(ax, float(bc.load.q_star))
    return _finish(fig)


# ---------------------------------------------------------------- Fig. 15: complex stiffness
def _stiffness_curves(ax, cycles, summaries, labels, legend_entries):
    for k, (bc, s) in enumerate(zip(cycles, summaries)):
        name, c = _style(bc, k, labels)
        if s.liftoff:
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

    cycles = _as_cycles(cycles)
    zoom = (ax is None) if zoom is None else bool(zoom)
    fig, axes = _axes_row(ax, 2 if zoom else 1, size=(7.0, 5.4))
    if summaries is None:
        summaries = [analyse_cycle(bc, psi_grid(psi_max)) for bc in cycles]
    ax = axes[0]
    _stiffness_curves(ax, cycles, summaries, labels, True)
    ax.plot([], [], "o", color="w", mec="k", label="ψ_fs (end of full stick)")
    ax.plot([], [], "s", color="w", mec="k", label="ψ_BC (Base-Cycle)")
    names = sorted({_shape_name(bc.shape) for bc in cycles})
    ax.set_title(f"{', '.join(names)}: complex stiffness of the platform")
    ax.set_xlim(0, psi_max)
    ax.legend(loc="upper right", fontsize=8, ncol=1)
    valid = [s.numbers["psi_bc_mrad"] for s in summaries if not s.liftoff]
    if zoom:
        z = axes[1]
        z_max = 1.6 * max(valid) if valid else psi_max
        # The same grid length as the full panel: the jit-compiled analysis is reused.
        fine = [analyse_cycle(bc, psi_grid(z_max, len(s.psi))) if not s.liftoff else s
                for bc, s in zip(cycles, summaries)]
        _stiffness_curves(z, cycles, fine, labels, False)
        z.set_xlim(0, z_max)
        z.set_title(f"zoom on 0 – {z_max:.2f} mrad (ψ_fs, ψ_BC)")
    return _finish(fig)


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


__all__ = ["PSI_LABEL", "MU_COLORS", "CONTACT_COLORS", "mu_color", "COINCIDENT_MARKERS",
           "COINCIDENT_TOL", "lies_on", "hidden_lines", "mark_coincident_lines",
           "section_lines_of_action", "plot_section", "force_track", "plot_equilibrium_tracks",
           "plot_moment_cycles", "default_amplitudes", "plot_stretched_cycles",
           "plot_complex_stiffness", "ZERO_BAR", "plot_energy", "FAMILY_PANELS",
           "plot_family_comparison"]
