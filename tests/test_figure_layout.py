"""Figure layout: every figure the study writes is rendered and its text checked for collisions.

A text here is any title, axis label, visible tick label, annotation, free text or legend (a legend
counts as one box). After `fig.canvas.draw()` each text's window extent (pixels) must
- lie inside the figure (no clipped title, label or legend),
- lie inside its axes when it is drawn in the axes (annotations, point labels, panel notes),
- not overlap any other text of the figure,
- not be crossed by a line or an arrow of its axes (a label sitting on the F_D arrow, "F≡0" crossed
  by a friction line), unless the text has an opaque background box drawn above the line,
and no marker may hide under a legend drawn inside the axes. Nothing is excluded: a failure is
fixed in the figure's layout.

The figures come from `jaxdamp.plotting.study.study_figures`, the code that writes the study's PNGs, for the
five shapes at mu = 0.7 and 0.3 (74L lifts off at 0.7: its placeholder panels are covered too).
"""

import matplotlib
import numpy as np
import pytest
from matplotlib.lines import Line2D
from matplotlib.patches import FancyArrowPatch
from matplotlib.text import Annotation

from jaxdamp.geometry import paper_tables
from jaxdamp.params import REFERENCE_KN, REFERENCE_KT, Contacts, LoadCase
from jaxdamp.paper.scoring import score_table
from jaxdamp.paper.study import DEFAULT_SHAPES, compute_cases, result_entry
from jaxdamp.plotting.study import study_figures

TOL_PX = 1.0  # boxes that merely touch (anti-aliasing) are not an overlap


def _shrunk(bb, d=TOL_PX):
    return matplotlib.transforms.Bbox.from_extents(bb.x0 + d, bb.y0 + d, bb.x1 - d, bb.y1 - d)


def _inside(inner, outer, d=TOL_PX):
    return (inner.x0 >= outer.x0 - d and inner.y0 >= outer.y0 - d and inner.x1 <= outer.x1 + d
            and inner.y1 <= outer.y1 + d)


def _all_axes(fig):
    """[(axes, name)]: every axes with its secondary axes (the µm scale on top)."""
    out = []
    for ax in fig.axes:
        out.append((ax, ax.get_title() or ax.get_label() or "axes"))
        out += [(c, out[-1][1] + ", top axis") for c in ax.child_axes if c.get_visible()]
    return out


def _shown(t):
    return t.get_visible() and t.get_text().strip() != ""


def _tick_labels(axis):
    lo, hi = sorted(axis.get_view_interval())
    span = hi - lo
    out = []
    for tick in axis.get_major_ticks() + axis.get_minor_ticks():
        if not (lo - 1e-9 * span <= tick.get_loc() <= hi + 1e-9 * span):
            continue
        out += [lab for lab in (tick.label1, tick.label2) if _shown(lab)]
    return out


def texts_of(fig):
    """[(name, artist, axes or None, in_axes)] for every visible text of the figure."""
    out = [(f"figure text {t.get_text()!r}", t, None, False) for t in fig.texts if _shown(t)]
    out += [(f"figure legend {k}", leg, None, False) for k, leg in enumerate(fig.legends)]
    for ax, where in _all_axes(fig):
        if not ax.get_visible():
            continue
        for t in (ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label):
            if _shown(t):
                out.append((f"[{where}] label {t.get_text()!r}", t, ax, False))
        for axis in (ax.xaxis, ax.yaxis):
            out += [(f"[{where}] tick {t.get_text()!r}", t, ax, False) for t in _tick_labels(axis)]
        out += [(f"[{where}] text {t.get_text()!r}", t, ax, True) for t in ax.texts if _shown(t)]
        leg = ax.get_legend()
        if leg is not None and leg.get_visible():
            out.append((f"[{where}] legend", leg, ax, False))
    return out


def _opaque_box_above(text, artist):
    """A text on an opaque box drawn above a thin line stays readable; an arrow is never hidden."""
    patch = text.get_bbox_patch()
    return (isinstance(artist, Line2D) and patch is not None and patch.get_facecolor()[3] >= 0.75
            and text.get_zorder() > artist.get_zorder())


def _crossers(ax):
    """Lines (data and reference lines) and annotation arrows drawn in the axes."""
    out = [ln for ln in ax.get_lines() if ln.get_visible() and len(ln.get_xdata()) > 0]
    out += [p for p in ax.patches if isinstance(p, FancyArrowPatch)]
    out += [t.arrow_patch for t in ax.texts if isinstance(t, Annotation) and t.arrow_patch is not None]
    return out


def _crosses(artist, bb):
    if isinstance(artist, Line2D):
        xy = artist.get_transform().transform(np.column_stack([artist.get_xdata(), artist.get_ydata()]))
        if artist.get_marker() not in (None, "None", "", " "):
            r = artist.get_markersize() / 2 * artist.figure.dpi / 72.0
            grown = matplotlib.transforms.Bbox.from_extents(bb.x0 - r, bb.y0 - r, bb.x1 + r, bb.y1 + r)
            if grown.count_contains(xy) > 0:
                return True
        if artist.get_linestyle() in ("None", "", " ") or len(xy) < 2:
            return False
        return matplotlib.path.Path(xy).intersects_bbox(bb, filled=False)
    return artist.get_transform().transform_path(artist.get_path()).intersects_bbox(bb, filled=False)


def layout_problems(fig):
    """Every text collision of a rendered figure, as readable strings (empty: the layout is clean)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = [(n, a, ax, ins, a.get_window_extent(renderer)) for n, a, ax, ins in texts_of(fig)]
    problems = []
    for name, art, ax, in_axes, bb in texts:
        if not _inside(bb, fig.bbox):
            problems.append(f"{name} leaves the figure")
        if in_axes and not _inside(bb, ax.bbox):
            problems.append(f"{name} leaves its axes")
    for i, (n1, _, _, _, b1) in enumerate(texts):
        for n2, _, _, _, b2 in texts[i + 1:]:
            if _shrunk(b1).overlaps(_shrunk(b2)):
                problems.append(f"{n1} overlaps {n2}")
    for name, art, ax, in_axes, bb in texts:
        if not in_axes:
            continue
        for other in _crossers(ax):
            if other is getattr(art, "arrow_patch", None) or _opaque_box_above(art, other):
                continue
            if _crosses(other, _shrunk(bb)):
                problems.append(f"{name} is crossed by {other.get_label() or type(other).__name__}")
    for ax, where in _all_axes(fig):
        leg = ax.get_legend()
        if leg is None or not _inside(leg.get_window_extent(renderer), ax.bbox):
            continue
        bb = leg.get_window_extent(renderer)
        for ln in ax.get_lines():
            if ln.get_visible() and ln.get_marker() not in (None, "None", "", " ") and len(ln.get_xdata()):
                xy = ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
                inside = [p for p in xy if _inside(matplotlib.transforms.Bbox([p, p]), bb, d=0.0)
                          and _inside(matplotlib.transforms.Bbox([p, p]), ax.bbox, d=0.0)]
                if inside:
                    problems.append(f"[{where}] legend hides a marker of {ln.get_label()!r}")
    return problems


@pytest.fixture(scope="module")
def study_inputs():
    """Cycles and summaries of the five shapes at mu = 0.7 and 0.3 (one compilation, reused)."""
    ref = paper_tables()["reference_case"]
    load = LoadCase(ref["F_D"], ref["q_star"], ref["r_sin_beta"])
    mus = (0.7, 0.3)
    cycles, summaries, _, _ = compute_cases(DEFAULT_SHAPES, mus, Contacts(REFERENCE_KN, REFERENCE_KT), load)
    results = {s: {m: result_entry(c) for m, c in per.items()} for s, per in summaries.items()}
    summary = {"results": results, "energies": {s: {m: c.energy_Nmm for m, c in per.items()}
                                                for s, per in summaries.items()},
               "load": {"q_star": float(load.q_star)}, "meta": {"mus": [f"{m:g}" for m in mus]},
               "scores": score_table(results)}
    return cycles, summaries, summary


@pytest.mark.slow  # 21 worker-s (run of 2026-11-25)
def test_every_study_figure_has_a_clean_layout(study_inputs):
    import matplotlib.pyplot as plt

    cycles, summaries, summary = study_inputs
    seen, problems = [], []
    for fig, name, _, _ in study_figures(cycles, summaries, summary):
        seen.append(name)
        problems += [f"{name}: {p}" for p in layout_problems(fig)]
        plt.close(fig)
    kinds = ("section", "tracks", "moment", "stretched", "stiffness")
    assert set(seen) == {f"{k}_{s}.png" for k in kinds for s in DEFAULT_SHAPES} | {
        "energy.png", "family.png", "key_figure.png"}
    assert not problems, "\n".join(problems)


def test_the_checker_sees_overlaps_and_clipping():
    """The checker itself: two texts on one spot, a title cut at the figure edge, a label on a line."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0, 1], [0, 1], label="diagonal")
    ax.text(0.5, 0.5, "first")
    ax.text(0.5, 0.5, "second")
    ax.set_title("a title far too long to fit into a figure only four inches wide at all")
    found = "\n".join(layout_problems(fig))
    plt.close(fig)
    assert "'first' overlaps" in found and "leaves the figure" in found and "crossed by diagonal" in found


@pytest.mark.slow  # 17 worker-s (2026-11-26); test_cli_sweep draws the heatmaps
def test_sweep_heatmap_has_a_clean_layout():
    """`jaxdamp sweep`'s heatmap: suptitle inside the figure, the paper's shapes on the map's edges
    (90L at theta_L = 90, 90R at theta_R = 90) labelled inside their panels."""
    import numpy as np

    from jaxdamp.batch import sweep
    from jaxdamp.plotting.sweep import heatmap_figure

    # Centred b_R (the longest suptitle), a 4 x 4 grid with the family's corners.
    res = sweep(np.linspace(40.0, 90.0, 4), np.linspace(40.0, 90.0, 4), [0.7, 0.3])
    problems = layout_problems(heatmap_figure(res))
    assert not problems, "\n".join(problems)


def test_no_study_figure_hides_a_curve(study_inputs):
    """Two curves drawn identically on top of each other (or one along another: 90R's moment cycle
    at mu = 0.7 runs along the mu = 0.5 one) get distinct markers and a note: no line is hidden."""
    import matplotlib.pyplot as plt

    from jaxdamp.plotting.labels import hidden_lines

    cycles, summaries, summary = study_inputs
    hidden, noted = [], []
    for fig, name, _, _ in study_figures(cycles, summaries, summary):
        for ax in fig.axes:
            hidden += [f"{name}: {a.get_label()!r} under {b.get_label()!r}" for a, b in hidden_lines(ax)]
            noted += [f"{name}: {ln.get_label()}" for ln in ax.get_lines() if "(dashed: on " in ln.get_label()]
        plt.close(fig)
    assert not hidden, "\n".join(hidden)
    assert noted  # some of the study's curves do lie on others (90R's): they were found and marked


def test_lies_on_needs_every_point_within_the_tolerance():
    import numpy as np

    from jaxdamp.plotting.labels import COINCIDENT_TOL, lies_on

    polyline = np.array([[0.0, 0.0], [0.5, 0.5], [1.0, 0.0]])
    on = np.array([[0.1, 0.1], [0.25, 0.25], [0.5, 0.5], [0.75, 0.25], [0.9, 0.1]] * 4)
    assert lies_on(on, polyline)
    assert lies_on(on + [0.0, 0.9 * COINCIDENT_TOL], polyline)
    assert not lies_on(on + [0.0, 2.0 * COINCIDENT_TOL], polyline)
    # one point off the curve but inside its box, where a spread subset of the points misses it
    off = on.copy()
    off[7] = [0.5, 0.2]
    assert not lies_on(off, polyline)
    assert not lies_on(on[:1] + [2.0, 0.0], polyline)  # outside the polyline's box
    assert not lies_on(on[:0], polyline) and not lies_on(on, polyline[:1])

def test_hidden_line_checker_and_the_90R_moment_cycles():
    import matplotlib.pyplot as plt

    import jaxdamp as jd
    from jaxdamp.plotting.figures import plot_moment_cycles
    from jaxdamp.plotting.labels import hidden_lines

    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0, 1, 2], "-o", color="C0", label="a")
    ax.plot([0, 2], [0, 2], "-o", color="C1", label="b")  # covers a exactly (a's vertices on it)
    ax.plot([0, 1], [1, 0], "-o", label="c")
    assert [(a.get_label(), b.get_label()) for a, b in hidden_lines(ax)] == [("a", "b")]
    plt.close(fig)
    bcs = [jd.base_cycle(jd.family_shape("90R"), m) for m in (0.7, 0.5)]
    fig = plot_moment_cycles(bcs)
    ax = fig.axes[0]
    assert hidden_lines(ax) == []
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert "μ = 0.7: ψ_BC = 0.436 mrad (dashed: on μ = 0.5)" in labels
    assert any("(dashed: on μ = 0.5)" in t.get_text() for t in ax.get_legend().get_texts())
    plt.close(fig)
