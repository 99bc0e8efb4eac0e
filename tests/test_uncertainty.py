"""Monte Carlo peak distribution: the sampler's ranges, the F_D and contact scaling law as an
independent identity, agreement with the per-design peak solver, quantile/exceedance consistency,
gradients against central finite differences, one-line input errors."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp import Contacts, LoadCase, family_shape
from jaxdamp.response import (BladeMode, damper_stiffness, design_peaks, peak_response,
                              prepare_scene, scaled_stiffness)
from jaxdamp.status import RESULTS
from jaxdamp.uncertainty import (Scenarios, Uncertainty, magnification_kernel, peak_distribution,
                                 sample_scenarios)

from helpers import assert_tree_allclose

SHAPE = family_shape("60sym")
FORCES = np.array([2.0, 5.0, 20.0])
C0 = Contacts()
KN0, KT0 = (np.asarray(k) for k in C0.per_contact())


def test_samples_lie_in_the_stated_ranges_and_pairs_are_drawn_independently():
    u = Uncertainty(0.3, 0.7, 0.2, 2.0, 3.0)
    s = sample_scenarios(jax.random.PRNGKey(0), 4000, u, C0, LoadCase())
    assert np.all((0.3 <= s.mu) & (s.mu <= 0.7))
    assert np.all((800.0 <= s.fd_n) & (s.fd_n <= 1200.0))
    rn, rt = np.log(s.kn / KN0[None]), np.log(s.kt / KT0[None])
    assert np.all(np.abs(rn) <= np.log(2.0) + 1e-12) and np.all(np.abs(rt) <= np.log(3.0) + 1e-12)
    # log-uniform: mean of log k is log k0 (3 sigma of the sample mean), the pairs uncorrelated
    assert np.all(np.abs(rn.mean(0)) < 3 * np.log(2.0) / np.sqrt(3 * 4000))
    assert abs(np.corrcoef(rn[:, 0], rn[:, 1])[0, 1]) < 0.06


@pytest.mark.slow  # 120 worker-s (run of 2026-11-25)
def test_a_common_contact_scale_and_fd_change_obey_the_scaling_law():
    """k(psi; F_D, c kn, c kt) = c k0(psi c F_D0 / F_D): the sample recomputes the exact curve at the
    scaled contacts and load; the reference rescales the nominal curve."""
    c, fd = 1.7, 1300.0
    scen = Scenarios(jnp.array([0.5]), jnp.array(KN0 * c)[None], jnp.array(KT0 * c)[None], jnp.array([fd]))
    dist = peak_distribution(SHAPE, scen, BladeMode(), FORCES)
    shape, mu, contacts, load, mode = prepare_scene(SHAPE, 0.5)
    ref = scaled_stiffness(damper_stiffness(shape, mu, contacts, load), 1000.0, fd, c)
    a_ref = np.asarray(jax.jit(lambda f: peak_response(ref, mode, f).peak_amplitude_mm)(FORCES))
    assert_tree_allclose(dist.magnification[0], a_ref / FORCES, rtol=1e-7, atol=0.0, equal_nan=True)


@pytest.mark.slow  # 107 worker-s (run of 2026-11-25)
def test_each_sample_matches_the_per_design_peak_solver_at_its_own_contacts_and_load():
    scen = sample_scenarios(jax.random.PRNGKey(3), 3)
    dist = peak_distribution(SHAPE, scen, BladeMode(), FORCES, history="assembly")
    for i in range(3):
        p = design_peaks(SHAPE, float(scen.mu[i]), Contacts(scen.kn[i], scen.kt[i]),
                         LoadCase(float(scen.fd_n[i])), force_n=FORCES, initial="assembly")
        assert_tree_allclose(dist.magnification[i], np.asarray(p.peak_amplitude_mm) / FORCES,
                             rtol=1e-10, atol=0.0, equal_nan=True)
        assert int(dist.status[i]) == RESULTS.ok


@pytest.mark.slow  # 130 worker-s (run of 2026-11-25)
def test_band_is_the_larger_history_and_quantiles_agree_with_exceedance():
    scen = sample_scenarios(jax.random.PRNGKey(1), 16)
    g = peak_distribution(SHAPE, scen, BladeMode(), 3.0, history="gross_slip")
    a = peak_distribution(SHAPE, scen, BladeMode(), 3.0, history="assembly")
    median = float(np.median(g.magnification[:, 0]))
    b = peak_distribution(SHAPE, scen, BladeMode(), 3.0, history="band", limit_mm_per_n=median,
                          levels=(0.5, 1.0))
    np.testing.assert_array_equal(b.magnification, np.maximum(g.magnification, a.magnification))
    assert b.n_ok == 16
    assert_tree_allclose(b.quantiles[1], b.worst, rtol=1e-7, atol=0.0)
    # the fraction above the gross-slip median: the band lies above gross slip sample by sample
    assert b.exceedance[0] >= np.mean(g.magnification[:, 0] > median)
    g_lim = peak_distribution(SHAPE, scen, BladeMode(), 3.0, limit_mm_per_n=median)
    assert g_lim.exceedance[0] == pytest.approx(0.5)  # 16 distinct samples: 8 above the median


@pytest.mark.slow  # 321 worker-s (run of 2026-11-25)
def test_magnification_gradient_in_the_shape_matches_central_differences():
    shape, _, _, load, mode = prepare_scene(SHAPE, 0.5)
    scen = Scenarios(jnp.asarray(0.45), jnp.asarray(KN0 * 1.2), jnp.asarray(KT0 * 0.8),
                     jnp.asarray(950.0))

    def f(theta_l):
        return magnification_kernel(shape._replace(theta_l=theta_l), scen, load, mode,
                                    jnp.array([2.0, 8.0]))[0]

    x = jnp.asarray(float(shape.theta_l))
    f = jax.jit(f)  # one program each for values and derivatives, not op-by-op loops
    g = jax.jit(jax.jacfwd(f))(x)
    h = 1e-5
    fd = (f(x + h) - f(x - h)) / (2 * h)
    assert np.all(np.abs(np.asarray(g)) > 0)
    assert_tree_allclose(g, fd, rtol=1e-5, atol=0.0)


@pytest.mark.parametrize("u, word", [(Uncertainty(mu_low=0.0), "mu range"),
                                     (Uncertainty(fd_spread=1.0), "fd_spread"),
                                     (Uncertainty(kn_factor=0.5), "kn_factor")])
def test_bad_uncertainty_is_refused_naming_the_field(u, word):
    with pytest.raises(ValueError, match=word):
        sample_scenarios(jax.random.PRNGKey(0), 4, u)


def test_bad_history_and_force_are_refused():
    scen = sample_scenarios(jax.random.PRNGKey(0), 2)
    with pytest.raises(ValueError, match="history"):
        peak_distribution(SHAPE, scen, history="worst")
    with pytest.raises(ValueError, match="force_n"):
        peak_distribution(SHAPE, scen, force_n=-1.0)


def test_key_scenarios_levels_and_limit_are_refused_before_any_work(monkeypatch):
    """One line naming each (the levels were read after every scenario had run, as numpy's
    "Quantiles must be in the range [0, 1]"; a seed for a key was JAX's invalid key data)."""
    import jaxdamp.uncertainty as unc

    scen = sample_scenarios(jax.random.PRNGKey(0), 2)
    with pytest.raises(ValueError, match=r"^key must be one JAX random key"):
        sample_scenarios(0, 2)
    with pytest.raises(ValueError, match=r"^uncertainty must be a jaxdamp.Uncertainty; got str$"):
        sample_scenarios(jax.random.PRNGKey(0), 2, "wide")  # was an AttributeError
    monkeypatch.setattr(unc, "map_batched", lambda *a, **k: pytest.fail("ran the scenarios"))
    for kwargs, says in (({"levels": (0.5, 1.5)}, r"^levels must be in \[0, 1\]; got 1.5$"),
                         ({"levels": []}, r"^levels must be one or more quantiles in \[0, 1\]"),
                         ({"limit_mm_per_n": -1.0}, r"^limit_mm_per_n must be in \(0, inf\) mm/N")):
        with pytest.raises(ValueError, match=says):
            peak_distribution(SHAPE, scen, **kwargs)
    with pytest.raises(ValueError, match=r"^scenarios must be a jaxdamp.Scenarios"):
        peak_distribution(SHAPE, 5)
