"""The single-design fast path `jaxdamp.cycle_numbers` and the `loop="while"` Base-Cycle it runs.

Reference: `five_numbers(base_cycle(...))`, the masked-scan program. Both run the same tract
arithmetic; the while form only stops its loops when they are done, so the numbers must agree to
rounding and the status exactly, on the paper's hard cases and on random designs.
"""

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.cycle import base_cycle_kernel
from jaxdamp.harmonics import five_numbers_kernel

from helpers import assert_tree_allclose

CASES = (("60sym", 0.5), ("74R", 0.7), ("90R", 0.5), ("90L", 0.7), ("74L", 0.05), ("45sym", 0.9),
         ("60sym", 0.02))


def _reference(shape, mu, contacts=jd.Contacts(), load=jd.LoadCase()):
    bc = jd.base_cycle(shape, mu, contacts, load)
    return np.array(jd.five_numbers(bc).numbers()), int(bc.status)


@pytest.mark.parametrize("name,mu", CASES)
def test_paper_shapes_match_the_scan_program(name, mu):
    shape = jd.family_shape(name)
    got = jd.cycle_numbers(shape, mu)
    ref, status = _reference(shape, mu)
    assert_tree_allclose(np.array(got[:5]), ref, rtol=1e-12, atol=1e-9)
    assert got.status == status


def test_per_contact_stiffness_load_and_design_forms():
    shape = jd.family_shape("74R")
    contacts = jd.Contacts(np.array([1.5e4, 2.5e4, 2.0e4]), np.array([3e3, 4e3, 3.5e3]))
    load = jd.LoadCase(800.0, 120.0, 5.0)
    got = jd.cycle_numbers(jd.Design(shape, 0.4, contacts, load))
    ref, status = _reference(shape, 0.4, contacts, load)
    assert_tree_allclose(np.array(got[:5]), ref, rtol=1e-12, atol=1e-9)
    assert got.status == status
    # numpy scalars and jax arrays take the checked path and give the same numbers
    again = jd.cycle_numbers(shape, jnp.asarray(0.4), contacts, load)
    assert_tree_allclose(np.array(again[:5]), ref, rtol=1e-12, atol=1e-9)


def test_liftoff_is_a_status_with_zero_numbers():
    shape = jd.DamperShape(80.0, 30.0, 0.4, 0.8)
    ref, status = _reference(shape, 0.9)
    got = jd.cycle_numbers(shape, 0.9)
    assert got.status == status
    if status == jd.RESULTS.liftoff:
        assert np.all(np.array(got[:5]) == 0.0)
    assert_tree_allclose(np.array(got[:5]), ref, rtol=1e-12, atol=1e-9)


@pytest.mark.slow  # 26 worker-s (run of 2026-11-25)
def test_random_designs_while_equals_scan():
    rng = np.random.default_rng(7)
    n = 200
    shapes = jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n),
                            rng.uniform(-0.3, 0.4, n), rng.uniform(0.6, 0.9, n))
    mu = rng.uniform(0.05, 0.9, n)
    c, load = jd.Contacts(np.full(3, jd.REFERENCE_KN), np.full(3, jd.REFERENCE_KT)), jd.LoadCase(
        1000.0, 100.0, 0.0)

    def numbers(loop):
        def one(s, m):
            bc = base_cycle_kernel(s, m, c, load, loop=loop)
            return jnp.stack([*five_numbers_kernel(bc).numbers(), bc.status.astype(float),
                              bc.half_cycles.astype(float)])
        return np.asarray(jax.jit(jax.vmap(one))(shapes, mu))

    scan, wloop = numbers("scan"), numbers("while")
    np.testing.assert_array_equal(wloop[:, 5:], scan[:, 5:])  # status and half-cycles
    assert_tree_allclose(wloop[:, :5], scan[:, :5], rtol=1e-12, atol=1e-9)
    assert np.sum(scan[:, 5] == jd.RESULTS.ok) > n // 2  # the comparison covers real cycles


@pytest.mark.slow  # 62 worker-s (run of 2026-11-25)
def test_while_loop_is_forward_differentiable():
    shape = jd.family_shape("60sym")
    s, m, c, ld = jd.params.prepare_inputs(shape, 0.5, jd.Contacts(), jd.LoadCase())

    def k_im(theta_l, loop):
        bc = base_cycle_kernel(s._replace(theta_l=theta_l), m, c, ld, loop=loop)
        return five_numbers_kernel(bc).k_im_bc

    d_while = jax.jit(jax.jacfwd(lambda x: k_im(x, "while")))(s.theta_l)
    d_scan = jax.jit(jax.grad(lambda x: k_im(x, "scan")))(s.theta_l)
    assert_tree_allclose(d_while, d_scan, rtol=1e-10, atol=0.0)


def test_bad_input_and_float32_and_batches_are_refused():
    shape = jd.family_shape("60sym")
    with pytest.raises(ValueError, match="mu"):
        jd.cycle_numbers(shape, -0.1)
    with pytest.raises(ValueError, match="theta_l"):
        jd.cycle_numbers(jd.DamperShape(120.0, 60.0, 0.0), 0.5)
    with pytest.raises(ValueError, match="evaluate_designs"):
        jd.cycle_numbers(jd.DamperShape(np.array([60.0, 70.0]), 60.0, 0.0), 0.5)
    jax.config.update("jax_enable_x64", False)
    try:
        with pytest.raises(jd.Float64Required):
            jd.cycle_numbers(shape, 0.5)
    finally:
        jax.config.update("jax_enable_x64", True)


def test_small_rotation_warns_like_five_numbers():
    shape = jd.family_shape("60sym")
    soft = jd.Contacts(20.0, 3.0)
    with pytest.warns(jd.SmallRotationWarning):
        got = jd.cycle_numbers(shape, 0.5, soft)
    assert got.psi_bc > jd.blocks.SMALL_ROTATION_MRAD
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        jd.cycle_numbers(shape, 0.5)
