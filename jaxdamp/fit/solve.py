"""The loop fit itself: the parameter vector (log mu, log kn, log kt, shared per FitSpec, and the
loops' offsets), the residuals against the model's exact loops, the two-stage Levenberg-Marquardt
solve (optimistix), identifiability and confidence intervals (the module docstring of
`jaxdamp.fit` says how), and `fit_loops` / `fit_problem`, which check, analyse and stack the
loops first."""

from __future__ import annotations

import functools
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import check_int, check_range, require_x64
from ..amplitude import INITIAL_STATES, amplitude_kernel
from ..geometry import CONTACT_NAMES, DamperShape, validate_shape
from ..params import (VALIDATED_STIFFNESS_OVER_FD_PER_MM, Contacts, LoadCase, check_contacts_and_load,
                      check_one_shape, check_param, validate_load)
from ..response.scene import Scene
from ..status import RESULTS
from ..runtime import padded_size, run_program, side_by_side
from .loops import (COMPONENTS, ContactLoop, LoopError, MomentLoop, analyse_loop, loop_pair,
                    loop_direction_error)
from .model import contact_loop_force, loop_model_moment
from .result import LoopFit, identify, z_value

__all__ = ["FitSpec", "FitProblem", "fit_loops", "fit_problem", "fit_residuals",
           "DEFAULT_START", "GROUPINGS", "K_REF", "ROBUST_DELTA"]


# Generic start (as `jaxdamp calibrate`'s: a round order of magnitude, not the answer): mu = 0.5,
# kn = 1e4 N/mm, kt = kn / 2.
DEFAULT_START = {"mu": 0.5, "kn": 1.0e4, "kt": 5.0e3}
K_REF = 1.0e4  # N/mm, the stiffness of log-parameter 0
GROUPINGS = {"mu": ("shared", "contact"), "kn": ("shared", "side", "contact"),
             "kt": ("shared", "side", "contact")}
_INDEX = {"shared": (0, 0, 0), "side": (0, 1, 1), "contact": (0, 1, 2)}
_LABELS = {"shared": ("",), "side": ("R1", "L"), "contact": CONTACT_NAMES}
ROBUST_DELTA = 2.0  # pseudo-Huber threshold, in robust standard deviations of the residuals


class FitSpec(NamedTuple):
    """How each contact parameter is shared: mu 'shared' | 'contact'; kn, kt 'shared' | 'side'
    (R1 | L1 = L2) | 'contact'."""

    mu: str = "shared"
    kn: str = "shared"
    kt: str = "shared"

    def sizes(self) -> tuple[int, int, int]:
        return tuple(len(_LABELS[g]) for g in self)

    def names(self) -> list[str]:
        out = []
        for p, g in zip(("mu", "kn", "kt"), self):
            out += [p if not lab else f"{p}_{lab}" for lab in _LABELS[g]]
        return out



def _expand(theta, spec: FitSpec):
    """(mu, kn (3,), kt (3,), offsets) from the parameter vector."""
    n_mu, n_kn, n_kt = spec.sizes()
    lmu = theta[:n_mu]
    lkn = theta[n_mu:n_mu + n_kn]
    lkt = theta[n_mu + n_kn:n_mu + n_kn + n_kt]
    mu = jnp.exp(lmu)[0] if spec.mu == "shared" else jnp.exp(lmu)
    kn = K_REF * jnp.exp(lkn[jnp.asarray(_INDEX[spec.kn])])
    kt = K_REF * jnp.exp(lkt[jnp.asarray(_INDEX[spec.kt])])
    return mu, kn, kt, theta[n_mu + n_kn + n_kt:]


class _Data(NamedTuple):
    """The loops stacked and padded (loops, samples)."""

    psi_a: jnp.ndarray  # (L,)
    forward: jnp.ndarray  # (L, n) bool
    u: jnp.ndarray  # (L, n)
    moment: jnp.ndarray  # (L, n), in units of scale
    mask: jnp.ndarray  # (L, n) 1.0 for a sample, 0.0 for padding
    scale: jnp.ndarray  # (L,) each loop's force scale (N mm for moment loops, N for contact loops)
    kind: jnp.ndarray  # (L,) int: 0 moment loop, 1 tangential contact loop, 2 normal contact loop
    contact: jnp.ndarray  # (L,) int: the contact of a contact loop (0 R1, 1 L1, 2 L2)
    x: jnp.ndarray  # (L, n) contact loops: displacement from the measured centre, mm


def _model(theta, shape, load, data: _Data, spec: FitSpec, history: str, loop: str = "auto"):
    """(model moment or contact force (L, n) in units of each loop's scale, offsets, cycle statuses
    (L,), per loop: False for a tangential contact loop whose model displacement is not monotone
    along a half (then its force is not a function of the displacement there))."""
    mu, kn, kt, off = _expand(theta, spec)
    contacts = Contacts(kn, kt)

    def one(psi_a, fwd, u, kind, contact, x):
        ac = amplitude_kernel(shape, mu, contacts, load, psi_a, initial=history, loop=loop)
        m = loop_model_moment(ac, fwd, u)
        # contact loops: `forward` holds "the measured displacement decreases on this half"
        f, mono = contact_loop_force(ac, contact, kind == 2, fwd, x)
        return jnp.where(kind == 0, m, f * load.F_D), ac.status, mono | (kind != 1)

    m, status, mono = jax.vmap(one)(data.psi_a, data.forward, data.u, data.kind, data.contact, data.x)
    return m / data.scale[:, None], off, status, mono


@functools.cache
def _model_program(spec: FitSpec, history: str):
    """`_model` as a jitted function of arrays (theta, shape, load, data), its options constants of
    its closure (a runner can save it)."""
    @jax.jit
    def model(theta, shape, load, data):
        return _model(theta, shape, load, data, spec, history)

    return model


def fit_residuals(theta, shape, load, data: _Data, spec: FitSpec, history: str, inv_delta):
    """Residuals (flattened, padding zero) in units of the moment scale, pseudo-Huber rescaled
    where inv_delta > 0 (1 / delta; 0: plain least squares)."""
    return _residuals_and_status(theta, shape, load, data, spec, history, inv_delta)[0]


def _residuals_and_status(theta, shape, load, data: _Data, spec: FitSpec, history: str, inv_delta,
                          loop: str = "auto"):
    """(`fit_residuals`, the cycles' statuses (L,))."""
    m, off, status, _ = _model(theta, shape, load, data, spec, history, loop)
    r = (data.moment - m - off[:, None]) * data.mask
    z = r * inv_delta
    return (r * jnp.sqrt(2.0 / (1.0 + jnp.sqrt(1.0 + z * z)))).reshape(-1), status


_residuals_jit = jax.jit(fit_residuals, static_argnums=(4, 5))

def _lm_residuals(theta, args):
    """The solver's function: (residuals, the cycles' statuses) at theta, args = (shape, load,
    data, inv_delta, spec, history); spec and history are static. Its derivative in theta is the
    Jacobian matrix, computed once per point by forward mode through the kernel's while loops:
    the solver's products with J and J^T are then products with that matrix, not copies of the
    kernel's linearised scan program and its transpose (which made the step's program large)."""
    shape, load, data, inv_delta, spec, history = args

    def values(th):
        return _residuals_and_status(th, shape, load, data, spec, history, inv_delta, "while")

    @jax.custom_jvp
    def f(th):
        return values(th)

    @f.defjvp
    def f_jvp(primals, tangents):
        (th,), (t,) = primals, tangents

        def twice(x):
            r, status = values(x)
            return r, (r, status)

        jac, (r, status) = jax.jacfwd(twice, has_aux=True)(th)
        return (r, status), (jac @ t, np.zeros(status.shape, jax.dtypes.float0))

    return f(theta)


def _lm_solver(rtol):
    # Imported here, not with the module: optimistix (with equinox) adds 1-2 s to every
    # `import jaxdamp` (measured 2026-11-25), and only the loop fit uses it.
    import optimistix as optx

    return optx.LevenbergMarquardt(rtol=rtol, atol=rtol * 1e-3)


def _lm_init(theta, args, rtol):
    f_struct, aux_struct = jax.eval_shape(lambda: _lm_residuals(theta, args))
    return _lm_solver(rtol).init(_lm_residuals, theta, args, {}, f_struct, aux_struct, frozenset())


def _state_arrays(state) -> list:
    """The solver state's arrays (its other leaves, a jaxpr, are the same at every step)."""
    # equinox comes with optimistix: imported where used, as in _lm_solver
    import equinox as eqx

    return [x for x in jax.tree_util.tree_leaves(state) if eqx.is_array(x)]


def _state_of(arrays, theta, args, rtol):
    """The solver state from its arrays (`_state_arrays`); the rest of it comes from tracing the
    solver's init again (shapes only, no computation)."""
    # equinox comes with optimistix: imported where used, as in _lm_solver
    import equinox as eqx

    leaves, tree = jax.tree_util.tree_flatten(eqx.filter_eval_shape(_lm_init, theta, args, rtol))
    dynamic = [i for i, x in enumerate(leaves) if isinstance(x, jax.ShapeDtypeStruct)]
    if len(dynamic) != len(arrays):
        raise ValueError(f"the solver state has {len(dynamic)} arrays; got {len(arrays)}")
    for i, x in zip(dynamic, arrays):
        leaves[i] = x
    return jax.tree_util.tree_unflatten(tree, leaves)


@functools.cache
def _fit_programs(spec: FitSpec, history: str, rtol: float):
    """(start, step, at_solution): the fit's programs, jitted functions of arrays only (the
    options are constants of their closures), so that a runner can save them (the CLI does,
    `jaxdamp.cli.exported`: a later process neither traces nor lowers them). optimistix's
    Levenberg-Marquardt runs one step per call from Python, its state passed between the calls as
    its list of arrays.

    Why not one `optx.least_squares` program: its progress came out through a host callback, and
    JAX cannot store a program with a host callback in the persistent compilation cache (the
    callback's address is part of the program), so every process compiled the fit again (a repeat
    `jaxdamp fit-loops` took as long as the first, 58 s). Stepping from Python reports each step
    itself and every program is cached. The residuals, their Jacobian and the statuses at the
    solution come from the solver's own linearisation at its last accepted point."""

    def args_of(shape, load, data, inv_delta):
        return shape, load, data, inv_delta, spec, history

    @jax.jit
    def start(theta, shape, load, data, inv_delta):
        return _state_arrays(_lm_init(theta, args_of(shape, load, data, inv_delta), rtol))

    @jax.jit
    def step(theta, arrays, shape, load, data, inv_delta):
        # optimistix where used, as in _lm_solver (1-2 s of `import jaxdamp` otherwise)
        import optimistix as optx

        args = args_of(shape, load, data, inv_delta)
        state, lm = _state_of(arrays, theta, args, rtol), _lm_solver(rtol)
        theta, state, _ = lm.step(_lm_residuals, theta, args, {}, state, frozenset())
        done, result = lm.terminate(_lm_residuals, theta, args, {}, state, frozenset())
        r = state.f_info.residual
        return (theta, _state_arrays(state), done, result == optx.RESULTS.successful,
                0.5 * jnp.sum(r * r))

    @jax.jit
    def at_solution(theta, arrays, shape, load, data, inv_delta):
        state = _state_of(arrays, theta, args_of(shape, load, data, inv_delta), rtol)
        return state.f_info.residual, state.f_info.jac.as_matrix(), state.aux

    return start, step, at_solution


def _solve(theta0, shape, load, data, inv_delta, *, spec, history, max_steps, rtol, report,
           runner=None):
    """Levenberg-Marquardt from theta0 (at most max_steps steps; report(step, loss) after each):
    (theta, residuals, Jacobian, statuses at theta, converged, steps)."""
    start, step, at_solution = _fit_programs(spec, history, rtol)
    data_args = (shape, load, data, inv_delta)
    theta = theta0
    arrays = run_program(start, (theta,) + data_args, runner)
    done, ok, n = False, True, 0
    while not done and n < max_steps:
        theta, arrays, done, ok, loss = run_program(step, (theta, arrays) + data_args, runner)
        done, ok, n = bool(done), bool(ok), n + 1
        report(n, float(loss))
    r, jac, status = run_program(at_solution, (theta, arrays) + data_args, runner)
    return theta, r, jac, status, done and ok, n


def _robust_sd(r):
    r = np.asarray(r)
    return float(1.4826 * np.median(np.abs(r - np.median(r))))


def _pad(n: int) -> int:
    """Samples per loop, padded by the one padding rule (the next power of two, at least 512), so
    that loops of similar length share a compiled fit."""
    return padded_size(n, 512)


def _stack(loops: list, scale) -> _Data:
    n = _pad(max(lp.x.size for lp in loops))
    L = len(loops)
    fwd, u, m, mask, x = (np.zeros((L, n), bool), np.zeros((L, n)), np.zeros((L, n)), np.zeros((L, n)),
                          np.zeros((L, n)))
    kind, contact = np.zeros(L, np.int32), np.zeros(L, np.int32)
    scale = np.broadcast_to(np.asarray(scale, float), (L,))
    for i, lp in enumerate(loops):
        k = lp.x.size
        fwd[i, :k], u[i, :k], m[i, :k], mask[i, :k] = lp.forward, lp.u, lp.y / scale[i], 1.0
        if isinstance(lp, ContactLoop):
            kind[i] = 1 + COMPONENTS.index(lp.component)
            contact[i] = lp.contact
            x[i, :k] = lp.disp - lp.disp_c
    return _Data(jnp.asarray([lp.psi_a for lp in loops]), jnp.asarray(fwd), jnp.asarray(u),
                 jnp.asarray(m), jnp.asarray(mask), jnp.asarray(scale), jnp.asarray(kind),
                 jnp.asarray(contact), jnp.asarray(x))


class FitProblem(NamedTuple):
    """The least-squares problem of `fit_loops`, for your own solver: residuals(theta, inv_delta)
    (jit-compiled; flattened, padding zero, units of `scale`; inv_delta = 0 plain least squares, else
    1 / the pseudo-Huber threshold) from theta0 (the generic start, offsets from the data)."""

    residuals: Callable
    theta0: np.ndarray
    names: list
    scale: np.ndarray  # (L,) per loop: N mm or N
    loops: list
    spec: FitSpec
    n_phys: int
    data: object
    shape: DamperShape
    load: LoadCase
    initial: str
    loss0: float  # 0.5 sum r^2 at theta0 (plain)


def fit_problem(loops, shape: DamperShape, *, load: LoadCase = LoadCase(), initial: str = "gross_slip",
                mu: str = "shared", kn: str = "shared", kt: str = "shared", start: dict | None = None,
                names=None, runner=None) -> FitProblem:
    """The checked, analysed and stacked problem that `fit_loops` solves (same arguments)."""
    return _with_offsets(_stacked(loops, shape, load, initial, mu, kn, kt, start, names), runner)


def _stacked(loops, shape, load, initial, mu, kn, kt, start, names) -> FitProblem:
    """`fit_problem` before the model has run: the offsets in theta0 zero, no residuals, no loss0."""
    require_x64()
    if isinstance(shape, Scene):  # checked already (`prepare_scene`): its shape and load
        shape, load = shape.shape, shape.load
    else:
        check_one_shape(shape)  # one damper: the test's
        check_contacts_and_load(Contacts(), load)
        validate_shape(shape)
        validate_load(load)
    if initial not in INITIAL_STATES:
        raise ValueError(f"initial must be one of {', '.join(INITIAL_STATES)}; got {initial!r}")
    for key, g in (("mu", mu), ("kn", kn), ("kt", kt)):
        if g not in GROUPINGS[key]:
            raise ValueError(f"{key} grouping must be one of {', '.join(GROUPINGS[key])}; got {g!r}")
    if start is not None and not isinstance(start, dict):
        raise ValueError(f"start must be a dict of mu, kn, kt or None; got {type(start).__name__}")
    unknown = sorted(set(start or {}) - set(DEFAULT_START))
    if unknown:
        raise ValueError(f"start may give {', '.join(DEFAULT_START)}; got {', '.join(unknown)}")
    st = dict(DEFAULT_START, **(start or {}))
    # the start: mu in its range (params.RANGES), kn and kt inside the validated stiffness range
    # (at most VALIDATED_STIFFNESS_OVER_FD_PER_MM[1] F_D per mm: above it no cycle is trustworthy)
    check_param("mu", st["mu"], "start_mu")
    k_hi = VALIDATED_STIFFNESS_OVER_FD_PER_MM[1] * float(np.max(np.asarray(load.F_D, float)))
    check_range("start_kn", st["kn"], 0.0, k_hi, lo_open=True, unit="N/mm")
    check_range("start_kt", st["kt"], 0.0, k_hi, lo_open=True, unit="N/mm")
    if isinstance(loops, (str, bytes)) or not hasattr(loops, "__iter__"):
        raise ValueError(f"loops must be a list of loops; got {type(loops).__name__}")
    loops = list(loops)
    if not loops:
        raise ValueError("loops must hold at least one (psi_mrad, moment_nmm) loop")
    if names is not None and (isinstance(names, (str, bytes)) or not hasattr(names, "__len__")
                              or len(names) != len(loops)):
        raise ValueError(f"names must be a list of one name per loop ({len(loops)}); got "
                         f"{names!r:.60}")
    names = names or [f"loop {i + 1}" for i in range(len(loops))]
    loops = [lp if isinstance(lp, (MomentLoop, ContactLoop)) else analyse_loop(*loop_pair(lp, nm), name=nm)
             for lp, nm in zip(loops, names)]
    for lp, nm in zip(loops, names):
        check_range("psi_a_mrad", lp.psi_a, 0.0, 1e4, lo_open=True, unit="mrad")
        why = loop_direction_error(lp, nm)  # as the CLI: a loop of negative energy is refused
        if why is not None:
            raise LoopError(why)
    spec = FitSpec(mu, kn, kt)
    n_mu, n_kn, n_kt = spec.sizes()
    n_phys = n_mu + n_kn + n_kt
    # one residual scale per unit (N mm for moment loops, N for contact loops): half the largest
    # range of the loops in that unit
    group = lambda lp: isinstance(lp, ContactLoop)  # noqa: E731
    gscale = {g: max(float(np.ptp(lp.y)) for lp in loops if group(lp) == g) / 2.0 or 1.0
              for g in {group(lp) for lp in loops}}
    scale = np.array([gscale[group(lp)] for lp in loops])
    data = _stack(loops, scale)
    shape_j = DamperShape(*(None if v is None else jnp.asarray(v, float) for v in shape))
    load_j = LoadCase(*(jnp.asarray(v, float) for v in load))
    theta = np.concatenate([np.full(n_mu, np.log(st["mu"])), np.full(n_kn, np.log(st["kn"] / K_REF)),
                            np.full(n_kt, np.log(st["kt"] / K_REF)), np.zeros(len(loops))])
    pnames = spec.names() + [f"offset_{i}" for i in range(len(loops))]
    return FitProblem(None, theta, pnames, scale, loops, spec, n_phys, data, shape_j, load_j, initial,
                      float("nan"))


def _with_offsets(prob: FitProblem, runner) -> FitProblem:
    """The start's offsets (the mean gap between each measured loop and the model at the start),
    the loss there and the residual function."""
    spec, data, shape_j, load_j, initial = prob.spec, prob.data, prob.shape, prob.load, prob.initial
    theta = np.array(prob.theta0)
    m0, _, _, _ = run_program(_model_program(spec, initial), (jnp.asarray(theta), shape_j, load_j, data),
                              runner)
    gap = np.asarray(jnp.sum((data.moment - m0) * data.mask, axis=1) / jnp.sum(data.mask, axis=1))
    theta[prob.n_phys:] = gap
    r0 = (data.moment - m0 - jnp.asarray(gap)[:, None]) * data.mask

    def res(th, inv_delta):  # the module-level program; the data are its arguments, not constants
        return _residuals_jit(th, shape_j, load_j, data, spec, initial, inv_delta)

    return prob._replace(residuals=res, theta0=theta, loss0=float(0.5 * jnp.sum(r0 * r0)))


def _first_step(prob: FitProblem, rtol: float, runner) -> None:
    """One solver step from the start without offsets, its result dropped: run beside the model's
    first call (`_with_offsets`), it compiles the solver's programs (the step, the fit's largest)
    on the other core while the model's compiles (a jitted program compiles once when two threads
    call it)."""
    _solve(jnp.asarray(prob.theta0), prob.shape, prob.load, prob.data, jnp.asarray(0.0),
           spec=prob.spec, history=prob.initial, max_steps=1, rtol=rtol,
           report=lambda step, loss: None, runner=runner)


def fit_loops(loops, shape: DamperShape, *, load: LoadCase = LoadCase(), initial: str = "gross_slip",
              mu: str = "shared", kn: str = "shared", kt: str = "shared", start: dict | None = None,
              robust: bool = True, max_steps: int = 100, rtol: float = 1e-6,
              callback: Callable | None = None, names=None, runner=None) -> LoopFit:
    """Fit mu, kn, kt (and one moment offset per loop) to measured moment loops.

    loops: a list of (psi_mrad, moment_nmm) pairs of 1-D arrays (each several periods, any
    sampling) or of MomentLoop; shape: the damper's DamperShape, or a Scene
    (`response.prepare_scene`, checked already: its shape and load are used, unchecked, and load=
    is not); load: F_D, q*, r sin(beta) of the test. initial: the history of the model's steady
    cycle, "gross_slip" or "assembly". mu: "shared" or "contact"; kn, kt: "shared", "side"
    (R1 | L1 = L2) or "contact". start: {"mu", "kn", "kt"} (numbers; default DEFAULT_START, a
    generic guess). robust: a second, pseudo-Huber stage.
    callback(stage, step, loss): called after every solver step (loss: 0.5 sum r^2 at the last
    accepted step), and once with step 0 at the generic start. runner: how the fit's programs are
    called (`jaxdamp.runtime.run_program`; the CLI passes its saved-program cache).

    Returns a LoopFit: values, standard errors, CONFIDENCE intervals, correlations, and which
    parameters the loops do not identify (NaN values, with the reason). Loops that cannot be used
    raise LoopError (a ValueError) naming the loop.
    """
    check_int("max_steps", max_steps, 1)
    check_range("rtol", rtol, 0.0, 1.0, lo_open=True, hi_open=True)
    if not isinstance(robust, (bool, np.bool_)):  # "no" was taken as True
        raise ValueError(f"robust must be True or False; got {robust!r}")
    if callback is not None and not callable(callback):
        raise ValueError(f"callback must be a function (stage, step, loss) or None; got "
                         f"{type(callback).__name__}")
    prob = _stacked(loops, shape, load, initial, mu, kn, kt, start, names)
    prob = side_by_side(lambda: _with_offsets(prob, runner), lambda: _first_step(prob, rtol, runner))[0]
    spec, n_phys, data, scale, theta = prob.spec, prob.n_phys, prob.data, prob.scale, prob.theta0
    shape_j, load_j, loops = prob.shape, prob.load, prob.loops
    n_mu = spec.sizes()[0]
    history, steps = [], []
    stage_box = [0]

    def report(step, loss):
        history.append((stage_box[0], step, loss))
        if callback is not None:
            callback(stage_box[0], step, loss)

    kw = dict(spec=spec, history=initial, max_steps=max_steps, rtol=rtol, report=report,
              runner=runner)
    report(0, prob.loss0)  # the generic start
    theta, r, jac, status, converged, nsteps = _solve(jnp.asarray(theta), shape_j, load_j, data,
                                                      jnp.asarray(0.0), **kw)
    steps.append(nsteps)
    mask = np.asarray(data.mask).reshape(-1) > 0
    if robust:
        delta = ROBUST_DELTA * max(_robust_sd(np.asarray(r)[mask]), 1e-12)
        stage_box[0] = 1
        theta, r, jac, status, converged, nsteps = _solve(theta, shape_j, load_j, data,
                                                          jnp.asarray(1.0 / delta), **kw)
        steps.append(nsteps)
    theta, r, jac = np.asarray(theta), np.asarray(r)[mask], np.asarray(jac)[mask]
    n, p = r.size, theta.size
    dof = max(n - p, 1)
    sigma2 = float(np.sum(r ** 2) / dof)
    pnames = prob.names
    ident, why, cov = identify(jac, sigma2, pnames, n_phys)
    se_t = np.sqrt(np.maximum(np.diag(cov), 0.0))
    z = z_value()
    value = np.concatenate([np.exp(theta[:n_mu]), K_REF * np.exp(theta[n_mu:n_phys]),
                            theta[n_phys:] * scale])
    se = np.concatenate([value[:n_phys] * se_t[:n_phys], se_t[n_phys:] * scale])
    lo = np.concatenate([value[:n_phys] * np.exp(-z * se_t[:n_phys]), value[n_phys:] - z * se[n_phys:]])
    hi = np.concatenate([value[:n_phys] * np.exp(z * se_t[:n_phys]), value[n_phys:] + z * se[n_phys:]])
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    for a in (value, se, lo, hi):
        a[~ident] = np.nan
    mu_v, kn_v, kt_v, _ = (np.asarray(v) for v in _expand(jnp.asarray(theta), spec))
    m_fit, off, cyc_status, mono = run_program(_model_program(spec, initial),
                                               (jnp.asarray(theta), shape_j, load_j, data), runner)
    fitted = np.asarray((m_fit + off[:, None]) * scale[:, None])
    fitted_list = [fitted[i, :lp.x.size] for i, lp in enumerate(loops)]
    rms = np.array([float(np.sqrt(np.mean((lp.y - f) ** 2))) for lp, f in zip(loops, fitted_list)])
    # one residual sd where all loops share a unit (N mm or N); mixed units have none (see rms)
    sigma = float(np.sqrt(sigma2) * scale[0]) if np.all(scale == scale[0]) else float("nan")
    cyc_status = np.asarray(cyc_status)
    worst = RESULTS.ok
    for s in cyc_status:
        if not RESULTS.valid(int(s)):
            worst = int(s)
    if worst == RESULTS.ok and not converged:
        worst = RESULTS.not_converged
    held = [nm for nm, k in zip(pnames, ident) if not k]
    return LoopFit(pnames, value, se, lo, hi, corr, ident, why,
                   float(mu_v) if mu_v.ndim == 0 else mu_v, kn_v, kt_v, value[n_phys:] if np.all(
                       ident[n_phys:]) else theta[n_phys:] * scale, sigma,
                   rms, loops, fitted_list, cyc_status, steps, history, spec, initial,
                   int(worst), held, np.asarray(mono, bool))
