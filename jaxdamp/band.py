"""The band of responses at an amplitude: min and max of k_Re and k_Im over every statically
admissible initial state (the paper's ref. [32]: the limits of the response by constrained
optimisation over the initial states).

The initial state sits at the forward extreme (see `jaxdamp.amplitude`). It is parameterised by the
tangential forces T (3,) (units of F_D); the normal forces follow from the damper's equilibrium,
-A^T N + C^T T + e_y = 0, so N = P T + n0 is affine in T, and the admissible set

    N >= 0,   mu N - T >= 0,   mu N + T >= 0          (9 linear inequalities G T + h >= 0)

is a polyhedron in R^3: a polytope, plus a recession cone where the wedge self-locks (admissible
states with arbitrarily large forces; `recession_rays`). Its vertices are found exactly (every
triple of active constraints), the set is sampled uniformly, far out along the cone and by sparse
convex combinations of the vertices (vmap over the samples), and the four extremes are refined by
the tract-sequence structure (issue 24): for a fixed sequence of tracts
the steady cycle's corners are affine in the initial state, so the dissipated energy, and k_Im, is
a quadratic of T there. Trust-region steps take the exact minimum of the second-order model of k
(its gradient and Hessian from the corners' forward-mode Jacobian) over the polytope (`jaxdamp.qp3`: a small
quadratic program solved by enumerating its active sets) and run the exact cycle at the step; inside
one sequence the step is that sequence's own optimum, across sequences the exact cycle decides.
Every bound's state is re-run as a plain cycle (`Band.confirmed`). The band is the min / max over
the valid cycles (status ok or shakedown). `amplitude_bands` runs a grid of amplitudes through one
program (the response's band, `peak_band`): on the CPU in chunks of a few amplitudes on the
cores' threads (`CPU_CHUNK`), on an accelerator in one batch.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._validate import check_int, check_range
from .admissible import VERTEX_SLOTS as VERTEX_SLOTS
from .admissible import admissible_polytope as admissible_polytope
from .admissible import admissible_samples, box_extent
from .admissible import polytope_vertices as polytope_vertices
from .admissible import recession_rays as recession_rays
from .amplitude import MAX_PAIRS, MAX_TRACTS, amplitude_kernel, history_halves
from .ellipse import elliptic_kernel
from .geometry import DamperShape
from .params import Contacts, LoadCase, prepare_inputs
from .qp3 import minimise_quadratic
from .loops import tree_where
from .runtime import compile_ahead, map_in_parts, part_size, run_program
from .sequence import corner_rows, loop_stiffness
from .tract import NO_EVENT
from .status import RESULTS, number_repr, status_repr

BOUNDS = ("k_re_min", "k_re_max", "k_im_min", "k_im_max")
ADMISSIBLE_TOL = 1e-10  # units of F_D: a refined state must satisfy the constraints to this


class Band(NamedTuple):
    """The band at one amplitude (k in N mm/mrad); arrays of 4 follow BOUNDS."""

    psi_a: float
    bounds: np.ndarray  # (4,) k_re_min, k_re_max, k_im_min, k_im_max (zero where status is not ok)
    N: np.ndarray  # (4, 3) initial normal forces attaining each bound (units of F_D)
    T: np.ndarray  # (4, 3) initial tangential forces
    # Masks (docs/api.md, "Statuses and masks"): which bounds the optimiser improved beyond the
    # samples, and which a plain cycle from their state confirmed; the status says whether the
    # numbers hold.
    refined: np.ndarray  # (4,) bool: the bound was improved by the optimiser beyond the samples
    n_valid: int  # valid cycles among the samples
    # RESULTS.ok if an admissible state gives a valid cycle and every bound is confirmed;
    # not_converged where a bound is not confirmed; else the first real state's problem
    status: int
    confirmed: np.ndarray = None  # (4,) bool: each state re-run as a plain cycle gives its bound

    def as_dict(self) -> dict:
        """The bounds by name; None where no admissible state gives a valid cycle (status)."""
        exists = int(self.status) == RESULTS.ok
        return {name: (float(v) if exists else None) for name, v in zip(BOUNDS, self.bounds)}

    def __repr__(self) -> str:
        bounds = ", ".join(f"{n}={number_repr(v, 'N mm/mrad')}" for n, v in zip(BOUNDS, self.bounds))
        return (f"Band(status={status_repr(self.status)}, psi_a={number_repr(self.psi_a, 'mrad')}, "
                f"{bounds}, n_valid={self.n_valid})")


def state_cycle(shape, mu, contacts, load, psi, T, P, n0, motion=None):
    """(k_re, k_im, status) of the steady cycle from the admissible state T (N = P T + n0,
    `admissible.admissible_samples`) at the path's forward extreme: the in-phase path (motion
    None), a straight Motion, or an ellipse's X(0) = a X_r (`ellipse.elliptic_kernel`). On a
    platform path values only (while loops trace faster). The states do not depend on psi: one
    state's cycles over amplitudes are that state's curve (the row's band, `response.row_band`)."""
    N = P @ T + n0
    if motion is None:
        c = amplitude_kernel(shape, mu, contacts, load, psi, N, T, initial="explicit")
    elif motion.quadrature is None:
        c = amplitude_kernel(shape, mu, contacts, load, psi, N, T, initial="explicit",
                             motion=motion, loop="while")
    else:
        c = elliptic_kernel(shape, mu, contacts, load, psi, motion, N, T, initial="explicit",
                            loop="while")
    return c.k_re, c.k_im, c.status


def _sample(shape, mu, contacts, load, psi, key, n_samples, motion=None):
    T, valid_point, P, n0 = admissible_samples(shape, mu, key, n_samples)
    k_re, k_im, status = jax.vmap(lambda t: state_cycle(shape, mu, contacts, load, psi, t, P, n0,
                                                        motion))(T)
    status = jnp.where(valid_point, status, jnp.int32(RESULTS.singular))
    return T, P @ T.T + n0[:, None], k_re, k_im, status, valid_point


class _Model(NamedTuple):
    k: jnp.ndarray
    g: jnp.ndarray  # (3,) dk/dT
    H: jnp.ndarray  # (3, 3)
    status: jnp.ndarray
    A_reg: jnp.ndarray  # (R, 3) the sequence's region A_reg dT + b_reg >= 0 (mm per unit T)
    b_reg: jnp.ndarray  # (R,) mm; huge where a row is not live (no tract, no event)


def _k_model(shape, mu, contacts, load, psi, T, P, n0, which) -> _Model:
    """k (which: 0 k_Re, 1 k_Im), its gradient and Hessian in T, the cycle's status and its tract
    sequence's region, from one forward-mode pass (jacfwd: the cycle's while loops pass forward
    mode) of the loop's corners. Within the sequence the corners c (tract lengths, moments at the
    tract starts) are affine in T and every tract length and event slack of every half run is too
    (the sequence changes where one reaches zero). k is the closed-form first harmonic of the
    corners (`sequence.loop_stiffness`), so its Hessian is J^T (d2k/dc2) J, exact, from the
    corners' Jacobian J and the closed form's own second derivatives: no second pass through the
    cycle (4 forward lanes instead of the 16 of jacfwd of jacfwd)."""

    def corners_of(t):
        ac = amplitude_kernel(shape, mu, contacts, load, psi, P @ t + n0, t, initial="explicit",
                              loop="while")
        k = jnp.where(which == 0, ac.k_re, ac.k_im)
        rows = corner_rows(ac)
        dv, slack = ac.history_dv.reshape(-1), ac.history_slack.reshape(-1)
        return (rows, dv, slack), (rows, dv, slack, k, ac.status)

    (J_rows, J_dv, J_slack), (rows, dv, slack, k, status) = jax.jacfwd(corners_of, has_aux=True)(T)

    def k_of_rows(r):
        k_re, k_im = loop_stiffness(r, psi, load.q_star)
        return jnp.where(which == 0, k_re, k_im)

    J = J_rows.reshape(-1, 3)
    dk = jax.grad(k_of_rows)(rows).reshape(-1)
    d2k = jax.hessian(k_of_rows)(rows).reshape(J.shape[0], J.shape[0])
    g = dk @ J
    H = J.T @ d2k @ J
    # live rows: a tract that ran, and the slack of its nearest other event (NO_EVENT: none)
    live = jnp.concatenate([dv > 0.0, (dv > 0.0) & (slack < 0.5 * NO_EVENT)])
    A_reg = jnp.where(live[:, None], jnp.concatenate([J_dv, J_slack]), 0.0)
    b_reg = jnp.where(live, jnp.concatenate([dv, slack]), 1e300)
    valid = RESULTS.valid(status)
    # an invalid cycle's corners are zeros (no model): keep everything finite there
    return _Model(k, jnp.where(valid, g, 0.0), jnp.where(valid, 0.5 * (H + H.T), 0.0), status,
                  A_reg, b_reg)


def _trust_region(shape, mu, contacts, load, psi, T0, sign, which, scale, radius, steps):
    """`steps` trust-region steps from T0 (B, 3) minimising sign * k_which / scale over the
    admissible polytope, batched over starts. Each step takes the exact minimum (`qp3`) of the
    second-order model at the accepted state over the polytope and an inf-norm box of the trust
    radius, then runs the exact cycle there: accepted if not worse, else the radius shrinks. Within
    one tract sequence k_Im is quadratic in T, so there the model is exact and the step lands on the
    sequence's own optimum; the exact cycle at every step keeps a model that crossed into another
    sequence from being believed. Returns per start (the accepted state T, sign * k / scale and
    status there, the last proposal T_try, not run yet: `band_kernel` runs every start's last
    proposal in one batch with the bounds' confirmation)."""
    P, n0, G, h = admissible_polytope(shape, mu)
    eye = jnp.eye(3)
    A = jnp.concatenate([G, -eye, eye])

    def one(T_start, s, wh):
        def step(c, _):
            T_acc, v_acc, m_acc, r, T_try = c
            m = _k_model(shape, mu, contacts, load, psi, T_try, P, n0, wh)
            m = m._replace(k=s * m.k / scale, g=s * m.g / scale, H=s * m.H / scale)
            inside = jnp.all(G @ T_try + h >= -ADMISSIBLE_TOL)
            accept = RESULTS.valid(m.status) & inside & (m.k <= v_acc)
            moved = jnp.max(jnp.abs(T_try - T_acc))
            r = jnp.where(accept, jnp.maximum(r, 2.0 * moved), jnp.minimum(r, 0.25 * moved))
            T_acc = jnp.where(accept, T_try, T_acc)
            v_acc = jnp.where(accept, m.k, v_acc)
            m_acc = tree_where(accept, m, m_acc)
            b = jnp.concatenate([G @ T_acc + h, jnp.full(6, r)])
            d, _, ok = minimise_quadratic(m_acc.g, m_acc.H, A, b)
            d = jnp.where(ok & jnp.isfinite(v_acc), d, 0.0)
            # Within the accepted state's sequence the model is exact: go to where the step leaves
            # that sequence (a tract's length or an event's slack reaching zero), just across it,
            # so that the next model is the neighbouring sequence's.
            rate = m_acc.A_reg @ d
            t_out = jnp.where((rate < 0.0) & (m_acc.b_reg > 0.0), m_acc.b_reg / jnp.where(
                rate < 0.0, -rate, 1.0), jnp.inf)
            t = jnp.minimum(1.0, jnp.min(t_out) * (1.0 + 1e-6) + 1e-12)
            return (T_acc, v_acc, m_acc, r, T_acc + t * d), None

        init = (T_start, jnp.inf, _no_model(), radius, T_start)
        (T_acc, v_acc, m_acc, _, T_try), _ = jax.lax.scan(step, init, None, length=steps)
        return T_acc, v_acc, m_acc.status, T_try

    return jax.vmap(one)(T0, sign, which)


def _no_model() -> _Model:
    """The trust region's model before its first step: zeros of `_k_model`'s shapes (the region's
    rows: two per tract slot of every half an explicit start runs), status not_converged. Built
    from the shapes rather than by tracing `_k_model` once more (jax.eval_shape traced the
    cycle's forward-mode program: a tenth of the band program's trace)."""
    rows = 2 * history_halves("explicit", MAX_PAIRS) * MAX_TRACTS
    return _Model(jnp.zeros(()), jnp.zeros(3), jnp.zeros((3, 3)), jnp.int32(RESULTS.not_converged),
                  jnp.zeros((rows, 3)), jnp.zeros(rows))


SIGNS = np.array([1.0, -1.0, 1.0, -1.0])  # each bound minimises sign * k (BOUNDS' order)
WHICH = np.array([0, 0, 1, 1])  # 0: k_Re, 1: k_Im
CONFIRM_TOL = 1e-9  # a bound's state re-run as a plain cycle gives the bound to this (of the k scale)


class BandKernel(NamedTuple):
    """`band_kernel`'s arrays (a pytree; a batch of amplitudes has a leading axis)."""

    bounds: jnp.ndarray  # (4,) BOUNDS, N mm/mrad (zero where status is not ok)
    N: jnp.ndarray  # (4, 3) the attaining initial states, units of F_D
    T: jnp.ndarray  # (4, 3)
    refined: jnp.ndarray  # (4,) bool: the trust region improved the best sample
    confirmed: jnp.ndarray  # (4,) bool: the state re-run as a plain cycle gives the bound
    n_valid: jnp.ndarray  # valid cycles among the samples (int32)
    status: jnp.ndarray  # RESULTS code (int32)


def band_kernel(shape, mu, contacts, load, psi, key, *, n_samples: int = 64,
                steps: int = 6, starts: int = 2, motion=None) -> BandKernel:
    """The band at psi (mrad), pure JAX (jit / vmap over amplitudes or designs; values only).

    The polytope's vertices and n_samples random admissible states are run as cycles; the `starts`
    best samples of each bound then start `steps` trust-region steps (`_trust_region`, 0: none);
    each bound's final state is then re-run by the plain cycle (`amplitude_kernel`, loop "auto")
    to confirm it (with steps 0 the bounds are the samples' cycles themselves).

    motion: a platform path (`jaxdamp.motion.Motion`, straight or elliptic; None: the paper's
    in-phase motion) for the curved-flat damper. The admissible states are the same on every path
    (the damper's equilibrium with F_D does not depend on where the platforms are); on a path the
    state is the one at X(0) = a X_r and the band is the samples' (steps must be 0: the
    trust-region model is the in-phase cycle's closed-form first harmonic)."""
    if motion is not None and steps > 0:
        raise ValueError("steps must be 0 with a motion: the trust-region refinement runs on the "
                         "in-phase path only")
    T, N, k_re, k_im, status, real = _sample(shape, mu, contacts, load, psi, key, n_samples, motion)
    P, n0, G, h = admissible_polytope(shape, mu)
    valid = RESULTS.valid(status)
    values = jnp.stack([k_re, k_re, k_im, k_im])  # (4, samples)
    signs, which = jnp.asarray(SIGNS), jnp.asarray(WHICH)
    score = jnp.where(valid[None, :], signs[:, None] * values, jnp.inf)
    best = jnp.argmin(score, axis=1)
    T_best = T[best]
    any_valid = jnp.any(valid)
    scale = jnp.maximum(jnp.max(jnp.where(valid[None, :], jnp.abs(values), 0.0)), 1e-300)
    spread = box_extent(T, valid)
    sampled = signs * score[jnp.arange(4), best]
    if steps > 0:
        # the `starts` best samples of distinct k per bound: where the transient forgets the
        # initial state k is flat in T (a plateau of equal samples, no gradient to follow), and
        # the extremes can sit in different sequences' optima
        srt = jnp.sort(score, axis=1)
        order = jnp.argsort(score, axis=1)
        repeat = jnp.concatenate([jnp.zeros((4, 1), bool), jnp.abs(jnp.diff(srt, axis=1)) <= 1e-9 * (
            jnp.abs(srt[:, 1:]) + scale)], axis=1)
        distinct = jnp.where(repeat, jnp.inf, srt)
        _, pos = jax.lax.top_k(-distinct, starts)  # (4, starts)
        top = jnp.take_along_axis(order, pos, axis=1)
        T0 = T[top].reshape(4 * starts, 3)
        sign_s, which_s = jnp.repeat(signs, starts), jnp.repeat(which, starts)
        T_acc, v_acc, _, T_try = _trust_region(shape, mu, contacts, load, psi, T0, sign_s, which_s,
                                               scale, jnp.maximum(spread, 1e-6), steps)
        # One batch of plain cycles (`state_cycle`): every start's last proposal and accepted
        # state, and the best samples; the bounds' confirmation re-runs are among them (one copy
        # of the cycle in the program instead of two).
        k_re_c, k_im_c, st_c = jax.vmap(lambda t: state_cycle(shape, mu, contacts, load, psi, t, P,
                                                              n0))(
            jnp.concatenate([T_try, T_acc, T_best]))
        k_c = jnp.where(jnp.concatenate([which_s, which_s, which]) == 0, k_re_c, k_im_c)
        n_s = 4 * starts
        v_try = sign_s * k_c[:n_s] / scale
        inside = jnp.all(T_try @ G.T + h[None, :] >= -ADMISSIBLE_TOL, axis=1)
        accept = RESULTS.valid(st_c[:n_s]) & inside & (v_try <= v_acc)  # where not worse
        v_opt = jnp.where(accept, v_try, v_acc)
        v_opt = jnp.where(jnp.isfinite(v_opt), v_opt, jnp.inf).reshape(4, starts)
        pick = jnp.argmin(v_opt, axis=1)
        bound = signs * v_opt[jnp.arange(4), pick] * scale
        slot = jnp.arange(4) * starts + pick  # the picked start of each bound
        took_try = accept[slot]
        T_opt = jnp.where(took_try[:, None], T_try[slot], T_acc[slot])
        # the refined state only where it beats the sample beyond rounding
        refined = any_valid & (signs * bound < signs * sampled - 1e-12 * scale)
        T_at = jnp.where(refined[:, None], T_opt, T_best)
        # each bound's state by the plain cycle, from the batch: its confirmation
        at = jnp.where(refined, jnp.where(took_try, slot, n_s + slot), 2 * n_s + jnp.arange(4))
        bounds = k_c[at]
        confirmed = RESULTS.valid(st_c[at]) & (jnp.abs(bounds - jnp.where(refined, bound, sampled))
                                               <= CONFIRM_TOL * scale)
    else:
        refined = jnp.zeros(4, bool)
        T_at = T_best
        # the samples' own cycles: a re-run would be the same computation in the same program
        bounds, confirmed = sampled, jnp.ones(4, bool)
    # no valid cycle: the problem of the first real state (not a degenerate vertex slot); the
    # polytope has no vertex at all where the statics are singular
    first_bad = status[jnp.argmax(real)]
    band_status = jnp.where(any_valid, RESULTS.ok, jnp.where(jnp.any(real), first_bad,
                                                             RESULTS.singular))
    # A bound whose state, re-run as a plain cycle, does not give it is not to be trusted.
    band_status = RESULTS.first({RESULTS.not_converged: any_valid & ~jnp.all(confirmed)},
                                band_status)
    zero = lambda v: jnp.where(any_valid, v, jnp.zeros_like(v))  # noqa: E731
    return BandKernel(zero(bounds), zero(T_at @ P.T + n0[None, :]), zero(T_at), refined & any_valid,
                      confirmed & any_valid, jnp.sum(valid).astype(jnp.int32),
                      band_status.astype(jnp.int32))


# Amplitudes per band program call on the CPU: a vmapped while loop waits for its slowest lane, so
# chunks on the cores' threads waste less than one batch (24 amplitudes: 2.8 -> 0.9 s on 2 cores,
# docs/performance.md) and one chunk size is one program for every grid.
CPU_CHUNK = 3


@functools.cache
def bands_program(n_samples: int, steps: int, starts: int):
    """The jitted band of a grid of amplitudes, f(shape, mu, contacts, load, psi (n,), key) ->
    BandKernel with a leading amplitude axis (one program per option set; the CLI saves it)."""
    def program(shape, mu, contacts, load, psi, key):
        return jax.vmap(lambda p: band_kernel(shape, mu, contacts, load, p, key, n_samples=n_samples,
                                              steps=steps, starts=starts))(psi)
    return jax.jit(program)


def amplitude_bands(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, n_samples: int = 64, refine: bool = True,
                    steps: int = 6, starts: int = 2, seed: int = 0, runner=None) -> list:
    """`amplitude_band` at every amplitude of psi_a_mrad (mrad, 1-D) through one program
    (`bands_program`; on the CPU in chunks of CPU_CHUNK run on the cores' threads). runner(program,
    args) -> outputs runs it instead of a plain call (the CLI's saved programs; from threads)."""
    design = prepare_inputs(shape, mu, contacts, load)
    return amplitude_bands_unchecked(*design, psi_a_mrad, n_samples=n_samples, refine=refine,
                                  steps=steps, starts=starts, seed=seed, runner=runner)


def amplitude_bands_unchecked(shape: DamperShape, mu, contacts: Contacts, load: LoadCase, psi_a_mrad,
                           *, n_samples: int = 64, refine: bool = True, steps: int = 6,
                           starts: int = 2, seed: int = 0, runner=None) -> list:
    """`amplitude_bands` on a design prepared already (`params.prepare_inputs`, or a
    `response.Scene`'s fields): the design is NOT checked here; the amplitudes and counts are."""
    psi = check_band_amplitudes(psi_a_mrad)
    check_band_options(n_samples, steps, starts, refine, seed)
    n = psi.size
    program, inputs = _bands_call(shape, mu, contacts, load, n_samples, refine, steps, starts, seed)
    out = map_in_parts(lambda part: run_program(program, inputs(part), runner), psi, CPU_CHUNK)
    return [Band(float(psi[i]), out.bounds[i], out.N[i], out.T[i], out.refined[i],
                 int(out.n_valid[i]), int(out.status[i]), out.confirmed[i]) for i in range(n)]


def check_band_amplitudes(psi_a_mrad) -> np.ndarray:
    """The band's amplitudes (mrad) as a 1-D float array; ValueError naming psi_a_mrad otherwise."""
    check_range("psi_a_mrad", psi_a_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    psi = np.atleast_1d(np.asarray(psi_a_mrad, float))
    if psi.ndim != 1 or psi.size == 0:
        raise ValueError(f"psi_a_mrad must be one amplitude or a 1-D grid of them; got shape {psi.shape}")
    return psi


def check_band_options(n_samples: int, steps: int, starts: int, refine=True, seed=0) -> None:
    """ValueError naming the count, flag or seed out of its range."""
    if not isinstance(refine, (bool, np.bool_)):  # "no" and 0.5 were taken as True or False
        raise ValueError(f"refine must be True or False; got {refine!r}")
    check_int("seed", seed, 0)
    check_int("n_samples", n_samples, 2)
    check_int("steps", steps, 0)
    check_int("starts", starts, 1)
    if starts > n_samples:
        raise ValueError(f"starts must be an integer in [1, n_samples = {n_samples}]; got {starts}")


def _bands_call(shape, mu, contacts, load, n_samples, refine, steps, starts, seed):
    """(the bands' program, the function from one part of the amplitudes to its inputs)."""
    program = bands_program(n_samples, steps if refine else 0, starts)
    key = jax.random.PRNGKey(seed)
    return program, lambda part: (shape, mu, contacts, load, jnp.asarray(part), key)


def compile_bands_ahead(shape: DamperShape, mu, contacts: Contacts, load: LoadCase, n_psi: int, *,
                        n_samples: int = 64, refine: bool = True, steps: int = 6, starts: int = 2,
                        seed: int = 0, runner=None) -> None:
    """`runtime.compile_ahead` of the program `amplitude_bands_unchecked` runs for n_psi amplitudes
    with these options: for a caller whose amplitude grid waits on another result (`peak_band`'s
    on psi_BC). The counts are checked first: nothing compiles for options the call refuses."""
    check_band_options(n_samples, steps, starts, refine, seed)
    program, inputs = _bands_call(shape, mu, contacts, load, n_samples, refine, steps, starts, seed)
    compile_ahead(program, inputs(np.ones(part_size(n_psi, CPU_CHUNK))), runner)


def amplitude_band(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                   load: LoadCase = LoadCase(), *, n_samples: int = 64, refine: bool = True,
                   steps: int = 6, starts: int = 2, seed: int = 0, runner=None):
    """min / max of k_Re and k_Im (N mm/mrad) at psi_a (mrad) over the statically admissible
    initial states at the forward extreme, with the states that attain them.

    psi_a_mrad: one amplitude (a `Band`), or a 1-D grid of them (a list of `Band`s, one per
    amplitude, through one batched program: `amplitude_bands`). runner(program, args) -> outputs
    runs that program instead of a plain call (the CLI's saved programs).

    The polytope's vertices and n_samples random admissible states (sparse random combinations of the
    vertices) are run as cycles (vmap); the best sample of each bound then starts `steps`
    trust-region steps on the exact second-order model of k in T (within one tract sequence k_Im
    is quadratic in T: a step solves that sequence's quadratic program exactly, `qp3`). Every bound's
    state is re-run as a plain cycle (`Band.confirmed`). refine=False: the samples only. States
    giving liftoff or no periodic cycle are left out; if none is valid the status says why.
    """
    one = np.ndim(psi_a_mrad) == 0
    bands = amplitude_bands(shape, mu, [psi_a_mrad] if one else psi_a_mrad, contacts, load,
                            n_samples=n_samples, refine=refine, steps=steps, starts=starts,
                            seed=seed, runner=runner)
    return bands[0] if one else bands


__all__ = ["Band", "BOUNDS", "BandKernel", "amplitude_band", "amplitude_bands", "amplitude_bands_unchecked",
           "compile_bands_ahead", "check_band_amplitudes", "check_band_options",
           "band_kernel", "state_cycle", "bands_program", "CONFIRM_TOL",
           "admissible_polytope", "polytope_vertices", "recession_rays", "VERTEX_SLOTS"]
