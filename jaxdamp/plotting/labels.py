"""What keeps a figure readable: point labels that find a free spot next to their anchor once
the layout is final (`AutoLabel`, `point_label`), and curves that lie on another one found and
marked, so that no curve hides under another unseen (`mark_coincident_lines`)."""

from __future__ import annotations

import matplotlib
import numpy as np

__all__ = ["COINCIDENT_MARKERS", "COINCIDENT_TOL", "lies_on", "hidden_lines",
           "mark_coincident_lines", "AutoLabel", "point_label"]


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
    # Most pairs of curves are apart: outside the polyline's box, or a few spread points off it,
    # decides before the all-points-to-all-segments distances (a study's figures test ~800 pairs).
    lo, hi = polyline.min(axis=0) - tol, polyline.max(axis=0) + tol
    if np.any(points < lo) or np.any(points > hi):
        return False
    a, b = polyline[:-1], polyline[1:]
    d = b - a
    dd = np.maximum(np.einsum("sk,sk->s", d, d), 1e-300)

    def within(p):
        t = np.clip(np.einsum("psk,sk->ps", p[:, None, :] - a[None], d) / dd, 0.0, 1.0)
        nearest = a[None] + t[..., None] * d[None]
        return bool(np.all(np.min(np.linalg.norm(p[:, None, :] - nearest, axis=-1), axis=1) <= tol))

    return within(points[:: max(len(points) // 8, 1)]) and within(points)


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


class AutoLabel(matplotlib.text.Annotation):
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
                 if not isinstance(t, AutoLabel) and t.get_visible() and t.get_text().strip()]
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
                      if isinstance(t, AutoLabel) and t is not self and t.get_visible()]
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


def point_label(ax, text, xy, prefer=(0.0, 1.0), **kw):
    """A point label at xy (data) that moves to a free spot next to it when drawn (`AutoLabel`)."""
    lab = AutoLabel(text, xy, prefer=prefer, **kw)
    ax._add_text(lab)
    return lab
