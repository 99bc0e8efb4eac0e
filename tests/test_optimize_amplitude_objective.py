"""Objectives at a prescribed amplitude (optimize/amplitude_objective.py)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp_optimize.amplitude_objective import k_im_at_amplitude

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)


@pytest.mark.slow  # 72 worker-s (run of 2026-11-25)
def test_worst_over_mu_and_gradient():
    def worst(angles):
        shape = jd.DamperShape(angles[0], angles[1], 0.14, 0.8)
        return k_im_at_amplitude(shape, [0.5, 0.7], 1.2, CONTACTS)[1]

    x = jnp.array([60.0, 60.0])
    k_im, w, valid = k_im_at_amplitude(jd.family_shape("60sym"), [0.5, 0.7], 1.2, CONTACTS)
    assert bool(np.all(valid)) and float(w) == pytest.approx(float(jnp.min(k_im)))
    assert float(k_im[0]) == pytest.approx(2033.0, abs=1)  # the gross-slip value
    g = np.asarray(jax.jit(jax.grad(worst))(x))
    f = jax.jit(worst)
    fd = [(float(f(x + 1e-5 * e)) - float(f(x - 1e-5 * e))) / 2e-5 for e in np.eye(2)]
    assert_tree_allclose(g, np.array(fd), rtol=1e-5, atol=0.0)


@pytest.mark.slow  # 14 worker-s (run of 2026-11-25)
def test_robust_k_im_is_the_band_lower_bound():
    from jaxdamp_optimize.amplitude_objective import robust_k_im

    shape = jd.family_shape("60sym")
    low, bands = robust_k_im(shape, [0.5], 1.6, CONTACTS, n_samples=64, refine=False)
    assert low == pytest.approx(float(bands[0].bounds[2]))
    # Below the gross-slip value: some admissible history damps less than the gross-slip one.
    _, w, _ = k_im_at_amplitude(shape, [0.5], 1.6, CONTACTS)
    assert 0.0 < low < float(w)
