"""The k(psi_a) figure from exact cycles (jaxdamp.plotting.amplitude): data and drawing."""

import matplotlib
import pytest

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.plotting.amplitude import amplitude_stiffness_data, plot_amplitude_stiffness  # noqa: E402

from helpers import assert_tree_allclose


@pytest.mark.slow  # 14 worker-s (run of 2026-11-25)
def test_figure_data_and_panels():
    shape, mu, contacts = jd.family_shape("60sym"), 0.5, jd.Contacts(17900.0, 3580.0)
    psi = np.array([0.3, 1.2, 3.0, 6.0])
    d = amplitude_stiffness_data(shape, mu, contacts, psi_a_mrad=psi)
    assert d["gross_slip"][1][1] > d["assembly"][1][1] > 0  # 2033 vs 1793 at 1.2 mrad
    # Above psi_BC the exact curves are the paper's (the stretched Base-Cycle).
    for initial in ("gross_slip", "assembly"):
        assert_tree_allclose(np.asarray(d[initial])[:, 2:], np.asarray(d["interpolated"])[:, 2:],
                             rtol=1e-9, atol=0.0)
    d["band"] = (psi, np.stack([d["gross_slip"][0], d["gross_slip"][0], np.zeros(4),
                                d["gross_slip"][1]], axis=1))
    fig = plot_amplitude_stiffness(shape, mu, data=d, title="60sym")
    assert len(fig.axes) == 2 and fig.axes[1].get_legend() is not None


@pytest.mark.slow  # 30 worker-s (run of 2026-11-25)
def test_psi_labels_are_greek_and_clear_of_the_curves():
    """ψ_fs and ψ_BC (Greek, as in the other figures) sit where no curve passes (the study's
    amplitude_stiffness figures had ψ_fs on the k_Re curve, which peaks there)."""
    shape, mu = jd.family_shape("60sym"), 0.5
    d = amplitude_stiffness_data(shape, mu)
    fig = plot_amplitude_stiffness(shape, mu, data=d)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        assert ax.get_xlabel() == "ψ_a (mrad)"
        notes = [t for t in ax.texts if t.get_text() in ("ψ_fs", "ψ_BC")]
        assert sorted(t.get_text() for t in notes) == ["ψ_BC", "ψ_fs"]
        assert not any("psi" in t.get_text() for t in ax.texts)
        for t in notes:
            box = t.get_bbox_patch().get_window_extent(renderer)
            for ln in ax.get_lines():
                x, y = (np.asarray(v, float) for v in ln.get_data())
                if x.size < 3:  # the dotted verticals the labels stand on
                    continue
                fine = np.linspace(x.min(), x.max(), 4000)
                pts = ax.transData.transform(np.stack([fine, np.interp(fine, x, y)], -1))
                inside = ((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0)
                          & (pts[:, 1] <= box.y1))
                assert not inside.any(), (t.get_text(), ln.get_label())
