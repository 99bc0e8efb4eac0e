"""Brute-force grid search over the same bounds (vmap-batched), coarse to fine.

Level 0 is a full tensor grid over the design box. Each further level puts a finer tensor grid
(same number of points per axis) over +-1 spacing of the previous level around each of the best
`top` feasible designs found so far (distinct cells), clipped to the bounds. Every design is one
evaluation (values only, over the whole mu set), counted as in the gradient optimiser.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .objectives import DEFAULT_OBJECTIVE, Objective, parse_objective
from .problem import Problem, evaluate, is_feasible, make_problem
from .reference import Scorer, make_scorer


class GridResult(NamedTuple):
    X: np.ndarray  # (n, d) every evaluated design (physical units), level 0 first
    score: np.ndarray  # (n,) aggregated score (maximise; objective units, sense applied)
    value: np.ndarray  # (n,) objective as reported
    feasible: np.ndarray  # (n,) strict feasibility (all g >= 0, no liftoff, converged)
    level: np.ndarray  # (n,) refinement level of each design
    evaluations: int  # designs evaluated (+1 for the baseline normaliser)
    best_x: np.ndarray | None  # best feasible design (None if none is feasible)
    best_value: float | None
    axes: tuple  # level-0 grid axes, one 1-D array per free variable
    free: tuple  # names of the free variables
    sense: float  # value = sense * score for single metrics (+1 maximised, -1 minimised)


def _tensor(axes):
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], -1)


def grid_search(objective: str | Objective = DEFAULT_OBJECTIVE, problem: Problem | None = None,
                points=15, levels: int = 2, top: int = 2, refine_points: int = 7,
                scorer: Scorer | None = None, weights=None) -> GridResult:
    """Grid search. points: per-axis count at level 0 (int or one per free variable)."""
    problem = make_problem() if problem is None else problem
    obj = objective if isinstance(objective, Objective) else parse_objective(objective, weights)
    space = problem.space
    counts = np.broadcast_to(np.asarray(points, int), (space.dim,))
    if np.any(counts < 2) or levels < 1 or top < 1 or refine_points < 3:
        raise ValueError("points must be >= 2 per axis, levels >= 1, top >= 1, refine_points >= 3")
    evaluations = 0
    if scorer is None:
        scorer, evaluations = make_scorer(problem, obj)
    lo, hi = np.asarray(space.lower), np.asarray(space.upper)
    axes = tuple(np.linspace(lo[k], hi[k], counts[k]) for k in range(space.dim))
    spacing = (hi - lo) / (counts - 1)
    X = _tensor(axes)
    lev = np.zeros(len(X), int)
    ev = evaluate(problem, X)
    score = scorer.score(ev.metrics)
    feas = is_feasible(ev)
    for level in range(1, levels):
        centres = _best_distinct(X, score, feas, top, spacing)
        if not centres:
            break
        new = []
        for c in centres:
            local = [np.linspace(max(lo[k], c[k] - spacing[k]), min(hi[k], c[k] + spacing[k]),
                                 refine_points) for k in range(space.dim)]
            new.append(_tensor(local))
        Xn = np.concatenate(new, 0)
        ev_n = evaluate(problem, Xn)
        X = np.concatenate([X, Xn])
        lev = np.concatenate([lev, np.full(len(Xn), level)])
        score = np.concatenate([score, scorer.score(ev_n.metrics)])
        feas = np.concatenate([feas, is_feasible(ev_n)])
        spacing = 2.0 * spacing / (refine_points - 1)
    evaluations += len(X)
    value = np.asarray([scorer.value_of_score(s) for s in score])
    best_x = best_value = None
    if feas.any():
        k = int(np.argmax(np.where(feas, score, -np.inf)))
        best_x, best_value = X[k], float(value[k])
    return GridResult(X, score, value, feas, lev, evaluations, best_x, best_value, axes, space.free,
                      obj.sense)


def _best_distinct(X, score, feas, top, spacing):
    """Up to `top` best feasible designs, each more than one spacing from the ones already taken."""
    order = np.argsort(-np.where(feas, score, -np.inf))
    taken = []
    for k in order:
        if not feas[k]:
            break
        if all(np.any(np.abs(X[k] - c) > spacing * (1 + 1e-9)) for c in taken):
            taken.append(X[k])
        if len(taken) == top:
            break
    return taken


def heatmap(grid: GridResult, x_var: str = "theta_l", y_var: str = "theta_r"):
    """Best feasible objective (reported units) over the level-0 grid, maximised over the other
    variables, on the (x_var, y_var) plane. Returns (x_axis, y_axis, Z) with Z[j, i] at
    (x_axis[i], y_axis[j]) and NaN where no design is feasible."""
    free = list(grid.free)
    if x_var not in free or y_var not in free or x_var == y_var:
        raise ValueError(f"x_var and y_var must be two different free variables among {free}")
    shape = tuple(len(a) for a in grid.axes)
    n0 = int(np.prod(shape))
    s = np.where(grid.feasible[:n0], grid.score[:n0], -np.inf).reshape(shape)
    ix, iy = free.index(x_var), free.index(y_var)
    others = tuple(k for k in range(len(free)) if k not in (ix, iy))
    best = np.max(s, axis=others) if others else s  # axes in the order (min(ix,iy), max(ix,iy))
    best_xy = best if ix < iy else best.T
    Z = np.where(np.isfinite(best_xy), grid.sense * best_xy, np.nan).T
    return grid.axes[ix], grid.axes[iy], Z


__all__ = ["GridResult", "grid_search", "heatmap"]
