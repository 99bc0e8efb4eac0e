"""Steady cycles on elliptic platform paths (jaxdamp.ellipse; issue 34).

References: the straight-path engine (`amplitude_cycle`), whose events are linear in the travel,
run on the same path written as a degenerate ellipse (events as roots of c + alpha cos + beta
sin); the work identity (the modal forces' work per cycle, from forces and platform motion, is
the energy dissipated at the pads, from friction forces and slips); equilibrium and the friction
cone at every tract; the invariance of the cycle under a shift of the path's time origin."""

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import slip_fraction
from jaxdamp.ellipse import elliptic_kernel
from jaxdamp.params import prepare_inputs
from jaxdamp.tract import SLIP

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)
SHAPE = jd.family_shape("60sym")


# One compiled program for every case (elliptic_cycle refuses a zero quadrature; the kernel takes it).
KERNEL = jax.jit(elliptic_kernel, static_argnames=("initial", "max_tracts", "max_periods", "loop"))


def kernel(shape, mu, psi, motion, initial="assembly"):
    sh, m, c, load = prepare_inputs(shape, mu, CONTACTS, jd.LoadCase())
    return KERNEL(sh, m, c, load, jnp.asarray(psi), motion, initial=initial)


@pytest.mark.parametrize("name,mu,direction", [
    ("60sym", 0.5, [0.0, 0.1, 0.0]),      # in-phase
    ("74R", 0.3, [-0.04, 0.0, 2.0]),      # out-of-phase, h_C = 20 mm
    ("90L", 0.7, [0.03, 0.05, 1.5]),      # a general straight direction
])
# gross_slip: 22 worker-s (2026-11-26) in the slow tier; the gross-slip history on an ellipse is
# also test_agrees_with_the_time_marcher_on_the_ellipse's
@pytest.mark.parametrize("initial", ["assembly",
                                     pytest.param("gross_slip", marks=pytest.mark.slow)])
def test_a_straight_path_run_as_an_ellipse_gives_the_straight_engines_cycle(name, mu, direction,
                                                                          initial):
    """Zero quadrature: the same path, the events found as sinusoid roots in tau instead of
    linear ones in the travel, and the same history (assembly, or gross slip up the path)."""
    shape = jd.family_shape(name)
    straight = jd.straight_motion(direction, 10.0)
    as_ellipse = straight._replace(quadrature=jnp.zeros(3))
    for psi in (1.0, 5.0, 20.0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", jd.SmallRotationWarning)
            ref = jd.amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial, motion=straight)
        got = kernel(shape, mu, psi, as_ellipse, initial)
        assert jd.RESULTS.name_of(got.status) == jd.RESULTS.name_of(ref.status)
        scale = max(abs(float(ref.k_re)), abs(float(ref.k_im)))
        assert_tree_allclose((got.k_re, got.k_im), (ref.k_re, ref.k_im), rtol=0, atol=1e-10 * scale)
        assert_tree_allclose(got.energy, ref.energy, rtol=0, atol=1e-10 * max(float(ref.work), 1.0))
        # Time fractions: the ellipse's tract lengths in tau against arccos of the straight
        # halves' travel, which near an extreme turns a rounding of 1e-16 in cos tau into
        # sqrt(2e-16) = 1.5e-8 rad: the tolerance is a few of those over 2 pi.
        assert_tree_allclose(got.slip_fraction, jnp.asarray(slip_fraction(ref)), rtol=0, atol=2e-8)


PATHS = [(phi, psi) for phi in (30.0, 90.0, -90.0, 150.0) for psi in (2.0, 10.0)]


@pytest.mark.parametrize("phi,psi", PATHS)
def test_work_per_cycle_is_the_energy_dissipated_at_the_pads(phi, psi):
    ec = jd.elliptic_cycle(SHAPE, 0.5, psi, jd.interblade_motion(phi, 20.0, 100.0, 10.0), CONTACTS)
    assert jd.RESULTS.name_of(ec.status) == "ok"
    assert float(ec.closure) <= 1e-9
    work = float(ec.work)
    assert work > 0.0 and float(ec.k_im) > 0.0
    assert_tree_allclose(np.asarray(float(np.sum(ec.energy)), float),
                         np.asarray(work, float),
                         rtol=1e-9, atol=0.0)
    assert np.all(np.asarray(ec.energy) >= -1e-9 * work)  # friction only dissipates


def test_every_tract_balances_the_damper_and_keeps_the_cone():
    ec = jd.elliptic_cycle(SHAPE, 0.5, 10.0, jd.interblade_motion(90.0, 20.0, 100.0, 10.0), CONTACTS)
    arc, s_a = ec.period, 10.0 * 100.0 / 1e3
    act = np.asarray(arc.active)
    assert abs(float(np.sum(np.asarray(arc.dp)[act])) - 2 * np.pi) < 1e-12  # one whole period
    mech_a = jd.cycle.mechanics(*prepare_inputs(SHAPE, 0.5, CONTACTS, jd.LoadCase()))
    for k in np.flatnonzero(act):
        t0, t1 = float(arc.p0[k]), float(arc.p0[k] + arc.dp[k])
        for t in (t0, 0.5 * (t0 + t1), t1):
            dc, ds = np.cos(t) - np.cos(t0), np.sin(t) - np.sin(t0)
            N = np.asarray(arc.N0[k] + s_a * (arc.dN[k, 0] * dc - arc.dN[k, 1] * ds))
            T = np.asarray(arc.T0[k] + s_a * (arc.dT[k, 0] * dc - arc.dT[k, 1] * ds))
            residual = -N @ np.asarray(mech_a.a) + T @ np.asarray(mech_a.c) + np.array([0.0, 1.0, 0.0])
            assert np.max(np.abs(residual)) <= 1e-12
            assert np.all(N > 0.0) and np.all(np.abs(T) <= 0.5 * N + 1e-12)
            slipping = np.asarray(arc.state[k]) == SLIP
            assert_tree_allclose(np.asarray(np.abs(T[slipping]), float),
                                 np.asarray(0.5 * N[slipping], float),
                                 rtol=1e-12, atol=1e-14)


def test_a_shift_of_the_time_origin_leaves_the_cycle():
    """X_hat e^{i alpha} is the same ellipse started elsewhere: the steady cycle (from explicit
    forces, as the history's start moves with the origin) and k do not change."""
    motion = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    ref = jd.elliptic_cycle(SHAPE, 0.5, 10.0, motion, CONTACTS)
    x = np.asarray(motion.direction) + 1j * np.asarray(motion.quadrature)
    alpha = 0.8
    # The forces at tau = 0 of the shifted path are those of the reference at tau = alpha
    # (s_a = a q* / 1e3 = 1 mm).
    arc, act = ref.period, np.asarray(ref.period.active)
    starts, ends = np.asarray(arc.p0), np.asarray(arc.p0 + arc.dp)
    k = int(np.flatnonzero((starts <= alpha) & (ends > alpha) & act)[0])
    dc, ds = np.cos(alpha) - np.cos(starts[k]), np.sin(alpha) - np.sin(starts[k])
    N = np.asarray(arc.N0[k] + arc.dN[k, 0] * dc - arc.dN[k, 1] * ds)
    T = np.asarray(arc.T0[k] + arc.dT[k, 0] * dc - arc.dT[k, 1] * ds)
    shifted = jd.general_motion(x * np.exp(1j * alpha), 10.0)
    got = jd.elliptic_cycle(SHAPE, 0.5, 10.0, shifted, CONTACTS, initial=(N, T))
    assert jd.RESULTS.name_of(got.status) == "ok"
    assert_tree_allclose((got.k_re, got.k_im), (ref.k_re, ref.k_im), rtol=1e-9, atol=0)
    assert_tree_allclose(got.energy, ref.energy, rtol=1e-9, atol=1e-9 * float(ref.work))


def test_opposite_phase_angles_run_the_ellipse_in_opposite_senses():
    """+phi and -phi: the same ellipse, run the other way round. The curved-flat damper is not
    mirror-symmetric, so the two cycles differ; each is a valid dissipative cycle."""
    plus = jd.elliptic_cycle(SHAPE, 0.5, 10.0, jd.interblade_motion(90.0, 20.0, 100.0, 10.0), CONTACTS)
    minus = jd.elliptic_cycle(SHAPE, 0.5, 10.0, jd.interblade_motion(-90.0, 20.0, 100.0, 10.0), CONTACTS)
    assert_tree_allclose(plus.motion.direction, minus.motion.direction, rtol=1e-12, atol=1e-15)
    assert_tree_allclose(plus.motion.quadrature, -minus.motion.quadrature, rtol=1e-12, atol=1e-15)
    assert float(plus.k_im) > 0.0 and float(minus.k_im) > 0.0
    assert abs(float(plus.k_im) - float(minus.k_im)) > 1e-3 * float(plus.k_im)


def test_elliptic_inputs_are_checked_and_paths_go_to_their_solver():
    motion = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    with pytest.raises(ValueError, match=r"^motion must be a straight path for amplitude_cycle"):
        jd.amplitude_cycle(SHAPE, 0.5, 1.0, CONTACTS, motion=motion)
    with pytest.raises(ValueError, match=r"^motion must be elliptic for elliptic_cycle"):
        jd.elliptic_cycle(SHAPE, 0.5, 1.0, jd.interblade_motion(180.0, 20.0, 100.0, 10.0))
    with pytest.raises(ValueError, match=r"^amplitude_mrad must be in \(0, 10000\] mrad"):
        jd.elliptic_cycle(SHAPE, 0.5, 0.0, motion)
    with pytest.raises(ValueError, match=r"^initial must be assembly, gross_slip or an \(N, T\) pair"):
        jd.elliptic_cycle(SHAPE, 0.5, 1.0, motion, initial="steady")
    # An explicit start that is not a pair of arrays, or not admissible: one line naming initial
    # (amplitude_cycle's explicit starts go through the same check, `amplitude.explicit_start`).
    for start in (5, ("a", "b"), (np.ones(3), np.ones(3), np.ones(3))):
        with pytest.raises(ValueError, match=r"^initial must be assembly, gross_slip or an \(N, T\) "
                                             r"pair of arrays of one force per pad \(R1, L1, L2\)"):
            jd.elliptic_cycle(SHAPE, 0.5, 1.0, motion, initial=start)
    N, T, _ = jd.amplitude.gross_slip_state(SHAPE, 0.5)
    for cycle in (lambda s: jd.elliptic_cycle(SHAPE, 0.5, 1.0, motion, initial=s),
                  lambda s: jd.amplitude_cycle(SHAPE, 0.5, 1.0, initial=s)):
        with pytest.raises(ValueError, match=r"^initial \(N, T\) must be in equilibrium with F_D: "
                                             r"residual must be in \[0, 1e-06\] F_D; got 0.08"):
            cycle((1.1 * np.asarray(N), T))
    with pytest.raises(ValueError, match=r"^ibpa must be a finite angle in \[-360, 360\] deg"):
        jd.interblade_motion(400.0, 20.0)
    jax.config.update("jax_enable_x64", False)
    try:
        with pytest.raises(jd.Float64Required, match="enable_x64"):
            jd.elliptic_cycle(SHAPE, 0.5, 1.0, motion)
    finally:
        jax.config.update("jax_enable_x64", True)


# The last case: L1 and L2, on one flank, stop slipping together in gross slip, and only L2 may
# stick; the first order ties, the second order decides (`engine.choose`). Without that
# check k was 1.4e-4 of its scale off the marcher at every step count.
MARCHER_CASES = [("60sym", 0.5, 90.0, 10.0, 20.0, 10.0), ("74R", 0.3, -60.0, 5.0, 20.0, 10.0),
                 ("90L", 0.7, 150.0, 10.0, 20.0, 10.0),
                 (jd.DamperShape(42.038, 53.806, 0.242), 0.629, -101.991, 24.366, 55.335, 11.736)]


@pytest.mark.parametrize("name,mu,phi,psi,h_c,h_l,initial",
                         [c + ("assembly",) for c in MARCHER_CASES]
                         # microslip, where gross slip and assembly give other cycles (k_Im
                         # 952 against 229 and 1742 against 1266 N mm/mrad)
                         + [("60sym", 0.5, 60.0, 1.0, 20.0, 10.0, "gross_slip"),
                            pytest.param("60sym", 0.7, -30.0, 1.5, 20.0, 10.0, "gross_slip",
                                         marks=pytest.mark.slow)])
def test_agrees_with_the_time_marcher_on_the_ellipse(name, mu, phi, psi, h_c, h_l, initial):
    """The marcher (Newton with return mapping at 8000 uniform steps of tau per period, no events)
    converges to the direct method at second order: 1e-6 of the scale at 2000 steps, 1e-8 at
    8000 (benchmarks/results/ellipse_vs_marcher.json)."""
    from jaxdamp.baselines.ellipse_march import march_ellipse

    shape = jd.family_shape(name) if isinstance(name, str) else name
    motion = jd.interblade_motion(phi, h_c, 100.0, h_l)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        ec = jd.elliptic_cycle(shape, mu, psi, motion, CONTACTS, initial=initial)
    tm = march_ellipse(shape, mu, psi, motion, CONTACTS, n_steps=8000, periods=3, initial=initial)
    assert jd.RESULTS.name_of(tm.status) == "ok" and int(tm.newton_failures) == 0
    assert float(tm.closure) < 1e-9
    scale = max(abs(float(ec.k_re)), abs(float(ec.k_im)))
    assert_tree_allclose(np.asarray([float(tm.k_re), float(tm.k_im)], float),
                         np.asarray([float(ec.k_re), float(ec.k_im)], float),
                         rtol=0, atol=1e-6 * scale)
    assert_tree_allclose(np.asarray(np.asarray(tm.energy), float),
                         np.asarray(np.asarray(ec.energy), float),
                         rtol=0, atol=1e-5 * float(ec.work))


@pytest.mark.slow  # 21 worker-s (2026-11-26): the forward derivative program of the elliptic kernel
def test_derivative_along_the_phase_angle_matches_finite_differences():
    """d k / d phi by forward mode through the events (closed-form roots) against central
    differences, away from a change of the event sequence."""
    sh, mu, c, load = prepare_inputs(SHAPE, 0.5, CONTACTS, jd.LoadCase())

    @jax.jit
    def k(phi_deg):
        e = jnp.exp(1j * jnp.deg2rad(phi_deg))
        x = jnp.stack([20.0 * (e - 1.0) / 1e3, 50.0 * (e + 1.0) / 1e3, -(e - 1.0)])
        motion = jd.Motion(jnp.real(x), jnp.asarray(10.0), jnp.imag(x))
        ec = elliptic_kernel(sh, mu, c, load, jnp.asarray(10.0), motion, initial="assembly")
        return jnp.stack([ec.k_re, ec.k_im])

    phi = jnp.asarray(70.0)
    _, tangent = jax.jvp(k, (phi,), (jnp.asarray(1.0),))
    fd = (np.asarray(k(phi + 1e-4)) - np.asarray(k(phi - 1e-4))) / 2e-4
    assert np.all(np.isfinite(np.asarray(tangent)))
    assert_tree_allclose(np.asarray(np.asarray(tangent), float),
                         np.asarray(fd, float),
                         rtol=1e-5, atol=1e-6 * float(np.max(np.abs(fd))))
