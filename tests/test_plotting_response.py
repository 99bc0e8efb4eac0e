"""plotting.response.response_figure: both peaks drawn, the reduction annotated, styles explained once."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from jaxdamp import family_shape  # noqa: E402
from jaxdamp.plotting.response import response_figure  # noqa: E402
from jaxdamp.response import BladeMode, response_curves  # noqa: E402

MODE = BladeMode()


@pytest.mark.slow  # 14 worker-s (run of 2026-11-25)
def test_response_figure_shows_the_free_and_the_damped_peaks():
    forces = [2.0, 20.0]
    res = response_curves(family_shape("60sym"), 0.5, mode=MODE, force_n=forces,
                          method="interpolated")
    fig = response_figure(res, forces)
    ax = fig.axes[0]
    by_style = {}
    for line in ax.get_lines():
        by_style.setdefault(line.get_linestyle(), []).append(np.max(line.get_ydata()))
    # free (--) and stuck (-.) reach the linear resonance F / (eta k_b) of each force
    for style in ("--", "-."):
        assert sorted(by_style[style]) == pytest.approx(
            [f / (MODE.eta * MODE.k_b) for f in forces], rel=1e-6)
    damped = [float(a) for a in np.asarray(res.peaks.peak_amplitude_mm)]
    assert sorted(by_style["-"]) == pytest.approx(sorted(damped), rel=1e-6)
    notes = [t.get_text() for t in ax.texts]
    for f, a in zip(forces, damped):
        assert f"A*free/A* = {f / (MODE.eta * MODE.k_b) / a:.3g}" in notes
    legend_texts = [t.get_text() for leg in ax.findobj(matplotlib.legend.Legend)
                    for t in leg.get_texts()]
    for label in ("with the damper", "free (no damper)", "damper stuck"):
        assert legend_texts.count(label) == 1
