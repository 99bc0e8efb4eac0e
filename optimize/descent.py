"""Projected descent that only accepts feasible improvements, on the unit box of the free variables.

The response and robust optimisers minimise a worst case whose gradient is that of a smooth
surrogate (a log-sum-exp, or the peak of the worst scenario), under a constraint that is never
penalised: a step is kept only where the design is feasible and the true objective falls. This is
that loop, once: normalised gradient steps, clipped to [0, 1]; a step grows 1.5 times after an
accepted move and shrinks 0.3 times per rejected try.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

GROW = 1.5  # step factor after an accepted move
SHRINK = 0.3  # step factor after a rejected try


class Descent(NamedTuple):
    """Where a descent ended: z on the unit box, its objective value, the objective evaluations
    spent, and (step, value) of every accepted move."""

    z: np.ndarray
    value: float
    evaluations: int
    accepted: list


def feasible_descent(z, value: float, gradient: Callable, evaluate: Callable, *, steps: int,
                     step_size: float, tries: int, min_step: float = 0.0,
                     transform=None) -> Descent:
    """From z (unit box) with objective `value`: at most `steps` moves along -gradient(z) (any
    scale: it is normalised), each found in at most `tries` step sizes; evaluate(z) -> (value,
    feasible). Stops early at a zero or non-finite gradient, a step with no accepted try, or a
    step size below min_step. transform: an optax GradientTransformation (e.g.
    `optax.scale_by_lbfgs()`) whose update of the gradient at z is the direction instead (its
    state sees only accepted points: L-BFGS's curvature pairs are the accepted steps), normalised
    in the same way; the gradient itself where that is no descent direction."""
    z = np.asarray(z, float)
    evaluations, accepted = 0, []
    state = None if transform is None else transform.init(z)
    for step in range(steps):
        g = np.asarray(gradient(z), float)
        if transform is not None:
            d, state = transform.update(g, state, z)
            d = np.asarray(d, float)
            g = d if np.isfinite(d).all() and float(d @ g) > 0 else g
        norm = np.linalg.norm(g)
        if not np.isfinite(norm) or norm == 0:
            break
        moved = False
        for _ in range(tries):
            trial = np.clip(z - step_size * g / norm, 0.0, 1.0)
            trial_value, feasible = evaluate(trial)
            evaluations += 1
            if feasible and trial_value < value:
                z, value, step_size, moved = trial, float(trial_value), step_size * GROW, True
                accepted.append((step, value))
                break
            step_size *= SHRINK
        if not moved or step_size < min_step:
            break
    return Descent(z, float(value), evaluations, accepted)


def descend_from_best(Z, values, gradient: Callable, evaluate: Callable, *, starts: int,
                      steps: int, step_size: float, tries: int, min_step: float = 0.0,
                      tick: Callable = lambda n: None, transform=None):
    """`feasible_descent` (with its transform) from each of the `starts` best points of Z (finite
    values only): (best z or None where no start is finite, its value, evaluations spent, (start,
    step, value) of every accepted move). tick(1) after each descent."""
    best_z, best_val, n_desc, hist = None, np.inf, 0, []
    for k, i in enumerate(np.argsort(values)[:starts]):
        if not np.isfinite(values[i]):
            continue
        run = feasible_descent(Z[i], float(values[i]), gradient, evaluate, steps=steps,
                               step_size=step_size, tries=tries, min_step=min_step,
                               transform=transform)
        n_desc += run.evaluations
        hist += [(k, step, val) for step, val in run.accepted]
        if run.value < best_val:
            best_z, best_val = run.z, run.value
        tick(1)
    return best_z, best_val, n_desc, hist


__all__ = ["Descent", "feasible_descent", "descend_from_best", "GROW", "SHRINK"]
