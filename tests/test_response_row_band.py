"""The band over contact histories on a platform path and across a blade row (`band_kernel` with a
motion, `jaxdamp.row_band`): every history's cycle and peak lies inside it, its bounds are the
cycles of admissible states that the public elliptic cycle reproduces, on the in-phase path it is
the in-phase band's samples, and past gross slip (where every history gives the same cycle) it
closes to its bracket's resolution."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.admissible import admissible_samples
from jaxdamp.band import band_kernel, state_cycle
from jaxdamp.baselines.lumped_disk import LumpedDisk, modal_family
from jaxdamp.modal_file import load_modal_family
from jaxdamp.response.modes import nodal_scene
from jaxdamp.residual import through_residual
from jaxdamp.response.row_band import BISECTIONS, TABLE_DECADES, TABLE_POINTS
from jaxdamp.status import RESULTS

SHAPE, MU = jd.family_shape("60sym"), 0.5
LOAD = jd.LoadCase()
KEY = jax.random.PRNGKey(0)
H_L = 10.0
# the table's step, halved BISECTIONS times in log psi_d: the bracket's relative width
RESOLUTION = 10.0 ** (TABLE_DECADES / (TABLE_POINTS - 1) / 2 ** BISECTIONS) - 1.0


def _path(engine_order):
    return nodal_scene(load_modal_family("example"), engine_order, LOAD.q_star, H_L)


def _six_blade_family():
    """The six-blade lumped disk's family with its platform residual flexibility (h_c 20 mm)."""
    disk = LumpedDisk(n_blades=6)
    return jd.blocks.validate_family(modal_family(disk, LOAD.q_star, 20.0, residual=True))


def test_bad_arguments_are_refused_before_any_work():
    fam = load_modal_family("example")
    with pytest.raises(ValueError) as e:
        jd.row_band(SHAPE, MU, modes=fam, engine_orders=[3], force_n=[5.0], h_l_mm=H_L,
                    n_samples=1)
    assert "n_samples must be" in str(e.value) and "\n" not in str(e.value)
    undamped = fam._replace(loss_factor=np.where(fam.nodal_diameter == 3, 0.0, fam.loss_factor))
    with pytest.raises(ValueError, match="loss_factor must be > 0 at nodal diameter 3"):
        jd.row_band(SHAPE, MU, modes=undamped, engine_orders=[3], force_n=[5.0], h_l_mm=H_L)
    with pytest.raises(ValueError, match="steps must be 0 with a motion"):
        band_kernel(SHAPE, MU, jd.Contacts(), LOAD, 1.0, KEY, motion=_path(3).motion)


def test_elliptic_band_holds_both_histories_and_its_states_reproduce_its_bounds():
    """ND 3 of the example disk (an ellipse), at an amplitude in the microslip range where the
    band is open: the assembly and gross-slip cycles (the public `elliptic_cycle`) lie inside the
    band, and each bound's initial state, run by `elliptic_cycle(initial=(N, T))` (checked
    admissible there), gives that bound."""
    motion = _path(3).motion
    psi = 8.0
    band = jax.jit(lambda p: band_kernel(SHAPE, MU, jd.Contacts(), LOAD, p, KEY, n_samples=16,
                                         steps=0, motion=motion))(psi)
    lo_re, hi_re, lo_im, hi_im = np.asarray(band.bounds)
    assert int(band.status) == 0 and hi_im > lo_im + 10.0  # open: 0 ... 25 N mm/mrad
    for initial in ("assembly", "gross_slip"):
        ec = jd.elliptic_cycle(SHAPE, MU, psi, motion, initial=initial)
        assert int(ec.status) == 0
        assert lo_im <= float(ec.k_im) <= hi_im and lo_re <= float(ec.k_re) <= hi_re
    for i, bound in enumerate(np.asarray(band.bounds)):
        ec = jd.elliptic_cycle(SHAPE, MU, psi, motion, initial=(np.asarray(band.N[i]),
                                                               np.asarray(band.T[i])))
        value = float(ec.k_re) if i < 2 else float(ec.k_im)
        assert abs(value - bound) <= 1e-9 * abs(hi_re)


@pytest.mark.slow  # 37 worker-s (2026-11-27)
def test_band_on_the_in_phase_motion_is_the_in_phase_bands_samples():
    """The in-phase path given as a straight Motion (the path engine's explicit start) gives the
    in-phase band's samples (`band_kernel` without a motion, no refinement)."""
    motion = jd.in_phase_motion(LOAD.q_star)
    psi = jnp.array([0.6, 1.2, 4.0])
    run = jax.jit(jax.vmap(lambda p, m: band_kernel(SHAPE, MU, jd.Contacts(), LOAD, p, KEY,
                                                    n_samples=32, steps=0, motion=m),
                           in_axes=(0, None)))
    on_path = run(psi, motion)
    in_phase = jax.jit(jax.vmap(lambda p: band_kernel(SHAPE, MU, jd.Contacts(), LOAD, p, KEY,
                                                      n_samples=32, steps=0)))(psi)
    assert np.all(np.asarray(in_phase.status) == 0)
    assert_tree_allclose(on_path.bounds, in_phase.bounds, rtol=1e-9, atol=1e-6)
    np.testing.assert_array_equal(on_path.n_valid, in_phase.n_valid)


def _histories_inside(band, rows):
    for row in rows:
        amp = row.peaks.peak_amplitude_mm
        assert np.all(np.asarray(row.status) == 0)
        assert np.all(band.peak_min_mm <= amp) and np.all(amp <= band.peak_max_mm), (
            band.peak_min_mm, amp, band.peak_max_mm)


@pytest.mark.slow  # 465 worker-s (2026-11-27): two row band programs, four row programs
def test_row_band_holds_every_history_and_closes_past_gross_slip():
    """The example disk, 60sym mu 0.5, a straight (ND 0) and an elliptic (ND 3) path: both
    histories' peaks (`row_response`) lie inside the band at 2, 5 and 20 N; the band is open in
    microslip (2 N) and at 20 N, past gross slip, where every admissible state settles on the same
    cycle, it is no wider than its brackets."""
    fam = load_modal_family("example")
    kw = dict(modes=fam, engine_orders=[0, 3], force_n=[2.0, 5.0, 20.0], h_l_mm=H_L)
    band = jd.row_band(SHAPE, MU, **kw)
    assert np.all(band.status == 0)
    # each bracket is RESOLUTION wide in the damper's own amplitude psi_d; in the platforms'
    # psi = psi_d |1 + c k(psi_d)| it is narrower where |1 + c k| falls with the amplitude
    assert np.all(band.resolution > 0.0) and np.all(band.resolution <= RESOLUTION * (1 + 1e-9))
    _histories_inside(band, [jd.row_response(SHAPE, MU, initial=h, **kw)
                             for h in ("assembly", "gross_slip")])
    width = band.peak_max_mm / band.peak_min_mm - 1.0
    assert np.all(width[:, 0] > 0.3)  # 2 N: the histories differ by 10 %, the band by 50 %
    assert np.all(width[:, 2] <= 2.0 * RESOLUTION + 1e-12)


@pytest.mark.slow  # 7 s (2026-11-29): ND 0, 8 samples, each state's peak in its own amplitude
def test_row_band_with_residual_flexibility_holds_every_history():
    """A family with platform_residual: each admissible state's damper in series with it; the
    histories' peaks with the residual (`row_response`) lie inside the band, at nodal diameter 0
    of the lumped disk, where the residual matters most. And the band's bounds are where the
    states are, by the independent route that solves each state's series fixed point at the
    platforms' amplitude (`residual.through_residual`; the band searches each state's peak in
    its own amplitude psi_d instead): at r A_max every state with a valid cycle is at or past its
    root (g >= 0), at r A_min none has reached it (g <= 0)."""
    family = _six_blade_family()
    forces = np.array([2.0, 20.0])
    kw = dict(modes=family, engine_orders=[0], force_n=forces, h_l_mm=H_L)
    band = jd.row_band(SHAPE, MU, n_samples=8, **kw)
    assert np.all(band.status == 0)
    _histories_inside(band, [jd.row_response(SHAPE, MU, initial=h, **kw)
                             for h in ("assembly", "gross_slip")])

    scene = nodal_scene(family, 0, LOAD.q_star, H_L)
    mode, c = scene.mode, scene.residual_mrad_per_nmm
    T, real, P, n0 = admissible_samples(SHAPE, jnp.asarray(MU), jax.random.PRNGKey(0), 8)

    @jax.jit
    def g_of_states(psi, tip):  # the peak equation of every state at the platforms' psi
        def one(t):
            def cycle(a):
                return state_cycle(SHAPE, jnp.asarray(MU), jd.Contacts(), LOAD, a, t, P, n0,
                                   scene.motion)
            _, k_im, status, _ = through_residual(cycle, psi, c)
            g = psi / mode.r * (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_im) - tip
            return g, RESULTS.valid(status)
        return jax.vmap(one)(T)

    for j, force in enumerate(forces * scene.force_per_unit):
        g_hi, ok_hi = g_of_states(mode.r * band.peak_max_mm[0, j], force)
        g_lo, ok_lo = g_of_states(mode.r * band.peak_min_mm[0, j], force)
        ok_hi, ok_lo = np.asarray(ok_hi & real), np.asarray(ok_lo & real)
        assert ok_hi.sum() >= 8 and ok_lo.sum() >= 8
        assert np.all(np.asarray(g_hi)[ok_hi] >= -1e-9 * force), (force, g_hi)
        assert np.all(np.asarray(g_lo)[ok_lo] <= 1e-9 * force), (force, g_lo)


@pytest.mark.slow  # the residual test's program (same shapes), run at a higher mu
def test_row_band_is_never_above_the_free_blade_and_a_stuck_state_peaks_there():
    """No history's peak lies above the free blade's F / (eta k_b) (k_Im >= 0, and so is Im k /
    (1 + c k)): the band's highest peak is at most there, and where an admissible state sticks
    (60sym at mu 0.7 on the six-blade disk's nodal diameter 0 with its residual) it is exactly
    there, not at its bracket's outer end up to `resolution` above it."""
    family = _six_blade_family()
    kw = dict(modes=family, engine_orders=[0], force_n=np.array([2.0, 20.0]), h_l_mm=H_L)
    band = jd.row_band(SHAPE, 0.7, n_samples=8, **kw)
    free = jd.row_response(SHAPE, 0.7, **kw).free_peak_mm
    assert np.all(band.status == 0) and np.all(band.resolution > 0.0)
    assert np.all(band.peak_max_mm <= free)
    assert_tree_allclose(band.peak_max_mm, free, rtol=1e-12, atol=0.0)
    assert np.all(band.peak_min_mm < free)  # the band stays open below it
