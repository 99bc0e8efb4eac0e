"""The first harmonic of the damper's generalised force on a platform path (issue 34's outputs).

Over a steady cycle on X(tau) = a Re(X_hat e^{i tau}) the damper's generalised force G(tau) =
(F_u N, F_v N, M N mm) at D, conjugate to the right platform's motion relative to the left one
(`motion.platform_force_coefficients`: the sign of a spring, G = K X for a stuck damper), has the
first harmonic G_hat = (1/pi) int G e^{-i tau} dtau, so that G(tau) ~ G_0 + Re(G_hat e^{i tau}).
Its projection on the path is the cycle's modal complex stiffness (virtual work, tested):

    k = 2 (q*/2 + r sin beta) (1e3 / q*) (G_hat_u conj(X_u) + G_hat_v conj(X_v)
        + 1e-3 G_hat_M conj(X_theta)) / a,

with X_hat in mm, mm and mrad per mrad of a, and a in mrad: in-phase (X_hat = (0, q*/1e3, 0))
k = 2 (q*/2 + r sin beta) G_hat_v / a. The whole vector says what the damper does across the
path: e.g. out-of-phase, the horizontal force and the moment it couples into the blades.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_param
from .amplitude import AmplitudeCycle, loop_fourier
from .conventions import MRAD_PER_RAD, platform_arm, travel_mm
from .ellipse import EllipticCycle, period_fourier
from .motion import platform_force_coefficients
from .status import RESULTS

__all__ = ["platform_force_harmonic", "platform_force_kernel", "PLATFORM_FORCE_NAMES",
           "path_projection"]

PLATFORM_FORCE_NAMES = ("F_u_n", "F_v_n", "M_nmm")


def _size(motion, h_l_mm):
    """The damper's size (mm) that the moment about D needs: the path's where it turns the
    platforms (the Motion then carries it), else h_l_mm, which must be given."""
    turns = motion is not None and (float(np.asarray(motion.direction)[2]) != 0.0 or (
        motion.quadrature is not None and float(np.asarray(motion.quadrature)[2]) != 0.0))
    if turns:
        if h_l_mm is not None and float(h_l_mm) != float(motion.h_l):
            raise ValueError(f"h_l_mm must be the path's own damper size {float(motion.h_l):g} mm "
                             f"(or None); got {h_l_mm!r}")
        return jnp.asarray(motion.h_l, float)
    if h_l_mm is None:
        raise ValueError("h_l_mm must be given (the damper's left flank length in (0, 10000] mm): "
                         "the moment about D scales with the damper's size, which a path that "
                         "does not turn the platforms leaves open")
    check_param("h_l", h_l_mm)
    return jnp.asarray(float(h_l_mm), float)


def platform_force_harmonic(cycle, h_l_mm=None) -> jnp.ndarray:
    """G_hat (3,) complex: the first harmonic of (F_u N, F_v N, M N mm) over a steady cycle
    (module docstring), from an `amplitude_cycle` (in-phase or on a straight path) or an
    `elliptic_cycle` (any path, wedge included) result, computed exactly from its tracts.
    h_l_mm: the damper's left flank length (mm), needed where the path does not turn the
    platforms (the moment about D scales with it); a path that turns them carries its own.
    Zeros where the cycle's status is not valid (ok or shakedown). One compiled program per
    kind of cycle; `platform_force_kernel` is the unchecked, traceable form."""
    if not isinstance(cycle, (AmplitudeCycle, EllipticCycle)):
        raise ValueError(f"cycle must be an AmplitudeCycle or an EllipticCycle; got "
                         f"{type(cycle).__name__}")
    return _compiled(cycle, _size(cycle.motion, h_l_mm))


def platform_force_kernel(cycle, h_l_mm) -> jnp.ndarray:
    """`platform_force_harmonic` without checks: jit, vmap, grad."""
    fn, ft = platform_force_coefficients(cycle.shape, cycle.load, h_l_mm)
    if isinstance(cycle, EllipticCycle):
        s_a = travel_mm(cycle.amplitude, cycle.load.q_star)
        g = jax.vmap(lambda *c: period_fourier(cycle.period, s_a, c))(fn, ft)
    else:
        a_dv = travel_mm(cycle.psi_a, cycle.load.q_star)
        cos_part, sin_part = jax.vmap(
            lambda *c: loop_fourier(c, cycle.forward, cycle.backward, a_dv))(fn, ft)
        g = cos_part - 1j * sin_part
    return jnp.where(RESULTS.valid(cycle.status), g / jnp.pi, 0.0)


_compiled = jax.jit(platform_force_kernel)


def path_projection(g_hat, direction, load, amplitude_mrad):
    """The modal complex stiffness k (N mm/mrad) that G_hat projects to on the path X_hat
    (complex (3,), mm, mm, mrad per mrad of the amplitude): the module docstring's identity."""
    x = jnp.asarray(direction)
    work = (g_hat[0] * jnp.conj(x[0]) + g_hat[1] * jnp.conj(x[1])
            + g_hat[2] * jnp.conj(x[2]) / MRAD_PER_RAD)
    arm = platform_arm(load.q_star, load.r_sin_beta)
    return 2.0 * arm * MRAD_PER_RAD / load.q_star * work / amplitude_mrad
