"""The tanh-regularised friction law (`jaxdamp.baselines.regularized`): its bias shrinks with eps towards the
Coulomb result, and it is a bias (it over-dissipates), not noise."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.baselines.hbm import hbm_aft
from jaxdamp.baselines.regularized import local_tanh, regularized_aft

CONTACTS = jd.Contacts(jd.REFERENCE_KN, jd.REFERENCE_KT)


def test_local_slip_equation_is_solved():
    """mu N tanh(z) + c z = T_tr, across stick-like, slip-like and very stiff (small c) cases."""
    import jax.numpy as jnp

    T_tr = jnp.array([0.3, -2.0, 5.0, 0.999, -1e-3])
    muN = jnp.array([1.0, 1.0, 0.5, 1.0, 2.0])
    for c in (1.0, 1e-3, 1e-9):
        z = local_tanh(T_tr, muN, jnp.full(5, c))
        g = muN * jnp.tanh(z) + c * z - T_tr
        assert float(jnp.max(jnp.abs(g))) < 1e-12


def test_bias_shrinks_linearly_with_eps():
    shape, mu = jd.family_shape("60sym"), 0.5
    bc = jd.base_cycle(shape, mu, CONTACTS)
    psi = float(jd.five_numbers(bc).psi_bc)
    k_re, k_im = (float(x) for x in jd.complex_stiffness(bc, psi, method="interpolated"))
    coulomb = hbm_aft(shape, mu, psi, CONTACTS, n_time=256)
    eps = np.array([1e-2, 1e-3, 1e-4])
    bias = []
    for e in eps:
        r = regularized_aft(shape, mu, psi, float(e), CONTACTS, n_time=256)
        assert jd.RESULTS.name_of(r.status) == "ok"
        bias.append(float(r.k_im) / k_im - 1.0)
    bias = np.array(bias)
    assert np.all(bias > 0)  # creep below the cone dissipates extra energy
    slope = np.polyfit(np.log(eps), np.log(bias), 1)[0]
    assert 0.8 <= slope <= 1.2, (slope, bias)
    # The smallest eps sits close to the Coulomb AFT result at the same Nt.
    assert abs(float(r.k_im) / float(coulomb.k_im) - 1.0) < 5e-3
    assert abs(float(r.k_re) / k_re - 1.0) < 1e-3


@pytest.mark.parametrize("eps", [0.0, -1.0])
def test_bad_eps_raises(eps):
    with pytest.raises(ValueError, match="eps"):
        regularized_aft(jd.family_shape("60sym"), 0.5, 1.0, eps)
