"""The reduction of a bladed disk's mode family per engine order (`jaxdamp.response.modes`):
the one-mode blade and the damper's path, against the paper's kinematics and invariances. Numpy
only: nothing here compiles."""

import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.conventions import interblade_direction
from jaxdamp.response import BladeMode
from jaxdamp.response.modes import (ModalFamily, excited_nodal_diameter, family_from_blade_mode,
                                    nodal_scene, validate_family)

Q, H_C, H_L = 100.0, 40.0, 30.0


def _row(n_blades=24, mode=BladeMode(), name="fig4"):
    """Every nodal diameter with the same blade: platforms turning rigidly about C (Fig. 4)."""
    f = family_from_blade_mode(mode, Q, H_C, n_blades)
    n = n_blades // 2 + 1
    rep = lambda v: np.repeat(v, n, axis=0)  # noqa: E731
    return ModalFamily(n_blades, np.arange(n), 500.0 + np.arange(n), rep(f.loss_factor),
                       rep(f.modal_force), rep(f.response_displacement), rep(f.left_platform),
                       rep(f.right_platform), name)


def _mode_array(mode):
    return np.array([float(v) for v in mode])


def test_nodal_diameter_zero_gives_the_one_mode_blade_back():
    mode = BladeMode(430.0, 800.0, 2e-3, 1.7)
    s = nodal_scene(family_from_blade_mode(mode, Q, H_C), 0, Q, H_L)
    assert_tree_allclose(_mode_array(s.mode), _mode_array(mode), rtol=1e-12, atol=0.0)
    assert s.straight and s.nodal_diameter == 0 and s.ibpa_deg == 0.0
    assert_tree_allclose(np.asarray(s.motion.direction), np.array([0.0, Q / 1e3, 0.0]),
                         rtol=0.0, atol=1e-15)
    assert_tree_allclose(np.array(s.force_per_unit), np.array(1.0), rtol=1e-12, atol=0.0)


def test_engine_orders_fold_onto_nodal_diameters():
    got = [excited_nodal_diameter(e, 24) for e in (0, 1, 11, 12, 13, 23, 24, 25, 47)]
    assert got == [(0, False), (1, False), (11, False), (12, False), (11, True), (1, True),
                   (0, False), (1, False), (1, True)]
    assert excited_nodal_diameter(3, 7) == (3, False) and excited_nodal_diameter(4, 7) == (3, True)


@pytest.mark.parametrize("e", [1, 5, 7, 12, 17])
def test_path_is_the_papers_interblade_path(e):
    """With Fig. 4 platforms the reduced path is MODEL.md's X_hat(phi) up to a complex scale:
    |<a, b>| = |a| |b| (Cauchy-Schwarz holds with equality only for parallel complex vectors)."""
    s = nodal_scene(_row(), e, Q, H_L)
    x = np.asarray(s.motion.direction) + 1j * (0.0 if s.straight else np.asarray(s.motion.quadrature))
    ref = interblade_direction(360.0 * e / 24, H_C, Q)
    assert_tree_allclose(np.array(abs(np.vdot(ref, x))),
                         np.array(np.linalg.norm(ref) * np.linalg.norm(x)), rtol=1e-12, atol=0.0)
    assert s.straight == (e % 12 == 0)


def test_backward_wave_runs_the_ellipse_the_other_way():
    """Engine orders e and N - e excite one nodal diameter, travelling opposite ways: the same
    ellipse, run in the opposite sense (quadrature reversed)."""
    fam = _row()
    a, b = nodal_scene(fam, 5, Q, H_L), nodal_scene(fam, 19, Q, H_L)
    assert a.nodal_diameter == b.nodal_diameter == 5
    assert_tree_allclose(np.asarray(b.motion.direction), np.asarray(a.motion.direction),
                         rtol=1e-12, atol=1e-15)  # zeros to rounding of |X| ~ 0.1
    assert_tree_allclose(np.asarray(b.motion.quadrature), -np.asarray(a.motion.quadrature),
                         rtol=1e-12, atol=1e-15)  # zeros to rounding of |X| ~ 0.1
    assert_tree_allclose(_mode_array(b.mode), _mode_array(a.mode), rtol=1e-12, atol=0.0)


def test_reduction_does_not_depend_on_the_modal_coordinates_scale_or_phase():
    """A mode is defined up to a complex factor c: scaling every field by c (the force by conj(c)
    would also do; only |f| enters) leaves the blade, the path and the tip force unchanged."""
    fam = validate_family(_row())
    c = 3.7 * np.exp(0.9j)
    scaled = fam._replace(modal_force=fam.modal_force * c,
                          response_displacement=fam.response_displacement * c,
                          left_platform=fam.left_platform * c, right_platform=fam.right_platform * c)
    for e in (0, 4, 12):
        a, b = nodal_scene(fam, e, Q, H_L), nodal_scene(scaled, e, Q, H_L)
        k_b_ratio = np.array(b.mode.k_b / a.mode.k_b)
        assert_tree_allclose(k_b_ratio, np.array(1.0 / abs(c) ** 2), rtol=1e-12, atol=0.0)
        # k_b scales as 1/|c|^2: a tip mm per unit modal coordinate is |c| times larger; with the
        # force scaled too, the tip force per unit excitation is unchanged.
        assert_tree_allclose(np.array([b.mode.f0_hz, b.mode.eta, b.mode.r, b.force_per_unit]),
                             np.array([a.mode.f0_hz, a.mode.eta, a.mode.r, a.force_per_unit]),
                             rtol=1e-12, atol=0.0)
        assert_tree_allclose(np.asarray(b.motion.direction), np.asarray(a.motion.direction),
                             rtol=1e-12, atol=1e-15)  # zeros to rounding of |X| ~ 0.1


def test_k_b_and_force_follow_mass_normalisation():
    """Tip coordinates of a mass-normalised mode: k_b = omega^2 / |Phi_tip|^2, F_tip = |f| /
    |Phi_tip| (one row made by hand)."""
    fam = ModalFamily(8, np.array([2]), np.array([700.0]), np.array([0.004]),
                      np.array([0.3 - 0.4j]), np.array([2.0j]),
                      np.array([[0.01, 0.02, -1e-4]]) + 0j, np.array([[0.01, -0.02, -1e-4]]) + 0j)
    s = nodal_scene(fam, 2, Q, H_L)
    w = 2 * np.pi * 700.0
    assert_tree_allclose(np.array([s.mode.k_b, s.force_per_unit]), np.array([w * w / 4.0, 0.25]),
                         rtol=1e-12, atol=0.0)
    assert s.ibpa_deg == 90.0 and not s.straight


@pytest.mark.parametrize("change, needle", [
    (dict(nodal_diameter=np.array([0, 1, 1])), "nodal_diameter must not repeat"),
    (dict(nodal_diameter=np.array([0, 1, 13])), "nodal_diameter must hold integers in [0, 12]"),
    (dict(frequency_hz=np.array([500.0, -1.0, 520.0])), "frequency_hz must be"),
    (dict(loss_factor=np.array([0.001, 2.0, 0.001])), "loss_factor must be"),
    (dict(response_displacement=np.array([1.0, 0.0, 1.0])), "response_displacement must be non-zero"),
    (dict(left_platform=np.zeros((3, 2))), "left_platform must have shape (3, 3)"),
    (dict(frequency_hz=np.array([500.0, 510.0j, 520.0])), "frequency_hz must be real"),
    (dict(n_blades=1), "n_blades must be an integer in [2, inf)"),
])
def test_bad_families_are_refused_naming_the_field(change, needle):
    fam = _row()
    fam = fam._replace(**{k: getattr(fam, k)[:3] for k in fam._fields[1:8]})
    with pytest.raises(ValueError) as e:
        validate_family(fam._replace(**change))
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_missing_nodal_diameter_and_bad_engine_order_are_refused():
    fam = _row()
    fam = fam._replace(**{k: getattr(fam, k)[:3] for k in fam._fields[1:8]})
    with pytest.raises(ValueError, match="engine_order 5 excites nodal diameter 5"):
        nodal_scene(fam, 5, Q, H_L)
    with pytest.raises(ValueError, match="engine_order must be an integer"):
        nodal_scene(fam, -1, Q, H_L)
    with pytest.raises(ValueError, match="h_l must be"):
        nodal_scene(fam, 1, Q, -3.0)


def test_family_repr_is_one_line():
    text = repr(validate_family(_row()))
    assert "24 blades" in text and "\n" not in text
    assert "ModalFamily" in repr(jd.ModalFamily(2, [0], [1.0], [0.0], [1.0], [1.0],
                                                [[0, 0, 0]], [[0, 1, 0]]))


def _with_residual(fam, c6):
    return fam._replace(platform_residual=np.broadcast_to(c6, (len(fam.nodal_diameter), 6, 6)))


@pytest.mark.parametrize("c6, needle", [
    (np.zeros((6, 5)), "platform_residual must have shape (13, 6, 6)"),
    (np.diag([1.0, 1, 1, 1, 1, np.nan]), "platform_residual must be finite"),
    (np.triu(np.ones((6, 6))), "platform_residual must be Hermitian"),
    (-np.eye(6), "platform_residual must be positive semi-definite"),
])
def test_bad_residuals_are_refused_naming_the_field(c6, needle):
    fam = _row()
    fam = fam._replace(platform_residual=np.broadcast_to(c6, (13,) + c6.shape)) if c6.shape == (
        6, 6) else fam._replace(platform_residual=c6)
    with pytest.raises(ValueError) as e:
        validate_family(fam)
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_no_residual_is_zero_flexibility():
    fam = validate_family(_row())
    assert fam.platform_residual.shape == (13, 6, 6) and not np.any(fam.platform_residual)
    assert all(nodal_scene(fam, e, Q, H_L).residual_mrad_per_nmm == 0.0 for e in (0, 3, 12))


@pytest.mark.parametrize("e", [0, 1, 5, 12])
def test_path_residual_of_a_rotation_flexibility(e):
    """Platforms that turn about C by theta with a residual flexibility g (rad per N mm) on theta:
    C6 = g d d^T, d = (left; right) per rad. The damper's generalized force M (N mm, work
    1e-3 M psi) is a moment 1e-3 rho M on theta, rho = d psi / d theta (mrad/rad), so c = 1e-3
    rho^2 g, whatever the interblade phase angle. rho from the path's own size per rad of
    theta: the path is r X_unit per mm of tip, theta = r_theta per mm of tip."""
    from jaxdamp.conventions import platform_directions

    g = 3.0e-9
    left, right = platform_directions(Q, H_C)
    d = np.concatenate([left, right])
    fam = _with_residual(_row(), g * np.outer(d, d))
    s = nodal_scene(fam, e, Q, H_L)
    theta_per_tip = BladeMode().r / 1e3  # rad per mm of tip: _row's blade
    x = np.asarray(s.motion.direction) + 1j * (0.0 if s.straight else np.asarray(
        s.motion.quadrature))  # (mm, mm, mrad) per mrad of psi
    # rho: mrad of psi per rad of theta. |X_hat per rad of theta| in (mm, mm, mrad) units equals
    # |x| psi per rad of theta.
    phi = 2 * np.pi * e / 24
    per_theta = (np.exp(1j * phi) * left - right) * np.array([1.0, 1.0, 1e3])
    rho = np.linalg.norm(per_theta) / np.linalg.norm(x)
    assert_tree_allclose(np.array(s.residual_mrad_per_nmm), np.array(1e-3 * rho ** 2 * g),
                         rtol=1e-12, atol=0.0)
    assert_tree_allclose(np.array(rho), np.array(s.mode.r / theta_per_tip), rtol=1e-12, atol=0.0)
