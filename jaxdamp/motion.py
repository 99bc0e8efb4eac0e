"""Relative platform motions beyond the paper's in-phase one: straight and elliptic paths.

The paper's damper sees in-phase motion only: the right platform moves radially by dv = q* psi
relative to the left one. A blade row vibrating with a non-zero interblade phase angle, or
out-of-phase, also turns and shifts the platforms relative to each other (MODEL.md, "Any in-plane
motion"; the kinematics are in `conventions`). This module describes such a motion and turns it
into the per-contact platform motion that the tract engine runs on:

- A `Motion` is a path X(tau) = a Re(X_hat e^{i tau}), with X_hat = (du mm, dv mm, dtheta mrad)
  per mrad of the amplitude a (its real part `direction`, its imaginary part `quadrature`, None
  for a straight path), and the damper's absolute size (its left flank's length h_L, mm), which
  matters once the platforms turn relative to each other.
- `in_phase_motion` is the paper's (X_hat = (0, q*/1e3, 0)); `interblade_motion` gives the
  paper's Fig. 4 kinematics at phi = 0 (in-phase) and phi = 180 degrees (out-of-phase);
  `straight_motion` takes any X_hat that is real up to one phase (e.g. from modal data).
- Other interblade phase angles, and complex directions that are not real up to one phase, make
  the path an ellipse (`general_motion`; the cycle is `jaxdamp.elliptic_cycle`'s).

Modal force and complex stiffness on a path: M = 2 (q*/2 + r sin beta) F_D sum over the right
platform's pads of (-N nw + T tw), with nw, tw the pad's platform motion along its normal and
tangent per mm of the path parameter s = a q*/1e3. In-phase it is the paper's platform moment
M_P less its constant F_D (q*/2 + r sin beta) (the damper's vertical equilibrium), so k_Re, k_Im
are the paper's; on any path oint M ds/q* is the work the platforms put in, sum of T d(slip).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_param, check_values
from .conventions import (MRAD_PER_RAD, PLATFORM_MOTION, interblade_direction, platform_arm,
                          rigid_displacement)
from .geometry import DamperShape, is_wedge, pad_geometry, platform_moment_coefficients

# |Im| / |X_hat| above which a direction is not straight up to one phase (an ellipse).
STRAIGHT_TOL = 1e-9


class Motion(NamedTuple):
    """A relative platform path X(tau) = a (direction cos(tau) - quadrature sin(tau)) (a pytree):
    a straight segment (quadrature None) or an ellipse.

    direction: (3,) (du mm, dv mm, dtheta mrad) of the right platform relative to the left one
        at D, per mrad of the amplitude a (du right, dv up, dtheta counter-clockwise): Re(X_hat).
    h_l: the damper's left flank length, mm (its absolute size: only a relative rotation sees it).
    quadrature: (3,) Im(X_hat) of an elliptic path (`jaxdamp.elliptic_cycle`), None for a straight
        one (`amplitude_cycle(..., motion=...)`).
    """

    direction: jnp.ndarray
    h_l: jnp.ndarray
    quadrature: jnp.ndarray | None = None


def in_phase_motion(q_star_mm=100.0, h_l_mm=None) -> Motion:
    """The paper's in-phase motion: dv = q* psi, X_hat = (0, q*/1e3, 0) mm per mrad of psi."""
    q_star_mm = float(check_values("q_star", q_star_mm, max_ndim=0))
    return straight_motion([0.0, q_star_mm / MRAD_PER_RAD, 0.0], h_l_mm)


def interblade_motion(phi_deg, h_c_mm, q_star_mm=100.0, h_l_mm=None) -> Motion:
    """The paper's Fig. 4 kinematics at interblade phase angle phi (degrees), per mrad of the
    left-hand blade's platform rotation: each platform turns about its blade's centre C, h_c_mm
    below D and q*/2 to the side. phi = 0 is `in_phase_motion` exactly; phi = 180 is the
    out-of-phase path (no dv: relative rotation and horizontal motion), which needs the damper's
    size h_l_mm. Other phi give an elliptic path (`elliptic_cycle`); +phi and -phi run it in
    opposite senses."""
    try:
        phi = float(phi_deg) if not isinstance(phi_deg, (str, bytes, bool)) else np.nan
    except (TypeError, ValueError):
        phi = np.nan
    if not np.isfinite(phi) or not -360.0 <= phi <= 360.0:
        raise ValueError(f"ibpa must be a finite angle in [-360, 360] deg; got {phi_deg!r}")
    h_c_mm = float(check_values("h_c", h_c_mm, max_ndim=0))
    q_star_mm = float(check_values("q_star", q_star_mm, max_ndim=0))
    return general_motion(interblade_direction(phi, h_c_mm, q_star_mm), h_l_mm)


def _direction(direction) -> np.ndarray:
    """X_hat as a complex array; anything that is no numbers refused in one line."""
    try:
        return np.asarray(direction, dtype=complex)
    except (TypeError, ValueError):
        raise ValueError(f"motion must be 3 finite numbers (du mm, dv mm, dtheta mrad); got "
                         f"{type(direction).__name__}") from None


def straight_motion(direction, h_l_mm=None) -> Motion:
    """A Motion from X_hat (3 numbers, real or complex: du mm, dv mm, dtheta mrad per mrad of
    amplitude), which must be real up to one common phase (a straight path; it is rotated to
    real, which leaves the cycle and its complex stiffness unchanged), and the damper's left
    flank length h_l_mm, needed where dtheta is not zero (else unused). ValueError, naming the
    parameter and its range, for anything else."""
    x = _direction(direction)
    if x.shape != (3,) or not np.all(np.isfinite(x)):
        raise ValueError(f"motion must be 3 finite numbers (du mm, dv mm, dtheta mrad); got {direction!r}")
    norm = float(np.linalg.norm(x))
    if norm == 0.0:
        raise ValueError("motion must be non-zero: |(du, dv, dtheta)| in (0, inf); got 0")
    # The phase that makes x most real: x = e^{i alpha} r, with alpha from the largest component.
    k = int(np.argmax(np.abs(x)))
    r = x * np.exp(-1j * np.angle(x[k]))
    if np.max(np.abs(r.imag)) > STRAIGHT_TOL * norm:
        raise ValueError("motion must be a straight path: its components real up to one common "
                         "phase (|Im| <= 1e-9 |X|); an elliptic one is general_motion's")
    real = r.real * np.sign(x[k].real if x[k].real != 0.0 else 1.0)
    return Motion(jnp.asarray(real, float), _checked_size(real, h_l_mm))


def _checked_size(components, h_l_mm):
    """The damper's size h_L (mm, a float array) after checking the path's components: required
    where the path turns the platforms (dtheta != 0), unused (1 mm) where it does not."""
    for value in np.ravel(components):
        check_param("motion_component", value, "motion")
    if h_l_mm is None:
        if np.any(np.asarray(components).reshape(-1, 3)[:, 2] != 0.0):
            raise ValueError("h_l must be given for a motion that turns the platforms (dtheta != 0): "
                             "the damper's left flank length in (0, 10000] mm")
        h_l_mm = 1.0  # unused: without a relative rotation the damper's size drops out
    return jnp.asarray(float(check_values("h_l", h_l_mm, max_ndim=0)), float)


def general_motion(direction, h_l_mm=None) -> Motion:
    """A Motion from X_hat (3 numbers, real or complex): straight where it is real up to one
    common phase (as `straight_motion`), else the ellipse X(tau) = a Re(X_hat e^{i tau})."""
    x = _direction(direction)
    try:
        return straight_motion(x, h_l_mm)
    except ValueError as e:
        if not str(e).startswith("motion must be a straight path"):
            raise
    size = _checked_size(np.stack([x.real, x.imag]), h_l_mm)
    return Motion(jnp.asarray(x.real, float), size, jnp.asarray(x.imag, float))


def validate_motion(motion: Motion, load=None) -> Motion:
    """A Motion's fields checked (ValueError naming the parameter and its range). load: the
    design's LoadCase, checked against the motion where they must agree: a pure dv path is the
    in-phase motion of q* = 1e3 dv (per mrad), and its q* must be the load's (a q* of 50 mm on the
    load beside in_phase_motion(100) ran with k 3.4x off and status ok)."""
    if not isinstance(motion, Motion):
        raise ValueError(f"motion must be a jaxdamp.Motion (in_phase_motion, interblade_motion, "
                         f"straight_motion, general_motion); got {type(motion).__name__}")
    x = np.asarray(motion.direction, float)
    if motion.quadrature is not None:
        x = x + 1j * np.asarray(motion.quadrature, float)
    checked = general_motion(x, float(motion.h_l))
    if load is not None and checked.quadrature is None:
        du, dv, dtheta = (abs(float(v)) for v in np.asarray(checked.direction, float))
        q_motion, q_load = MRAD_PER_RAD * dv, float(np.asarray(load.q_star, float))
        if du == 0.0 and dtheta == 0.0 and abs(q_motion - q_load) > 1e-9 * q_load:
            raise ValueError(f"motion: a pure dv path of {dv:g} mm per mrad is "
                             f"in_phase_motion({q_motion:g}), but load.q_star is {q_load:g} mm; "
                             f"give both the same q* (in_phase_motion(load.q_star))")
    return checked


def pad_motion(shape: DamperShape, motion: Motion | None, q_star_mm):
    """(nw, tw): each pad's platform motion along its outward normal and up-flank tangent, per mm
    of the path parameter s = a q*/1e3 (the left platform is the reference: zero for L1, L2);
    motion None: the paper's in-phase motion, per mm of dv (the same numbers as
    `in_phase_motion(q_star_mm)`, without its rounding). The direction of a Motion is its real
    part (`path_parts` splits an ellipse). Unchecked, traceable (jit, vmap, grad)."""
    if motion is None:
        _, normals, tangents, _ = pad_geometry(shape)
        # R1 (and a wedge's R2) move with the right platform; L1, L2 (the reference) do not.
        on_right = np.array([1.0, 1.0, 0.0, 0.0]) if is_wedge(shape) else PLATFORM_MOTION
        return normals[:, 1] * on_right, tangents[:, 1] * on_right
    per_s = jnp.asarray(motion.direction, float) / (jnp.asarray(q_star_mm, float) / MRAD_PER_RAD)
    return _rigid_pad_motion(shape, per_s, motion.h_l)


def _rigid_pad_motion(shape: DamperShape, X, h_l_mm):
    """(nw, tw) of each pad for a rigid motion X = (du mm, dv mm, dtheta mrad) at D of the right
    platform (the left one fixed), the damper's left flank h_l_mm long."""
    points, normals, tangents, geo = pad_geometry(shape)
    on_right = np.array([1.0, 1.0, 0.0, 0.0]) if is_wedge(shape) else PLATFORM_MOTION
    height_mm = h_l_mm * jnp.sin(jnp.deg2rad(jnp.asarray(shape.theta_l, float)))  # H = h_L sin(theta_L)
    offsets = (points - geo.D[None, :]) * height_mm
    w = rigid_displacement(X, offsets) * on_right[:, None]
    return jnp.sum(normals * w, -1), jnp.sum(tangents * w, -1)


def platform_force_coefficients(shape: DamperShape, load, h_l_mm):
    """(fn, ft), each (3, P): the damper's generalised force G = (F_u N, F_v N, M N mm) at D,
    conjugate to the right platform's motion (du, dv, dtheta) relative to the left one, per unit
    normal / tangential force (units of F_D) of each pad: by virtual work, the pad motion's
    normal and tangential parts per unit of each coordinate (M per rad). Its sign is the modal
    force's (`motion_moment_coefficients`), that of a spring: G = K X for a stuck damper, the
    damper pushing the platform with -G; oint G . dX is the energy dissipated. h_l_mm: the
    damper's size (M scales with it). Unchecked, traceable."""
    unit = jnp.eye(3)
    nw, tw = jax.vmap(lambda X: _rigid_pad_motion(shape, X, h_l_mm))(unit)
    per = jnp.array([1.0, 1.0, MRAD_PER_RAD])[:, None] * jnp.asarray(load.F_D, float)
    return -per * nw, per * tw


def loop_moment_coefficients(shape: DamperShape, load, motion: Motion | None):
    """(fn, ft) of the force whose first harmonic is a cycle's k, per unit normal / tangential
    force (units of F_D) of each pad: the paper's platform moment M_P in-phase (motion None,
    `geometry.platform_moment`), the modal force on a path. Unchecked, traceable."""
    if motion is None:
        return platform_moment_coefficients(shape, load)
    return motion_moment_coefficients(*pad_motion(shape, motion, load.q_star), load)


def path_parts(motion: Motion) -> tuple[Motion, Motion]:
    """An elliptic Motion as two straight ones: along Re(X_hat) and along Im(X_hat), so that
    X(tau) = a (cos tau X_r - sin tau X_i)."""
    return Motion(motion.direction, motion.h_l), Motion(motion.quadrature, motion.h_l)


def as_ellipse(motion: Motion) -> Motion:
    """The same path as an elliptic Motion: a straight one with a zero quadrature (an ellipse of
    zero width, which the elliptic engines run as they run any ellipse); an ellipse as it is.
    Traceable."""
    if motion.quadrature is not None:
        return motion
    return motion._replace(quadrature=jnp.zeros_like(jnp.asarray(motion.direction, float)))


def motion_moment_coefficients(nw, tw, load):
    """(fn, ft): the modal force M (N mm, module docstring) per unit normal / tangential force
    (units of F_D) of each pad. Unchecked, traceable."""
    scale = 2.0 * platform_arm(load.q_star, load.r_sin_beta) * load.F_D
    return -scale * nw, scale * tw


__all__ = ["Motion", "in_phase_motion", "interblade_motion", "straight_motion", "general_motion",
           "validate_motion",
           "pad_motion", "loop_moment_coefficients", "path_parts", "as_ellipse",
           "motion_moment_coefficients",
           "platform_force_coefficients",
           "STRAIGHT_TOL"]
