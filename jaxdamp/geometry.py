"""Damper cross-section geometry (the paper's Fig. 3).

Coordinates are normalised to the damper height H = 1 (absolute size drops out of every force
result). The origin is the left base corner A, x is circumferential (to the right), y is radial
(outward, "up"). The left flank runs from A to the vertex V, the right flank from B to V.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import NamedTuple

import jax.numpy as jnp

from ._validate import check_param, traced
from .conventions import moment_coefficients
from .linalg import rowdot

from .conventions import CONTACT_NAMES as CONTACT_NAMES  # noqa: E402  (re-exported)
FAMILY = ("90L", "74L", "60sym", "74R", "90R")
WEDGE_PAD_NAMES = ("R1", "R2", "L1", "L2")


class DamperShape(NamedTuple):
    """A damper shape, as a pytree (every field may be a traced array).

    theta_l, theta_r: base angles in degrees, in (0, 90].
    br_over_hr: offset b_R of pad R1 from R, up the right flank, in units of the flank length h_R.
    bl2_over_hl: pad spacing 2 b_L between L1 and L2 in units of the left flank length h_L, in (0, 1].
    x_d: horizontal position of the centre of mass (where F_D acts) in units of the height H,
        measured from the left base corner; None means the triangle's centroid.
    br2_over_hr: None for the paper's curved-flat damper (one curved pad R1 on the right flank);
        a number in (0, 1] makes it a wedge: two pads R1 (upper) and R2 (lower) at +-b from the
        right flank's midpoint, 2 b = br2_over_hr h_R (br_over_hr is then unused). A wedge is
        computed on platform paths (`elliptic_cycle`, `interblade_sweep`, MODEL.md "Any in-plane
        motion"); the in-phase Base-Cycle, statics and batches take the curved-flat damper only.
    """

    theta_l: jnp.ndarray | float
    theta_r: jnp.ndarray | float
    br_over_hr: jnp.ndarray | float
    bl2_over_hl: jnp.ndarray | float = 0.8
    x_d: jnp.ndarray | float | None = None
    br2_over_hr: jnp.ndarray | float | None = None


WEDGE_REFUSED = ("br2_over_hr: this function computes the curved-flat damper only (leave "
                 "br2_over_hr None); a wedge runs on platform paths: elliptic_cycle, "
                 "interblade_sweep, jaxdamp amplitude --damper wedge")


def validate_shape(shape: DamperShape, *, wedge_ok: bool = False) -> DamperShape:
    """Raise ValueError naming the parameter and its valid range (concrete values only; the ranges
    are `params.RANGES`). wedge_ok: the caller computes a wedge (`br2_over_hr`); every other
    caller refuses one (WEDGE_REFUSED)."""
    if shape.br2_over_hr is not None and not wedge_ok:
        raise ValueError(WEDGE_REFUSED)
    for name in ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl"):
        check_param(name, getattr(shape, name))
    if shape.x_d is not None:
        check_param("x_d", shape.x_d)
    if shape.br2_over_hr is not None:
        check_param("br2_over_hr", shape.br2_over_hr)
    return shape


def is_wedge(shape: DamperShape) -> bool:
    """True for a wedge (pads R1, R2 | L1, L2), False for the curved-flat damper (R1 | L1, L2)."""
    return shape.br2_over_hr is not None


def pad_names(shape: DamperShape) -> tuple[str, ...]:
    """The pads of a damper in the order of every per-pad array: (R1, L1, L2) or (R1, R2, L1, L2).
    Unchecked, traceable (it reads only whether the shape is a wedge)."""
    return WEDGE_PAD_NAMES if is_wedge(shape) else CONTACT_NAMES


def pad_geometry(shape: DamperShape):
    """(points, normals, tangents, geometry) of every pad (`pad_names` order), (P, 2) each:
    `section_geometry`'s for the curved-flat damper; for a wedge R1, R2 at +-b from the right
    flank's midpoint (2 b = br2_over_hr h_R), then L1, L2. Unchecked, traceable."""
    geo = section_geometry(shape)
    if not is_wedge(shape):
        return geo.points, geo.normals, geo.tangents, geo
    e_r = geo.tangents[0]
    mid = geo.B + 0.5 * geo.h_r * e_r
    b = 0.5 * jnp.asarray(shape.br2_over_hr, float) * geo.h_r
    r1, r2 = mid + b * e_r, mid - b * e_r
    points = jnp.stack([r1, r2, geo.points[1], geo.points[2]])
    normals = jnp.stack([geo.normals[0], geo.normals[0], geo.normals[1], geo.normals[2]])
    tangents = jnp.stack([e_r, e_r, geo.tangents[1], geo.tangents[2]])
    return points, normals, tangents, geo


def paper_tables() -> dict:
    """The paper's reference numbers shipped with the package (jaxdamp/data/paper_tables.json)."""
    text = resources.files("jaxdamp").joinpath("data/paper_tables.json").read_text()
    return json.loads(text)


def family_shape(name: str) -> DamperShape:
    """The paper's shapes: 90L, 74L, 60sym, 74R, 90R (the 60sym family) and 45sym (b_R/h_R = +0.20)."""
    shapes = paper_tables()["shapes"]
    if name not in shapes:
        raise ValueError(f"shape must be one of {', '.join(shapes)}; got {name!r}")
    s = shapes[name]
    return DamperShape(s["theta_l"], s["theta_r"], s["br_over_hr"], s["bl2_over_hl"])


class SectionGeometry(NamedTuple):
    """Points (x, y), outward unit normals and unit tangents (up the flank) of the section.

    Contact arrays are ordered (R1, L1, L2); shape (..., 3, 2).
    """

    points: jnp.ndarray
    normals: jnp.ndarray
    tangents: jnp.ndarray
    D: jnp.ndarray
    R: jnp.ndarray
    L: jnp.ndarray
    A: jnp.ndarray
    B: jnp.ndarray
    V: jnp.ndarray
    h_l: jnp.ndarray
    h_r: jnp.ndarray


def section_geometry(shape: DamperShape) -> SectionGeometry:
    """Pads, reference points, normals and tangents; differentiable, valid at vertical flanks.
    Unchecked, traceable (jit, vmap, grad): a building block of the kernels (the entry points, e.g.
    `base_cycle`, check the shape). Called with concrete values, it checks them (types, ranges)."""
    if not traced(shape):
        if not isinstance(shape, DamperShape):
            raise TypeError(f"shape must be a jaxdamp.DamperShape; got {type(shape).__name__}")
        validate_shape(shape, wedge_ok=True)
        try:
            jnp.broadcast_shapes(*(jnp.shape(v) for v in shape if v is not None))
        except ValueError:
            raise ValueError("shape: the fields' arrays do not broadcast together; got shapes "
                             f"{[jnp.shape(v) for v in shape if v is not None]}") from None
    tl = jnp.deg2rad(jnp.asarray(shape.theta_l, dtype=float))
    tr = jnp.deg2rad(jnp.asarray(shape.theta_r, dtype=float))
    sl, cl, sr, cr = jnp.sin(tl), jnp.cos(tl), jnp.sin(tr), jnp.cos(tr)
    # cot written as cos/sin: finite at 90 degrees, no tan() singularity.
    x_v = cl / sl
    x_b = x_v + cr / sr
    zero = jnp.zeros_like(x_v)
    A = jnp.stack([zero, zero], -1)
    B = jnp.stack([x_b, zero], -1)
    V = jnp.stack([x_v, jnp.ones_like(x_v)], -1)
    h_l, h_r = 1.0 / sl, 1.0 / sr
    e_l = jnp.stack([cl, sl], -1)
    e_r = jnp.stack([-cr, sr], -1)
    n_l = jnp.stack([-sl, cl], -1)
    n_r = jnp.stack([sr, cr], -1)
    L = A + 0.5 * h_l[..., None] * e_l
    R = B + 0.5 * h_r[..., None] * e_r
    x_d = (x_b + x_v) / 3.0 if shape.x_d is None else jnp.asarray(shape.x_d, dtype=float) + zero
    D = jnp.stack([x_d, 0.5 + zero], -1)
    b_l = 0.5 * jnp.asarray(shape.bl2_over_hl, dtype=float) * h_l
    b_r = jnp.asarray(shape.br_over_hr, dtype=float) * h_r
    r1 = R + b_r[..., None] * e_r
    l1 = L + b_l[..., None] * e_l
    l2 = L - b_l[..., None] * e_l
    points = jnp.stack([r1, l1, l2], -2)
    normals = jnp.stack([n_r, n_l, n_l], -2)
    tangents = jnp.stack([e_r, e_l, e_l], -2)
    return SectionGeometry(points, normals, tangents, D, R, L, A, B, V, h_l, h_r)


def full_slip_slide_rates(shape: DamperShape) -> jnp.ndarray:
    """Sliding per unit relative platform displacement in full slip (Appendix C, eqs. C.1-C.2).

    Returns (R1, L1, L2) magnitudes; written as cos/sin(theta_l + theta_r) so vertical flanks are finite.
    """
    tl = jnp.deg2rad(jnp.asarray(shape.theta_l, dtype=float))
    tr = jnp.deg2rad(jnp.asarray(shape.theta_r, dtype=float))
    s = jnp.sin(tl + tr)
    right = jnp.cos(tl) / s
    left = jnp.cos(tr) / s
    return jnp.stack([right, left, left], -1)


def platform_moment_coefficients(shape: DamperShape, load):
    """(fn, ft): the platform moment M_P (N mm) per unit normal / tangential force (units of F_D)
    of each contact (conventions.moment_coefficients). Unchecked, traceable."""
    geo = section_geometry(shape)
    return moment_coefficients(geo.normals[:, 1], geo.tangents[:, 1], load.F_D, load.q_star,
                               load.r_sin_beta)


def platform_moment(shape: DamperShape, load, N, T):
    """Platform moment M_P (N mm) of contact forces N, T (units of F_D, last axis = contact) for a
    shape and load (conventions.moment_coefficients: M_P = (F_R1,v - F_L,v)(q*/2 + r sin beta)).
    Unchecked, traceable (jit, vmap, grad): a building block of the kernels."""
    fn, ft = platform_moment_coefficients(shape, load)
    return rowdot(N, fn) + rowdot(T, ft)


__all__ = ["CONTACT_NAMES", "WEDGE_PAD_NAMES", "WEDGE_REFUSED", "FAMILY", "DamperShape", "validate_shape", "is_wedge",
           "pad_names", "pad_geometry", "paper_tables",
           "family_shape", "SectionGeometry", "section_geometry", "full_slip_slide_rates",
           "platform_moment_coefficients", "platform_moment"]
