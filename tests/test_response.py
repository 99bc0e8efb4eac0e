"""Amplitude-layered blade response: physics identities, analytic k(psi), scaling law, gradients."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp import Contacts, LoadCase, base_cycle, complex_stiffness, family_shape, five_numbers
from helpers import assert_tree_allclose, count_compiles
from jaxdamp.response import (BladeMode, DamperStiffness, damper_stiffness, design_peaks,
                              designer_diagram, frf, linear_frf, no_damper, peak_response,
                              response_amplitude_linear, response_curves, scaled_stiffness,
                              stuck_damper)
from jaxdamp.band import CONFIRM_TOL
from jaxdamp.status import RESULTS

MODE = BladeMode()
SHAPE = family_shape("60sym")


def analytic(k_re, k_im_fn, psi_ref=1.0):
    """A damper given by formulas (k_re constant, k_im a function of psi)."""
    return DamperStiffness(lambda p: (jnp.zeros_like(p) + k_re, k_im_fn(jnp.asarray(p, float))),
                           jnp.int32(0), jnp.asarray(float(k_re)), jnp.asarray(psi_ref))


def test_defaults_give_a_few_percent_stick_rise_and_damper_dominated_gross_slip():
    nums = five_numbers(base_cycle(SHAPE, 0.5))
    rise = np.sqrt(1 + 1e-3 * MODE.r ** 2 * float(nums.k_re_fs) / MODE.k_b) - 1
    assert 0.01 < rise < 0.05
    assert 1e-3 * MODE.r ** 2 * float(nums.k_im_bc) > 5 * MODE.eta * MODE.k_b


def test_frf_branches_solve_the_first_harmonic_equation():
    d = damper_stiffness(SHAPE, 0.5, method="interpolated")
    force = 5.0
    a = jnp.geomspace(0.005, 3.0, 60)  # from below the static deflection 0.0095 mm
    curve = jax.jit(lambda a: frf(d, MODE, force, a))(a)
    k_re, k_im = complex_stiffness(base_cycle(SHAPE, 0.5), MODE.r * a, method="interpolated")
    for f, has in ((curve.f_low_hz, curve.has_low), (curve.f_high_hz, curve.has_high)):
        w = (np.asarray(f) / MODE.f0_hz) ** 2
        D = MODE.k_b * (1 - w + 1j * MODE.eta) + 1e-3 * MODE.r ** 2 * (k_re + 1j * k_im)
        resid = np.abs(D) * np.asarray(a) - force
        assert np.all(np.abs(resid[np.asarray(has)]) < 1e-9 * force)
        assert np.all(np.isfinite(np.asarray(f)))
    # Below the static deflection F / (k_b + stiffening) there is no low branch (omega^2 < 0).
    assert not bool(curve.has_low[0]) and bool(curve.has_high[0])
    # Branches exist exactly below the peak amplitude and meet there.
    peak = peak_response(d, MODE, force)
    A = float(peak.peak_amplitude_mm)
    both = np.asarray(curve.has_low & curve.has_high)
    assert np.all(np.asarray(a)[both] < A) and np.all(np.asarray(a)[~np.asarray(curve.has_high)] > A)
    near = frf(d, MODE, force, A * (1 - 1e-10))
    assert float(near.f_high_hz - near.f_low_hz) < 1e-3
    assert abs(float(near.f_high_hz) - float(peak.peak_frequency_hz)) < 1e-3


def test_free_and_stuck_limits_are_the_linear_resonances():
    force = 2.0
    for d, k in ((no_damper(), 0.0), (stuck_damper(28000.0), 28000.0)):
        p = peak_response(d, MODE, force)
        assert float(p.peak_amplitude_mm) == pytest.approx(force / (MODE.eta * MODE.k_b), rel=1e-12)
        f_exp = MODE.f0_hz * np.sqrt(1 + 1e-3 * MODE.r ** 2 * k / MODE.k_b)
        assert float(p.peak_frequency_hz) == pytest.approx(f_exp, rel=1e-12)
        # The linear FRF at the peak frequency has that amplitude (resonance of a linear system
        # with hysteretic damping: |D| = eta k_b there).
        amp = response_amplitude_linear(MODE, k, 0.0, force, p.peak_frequency_hz)
        assert float(amp) == pytest.approx(float(p.peak_amplitude_mm), rel=1e-12)


def test_every_root_of_an_isola_is_found():
    # With r = 1 and eta k_b + 1e-3 k_Im(psi) = c (psi^2 - 6 psi + 11), F = 6 c gives
    # A (eta k_b + 1e-3 k_Im) - F = c (A - 1)(A - 2)(A - 3): the main branch peaks at 1 mm, an
    # isola spans 2 ... 3 mm.
    c = 1.0
    mode = BladeMode(r=1.0)
    d = analytic(1000.0, lambda p: 1e3 * (c * (p * p - 6 * p + 11) - mode.eta * mode.k_b))
    p = jax.jit(lambda f: peak_response(d, mode, f))(6.0 * c)
    assert int(p.n_roots) == 3 and int(p.status) == RESULTS.ok
    assert_tree_allclose(p.roots_mm[:3], np.array([1.0, 2.0, 3.0]), rtol=1e-12, atol=0.0)
    assert not bool(p.found[3]) and float(p.roots_mm[3]) == 0.0
    assert float(p.peak_amplitude_mm) == pytest.approx(1.0, rel=1e-12)
    assert float(p.max_amplitude_mm) == pytest.approx(3.0, rel=1e-12)
    assert float(p.psi_a_mrad) == pytest.approx(1.0, rel=1e-12)


def test_a_force_array_shares_one_grid_and_finds_every_root():
    # The isola of the previous test at forces around 6 c, with the analytic roots of
    # c (A^3 - 6 A^2 + 11 A) = F: the shared grid must find the same roots as one call per force.
    mode = BladeMode(r=1.0)
    d = analytic(1000.0, lambda p: 1e3 * ((p * p - 6 * p + 11) - mode.eta * mode.k_b))
    forces = jnp.array([0.5, 5.9, 6.0, 6.05, 40.0])
    many = jax.jit(lambda f: peak_response(d, mode, f))(forces)
    assert many.peak_amplitude_mm.shape == (5,)
    for i, f in enumerate(np.asarray(forces)):
        one = peak_response(d, mode, float(f))
        assert int(many.n_roots[i]) == int(one.n_roots)
        assert_tree_allclose(many.roots_mm[i], one.roots_mm, rtol=1e-12, atol=0.0)
        cubic = np.roots([1.0, -6.0, 11.0, -f])
        real = np.sort(cubic[np.abs(cubic.imag) < 1e-9].real)
        assert_tree_allclose(np.asarray(many.roots_mm[i])[: real.size], real, rtol=1e-11, atol=0.0)
    with pytest.raises(ValueError, match="force_n"):
        peak_response(d, mode, jnp.ones((2, 2)))


@pytest.mark.slow  # 61 worker-s (run of 2026-11-25)
def test_exact_damper_values_are_its_curve_without_design_derivatives():
    d = damper_stiffness(SHAPE, 0.5)
    psi = jnp.geomspace(0.3, 8.0, 9)
    assert_tree_allclose(d.values(psi)[1], d.k_of_psi(psi)[1], rtol=1e-12, atol=0.0)

    def through_values(mu):
        return jnp.sum(damper_stiffness(SHAPE, mu).values(psi)[1])

    assert float(jax.grad(through_values)(0.5)) == 0.0
    scaled = scaled_stiffness(d, 1000.0, 1500.0, 2.0)
    assert_tree_allclose(scaled.values(psi)[1], scaled.k_of_psi(psi)[1], rtol=1e-12, atol=0.0)


def test_no_root_without_structural_damping_beyond_the_friction_force():
    # eta = 0 and a damper whose dissipative modal force saturates at 1e-3 r^2 A k_Im -> 3 N.
    mode = BladeMode(eta=0.0)
    d = analytic(1000.0, lambda p: 3e3 * p / (p * p + 1e-2))
    assert int(peak_response(d, mode, 10.0, amplitude_cap_mm=1e4).status) == RESULTS.no_root
    ok = peak_response(d, mode, 1.0, amplitude_cap_mm=1e4)
    assert int(ok.status) == RESULTS.ok
    a = float(ok.peak_amplitude_mm)  # 3 a^2 / (a^2 + 0.01) = 1
    assert a == pytest.approx(np.sqrt(0.01 / 2.0), rel=1e-12)


@pytest.mark.slow  # 48 worker-s (run of 2026-11-25)
def test_liftoff_is_reported():
    p = design_peaks(family_shape("74L"), 0.7, force_n=5.0)
    assert int(p.status) == RESULTS.liftoff


@pytest.mark.parametrize("fd, c", [(500.0, 1.0), (2300.0, 1.0), (1000.0, 2.5), (700.0, 0.4)])
def test_scaling_law_matches_direct_recomputation(fd, c):
    ref = damper_stiffness(SHAPE, 0.5, Contacts(), LoadCase(1000.0), method="interpolated")
    scaled = scaled_stiffness(ref, 1000.0, fd, contact_scale=c)
    direct = complex_stiffness(
        base_cycle(SHAPE, 0.5, Contacts(c * Contacts().kn, c * Contacts().kt), LoadCase(fd)),
        jnp.asarray([0.01, 0.3, 0.7, 1.0, 1.5, 2.2, 4.0, 10.0]) * fd / 1000.0 / c, method="interpolated")
    psi = jnp.asarray([0.01, 0.3, 0.7, 1.0, 1.5, 2.2, 4.0, 10.0]) * fd / 1000.0 / c
    got = scaled.k_of_psi(psi)
    for g, e in zip(got, direct):
        assert_tree_allclose(g, e, rtol=1e-9, atol=1e-9 * 3e4)


def _peak_and_frequency(x):
    theta_l, theta_r, br, mu, fd, f0, kb, eta, r, force = x
    shape = SHAPE._replace(theta_l=theta_l, theta_r=theta_r, br_over_hr=br)
    d = damper_stiffness(shape, mu, Contacts(), LoadCase(fd), method="interpolated")
    p = peak_response(d, BladeMode(f0, kb, eta, r), force)
    return jnp.stack([p.peak_amplitude_mm, p.peak_frequency_hz])


@pytest.mark.slow  # 126 worker-s (run of 2026-11-25)
def test_gradients_by_implicit_function_match_central_differences():
    f = jax.jit(_peak_and_frequency)
    jf = jax.jit(jax.jacfwd(_peak_and_frequency))
    # F = 5 N: microslip (psi_a = 1.5 mrad, the interpolated range); F = 20 N: gross slip.
    for force in (5.0, 20.0):
        x = np.array([60.0, 60.0, 0.14, 0.5, 1000.0, 500.0, 500.0, 1e-3, 1.0, force])
        jac = np.asarray(jf(x))
        for i, h in enumerate(np.abs(x) * 1e-6):
            e = np.zeros_like(x)
            e[i] = h
            fd = (np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2 * h)
            assert_tree_allclose(jac[:, i], fd, rtol=2e-5, atol=1e-9 * np.abs(jac).max(),
                                 err_msg=f"F = {force}, input {i}")
        assert np.all(np.isfinite(jac)) and np.abs(jac[0, 3]) > 0
    # Reverse mode through the root (custom_root's transpose) gives the same Jacobian.
    jrev = np.asarray(jax.jit(jax.jacrev(_peak_and_frequency))(x))
    assert_tree_allclose(jrev, jac, rtol=1e-10, atol=1e-14)


@pytest.mark.slow  # 146 worker-s (run of 2026-11-25)
def test_designer_diagram_band_and_limits():
    dd = designer_diagram(SHAPE, force_n=[0.2, 5.0, 50.0], fd_n=[100.0, 1000.0, 1e5],
                          force_at_fd_n=5.0, mu=(0.3, 0.7))
    assert np.all(dd.status == RESULTS.ok)
    assert np.all(dd.band_force_mm[0] <= dd.peak_vs_force_mm) and np.all(
        dd.peak_vs_force_mm <= dd.band_force_mm[1])
    # The damper never does worse than free or stuck (k_Im >= 0), and at small force it is stuck.
    assert np.all(dd.peak_vs_force_mm <= dd.free_vs_force_mm * (1 + 1e-9))
    n_mu = len(dd.mu)
    assert_tree_allclose(dd.peak_vs_force_mm[:, 0], np.full(n_mu, dd.stuck_vs_force_mm[0]), rtol=1e-9,
                         atol=0.0)
    # A very heavy damper stays stuck: the classic optimum has the free/stuck value at both ends.
    assert_tree_allclose(dd.peak_vs_fd_mm[:, -1], np.full(n_mu, dd.stuck_vs_fd_mm[-1]), rtol=1e-9,
                         atol=0.0)
    assert np.all(dd.peak_vs_fd_mm[:, 1] < 0.5 * dd.free_vs_fd_mm[1])
    # The scaled F_D = 1000 N column equals the direct F = 5 N column.
    assert_tree_allclose(dd.peak_vs_fd_mm[:, 1], dd.peak_vs_force_mm[:, 1], rtol=1e-10, atol=0.0)
    f_stuck = MODE.f0_hz * np.sqrt(1 + 1e-3 * 28744.25647085 / MODE.k_b)
    assert_tree_allclose(dd.stuck_frequency_hz, np.full(n_mu, f_stuck), rtol=1e-8, atol=0.0)


@pytest.mark.slow  # 170 worker-s (run of 2026-11-25)
def test_peak_band_brackets_every_named_history():
    """The band of k(psi_a) over all admissible histories bounds each history's k_Im pointwise, and
    the peak equation is monotone in k_Im: the band's peaks bracket the peak of the gross-slip and
    of the assembly history (computed independently, by their own exact cycles)."""
    from jaxdamp.response import peak_band

    highest, lowest, grid, k = peak_band(SHAPE, 0.5, force_n=[2.0, 5.0])
    # Where every pad sticks k_Im is zero and its two bounds are rounding (+-2e-10 N mm/mrad, in
    # either order): ordered to the band's own accuracy, CONFIRM_TOL of the k scale.
    assert np.all(k[:, 2] <= k[:, 3] + CONFIRM_TOL * np.max(np.abs(k)))
    for initial in ("gross_slip", "assembly"):
        p = design_peaks(SHAPE, 0.5, force_n=jnp.asarray([2.0, 5.0]), initial=initial)
        a = np.asarray(p.peak_amplitude_mm)
        assert np.all(np.asarray(lowest.peak_amplitude_mm) <= a + 1e-12), initial
        assert np.all(a <= np.asarray(highest.peak_amplitude_mm) + 1e-12), initial
    # Below gross slip the histories differ: the band is a real band there.
    assert float(highest.peak_amplitude_mm[0]) > 1.2 * float(lowest.peak_amplitude_mm[0])


def test_peak_band_compiles_ahead_the_programs_it_then_runs():
    """peak_band compiles the band's program before psi_BC fixes its grid, and the peaks' program
    while the band runs (`runtime.compile_ahead`): each for exactly the program, the input
    structure, shapes and dtypes that it then runs, else the compile would be wasted. A runner
    records both and returns ones of each program's output shapes (nothing is compiled)."""
    import threading

    from jaxdamp.cli.exported import program_identity
    from jaxdamp.response import peak_band

    def signature(program, args):
        leaves, tree = jax.tree_util.tree_flatten(args)
        return (program_identity(program), tree,
                [(np.shape(x), jnp.result_type(x), getattr(x, "weak_type", False)) for x in leaves])

    ran, ahead = [], []

    class Recorder:
        def __call__(self, program, args):
            ran.append(signature(program, args))
            out = jax.eval_shape(getattr(program, "__wrapped__", program), *args)
            return jax.tree_util.tree_map(lambda o: jnp.ones(o.shape, o.dtype), out)

        def compile_ahead(self, program, args):
            ahead.append(signature(program, args))

    peak_band(SHAPE, 0.5, force_n=[2.0, 5.0], psi_grid_mrad=np.geomspace(0.1, 5.0, 7),
              n_samples=8, steps=1, runner=Recorder())
    for thread in threading.enumerate():
        if thread.name == "compile_ahead":
            thread.join()
    assert len(ahead) == 2 and all(a[0] is not None for a in ahead)
    for a in ahead:
        assert a in ran


def test_peak_band_refuses_bad_grids_and_counts_before_compiling_ahead(monkeypatch):
    """A bad amplitude grid or count is one ValueError naming it, raised before any program is
    compiled ahead (no thread left compiling for a call that was refused)."""
    import importlib

    from jaxdamp.response import peak_band

    band_module = importlib.import_module("jaxdamp.band")
    # the module (jaxdamp.response re-exports its function under the same name)
    peak_band_module = importlib.import_module("jaxdamp.response.peak_band")

    started = []
    for module in (band_module, peak_band_module):
        monkeypatch.setattr(module, "compile_ahead", lambda *a, **k: started.append(a))
    with pytest.raises(ValueError, match="psi_a_mrad"):
        peak_band(SHAPE, 0.5, force_n=5.0, psi_grid_mrad=[0.5, -1.0])
    with pytest.raises(ValueError, match="n_samples"):
        peak_band(SHAPE, 0.5, force_n=5.0, n_samples=1)
    with pytest.raises(ValueError, match="steps"):
        peak_band(SHAPE, 0.5, force_n=5.0, steps=-1)
    assert started == []


def test_linear_frf_reaches_the_closed_form_resonance_of_free_and_stuck():
    """A linear oscillator k_b (1 - W + i eta) + g k: the peak is F / (eta k_b) at
    W = 1 + g k / k_b; every point is |A| = F / |D| (response_amplitude_linear, a second
    formula)."""
    k_stuck = 28744.0
    for k in (0.0, k_stuck):
        curve = linear_frf(MODE, k, 20.0)
        a = np.asarray(curve.amplitude_mm)
        top = 20.0 / (MODE.eta * MODE.k_b)
        assert a.max() == pytest.approx(top, rel=1e-6) and a.min() < 0.02 * top
        f_res = MODE.f0_hz * np.sqrt(1 + 1e-3 * MODE.r ** 2 * k / MODE.k_b)
        i = np.argmax(a)
        assert curve.f_low_hz[i] == pytest.approx(f_res, rel=1e-6)
        assert curve.f_high_hz[i] == pytest.approx(f_res, rel=1e-6)
        for f, has in ((curve.f_low_hz, curve.has_low), (curve.f_high_hz, curve.has_high)):
            assert bool(np.all(has))
            back = response_amplitude_linear(MODE, k, 0.0, 20.0, f)
            assert_tree_allclose(back, a, rtol=1e-8, atol=0.0)


@pytest.mark.slow  # 12 worker-s (run of 2026-11-25)
def test_response_curves_carry_the_damper_status_and_readable_reprs():
    res = response_curves(SHAPE, 0.5, contacts=Contacts(kt=1e12), force_n=[5.0],
                          method="interpolated")
    assert RESULTS(int(res.status)) == RESULTS.ill_conditioned
    assert RESULTS(int(res.peaks.status[0])) == RESULTS.ill_conditioned
    assert RESULTS(int(res.damper.status[0])) == RESULTS.ill_conditioned
    ok = response_curves(SHAPE, 0.5, force_n=[2.0, 20.0], method="interpolated")
    text = repr(ok.peaks)
    assert "mm" in text and "Hz" in text and "status [ok, ok]" in text and len(text) < 300
    assert "ill_conditioned" in repr(res) and len(repr(res)) < 400
    assert "status ok" in repr(damper_stiffness(SHAPE, 0.5, method="interpolated"))


@pytest.mark.slow  # 32 worker-s (run of 2026-11-25)
def test_a_second_call_with_new_values_compiles_nothing():
    """The response and diagram programs live at module level (#23): new numbers, same shapes."""
    mus = (0.4, 0.5)
    kw = dict(force_n=[0.5, 1.0], fd_n=[500.0, 2000.0], method="interpolated")
    response_curves(SHAPE, 0.5, force_n=[2.0, 5.0, 20.0, 20.0], method="interpolated")
    designer_diagram(SHAPE, MODE, mu=mus, **kw)
    with count_compiles() as compiled:
        response_curves(family_shape("74R"), 0.6, contacts=Contacts(kt=3000.0),
                        force_n=[1.0, 3.0, 7.0, 9.0], method="interpolated")
        designer_diagram(family_shape("74R"), MODE, mu=(0.45, 0.55), **kw)
    assert compiled == []


def test_peak_response_of_a_damper_stiffness_runs_one_compiled_program():
    """The obvious composition, peak_response(damper_stiffness(...), ...) from plain Python, runs
    the compiled peak program (issue 32): the same numbers as the function traced as a whole under
    jit, and a second design with new values compiles nothing."""
    forces = np.array([2.0, 20.0])
    d = damper_stiffness(SHAPE, 0.5, method="interpolated")
    got = peak_response(d, MODE, forces)
    untied = d._replace(source=None)  # the plain function, traced whole by one jit
    ref = jax.jit(lambda f: peak_response(untied, MODE, f))(forces)
    for name in ("roots_mm", "peak_amplitude_mm", "peak_frequency_hz", "n_roots", "status"):
        assert_tree_allclose(getattr(got, name), getattr(ref, name), rtol=1e-12, atol=0.0, err_msg=name)
    assert np.all(np.asarray(got.peak_amplitude_mm) > 0)
    with count_compiles() as compiled:
        d2 = damper_stiffness(family_shape("74R"), 0.4, Contacts(kt=3000.0), method="interpolated")
        peak_response(d2, MODE, np.array([3.0, 9.0]))
    assert compiled == []
    # A curve replaced by another (here scaled) is no longer the one its source describes.
    scaled = scaled_stiffness(d, 1000.0, 1200.0)
    assert scaled.source is None or not scaled.source.matches(scaled)


def test_a_scene_is_checked_once_and_taken_as_it_is():
    """`prepare_scene` checks every input once (each range of params.RANGES counted once) and
    returns a Scene of float64 arrays; a Scene given again is returned as it is, unchecked."""
    from jaxdamp._validate import MOTION_RANGES
    from jaxdamp.params import RANGE_CHECKS, RANGES
    from jaxdamp.response import Scene, prepare_scene

    RANGE_CHECKS.clear()
    scene = prepare_scene(SHAPE, 0.5, Contacts(), LoadCase(), MODE)
    assert isinstance(scene, Scene)
    # A scene has no platform path (MOTION_RANGES) and no forces.
    assert dict(RANGE_CHECKS) == {n: 1 for n in set(RANGES) - {"x_d", "br2_over_hr", "force_n"}
                                  - MOTION_RANGES}
    assert all(np.asarray(v).dtype == np.float64 for v in jax.tree_util.tree_leaves(scene))
    assert np.shape(scene.contacts.kn) == (3,)
    RANGE_CHECKS.clear()
    assert prepare_scene(scene) is scene and not RANGE_CHECKS
    with pytest.raises(ValueError, match="not both"):
        prepare_scene(scene, 0.5)
    with pytest.raises(ValueError, match="^eta must be in \\[0, 1\\]; got 2$"):
        prepare_scene(SHAPE, 0.5, mode=MODE._replace(eta=2.0))



def test_a_stiffness_method_refuses_options_it_does_not_take_before_any_work():
    """A misspelt or misplaced option, or an unknown history, is one line naming it, raised when
    the curve is built (it was a TypeError from the factory's call, or for initial= a message
    listing a history the curves do not take, raised at the curve's first evaluation)."""
    with pytest.raises(ValueError, match=r"^bogus is not an option of method 'exact': its options "
                                         r"are initial$"):
        damper_stiffness(SHAPE, 0.5, bogus=1)
    with pytest.raises(ValueError, match=r"^initial is not an option of method 'interpolated': "
                                         r"its options are none$"):
        damper_stiffness(SHAPE, 0.5, method="interpolated", initial="assembly")
    with pytest.raises(ValueError, match=r"^initial must be one of assembly, gross_slip; got 'x'$"):
        damper_stiffness(SHAPE, 0.5, initial="x")
    # (raised while its program is traced, before XLA compiles: JAX adds a note after the line)
    with pytest.raises(ValueError, match=r"^initial must be one of assembly, gross_slip; got 'x'"):
        design_peaks(SHAPE, 0.5, mode=MODE, initial="x")


def test_peak_search_options_and_the_damper_are_refused_in_one_line():
    """A grid smaller than max_roots failed inside with a broadcasting error, one grid point
    found no root silently, max_roots 0 with an IndexError, a number for the damper with an
    AttributeError."""
    d = damper_stiffness(SHAPE, 0.5)
    for kwargs, says in (({"n_grid": 3}, r"^n_grid must be an integer in \[4, inf\); got 3$"),
                         ({"n_grid": 1, "max_roots": 1}, r"^n_grid must be an integer in \[2, inf\)"),
                         ({"max_roots": 0}, r"^max_roots must be an integer in \[1, inf\); got 0$"),
                         ({"search_width": 0}, r"^search_width must be an integer in \[1, inf\)"),
                         ({"amplitude_cap_mm": -1.0}, r"^amplitude_cap_mm must be in \(0, inf\) mm"),
                         ({"differentiable": "no"}, r"^differentiable must be True or False")):
        with pytest.raises(ValueError, match=says):
            peak_response(d, MODE, 1.0, **kwargs)
    for call in (lambda: peak_response(5, MODE, 1.0), lambda: frf(5, MODE, 1.0, 1.0)):
        with pytest.raises(TypeError, match=r"^damper must be a jaxdamp.DamperStiffness"):
            call()
