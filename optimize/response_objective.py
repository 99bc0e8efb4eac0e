"""Response-based shape optimisation: minimise the worst-case blade peak A* over the friction set
(optionally over F_D +/- a spread) at a given modal force, under the no-liftoff constraint.

The objective is what a designer asks (how far does the shape lower the resonant response, whatever
mu and F_D turn out to be), not a damper number. It uses `jaxdamp.response` (public API):

    worst_peak(v) = max over mu in the set, F_D in {F_D (1 - s), F_D, F_D (1 + s)} of A*(v; mu, F_D, F)

with A* the peak of the branch connected to small amplitudes. The F_D variants cost nothing extra:
`scaled_stiffness` rescales one damper curve per mu. Gradients of A* come by the implicit function
theorem through the root; the max picks the worst case (a subgradient at ties).

Search: a coarse grid over the design space (the constraint is checked by `jaxdamp_optimize.problem`, the
same margins as the k_Im,BC optimiser), then projected gradient descent from the best feasible grid
points on the unit box, with backtracking that rejects infeasible or non-improving steps (the
no-liftoff constraint is kept strictly, never penalised).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxdamp import RESULTS, BladeMode, Contacts, LoadCase, damper_stiffness, peak_response
from jaxdamp.blocks import scaled_stiffness

from .descent import feasible_descent
from .design import VARIABLES, shape_of_vector
from .problem import Problem, evaluate_shapes, is_feasible, make_problem


def _peaks_one(v, mus, fd_factors, force_n, mode, kn, kt, load):
    """(n_mu, n_fd) peak amplitudes (mm) and damper statuses of the complete shape vector v."""
    load = LoadCase(*load)

    def per_mu(mu):
        d = damper_stiffness(shape_of_vector(v), mu, Contacts(kn, kt), load, method="interpolated")
        a = jax.vmap(lambda c: peak_response(scaled_stiffness(d, load.F_D, load.F_D * c), mode,
                                             force_n).peak_amplitude_mm)(fd_factors)
        return a, d.status

    return jax.vmap(per_mu)(mus)


@jax.jit
def _worst(v, mus, fd_factors, force_n, mode, kn, kt, load):
    a, status = _peaks_one(v, mus, fd_factors, force_n, mode, kn, kt, load)
    return jnp.max(a), RESULTS.worst(status)


_worst_batch = jax.jit(jax.vmap(_worst, (0,) + (None,) * 7))
_worst_grad = jax.jit(jax.value_and_grad(lambda *a: _worst(*a)[0]))


class ResponseDesign(NamedTuple):
    """A design and its worst-case peak over the friction (and F_D) set."""

    name: str
    shape: tuple  # (theta_l, theta_r, br_over_hr, bl2_over_hl)
    worst_peak_mm: float | None  # None where the design is infeasible (liftoff / margins)
    feasible: bool
    min_k_im_bc: float | None  # worst-case k_Im,BC over the mu set, for comparison


class ResponseOptimum(NamedTuple):
    best: ResponseDesign
    references: list  # ResponseDesign of 60sym and of the k_Im,BC optimum (when given)
    force_n: float
    fd_spread: float
    mus: tuple
    grid_evaluations: int
    descent_steps: int


def _args(problem: Problem, force_n, fd_spread, mode):
    fd = jnp.asarray([1.0 - fd_spread, 1.0, 1.0 + fd_spread] if fd_spread > 0 else [1.0])
    mode = BladeMode(*(jnp.asarray(x, float) for x in mode))
    return (jnp.asarray(problem.mus), fd, jnp.asarray(float(force_n)), mode,
            jnp.asarray(problem.kn), jnp.asarray(problem.kt), tuple(jnp.asarray(x) for x in problem.load))


def worst_peak(V, problem: Problem | None = None, force_n=20.0, fd_spread=0.0,
               mode: BladeMode = BladeMode()):
    """(B,) worst-case peak A* (mm) of complete shape vectors V (B, 4), NaN-free: None-like
    np.inf where the damper lifts off at some mu; and (B,) feasibility by the optimiser's margins."""
    problem = make_problem() if problem is None else problem
    V = np.atleast_2d(np.asarray(V, float))
    a, st = _worst_batch(jnp.asarray(V), *_args(problem, force_n, fd_spread, mode))
    feasible = np.asarray(is_feasible(evaluate_shapes(problem, V))) & (np.asarray(st) == 0)
    return np.where(np.asarray(st) == 0, np.asarray(a), np.inf), feasible


def complete_shape(problem: Problem, z):
    """Complete shape vector from unit-box coordinates of the free variables."""
    sp = problem.space
    fixed = dict(sp.fixed)
    lo, hi = np.asarray(sp.lower), np.asarray(sp.upper)
    x = dict(zip(sp.free, lo + np.asarray(z) * (hi - lo)))
    return np.array([x.get(n, fixed.get(n)) for n in VARIABLES], float)


def optimize_response(problem: Problem | None = None, force_n=20.0, fd_spread=0.0,
                      mode: BladeMode = BladeMode(), *, grid_points: int = 7, starts: int = 3,
                      steps: int = 25, k_im_optimum=None) -> ResponseOptimum:
    """Minimise the worst-case peak A* (see module doc). k_im_optimum: a complete shape vector
    (the k_Im,BC optimiser's result) to report on the same objective."""
    import itertools

    problem = make_problem() if problem is None else problem
    sp = problem.space
    args = _args(problem, force_n, fd_spread, mode)
    axes = [np.linspace(0.0, 1.0, grid_points)] * sp.dim
    Z = np.array(list(itertools.product(*axes)))
    V = np.stack([complete_shape(problem, z) for z in Z])
    vals, feas = worst_peak(V, problem, force_n, fd_spread, mode)
    vals = np.where(feas, vals, np.inf)
    order = np.argsort(vals)[:starts]
    span = np.asarray(sp.upper) - np.asarray(sp.lower)
    free_idx = [VARIABLES.index(n) for n in sp.free]
    best_z, best_val, n_steps = None, np.inf, 0

    def gradient(z):
        _, g = _worst_grad(jnp.asarray(complete_shape(problem, z)), *args)
        return np.asarray(g)[free_idx] * span

    def evaluate(z):
        vn, fn = worst_peak(complete_shape(problem, z)[None], problem, force_n, fd_spread, mode)
        return float(vn[0]), bool(fn[0])

    for i in order:
        if not np.isfinite(vals[i]):
            continue
        run = feasible_descent(Z[i], float(vals[i]), gradient, evaluate, steps=steps,
                               step_size=0.05, tries=6, min_step=1e-5)
        n_steps += run.evaluations
        if run.value < best_val:
            best_z, best_val = run.z, run.value
    best = _report(problem, "response optimum", complete_shape(problem, best_z), force_n, fd_spread, mode) \
        if best_z is not None else ResponseDesign("response optimum", (), None, False, None)
    from jaxdamp import family_shape

    s = family_shape("60sym")
    refs = [_report(problem, "60sym", np.array([s.theta_l, s.theta_r, s.br_over_hr, s.bl2_over_hl]),
                    force_n, fd_spread, mode)]
    if k_im_optimum is not None:
        refs.append(_report(problem, "k_Im,BC optimum", np.asarray(k_im_optimum, float), force_n,
                            fd_spread, mode))
    return ResponseOptimum(best, refs, float(force_n), float(fd_spread), problem.mus, len(Z), n_steps)


def _report(problem, name, v, force_n, fd_spread, mode) -> ResponseDesign:
    val, feas = worst_peak(v[None], problem, force_n, fd_spread, mode)
    ev = evaluate_shapes(problem, v[None])
    k_im = float(np.min(np.asarray(ev.metrics)[0, :, 0]))
    ok = bool(feas[0])
    return ResponseDesign(name, tuple(float(x) for x in v), float(val[0]) if ok else None, ok,
                          k_im if ok else None)


__all__ = ["worst_peak", "optimize_response", "complete_shape", "ResponseDesign", "ResponseOptimum"]
