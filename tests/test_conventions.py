"""The conventions module: unit conversions and the first-harmonic sign, checked on loops whose
harmonics are known in closed form."""

import numpy as np
import pytest

from jaxdamp import conventions as C

from helpers import assert_tree_allclose


def test_units_round_trip():
    assert C.psi_mrad(0.1, 100.0) == pytest.approx(1.0)
    assert C.travel_mm(C.psi_mrad(0.37, 80.0), 80.0) == pytest.approx(0.37)
    assert C.platform_arm(100.0, 5.0) == 55.0


def test_elliptic_loop_gives_its_complex_stiffness():
    """M = psi_a (k_re cos tau - k_im sin tau) must return (k_re, k_im), with k_im > 0 for the loop
    traversed with positive work oint M dpsi = pi psi_a^2 k_im (psi = psi_a cos tau)."""
    k_re, k_im, psi_a = 2.0e4, 3.0e3, 1.7
    n = 256
    tau = 2 * np.pi * np.arange(n) / n
    M = psi_a * (k_re * np.cos(tau) - k_im * np.sin(tau))
    got = C.stiffness_from_rfft(np.fft.rfft(M)[1], n, psi_a)
    assert got == pytest.approx((k_re, k_im), rel=1e-12)
    cos_int = np.sum(M * np.cos(tau)) * 2 * np.pi / n
    sin_int = np.sum(M * np.sin(tau)) * 2 * np.pi / n
    assert C.stiffness_from_fourier(cos_int, sin_int, psi_a) == pytest.approx((k_re, k_im), rel=1e-12)
    dpsi_dtau = -psi_a * np.sin(tau)  # psi = psi_a cos tau
    work = np.sum(M * dpsi_dtau) * 2 * np.pi / n  # oint M dpsi; exact for sampled trig products
    assert work == pytest.approx(np.pi * psi_a ** 2 * k_im, rel=1e-12)


def test_moment_coefficients_take_R1_up_and_the_left_pads_down():
    ny, ty = np.array([0.5, -0.2, -0.2]), np.array([0.8, 0.9, 0.9])
    fn, ft = C.moment_coefficients(ny, ty, 1000.0, 100.0, 0.0)
    # A unit normal force pushes along -n: its vertical component is -n_y, weighted +1 for R1 and
    # -1 for L1, L2, times the arm q*/2 and F_D.
    assert_tree_allclose(fn, -ny * np.array([1, -1, -1]) * 50.0 * 1000.0, rtol=1e-7, atol=0.0)
    assert_tree_allclose(ft, ty * np.array([1, -1, -1]) * 50.0 * 1000.0, rtol=1e-7, atol=0.0)
