"""The Design pytree: one type for single designs, batches and derivatives; values never recompile."""

import jax
import numpy as np
import pytest

import jaxdamp as jd
from helpers import count_compiles, tree_allclose


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


def test_derivatives_come_back_as_designs():
    jac = jd.five_numbers_jacobian(jd.family_shape("60sym"), 0.5)
    d = jac.d.psi_bc
    assert isinstance(d, jd.Design) and isinstance(d.shape, jd.DamperShape)
    # psi scales with F_D / k (MODEL.md): F_D d psi / d F_D = psi (Euler's theorem, degree 1).
    assert float(d.load.F_D) * 1000.0 == pytest.approx(float(jac.values.psi_bc), rel=1e-9)
    assert jax.tree_util.tree_structure(d) == jax.tree_util.tree_structure(
        jd.Design(jd.DamperShape(0.0, 0.0, 0.0, 0.0), 0.0, jd.Contacts(0.0, 0.0), jd.LoadCase(0.0, 0.0, 0.0)))


def test_complex_stiffness_compiles_once_for_many_numbers_of_amplitudes():
    bc = jd.base_cycle(jd.family_shape("74R"), 0.5)
    jd.complex_stiffness(bc, [1.0, 2.0], method="interpolated")
    with count_compiles() as compiled:
        for n in (1, 3, 5, 8):
            k_re, k_im = jd.complex_stiffness(bc, np.linspace(0.5, 4.0, n), method="interpolated")
            assert k_re.shape == (n,)
    assert compiled == []
    # A scalar stays a scalar.
    assert np.shape(jd.complex_stiffness(bc, 2.0, method="interpolated")[0]) == ()

