"""Robust response design: minimise the worst case (or the 95th percentile) of the dynamic
magnification A*/F (mm/N) over a force range and what the designer does not know, on the exact
damper curve, under the strict no-liftoff constraint.

Uncertain: mu (the problem's mu set), F_D (+/- fd_spread), kn and kt (a factor each way), and
by default the contact history (history="band": the larger A*/F of the gross-slip and the
assembly histories, the cheap upper edge of the history band; history="gross_slip" is half the
curves, but its optimum exploits the gross-slip assumption: issue 35).

The descent sees, per design, one exact curve per (mu, contact corner, history): the corners are
nominal and (kn, kt) scaled by (1/f or f, 1/f or f) on every pair together. The F_D spread costs
nothing: with the scaling law k(psi; s F_D0) = k0(psi / s), the peak equation gives
A*(F; s F_D0) = s A*0(F / s), so the magnification at F and F_D = s F_D0 is the nominal one at F / s:
the worst over F in [F_min, F_max] and s in [1 - d, 1 + d] is the nominal worst over
[F_min / (1 + d), F_max / (1 - d)]. A smooth maximum (temperature tau on log A*/F) drives a
projected descent with forward-mode gradients (IFT through the peak); the result is certified by
`certify`: an independent dense re-evaluation (`jaxdamp.uncertainty`, F_D and per-pair contacts
applied explicitly, 50 forces) plus a per-pair Monte Carlo.
"""

from __future__ import annotations

import functools
import itertools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from jaxdamp import (RESULTS, BladeMode, Contacts, LoadCase, Scenarios, Uncertainty,
                     damper_stiffness_kernel, family_shape, magnification_kernel, peak_distribution,
                     peak_response, sample_scenarios)

from .descent import descend_from_best
from .design import VARIABLES, shape_of_vector
from .problem import Problem, evaluate_shapes, is_feasible, make_problem
from .response_objective import complete_shape

ROBUST_MU_SET = (0.3, 0.4, 0.5, 0.6, 0.7)
OBJECTIVES = ("worst", "q95")
HISTORY_CHOICES = ("gross_slip", "band")
# Earlier optima, for comparison (benchmarks/results/response_optimisation.json): the shipped
# k_Im,BC:worst optimum and the response optimum at 20 N on the interpolated curve.
PREVIOUS_OPTIMA = {"k_Im,BC optimum": (81.08627870410612, 72.3580712759619, 0.028166034292721354, 0.8),
                   "response optimum (20 N, interpolated)": (35.0, 50.44859929975273,
                                                             0.37257150196876127, 0.8)}


class RobustSpec(NamedTuple):
    """What the robust objective covers. force_range_n: (F_min, F_max) in N; fd_spread: relative
    F_D spread; kn_factor, kt_factor: contact stiffness range factor each way; history: "band"
    (default: the larger peak of the gross-slip and assembly histories, so that a design is not
    tuned to one history) or "gross_slip"; objective: "worst" or "q95"; n_forces: forces in the
    descent; temperature: of the smooth maximum on log A*/F; n_samples: Monte Carlo samples of
    "q95"."""

    force_range_n: tuple = (2.0, 20.0)
    fd_spread: float = 0.2
    kn_factor: float = 2.0
    kt_factor: float = 2.0
    history: str = "band"
    objective: str = "worst"
    n_forces: int = 6
    temperature: float = 0.02
    n_samples: int = 64


def validate_spec(spec: RobustSpec, histories=HISTORY_CHOICES) -> RobustSpec:
    """ValueError naming the CLI flag and its valid range (histories: those the caller runs)."""
    f_min, f_max = (float(x) for x in spec.force_range_n)
    if not 0.0 < f_min <= f_max:
        raise ValueError(f"--force-n must be FMIN:FMAX with 0 < FMIN <= FMAX N; got {f_min:g}:{f_max:g}")
    if not 0.0 <= spec.fd_spread < 1.0:
        raise ValueError(f"--fd-spread must be in [0, 1); got {spec.fd_spread:g}")
    for flag, f in (("--kn-range", spec.kn_factor), ("--kt-range", spec.kt_factor)):
        if not 1.0 <= f <= 100.0:
            raise ValueError(f"{flag} must be a factor in [1, 100]; got {f:g}")
    if spec.history not in histories:
        raise ValueError(f"--history must be one of {', '.join(histories)}; got {spec.history!r}")
    if spec.objective not in OBJECTIVES:
        raise ValueError(f"--objective must be peak:worst or peak:q95; got peak:{spec.objective}")
    if int(spec.n_forces) < 1 or int(spec.n_samples) < 2 or not spec.temperature > 0:
        raise ValueError("n_forces >= 1, n_samples >= 2 and temperature > 0 are required")
    return spec


def descent_forces(spec: RobustSpec) -> np.ndarray:
    """The nominal-F_D forces (N) that cover the force range under the F_D spread (module doc)."""
    f_min, f_max = spec.force_range_n
    return np.geomspace(f_min / (1.0 + spec.fd_spread), f_max / (1.0 - spec.fd_spread),
                        int(spec.n_forces))


def contact_corners(spec: RobustSpec) -> np.ndarray:
    """(5, 2) kn and kt factors: nominal, then every pair of (1/f, f)."""
    fn, ft = spec.kn_factor, spec.kt_factor
    return np.array([(1.0, 1.0)] + [(a, b) for a in (1 / fn, fn) for b in (1 / ft, ft)])


def _initials(history: str):
    return ("gross_slip", "assembly") if history == "band" else ("gross_slip",)


def _worst_scores(v, history, mus, corners, forces, mode, kn, kt, load):
    """log A*/F of every (history, mu, corner, force) and the worst damper status."""
    load = LoadCase(*load)

    def one(mu, c, initial):
        # Traced (vmapped) inputs: the unchecked kernel; the spec was checked once by the caller.
        d = damper_stiffness_kernel(shape_of_vector(v), mu, Contacts(kn * c[0], kt * c[1]), load, "exact",
                                    initial=initial)
        return jnp.log(peak_response(d, mode, forces).peak_amplitude_mm / forces), d.status

    outs = [jax.vmap(lambda mu: jax.vmap(lambda c: one(mu, c, h))(corners))(mus)
            for h in _initials(history)]
    return (jnp.concatenate([o[0].ravel() for o in outs]),
            RESULTS.worst(jnp.stack([o[1] for o in outs])))


def _q95_scores(v, history, scenarios, forces, mode, load):
    """log of the 95th percentile of A*/F over the samples, per force; worst sample status."""
    load = LoadCase(*load)
    outs = [jax.vmap(lambda s: magnification_kernel(shape_of_vector(v), s, load, mode, forces, h))(scenarios)
            for h in _initials(history)]
    m = jnp.max(jnp.stack([o[0] for o in outs]), axis=0)  # history band: the upper edge
    return (jnp.log(jnp.quantile(m, 0.95, axis=0)),
            RESULTS.worst(jnp.stack([o[1] for o in outs])))


def smooth_objective(v, objective, history, temperature, *args):
    """(smooth max in mm/N, (hard max in mm/N, status)) of one design vector v: the log-sum-exp
    of the scenarios' log magnifications at `temperature`, which bounds the hard maximum from
    above by at most temperature * log(number of scores). Traced as it is: jit it, or use
    objective_programs."""
    scores, status = (_worst_scores if objective == "worst" else _q95_scores)(v, history, *args)
    smooth = temperature * jax.nn.logsumexp(scores / temperature)
    return jnp.exp(smooth), (jnp.exp(jnp.max(scores)), status)


def _value(v, objective, history, temperature, *args):
    return smooth_objective(v, objective, history, temperature, *args)[1]


@functools.cache
def objective_programs(objective: str, history: str):
    """(batched values, gradient of the smooth maximum) compiled once per objective and history."""
    def value(v, temperature, *args):
        return smooth_objective(v, objective, history, temperature, *args)[1]

    def smooth(v, temperature, *args):
        return smooth_objective(v, objective, history, temperature, *args)

    return (jax.jit(jax.vmap(value, (0,) + (None,) * (8 if objective == "worst" else 5))),
            jax.jit(jax.jacfwd(smooth, has_aux=True)))


def objective_args(problem: Problem, spec: RobustSpec, mode: BladeMode = BladeMode(),
                   key=None) -> tuple:
    """The shared arrays of the objective (scenario set, forces, mode, contacts, load)."""
    forces = jnp.asarray(descent_forces(spec))
    mode = BladeMode(*(jnp.asarray(x, float) for x in mode))
    load = tuple(jnp.asarray(x, float) for x in problem.load)
    if spec.objective == "worst":
        return (jnp.asarray(problem.mus), jnp.asarray(contact_corners(spec)), forces, mode,
                jnp.asarray(problem.kn), jnp.asarray(problem.kt), load)
    # q95: common random numbers (one fixed sample set for every design), F_D sampled explicitly
    u = Uncertainty(min(problem.mus), max(problem.mus), spec.fd_spread, spec.kn_factor,
                    spec.kt_factor)
    scen = sample_scenarios(jax.random.PRNGKey(0) if key is None else key, int(spec.n_samples), u,
                            Contacts(problem.kn, problem.kt), LoadCase(*problem.load))
    forces = jnp.asarray(np.geomspace(*spec.force_range_n, int(spec.n_forces)))
    return scen, forces, mode, load


def robust_values(V, problem: Problem, spec: RobustSpec, args) -> tuple[np.ndarray, np.ndarray]:
    """(B,) hard maximum of the objective (mm/N; inf where infeasible) and (B,) feasibility (the
    optimiser's margins at every mu and an ok damper status in every scenario)."""
    V = np.atleast_2d(np.asarray(V, float))
    run = objective_programs(spec.objective, spec.history)[0]
    vals, status = (np.asarray(x) for x in run(jnp.asarray(V), spec.temperature, *args))
    feasible = np.asarray(is_feasible(evaluate_shapes(problem, V))) & (status == 0)
    return np.where(feasible, vals, np.inf), feasible


class CertifiedDesign(NamedTuple):
    """A design re-evaluated independently (see `certify`). Magnifications in mm/N.

    worst_dense: max over the dense grid and 50 forces; worst_mc, q95_mc: over the per-pair Monte
    Carlo samples (max over forces of the worst / of the 95th percentile); band_mm_per_n: (2, 50)
    min and max over the dense grid per force; feasible: margins and status everywhere; reason:
    why not ("margins" where the optimiser's no-liftoff margins fail, else the damper statuses that
    are not ok, with their counts among the scenarios), "ok" when feasible."""

    name: str
    shape: tuple
    feasible: bool
    worst_dense: float | None
    worst_mc: float | None
    q95_mc: float | None
    force_n: tuple
    band_mm_per_n: tuple
    scenarios: int
    reason: str = "ok"
    status: str = "ok"  # RESULTS name: the worst damper status, or liftoff (margins); ok if certified


def dense_scenarios(problem: Problem, spec: RobustSpec, n_mu: int = 9, n_k: int = 3,
                    n_fd: int = 3) -> Scenarios:
    """The certification grid: n_mu mu over the set's range, n_k kn and n_k kt factors (log
    spaced, every pair together), n_fd F_D values across the spread."""
    mus = np.linspace(min(problem.mus), max(problem.mus), n_mu)
    kn = np.geomspace(1 / spec.kn_factor, spec.kn_factor, n_k)
    kt = np.geomspace(1 / spec.kt_factor, spec.kt_factor, n_k)
    fd = problem.load[0] * np.linspace(1 - spec.fd_spread, 1 + spec.fd_spread, n_fd)
    grid = np.array(list(itertools.product(mus, kn, kt, fd)))
    ones = np.ones((len(grid), 3))
    return Scenarios(jnp.asarray(grid[:, 0]), jnp.asarray(problem.kn * grid[:, 1:2] * ones),
                     jnp.asarray(problem.kt * grid[:, 2:3] * ones), jnp.asarray(grid[:, 3]))


def certify(name: str, v, problem: Problem, spec: RobustSpec, mode: BladeMode = BladeMode(), *,
            n_forces: int = 50, n_mc: int = 256, dense: Scenarios | None = None,
            progress=None) -> CertifiedDesign:
    """Independent re-evaluation of one complete shape vector v: the exact curve per scenario with
    F_D and the contacts applied explicitly (no scaling law), at n_forces forces over the range;
    the dense grid (`dense_scenarios`) and n_mc per-pair Monte Carlo samples."""
    v = np.asarray(v, float)
    forces = np.geomspace(*spec.force_range_n, n_forces)
    feasible = bool(np.asarray(is_feasible(evaluate_shapes(problem, v[None])))[0])
    dense = dense_scenarios(problem, spec) if dense is None else dense
    hist = "band" if spec.history == "band" else "gross_slip"
    shape = shape_of_vector(v)
    load = LoadCase(*problem.load)
    d = peak_distribution(shape, dense, mode, forces, load, history=hist, progress=progress)
    u = Uncertainty(min(problem.mus), max(problem.mus), spec.fd_spread, spec.kn_factor,
                    spec.kt_factor)
    mc_scen = sample_scenarios(jax.random.PRNGKey(1), n_mc, u, Contacts(problem.kn, problem.kt), load)
    mc = peak_distribution(shape, mc_scen, mode, forces, load, history=hist, levels=(0.95,),
                           progress=progress)
    ok = feasible and d.n_ok == len(dense.mu) and mc.n_ok == n_mc
    statuses = np.concatenate([d.status, mc.status])
    reason = "ok" if ok else uncertified_reason(feasible, statuses)
    band = (np.nanmin(d.magnification, axis=0), np.nanmax(d.magnification, axis=0))
    return CertifiedDesign(name, tuple(map(float, v)), ok,
                           float(np.max(d.worst)) if ok else None,
                           float(np.max(mc.worst)) if ok else None,
                           float(np.max(mc.quantiles[0])) if ok else None,
                           tuple(map(float, forces)), tuple(tuple(map(float, b)) for b in band),
                           len(dense.mu), reason,
                           "ok" if ok else uncertified_status(feasible, statuses))


def uncertified_status(margins_ok: bool, status) -> str:
    """The RESULTS name of a certification: the most severe damper status among the scenarios
    (jaxdamp.status.SEVERITY); liftoff where those are ok but the no-liftoff margins fail."""
    worst = RESULTS(int(RESULTS.worst(np.asarray(status)))) if np.size(status) else RESULTS.ok
    return (RESULTS.liftoff if worst == RESULTS.ok and not margins_ok else worst).name


def uncertified_reason(margins_ok: bool, status) -> str:
    """Why a design is not certified, in words: the margins, and every damper status that is not
    ok with how many scenarios gave it (a non-converged cycle is not a liftoff)."""
    status = np.asarray(status)
    parts = [] if margins_ok else ["margins (no-liftoff constraints at the mu set)"]
    names, counts = np.unique(status[status != RESULTS.ok], return_counts=True)
    parts += [f"{RESULTS(int(c)).name} in {int(n)} of {status.size} scenarios"
              for c, n in zip(names, counts)]
    return "; ".join(parts) or "ok"


class RobustOptimum(NamedTuple):
    best: CertifiedDesign
    references: list  # CertifiedDesign of 60sym and PREVIOUS_OPTIMA
    spec: RobustSpec
    objective_value: float  # the descent's (hard) objective at the optimum, mm/N
    grid_evaluations: int
    descent_evaluations: int
    history: list  # (start, step, objective) of accepted steps


def reference_shapes() -> dict:
    s = family_shape("60sym")
    return {"60sym": (s.theta_l, s.theta_r, s.br_over_hr, s.bl2_over_hl), **PREVIOUS_OPTIMA}


def optimize_robust(problem: Problem | None = None, spec: RobustSpec = RobustSpec(),
                    mode: BladeMode = BladeMode(), *, grid_points: int = 3, starts: int = 2,
                    steps: int = 10, certify_references: bool = True,
                    progress=None) -> RobustOptimum:
    """Minimise the robust objective (module doc): a grid over the free variables' unit box, then
    projected normalised gradient steps on the smooth maximum from the best feasible grid points,
    each accepted only when feasible and lowering the hard maximum (the constraint is never
    penalised); then `certify` the optimum and the references. progress(n) after each stage."""
    problem = make_problem(mus=ROBUST_MU_SET) if problem is None else problem
    spec = validate_spec(spec)
    tick = progress or (lambda n: None)
    args = objective_args(problem, spec, mode)
    grad = objective_programs(spec.objective, spec.history)[1]
    sp = problem.space
    Z = np.array(list(itertools.product(*[np.linspace(0.0, 1.0, grid_points)] * sp.dim)))
    V = np.stack([complete_shape(problem, z) for z in Z])
    vals = np.concatenate([robust_values(V[i:i + 8], problem, spec, args)[0]
                           for i in range(0, len(V), 8)])
    tick(1)
    span = np.asarray(sp.upper) - np.asarray(sp.lower)
    free_idx = [VARIABLES.index(n) for n in sp.free]

    def gradient(z):
        g, _ = grad(jnp.asarray(complete_shape(problem, z)), spec.temperature, *args)
        return np.asarray(g)[free_idx] * span

    def evaluate(z):  # the true (hard) maximum decides, not the smooth one the gradient is of
        vn, fn = robust_values(complete_shape(problem, z), problem, spec, args)
        return float(vn[0]), bool(fn[0])

    best_z, best_val, n_desc, hist = descend_from_best(
        Z, vals, gradient, evaluate, starts=starts, steps=steps, step_size=0.1, tries=4,
        tick=tick)
    if best_z is None:
        raise ValueError("no feasible design on the grid: widen the bounds or the margins")
    best = certify("robust optimum", complete_shape(problem, best_z), problem, spec, mode)
    tick(1)
    refs = []
    if certify_references:
        refs = [certify(n, v, problem, spec, mode) for n, v in reference_shapes().items()]
        tick(1)
    return RobustOptimum(best, refs, spec, best_val, len(Z), n_desc, hist)


__all__ = ["RobustSpec", "CertifiedDesign", "RobustOptimum", "ROBUST_MU_SET", "PREVIOUS_OPTIMA",
           "OBJECTIVES", "HISTORY_CHOICES", "validate_spec", "descent_forces", "objective_args",
           "robust_values", "contact_corners", "dense_scenarios", "certify", "uncertified_reason",
           "reference_shapes", "optimize_robust"]
