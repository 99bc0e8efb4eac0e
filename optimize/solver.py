"""Shape optimisation: augmented Lagrangian outer loop, optax inner loop, multi-start, history.

Problem:  maximise S(z)  subject to  g_j(z) >= 0  and  z in [0, 1]^d  (the unit box of the bounds)

with S the objective's score divided by the 60sym baseline's (so O(1) whatever the units: k_Im is
thousands of N mm/mrad) and g the no-liftoff margins of `jaxdamp_optimize.constraints` in % of F_D. The
constraints go into the PHR augmented Lagrangian (`jaxdamp_optimize.augmented`); the bounds are enforced by
projection onto the box (clipping z, the exact Euclidean projection). Inner methods (optax):

- ``lbfgs`` (default): `optax.scale_by_lbfgs` directions (vmapped over starts), projected onto the
  box, step length by Armijo backtracking (each trial is one evaluation), the step capped at
  `max_step` in the unit box; memory reset when the direction is not a descent direction or the
  augmented Lagrangian changes (multiplier update);
- ``adam``: projected Adam with a cosine-decayed step.

Every evaluation (one design over the whole mu set, values and forward-mode Jacobian) is counted.
A design is accepted only if it passes the strict check (every g >= 0, no liftoff, cycles
converged); the optimum is the best accepted design over all starts, re-checked by the public
statics and Base-Cycle (`jaxdamp_optimize.check`). If no start produced a feasible design the result is
infeasible, with the reason, and its design is the least-violating one found (not an optimum).
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import optax

from .augmented import ALConfig, ALState, al_init, al_update, al_value_and_grad
from .check import DesignCheck, active_constraints, check_design, infeasibility_reason
from .design import family_start, from_unit, project, shape_dict, to_unit
from .objectives import DEFAULT_OBJECTIVE, Objective, mu_index, parse_objective, per_mu_scores
from .problem import (Problem, evaluate_with_jacobian, is_feasible, make_problem, max_violation,
                      min_margin_pct)
from .reference import FAMILY_NAMES, Scorer, make_scorer

G_SCALE = 100.0  # the optimiser sees g in % of F_D
METHODS = ("lbfgs", "adam")


class SolverConfig(NamedTuple):
    method: str = "lbfgs"
    rounds: int = 60  # evaluation rounds; each running start makes one evaluation per round
    screen_rounds: int = 20  # rounds every start runs before the pruning to the best `keep`
    keep: int = 2
    al_every: int = 5  # rounds between multiplier updates
    al: ALConfig = ALConfig()
    # L-BFGS
    memory: int = 8
    max_step: float = 0.08  # cap on a step's length in the unit box
    armijo: float = 1e-4
    min_fraction: float = 1.0 / 64  # backtracking gives up below this fraction of the step
    tol: float = 1e-6  # a start has converged when its projected step is shorter than this
    # Adam
    learning_rate: float = 0.03
    final_learning_rate: float = 0.002
    # reporting
    active_tol_pct: float = 0.5  # margins within this (% of L1-L2) of the bound are "active"
    active_tol_normal: float = 0.005  # normal forces within this (F_D) of the bound are "active"
    active_tol_deg: float = 0.5  # the vertex angle within this (deg) of its minimum is "active"


class StartSummary(NamedTuple):
    name: str
    x0: np.ndarray
    best_x: np.ndarray | None  # best feasible design of this start (None if none)
    best_objective: float | None  # its objective, reported units
    final_x: np.ndarray
    evaluations: int
    pruned: bool


class OptimizationResult(NamedTuple):
    feasible: bool
    x: np.ndarray  # the optimum (free variables); if infeasible: least-violating design, NOT an optimum
    shape: dict  # theta_l, theta_r, br_over_hr, bl2_over_hl at x
    objective: float  # at x, reported units (re-checked)
    objective_name: str
    units: str
    baseline: dict  # {"shape": "60sym", "objective": value}
    min_margin_pct: float | None  # achieved margin at x: smallest resultant distance from a pad
    active: list  # active constraints at the optimum (see check.active_constraints)
    reason: str | None  # why infeasible; None when feasible
    evaluations: int  # all design evaluations, including the baseline and the final re-check
    history: list  # the winning start, one dict per accepted iterate
    histories: dict  # start name -> its history
    starts: list  # StartSummary per start
    paths: dict  # start name -> (n, d) accepted iterates (physical)
    problem: Problem
    check: DesignCheck


def default_starts(space, names=FAMILY_NAMES):
    """The paper's family shapes (free variables, projected onto the bounds), duplicates removed."""
    starts, seen = [], set()
    for n in names:
        x = family_start(space, n)
        key = tuple(np.round(x, 12))
        if key not in seen:
            seen.add(key)
            starts.append((n, x))
    return starts


def objective_and_gradient(scorer: Scorer, metrics, d_metrics):
    """Normalised score S (B,) and dS/dz (B, d) from metrics (B, n_mu, 3) and their Jacobians.

    The worst case is the exact min over mu and its derivative that of the worst mu (the score is
    linear in the metrics at a fixed worst mu); ties are broken by the lowest index.
    """
    obj = scorer.objective
    per_mu = np.asarray(per_mu_scores(obj, metrics, scorer.refs))  # (B, n_mu)
    d_per_mu = np.moveaxis(np.asarray(per_mu_scores(obj, np.moveaxis(d_metrics, -1, 0),
                                                    scorer.refs)), 0, -1)  # (B, n_mu, d)
    rows = np.arange(per_mu.shape[0])
    if obj.aggregate == "worst":
        k = np.argmin(per_mu, axis=-1)
        s, ds = per_mu[rows, k], d_per_mu[rows, k]
    elif obj.aggregate == "mean":
        s, ds = per_mu.mean(-1), d_per_mu.mean(-2)
    else:
        k = mu_index(obj, scorer.mus)
        s, ds = per_mu[:, k], d_per_mu[:, k]
    return s / scorer.scale, ds / scorer.scale


class _Point(NamedTuple):
    """What the loop keeps about the current iterate of each running start (batch axis first)."""

    z: np.ndarray
    s: np.ndarray  # normalised score
    ds: np.ndarray
    g: np.ndarray  # (B, m) scaled constraints
    dg: np.ndarray  # (B, m, d)


class _Tracker:
    """Per-start bookkeeping: paths, history, best feasible and least-violating designs."""

    def __init__(self, names, problem, scorer):
        self.names, self.problem, self.scorer = names, problem, scorer
        self.paths = {n: [] for n in names}
        self.history = {n: [] for n in names}
        self.best = {n: None for n in names}  # (s, x)
        self.least = {n: None for n in names}  # (violation, x, dg)
        self.evals = {n: 0 for n in names}
        self.total = 0
        self.on_round = None  # progress(round) callback, called at the start of every round

    def seen(self, idx, z, ev, s, dg):
        """Record evaluated points (all of them count and may become the optimum)."""
        x = np.asarray(from_unit(self.problem.space, z))
        feas, viol = is_feasible(ev), max_violation(ev)
        for b, i in enumerate(idx):
            n = self.names[i]
            self.evals[n] += 1
            self.total += 1
            if feas[b] and (self.best[n] is None or s[b] > self.best[n][0]):
                self.best[n] = (float(s[b]), x[b].copy())
            if self.least[n] is None or viol[b] < self.least[n][0]:
                self.least[n] = (float(viol[b]), x[b].copy(), dg[b].copy())
        return x, feas, viol

    def accepted(self, idx, x, ev, feas, viol, al: ALState, mask=None):
        values = self.scorer.value(ev.metrics)
        margin = min_margin_pct(ev)
        for b, i in enumerate(idx):
            if mask is not None and not mask[b]:
                continue
            n = self.names[i]
            self.paths[n].append(x[b].copy())
            m = float(margin[b])
            self.history[n].append({
                "iteration": len(self.history[n]), "evaluations": self.total,
                **shape_dict(self.problem.space, x[b]), "objective": float(values[b]),
                "max_violation": float(viol[b]), "min_margin_pct": m if np.isfinite(m) else None,
                "feasible": bool(feas[b]), "rho": float(al.rho[b])})


def _select(mask, new, old):
    """Per-start choice between two batched pytrees (mask over the leading axis)."""
    def pick(a, b):
        a, b = jnp.asarray(a), jnp.asarray(b)
        return jnp.where(mask.reshape((-1,) + (1,) * (a.ndim - 1)), a, b)
    return jax.tree_util.tree_map(pick, new, old)


def optimize(objective: str | Objective = DEFAULT_OBJECTIVE, problem: Problem | None = None,
             starts=None, config: SolverConfig = SolverConfig(), weights=None,
             progress=None) -> OptimizationResult:
    """Optimise the damper shape under the no-liftoff constraint over the problem's mu set.

    objective: NAME[:AGG] (see jaxdamp_optimize.objectives), default robust worst-case k_Im,BC.
    starts: names of family shapes and/or (name, x0) pairs; default the paper's family.
    progress: None or progress(round) called at the start of each of the config.rounds rounds.
    """
    problem = make_problem() if problem is None else problem
    obj = objective if isinstance(objective, Objective) else parse_objective(objective, weights)
    mu_index(obj, problem.mus)  # raises if a single-mu objective is not in the set
    _check_config(config)
    space = problem.space
    if starts is None:
        starts = default_starts(space)
    else:
        starts = [(s, family_start(space, s)) if isinstance(s, str)
                  else (str(s[0]), np.clip(np.asarray(s[1], float), space.lower, space.upper))
                  for s in starts]
    if not starts:
        raise ValueError("starts must contain at least one start point")
    scorer, n_baseline = make_scorer(problem, obj)
    names = [n for n, _ in starts]
    track = _Tracker(names, problem, scorer)
    track.on_round = progress
    track.total += n_baseline
    z0 = np.stack([np.asarray(to_unit(space, x)) for _, x in starts])
    run = _run_lbfgs if config.method == "lbfgs" else _run_adam
    alive = run(problem, scorer, z0, track, config)

    best = {n: b for n, b in track.best.items() if b is not None}
    if best:
        winner = max(best, key=lambda n: best[n][0])
        x = best[winner][1]
    else:
        winner = min(names, key=lambda n: track.least[n][0])
        x = track.least[winner][1]
    check = check_design(problem, x)
    track.total += 1
    feasible = bool(best) and check.feasible
    objective_value = float(scorer.value(check.metrics[None])[0])
    active = active_constraints(problem, check, config.active_tol_pct, config.active_tol_normal,
                                config.active_tol_deg) if feasible else []
    reason = None
    if not feasible:
        jac = track.least[winner][2] if not best else None
        reason = infeasibility_reason(problem, check, jac)
        if best:
            reason = "the best design failed the final re-check: " + reason
    summaries = [StartSummary(n, np.asarray(x0), None if track.best[n] is None else track.best[n][1],
                              None if track.best[n] is None else float(
                                  scorer.value_of_score(track.best[n][0] * scorer.scale)),
                              np.asarray(track.paths[n][-1]) if track.paths[n] else np.asarray(x0),
                              track.evals[n], i not in set(alive.tolist()))
                 for i, (n, x0) in enumerate(starts)]
    return OptimizationResult(
        feasible=feasible, x=np.asarray(x), shape=shape_dict(space, x), objective=objective_value,
        objective_name=obj.name, units=obj.units,
        baseline={"shape": "60sym", "objective": scorer.baseline_value},
        min_margin_pct=check.min_margin_pct, active=active, reason=reason,
        evaluations=track.total, history=track.history[winner], histories=track.history,
        starts=summaries,
        paths={n: np.asarray(p) for n, p in track.paths.items()}, problem=problem, check=check)


def _evaluate(problem, scorer, z):
    """Evaluate unit-box points z (B, d): the constraint vector is the margins (n_mu * 9, in the
    order of Margins.g flattened) followed by the vertex-angle constraint, all scaled by G_SCALE."""
    ev, d_metrics, d_g, d_vertex = evaluate_with_jacobian(problem, z)
    s, ds = objective_and_gradient(scorer, ev.metrics, d_metrics)
    B = z.shape[0]
    g = G_SCALE * np.concatenate([ev.margins.g.reshape(B, -1), ev.vertex], -1)
    dg = G_SCALE * np.concatenate([d_g.reshape(B, -1, d_g.shape[-1]), d_vertex], 1)
    return ev, _Point(np.asarray(z), s, ds, g, dg)


def _prune(track, alive, config):
    order = []
    for k, i in enumerate(alive):
        n = track.names[i]
        b, lst = track.best[n], track.least[n]
        order.append((0, -b[0], k) if b is not None else (1, lst[0], k))
    return np.sort(np.array([k for *_, k in sorted(order)][:config.keep]))


@functools.cache
def _lbfgs(memory: int):
    """optax L-BFGS init/update, vmapped over starts and jitted (eager vmap re-traces its scans)."""
    t = optax.scale_by_lbfgs(memory_size=memory)
    return jax.jit(jax.vmap(t.init)), jax.jit(jax.vmap(t.update))


def _run_lbfgs(problem, scorer, z0, track, config):
    """Projected L-BFGS with Armijo backtracking on the augmented Lagrangian, batched over starts.

    When backtracking fails, the search restarts from steepest descent (memory reset); if that
    fails too and the start sits on a face of the box, the search continues within the face
    (variables at a bound frozen: e.g. on theta_R = 90 deg, where the right flank is vertical and
    psi_BC jumps); otherwise the start has converged for the present multipliers.
    """
    init, update = _lbfgs(config.memory)
    ids = np.arange(len(z0))
    alive = ids
    ev, pt = _evaluate(problem, scorer, z0)
    x, feas, viol = track.seen(ids, z0, ev, pt.s, pt.dg)
    al = al_init(len(z0), pt.g.shape[1], config.al)
    track.accepted(ids, x, ev, feas, viol, al)
    f, gf = (np.array(a) for a in al_value_and_grad(-pt.s, -pt.ds, pt.g, pt.dg, al))
    lb = init(jnp.asarray(pt.z))
    B = len(z0)
    need_dir = np.ones(B, bool)  # compute a new direction (after an accepted step or a reset)
    direction = np.zeros_like(pt.z)
    frac = np.ones(B)  # backtracking fraction of the current direction
    steepest = np.zeros(B, bool)  # the current direction came from an empty memory
    face = np.zeros(B, bool)  # search restricted to the current face of the box
    done = np.zeros(B, bool)
    pruned = np.zeros(B, bool)  # stopped by the screening (arrays keep their size: no recompiles)
    for rnd in range(config.rounds):
        if track.on_round is not None:
            track.on_round(rnd)
        if need_dir.any():
            first = np.asarray(lb.count) == 0
            upd, lb_new = update(jnp.asarray(gf), lb, jnp.asarray(pt.z))
            upd = np.array(upd)
            descent = np.sum(upd * gf, -1) > 0
            lb_new = _select(jnp.asarray(descent), lb_new, init(jnp.asarray(pt.z)))
            upd = np.where(descent[:, None], upd, gf)
            at_bound = (pt.z <= 0.0) | (pt.z >= 1.0)
            upd = np.where(face[:, None] & at_bound, 0.0, upd)
            norm = np.linalg.norm(upd, axis=-1, keepdims=True)
            upd = upd * np.minimum(1.0, config.max_step / np.maximum(norm, 1e-300))
            lb = _select(jnp.asarray(need_dir), lb_new, lb)
            direction = np.where(need_dir[:, None], upd, direction)
            steepest = np.where(need_dir, first | ~descent, steepest)
            frac = np.where(need_dir, 1.0, frac)
            need_dir[:] = False
        trial = np.asarray(project(pt.z - frac[:, None] * direction))
        step = trial - pt.z
        done |= np.linalg.norm(step, axis=-1) < config.tol
        running = ~done & ~pruned
        if running.any():
            idx = np.nonzero(running)[0]
            ev_t, pt_t = _evaluate(problem, scorer, trial[idx])
            x_t, feas_t, viol_t = track.seen(ids[idx], trial[idx], ev_t, pt_t.s, pt_t.dg)
            sub = ALState(*(a[idx] for a in al))
            f_t, gf_t = (np.asarray(a) for a in al_value_and_grad(-pt_t.s, -pt_t.ds, pt_t.g,
                                                                  pt_t.dg, sub))
            ok = f_t <= f[idx] + config.armijo * np.sum(gf[idx] * step[idx], -1)
            track.accepted(ids[idx], x_t, ev_t, feas_t, viol_t, sub, mask=ok)
            acc = idx[ok]
            pt = _Point(*(np.array(a) for a in pt))
            for field in range(len(pt)):
                pt[field][acc] = pt_t[field][ok]
            f[acc], gf[acc] = f_t[ok], gf_t[ok]
            need_dir[acc] = True
            rej = idx[~ok]
            frac[rej] *= 0.5
            stalled = rej[frac[rej] < config.min_fraction]
            if stalled.size:
                on_face = np.any((pt.z[stalled] <= 0.0) | (pt.z[stalled] >= 1.0), -1)
                to_face = steepest[stalled] & ~face[stalled] & on_face
                finished = steepest[stalled] & ~to_face
                face[stalled[to_face]] = True
                done[stalled[finished]] = True
                reset = np.zeros(B, bool)
                reset[stalled[~finished]] = True
                lb = _select(jnp.asarray(reset), init(jnp.asarray(pt.z)), lb)
                need_dir |= reset
        # Multiplier update every al_every rounds, and at once when every start has converged
        # for the present multipliers (the run ends only if the update changes nothing).
        if (rnd + 1) % config.al_every == 0 or (done | pruned).all():
            new = al_update(al, pt.g, config.al)
            changed = np.asarray(jnp.any(new.lam != al.lam, -1) | (new.rho != al.rho))
            al = new
            if changed.any():
                f, gf = (np.array(a) for a in al_value_and_grad(-pt.s, -pt.ds, pt.g, pt.dg, al))
                lb = _select(jnp.asarray(changed), init(jnp.asarray(pt.z)), lb)
                need_dir |= changed
                done &= ~changed
                face &= ~changed
        if rnd + 1 == config.screen_rounds and len(alive) > config.keep:
            alive = alive[_prune(track, alive, config)]
            pruned = ~np.isin(ids, alive)
        if (done | pruned).all():
            break
    return alive


@functools.cache
def _adam(learning_rate: float, rounds: int, final_learning_rate: float):
    """optax Adam on a cosine schedule, init/update vmapped over starts and jitted once per
    schedule (not per call: a new jit would compile again)."""
    schedule = optax.cosine_decay_schedule(learning_rate, rounds, final_learning_rate / learning_rate)
    opt = optax.adam(schedule)
    return jax.jit(jax.vmap(opt.init)), jax.jit(jax.vmap(opt.update))


def _run_adam(problem, scorer, z0, track, config):
    """Projected Adam on the augmented Lagrangian, batched over starts (one evaluation per round)."""
    init, update = _adam(float(config.learning_rate), int(config.rounds),
                         float(config.final_learning_rate))
    alive = np.arange(len(z0))
    z = np.asarray(z0, float)
    state = init(jnp.asarray(z))
    al = None
    for rnd in range(config.rounds):
        if track.on_round is not None:
            track.on_round(rnd)
        ev, pt = _evaluate(problem, scorer, z[alive])
        if al is None:
            al = al_init(len(z0), pt.g.shape[1], config.al)
        sub = ALState(*(a[alive] for a in al))
        x, feas, viol = track.seen(alive, pt.z, ev, pt.s, pt.dg)
        track.accepted(alive, x, ev, feas, viol, sub)
        grad = np.zeros_like(z)
        grad[alive] = np.asarray(al_value_and_grad(-pt.s, -pt.ds, pt.g, pt.dg, sub)[1])
        updates, state = update(jnp.asarray(grad), state, jnp.asarray(z))
        moved = np.asarray(project(optax.apply_updates(jnp.asarray(z), updates)))
        z[alive] = moved[alive]  # pruned starts stay put (arrays keep their size)
        if (rnd + 1) % config.al_every == 0:
            g = np.zeros((len(z0), pt.g.shape[1]))
            g[alive] = pt.g
            al = al_update(al, jnp.asarray(g), config.al)
        if rnd + 1 == config.screen_rounds and len(alive) > config.keep:
            alive = alive[_prune(track, alive, config)]
    return alive


def _check_config(c: SolverConfig):
    if c.method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}; got {c.method!r}")
    for name in ("rounds", "screen_rounds", "keep", "al_every", "memory"):
        if int(getattr(c, name)) < 1:
            raise ValueError(f"{name} must be >= 1; got {getattr(c, name)!r}")
    for name in ("max_step", "learning_rate", "final_learning_rate", "armijo", "min_fraction", "tol"):
        if not getattr(c, name) > 0:
            raise ValueError(f"{name} must be > 0; got {getattr(c, name)!r}")
    if not c.al.rho_growth >= 1 or not c.al.rho0 > 0:
        raise ValueError("al.rho0 must be > 0 and al.rho_growth >= 1")


__all__ = ["SolverConfig", "OptimizationResult", "StartSummary", "optimize", "default_starts",
           "objective_and_gradient", "METHODS", "G_SCALE"]
