"""Figures: each function returns a labelled Figure, and what it draws is checked independently."""

import subprocess
import sys

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import plotting as P
from jaxdamp.summary import moment_polyline, numeric_first_harmonic, stiffness_at

from helpers import assert_tree_allclose


@pytest.fixture(scope="module")
def cycles():
    """60sym at the three mu, 74R at 0.7, 74L at 0.5 and at 0.7 (liftoff)."""
    out = {("60sym", m): jd.base_cycle(jd.family_shape("60sym"), m) for m in (0.7, 0.5, 0.3)}
    out[("74R", 0.7)] = jd.base_cycle(jd.family_shape("74R"), 0.7)
    out[("74L", 0.5)] = jd.base_cycle(jd.family_shape("74L"), 0.5)
    out[("74L", 0.7)] = jd.base_cycle(jd.family_shape("74L"), 0.7)
    return out


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _labelled(fig, x_units=True):
    axes = [a for a in fig.axes if a.get_visible() and a.get_label() != "<colorbar>"]
    main = [a for a in axes if a.get_xlabel() and a.get_ylabel()]
    assert main, "no axes with both labels"
    for a in main:
        assert "(" in a.get_ylabel() and ("(" in a.get_xlabel() or not x_units), "axis labels need units"
        assert a.get_title()
    return main


def test_tests_draw_headless_with_agg():
    assert matplotlib.get_backend().lower() == "agg"  # chosen by conftest.py, as the CLI does


def test_importing_plotting_chooses_no_backend():
    code = ("import os; os.environ.pop('MPLBACKEND', None); import matplotlib, jaxdamp.plotting; "
            "print(matplotlib.rcParams._get_backend_or_none())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "None"


def test_section_lines_of_action_meet_on_the_line_of_FD():
    """Three-force equilibrium: F_R1, the left resultant and F_D are concurrent (Fig. 7)."""
    for name in ("60sym", "74R", "90L", "90R"):
        for mu in (0.7, 0.3):
            for end in ("start", "mid"):
                d = P.section_lines_of_action(jd.family_shape(name), mu, end)
                assert d["X"][0] == pytest.approx(d["D"][0], abs=1e-9), (name, mu, end)
                # The left resultant plus F_R1 balances F_D = 1 (upward).
                assert_tree_allclose(d["F_L"] + d["F"][0], np.array([0.0, -1.0]), rtol=1e-7, atol=1e-12)


def test_section_resultant_position_matches_table_1(paper):
    row = paper["table_1_60sym_resultant_distance"]["rows"][0]
    start = P.section_lines_of_action(jd.family_shape("60sym"), row["mu"], "start")
    mid = P.section_lines_of_action(jd.family_shape("60sym"), row["mu"], "mid")
    assert start["pos_pct"] == pytest.approx(row["dist_L1"], abs=0.06)
    assert 100 - mid["pos_pct"] == pytest.approx(row["dist_L2"], abs=0.06)


def test_plot_section_figure_and_liftoff_title():
    fig = P.plot_section(jd.family_shape("60sym"), 0.7)
    assert len(_labelled(fig)) == 2
    fig = P.plot_section(jd.family_shape("74L"), 0.7, end="start")
    assert "LIFTOFF" in fig.axes[0].get_title()
    with pytest.raises(ValueError, match="end must be"):
        P.plot_section(jd.family_shape("60sym"), 0.7, end="middle")


def test_force_track_starts_and_turns_at_the_full_slip_statics(cycles):
    """The track point is -F_L: at 0 it is the cycle-start full slip, at C the mid-cycle one."""
    bc = cycles[("60sym", 0.7)]
    track, sec, labels = P.force_track(bc)
    st = jd.full_slip_statics(jd.family_shape("60sym"), 0.7)
    geo = jd.blocks.section_geometry(jd.family_shape("60sym"))
    n, t = np.asarray(geo.normals), np.asarray(geo.tangents)

    def minus_left(state):
        F = -np.asarray(state.N)[:, None] * n + np.asarray(state.T)[:, None] * t
        return -(F[1] + F[2]), -F[1]

    p0, l0 = minus_left(st.start)
    pc, _ = minus_left(st.mid)
    assert_tree_allclose(track[0], p0, rtol=1e-7, atol=1e-9)
    assert_tree_allclose(sec[0], l0, rtol=1e-7, atol=1e-9)
    assert_tree_allclose(track[-1], track[0], rtol=1e-7, atol=1e-9)  # F = 0: the cycle closes
    assert labels[3] == "C"
    assert_tree_allclose(track[3], pc, rtol=1e-7, atol=1e-9)


def test_plot_equilibrium_tracks_marks_liftoff(cycles):
    bcs = [cycles[("74L", 0.7)], cycles[("74L", 0.5)]]
    fig = P.plot_equilibrium_tracks(bcs)
    assert len(fig.axes) == 2
    assert any("LIFTOFF" in t.get_text() for t in fig.axes[0].texts)
    _labelled(fig)
    assert fig.legends, "shared legend"


def test_moment_polyline_point_names_follow_the_paper(cycles):
    """60sym closes exactly (F = 0), 74R has the mid-cycle stretch C-C′, 74L at 0.5 the F-0 stretch."""
    _, _, names = moment_polyline(cycles[("60sym", 0.7)])
    assert names == ["0", "A", "B", "C", "D", "E", "F≡0"]
    _, _, names = moment_polyline(cycles[("74R", 0.7)])
    assert names[:5] == ["0", "A", "B", "C", "C\u2032"]  # the paper's C′, not "C2"
    _, _, names = moment_polyline(cycles[("74L", 0.5)])
    assert names[-2:] == ["F", "0"]


@pytest.mark.parametrize("key", [("60sym", 0.7), ("74R", 0.7), ("74L", 0.5)])
def test_polyline_fourier_and_area_agree_with_closed_form(cycles, key):
    """Numerical Fourier sums of the drawn polyline reproduce complex_stiffness, and its enclosed
    area (shoelace, N mm mrad) equals pi psi_a^2 k_Im (the cycle identity)."""
    bc = cycles[key]
    psi_bc = max(float(bc.forward.span), float(bc.backward.span)) / (2 * float(bc.load.q_star)) * 1e3
    k_ref = stiffness_at(bc, [psi_bc, 2.0 * psi_bc])  # complex_stiffness, jit-compiled once
    for j, psi_a in enumerate((psi_bc, 2.0 * psi_bc)):
        psi, M, _ = moment_polyline(bc, psi_a)
        assert psi.max() == pytest.approx(psi_a) and psi.min() == pytest.approx(-psi_a)
        _, k_re, k_im = numeric_first_harmonic(psi, M, psi_a, n=1 << 14)
        ref_re, ref_im = float(k_ref[0][j]), float(k_ref[1][j])
        assert k_re == pytest.approx(ref_re, rel=1e-4)
        assert k_im == pytest.approx(ref_im, rel=1e-4)
        area = 0.5 * np.sum(psi[:-1] * M[1:] - psi[1:] * M[:-1])
        assert abs(area) == pytest.approx(np.pi * psi_a**2 * ref_im, rel=1e-9)


def test_default_amplitudes_are_the_papers_fig_14(cycles):
    """Fig. 14 (60sym, mu = 0.7) stretches the Base-Cycle to 3, 4 and 6 mrad."""
    amps = P.default_amplitudes(cycles[("60sym", 0.7)])
    assert amps[1:] == [3.0, 4.0, 6.0]


def test_moment_stretched_and_stiffness_figures(cycles):
    bcs = [cycles[("60sym", m)] for m in (0.7, 0.5, 0.3)]
    fig = P.plot_moment_cycles(bcs + [cycles[("74L", 0.7)]])
    (ax,) = [a for a in _labelled(fig)]
    labels = ax.get_legend_handles_labels()[1]
    assert any("LIFTOFF" in s for s in labels) and len(ax.get_lines()) >= 3
    fig = P.plot_stretched_cycles(bcs[0])
    (ax,) = _labelled(fig)
    assert sum(line.get_linestyle() == ":" for line in ax.get_lines()) >= 4  # one ellipse per cycle
    fig = P.plot_stretched_cycles(cycles[("74L", 0.7)])
    assert any("LIFTOFF" in t.get_text() for t in fig.axes[0].texts)
    fig = P.plot_complex_stiffness(bcs, labels=["a", "b", "c"])
    ax, zoom = _labelled(fig)
    assert ax.get_xlim() == (0.0, 20.0)
    # The zoom panel spans the microslip range: up to 1.6 times the largest psi_BC.
    psi_bc = max(P.default_amplitudes(bc)[0] for bc in bcs)
    assert zoom.get_xlim() == pytest.approx((0.0, 1.6 * psi_bc))
    assert any(s.startswith("a: k_Re") for s in ax.get_legend_handles_labels()[1])


def _results():
    e = {"psi_fs_mrad": 0.6, "k_re_fs": 28000.0, "psi_bc_mrad": 2.5, "k_re_bc": 22000.0, "k_im_bc": 4500.0,
         "w_R1": 1.0, "w_L1": 0.6, "w_L2": 0.4, "w_M": 2.0, "liftoff": False, "converged": True}
    lift = {k: None for k in e} | {"liftoff": True, "converged": False}
    return {"60sym": {"0.7": e, "0.5": e}, "74L": {"0.7": lift, "0.5": e}}


def test_energy_and_family_figures_mark_liftoff():
    res = _results()
    energies = {s: {m: {"R1": 1.0, "L1": 2.0, "L2": 3.0, "M": 6.0} for m in per} for s, per in res.items()}
    fig = P.plot_energy(res, energies)
    assert len(fig.axes) == 4
    _labelled(fig, x_units=False)  # x: shape names
    assert any(t.get_text() == "LIFTOFF" for t in fig.axes[0].texts)
    fig = P.plot_family_comparison(res, paper={"60sym": {"0.7": {"k_re_fs": 28741.0}}})
    assert len(_labelled(fig, x_units=False)) == 6
    assert any(t.get_text() == "liftoff" for a in fig.axes for t in a.texts)


def test_energy_figure_labels_empty_bars_0_and_says_where_energy_is_taken():
    """A shape whose cycle dissipates nothing (bars empty) is labelled 0; the energy row says that
    each shape's energy is taken at its own psi_BC."""
    import matplotlib.pyplot as plt

    from jaxdamp.plotting.figures import plot_energy

    w = {"w_R1": 0.2, "w_L1": 0.3, "w_L2": 0.1, "w_M": 0.6, "liftoff": False}
    zero = {"w_R1": 0.0, "w_L1": 0.0, "w_L2": 0.0, "w_M": 0.0, "liftoff": False}
    results = {"60sym": {"0.7": w}, "90R": {"0.7": zero}}
    energies = {"60sym": {"0.7": {"R1": 10.0, "L1": 20.0, "L2": 5.0, "M": 35.0}},
                "90R": {"0.7": {"R1": 0.0, "L1": 0.0, "L2": 0.0, "M": 0.0}}}
    fig = plot_energy(results, energies)
    for ax in fig.axes:
        zeros = [t for t in ax.texts if t.get_text() in ("0", "≈0")]
        assert len(zeros) == 1 and zeros[0].get_position()[0] == 1  # under 90R only
    assert "each shape at its own ψ_BC" in fig.axes[1].get_title()
    plt.close(fig)
