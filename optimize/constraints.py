"""The no-liftoff constraint as margin functions g >= 0, from the statics and the Base-Cycle.

At every friction coefficient of the set, at both full-slip ends (cycle start and mid-cycle, from
the full-slip statics) and throughout the Base-Cycle, every normal force must stay positive and the
left resultant must stay inside L1-L2 with a margin m (% of L1-L2) from both pads.

Within a tract the normal forces are linear in the travel, so the left resultant position
N_L2 / (N_L1 + N_L2) is monotone there and its extremes over the cycle are at tract end points;
the constraints over the cycle are the minima over those end points (exact, piecewise smooth).

The optimiser uses division-free forms in units of F_D, smooth and defined past liftoff:

    g_L1 = N_L2 - m (N_L1 + N_L2)   (>= 0: resultant at least m from L1)
    g_L2 = N_L1 - m (N_L1 + N_L2)   (>= 0: resultant at least m from L2)
    g_N  = min_i N_i - N_min         (>= 0: every normal force above N_min, default 0)

with m as a fraction. Where N_L1 + N_L2 > 0 they have the sign of (distance - m); where it is not
positive, g_L1 + g_L2 < 0, so the point is still reported as violating. Distances in % of L1-L2
are returned alongside for reporting.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp

from jaxdamp import FullSlipStatics

LOCATIONS = ("start", "mid", "cycle")
LOCATION_TEXT = {"start": "cycle start (full slip)", "mid": "mid-cycle (full slip)",
                 "cycle": "during the Base-Cycle"}
KINDS = ("L1", "L2", "normal")
BIG = 1e6  # masked points (inactive tracts) never bind


def select_min(a, axis):
    """min along axis whose derivative is the selected element's (by argmin and a gather).

    jnp.min's JVP finds the minimum by an equality test between the operand and the result; under
    jit, XLA may recompute the two with different rounding, the test then fails everywhere and the
    JVP is 0/0 = NaN. Selecting by index has no such test.
    """
    idx = jnp.expand_dims(jnp.argmin(a, axis=axis), axis)
    return jnp.squeeze(jnp.take_along_axis(a, idx, axis=axis), axis)


class Margins(NamedTuple):
    """Constraint values at one friction coefficient; first axis over LOCATIONS."""

    g: jnp.ndarray  # (3 locations, 3 kinds), units of F_D, feasible where >= 0
    dist_pct: jnp.ndarray  # (3, 2) smallest resultant distance from L1 / from L2, % of L1-L2
    min_normal: jnp.ndarray  # (3,) smallest normal force / F_D


def point_constraints(N, margin_frac, min_normal):
    """(g_L1, g_L2, g_N) at contact forces N (..., 3) ordered (R1, L1, L2)."""
    left = N[..., 1] + N[..., 2]
    g_l1 = N[..., 2] - margin_frac * left
    g_l2 = N[..., 1] - margin_frac * left
    g_n = select_min(N, -1) - min_normal
    return jnp.stack([g_l1, g_l2, g_n], -1)


def resultant_distances_pct(N):
    """Distance of the left resultant from L1 and from L2 (..., 2), % of L1-L2; negative outside.

    Where N_L1 + N_L2 <= 0 the left side has lifted off and the distance is -inf.
    """
    left = N[..., 1] + N[..., 2]
    ok = left > 1e-12
    safe = jnp.where(ok, left, 1.0)
    pos = 100.0 * N[..., 2] / safe
    d = jnp.stack([pos, 100.0 - pos], -1)
    return jnp.where(ok[..., None], d, -jnp.inf)


def cycle_points(bc):
    """Contact normal forces at every tract end point of both halves, and a validity mask.

    Returns N (P, 3) and mask (P,): tract starts and ends of active tracts and the two half ends.
    """
    pts, mask = [], []
    for half in (bc.forward, bc.backward):
        pts += [half.N0, half.N0 + half.dN * half.dv[:, None], half.N_end[None]]
        mask += [half.active, half.active, jnp.ones((1,), bool)]
    return jnp.concatenate(pts, 0), jnp.concatenate(mask, 0)


def margins(statics: FullSlipStatics, bc, margin_pct, min_normal=0.0) -> Margins:
    """Margins at both full-slip ends (statics) and over the Base-Cycle (tract end points)."""
    m = jnp.asarray(margin_pct, float) / 100.0
    ends = jnp.stack([statics.start.N, statics.mid.N])  # (2, 3)
    g_ends = point_constraints(ends, m, min_normal)
    d_ends = resultant_distances_pct(ends)
    n_ends = jnp.min(ends, axis=-1)
    # If the statics solve fails, the forces are zero: that is reported as a violation (g_N < 0 for
    # min_normal > 0, and the flag `solvable`); make it strict by subtracting a tiny amount.
    solvable = jnp.stack([statics.start.solvable, statics.mid.solvable])
    g_ends = jnp.where(solvable[:, None], g_ends, jnp.minimum(g_ends, -1e-9))

    N, mask = cycle_points(bc)
    g_pts = point_constraints(N, m, min_normal)
    g_cyc = select_min(jnp.where(mask[:, None], g_pts, BIG), 0)
    d_cyc = jnp.min(jnp.where(mask[:, None], resultant_distances_pct(N), BIG), axis=0)
    n_cyc = jnp.min(jnp.where(mask, jnp.min(N, axis=-1), BIG))
    # With liftoff already at the cycle start the cycle is not run (its arrays are placeholders):
    # the cycle inherits the cycle-start values, which are violating.
    lift0 = (statics.start.min_normal <= 0.0) | ~statics.start.solvable
    g_cyc = jnp.where(lift0, g_ends[0], g_cyc)
    d_cyc = jnp.where(lift0, d_ends[0], d_cyc)
    n_cyc = jnp.where(lift0, n_ends[0], n_cyc)
    g = jnp.concatenate([g_ends, g_cyc[None]], 0)
    dist = jnp.concatenate([d_ends, d_cyc[None]], 0)
    nmin = jnp.concatenate([n_ends, n_cyc[None]], 0)
    return Margins(g, dist, nmin)


def constraint_label(mu, location: str, kind: str, margin_pct: float, min_normal: float = 0.0) -> str:
    where = LOCATION_TEXT[location]
    if kind == "normal":
        return f"mu={mu:g}, {where}: every normal force > {min_normal:g} F_D"
    return f"mu={mu:g}, {where}: left resultant >= {margin_pct:g} % of L1-L2 from {kind}"


def describe_violation(mu, location: str, kind: str, dist_pct: float, min_normal_value: float,
                       margin_pct: float) -> str:
    """One human-readable line for a violated (or active) constraint."""
    where = LOCATION_TEXT[location]
    if kind == "normal":
        return f"mu={mu:g}, {where}: a normal force reaches {min_normal_value:.4f} F_D (liftoff)"
    if not jnp.isfinite(dist_pct):
        return f"mu={mu:g}, {where}: both left pads unloaded (left resultant undefined, liftoff)"
    if dist_pct < 0:
        return (f"mu={mu:g}, {where}: left resultant outside L1-L2, {-dist_pct:.2f} % of L1-L2 beyond "
                f"{kind}")
    return (f"mu={mu:g}, {where}: left resultant {dist_pct:.2f} % of L1-L2 from {kind} "
            f"(required >= {margin_pct:g} %)")


__all__ = ["LOCATIONS", "LOCATION_TEXT", "KINDS", "BIG", "select_min", "Margins",
           "point_constraints", "resultant_distances_pct", "cycle_points", "margins",
           "constraint_label", "describe_violation"]
