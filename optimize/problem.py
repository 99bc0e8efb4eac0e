"""The optimisation problem and its compiled, batched evaluators.

One *evaluation* is one design evaluated over the whole mu set: for each mu the full-slip statics
and one Base-Cycle (all metrics and all constraint values together), with or without the Jacobian
with respect to the design variables (forward mode: `jax.jacfwd`, d <= 4 tangents). The grid
search and the gradient optimiser count evaluations the same way.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxdamp import (REFERENCE_KN, REFERENCE_KT, Contacts, Design, LoadCase, base_cycle_kernel,
                     five_numbers, full_slip_work_shape_factors, map_batched, statics_kernel)
from jaxdamp import RESULTS, check_design, family_shape
from jaxdamp.blocks import validate_contacts, validate_mu

from .constraints import Margins, margins
from .design import DesignSpace, design_from_vector, design_space, embed, free_columns, from_unit

DEFAULT_MU_SET = (0.3, 0.5, 0.7)
DEFAULT_MARGIN_PCT = 5.0
# Geometric constraint on the vertex angle 180 - theta_L - theta_R. Within the bounds the wedge can
# degenerate (theta_L = theta_R = 90 deg is a zero-width section): w_M and psi_BC then diverge like
# 1 / vertex angle, so w_M would have no finite optimum. The paper's shapes have 49-90 deg.
DEFAULT_MIN_VERTEX_DEG = 20.0
CHUNK = 256  # designs per compiled call of the value evaluator
JAC_BATCH = 8  # designs per compiled call of the Jacobian evaluator


@dataclass(frozen=True)
class Problem:
    """Design space, friction set, contacts, load and the no-liftoff requirement."""

    space: DesignSpace
    mus: tuple[float, ...] = DEFAULT_MU_SET
    kn: float = REFERENCE_KN
    kt: float = REFERENCE_KT
    load: tuple[float, float, float] = (1000.0, 100.0, 0.0)  # F_D (N), q* (mm), r sin(beta) (mm)
    margin_pct: float = DEFAULT_MARGIN_PCT
    min_normal: float = 0.0  # units of F_D
    min_vertex_deg: float = DEFAULT_MIN_VERTEX_DEG  # 180 - theta_l - theta_r >= this (0: off)


def make_problem(space: DesignSpace | None = None, mus=DEFAULT_MU_SET, kn=REFERENCE_KN,
                 kt=REFERENCE_KT, load: LoadCase | tuple = LoadCase(),
                 margin_pct=DEFAULT_MARGIN_PCT, min_normal=0.0,
                 min_vertex_deg=DEFAULT_MIN_VERTEX_DEG) -> Problem:
    """Validated Problem (ValueError naming the parameter and its range)."""
    space = design_space() if space is None else space
    validate_mu(mus, "mu_set")  # numbers in range: None, text or NaN refused in one line
    if np.ndim(mus) > 1 or np.size(mus) == 0:
        raise ValueError(f"mu_set must hold one or more friction coefficients in (0, 5]; got shape "
                         f"{np.shape(mus)}")
    mus = tuple(float(m) for m in np.atleast_1d(np.asarray(mus, float)))
    # The library's validators: one message for the same parameter in the library, the CLI and here.
    for m in mus:
        validate_mu(m, "mu_set")
    if len(set(mus)) != len(mus):
        raise ValueError(f"mu_set values must be distinct; got {mus}")
    for name, k in (("kn", kn), ("kt", kt)):
        if np.ndim(k) != 0:
            raise ValueError(f"{name} must be one number (shared by R1, L1, L2); got {k!r}")
    validate_contacts(Contacts(kn, kt))
    load = LoadCase(*load) if type(load) is tuple else load  # a plain tuple, not another type
    # the contacts and load checked as one design's (types, one number per field, ranges): the
    # shape is the design space's business, any valid one serves here
    check_design(family_shape("60sym"), mus[0], Contacts(float(kn), float(kt)), load)
    load = tuple(float(v) for v in load)
    if not (np.isfinite(margin_pct) and 0.0 <= margin_pct < 50.0):
        raise ValueError(f"margin must be in [0, 50) % of L1-L2; got {margin_pct!r}")
    if not (np.isfinite(min_normal) and 0.0 <= min_normal < 1.0):
        raise ValueError(f"min_normal must be in [0, 1) F_D; got {min_normal!r}")
    if not (np.isfinite(min_vertex_deg) and 0.0 <= min_vertex_deg < 180.0):
        raise ValueError(f"min_vertex_deg must be in [0, 180) deg; got {min_vertex_deg!r}")
    return Problem(space, mus, float(kn), float(kt), load, float(margin_pct), float(min_normal),
                   float(min_vertex_deg))


class Evaluation(NamedTuple):
    """One design over the mu set (leading axis n_mu; a batch axis in front when batched)."""

    metrics: np.ndarray  # (n_mu, 3): k_im_bc (N mm/mrad), psi_bc (mrad), w_m (-)
    margins: Margins  # g (n_mu, 3, 3), dist_pct (n_mu, 3, 2), min_normal (n_mu, 3)
    status: np.ndarray  # (n_mu,) Base-Cycle RESULTS codes
    vertex: np.ndarray | None = None  # (1,) (180 - theta_l - theta_r - min_vertex_deg) / 100


def _one_mu(design: Design, margin_pct, min_normal):
    st = statics_kernel(design.shape, design.mu)
    bc = base_cycle_kernel(*design)
    nums = five_numbers(bc)
    w_m = full_slip_work_shape_factors(design.shape, design.mu).w_M
    metrics = jnp.stack([nums.k_im_bc, nums.psi_bc, w_m])
    return metrics, margins(st, bc, margin_pct, min_normal), bc.status


def _evaluate_full(v, mus, kn, kt, load, margin_pct, min_normal) -> Evaluation:
    """One complete shape vector v = (theta_l, theta_r, br_over_hr, bl2_over_hl) over the mu set."""
    designs = design_from_vector(v, mus, Contacts(kn, kt), LoadCase(*load))
    out = jax.vmap(_one_mu, (Design(None, 0, None, None), None, None))(designs, margin_pct,
                                                                      min_normal)
    return Evaluation(*out)


# One compiled program each, whatever the design space (evaluations take complete shape vectors
# and derivatives are taken with respect to all four parameters), batched by jaxdamp.map_batched.


def _with_jacobian(v, *args):
    def f(v):
        ev = _evaluate_full(v, *args)
        return (ev.metrics, ev.margins.g), ev

    return jax.jacfwd(f, has_aux=True)(v)




MU_PAD = 3  # mu sets are padded (repeating the last mu) to at least this length: one compile


def _padded_mus(problem: Problem):
    mus = list(problem.mus)
    return jnp.asarray(mus + [mus[-1]] * max(0, MU_PAD - len(mus)))


def _unpad(problem: Problem, tree):
    """Drop the padding entries on the mu axis (axis 1 of every batched output)."""
    n = len(problem.mus)
    return jax.tree_util.tree_map(lambda a: a[:, :n], tree)


def _args(problem: Problem):
    return (_padded_mus(problem), jnp.asarray(problem.kn), jnp.asarray(problem.kt),
            tuple(jnp.asarray(v) for v in problem.load), jnp.asarray(problem.margin_pct),
            jnp.asarray(problem.min_normal))


def _check_columns(problem: Problem, X):
    X = np.atleast_2d(np.asarray(X, float))
    if X.ndim != 2 or X.shape[-1] != problem.space.dim:
        raise ValueError(f"designs must have {problem.space.dim} columns {problem.space.free}; "
                         f"got shape {X.shape}")
    return X


def evaluate(problem: Problem, X) -> Evaluation:
    """Values (no derivatives) for a batch of physical design vectors X (B, d)."""
    X = _check_columns(problem, X)
    return evaluate_shapes(problem, embed(problem.space, X))


def evaluate_shapes(problem: Problem, V) -> Evaluation:
    """Values for complete shape vectors V (B, 4) ordered as design.VARIABLES."""
    V = np.atleast_2d(np.asarray(V, float))
    ev = _unpad(problem, map_batched(_evaluate_full, V, *_args(problem), chunk_size=CHUNK))
    return ev._replace(vertex=vertex_constraint(problem, V))


def evaluate_with_jacobian(problem: Problem, Z):
    """Values and Jacobians at unit-box points Z (B, d).

    Returns (Evaluation, d_metrics (B, n_mu, 3, d), d_g (B, n_mu, 3, 3, d), d_vertex (B, 1, d)),
    derivatives with respect to the unit-box coordinates z (forward mode).
    """
    Z = _check_columns(problem, Z)
    space = problem.space
    V = embed(space, np.asarray(from_unit(space, Z)))
    (d_metrics, d_g), ev = _unpad(problem, map_batched(_with_jacobian, V, *_args(problem), chunk_size=JAC_BATCH))
    cols = free_columns(space)
    span = np.asarray(space.upper) - np.asarray(space.lower)
    d_vertex = np.zeros((len(V), 1, 4))
    d_vertex[..., :2] = -1.0 / VERTEX_SCALE
    ev = ev._replace(vertex=vertex_constraint(problem, V))
    return ev, d_metrics[..., cols] * span, d_g[..., cols] * span, d_vertex[..., cols] * span


VERTEX_SCALE = 100.0  # degrees per unit of the vertex constraint (1 deg ~ a 1 % margin)


def vertex_constraint(problem: Problem, V) -> np.ndarray:
    """(B, 1) geometric constraint (180 - theta_l - theta_r - min_vertex_deg) / 100 >= 0."""
    V = np.atleast_2d(np.asarray(V, float))
    return ((180.0 - V[:, 0] - V[:, 1] - problem.min_vertex_deg) / VERTEX_SCALE)[:, None]


def is_feasible(ev: Evaluation):
    """Strict feasibility per design (batch axis kept): every g >= 0, every Base-Cycle ok."""
    g = np.asarray(ev.margins.g)
    ok = np.all(g >= 0.0, axis=(-3, -2, -1)) & np.all(np.asarray(ev.vertex) >= 0.0, axis=-1)
    cycles_ok = np.all(np.asarray(ev.status) == RESULTS.ok, axis=-1)
    return ok & cycles_ok


def max_violation(ev: Evaluation):
    """Largest constraint violation per design (units of F_D); 0 when every g >= 0."""
    g = np.asarray(ev.margins.g)
    worst = np.max(np.maximum(-g, 0.0), axis=(-3, -2, -1))
    return np.maximum(worst, np.max(np.maximum(-np.asarray(ev.vertex), 0.0), axis=-1))


def min_margin_pct(ev: Evaluation):
    """Smallest distance of the left resultant from the nearer pad, over mu, both ends and the
    cycle (% of L1-L2); this is the achieved margin, to compare with the required one."""
    return np.min(np.asarray(ev.margins.dist_pct), axis=(-3, -2, -1))


__all__ = ["DEFAULT_MU_SET", "DEFAULT_MARGIN_PCT", "DEFAULT_MIN_VERTEX_DEG", "CHUNK", "JAC_BATCH",
           "Problem", "make_problem", "Evaluation", "MU_PAD", "evaluate", "evaluate_shapes",
           "evaluate_with_jacobian", "VERTEX_SCALE", "vertex_constraint", "is_feasible",
           "max_violation", "min_margin_pct"]
