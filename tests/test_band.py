"""The band of responses over the statically admissible initial states (jaxdamp.band)."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_cycle, check_admissible
from jaxdamp.band import admissible_polytope, amplitude_band, polytope_vertices

CONTACTS = jd.Contacts(17900.0, 3580.0)


def test_polytope_vertices_are_admissible_and_include_full_slip():
    shape, mu = jd.family_shape("60sym"), 0.5
    P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
    V, ok = (np.asarray(v) for v in polytope_vertices(G, h))
    assert ok.sum() >= 8
    for T in V[ok]:
        res, cone, n_min = check_admissible(shape, mu, P @ T + n0, T)
        assert float(res) < 1e-12 and float(cone) < 1e-12 and float(n_min) > -1e-12
    # Both full-slip states of the Base-Cycle (all three contacts on their limits) are vertices.
    for signs in (jd.statics.START_FRICTION_SIGNS, -jd.statics.START_FRICTION_SIGNS):
        st = jd.full_slip_state(shape, mu, signs)
        assert np.min(np.max(np.abs(V[ok] - np.asarray(st.T)), axis=1)) < 1e-12


@pytest.mark.parametrize("name,mu,psi", [("60sym", 0.5, 1.2), ("74R", 0.7, 1.5)])
def test_band_contains_named_states(name, mu, psi):
    shape = jd.family_shape(name)
    band = amplitude_band(shape, mu, psi, CONTACTS, n_samples=64, outer=2, inner=10)
    assert band.status == 0 and band.n_valid > 32
    lo_re, hi_re, lo_im, hi_im = band.bounds
    assert hi_im > lo_im + 100.0  # a real band in the microslip range
    for initial in ("gross_slip", "assembly"):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=initial)
        slack = 1e-9 * abs(float(ac.k_re))
        assert lo_re - slack <= float(ac.k_re) <= hi_re + slack
        assert lo_im - slack <= float(ac.k_im) <= hi_im + slack
    # The states reported for the bounds give those bounds.
    for j, (N, T) in enumerate(zip(band.N, band.T)):
        ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(N, T))
        assert [float(ac.k_re), float(ac.k_re), float(ac.k_im), float(ac.k_im)][j] == \
            pytest.approx(band.bounds[j], rel=1e-12, abs=1e-9)


def test_band_closes_above_psi_bc():
    shape, mu = jd.family_shape("60sym"), 0.5
    n = jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS))
    psi = 1.4 * float(n.psi_bc)
    band = amplitude_band(shape, mu, psi, CONTACTS, n_samples=64, refine=False)
    ref = np.asarray(jd.complex_stiffness(jd.base_cycle(shape, mu, CONTACTS), psi,
                                          method="interpolated"))
    np.testing.assert_allclose(band.bounds, [ref[0], ref[0], ref[1], ref[1]], rtol=1e-9)


def test_self_locked_state_keeps_the_band_open_above_psi_bc():
    """74R at mu 0.7 self-locks: the full-slip state with friction signs (+, +, -) is admissible
    with contact forces of ~24 F_D. From it the cycle at 3.5 mrad (> psi_BC = 3.29) settles, after
    a transient, on an elastic cycle, so the band's k_Im reaches 0 above psi_BC. The time marcher
    confirms it (200 pairs without acceleration; the direct method needs 3 with Aitken's)."""
    import jax.numpy as jnp

    from jaxdamp.status import RESULTS
    from jaxdamp.baselines.timemarch import march_amplitude

    shape, mu, psi = jd.family_shape("74R"), 0.7, 3.5
    assert float(jd.five_numbers(jd.base_cycle(shape, mu, CONTACTS)).psi_bc) < psi
    st = jd.full_slip_state(shape, mu, jnp.array([1.0, 1.0, -1.0]))
    N, T = np.asarray(st.N), np.asarray(st.T)
    assert np.min(N) > 1.0 and float(check_admissible(shape, mu, N, T)[0]) < 1e-12
    ac = amplitude_cycle(shape, mu, psi, CONTACTS, initial=(N, T))
    assert RESULTS.name_of(ac.status) == "shakedown" and int(ac.cycles) == 3
    tm = march_amplitude(shape, mu, psi, CONTACTS, initial=(N, T), n_steps=1000, max_pairs=200)
    assert float(np.asarray(tm.closure)[-1]) < 1e-9
    np.testing.assert_allclose(np.asarray(tm.N_start), np.asarray(ac.N_start), atol=1e-9)
    assert float(tm.k_re) == pytest.approx(float(ac.k_re), rel=1e-9)
    assert abs(float(tm.k_im)) < 1e-9 * float(ac.k_re)
