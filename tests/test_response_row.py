"""The forced response across a blade row (`jaxdamp.row_response`): nodal diameter 0 of an
in-phase family is the one-mode blade's response; at an elliptic engine order the peak solves the
first-harmonic peak equation with the damper's k from an independent elliptic cycle; bad
arguments are refused before anything is compiled."""

import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.response import BladeMode, design_peaks, nodal_scene, row_response
from jaxdamp.response.modes import ModalFamily, family_from_blade_mode
from jaxdamp.response.row import engine_orders_of

SHAPE = jd.family_shape("60sym")
Q, H_C, H_L = 100.0, 40.0, 30.0


def _row(n_blades=8):
    f = family_from_blade_mode(BladeMode(), Q, H_C, n_blades)
    n = n_blades // 2 + 1
    rep = lambda v: np.repeat(v, n, axis=0)  # noqa: E731
    return ModalFamily(n_blades, np.arange(n), 500.0 + 10.0 * np.arange(n), rep(f.loss_factor),
                       rep(f.modal_force), rep(f.response_displacement), rep(f.left_platform),
                       rep(f.right_platform), "test row")


def test_engine_order_specs():
    assert engine_orders_of("all", 8) == [0, 1, 2, 3, 4]
    assert engine_orders_of("2:5", 8) == [2, 3, 4, 5]
    assert engine_orders_of("1, 9", 8) == [1, 9]
    for bad in ("x", "3:", "-1", ""):
        with pytest.raises(ValueError, match="engine_order must be 'a:b', 'a,b,...' or 'all'"):
            engine_orders_of(bad, 8)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(engine_orders=[0], initial="steady"), "initial must be one of assembly, gross_slip"),
    (dict(engine_orders=[], initial="assembly"), "engine_orders must hold at least one"),
    (dict(engine_orders=[0], force_n=[-1.0]), "force_n must be"),
    (dict(engine_orders=[0], h_l_mm=0.0), "h_l must be"),
])
def test_bad_arguments_are_refused_before_any_work(kwargs, needle):
    args = dict(modes=_row(), force_n=[5.0], h_l_mm=H_L) | kwargs
    with pytest.raises(ValueError) as e:
        row_response(SHAPE, 0.5, **args)
    assert needle in str(e.value) and "\n" not in str(e.value)


@pytest.mark.slow  # two peak programs (the row's and design_peaks'), about 2 min to build
@pytest.mark.parametrize("initial", ["assembly"])
def test_nodal_diameter_zero_is_the_one_mode_blade(initial):
    """A family whose ND 0 platforms only turn about C gives today's BladeMode response: the same
    peaks (amplitude, frequency, psi) to 1e-10, through the path engine on the in-phase path."""
    mode = BladeMode(520.0, 650.0, 1.5e-3, 1.3)
    fam = family_from_blade_mode(mode, Q, H_C, 8)
    forces = np.array([3.0, 20.0])
    row = row_response(SHAPE, 0.5, modes=fam, engine_orders=[0], force_n=forces, h_l_mm=H_L,
                       initial=initial)
    ref = design_peaks(SHAPE, 0.5, mode=mode, force_n=forces, initial=initial)
    got = [row.peaks.peak_amplitude_mm[0], row.peaks.peak_frequency_hz[0], row.peaks.psi_a_mrad[0]]
    want = [np.asarray(ref.peak_amplitude_mm), np.asarray(ref.peak_frequency_hz),
            np.asarray(ref.psi_a_mrad)]
    assert_tree_allclose(got, want, rtol=1e-10, atol=0.0)
    assert list(row.status[0]) == [int(jd.RESULTS.ok)] * 2
    assert_tree_allclose(row.free_peak_mm[0], forces / (mode.eta * mode.k_b), rtol=1e-12, atol=0.0)


@pytest.mark.slow  # the elliptic peak program, about 2 min to build
def test_elliptic_peak_solves_the_peak_equation():
    """At the peak A* of an elliptic engine order, A* (eta k_b + 1e-3 r^2 k_Im(r A*)) = F_tip and
    f* = f0 sqrt(1 + 1e-3 r^2 k_Re(r A*) / k_b), with k from `elliptic_cycle` (the checked public
    cycle, called on its own) on the reduced path: the reduction and the peak search agree with
    the first-harmonic equation they solve."""
    fam = _row()
    forces = np.array([5.0, 20.0])
    row = row_response(SHAPE, 0.5, modes=fam, engine_orders=[3, 5], force_n=forces, h_l_mm=H_L)
    assert row.elliptic.tolist() == [True, True] and row.nodal_diameter.tolist() == [3, 3]
    for i, e in enumerate((3, 5)):
        s = nodal_scene(fam, e, Q, H_L)
        m = s.mode
        for j, force in enumerate(forces):
            a = float(row.peaks.peak_amplitude_mm[i, j])
            cyc = jd.elliptic_cycle(SHAPE, 0.5, m.r * a, s.motion)
            assert jd.RESULTS.valid(cyc.status)
            lhs = a * (m.eta * m.k_b + 1e-3 * m.r ** 2 * float(cyc.k_im))
            f = m.f0_hz * np.sqrt(1.0 + 1e-3 * m.r ** 2 * float(cyc.k_re) / m.k_b)
            assert_tree_allclose(np.array([lhs, row.peaks.peak_frequency_hz[i, j]]),
                                 np.array([force * s.force_per_unit, f]), rtol=1e-9, atol=0.0)
    # The two travelling directions of one nodal diameter see the ellipse run both ways: the
    # damper is not symmetric in them (the path couples rotation with dv), so the peaks differ.
    assert abs(row.peaks.peak_amplitude_mm[0, 0] - row.peaks.peak_amplitude_mm[1, 0]) > 1e-3


@pytest.mark.slow  # 10 s (2026-12-02): five programs
def test_the_row_bound_settles_the_slow_out_of_phase_cycle(monkeypatch):
    """Out-of-phase near gross slip a steady cycle can take 21 pairs of halves to settle by plain
    iteration (the in-phase robust optimum at mu 0.7 from gross slip, 32.7 mrad of the example
    disk's nodal diameter 12 path), past the straight kernel's 12: `path_cycle_kernel(...,
    repeats=)` lifts the bound for the row. Since the period map's two-mode extrapolation
    (ec33c44, `periodic.accelerate`) the default bound closes it too, on the cycle that the row's
    and a far larger bound close; the plain iteration (extrapolation off) closes on it within its
    closure tolerance (measured 1.1e-9 of |k|) and still needs more than 12 pairs."""
    import jax
    from jaxdamp import periodic
    from jaxdamp.modal_file import load_modal_family
    from jaxdamp.params import prepare_inputs
    from jaxdamp.response.peaks import PATH_REPEATS
    from jaxdamp.response.stiffness import path_cycle_kernel

    shape = jd.DamperShape(42.59891282213617, 52.95829312005082, 0.3988034770924406,
                           0.8876839281573497)
    motion = nodal_scene(load_modal_family("example"), 12, 100.0, 10.0).motion
    design = prepare_inputs(shape, 0.7, jd.Contacts(), jd.LoadCase())

    def run(n):  # traced anew: the patched extrapolation below is seen
        return jax.jit(lambda a: path_cycle_kernel(*design, a, motion, "gross_slip", "while",
                                                   n))(32.69186086263253)

    default, row, far = (run(n) for n in (None, PATH_REPEATS, 256))
    assert [jd.RESULTS.name_of(r[2]) for r in (default, row, far)] == ["ok"] * 3
    assert_tree_allclose(default[:2], far[:2], rtol=1e-13, atol=0)
    assert_tree_allclose(row[:2], far[:2], rtol=1e-13, atol=0)
    monkeypatch.setattr(periodic, "accelerate", lambda mu, starts, there, plain: (
        there, jax.numpy.zeros((), bool)))  # the plain iteration
    plain_default, plain_row = run(None), run(PATH_REPEATS)
    assert jd.RESULTS.name_of(plain_default[2]) == "not_converged"
    assert jd.RESULTS.name_of(plain_row[2]) == "ok"
    scale = float(np.hypot(*far[:2]))
    assert_tree_allclose(plain_row[:2], far[:2], rtol=0, atol=1e-8 * scale)
