"""Design variables: the vector x (physical units) <-> DamperShape, bounds, unit box, projection.

The optimiser works on z in the unit box [0, 1]^d, z = (x - lower) / (upper - lower), so that an
Adam step of the same size moves every variable by the same fraction of its range. The bounds are
handled by Euclidean projection onto the box (clipping z); the no-liftoff constraints are not
bounds and are handled by the augmented Lagrangian in `jaxdamp_optimize.solver`.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np

from jaxdamp import Contacts, DamperShape, Design, LoadCase, family_shape

VARIABLES = ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl")
UNITS = {"theta_l": "deg", "theta_r": "deg", "br_over_hr": "", "bl2_over_hl": ""}
# The bounds for angles and b_R/h_R. 2b_L/h_L (optional variable): the pads must fit on
# the flank; the paper uses 0.8 (0.85 for 90L).
DEFAULT_BOUNDS = {"theta_l": (35.0, 90.0), "theta_r": (35.0, 90.0), "br_over_hr": (-0.3, 0.4),
                  "bl2_over_hl": (0.5, 0.9)}
# The widest box the model accepts (DamperShape validation).
_HARD_LIMITS = {"theta_l": (1e-6, 90.0), "theta_r": (1e-6, 90.0), "br_over_hr": (-0.5, 0.5),
                "bl2_over_hl": (1e-6, 1.0)}
DEFAULT_FIXED = {"theta_l": 60.0, "theta_r": 60.0, "br_over_hr": 0.14, "bl2_over_hl": 0.8}


@dataclass(frozen=True)
class DesignSpace:
    """Which shape parameters are free (with their bounds) and the values of the fixed ones.

    Hashable, so that compiled evaluators can be cached per design space.
    """

    free: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    fixed: tuple[tuple[str, float], ...]

    @property
    def dim(self) -> int:
        return len(self.free)

    def bounds(self) -> dict:
        return {n: (lo, hi) for n, lo, hi in zip(self.free, self.lower, self.upper)}


def design_space(free=("theta_l", "theta_r", "br_over_hr"), bounds=None, fixed=None) -> DesignSpace:
    """Build a design space.

    free: names among theta_l, theta_r, br_over_hr, bl2_over_hl (order is kept as in VARIABLES).
    bounds: {name: (lo, hi)} overriding DEFAULT_BOUNDS for free variables.
    fixed: {name: value} for the parameters that are not free (default: 60sym's, 2b_L/h_L = 0.8).
    """
    free = tuple(free)
    for name in free:
        if name not in VARIABLES:
            raise ValueError(f"free variables must be among {', '.join(VARIABLES)}; got {name!r}")
    if len(set(free)) != len(free) or not free:
        raise ValueError(f"free must name at least one variable, each once; got {free!r}")
    bounds = dict(bounds or {})
    for name in bounds:
        if name not in free:
            raise ValueError(f"bounds given for {name!r}, which is not a free variable {free!r}")
    fixed = dict(fixed or {})
    for name in fixed:
        if name not in VARIABLES:
            raise ValueError(f"fixed parameters must be among {', '.join(VARIABLES)}; got {name!r}")
        if name in free:
            raise ValueError(f"{name!r} is both free and fixed")
    ordered = tuple(n for n in VARIABLES if n in free)
    lower, upper = [], []
    for name in ordered:
        lo, hi = bounds.get(name, DEFAULT_BOUNDS[name])
        hard_lo, hard_hi = _HARD_LIMITS[name]
        if not (np.isfinite(lo) and np.isfinite(hi) and hard_lo <= lo < hi <= hard_hi):
            raise ValueError(f"bounds of {name} must satisfy {hard_lo:g} <= lo < hi <= {hard_hi:g}; "
                             f"got ({lo:g}, {hi:g})")
        lower.append(float(lo))
        upper.append(float(hi))
    fixed_all = []
    for name in VARIABLES:
        if name in ordered:
            continue
        value = float(fixed.get(name, DEFAULT_FIXED[name]))
        hard_lo, hard_hi = _HARD_LIMITS[name]
        if not (np.isfinite(value) and hard_lo <= value <= hard_hi):
            raise ValueError(f"fixed {name} must be in [{hard_lo:g}, {hard_hi:g}]; got {value:g}")
        fixed_all.append((name, value))
    return DesignSpace(ordered, tuple(lower), tuple(upper), tuple(fixed_all))


def _lo_span(space: DesignSpace):
    lo = jnp.asarray(space.lower, dtype=float)
    return lo, jnp.asarray(space.upper, dtype=float) - lo


def to_unit(space: DesignSpace, x):
    """Physical design vector(s) (..., d) -> unit-box coordinates."""
    lo, span = _lo_span(space)
    x = jnp.asarray(x, dtype=float)
    return (x - jnp.broadcast_to(lo, x.shape)) / jnp.broadcast_to(span, x.shape)


def from_unit(space: DesignSpace, z):
    """Unit-box coordinates (..., d) -> physical design vector(s)."""
    lo, span = _lo_span(space)
    z = jnp.asarray(z, dtype=float)
    return jnp.broadcast_to(lo, z.shape) + z * jnp.broadcast_to(span, z.shape)


def project(z):
    """Euclidean projection onto the unit box (the design bounds)."""
    return jnp.clip(z, 0.0, 1.0)


def shape_of(space: DesignSpace, x) -> DamperShape:
    """DamperShape (float arrays, x_d = None) of one physical design vector x (d,); jit-able."""
    x = jnp.asarray(x, dtype=float)
    values = dict(space.fixed)
    fields = {}
    for name in VARIABLES:
        if name in space.free:
            fields[name] = x[space.free.index(name)]
        else:
            fields[name] = jnp.asarray(values[name], dtype=float)
    return DamperShape(fields["theta_l"], fields["theta_r"], fields["br_over_hr"],
                       fields["bl2_over_hl"], None)


def shape_of_vector(v) -> DamperShape:
    """DamperShape (x_d = None) of a complete shape vector v = (theta_l, theta_r, br_over_hr,
    bl2_over_hl), leading axes kept; jit-able."""
    return DamperShape(v[..., 0], v[..., 1], v[..., 2], v[..., 3], None)


def design_from_vector(v, mu, contacts: Contacts = Contacts(), load: LoadCase = LoadCase()) -> Design:
    """The Design of a complete shape vector v = (theta_l, theta_r, br_over_hr, bl2_over_hl) at mu
    (scalar or an array: then a batch over mu); jit-able. Every optimiser path reaches the solver
    through here (unit box -> `from_unit` -> `embed` -> this)."""
    return Design(shape_of_vector(jnp.asarray(v, dtype=float)), mu, contacts, load)


def design_of(space: DesignSpace, z, mu, contacts: Contacts = Contacts(),
              load: LoadCase = LoadCase()) -> Design:
    """The optimiser's unit-box point z (d,) as a jaxdamp Design (concrete z; see `unit_of`)."""
    return design_from_vector(embed(space, np.asarray(from_unit(space, z))), mu, contacts, load)


def unit_of(space: DesignSpace, design: Design) -> np.ndarray:
    """The unit-box point of a Design's free shape variables (the inverse of `design_of`)."""
    return np.asarray(to_unit(space, vector_of(space, design.shape)))


def embed(space: DesignSpace, X) -> np.ndarray:
    """Complete shape vectors (..., 4) ordered as VARIABLES, from physical design vectors (..., d)."""
    X = np.asarray(X, float)
    out = np.empty(X.shape[:-1] + (len(VARIABLES),))
    fixed = dict(space.fixed)
    for k, name in enumerate(VARIABLES):
        out[..., k] = X[..., space.free.index(name)] if name in space.free else fixed[name]
    return out


def free_columns(space: DesignSpace) -> list[int]:
    """Positions of the free variables in the complete shape vector."""
    return [VARIABLES.index(n) for n in space.free]


def vector_of(space: DesignSpace, shape: DamperShape) -> np.ndarray:
    """The free variables of a shape, as a physical design vector (not projected)."""
    return np.array([float(getattr(shape, name)) for name in space.free])


def shape_dict(space: DesignSpace, x) -> dict:
    """All four shape parameters of design x as plain floats."""
    s = shape_of(space, x)
    return {name: float(getattr(s, name)) for name in VARIABLES}


def family_start(space: DesignSpace, name: str) -> np.ndarray:
    """A family shape as a start point: its free variables, projected onto the bounds."""
    x = vector_of(space, family_shape(name))
    return np.clip(x, space.lower, space.upper)


def in_bounds(space: DesignSpace, x, tol=1e-12) -> bool:
    x = np.asarray(x, float)
    return bool(np.all(x >= np.asarray(space.lower) - tol) and np.all(x <= np.asarray(space.upper) + tol))


__all__ = ["VARIABLES", "UNITS", "DEFAULT_BOUNDS", "DEFAULT_FIXED", "DesignSpace", "design_space",
           "to_unit", "from_unit", "project", "shape_of", "shape_of_vector", "design_from_vector",
           "design_of", "unit_of", "embed", "free_columns", "vector_of", "shape_dict", "family_start",
           "in_bounds"]
