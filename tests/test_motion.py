"""Straight platform paths beyond the in-phase one (jaxdamp.motion; issue 34's straight paths).

References: rigid-body kinematics written out here with exact rotation matrices, the paper's
in-phase cycle (a path that is in-phase must give it), the work identities (the modal force's
loop work is the energy dissipated at the pads, sum of T d(slip); and pi a^2 k_Im), the erasure of
history above gross slip, and the project's time marcher run on the same path."""

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines.timemarch import march_amplitude
from jaxdamp.geometry import section_geometry
from jaxdamp.motion import as_ellipse, pad_motion

from helpers import assert_tree_allclose, fd_jvp

CONTACTS = jd.Contacts(17900.0, 3580.0)
LOAD = jd.LoadCase()


def rotation(theta_rad):
    c, s = np.cos(theta_rad), np.sin(theta_rad)
    return np.array([[c, -s], [s, c]])


@pytest.mark.parametrize("name", ["60sym", "74R", "90L"])
def test_pad_motion_is_the_right_platforms_rigid_motion(name):
    """nw, tw against the pads' displacement under a small exact rigid motion of the right
    platform (rotation matrix about D, then translation), per mm of the path parameter."""
    shape = jd.family_shape(name)
    rng = np.random.default_rng(7)
    h_l = 14.0
    geo = section_geometry(shape)
    H = h_l * np.sin(np.deg2rad(shape.theta_l))  # mm per unit of the normalised section
    points = (np.asarray(geo.points) - np.asarray(geo.D)) * H  # pads relative to D, mm
    for _ in range(4):
        direction = rng.normal(size=3) * np.array([0.05, 0.05, 2.0])
        motion = jd.straight_motion(direction, h_l)
        nw, tw = (np.asarray(v) for v in pad_motion(shape, motion, LOAD.q_star))
        eps = 1e-6  # mrad of amplitude
        moved = points @ rotation(eps * direction[2] * 1e-3).T + eps * direction[:2]
        disp = (moved - points) / (eps * LOAD.q_star * 1e-3)  # per mm of the path parameter
        scale = np.max(np.abs(disp))
        assert_tree_allclose(np.asarray(nw[0], float),
                             np.asarray(np.dot(geo.normals[0], disp[0]), float),
                             rtol=0, atol=1e-7 * scale)
        assert_tree_allclose(np.asarray(tw[0], float),
                             np.asarray(np.dot(geo.tangents[0], disp[0]), float),
                             rtol=0, atol=1e-7 * scale)
        assert np.all(nw[1:] == 0.0) and np.all(tw[1:] == 0.0)  # the left platform is the reference


@pytest.mark.parametrize("h_c", [0.0, 25.0])
def test_interblade_paths_are_the_blades_rotations_about_their_centres(h_c):
    """phi = 0 is the in-phase motion; phi = 180 the relative motion of two platforms turning in
    opposite senses about centres h_c below D and q*/2 to each side (clockwise rotation matrices)."""
    q = 100.0
    assert np.array_equal(np.asarray(jd.interblade_motion(0, h_c, q).direction),
                          np.asarray(jd.in_phase_motion(q).direction))
    eps = 1e-6  # mrad of the left blade's clockwise rotation
    D = np.zeros(2)

    def platform_at_D(centre, theta_mrad):
        R = rotation(-theta_mrad * 1e-3)  # clockwise
        return centre + R @ (D - centre) - D

    left = platform_at_D(np.array([-q / 2, -h_c]), eps)
    right = platform_at_D(np.array([q / 2, -h_c]), -eps)  # phi = 180: the opposite rotation
    expected = np.array([*(right - left) / eps, (-(-eps) + eps) / eps])  # relative ccw rotation
    got = np.asarray(jd.interblade_motion(180, h_c, q, h_l_mm=10.0).direction)
    assert_tree_allclose(np.asarray(got, float), np.asarray(expected, float), rtol=1e-6, atol=1e-9)
    assert got[1] == 0.0  # out-of-phase: no relative radial motion


def test_paths_that_are_not_straight_or_inputs_out_of_range_are_refused():
    with pytest.raises(ValueError, match=r"^ibpa must be a finite angle in \[-360, 360\] deg"):
        jd.interblade_motion(np.nan, 20.0)
    with pytest.raises(ValueError, match=r"^motion must be a straight path"):
        jd.straight_motion([0.01, 0.05j, 1.0])
    # Other phase angles and complex directions are ellipses (tests/test_ellipse.py).
    assert jd.interblade_motion(90.0, 20.0, h_l_mm=10.0).quadrature is not None
    assert jd.general_motion([0.01, 0.05j, 1.0], 10.0).quadrature is not None
    with pytest.raises(ValueError, match=r"^motion must be non-zero"):
        jd.straight_motion([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^h_l must be in \(0, 10000\] mm"):
        jd.straight_motion([0.0, 0.1, 1.0], h_l_mm=-1.0)
    with pytest.raises(ValueError, match=r"^h_l must be given for a motion that turns the platforms"):
        jd.interblade_motion(180, 20.0)
    with pytest.raises(ValueError, match=r"^h_c must be a finite number in \[-10000, 10000\] mm; got inf"):
        jd.interblade_motion(180, np.inf)
    # A complex direction that is real up to one phase is the same straight path.
    a = jd.straight_motion(np.exp(0.7j) * np.array([0.01, -0.05, 1.0]), 10.0)
    assert_tree_allclose(a.direction, jnp.array([0.01, -0.05, 1.0]), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("name,mu", [("60sym", 0.5), ("74R", 0.3)])
@pytest.mark.parametrize("initial", ["assembly", "gross_slip"])
def test_an_in_phase_path_gives_the_papers_cycle(name, mu, initial):
    """The same cycle as the in-phase model (the same tracts; from gross slip the start state comes
    from assembly and a run up the path instead of the full-slip statics, equal to rounding), with
    k from the modal force, which differs from the paper's moment by a constant only (the damper's
    equilibrium)."""
    shape = jd.family_shape(name)
    for psi in (0.3, 1.0, 5.0):
        ref = jd.amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
        got = jd.amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial,
                                 motion=jd.in_phase_motion(LOAD.q_star))
        assert int(got.status) == int(ref.status)
        assert_tree_allclose((got.forward.dv, got.backward.dv), (ref.forward.dv, ref.backward.dv),
                             rtol=1e-12, atol=1e-15)
        scale = float(abs(ref.k_re))
        assert_tree_allclose((got.k_re, got.k_im), (ref.k_re, ref.k_im), rtol=0, atol=1e-12 * scale)
        assert_tree_allclose(got.energy, ref.energy, rtol=1e-12, atol=1e-12 * float(abs(ref.work)))


PATHS = [  # (shape, mu, motion, amplitude mrad): out-of-phase, and general straight directions
    ("60sym", 0.5, jd.interblade_motion(180, 20.0, 100.0, 10.0), 10.0),
    ("60sym", 0.3, jd.interblade_motion(180, 60.0, 100.0, 10.0), 5.0),
    ("74R", 0.3, jd.straight_motion([0.03, 0.05, 1.5], 12.0), 5.0),
    ("90L", 0.7, jd.straight_motion([-0.02, 0.08, -1.0], 8.0), 3.0),
]


@pytest.mark.parametrize("name,mu,motion,psi", PATHS)
def test_the_modal_forces_loop_work_is_the_energy_dissipated_at_the_pads(name, mu, motion, psi):
    ac = jd.amplitude_cycle(jd.family_shape(name), mu, psi, CONTACTS, initial="assembly",
                            motion=motion)
    assert jd.RESULTS.name_of(ac.status) == "ok"
    work = float(ac.work)
    assert work > 0.0
    assert_tree_allclose(np.asarray(float(np.sum(ac.energy)), float),
                         np.asarray(work, float),
                         rtol=1e-10, atol=0.0)
    assert_tree_allclose(np.asarray(np.pi * psi**2 * float(ac.k_im) * 1e-3, float),
                         np.asarray(work, float),
                         rtol=1e-10, atol=0.0)


def test_gross_slip_erases_the_history_on_a_path():
    """Above the amplitude at which every pad slips, the assembly and gross-slip histories reach
    the same steady cycle; below, they need not."""
    shape, motion = jd.family_shape("60sym"), jd.interblade_motion(180, 20.0, 100.0, 10.0)
    big = [jd.amplitude_cycle(shape, 0.5, 20.0, CONTACTS, initial=h, motion=motion)
           for h in ("assembly", "gross_slip")]
    assert all(jd.RESULTS.name_of(c.status) == "ok" for c in big)
    assert_tree_allclose((big[0].k_re, big[0].k_im), (big[1].k_re, big[1].k_im), rtol=1e-10, atol=0)
    small = [jd.amplitude_cycle(shape, 0.5, 5.0, CONTACTS, initial=h, motion=motion)
             for h in ("assembly", "gross_slip")]
    assert [jd.RESULTS.name_of(c.status) for c in small] == ["ok", "shakedown"]


def _against_marcher(name, mu, motion, psi, rtol):
    shape = jd.family_shape(name)
    ac = jd.amplitude_cycle(shape, mu, psi, CONTACTS, initial="assembly", motion=motion)
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial="assembly", n_steps=4000, max_pairs=3,
                         motion=motion)
    assert jd.RESULTS.name_of(tm.status) == "ok" and int(tm.newton_failures) == 0
    assert float(np.asarray(tm.closure)[-1]) < 1e-9
    scale = max(abs(float(ac.k_re)), abs(float(ac.k_im)))
    assert_tree_allclose(np.asarray([float(tm.k_re), float(tm.k_im)], float),
                         np.asarray([float(ac.k_re), float(ac.k_im)], float),
                         rtol=0, atol=rtol * scale)
    assert_tree_allclose(np.asarray(np.asarray(tm.work_contacts), float),
                         np.asarray(np.asarray(ac.energy), float),
                         rtol=0, atol=rtol * float(ac.work))


def test_out_of_phase_agrees_with_the_time_marcher():
    _against_marcher(*PATHS[0], rtol=1e-6)


@pytest.mark.parametrize("name,mu,motion,psi", PATHS[1:])
def test_straight_paths_agree_with_the_time_marcher(name, mu, motion, psi):
    _against_marcher(name, mu, motion, psi, rtol=1e-6)


@pytest.mark.slow  # 13 worker-s (2026-11-26): the forward derivative program of the amplitude kernel
def test_derivative_along_the_rotation_centre_matches_finite_differences():
    shape, mu, psi = jd.family_shape("60sym"), 0.5, 10.0
    shape, mu, contacts, load = jd.params.prepare_inputs(shape, mu, CONTACTS, LOAD)

    @jax.jit
    def k(h_c):
        direction = jnp.stack([-2.0 * h_c / 1e3, 0.0, 2.0])
        m = jd.Motion(direction, jnp.asarray(10.0))
        ac = jd.amplitude_kernel(shape, mu, contacts, load, jnp.asarray(psi), initial="assembly",
                                 motion=m)
        return jnp.stack([ac.k_re, ac.k_im])

    h_c = jnp.asarray(20.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, tangent = jax.jvp(k, (h_c,), (jnp.asarray(1.0),))
    fd = fd_jvp(k, h_c, jnp.asarray(1.0), h=1e-4)
    assert np.all(np.isfinite(np.asarray(tangent)))
    assert_tree_allclose(np.asarray(np.asarray(tangent), float),
                         np.asarray(np.asarray(fd), float),
                         rtol=1e-6, atol=1e-6 * float(jnp.max(jnp.abs(fd))))


def test_as_ellipse_gives_a_straight_path_zero_width_and_leaves_an_ellipse():
    straight = jd.interblade_motion(180.0, 20.0, 100.0, 10.0)
    assert straight.quadrature is None
    flat = as_ellipse(straight)
    assert_tree_allclose((flat.direction, flat.h_l), (straight.direction, straight.h_l), rtol=0,
                         atol=0)
    assert np.all(np.asarray(flat.quadrature) == 0.0) and flat.quadrature.shape == (3,)
    ellipse = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    assert as_ellipse(ellipse) is ellipse
