"""Steady cycles at a prescribed amplitude (jaxdamp.amplitude), checked against independent
references: the Base-Cycle's stretched continuation above psi_BC, the all-stick slope below psi_fs,
the energy identity, the time marcher and HBM-AFT started from the same state."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_cycle, check_admissible, gross_slip_state, moment_loop
from jaxdamp.cycle import mechanics
from jaxdamp.half import assemble_in_phase
from jaxdamp.charts import transitions_chart
from jaxdamp.baselines import hbm_aft
from jaxdamp.status import RESULTS
from jaxdamp.baselines.timemarch import assemble, march_amplitude, march_model

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)  # the issue's pair


def numbers(name, mu):
    shape = jd.family_shape(name) if isinstance(name, str) else name
    return shape, jd.base_cycle(shape, mu, CONTACTS), jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))


@pytest.mark.parametrize("name,mu", [("60sym", 0.5), ("74R", 0.7), ("60sym", 0.3), ("74R", 0.5)])
def test_history_erased_above_psi_bc(name, mu):
    """At psi_a >= psi_BC both named histories give the Base-Cycle's stretched continuation."""
    shape, bc, n = numbers(name, mu)
    for psi in (float(n.psi_bc) * (1 + 1e-6), 1.5 * float(n.psi_bc), 12.0):
        ref = np.asarray(jd.complex_stiffness(bc, psi, method="interpolated"))
        for initial in ("gross_slip", "assembly"):
            ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
            assert RESULTS.name_of(ac.status) == "ok"
            got = np.array([float(ac.k_re), float(ac.k_im)])
            assert_tree_allclose(got, ref, rtol=1e-9, atol=1e-9 * abs(ref[0]))


def test_frozen_mechanism_keeps_history():
    """90R: gross slip is R1 sliding along the vertical flank while L1 and L2 stay stuck, so gross
    slip does not erase the left contacts' history. From gross slip the cycle is the Base-Cycle's
    continuation; from assembly it is another one, which the time marcher confirms."""
    shape, mu, psi = jd.family_shape("90R"), 0.5, 12.0
    _, bc, n = numbers(shape, mu)
    ref = np.asarray(jd.complex_stiffness(bc, psi, method="interpolated"))
    ac = amplitude_cycle(shape, mu, psi, CONTACTS)
    assert_tree_allclose(np.array([float(ac.k_re), float(ac.k_im)]), ref, rtol=1e-9, atol=0.0)
    asm = amplitude_cycle(shape, mu, psi, CONTACTS, initial="assembly")
    assert RESULTS.name_of(asm.status) == "ok"
    assert float(asm.k_im) > 1.2 * float(ac.k_im)
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial="assembly", n_steps=4000, max_pairs=2)
    assert_tree_allclose(np.array([float(tm.k_re), float(tm.k_im)]),
                         np.array([float(asm.k_re), float(asm.k_im)]), rtol=1e-6, atol=0.0)


@pytest.mark.parametrize("mu", [0.3, 0.5, 0.7])
def test_elastic_below_psi_fs(mu):
    """Below psi_fs the gross-slip start sticks: an elastic loop with the first tract's slope."""
    shape, bc, n = numbers("60sym", mu)
    for psi in (0.2 * float(n.psi_fs), 0.9 * float(n.psi_fs)):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS)
        assert RESULTS.name_of(ac.status) == "shakedown"
        assert float(ac.k_im) == pytest.approx(0.0, abs=1e-9 * float(n.k_re_fs))
        assert float(ac.k_re) == pytest.approx(float(n.k_re_fs), rel=1e-9)
        assert np.all(np.asarray(ac.energy) == 0.0)


def test_issue_examples():
    """The issue's brute-force numbers (not exact references): 60sym mu 0.5 at 1.2 mrad, k_Im ~2033
    from gross slip and ~1793 from assembly; 74R mu 0.7 at 1.5 mrad, ~1540 against 0."""
    sym, r74 = jd.family_shape("60sym"), jd.family_shape("74R")
    assert float(amplitude_cycle(sym, 0.5, 1.2, CONTACTS).k_im) == pytest.approx(2033, abs=1)
    asm = amplitude_cycle(sym, 0.5, 1.2, CONTACTS, initial="assembly")
    assert float(asm.k_im) == pytest.approx(1793, abs=1)
    assert float(amplitude_cycle(r74, 0.7, 1.5, CONTACTS).k_im) == pytest.approx(1540, abs=1)
    ac = amplitude_cycle(r74, 0.7, 1.5, CONTACTS, initial="assembly")
    assert RESULTS.name_of(ac.status) == "shakedown" and float(ac.k_im) == pytest.approx(0, abs=1e-6)


@pytest.mark.parametrize("name,mu,frac,initial", [
    ("60sym", 0.5, 0.5, "gross_slip"), ("60sym", 0.5, 0.5, "assembly"), ("74R", 0.7, 0.6, "gross_slip"),
    ("90R", 0.5, 0.5, "gross_slip"), ("90R", 0.7, 1.3, "assembly"), ("74R", 0.3, 1.2, "gross_slip")])
def test_energy_identity(name, mu, frac, initial):
    """sum_i W_i = oint M dpsi = pi psi_a^2 k_Im, to 1e-9 of the loop's elastic energy scale."""
    shape, bc, n = numbers(name, mu)
    psi = float(n.psi_fs) + frac * (float(n.psi_bc) - float(n.psi_fs))
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
    assert RESULTS.valid(ac.status)
    scale = abs(float(ac.k_re)) * psi**2 * 1e-3
    w = np.pi * psi**2 * float(ac.k_im) * 1e-3
    assert abs(float(np.sum(ac.energy)) - w) <= 1e-9 * scale
    assert abs(float(ac.work) - w) <= 1e-9 * scale
    assert np.all(np.asarray(ac.energy) >= -1e-12 * scale)  # every contact dissipates


# (shape, mu, amplitude regime, initial, step count, tolerance): the step counts and tolerances
# come from benchmarks/amplitude_vs_timemarch.py, where the marcher's error falls like h^2 (and like
# h where an event ends a back-slide, 74R: 1e-6 needs 256000 steps) down to 1e-11..1e-13; elsewhere
# moderate steps keep CI short.
MARCH_CASES = [
    ("60sym", 0.3, "between", "gross_slip", 4000, 1e-7),
    ("60sym", 0.5, "between", "assembly", 4000, 1e-7),
    ("60sym", 0.7, "between", "gross_slip", 4000, 1e-7),
    ("74R", 0.7, "between", "gross_slip", 256000, 1e-6),  # 2.2e-6 at 64000 steps
    ("90R", 0.5, "above", "gross_slip", 4000, 1e-6),
    ("random", 0.5, "between", "gross_slip", 4000, 1e-7),
    ("60sym", 0.5, "below", "assembly", 1000, 1e-9),
    ("74R", 0.7, "above", "assembly", 64000, 1e-6),  # 2e-5 at 4000 steps (back-slide end)
]


def _regime(n, regime):
    fs, bc = float(n.psi_fs), float(n.psi_bc)
    return {"below": 0.5 * fs, "between": 0.5 * (fs + bc), "above": 1.5 * bc}[regime]


@pytest.mark.slow  # 21 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name,mu,regime,initial,steps,tol", MARCH_CASES)
def test_agrees_with_time_marcher(name, mu, regime, initial, steps, tol):
    shape = jd.DamperShape(55.0, 66.0, 0.10) if name == "random" else jd.family_shape(name)
    _, _, n = numbers(shape, mu)
    psi = _regime(n, regime)
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
    # 90R's frozen gross slip converges geometrically (ratio ~0.06 per pair) in the marcher.
    pairs = 9 if name == "90R" else 4
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial=initial, n_steps=steps, max_pairs=pairs)
    assert int(tm.newton_failures) == 0 and jd.RESULTS.name_of(tm.status) == "ok"
    assert float(np.asarray(tm.closure)[-1]) < 1e-9
    scale = max(abs(float(ac.k_re)), abs(float(ac.k_im)))
    err = max(abs(float(tm.k_re) - float(ac.k_re)), abs(float(tm.k_im) - float(ac.k_im))) / scale
    assert err < tol
    assert_tree_allclose(tm.work_contacts, ac.energy, rtol=1e-7,
                         atol=10 * tol * scale * psi**2 * 1e-3)


def _assembly_state(shape, mu):
    """(N, T, ok) after F_D from zero, the platforms held: the engine's assembly of the pads."""
    args = jd.params.prepare_inputs(shape, mu, CONTACTS, jd.LoadCase())
    return assemble_in_phase(mechanics(*args))


def test_explicit_state_agrees_with_time_marcher():
    """An explicit admissible state (the mid-cycle full slip of the other direction, tilted inside
    the cone) run by both methods."""
    shape, mu, psi = jd.family_shape("60sym"), 0.5, 1.0
    N0, T0, _ = gross_slip_state(shape, mu)
    Na, Ta, _ = _assembly_state(shape, mu)
    N, T = 0.5 * (N0 + Na), 0.5 * (T0 + Ta)  # the admissible set is convex
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(N, T))
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial=(N, T), n_steps=4000, max_pairs=4)
    scale = abs(float(ac.k_re))
    assert abs(float(tm.k_re) - float(ac.k_re)) < 1e-7 * scale
    assert abs(float(tm.k_im) - float(ac.k_im)) < 1e-7 * scale


def test_assembly_state_matches_marcher_load_steps():
    """Proportional loading by enumeration of stick/slip sets = load stepping with Newton and return
    mapping (16 steps), including a design whose all-stick friction demand exceeds mu at a contact."""
    for shape, mu in ((jd.family_shape("60sym"), 0.5), (jd.family_shape("74R"), 0.2),
                      (jd.family_shape("90R"), 0.3)):
        N, T, ok = _assembly_state(shape, mu)
        args = jd.params.prepare_inputs(shape, mu, CONTACTS, jd.LoadCase())
        m, _ = march_model(*args)
        _, s, conv = assemble(m, 16)
        assert bool(ok) and bool(conv)
        assert_tree_allclose(N, s.N, rtol=1e-7, atol=1e-10)
        assert_tree_allclose(T, s.T, rtol=1e-7, atol=1e-10)
        res, cone, n_min = check_admissible(shape, mu, N, T)
        assert float(res) < 1e-12 and float(cone) <= 1e-12 and float(n_min) > 0


def test_agrees_with_hbm_aft_from_gross_slip():
    """HBM-AFT marches psi_a cos(tau) from state 0 at tau = 0: the gross-slip history."""
    shape, mu = jd.family_shape("60sym"), 0.5
    for psi in (1.2, 1.8):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS)
        r = hbm_aft(shape, mu, psi, CONTACTS, n_time=2048, n_periods=3)
        assert jd.RESULTS.name_of(r.status) == "ok"
        assert abs(float(r.k_re) - float(ac.k_re)) < 1e-5 * float(ac.k_re)
        assert abs(float(r.k_im) - float(ac.k_im)) < 1e-5 * float(ac.k_re)


def test_loop_and_chart():
    shape, mu = jd.family_shape("74R"), 0.7
    ac = amplitude_cycle(shape, mu, 1.5, CONTACTS)
    psi, M = moment_loop(ac)
    assert psi[0] == pytest.approx(1.5) and psi[-1] == pytest.approx(1.5)
    assert min(psi) == pytest.approx(-1.5)
    assert M[-1] == pytest.approx(M[0], abs=1e-9 * np.max(np.abs(M)))  # the loop closes
    # Shoelace area of the polygon = oint M dpsi (psi in mrad -> 1e-3).
    area = -0.5 * np.sum(psi[:-1] * M[1:] - psi[1:] * M[:-1]) * 1e-3
    assert area == pytest.approx(float(ac.work), rel=1e-9)
    rows = transitions_chart(ac)
    assert sum(r["dv_mm"] for r in rows if r["half"] == "forward") == pytest.approx(0.3, rel=1e-12)
    assert rows[0]["R1"] == "stick"


def test_liftoff_and_validation():
    ac = amplitude_cycle(jd.family_shape("74L"), 0.7, 1.0, CONTACTS)
    assert RESULTS.name_of(ac.status) == "liftoff" and float(ac.k_im) == 0.0
    shape = jd.family_shape("60sym")
    with pytest.raises(ValueError, match="psi_a_mrad"):
        amplitude_cycle(shape, 0.5, 0.0)
    with pytest.raises(ValueError, match="initial"):
        amplitude_cycle(shape, 0.5, 1.0, initial="rest")
    N, T, _ = gross_slip_state(shape, 0.5)
    with pytest.raises(ValueError, match="equilibrium"):
        amplitude_cycle(shape, 0.5, 1.0, initial=(N * 1.1, T))
    with pytest.raises(ValueError, match=r"\|T\| <= mu N"):
        amplitude_cycle(shape, 0.4, 1.0, initial=(N, T))


def _design_params(x):
    """x (..., 7): theta_l, theta_r, b_R/h_R, mu, kn, kt, psi_a."""
    shape = jd.DamperShape(x[..., 0], x[..., 1], x[..., 2], 0.8)
    return shape, x[..., 3], jd.Contacts(x[..., 4], x[..., 5]), x[..., 6]


def test_curves_match_single_cycles():
    rng = np.random.default_rng(3)
    shapes = jd.DamperShape(rng.uniform(50, 75, 4), rng.uniform(50, 75, 4), rng.uniform(0.0, 0.15, 4))
    mu = rng.uniform(0.3, 0.7, 4)
    psi = np.array([0.3, 1.1, 2.5, 7.0])
    cv = jd.curves.cycle_curves(shapes, mu, psi, CONTACTS, initial="assembly")
    assert cv.k_re.shape == (4, 4)
    for d in range(4):
        for j in (1, 3):
            ac = amplitude_cycle(jd.DamperShape(*(float(v[d]) for v in shapes[:3])), float(mu[d]),
                                 float(psi[j]), CONTACTS, initial="assembly")
            assert int(cv.status[d, j]) == int(ac.status)
            assert_tree_allclose(np.array([cv.k_re[d, j], cv.k_im[d, j]]),
                                 np.array([ac.k_re, ac.k_im]), rtol=1e-12, atol=1e-9)


@pytest.mark.slow  # 30 worker-s (run of 2026-11-25)
def test_curves_above_psi_bc_are_the_stretched_base_cycle_and_match_the_cycles():
    """amplitude_curves takes the stretched Base-Cycle (closed form) at psi_a >= psi_BC from gross
    slip; curves_kernel (traced: every cycle by the direct method) is the reference, on random
    designs with amplitudes on both sides of their psi_BC, liftoff included."""
    from jaxdamp.curves import curves_kernel

    rng = np.random.default_rng(11)
    n = 24
    shapes = jd.DamperShape(rng.uniform(40, 90, n), rng.uniform(40, 90, n), rng.uniform(-0.2, 0.3, n))
    mu = rng.uniform(0.15, 0.85, n)
    nums = jd.evaluate_designs(jd.stack_designs(shapes, mu, CONTACTS))
    psi = np.geomspace(0.2, 12.0, 12)
    above = (np.asarray(nums.status)[:, None] == RESULTS.ok) & (psi[None] > np.asarray(nums.psi_bc)[:, None])
    assert 40 <= above.sum() <= above.size - 40  # both paths are exercised
    got = jd.amplitude_curves(shapes, mu, psi, CONTACTS)
    ref = jax.jit(lambda s, m: curves_kernel(s, m, CONTACTS, jd.LoadCase(), psi))(shapes, mu)
    np.testing.assert_array_equal(got.status, ref.status)
    np.testing.assert_array_equal(got.cycles, ref.cycles)
    scale = np.max(np.abs(np.asarray(ref.k_re)))
    for a, b in ((got.k_re, ref.k_re), (got.k_im, ref.k_im)):
        assert_tree_allclose(np.asarray(a)[above], np.asarray(b)[above], rtol=1e-9,
                             atol=1e-9 * scale)
        assert_tree_allclose(np.asarray(a)[~above], np.asarray(b)[~above], rtol=1e-9,
                             atol=1e-9 * scale)


@pytest.mark.slow  # 46 worker-s (run of 2026-11-25)
def test_curves_gradients_nan_free_and_match_fd():
    """Reverse- and forward-mode derivatives of k_Re + k_Im w.r.t. theta_L, theta_R, b_R/h, mu, kn,
    kt and psi_a: finite over random designs and amplitudes, including amplitudes whose reversal
    falls exactly on a transition (psi_fs, psi_BC); central differences agree away from switches.
    One batch holds every point (random, special and finite-difference), so that each program is
    compiled once."""
    from jaxdamp.curves import curves_kernel

    rng = np.random.default_rng(7)
    D = 5
    rand = np.stack([rng.uniform(48, 80, D), rng.uniform(48, 80, D), rng.uniform(-0.05, 0.18, D),
                     rng.uniform(0.25, 0.75, D), rng.uniform(1.5e4, 2.5e4, D),
                     rng.uniform(3e3, 5e3, D), rng.uniform(0.3, 5.0, D)], axis=1)
    # Reversals exactly on a transition: 60sym at its own psi_fs and psi_BC.
    n = jd.five_numbers(jd.base_cycle(jd.family_shape("60sym"), 0.5, CONTACTS))
    x0 = np.array([60.0, 60.0, 0.14, 0.5, 17900.0, 3580.0, 1.2])  # microslip, away from switches
    special = np.array([x0, x0])
    special[0, 6], special[1, 6] = float(n.psi_fs), float(n.psi_bc)
    steps = 1e-6 * np.maximum(np.abs(x0), 1.0)
    fd_points = np.concatenate([x0 + steps[:, None] * np.eye(7), x0 - steps[:, None] * np.eye(7)])
    x = jnp.asarray(np.concatenate([rand, special, x0[None], fd_points]))
    i0 = D + 2

    def values(x, initial):
        shape, mu, contacts, psi = _design_params(x)
        cv = curves_kernel(shape, mu, contacts, jd.LoadCase(), psi[:, None], initial=initial)
        return jnp.sum(cv.k_re + cv.k_im, axis=1)

    for initial in ("gross_slip", "assembly"):
        f = jax.jit(lambda x: values(x, initial))
        vals = np.asarray(f(x))
        grad = np.asarray(jax.jit(jax.grad(lambda x: jnp.sum(f(x))))(x))
        assert np.all(np.isfinite(vals)) and np.all(np.isfinite(grad))
        fd = (vals[i0 + 1: i0 + 8] - vals[i0 + 8: i0 + 15]) / (2 * steps)
        assert_tree_allclose(grad[i0], fd, rtol=2e-5, atol=1e-6 * np.max(np.abs(fd)))
        if initial == "assembly":
            tangent = jnp.asarray(rng.normal(size=x.shape)) * jnp.asarray(
                [[1, 1, 0.01, 0.01, 100, 20, 0.05]])
            _, jvp = jax.jit(lambda x, t: jax.jvp(f, (x,), (t,)))(x, tangent)
            # Designs are independent: forward mode = the gradient rows dotted with the tangent.
            assert np.all(np.isfinite(np.asarray(jvp)))
            assert_tree_allclose(np.sum(grad * np.asarray(tangent), axis=1), np.asarray(jvp),
                                 rtol=1e-8, atol=1e-8 * np.max(np.abs(jvp)))


def test_complex_stiffness_methods():
    """complex_stiffness defaults to the exact cycle from gross slip; "interpolated" keeps the
    paper's numbers (psi_fs, k_Re,fs and the Base-Cycle's at psi_BC)."""
    shape, mu = jd.family_shape("60sym"), 0.5
    bc = jd.base_cycle(shape, mu, CONTACTS)
    n = jd.five_numbers(bc)
    psi = np.array([0.3, 1.2])
    for initial in ("gross_slip", "assembly"):
        k_re, k_im = jd.complex_stiffness(bc, psi, initial=initial)
        for j, p in enumerate(psi):
            ac = amplitude_cycle(shape, mu, float(p), CONTACTS, initial=initial)
            assert_tree_allclose(np.array([k_re[j], k_im[j]]), np.array([ac.k_re, ac.k_im]), rtol=1e-12,
                                 atol=1e-9)
    k_re, k_im = jd.complex_stiffness(bc, psi, method="interpolated")
    frac = (1.2 - float(n.psi_fs)) / (float(n.psi_bc) - float(n.psi_fs))
    assert float(k_im[1]) == pytest.approx(frac * float(n.k_im_bc), rel=1e-12)
    with pytest.raises(ValueError, match="method"):
        jd.complex_stiffness(bc, psi, method="spline")


def test_a_runner_runs_the_same_cycle():
    """amplitude_cycle(runner=): the kernel with its static options bound, handed to the runner
    once (the CLI saves it, jaxdamp.cli.exported); the same cycle as the plain call."""
    calls = []

    def runner(program, args):
        calls.append(len(args))
        return program(*args)

    shape = jd.family_shape("60sym")
    through = jd.amplitude_cycle(shape, 0.5, 1.2, runner=runner)
    plain = jd.amplitude_cycle(shape, 0.5, 1.2)
    assert calls == [8] and int(plain.status) == 0
    assert_tree_allclose(through, plain, rtol=1e-12, atol=1e-12)


def test_in_phase_kernels_refuse_a_wedge():
    """The in-phase engine is the curved-flat damper's three pads: a wedge given to its unchecked
    kernels is refused in one line naming br2_over_hr (not an error from inside the engine)."""
    wedge = jd.DamperShape(60.0, 60.0, 0.0, 0.8, br2_over_hr=0.8)
    with pytest.raises(ValueError, match="^br2_over_hr: .*elliptic_cycle"):
        jd.amplitude_kernel(wedge, 0.5, jd.Contacts(), jd.LoadCase(), 2.0)
    with pytest.raises(ValueError, match="^br2_over_hr: "):
        jd.base_cycle_kernel(wedge, 0.5, jd.Contacts(), jd.LoadCase())
