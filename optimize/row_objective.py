"""Robust design over a blade row: minimise the worst peak magnification A*/F (mm/N) over the
engine orders a user names (each on its own nodal diameter's mode and platform path, from a
modal file: `jaxdamp.row_response`), over what the designer does not know and over the contact
history, under the strict no-liftoff constraint (the paper's full-slip design check at every mu).

The descent sees, per design, one row of peaks per (history, mu, contact corner): histories
gross slip and assembly (history="band", the default: the larger of the two, as the in-phase
robust objective; "assembly" alone is half the cost); mu the problem's set; contact corners the
nominal kn, kt only (corners="nominal", the default: each corner costs a whole row) or also
(kn, kt) scaled by (1/f or f, 1/f or f) together ("all"). The F_D spread costs nothing: the
quasi-static contact problem is homogeneous in F_D and the amplitude on every path, so that
A*(F; s F_D) = s A*(F / s) (`robust_objective`'s law, here per engine order).

Each row is one call of `jaxdamp.row_response`, the public function the CLI's `response --modes`
runs (values only: the programs that command saves, compiled once per history). The descent's
direction is the gradient of the smooth maximum, from `jaxdamp.row_gradient` (each peak's
derivative with respect to the shape by the implicit function theorem at the roots the values
found; its derivative program compiles once per history); a step is kept only where the design is
feasible and the smooth maximum falls (`descent.feasible_descent`): the objective the descent
minimises is the smooth maximum itself, whose gradient it follows (the hard maximum is flat
wherever one stuck peak binds, so that steps along a smooth gradient were rejected there). The result is certified by
`certify_row`: every engine order under each history separately and their band, over a grid of
mu, kn and kt factors and F_D applied explicitly.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np
import optax

from jaxdamp import (RESULTS, Contacts, LoadCase, ModalFamily, nodal_scene, row_gradient,
                     row_response)

from .descent import descend_from_best
from .design import VARIABLES, in_bounds, shape_of_vector, to_unit
from .problem import Problem, evaluate_shapes, is_feasible, make_problem
from .response_objective import complete_shape
from .robust_objective import (ROBUST_MU_SET, RobustSpec, contact_corners, descent_forces,
                               reference_shapes, uncertified_reason, uncertified_status,
                               validate_spec)

ROW_HISTORIES = ("assembly", "band")
CORNER_CHOICES = ("nominal", "all")
HISTORY_NAMES = ("gross_slip", "assembly")
DIRECTIONS = ("lbfgs", "gradient")  # the descent's direction (`optimize_row`)
LBFGS_MEMORY = 4  # curvature pairs: a descent of a few steps in four variables
FORCE_CHUNK = 4  # forces per row call: the row's force bucket, so one program serves every call
# The in-phase robust optimum (benchmarks/results/robust_optimisation_band.json): how a design
# tuned to nodal diameter 0 of the illustrative blade fares across a real row.
IN_PHASE_ROBUST_OPTIMUM = (42.59891282213617, 52.95829312005082, 0.3988034770924406,
                           0.8876839281573497)

__all__ = ["RowTask", "RowCertified", "RowOptimum", "ROW_HISTORIES", "CORNER_CHOICES",
           "FORCE_CHUNK", "DIRECTIONS", "LBFGS_MEMORY", "IN_PHASE_ROBUST_OPTIMUM",
           "row_magnification", "row_values", "certify_row", "optimize_row",
           "row_reference_shapes"]


class RowTask(NamedTuple):
    """The row a design is judged on: the modal family, the engine orders and the damper's size
    (h_l_mm, mm)."""

    family: ModalFamily
    engine_orders: tuple
    h_l_mm: float


def row_magnification(v, task: RowTask, mu, contacts: Contacts, load: LoadCase, forces,
                      initial: str, gradient: bool = False):
    """(A*/F (m, n_f) mm/N, status (m, n_f)) of one complete shape vector v over the row at the
    forces (N per blade), from the history `initial`: `row_response` in chunks of FORCE_CHUNK
    forces. gradient: also d(A*/F)/dv (m, n_f, 4), by `row_gradient` (zero where a peak is not
    valid)."""
    forces = np.asarray(forces, float).reshape(-1)
    mags, stats, grads = [], [], []
    shape = shape_of_vector(np.asarray(v, float))
    for i in range(0, forces.size, FORCE_CHUNK):
        f = forces[i:i + FORCE_CHUNK]
        kw = dict(modes=task.family, engine_orders=list(task.engine_orders), force_n=f,
                  h_l_mm=task.h_l_mm, initial=initial)
        if gradient:
            got = row_gradient(shape, mu, contacts, load, **kw)
            row = got.row
            grads.append(got.d_peak_mm[..., :len(VARIABLES)] / f[None, :, None])
        else:
            row = row_response(shape, mu, contacts, load, **kw)
        mags.append(np.asarray(row.peaks.peak_amplitude_mm) / f[None, :])
        stats.append(np.asarray(row.status))
    out = np.concatenate(mags, axis=1), np.concatenate(stats, axis=1)
    return (*out, np.concatenate(grads, axis=1)) if gradient else out


def _initials(history: str):
    return HISTORY_NAMES if history == "band" else ("assembly",)


def _counted(status, initial: str):
    """(valid, usable) masks: a valid peak counts; a gross-slip history that does not exist on a
    path (`unreachable`: a pad opens before every pad slips) is no failure, there is just no such
    history there; anything else (liftoff, not_converged, a peak outside the small-rotation model:
    large_rotation, ...) makes the design infeasible."""
    valid = np.asarray(RESULTS.valid(status))
    missing = (initial == "gross_slip") & (np.asarray(status) == RESULTS.unreachable)
    return valid, valid | missing


def row_values(V, problem: Problem, spec: RobustSpec, task: RowTask, corners: str = "nominal",
               gradient: bool = False):
    """(smooth, hard, feasible) per complete shape vector of V (B, 4): the smooth maximum (the
    log-sum-exp of log A*/F at spec.temperature) and the hard maximum of A*/F (mm/N; inf where
    infeasible), and feasibility (margins at every mu of the set and a valid peak in every
    scenario: liftoff, non-convergence or a singular cycle anywhere is infeasible; a damper
    stuck at a peak is a valid, bad, peak; a gross-slip history that does not exist on a path is
    left out there, `_counted`). gradient: also d log(smooth) / dv (B, 4) (zero where
    infeasible): the softmax of the scores weighs each peak's d log(A*/F) / dv."""
    V = np.atleast_2d(np.asarray(V, float))
    margins = np.asarray(is_feasible(evaluate_shapes(problem, V)))
    c = contact_corners(spec) if corners == "all" else np.array([(1.0, 1.0)])
    forces = descent_forces(spec)
    load = LoadCase(*problem.load)
    smooth, hard, feasible = (np.full(len(V), np.inf), np.full(len(V), np.inf),
                              np.zeros(len(V), bool))
    d_log_smooth = np.zeros(V.shape)
    for b, v in enumerate(V):
        if not margins[b]:  # the design check fails: no row is run
            continue
        scores, slopes, ok = [], [], True
        for initial, mu, (fn, ft) in itertools.product(_initials(spec.history), problem.mus, c):
            got = row_magnification(v, task, mu, Contacts(problem.kn * fn, problem.kt * ft),
                                    load, forces, initial, gradient)
            mag, status = got[:2]
            valid, usable = _counted(status, initial)
            ok &= bool(np.all(usable))
            scores.append(np.log(mag[valid]))
            if gradient:
                slopes.append(got[2][valid] / mag[valid][:, None])  # d log(A*/F) / dv
            if not ok:
                break
        if ok:
            s = np.concatenate(scores)
            t = spec.temperature
            smooth[b] = float(np.exp(t * np.log(np.sum(np.exp((s - s.max()) / t))) + s.max()))
            hard[b], feasible[b] = float(np.exp(s.max())), True
            if gradient:
                w = np.exp((s - s.max()) / t)
                d_log_smooth[b] = (w / w.sum()) @ np.concatenate(slopes)
    return (smooth, hard, feasible, d_log_smooth) if gradient else (smooth, hard, feasible)


class RowCertified(NamedTuple):
    """A design re-evaluated across the row (`certify_row`). worst_by_history: {history: (m,)
    worst A*/F per engine order, mm/N, over the grid and forces (None where the history exists in
    no scenario)}; worst_band: (m,) the larger of the two; worst: the band's maximum over the row;
    worst_engine_order: where it is; feasible: margins and a valid peak everywhere (a gross-slip
    history that does not exist is no failure); reason: why not ("ok" when feasible);
    no_gross_slip: (m,) how many (scenario, force) pairs of each engine order have no gross-slip
    state (`RESULTS.unreachable`); worst_scenario: where the worst peak binds (mu, the kn and kt
    factors, F_D in N, the force in N, the history; the grid's first where several tie, as a
    stuck damper's peak does in every scenario where it sticks), None where not certified."""

    name: str
    shape: tuple
    feasible: bool
    engine_order: tuple
    worst_by_history: dict
    worst_band: tuple
    worst: float | None
    worst_engine_order: int | None
    scenarios: int
    force_n: tuple
    reason: str = "ok"
    no_gross_slip: tuple = ()
    status: str = "ok"  # RESULTS name: the worst damper status, or liftoff (margins); ok if certified
    worst_scenario: dict | None = None


def certify_row(name: str, v, problem: Problem, spec: RobustSpec, task: RowTask, *,
                n_forces: int = 4, n_mu: int = 3, n_k: int = 3, n_fd: int = 3,
                progress=None, on_scenario=None) -> RowCertified:
    """Independent re-evaluation of one complete shape vector v across the row: every engine
    order, from gross slip and from assembly separately, over n_mu mu of the set's range, n_k kn
    and n_k kt factors (every pair) and n_fd F_D values applied explicitly (no scaling law), at
    n_forces forces over the range (one point on an axis is its middle: the nominal value).
    progress(1) per scenario. on_scenario(scenario, rows): after each scenario, with scenario =
    {mu, kn_factor, kt_factor, fd_n, contacts, load} and rows = {history: (A*/F (m, n_f) mm/N,
    status (m, n_f))}: what a caller needs beyond the worst (percentiles, the band)."""
    v = np.asarray(v, float)
    margins_ok = bool(np.asarray(is_feasible(evaluate_shapes(problem, v[None])))[0])

    def axis(lo, hi, n, spacing=np.linspace):
        return spacing(lo, hi, n) if n > 1 else np.array([spacing(lo, hi, 3)[1]])

    grid = list(itertools.product(
        axis(min(problem.mus), max(problem.mus), n_mu),
        axis(1 / spec.kn_factor, spec.kn_factor, n_k, np.geomspace),
        axis(1 / spec.kt_factor, spec.kt_factor, n_k, np.geomspace),
        problem.load[0] * axis(1 - spec.fd_spread, 1 + spec.fd_spread, n_fd)))
    forces = np.geomspace(*spec.force_range_n, n_forces)
    m = len(task.engine_orders)
    worst = {h: np.full(m, -np.inf) for h in HISTORY_NAMES}
    statuses, missing = [], np.zeros(m, int)
    binding, top = None, -np.inf
    for mu, fn, ft, f_d in grid:
        load = LoadCase(f_d, *problem.load[1:])
        contacts = Contacts(problem.kn * fn, problem.kt * ft)
        rows = {}
        for h in HISTORY_NAMES:
            mag, status = rows[h] = row_magnification(v, task, mu, contacts, load, forces, h)
            valid, usable = _counted(status, h)
            statuses.append(np.where(usable, RESULTS.ok, status).ravel())
            missing += np.sum(usable & ~valid, axis=1)
            scored = np.where(valid, mag, -np.inf)
            worst[h] = np.maximum(worst[h], np.max(scored, axis=1))
            if scored.max() > top:
                top = float(scored.max())
                j = np.unravel_index(int(np.argmax(scored)), scored.shape)[1]
                binding = {"mu": float(mu), "kn_factor": float(fn), "kt_factor": float(ft),
                           "fd_n": float(f_d), "force_n": float(forces[j]), "history": h}
        if on_scenario:
            on_scenario({"mu": float(mu), "kn_factor": float(fn), "kt_factor": float(ft),
                         "fd_n": float(f_d), "contacts": contacts, "load": load}, rows)
        if progress:
            progress(1)
    status = np.concatenate(statuses)
    ok = margins_ok and bool(np.all(status == RESULTS.ok))
    band = np.maximum(worst["gross_slip"], worst["assembly"])
    w = int(np.argmax(band))
    return RowCertified(name, tuple(map(float, v)), ok, tuple(int(e) for e in task.engine_orders),
                        {h: _numbers(worst[h]) for h in HISTORY_NAMES}, _numbers(band), float(band[w]) if ok else None,
                        int(task.engine_orders[w]) if ok else None, len(grid),
                        tuple(map(float, forces)),
                        "ok" if ok else uncertified_reason(margins_ok, status),
                        tuple(int(n) for n in missing),
                        "ok" if ok else uncertified_status(margins_ok, status),
                        binding if ok else None)


def _numbers(values) -> tuple:
    """Floats, None where there is no number (JSON has no infinities)."""
    return tuple(float(x) if np.isfinite(x) else None for x in np.asarray(values, float))


def _reference_starts(problem: Problem) -> list:
    """Unit-box points of the reference shapes that lie in the problem's design space (its fixed
    variables equal, its free ones in bounds): known designs compete with the grid as starts (the
    row's worst peak is flat wherever the damper sticks, so that a coarse grid may see no slope)."""
    sp = problem.space
    free = [VARIABLES.index(n) for n in sp.free]
    out = []
    for v in row_reference_shapes().values():
        v = np.asarray(v, float)
        fixed_ok = all(abs(v[VARIABLES.index(n)] - float(x)) <= 1e-9 for n, x in dict(sp.fixed).items())
        if fixed_ok and in_bounds(sp, v[free]):
            out.append(np.asarray(to_unit(sp, v[free])))
    return out


def row_reference_shapes() -> dict:
    """60sym and the in-phase robust optimum: what the row optimum is compared with."""
    return {"60sym": reference_shapes()["60sym"],
            "in-phase robust optimum (band)": IN_PHASE_ROBUST_OPTIMUM}


class RowOptimum(NamedTuple):
    best: RowCertified
    references: list  # RowCertified of row_reference_shapes()
    spec: RobustSpec
    corners: str
    objective_value: float  # the descent's smooth maximum at the optimum, mm/N
    grid_evaluations: int
    descent_evaluations: int
    history: list  # (start, step, objective) of accepted steps
    gradient_evaluations: int = 0  # row_gradient calls of the descent (each: every row once)


def optimize_row(family: ModalFamily, engine_orders, h_l_mm: float, problem: Problem | None = None,
                 spec: RobustSpec = RobustSpec(), *, corners: str = "nominal",
                 grid_points: int = 3, starts: int = 1, steps: int = 6,
                 certify_references: bool = True, certify_options: dict | None = None,
                 progress=None, direction: str = "lbfgs") -> RowOptimum:
    """Minimise the worst A*/F over the row (module doc), as its smooth maximum: a grid over the
    free variables' unit box and the reference shapes that lie in the design space, then feasible
    descent steps from the best of them along the smooth maximum's gradient (`row_gradient`):
    direction "lbfgs" (default) the quasi-Newton direction of optax's L-BFGS
    (`optax.scale_by_lbfgs`, its curvature pairs the accepted steps), "gradient" the gradient's;
    then `certify_row` of the optimum and the references. Inputs are checked
    (ValueError naming the flag or parameter) before any row is run. progress(n) per stage."""
    problem = make_problem(mus=ROBUST_MU_SET) if problem is None else problem
    spec = validate_spec(spec, ROW_HISTORIES)
    if spec.objective != "worst":
        raise ValueError(f"--objective must be peak:worst with --modes; got peak:{spec.objective}")
    if corners not in CORNER_CHOICES:
        raise ValueError(f"corners must be one of {', '.join(CORNER_CHOICES)}; got {corners!r}")
    if direction not in DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(DIRECTIONS)}; got {direction!r}")
    task = RowTask(family, tuple(int(e) for e in engine_orders), float(h_l_mm))
    # Check the row once (family, engine orders, h_L) before the grid: one line, no compiling.
    for e in task.engine_orders:
        nodal_scene(family, e, float(problem.load[1]), task.h_l_mm)
    tick = progress or (lambda n: None)
    sp = problem.space
    Z = np.array(list(itertools.product(*[np.linspace(0.0, 1.0, grid_points)] * sp.dim)))
    Z = np.vstack([Z] + [z[None] for z in _reference_starts(problem)])
    vals = row_values(np.stack([complete_shape(problem, z) for z in Z]), problem, spec, task,
                      corners)[0]
    tick(1)

    free = [VARIABLES.index(n) for n in sp.free]
    span = np.asarray(sp.upper) - np.asarray(sp.lower)
    gradients = []

    def gradient(z):
        # The smooth maximum's log, differentiated: by the shape, then into the unit box.
        gradients.append(z)
        g = row_values(complete_shape(problem, z), problem, spec, task, corners, gradient=True)[3]
        g = g[0, free] * span
        return np.where(np.isfinite(g), g, 0.0)

    def evaluate(z):
        smooth, _, feasible = row_values(complete_shape(problem, z), problem, spec, task, corners)
        return float(smooth[0]), bool(feasible[0])

    best_z, best_val, n_desc, hist = descend_from_best(
        Z, vals, gradient, evaluate, starts=starts, steps=steps, step_size=0.1, tries=3,
        min_step=1e-3, tick=tick,
        transform=optax.scale_by_lbfgs(memory_size=LBFGS_MEMORY) if direction == "lbfgs" else None)
    if best_z is None:
        raise ValueError("no feasible design on the grid: widen the bounds or the margins")
    opts = certify_options or {}
    best = certify_row("row robust optimum", complete_shape(problem, best_z), problem, spec, task,
                       **opts)
    tick(1)
    refs = []
    if certify_references:
        refs = [certify_row(n, v, problem, spec, task, **opts)
                for n, v in row_reference_shapes().items()]
        tick(1)
    return RowOptimum(best, refs, spec, corners, best_val, len(Z), n_desc, hist, len(gradients))
