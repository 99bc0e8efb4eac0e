"""Derivatives of the peaks by the implicit function theorem at the roots the values found
(`jaxdamp.response.row_gradient`), against float64 central differences of the values pipeline
itself (the peak search of `path_peaks`, `row_response`), away from switches."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.modal_file import load_modal_family
from jaxdamp.response import BladeMode
from jaxdamp.response.peaks import path_peaks
from jaxdamp.response.row_gradient import VARIABLES, peak_amplitudes_at, row_gradient
from jaxdamp.status import RESULTS

SHAPE = jd.family_shape("60sym")
MODE = BladeMode(500.0, 500.0, 1e-3, 1.0)
FORCES = jnp.array([20.0, 60.0])


def _peaks(mu, f_d, motion, residual):
    load = jd.LoadCase(F_D=f_d)
    return path_peaks(SHAPE, mu, jd.Contacts(), load, MODE, motion, FORCES, "assembly",
                      residual=residual)[1]


@pytest.mark.slow  # the in-phase peak search and the cycle's derivative program: 30 s each
@pytest.mark.parametrize("residual", [None, 2e-5])
def test_peak_derivative_matches_central_differences_in_phase(residual):
    """The in-phase straight path, with and without a residual flexibility in series (c k about
    0.6 at the stuck damper): dA*/dmu and dA*/dF_D by forward and reverse mode against central
    differences of the peak search, to 1e-6 of the derivative."""
    motion = jd.in_phase_motion(100.0)
    values = jax.jit(lambda mu, f_d: _peaks(mu, f_d, motion, residual))
    pk = values(0.5, 1000.0)
    assert np.all(np.asarray(pk.status) == RESULTS.ok) and np.all(np.asarray(pk.n_roots) == 1)

    def amplitude(mu, f_d):
        return peak_amplitudes_at(SHAPE, mu, jd.Contacts(), jd.LoadCase(F_D=f_d), MODE, motion,
                                  FORCES, pk.peak_amplitude_mm, pk.psi_a_mrad,
                                  RESULTS.valid(pk.status), "assembly", residual)[0]

    fwd = jax.jit(jax.jacfwd(amplitude, argnums=(0, 1)))(0.5, 1000.0)
    rev = jax.jit(jax.jacrev(amplitude, argnums=(0, 1)))(0.5, 1000.0)
    h_mu, h_fd = 1e-5, 1e-2
    cd = ((values(0.5 + h_mu, 1000.0).peak_amplitude_mm
           - values(0.5 - h_mu, 1000.0).peak_amplitude_mm) / (2 * h_mu),
          (values(0.5, 1000.0 + h_fd).peak_amplitude_mm
           - values(0.5, 1000.0 - h_fd).peak_amplitude_mm) / (2 * h_fd))
    assert np.all(np.abs(np.asarray(cd[0])) > 1e-2)  # the derivatives compared are not zero
    assert_tree_allclose(fwd, cd, rtol=1e-6, atol=0.0)
    assert_tree_allclose(rev, fwd, rtol=1e-10, atol=0.0)


@pytest.mark.slow
def test_an_invalid_peak_has_zero_derivative_not_nan():
    """Roots marked not valid (a NaN amplitude among them) give zero values and derivatives."""
    motion = jd.in_phase_motion(100.0)

    def amplitude(mu):
        return peak_amplitudes_at(SHAPE, mu, jd.Contacts(), jd.LoadCase(), MODE, motion, FORCES,
                                  jnp.array([0.1, jnp.nan]), jnp.full(2, jnp.nan),
                                  jnp.array([False, False]))[0]

    value, d = jax.jvp(amplitude, (0.5,), (1.0,))
    assert_tree_allclose((value, d), (jnp.zeros(2), jnp.zeros(2)), rtol=0.0, atol=0.0)


@pytest.mark.slow
def test_row_gradient_matches_central_differences_of_the_row():
    """The example disk's row at engine orders 0 (straight path) and 3 (an ellipse): every peak's
    derivative with respect to all nine VARIABLES against central differences of
    `row_response`, to 1e-6 of the largest entry per variable."""
    family = load_modal_family("example")
    kw = dict(modes=family, engine_orders=[0, 3], force_n=[5.0])
    contacts, load = jd.Contacts(), jd.LoadCase()
    got = row_gradient(SHAPE, 0.5, contacts, load, h_l_mm=10.0, **kw)
    assert got.variables == VARIABLES
    assert np.all(np.asarray(got.row.status) == RESULTS.ok)
    p0 = np.array([SHAPE.theta_l, SHAPE.theta_r, SHAPE.br_over_hr, SHAPE.bl2_over_hl, 0.5,
                   load.F_D, 1.0, 1.0, 10.0], float)
    steps = np.array([1e-3, 1e-3, 1e-5, 1e-5, 1e-5, 1e-2, 1e-5, 1e-5, 1e-4])

    def peaks(p):
        shape = SHAPE._replace(theta_l=p[0], theta_r=p[1], br_over_hr=p[2], bl2_over_hl=p[3])
        row = jd.row_response(shape, p[4], jd.Contacts(p[6] * contacts.kn, p[7] * contacts.kt),
                              load._replace(F_D=p[5]), h_l_mm=p[8], **kw)
        return np.asarray(row.peaks.peak_amplitude_mm)

    for j, name in enumerate(VARIABLES):
        e = np.zeros(9)
        e[j] = steps[j]
        cd = (peaks(p0 + e) - peaks(p0 - e)) / (2 * steps[j])
        scale = np.max(np.abs(cd))
        assert scale > 0, name  # h_L: engine order 3's path turns the platforms
        assert_tree_allclose(got.d_peak_mm[..., j], cd, rtol=0.0, atol=1e-6 * scale)


def test_row_gradient_refuses_an_unknown_history():
    with pytest.raises(ValueError, match="initial must be one of assembly, gross_slip"):
        row_gradient(SHAPE, 0.5, modes=load_modal_family("example"), engine_orders=[0],
                     h_l_mm=10.0, initial="settled")
