"""HBM-AFT (`jaxdamp.baselines.hbm`): convergence to the direct method's closed-form first harmonic, the
stick limit, periodicity flags, input checks."""

import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines.hbm import first_harmonic, hbm_aft

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(jd.REFERENCE_KN, jd.REFERENCE_KT)


def test_first_harmonic_of_a_pure_harmonic():
    """M = psi_a (k_Re cos tau - k_Im sin tau) + a constant + a third harmonic is recovered exactly."""
    tau = 2 * np.pi * np.arange(64) / 64
    psi_a, k_re, k_im = 2.5, 3.0e4, 7.0e3
    M = psi_a * (k_re * np.cos(tau) - k_im * np.sin(tau)) + 11.0 + 900.0 * np.cos(3 * tau)
    got = first_harmonic(jnp.asarray(M), psi_a)
    assert_tree_allclose(np.asarray(got), np.array([k_re, k_im]), rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("name", ["60sym", "74R"])
def test_converges_to_direct_above_psi_bc(name):
    """At 1.3 psi_BC the Base-Cycle plus full-slip stretches is the exact loop: HBM-AFT's error on
    (k_Re, k_Im) falls as Nt grows and is below 1e-4 (of k_Re) at Nt = 1024."""
    shape, mu = jd.family_shape(name), 0.5
    bc = jd.base_cycle(shape, mu, CONTACTS)
    psi = 1.3 * float(jd.five_numbers(bc).psi_bc)
    k_re, k_im = (float(x) for x in jd.complex_stiffness(bc, psi, method="interpolated"))
    errs = []
    for nt in (32, 1024):
        r = hbm_aft(shape, mu, psi, CONTACTS, n_time=nt)
        assert jd.RESULTS.name_of(r.status) == "ok"
        errs.append(max(abs(float(r.k_re) - k_re), abs(float(r.k_im) - k_im)) / abs(k_re))
    assert errs[1] < errs[0] / 10
    assert errs[1] < 1e-4
    # k_Im > 0: the loop dissipates (W = pi psi_a^2 k_Im matches the direct cycle work).
    w = float(jd.blocks.cycle_work(bc, psi))
    assert abs(float(r.work) / w - 1.0) < 1e-4


def test_stick_amplitude_is_linear_and_lossless():
    """Below psi_fs every contact sticks: k_Re = k_Re,fs and k_Im = 0 to rounding."""
    shape, mu = jd.family_shape("60sym"), 0.5
    nums = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))
    r = hbm_aft(shape, mu, 0.4 * float(nums.psi_fs), CONTACTS, n_time=64)
    assert jd.RESULTS.name_of(r.status) == "ok"
    assert abs(float(r.k_re) / float(nums.k_re_fs) - 1.0) < 1e-10
    assert abs(float(r.k_im)) < 1e-9 * float(nums.k_re_fs)


def test_90r_needs_more_periods_and_says_so():
    """90R's frozen mechanism settles geometrically: 3 periods are flagged non-periodic, 10 are not."""
    shape, mu = jd.family_shape("90R"), 0.5
    psi = float(jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS)).psi_bc)
    short = hbm_aft(shape, mu, psi, CONTACTS, n_time=64, n_periods=3)
    long = hbm_aft(shape, mu, psi, CONTACTS, n_time=64, n_periods=10)
    assert jd.RESULTS.name_of(short.status) == "not_converged" and float(short.periodicity) > 1e-6
    assert jd.RESULTS.name_of(long.status) == "ok"


def test_liftoff_is_flagged():
    r = hbm_aft(jd.family_shape("74L"), 0.7, 3.0, CONTACTS, n_time=32)
    assert jd.RESULTS.name_of(r.status) == "liftoff"


@pytest.mark.parametrize("kwargs, name", [(dict(psi_a_mrad=0.0), "psi_a_mrad"),
                                          (dict(psi_a_mrad=1.0, n_time=2), "n_time"),
                                          (dict(psi_a_mrad=1.0, n_periods=0), "n_periods")])
def test_bad_input_raises(kwargs, name):
    with pytest.raises(ValueError, match=name):
        hbm_aft(jd.family_shape("60sym"), 0.5, **kwargs)
