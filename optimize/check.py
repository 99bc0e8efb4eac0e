"""Final feasibility check of a design, active constraints and the reason for infeasibility.

The check goes through the public API (`jaxdamp.full_slip_statics`, `jaxdamp.base_cycle`, one
mu at a time), a different path from the optimiser's batched, differentiated evaluator.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import numpy as np

import jaxdamp as jd
from jaxdamp import RESULTS

from .constraints import KINDS, LOCATIONS, constraint_label, describe_violation, margins
from .design import shape_of
from .problem import Problem


class DesignCheck(NamedTuple):
    """One design re-checked at every mu of the set."""

    feasible: bool
    metrics: np.ndarray  # (n_mu, 3): k_im_bc, psi_bc, w_m
    min_margin_pct: float | None  # smallest resultant distance from the nearer pad (% L1-L2)
    min_normal: float  # smallest normal force (F_D) over mu, both ends and the cycle
    g: np.ndarray  # (n_mu, 3, 3) constraint values (F_D)
    dist_pct: np.ndarray  # (n_mu, 3, 2)
    normals: np.ndarray  # (n_mu, 3)
    flags: list  # per mu: {"mu", "status", "statics_status"} (RESULTS names)
    vertex_deg: float  # vertex angle 180 - theta_l - theta_r


def check_design(problem: Problem, x) -> DesignCheck:
    """Feasibility of design x (physical free variables) at every mu of the problem's set."""
    s = shape_of(problem.space, np.asarray(x, float))
    shape = jd.DamperShape(*(float(v) for v in s[:4]))
    contacts = jd.Contacts(problem.kn, problem.kt)
    load = jd.LoadCase(*problem.load)
    gs, ds, ns, flags, metrics = [], [], [], [], []
    for mu in problem.mus:
        st = jd.full_slip_statics(shape, mu)
        bc = jd.base_cycle(shape, mu, contacts, load)
        mg, k_im, psi, w_m = _derived(st, bc, problem.margin_pct, problem.min_normal)
        gs.append(np.asarray(mg.g))
        ds.append(np.asarray(mg.dist_pct))
        ns.append(np.asarray(mg.min_normal))
        flags.append({"mu": mu, "status": RESULTS.name_of(bc.status),
                      "statics_status": RESULTS.name_of(st.status)})
        metrics.append([float(k_im), float(psi), float(w_m)])
    g, dist, normals = np.array(gs), np.array(ds), np.array(ns)
    ok_flags = all(f["status"] == f["statics_status"] == "ok" for f in flags)
    vertex = 180.0 - shape.theta_l - shape.theta_r
    ok_vertex = vertex >= problem.min_vertex_deg
    dmin = float(np.min(dist))
    return DesignCheck(bool(np.all(g >= 0.0) and ok_flags and ok_vertex), np.array(metrics),
                       dmin if np.isfinite(dmin) else None, float(np.min(normals)), g, dist,
                       normals, flags, float(vertex))


@jax.jit
def _derived(st, bc, margin_pct, min_normal):
    """Margins and metrics from the statics and Base-Cycle (jitted: op-by-op is slow)."""
    from jaxdamp import five_numbers, full_slip_work_shape_factors

    nums = five_numbers(bc)
    w_m = full_slip_work_shape_factors(bc.shape, bc.mu).w_M
    return margins(st, bc, margin_pct, min_normal), nums.k_im_bc, nums.psi_bc, w_m


def active_constraints(problem: Problem, check: DesignCheck, tol_pct=0.5, tol_normal=0.005,
                       tol_deg=0.5) -> list[dict]:
    """Constraints of a design that are at their bound within a tolerance: a resultant margin
    within tol_pct (% of L1-L2) of the required one, a normal force within tol_normal (F_D) of its
    minimum, the vertex angle within tol_deg of its minimum."""
    out = []
    if problem.min_vertex_deg > 0 and check.vertex_deg - problem.min_vertex_deg <= tol_deg:
        out.append({"constraint": f"vertex angle 180 - theta_L - theta_R >= "
                                  f"{problem.min_vertex_deg:g} deg", "mu": None,
                    "location": "geometry", "kind": "vertex", "value": check.vertex_deg,
                    "unit": "deg"})
    for i, mu in enumerate(problem.mus):
        for j, loc in enumerate(LOCATIONS):
            for k, kind in enumerate(KINDS):
                if kind == "normal":
                    value, unit = float(check.normals[i, j]), "F_D"
                    near = value - problem.min_normal <= tol_normal
                else:
                    value, unit = float(check.dist_pct[i, j, k]), "% of L1-L2"
                    near = value - problem.margin_pct <= tol_pct
                if near:
                    out.append({"constraint": constraint_label(mu, loc, kind, problem.margin_pct,
                                                               problem.min_normal),
                                "mu": mu, "location": loc, "kind": kind, "value": value,
                                "unit": unit})
    return out


def design_status(check: DesignCheck) -> RESULTS:
    """The status of a checked design: the most severe of its cycles' and statics' statuses
    (jaxdamp.status.SEVERITY); where those are ok but the design is infeasible, liftoff (its
    no-liftoff margins, or the vertex angle of the design rule, fail)."""
    codes = [RESULTS[f[key]] for f in check.flags for key in ("status", "statics_status")]
    worst = RESULTS(int(RESULTS.worst(codes)))
    if worst == RESULTS.ok and not check.feasible:
        return RESULTS.liftoff
    return worst


def violations(problem: Problem, check: DesignCheck) -> list[str]:
    """Human-readable violated constraints and failed cycle flags of a checked design."""
    out = []
    if check.vertex_deg < problem.min_vertex_deg:
        out.append(f"vertex angle {check.vertex_deg:.2f} deg below the minimum "
                   f"{problem.min_vertex_deg:g} deg")
    for i, mu in enumerate(problem.mus):
        for j, loc in enumerate(LOCATIONS):
            for k, kind in enumerate(KINDS):
                if check.g[i, j, k] < 0:
                    d = check.dist_pct[i, j, min(k, 1)]
                    out.append(describe_violation(mu, loc, kind, float(d),
                                                  float(check.normals[i, j]), problem.margin_pct))
        f = check.flags[i]
        if f["status"] == "singular":
            out.append(f"mu={mu:g}: the Base-Cycle solver found no consistent contact states")
        elif f["status"] == "not_converged":
            out.append(f"mu={mu:g}: the Base-Cycle did not close within its iteration bound")
        elif f["status"] == "ill_conditioned":
            out.append(f"mu={mu:g}: {RESULTS.message(RESULTS.ill_conditioned)}")
    return out


def _short(problem: Problem, idx) -> str:
    i, j, k = idx
    what = ("normal forces > 0" if KINDS[k] == "normal"
            else f"left resultant inside, clear of {KINDS[k]}")
    return f"mu={problem.mus[i]:g} {LOCATIONS[j]}: {what}"


def conflicting_pairs(check: DesignCheck, jacobian, cos_limit=-0.5) -> list[tuple]:
    """Pairs of violated constraints whose gradients (rows of jacobian (m, d)) point in opposite
    directions (cosine below cos_limit): improving one worsens the other."""
    g = check.g.reshape(-1)
    bad = np.nonzero(g < 0)[0]  # margins only (the first check.g.size rows of the jacobian)
    pairs = []
    for a in range(len(bad)):
        for b in range(a + 1, len(bad)):
            u, v = jacobian[bad[a]], jacobian[bad[b]]
            nu, nv = np.linalg.norm(u), np.linalg.norm(v)
            if nu > 0 and nv > 0 and np.dot(u, v) / (nu * nv) < cos_limit:
                pairs.append((np.unravel_index(bad[a], check.g.shape),
                              np.unravel_index(bad[b], check.g.shape)))
    return pairs


def infeasibility_reason(problem: Problem, check: DesignCheck, jacobian=None) -> str:
    """Why no feasible design was found, from the least-violating design and its constraint
    Jacobian (m, d) (rows in the order of check.g.reshape(-1))."""
    lines = violations(problem, check) or ["no constraint is violated but a cycle flag failed"]
    text = ("no feasible design within the bounds; at the least-violating design found: "
            + "; ".join(lines) + ".")
    if jacobian is not None:
        pairs = conflicting_pairs(check, np.asarray(jacobian))
        if pairs:
            a, b = pairs[0]
            free = ", ".join(problem.space.free)
            text += (f" The violated constraints '{_short(problem, a)}' and '{_short(problem, b)}' "
                     f"pull {free} in opposite directions, so no design in the bounds meets both.")
    return text


__all__ = ["DesignCheck", "check_design", "design_status", "active_constraints", "violations", "conflicting_pairs",
           "infeasibility_reason"]
