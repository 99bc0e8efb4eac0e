"""The first harmonic of the damper's generalised force (F_u, F_v, M) over a steady cycle
(jaxdamp.platform_force; issue 34's outputs).

References: virtual work (the vector projected on the path is the cycle's modal complex stiffness,
computed by its own kernel from other coefficients), the straight-path cycle against the same
path run as a degenerate ellipse (the halves' Fourier formulas in the travel against the tracts'
sinusoid integrals in tau, component by component), and a stuck damper's linearity (G = K X)."""

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.ellipse import elliptic_kernel
from jaxdamp.params import prepare_inputs
from jaxdamp.platform_force import path_projection, platform_force_harmonic

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)
KERNEL = jax.jit(elliptic_kernel, static_argnames=("initial", "max_tracts", "max_periods", "loop"))


def ellipse_kernel(shape, mu, psi, motion, initial="assembly"):
    return KERNEL(*prepare_inputs(shape, mu, CONTACTS, jd.LoadCase(), wedge_ok=True),
                  jnp.asarray(psi), motion, initial=initial)


def x_hat(motion):
    q = 0.0 if motion.quadrature is None else np.asarray(motion.quadrature)
    return np.asarray(motion.direction) + 1j * q


def k_of(cycle):
    return complex(float(cycle.k_re), float(cycle.k_im))


@pytest.mark.parametrize("name,mu,direction", [
    ("60sym", 0.5, [0.0, 0.1, 0.0]),      # in-phase
    ("74R", 0.3, [-0.04, 0.0, 2.0]),      # out-of-phase, h_C = 20 mm
    ("90L", 0.7, [0.03, 0.05, 1.5]),      # a general straight direction
])
def test_straight_cycles_project_to_k_and_match_the_degenerate_ellipse(name, mu, direction):
    shape = jd.family_shape(name)
    straight = jd.straight_motion(direction, 10.0)
    for psi in (1.0, 5.0, 20.0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", jd.SmallRotationWarning)
            ref = jd.amplitude_cycle(shape, mu, psi, CONTACTS, initial="assembly", motion=straight)
        got = ellipse_kernel(shape, mu, psi, straight._replace(quadrature=jnp.zeros(3)))
        assert jd.RESULTS.name_of(ref.status) in ("ok", "shakedown")
        assert jd.RESULTS.name_of(got.status) == jd.RESULTS.name_of(ref.status)
        g_ref = platform_force_harmonic(ref, h_l_mm=10.0)
        g_got = platform_force_harmonic(got, h_l_mm=10.0)
        scale = float(jnp.max(jnp.abs(g_ref)))
        assert scale > 0
        assert_tree_allclose(g_got, g_ref, rtol=0, atol=1e-10 * scale)
        k = path_projection(g_ref, x_hat(straight), jd.LoadCase(), psi)
        assert abs(complex(k) - k_of(ref)) <= 1e-11 * abs(k_of(ref))


@pytest.mark.parametrize("shape,phi,psi", [
    (jd.family_shape("60sym"), 90.0, 5.0),
    (jd.family_shape("74R"), -45.0, 12.0),
    (jd.DamperShape(60.0, 60.0, 0.0, 0.8, br2_over_hr=0.8), 135.0, 8.0),  # a wedge
])
def test_elliptic_cycles_project_to_k(shape, phi, psi):
    motion = jd.interblade_motion(phi, 20.0, 100.0, 10.0)
    c = ellipse_kernel(shape, 0.5, psi, motion)
    assert jd.RESULTS.name_of(c.status) == "ok"
    g = platform_force_harmonic(c)  # the path turns the platforms: its own h_L
    assert g.shape == (3,) and g.dtype == jnp.complex128
    k = path_projection(g, x_hat(motion), jd.LoadCase(), psi)
    assert abs(complex(k) - k_of(c)) <= 1e-11 * abs(k_of(c))


def test_a_stuck_damper_is_linear_in_the_path():
    """Every pad stuck (shakedown, a tiny amplitude from assembly): G = K X, so the harmonic is
    real up to rounding along a real path, proportional to the amplitude, and the harmonic on
    the ellipse is the sum of those along its real and imaginary parts (superposition)."""
    shape = jd.family_shape("60sym")
    motion = jd.interblade_motion(60.0, 20.0, 100.0, 10.0)
    parts = [motion._replace(quadrature=jnp.zeros(3)),
             jd.Motion(motion.quadrature, motion.h_l, jnp.zeros(3))]
    gs = []
    for m in (motion, *parts):
        small = [platform_force_harmonic(ellipse_kernel(shape, 0.5, a, m)) for a in (1e-4, 2e-4)]
        assert_tree_allclose(small[1], 2.0 * small[0], rtol=1e-9, atol=0)
        gs.append(small[0])
    # X(tau) = a Re((X_r + i X_i) e^{i tau}): G_hat(ellipse) = G_hat(X_r) + i G_hat(X_i).
    scale = float(jnp.max(jnp.abs(gs[0])))
    assert_tree_allclose(gs[0], gs[1] + 1j * gs[2], rtol=0, atol=1e-9 * scale)
    assert float(jnp.max(jnp.abs(gs[1].imag))) <= 1e-9 * float(jnp.max(jnp.abs(gs[1])))


def test_the_size_is_needed_where_the_path_does_not_turn_the_platforms():
    c = jd.amplitude_cycle(jd.family_shape("60sym"), 0.5, 1.2, CONTACTS, initial="assembly",
                           motion=jd.straight_motion([0.0, 0.1, 0.0]))  # in-phase, no size
    with pytest.raises(ValueError, match="h_l_mm must be given"):
        platform_force_harmonic(c)
    with pytest.raises(ValueError, match="h_l must be"):
        platform_force_harmonic(c, h_l_mm=-1.0)
    turning = ellipse_kernel(jd.family_shape("60sym"), 0.5, 5.0,
                             jd.interblade_motion(90.0, 20.0, 100.0, 10.0))
    with pytest.raises(ValueError, match="h_l_mm must be the path's own damper size 10 mm"):
        platform_force_harmonic(turning, h_l_mm=12.0)
    with pytest.raises(ValueError, match="cycle must be an AmplitudeCycle or an EllipticCycle"):
        platform_force_harmonic(jd.in_phase_motion())
