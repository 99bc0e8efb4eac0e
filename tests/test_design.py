"""The Design pytree: one type for single designs, batches and derivatives; values never recompile."""

import jax
import numpy as np
import pytest

import jaxdamp as jd
from helpers import tree_allclose
from jaxdamp import batch as B


def test_base_cycle_takes_a_design_or_its_parts():
    d = jd.Design(jd.family_shape("74R"), 0.5)
    assert tree_allclose(jd.five_numbers(jd.base_cycle(d)),
                         jd.five_numbers(jd.base_cycle(d.shape, 0.5)), rtol=0.0)
    with pytest.raises(ValueError, match="mu is required"):
        jd.base_cycle(jd.family_shape("74R"))
    with pytest.raises(ValueError, match="not both"):
        jd.base_cycle(d, 0.5)


def test_prepared_validates_and_carries_stiffness_per_contact():
    d = jd.Design(jd.family_shape("60sym"), 0.5, jd.Contacts(2e4, 3e3)).prepared()
    assert np.shape(d.contacts.kn) == (3,) and np.shape(d.contacts.kt) == (3,)
    with pytest.raises(ValueError, match=r"theta_l must be in \(0, 90\] deg"):
        jd.Design(jd.DamperShape(95.0, 60.0, 0.1), 0.5).prepared()
    with pytest.raises(ValueError, match="kn must be a finite number"):
        jd.Design(jd.family_shape("60sym"), 0.5, jd.Contacts(np.inf, 3e3)).prepared()


def test_values_and_stiffness_forms_share_one_compiled_program():
    s = jd.family_shape("60sym")
    jd.base_cycle(s, 0.5)
    before = jd.base_cycle_kernel._cache_size()
    jd.base_cycle(s, 0.3, jd.Contacts(1.5e4, 4e3))
    jd.base_cycle(s._replace(theta_l=55.0), 0.7, jd.Contacts(np.array([1e4, 2e4, 3e4]), 4e3),
                  jd.LoadCase(F_D=500.0))
    assert jd.base_cycle_kernel._cache_size() == before


def test_batch_sizes_share_bucketed_programs():
    rng = np.random.default_rng(3)

    def designs(n):
        return jd.stack_designs(jd.DamperShape(rng.uniform(45, 85, n), rng.uniform(45, 85, n),
                                               rng.uniform(-0.1, 0.2, n)), 0.5)

    jd.evaluate_designs(designs(20))
    compiled = {k: f._cache_size() for k, f in B._COMPILED.items()}
    for n in (17, 25, 32):  # one bucket (32 designs)
        jd.evaluate_designs(designs(n))
    assert {k: f._cache_size() for k, f in B._COMPILED.items()} == compiled


def test_bucket_sizes():
    assert B.bucket_size(1, 1, 1024) == B.MIN_BATCH
    assert B.bucket_size(100, 1, 1024) == 128
    assert B.bucket_size(5000, 1, 1024) == 1024
    assert B.bucket_size(37, 2, 1024) == 64
    assert B.bucket_size(3, 3, 1024) % 3 == 0


def test_default_chunk_by_platform_and_memory():
    assert B.default_chunk("cpu") == 1024
    assert B.default_chunk("gpu") == 131072
    # 80 GB free: the platform default stands; 1 GB free: bounded by memory, a power of two.
    assert B.default_chunk("gpu", free_bytes=80 * 2**30) == 131072
    small = B.default_chunk("gpu", free_bytes=2**30)
    assert small * B.BYTES_PER_DESIGN <= B.MEMORY_SHARE * 2**30 and small & (small - 1) == 0
    assert B.default_chunk("gpu", free_bytes=0) == B.MIN_BATCH
    assert B.default_chunk("unknown-accelerator") == 1024


def test_map_batched_matches_a_loop_and_rejects_bad_chunks():
    def f(x, y):
        return x * y

    x = np.arange(37.0)
    np.testing.assert_array_equal(jd.map_batched(f, x, 2.0, chunk_size=8), 2.0 * x)
    with pytest.raises(ValueError, match="chunk_size"):
        jd.map_batched(f, x, 2.0, chunk_size=0)


def test_derivatives_come_back_as_designs():
    jac = jd.five_numbers_jacobian(jd.family_shape("60sym"), 0.5)
    d = jac.d.psi_bc
    assert isinstance(d, jd.Design) and isinstance(d.shape, jd.DamperShape)
    # psi scales with F_D / k (MODEL.md): F_D d psi / d F_D = psi (Euler's theorem, degree 1).
    assert float(d.load.F_D) * 1000.0 == pytest.approx(float(jac.values.psi_bc), rel=1e-9)
    assert jax.tree_util.tree_structure(d) == jax.tree_util.tree_structure(
        jd.Design(jd.DamperShape(0.0, 0.0, 0.0, 0.0), 0.0, jd.Contacts(0.0, 0.0), jd.LoadCase(0.0, 0.0, 0.0)))
