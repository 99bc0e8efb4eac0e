"""The row's designer's diagram (`jaxdamp.row_diagram`): its mass curve against rows computed at
the scaled F_D itself (the scaling law is the diagram's shortcut, the direct rows are not), its
force curve against the row's own peaks, and its inputs checked before any work."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.modal_file import load_modal_family

from helpers import assert_tree_allclose

ORDERS = [0, 12]  # both straight: one program


@pytest.mark.slow  # the straight row program (about a minute) and three rows
def test_the_mass_curve_is_the_row_at_the_scaled_f_d():
    """At F = 5 N and F_D scaled by 0.5 and 2, the diagram's worst A*/F over the row equals the
    worst of a row computed with F_D = 500 and 2000 N (`LoadCase`), and its engine order; the
    force curve at the nominal F_D is the row's largest valid A*/F per force."""
    family = load_modal_family("example")
    shape = jd.family_shape("60sym")
    dd = jd.row_diagram(shape, 0.5, modes=family, engine_orders=ORDERS, h_l_mm=10.0,
                        force_n=[2.0, 20.0], fd_factor=[0.5, 2.0], force_at_fd_n=5.0)
    for k, s in enumerate(dd.fd_factor):
        row = jd.row_response(shape, 0.5, load=jd.LoadCase(F_D=1000.0 * s), modes=family,
                              engine_orders=ORDERS, force_n=[5.0], h_l_mm=10.0)
        valid = np.asarray(jd.RESULTS.valid(row.status[:, 0]))
        mag = np.where(valid, row.peaks.peak_amplitude_mm[:, 0] / 5.0, -np.inf)
        assert_tree_allclose(np.float64(dd.worst_vs_fd_mm_per_n[k]), np.float64(mag.max()),
                             rtol=1e-7, atol=0.0)
        assert int(dd.engine_order_vs_fd[k]) == ORDERS[int(np.argmax(mag))]
        assert int(dd.status_vs_fd[k]) == int(jd.RESULTS.worst(row.status[:, 0]))
    row = dd.row
    for j, f in enumerate(dd.force_n):
        col = int(np.flatnonzero(row.force_n == f)[0])
        valid = np.asarray(jd.RESULTS.valid(row.status[:, col]))
        want = np.max(np.where(valid, row.peaks.peak_amplitude_mm[:, col] / f, -np.inf))
        assert float(dd.worst_vs_force_mm_per_n[j]) == pytest.approx(float(want), rel=1e-12)
    assert "RowDiagram(" in repr(dd) and "\n" not in repr(dd)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(fd_factor=[0.5, -1.0]), "fd_factor must be in (0, inf)"),
    (dict(fd_factor=[[0.5]]), "fd_factor must be a number or a 1-D sequence"),
    (dict(force_at_fd_n=0.0), "force_at_fd_n must be"),
    (dict(force_n="2"), "force_n must be a number or a 1-D sequence"),
    (dict(h_l_mm=-1.0), "h_l must be"),
])
def test_bad_inputs_are_refused_before_any_work(kwargs, needle):
    args = dict(modes=load_modal_family("example"), engine_orders=ORDERS, h_l_mm=10.0,
                force_n=[2.0], fd_factor=[1.0], force_at_fd_n=5.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=needle.replace("(", r"\(").replace(")", r"\)")):
        jd.row_diagram(jd.family_shape("60sym"), 0.5, **args)
