"""The whole ring with explicit dampers, integrated in time (jaxdamp.baselines.ring): linear
without dampers against the frequency-domain sector solution and the one-mode closed form, and the
dampers of a travelling wave as time-shifted copies of each other."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines.lumped_disk import LumpedDisk, modal_family, sector_matrices
from jaxdamp.baselines.ring import linear_ring_response, ring_response, travelling_force

from helpers import assert_tree_allclose

SHAPE = jd.family_shape("60sym")
GEOMETRY = dict(h_c_mm=20.0, h_l_mm=10.0)


def _bare(disk, e, force, freq, periods, steps=64):
    return ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, e, force, freq,
                         n_periods=periods, steps_per_period=steps, dampers=False, **GEOMETRY)


def test_bare_ring_from_rest_reaches_the_sector_solution():
    """Without dampers the ring is linear: from rest, its steady first harmonic at every nodal
    diameter is the 2x2 sector solve (K(phi) (1 + i eta) - omega^2 M) [Theta, X] = [0, F], the
    same at every blade, phase-shifted by e phi. eta = 0.05 makes the transient decay in ~100
    periods (the damping is (eta / omega) K: mode n decays by exp(-pi eta (omega_n / omega)^2)
    per forcing period, at worst e^-13 here over 120 periods, 600 Hz against the lowest mode's
    506 Hz)."""
    disk = LumpedDisk(n_blades=6, eta=0.05)
    freq, force = 600.0, 2.0
    for e in range(4):
        r = _bare(disk, e, force, freq, periods=120)
        phi = 2 * np.pi * e / 6
        M, K = sector_matrices(disk, phi)
        _, x = np.linalg.solve(K * (1 + 1j * disk.eta) - (2 * np.pi * freq) ** 2 * M,
                               np.array([0.0, force]))
        assert_tree_allclose(np.asarray(r.amplitude_mm), np.full(6, abs(x)), rtol=1e-3, atol=0.0)
        expected_phase = np.angle(x * np.exp(1j * phi * np.arange(6)))
        dphase = np.angle(np.exp(1j * (np.asarray(r.phase_rad) - expected_phase)))
        assert_tree_allclose(dphase, np.zeros(6), rtol=0.0, atol=2e-3)
        assert int(r.status) == int(jd.RESULTS.ok)


def test_force_phase_shifts_the_steady_solution():
    """force_phase_rad alpha: F_j(t) = F cos(omega t + j phi + alpha), so the linear ring's steady
    first harmonic is the sector solve times e^{i (j phi + alpha)}."""
    disk = LumpedDisk(n_blades=6, eta=0.05)
    freq, force, alpha = 600.0, 2.0, 0.7  # the transient as in the test above
    r = ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, 2, force, freq,
                      n_periods=120, steps_per_period=64, dampers=False, force_phase_rad=alpha,
                      **GEOMETRY)
    M, K = sector_matrices(disk, 2 * np.pi * 2 / 6)
    _, x = np.linalg.solve(K * (1 + 1j * disk.eta) - (2 * np.pi * freq) ** 2 * M,
                           np.array([0.0, force]))
    expected = x * np.exp(1j * (2 * np.pi * 2 / 6 * np.arange(6) + alpha))
    got = np.asarray(r.amplitude_mm) * np.exp(1j * np.asarray(r.phase_rad))
    assert_tree_allclose(got, expected, rtol=2e-3, atol=0.0)


def test_bare_ring_at_resonance_is_the_one_mode_closed_form():
    """At each nodal diameter's natural frequency, the steady tip amplitude is
    |F_tip| / |k_b (1 - w^2/w0^2 + i eta)| = F / (eta k_b) of the reduced one-mode blade
    (`nodal_scene`) within 1e-3 (the second family adds ~eta (w1/w2)^2 of that)."""
    disk = LumpedDisk(n_blades=6, eta=0.05)
    family = jd.blocks.validate_family(modal_family(disk, 100.0, 20.0))
    for e in range(4):
        scene = jd.nodal_scene(family, e, 100.0, 10.0)
        f0 = scene.mode.f0_hz
        r = _bare(disk, e, 1.0, f0, periods=150)
        closed = scene.force_per_unit / abs(scene.mode.k_b * (1 + 1j * scene.mode.eta - 1.0))
        assert_tree_allclose(np.asarray(r.amplitude_mm), np.full(6, closed), rtol=1e-3, atol=0.0)


def test_linear_ring_response_matches_the_sector_solution():
    disk = LumpedDisk(n_blades=8)
    y = linear_ring_response(disk, 3, 1.5, 950.0)
    M, K = sector_matrices(disk, 2 * np.pi * 3 / 8)
    sector = np.linalg.solve(K * (1 + 1j * disk.eta) - (2 * np.pi * 950.0) ** 2 * M,
                             np.array([0.0, 1.5]))
    shift = travelling_force(8, 3)
    assert_tree_allclose(y[1::2], sector[1] * shift, rtol=1e-10, atol=0.0)
    assert_tree_allclose(y[0::2], sector[0] * shift, rtol=1e-10, atol=0.0)


def test_travelling_wave_dampers_are_time_shifted_copies():
    """Engine order 1 on 6 blades: in the steady state damper j's modal forces are damper 0's
    shifted by j/6 of a period, every blade's amplitude the same. From rest with the dampers
    slipping (a large force near the nodal-diameter-1 frequency, 515 Hz; eta 0.02 for a short
    transient)."""
    disk = LumpedDisk(n_blades=6, eta=0.02)
    steps = 60  # a multiple of 6: the shift is a whole number of steps
    r = ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, 1, 60.0, 515.0,
                      n_periods=70, steps_per_period=steps, **GEOMETRY)
    assert int(r.status) == int(jd.RESULTS.ok)
    moments = np.asarray(r.damper_moment)  # (steps, N, 2)
    scale = np.max(np.abs(moments))
    assert scale > 0.0
    for j in range(1, 6):
        # Blade j leads blade 0 by j phi: its signal at t equals blade 0's at t + j T/6.
        shifted = np.roll(moments[:, 0, :], -j * steps // 6, axis=0)
        assert_tree_allclose(moments[:, j, :] / scale, shifted / scale, rtol=0.0, atol=2e-3)
    assert float(r.spread) < 2e-3


def test_bad_inputs_are_refused():
    disk = LumpedDisk(n_blades=6)
    with pytest.raises(ValueError, match="x0"):
        ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, 1, 1.0, 900.0,
                      x0=np.zeros(5), **GEOMETRY)
    with pytest.raises(ValueError, match="force_phase_rad"):
        ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, 1, 1.0, 900.0,
                      force_phase_rad=np.nan, **GEOMETRY)
    with pytest.raises(ValueError, match="frequency_hz"):
        ring_response(SHAPE, 0.5, jd.Contacts(), jd.LoadCase(), disk, 1, 1.0, -1.0, **GEOMETRY)
