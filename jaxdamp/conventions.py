"""The model's sign and unit conventions, stated once (MODEL.md; the paper's Fig. 3 and §5).

Every solver (direct method, time marching, HBM-AFT, amplitude cycles) and every derived quantity
(moment, first harmonic, energy) takes these from here.

Kinematics
    Parallel blades: only the relative radial platform motion dv = v_PR - v_PL (mm) matters. The
    right platform carries R1 and moves by dv; the left platform (L1, L2) is the reference.
    psi = dv / q* is the platform rotation; it is reported in mrad.
    Cycle start (state 0) is full slip after the left platform moved down relative to the right one
    (dv increasing): state 0 is the top of the travel, and the forward half runs with dv decreasing.

Forces
    Contact forces are those the platforms exert on the damper, normalised to F_D inside the solvers:
    N > 0 in compression along the outward normal, T along the up-flank tangent. At state 0 the
    damper slides down the right flank and up the left one, so friction points up the right flank
    (+) and down the left one (-): T_i = s_i mu N_i with s = START_FRICTION_SIGNS.

Any straight relative platform motion (jaxdamp.motion; MODEL.md, "Any in-plane motion")
    The right platform moves relative to the left one as a small rigid body: X = (du, dv, dtheta)
    at D, du and dv in mm (right, up), dtheta in mrad (counter-clockwise). A point at (x, y) mm
    from D moves by (du - dtheta (y) / 1e3, dv + dtheta (x) / 1e3). A path X = a cos(tau) X_hat
    runs the solvers with the path parameter s = a q* / 1e3 mm (the travel dv of in-phase
    motion), so that in-phase motion, X_hat = (0, q*/1e3, 0) per mrad, is exactly the model
    above. Interblade phase angle phi (the paper's Fig. 4: each platform turns about its blade's
    centre C, h_C below D and q*/2 to the side; the right-hand blade lags by phi): per mrad of
    the left-hand blade's clockwise rotation, X_hat = (h_C (e^{i phi} - 1), q*/2 (e^{i phi} + 1),
    -1e3 (e^{i phi} - 1)) / 1e3.

Moment and complex stiffness
    M_P = (F_R1,v - F_L,v)(q*/2 + r sin beta) in N mm: the moment that imposes psi, so the stick
    stiffness is positive and the loop is traversed with positive work oint M dpsi.
    For psi = psi_c + psi_a cos(tau): M ~ psi_a (k_Re cos tau - k_Im sin tau), i.e. the phasor
    relation M = (k_Re + i k_Im) psi with k_Im = W / (pi psi_a^2) > 0 for a dissipative loop.
    Units: psi in mrad, M in N mm, k in N mm/mrad, energy in N mm per cycle.
"""

from __future__ import annotations

import warnings

import jax
import jax.numpy as jnp
import numpy as np

MRAD_PER_RAD = 1e3
CONTACT_NAMES = ("R1", "L1", "L2")

# Friction direction s_i at cycle start (T_i = s_i mu N_i along the up-flank tangent), (R1, L1, L2).
START_FRICTION_SIGNS = np.array([1.0, -1.0, -1.0])

# Radial motion of each contact's platform per unit dv: R1 moves with the right platform, the left
# platform (L1, L2) is the reference.
PLATFORM_MOTION = np.array([1.0, 0.0, 0.0])

# Generalised force (Fx, Fy, Mz about D) of F_D = 1: radially outward ("up"), applied at D.
CENTRIFUGAL_LOAD = np.array([0.0, 1.0, 0.0])

# M_P takes +F_R1,v and -F_L,v.
MOMENT_SIDE = np.array([1.0, -1.0, -1.0])


def rigid_displacement(direction, offsets_mm):
    """Displacements (mm, (..., 2)) of points at offsets (x, y) mm from D of a rigid platform that
    moves by X = (du mm, dv mm, dtheta mrad) at D (small rotations)."""
    turn = direction[2] / MRAD_PER_RAD
    return jnp.stack([direction[0] - turn * offsets_mm[..., 1],
                      direction[1] + turn * offsets_mm[..., 0]], -1)


def platform_directions(q_star_mm, h_c_mm):
    """(left, right): a blade's left-hand and right-hand platform motion at D, (u mm, v mm, theta
    rad), per rad of the blade's rotation theta about its centre C (the paper's Fig. 4: C lies
    h_C below D and q*/2 to the side; theta clockwise, so that in-phase the right platform of a
    damper rises by q* theta relative to its left one: the convention of `interblade_direction`)."""
    q, h = float(q_star_mm), float(h_c_mm)
    return np.array([h, 0.5 * q, -1.0]), np.array([h, -0.5 * q, -1.0])


def interblade_direction(phi_deg, h_c_mm, q_star_mm):
    """X_hat (complex (3,): du mm, dv mm, dtheta mrad) per mrad of the left-hand blade's platform
    rotation for an interblade phase angle phi (the convention above). phi = 0 and 180 degrees are
    exact (e^{i phi} = +-1): the straight in-phase and out-of-phase paths."""
    phi = float(phi_deg) % 360.0
    e = {0.0: 1.0 + 0j, 180.0: -1.0 + 0j}.get(phi, np.exp(1j * np.deg2rad(phi)))
    return np.array([h_c_mm * (e - 1.0) / MRAD_PER_RAD, 0.5 * q_star_mm * (e + 1.0) / MRAD_PER_RAD,
                     -(e - 1.0)])


def psi_mrad(dv_mm, q_star_mm):
    """Platform rotation (mrad) of a relative platform displacement dv (mm)."""
    return dv_mm / q_star_mm * MRAD_PER_RAD


def travel_mm(psi_mrad_value, q_star_mm):
    """Relative platform displacement (mm) of a platform rotation (mrad)."""
    return psi_mrad_value * q_star_mm / MRAD_PER_RAD


def platform_arm(q_star_mm, r_sin_beta_mm):
    """Arm (mm) that turns the vertical force difference into the platform moment."""
    return q_star_mm / 2.0 + r_sin_beta_mm


def moment_coefficients(normals_y, tangents_y, F_D, q_star_mm, r_sin_beta_mm):
    """(fn, ft): platform moment M_P in N mm per unit normal / tangential force (units of F_D) of
    each contact, from the vertical components of the contact normals and tangents."""
    arm = platform_arm(q_star_mm, r_sin_beta_mm) * F_D
    return -normals_y * MOMENT_SIDE * arm, tangents_y * MOMENT_SIDE * arm


def stiffness_from_fourier(cos_integral, sin_integral, psi_a_mrad):
    """(k_Re, k_Im) in N mm/mrad from int M cos(tau) dtau and int M sin(tau) dtau over a period."""
    return cos_integral / (np.pi * psi_a_mrad), -sin_integral / (np.pi * psi_a_mrad)


def stiffness_from_rfft(first_bin, n_samples, psi_a_mrad):
    """(k_Re, k_Im) from the first rfft bin of n samples of M at tau_k = 2 pi k / n (the discrete
    form of `stiffness_from_fourier`: sum M e^(-i tau) = n/2 psi_a (k_Re + i k_Im))."""
    scale = 2.0 / (n_samples * psi_a_mrad)
    return first_bin.real * scale, first_bin.imag * scale


# The model is a small-rotation one (linearised kinematics of a rigid damper between parallel
# platforms). Beyond this platform rotation the numbers are the model's, not a damper's: warn.
SMALL_ROTATION_MRAD = 50.0


class SmallRotationWarning(UserWarning):
    """A rotation amplitude (psi_BC, or a prescribed psi_a) exceeds SMALL_ROTATION_MRAD."""


def warn_small_rotation(psi_mrad, name="psi_BC", stacklevel=2):
    """SmallRotationWarning where a (concrete) rotation amplitude exceeds SMALL_ROTATION_MRAD.
    name: what the amplitude is ("psi_BC": then the cause is a contact stiffness too low for the
    load; "psi_a": an amplitude the user asked for)."""
    if isinstance(psi_mrad, jax.core.Tracer) or not np.any(np.asarray(psi_mrad) > SMALL_ROTATION_MRAD):
        return
    cause = ("the contact stiffness is too low for the load" if name == "psi_BC"
             else "the linearised kinematics do not hold there")
    warnings.warn(f"{name} = {float(np.max(np.asarray(psi_mrad))):.4g} mrad exceeds the "
                  f"small-rotation limit of {SMALL_ROTATION_MRAD:g} mrad: {cause}; the numbers "
                  "are the model's, not a damper's (docs/model.md, validated range)",
                  SmallRotationWarning, stacklevel=stacklevel)


__all__ = ["MRAD_PER_RAD", "CONTACT_NAMES", "START_FRICTION_SIGNS", "PLATFORM_MOTION",
           "CENTRIFUGAL_LOAD", "MOMENT_SIDE", "psi_mrad", "travel_mm", "platform_arm",
           "moment_coefficients", "rigid_displacement", "platform_directions", "interblade_direction", "stiffness_from_fourier", "stiffness_from_rfft",
           "SMALL_ROTATION_MRAD", "SmallRotationWarning", "warn_small_rotation"]
