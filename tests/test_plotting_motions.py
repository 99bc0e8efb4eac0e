"""The interblade-phase-angle figure (jaxdamp.plotting.plot_ibpa_claim) on hand-made data."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from jaxdamp.plotting import plot_ibpa_claim  # noqa: E402


def _curve(damper, pads, mu, a, opened, status=None):
    phis = [0.0, 90.0, 180.0]
    status = status or ["ok"] * 3
    return {"damper": damper, "pads": pads, "mu": mu, "amplitude_mrad": a,
            "rows": [{"ibpa_deg": p, "status": s, "k_im_over_in_phase": 1.0 - p / 360.0,
                      "open_fraction": o} for p, s, o in zip(phis, status, opened)]}


def test_the_figure_draws_damping_ratios_open_pads_and_failures():
    curves = [_curve("60sym", ["R1", "L1", "L2"], 0.5, 10.0, [[0.0] * 3] * 3),
              _curve("wedge", ["R1", "R2", "L1", "L2"], 0.5, 10.0,
                     [[0.0] * 4, [0.3, 0.0, 0.0, 0.0], [0.2, 0.1, 0.0, 0.0]],
                     status=["ok", "ok", "unseated"])]
    fig = plot_ibpa_claim(curves)
    try:
        top, bottom = fig.axes[0], fig.axes[1]
        assert len(fig.axes) == 2
        labels = [line.get_label() for line in top.get_lines()]
        assert "60sym, a = 10 mrad" in labels and "wedge, a = 10 mrad" in labels
        wedge = next(line for line in top.get_lines() if line.get_label() == "wedge, a = 10 mrad")
        assert np.isnan(wedge.get_ydata()[-1])  # no valid cycle: no ratio drawn
        failures = [line for line in top.get_lines() if line.get_marker() == "x"]
        assert len(failures) == 1 and list(failures[0].get_xdata()) == [180.0]
        open_lines = [line.get_label() for line in bottom.get_lines()]
        assert open_lines == ["wedge R1, a = 10 mrad"]  # R2 opens only where the cycle failed
        notes = [t.get_text() for t in bottom.texts]
        assert notes == ["no pad opens: 60sym"]
    finally:
        plt.close(fig)
