"""The k(psi_a) figure from exact cycles (jaxdamp.plotting.amplitude): data and drawing."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.plotting.amplitude import amplitude_stiffness_data, plot_amplitude_stiffness  # noqa: E402


def test_figure_data_and_panels():
    shape, mu, contacts = jd.family_shape("60sym"), 0.5, jd.Contacts(17900.0, 3580.0)
    psi = np.array([0.3, 1.2, 3.0, 6.0])
    d = amplitude_stiffness_data(shape, mu, contacts, psi_a_mrad=psi)
    assert d["gross_slip"][1][1] > d["assembly"][1][1] > 0  # 2033 vs 1793 at 1.2 mrad
    # Above psi_BC the exact curves are the paper's (the stretched Base-Cycle).
    for initial in ("gross_slip", "assembly"):
        np.testing.assert_allclose(np.asarray(d[initial])[:, 2:], np.asarray(d["interpolated"])[:, 2:],
                                   rtol=1e-9)
    d["band"] = (psi, np.stack([d["gross_slip"][0], d["gross_slip"][0], np.zeros(4),
                                d["gross_slip"][1]], axis=1))
    fig = plot_amplitude_stiffness(shape, mu, data=d, title="60sym")
    assert len(fig.axes) == 2 and fig.axes[1].get_legend() is not None
