"""The lumped disk (jaxdamp.baselines.lumped_disk): its cyclic sector eigenproblem against the
whole ring's, the mass normalisation, the in-phase path of nodal diameter 0, and the example file."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines.lumped_disk import (LumpedDisk, example_family, full_matrices, modal_family,
                                           sector_matrices, sector_modes, write_example_family)
from jaxdamp.modal_file import EXAMPLE_PATH
from jaxdamp.response.modes import FAMILY_FIELDS

from helpers import assert_tree_allclose


@pytest.mark.parametrize("n_blades", [6, 7, 24])
def test_sector_eigenvalues_are_the_whole_rings(n_blades):
    """The union over phi = 2 pi n / N (n = 0 ... N-1) of the 2x2 sector eigenvalues equals the
    eigenvalues of the full 2N-DOF ring (an independent dense generalised eigenproblem)."""
    disk = LumpedDisk(n_blades=n_blades)
    M, K = full_matrices(disk)
    m_half = 1.0 / np.sqrt(np.diag(M))
    ring = np.sort(np.linalg.eigvalsh(m_half[:, None] * K * m_half[None, :]))
    sectors = np.sort(np.concatenate([sector_modes(disk, 2 * np.pi * n / n_blades)[0]
                                      for n in range(n_blades)]))
    assert_tree_allclose(sectors, ring, rtol=1e-10, atol=0.0)


def test_full_ring_matrices_are_symmetric_and_hold_the_sector_per_travelling_wave():
    """K_ring applied to a travelling wave theta_j = e^{i j phi} Theta gives K(phi) per blade."""
    disk = LumpedDisk(n_blades=8)
    M, K = full_matrices(disk)
    assert_tree_allclose(K, K.T, rtol=0.0, atol=0.0)
    phi = 2 * np.pi * 3 / 8
    shape = np.array([0.3, -1.2])
    y = np.kron(np.exp(1j * phi * np.arange(8)), shape)
    m_s, k_s = sector_matrices(disk, phi)
    expected = np.kron(np.exp(1j * phi * np.arange(8)), k_s @ shape)
    assert_tree_allclose(K @ y, expected, rtol=1e-12, atol=1e-6)
    assert_tree_allclose(M @ y, np.kron(np.exp(1j * phi * np.arange(8)), m_s @ shape),
                         rtol=1e-14, atol=0.0)


def test_modes_are_mass_normalised_per_sector_and_solve_the_eigenproblem():
    disk = LumpedDisk()
    for nd in (0, 5, 12):
        phi = 2 * np.pi * nd / disk.n_blades
        lam, modes = sector_modes(disk, phi)
        M, K = sector_matrices(disk, phi)
        assert_tree_allclose(modes.T @ M @ modes, np.eye(2), rtol=0.0, atol=1e-12)
        assert_tree_allclose(K @ modes, M @ modes * lam[None, :], rtol=1e-10, atol=1e-6)


def test_family_fields_and_the_one_mode_reduction():
    """Frequencies are the first family's; the modal stiffness at the tip is omega^2 / Phi_tip^2;
    the tip force per unit excitation is 1 (the force acts at the response point)."""
    disk = LumpedDisk()
    family = jd.blocks.validate_family(modal_family(disk, 100.0, 20.0))
    assert family.n_blades == 24
    assert family.nodal_diameter.tolist() == list(range(13))
    for nd in (0, 3, 12):
        lam, modes = sector_modes(disk, 2 * np.pi * nd / 24)
        assert_tree_allclose(family.frequency_hz[nd], np.float64(np.sqrt(lam[0]) / (2 * np.pi)),
                             rtol=1e-14, atol=0.0)
        scene = jd.nodal_scene(family, nd, 100.0, 10.0)
        assert_tree_allclose(np.float64(scene.mode.k_b), np.float64(lam[0] / modes[1, 0] ** 2),
                             rtol=1e-12, atol=0.0)
        assert_tree_allclose(np.float64(scene.force_per_unit), np.float64(1.0), rtol=1e-14, atol=0.0)
    # The family rises with nodal diameter (the disk stiffens the roots).
    assert np.all(np.diff(family.frequency_hz) > 0)


def test_nodal_diameter_zero_gives_the_in_phase_path():
    """Fig. 4 kinematics at phi = 0: the damper sees (0, q* theta, 0), and r is the mode's
    root rotation per tip motion (mrad/mm)."""
    disk = LumpedDisk(n_blades=6)
    family = jd.blocks.validate_family(modal_family(disk, 100.0, 20.0))
    scene = jd.nodal_scene(family, 0, 100.0, 10.0)
    assert scene.straight
    inphase = jd.in_phase_motion(100.0)
    assert_tree_allclose(np.asarray(scene.motion.direction), np.asarray(inphase.direction),
                         rtol=0.0, atol=1e-15)
    _, modes = sector_modes(disk, 0.0)
    assert_tree_allclose(np.float64(scene.mode.r), np.float64(1e3 * modes[0, 0] / modes[1, 0]),
                         rtol=1e-12, atol=0.0)


def test_other_nodal_diameters_give_the_interblade_path():
    """At phi the damper's path is interblade_motion(phi)'s direction up to scale and phase."""
    family = jd.blocks.validate_family(modal_family(LumpedDisk(n_blades=6), 100.0, 20.0))
    for e in (1, 2, 3):
        scene = jd.nodal_scene(family, e, 100.0, 10.0)
        ref = jd.interblade_motion(60.0 * e, 20.0, 100.0, 10.0)

        def complex_of(m):
            q = np.zeros(3) if m.quadrature is None else np.asarray(m.quadrature)
            return np.asarray(m.direction) + 1j * q

        a, b = complex_of(scene.motion), complex_of(ref)
        k = int(np.argmax(np.abs(b)))
        assert_tree_allclose(a / a[k] * b[k], b, rtol=1e-12, atol=1e-14)


def test_the_platforms_rotation_per_tip_motion():
    """What the small-rotation model limits, from the disk's own eigenvectors: at nodal diameter
    0 the platforms turn together by the mode's r (mrad per mm of tip: the path parameter is their
    rotation); at N/2 (out of phase) they turn against each other, 2 theta relative, while the
    path parameter scales the whole path, |X_hat| = q*/1000 per mrad: (2 h_C theta, 0, 2 theta)
    gives r = 1e3 |(2 h_C, 2000)| / q* per unit theta, ten times the relative rotation at
    q* = 100 mm."""
    disk = LumpedDisk(n_blades=6)
    family = jd.blocks.validate_family(modal_family(disk, 100.0, 20.0))
    zero, half = jd.nodal_scene(family, 0, 100.0, 10.0), jd.nodal_scene(family, 3, 100.0, 10.0)
    _, modes = sector_modes(disk, 0.0)
    assert_tree_allclose(np.float64(zero.rotation_mrad_per_mm),
                         np.float64(1e3 * modes[0, 0] / modes[1, 0]), rtol=1e-12, atol=0.0)
    _, modes = sector_modes(disk, np.pi)
    relative = 2e3 * abs(modes[0, 0] / modes[1, 0])
    assert_tree_allclose(np.float64(half.rotation_mrad_per_mm), np.float64(relative), rtol=1e-12,
                         atol=0.0)
    assert_tree_allclose(np.float64(half.mode.r / half.rotation_mrad_per_mm),
                         np.float64(np.hypot(40.0, 2000.0) / 200.0), rtol=1e-12, atol=0.0)


def test_example_file_is_what_the_generator_makes_now(tmp_path):
    fresh = write_example_family(tmp_path / "modes.npz")
    with np.load(EXAMPLE_PATH) as stored, np.load(fresh) as new:
        # the example carries its platforms' residual flexibility (issue 61)
        assert set(stored.files) == set(new.files) == set(FAMILY_FIELDS) | {
            "n_blades", "name", "unit_system", "platform_residual"}
        for name in new.files:
            assert stored[name].dtype == new[name].dtype, name
            if stored[name].dtype.kind in "fc":
                assert_tree_allclose(stored[name], new[name], rtol=1e-13, atol=0.0)
            else:
                assert stored[name].tolist() == new[name].tolist(), name
        for name in ("modal_force", "response_displacement", "left_platform", "right_platform"):
            assert np.iscomplexobj(stored[name]), name
        assert stored["n_blades"].shape == stored["name"].shape == ()
    family = example_family()
    assert family.n_blades == 24 and family.platform_residual.shape == (13, 6, 6)
    assert example_family(residual=False).platform_residual is None


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="k_blade"):
        sector_matrices(LumpedDisk(k_blade=-1.0), 0.0)
    with pytest.raises(ValueError, match="n_blades"):
        full_matrices(LumpedDisk(n_blades=1))


@pytest.mark.parametrize("nd", [0, 1, 3])
def test_residual_is_the_sectors_flexibility_without_the_first_mode(nd):
    """platform_residual's theta-theta flexibility against the dense sector solve: (K - w^2 M)^-1
    minus the first mode's theta_1^2 / (w_1^2 - w^2), at w around the first frequency (the
    second family's own share, theta_2^2 / (w_2^2 - w^2), is what is left); mapped to the
    platforms at D by their motion per rad of theta."""
    from jaxdamp.conventions import platform_directions

    disk = LumpedDisk(n_blades=6)
    family = jd.blocks.validate_family(modal_family(disk, 100.0, 20.0, residual=True))
    phi = 2 * np.pi * nd / 6
    M, K = sector_matrices(disk, phi)
    lam, modes = sector_modes(disk, phi)
    # Either side of w_1^2 by 1e-4 (the first mode's term then cancels to 1e-12), averaged: the
    # second family's term is then w_1's to 1e-8.
    g = np.mean([np.linalg.inv(K - w2 * M)[0, 0] - modes[0, 0] ** 2 / (lam[0] - w2)
                 for w2 in lam[0] * (1.0 + np.array([-1e-4, 1e-4]))])
    d = np.concatenate(platform_directions(100.0, 20.0))
    assert_tree_allclose(family.platform_residual[nd], g * np.outer(d, d) + 0j, rtol=1e-6, atol=0.0)
    assert not np.any(jd.blocks.validate_family(modal_family(disk, 100.0, 20.0)).platform_residual)
