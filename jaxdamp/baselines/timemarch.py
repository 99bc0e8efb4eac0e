"""An independent, conventional solver: quasi-static time marching with incremental return mapping.

This is what a general-purpose friction-contact code does with the same damper model (rigid 3-DOF
damper, three Jenkins contacts): prescribe the relative platform motion dv in small steps, and at
each step solve the damper's nonlinear (piecewise-linear) equilibrium by Newton iterations with a
per-contact return mapping (trial stick, projection onto the Coulomb cone, open contact when the
normal force would be negative) and the consistent tangent. It shares no state-choice or event logic
with the direct method (`tract.py`, `cycle.py`); it reuses only the geometry and the full-slip
statics that define the cycle start (state 0). It serves as an independent check of the direct
method and as the conventional baseline in `benchmarks/speed_accuracy.py`.

Formulation (forces normalised to F_D = 1 inside, like the direct solver; lengths in mm). The damper
displacement q = (u, v, theta) at D, the platform motion dv and the accumulated slips p are all
measured from state 0, where the forces are the full-slip statics (N_ref, T_ref):

    N_i = max(0, N_ref_i + kn_i (a_i.q - nw_i dv))
    T_i = T_ref_i - kt_i (c_i.q - tw_i dv - p_i)   projected onto |T_i| <= mu N_i (T_i = 0 if open)
    R(q) = sum_i (-N_i a_i + T_i c_i) + e_y = 0     (equilibrium of the rigid damper, F_D at D)

The five numbers are then taken the way a time-marching user would take them (see `time_march`).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..linalg import solve3
from .._validate import check_int, check_range
from ..geometry import DamperShape
from ..params import Contacts, LoadCase, prepare_inputs
from ..conventions import (CENTRIFUGAL_LOAD, MRAD_PER_RAD, START_FRICTION_SIGNS,
                           psi_mrad, travel_mm)
from ..motion import loop_moment_coefficients, pad_motion, validate_motion
from ..statics import contact_columns, full_slip_state
from ..status import RESULTS

NEWTON_TOL = 1e-12  # equilibrium residual, units of F_D
GROSS_TOL = 1e-9  # incremental force rate (per mm) below which the damper is in gross slip, x k/F_D
CLOSE_TOL = 1e-9  # end-state repeat tolerance on forces (units of F_D)
MAX_PAIRS = 10
MAX_NEWTON = 12
MIN_ALPHA = 1.0 / 64.0  # smallest line-search step fraction


class MarchModel(NamedTuple):
    """Constant data of the time-marching model (a pytree of arrays; forces in units of F_D,
    stiffness per F_D in 1/mm, moments in N mm; per-contact arrays (3,) in R1, L1, L2 order)."""

    a: jnp.ndarray  # (3, 3) generalised outward normals about D, one row per contact (R1, L1, L2)
    c: jnp.ndarray  # (3, 3) generalised up-flank tangents
    nw: jnp.ndarray  # (3,) normal motion of each contact's platform per unit dv
    tw: jnp.ndarray  # (3,) tangential motion of each contact's platform per unit dv
    kn: jnp.ndarray  # (3,) kn / F_D, 1/mm
    kt: jnp.ndarray  # (3,) kt / F_D, 1/mm
    mu: jnp.ndarray
    N_ref: jnp.ndarray  # (3,) forces at state 0 (q = 0, dv = 0, p = 0)
    T_ref: jnp.ndarray
    fn: jnp.ndarray  # (3,) platform moment (N mm) per unit normal force (units of F_D)
    ft: jnp.ndarray  # (3,) platform moment (N mm) per unit tangential force
    q_star: jnp.ndarray
    F_D: jnp.ndarray


def march_model(shape: DamperShape, mu, contacts: Contacts, load: LoadCase, motion=None):
    """(model, liftoff_at_start): the model whose reference state 0 is the cycle-start full slip.
    Inputs as `jaxdamp.base_cycle` (angles in degrees, kn, kt in N/mm, F_D in N, q* in mm); the
    model holds forces in units of F_D and stiffness per F_D (1/mm). motion: None (in-phase, dv
    in mm) or a straight `jaxdamp.Motion` ("dv" is then its path parameter a q*/1e3, mm, and the
    moment its modal force). Unchecked, traceable."""
    a, c, geo = contact_columns(shape)
    kn, kt = contacts.per_contact()
    F_D = jnp.asarray(load.F_D, float)
    mu = jnp.asarray(mu, float)
    start = full_slip_state(shape, mu, START_FRICTION_SIGNS)
    lift0 = (start.min_normal <= 0.0) | ~start.solvable
    N_ref = jnp.where(lift0, jnp.ones(3), start.N)  # keep the masked computation finite
    T_ref = START_FRICTION_SIGNS * mu * N_ref
    fn, ft = loop_moment_coefficients(shape, load._replace(F_D=F_D), motion)
    nw, tw = pad_motion(shape, motion, load.q_star)
    model = MarchModel(a, c, nw, tw, kn / F_D, kt / F_D, mu,
                       N_ref, T_ref, fn, ft, jnp.asarray(load.q_star, float), F_D)
    return model, lift0


class Response(NamedTuple):
    """Return-mapped contact response at a trial damper position."""

    N: jnp.ndarray
    T: jnp.ndarray
    p: jnp.ndarray  # updated slips
    closed: jnp.ndarray
    slip: jnp.ndarray
    sign: jnp.ndarray
    R: jnp.ndarray  # equilibrium residual
    J: jnp.ndarray  # consistent tangent dR/dq


def respond(m: MarchModel, q, dv, p_old) -> Response:
    """Return mapping of the three contacts for damper position q (3,) and platform motion dv (mm):
    forces N, T (3,) in units of F_D, slips and stick/slip codes."""
    gn = m.a @ q - m.nw * dv
    gt = m.c @ q - m.tw * dv
    N_tr = m.N_ref + m.kn * gn
    closed = N_tr > 0.0
    N = jnp.where(closed, N_tr, 0.0)
    T_tr = m.T_ref - m.kt * (gt - p_old)
    sign = jnp.where(T_tr >= 0.0, 1.0, -1.0)
    slip = closed & (jnp.abs(T_tr) > m.mu * N)
    T = jnp.where(closed, jnp.where(slip, sign * m.mu * N, T_tr), 0.0)
    p = gt - (m.T_ref - T) / m.kt
    R = -m.a.T @ N + m.c.T @ T + CENTRIFUGAL_LOAD
    dN = jnp.where(closed, m.kn, 0.0)[:, None] * m.a
    dT = jnp.where((closed & slip)[:, None], (sign * m.mu * m.kn)[:, None] * m.a,
                   jnp.where(closed, -m.kt, 0.0)[:, None] * m.c)
    J = -m.a.T @ dN + m.c.T @ dT
    return Response(N, T, p, closed, slip, sign, R, J)


def force_rates(m: MarchModel, r: Response):
    """Consistent incremental rates (dN/ddv, dT/ddv, dq/ddv) at a converged state, and solvability."""
    dN_dv = jnp.where(r.closed, -m.kn * m.nw, 0.0)
    dT_dv = jnp.where(r.closed, jnp.where(r.slip, r.sign * m.mu * dN_dv, m.kt * m.tw), 0.0)
    dR_dv = -m.a.T @ dN_dv + m.c.T @ dT_dv
    dq, ok = solve3(r.J, -dR_dv)
    dN = jnp.where(r.closed, m.kn, 0.0) * (m.a @ dq) + dN_dv
    dT = jnp.where(r.closed, jnp.where(r.slip, r.sign * m.mu * m.kn * (m.a @ dq),
                                       -m.kt * (m.c @ dq)), 0.0) + dT_dv
    return dN, dT, dq, ok


class MarchState(NamedTuple):
    """The marcher's state after a step: damper displacement, platform travel dv (mm), slips, and
    the contact forces N, T (3,) in units of F_D, all measured from state 0."""

    q: jnp.ndarray  # (3,) damper displacement from state 0
    dv: jnp.ndarray  # relative platform displacement from state 0, mm
    p: jnp.ndarray  # (3,) accumulated slips
    N: jnp.ndarray
    T: jnp.ndarray
    vel: jnp.ndarray  # (3,) consistent tangent dq/ddv at this state (the next step's predictor)


class Sample(NamedTuple):
    """What a step records (arrays with a leading step axis after `march`): dv (mm), N, T, p (3,)
    in units of F_D and mm, the moment M (N mm), stick/slip codes and flags."""

    dv: jnp.ndarray
    N: jnp.ndarray
    T: jnp.ndarray
    p: jnp.ndarray
    M: jnp.ndarray  # platform moment, N mm
    code: jnp.ndarray  # per contact: 0 stick, 1 slip up (+), 2 slip down (-), 3 open
    gross: jnp.ndarray  # incremental stiffness ~ 0 at the end of the step (gross slip)
    newton_ok: jnp.ndarray  # Newton reached the tolerance
    iters: jnp.ndarray


def initial_state(m: MarchModel) -> MarchState:
    """State 0: the cycle-start full slip (no displacement, dv = 0 mm, forces N_ref, T_ref in F_D)."""
    z = jnp.zeros(3)
    return MarchState(z, jnp.zeros(()), z, m.N_ref, m.T_ref, z)


def moment_of(m: MarchModel, N, T):
    return jnp.sum(N * m.fn + T * m.ft, axis=-1)


def newton(residual, q0, max_newton: int = MAX_NEWTON):
    """Newton iterations on residual(q) -> (R, J) from q0, with a backtracking line search (halving
    the step while the largest residual does not decrease, down to MIN_ALPHA) so that an iterate
    does not jump into a region where a contact opens and the tangent is singular.

    Returns (q, max |R|, iterations)."""
    R0, J0 = residual(q0)

    def cond(c):
        _, R, _, it = c
        return (it < max_newton) & (jnp.max(jnp.abs(R)) > NEWTON_TOL)

    def body(c):
        q, R, J, it = c
        dq, _ = solve3(J, -R)
        r0 = jnp.max(jnp.abs(R))

        def ls_cond(t):
            alpha, Rn, _ = t
            return (alpha > MIN_ALPHA) & (jnp.max(jnp.abs(Rn)) > (1.0 - 1e-4 * alpha) * r0)

        def ls_body(t):
            alpha = 0.5 * t[0]
            Rn, Jn = residual(q + alpha * dq)
            return alpha, Rn, Jn

        R1, J1 = residual(q + dq)
        alpha, Rn, Jn = jax.lax.while_loop(ls_cond, ls_body, (jnp.asarray(1.0), R1, J1))
        return q + alpha * dq, Rn, Jn, it + 1

    q, R, _, iters = jax.lax.while_loop(cond, body, (q0, R0, J0, jnp.array(0)))
    return q, jnp.max(jnp.abs(R)), iters


def step(m: MarchModel, s: MarchState, dv_new, max_newton: int = MAX_NEWTON):
    """One load step to platform travel dv_new (mm): Newton on R(q) = 0 with return mapping, from
    the tangent predictor. Returns (state, Sample)."""
    q0 = s.q + s.vel * (dv_new - s.dv)

    def residual(q):
        r = respond(m, q, dv_new, s.p)
        return r.R, r.J

    q, res, iters = newton(residual, q0, max_newton)
    r = respond(m, q, dv_new, s.p)
    dN, dT, vel, ok = force_rates(m, r)
    scale = jnp.max(jnp.maximum(m.kn, m.kt))
    gross = ok & (jnp.max(jnp.abs(jnp.concatenate([dN, dT]))) <= GROSS_TOL * scale)
    code = jnp.where(r.closed, jnp.where(r.slip, jnp.where(r.sign > 0, 1, 2), 0), 3)
    new = MarchState(q, jnp.asarray(dv_new, float), r.p, r.N, r.T, vel)
    sample = Sample(new.dv, r.N, r.T, r.p, moment_of(m, r.N, r.T), code, gross, res <= NEWTON_TOL,
                    iters)
    return new, sample


def march(m: MarchModel, s: MarchState, dv_path, max_newton: int = MAX_NEWTON):
    """March along dv_path (n,): (end state, samples). Unchecked, traceable (jit, vmap, grad)."""
    return jax.lax.scan(lambda c, dv: step(m, c, dv, max_newton), s, dv_path)


class HalfMarch(NamedTuple):
    """One half-cycle marched at a uniform step h; samples include the start (index 0)."""

    samples: Sample  # leading axis n_steps + 1
    gross_step: jnp.ndarray  # first step index ending in gross slip (n_steps + 1 if never)


def march_half(m: MarchModel, s: MarchState, direction, h, n_steps: int, max_newton: int = MAX_NEWTON):
    """March one half-cycle from s: n_steps steps of h (mm of platform travel dv) in direction
    (+1 or -1). Returns (end state, HalfMarch) with the n_steps + 1 samples, start included."""
    path = s.dv + direction * h * jnp.arange(1, n_steps + 1, dtype=float)
    end, smp = march(m, s, path, max_newton)
    first = Sample(s.dv, s.N, s.T, s.p, moment_of(m, s.N, s.T), jnp.zeros(s.N.shape, int),
                   jnp.array(False),
                   jnp.array(True), jnp.array(0))
    smp = jax.tree_util.tree_map(lambda x0, xs: jnp.concatenate([x0[None], xs]), first, smp)
    idx = jnp.arange(n_steps + 1)
    gross_step = jnp.min(jnp.where(smp.gross & (idx > 0), idx, n_steps + 1))
    return end, HalfMarch(smp, gross_step)


class TimeMarchResult(NamedTuple):
    """The five numbers as a time-marching user obtains them, plus energies and status flags.

    psi in mrad, k in N mm/mrad, energy in N mm per cycle, spans in mm.
    """

    psi_fs: jnp.ndarray
    k_re_fs: jnp.ndarray
    psi_bc: jnp.ndarray
    k_re_bc: jnp.ndarray
    k_im_bc: jnp.ndarray
    k_im_energy: jnp.ndarray  # k_Im from sum of T d(slip) over the contacts: W / (pi psi_BC^2)
    work_contacts: jnp.ndarray  # (3,) energy dissipated at R1, L1, L2 per cycle
    work_moment: jnp.ndarray  # oint M dpsi of the sampled loop
    span_forward: jnp.ndarray
    span_backward: jnp.ndarray
    N_C: jnp.ndarray  # (3,) forces (units of F_D) at the end of the forward half (gross slip, point C)
    T_C: jnp.ndarray
    N_F: jnp.ndarray  # (3,) forces at the end of the backward half (point F)
    T_F: jnp.ndarray
    half_cycles: jnp.ndarray
    newton_failures: jnp.ndarray  # steps whose Newton iterations did not reach the tolerance
    # RESULTS code: liftoff (a contact opened, N = 0, or the start statics has N <= 0), else
    # singular (Newton did not converge, or gross slip was not reached in n_steps), else
    # not_converged (the cycle's end state did not repeat within max_pairs), else ok
    status: jnp.ndarray


def loop_harmonics(M_fwd, M_bwd, K, psi_a_mrad):
    """First harmonic of a moment loop sampled at uniform psi steps (quadrature of the samples).

    M_fwd, M_bwd: samples at x = cos(tau) = 1 - 2k/K (forward) and -1 + 2k/K (backward), k = 0..K;
    samples beyond K are ignored. The samples are joined linearly and the Fourier integrals of that
    interpolant are taken exactly (product integration). Returns (k_Re, k_Im, work in N mm) with
    M ~ psi_a (k_Re cos tau - k_Im sin tau).
    """
    n = M_fwd.shape[0]
    k = jnp.arange(n, dtype=float)
    use = (k[1:] <= K)

    def half(M, branch):
        x = branch * jnp.clip(1.0 - 2.0 * k / K, -1.0, 1.0)
        x1, x2, m1, m2 = x[:-1], x[1:], M[:-1], M[1:]
        dx = x2 - x1
        beta = jnp.where(use, (m2 - m1) / jnp.where(use, dx, 1.0), 0.0)
        alpha = m1 - beta * x1
        t1, t2 = jnp.arccos(jnp.clip(x1, -1, 1)), jnp.arccos(jnp.clip(x2, -1, 1))
        if branch < 0:  # tau in [pi, 2 pi]
            t1, t2 = 2 * jnp.pi - t1, 2 * jnp.pi - t2
        s1, s2 = jnp.sin(t1), jnp.sin(t2)
        f_cos = alpha * (s2 - s1) + 0.5 * beta * ((t2 + s2 * x2) - (t1 + s1 * x1))
        f_sin = 0.5 * (m1 + m2) * (x1 - x2)  # int M sin(tau) dtau = -int M dx
        return jnp.sum(jnp.where(use, f_cos, 0.0)), jnp.sum(jnp.where(use, f_sin, 0.0))

    c1, s1 = half(M_fwd, 1.0)
    c2, s2 = half(M_bwd, -1.0)
    k_re = (c1 + c2) / (jnp.pi * psi_a_mrad)
    k_im = -(s1 + s2) / (jnp.pi * psi_a_mrad)
    work = jnp.pi * psi_a_mrad ** 2 * k_im * 1e-3  # N mm (psi in mrad)
    return k_re, k_im, work


def _dissipated(smp: Sample, K, F_D):
    """sum over steps 1..K of -(T_k-1 + T_k)/2 (p_k - p_k-1), per contact, N mm."""
    k = jnp.arange(1, smp.T.shape[0])
    use = (k <= K)[:, None]
    w = -0.5 * (smp.T[1:] + smp.T[:-1]) * (smp.p[1:] - smp.p[:-1])
    return F_D * jnp.sum(jnp.where(use, w, 0.0), axis=0)


@partial(jax.jit, static_argnames=("n_steps", "max_pairs", "max_newton"))
def time_march_kernel(shape, mu, contacts, load, h, n_steps: int, max_pairs: int = MAX_PAIRS,
                max_newton: int = MAX_NEWTON) -> TimeMarchResult:
    m, lift0 = march_model(shape, mu, contacts, load)
    h = jnp.asarray(h, float)
    s0 = initial_state(m)

    def pair(s):
        s1, fwd = march_half(m, s, -1.0, h, n_steps, max_newton)
        s2, bwd = march_half(m, s1, 1.0, h, n_steps, max_newton)
        return s2, fwd, bwd

    def bad_half(hm):
        smp = hm.samples
        lift = jnp.any(smp.code == 3)
        fail = ~jnp.all(smp.newton_ok) | (hm.gross_step > n_steps)
        return lift, fail

    def cond(c):
        return (c["k"] < max_pairs) & ~c["stop"]

    def body(c):
        s2, fwd, bwd = pair(c["s"])
        lf, ff = bad_half(fwd)
        lb, fb = bad_half(bwd)
        closed = (jnp.max(jnp.abs(s2.N - c["s"].N)) + jnp.max(jnp.abs(s2.T - c["s"].T))) <= CLOSE_TOL
        bad = lf | lb | ff | fb
        return dict(s=s2, fwd=fwd, bwd=bwd, k=c["k"] + 1, stop=closed | bad, closed=closed & ~bad,
                    lift=lf | lb, fail=ff | fb)

    _, fwd0, bwd0 = jax.eval_shape(pair, s0)
    zeros = lambda t: jax.tree_util.tree_map(lambda x: jnp.zeros(x.shape, x.dtype), t)  # noqa: E731
    init = dict(s=s0, fwd=zeros(fwd0), bwd=zeros(bwd0), k=jnp.array(0), stop=lift0,
                closed=jnp.array(False), lift=jnp.array(False), fail=jnp.array(False))
    out = jax.lax.while_loop(cond, body, init)
    fwd, bwd = out["fwd"], out["bwd"]
    liftoff = lift0 | out["lift"]

    # psi_BC: the longer half-span, from the first step that ends in gross slip.
    K = jnp.maximum(fwd.gross_step, bwd.gross_step)
    Kf = jnp.maximum(K, 1).astype(float)
    span_f, span_b = fwd.gross_step * h, bwd.gross_step * h
    psi_bc = psi_mrad(Kf * h / 2.0, m.q_star)
    k_re_bc, k_im_bc, work_m = loop_harmonics(fwd.samples.M, bwd.samples.M, Kf, psi_bc)
    work_c = _dissipated(fwd.samples, K, m.F_D) + _dissipated(bwd.samples, K, m.F_D)
    k_im_energy = jnp.sum(work_c) * MRAD_PER_RAD / (jnp.pi * psi_bc ** 2)

    # psi_fs: the first tract ends in the first step whose contact states differ from those of step 1;
    # take the middle of that step. k_Re,fs: the slope of the first step.
    code = fwd.samples.code
    idx = jnp.arange(code.shape[0])
    changed = jnp.any(code != code[1][None], axis=1) & (idx > 1)
    j = jnp.min(jnp.where(changed | (idx == fwd.gross_step), idx, n_steps + 1))
    psi_fs = psi_mrad((j - 0.5) * h / 2.0, m.q_star)
    M = fwd.samples.M
    k_re_fs = (M[1] - M[0]) / (-h) * travel_mm(1.0, m.q_star)

    newton_fail = jnp.where(out["k"] > 0, jnp.sum(~fwd.samples.newton_ok)
                            + jnp.sum(~bwd.samples.newton_ok), 0)
    failed = ~liftoff & out["fail"]
    return TimeMarchResult(psi_fs, k_re_fs, psi_bc, k_re_bc, k_im_bc, k_im_energy, work_c, work_m,
                           span_f, span_b, fwd.samples.N[-1], fwd.samples.T[-1], bwd.samples.N[-1],
                           bwd.samples.T[-1], 2 * out["k"], newton_fail,
                           RESULTS.first({RESULTS.liftoff: liftoff, RESULTS.singular: failed,
                                         RESULTS.not_converged: ~(out["closed"] & ~liftoff)}))


def time_march(shape: DamperShape, mu, contacts: Contacts = Contacts(), load: LoadCase = LoadCase(),
               *, h, n_steps: int, max_pairs: int = MAX_PAIRS,
               max_newton: int = MAX_NEWTON) -> TimeMarchResult:
    """The five numbers by quasi-static time marching at a fixed step h (mm of relative platform
    motion), n_steps steps per half-cycle.

    Procedure (what a time-marching user does): start at the full-slip statics (state 0); march the
    forward half (dv decreasing) for n_steps steps; a half reaches gross slip at the first step whose
    consistent incremental stiffness is ~0. Reverse, march back; repeat pairs of halves until the end
    state repeats (at most max_pairs). Then psi_BC = (longer half-span)/(2 q*) with a span measured
    in whole steps; k_Re,BC and k_Im,BC from the first harmonic of the sampled moment loop at
    amplitude psi_BC; psi_fs from the first step where the contact states change (middle of that
    step); k_Re,fs from the first step's slope. n_steps * h must exceed the longer half-span, or the
    result is flagged `failed`. Liftoff, Newton failures and non-closure are flags, never NaN.
    """
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("h", h, 0.0, np.inf, lo_open=True, unit="mm")
    return time_march_kernel(shape, mu, contacts, load, jnp.asarray(h, float),
                       n_steps=check_int("n_steps", n_steps, 2), max_pairs=check_int("max_pairs", max_pairs, 1),
                       max_newton=check_int("max_newton", max_newton, 1))


# ---------------------------------------------------------------- cycles at a prescribed amplitude
def model_from_state(m: MarchModel, N, T) -> MarchModel:
    """The model whose reference state (q = 0, dv = 0, p = 0) carries the forces N, T (units of F_D).
    (N, T) must be in equilibrium with F_D for q = 0 to be the equilibrium at dv = 0."""
    return m._replace(N_ref=jnp.asarray(N, float), T_ref=jnp.asarray(T, float))


def assemble(m: MarchModel, n_load: int, max_newton: int = MAX_NEWTON):
    """Apply F_D from zero in n_load equal steps with the platforms held (dv = 0), from zero contact
    forces: Newton with return mapping at each load level. Returns (model with zero reference
    forces, the state at full load, Newton converged at every level)."""
    z = jnp.zeros_like(m.kn)  # one per pad
    m0 = m._replace(N_ref=z, T_ref=z)
    K0 = (jnp.einsum("i,ij,ik->jk", m0.kn, m0.a, m0.a) + jnp.einsum("i,ij,ik->jk", m0.kt, m0.c, m0.c))
    q_unit, _ = solve3(K0, CENTRIFUGAL_LOAD)  # all-stick response to F_D: the first level's predictor

    def level(carry, lam):
        q, p, lam_old = carry
        q0 = jnp.where(lam_old > 0.0, q * lam / jnp.where(lam_old > 0.0, lam_old, 1.0), lam * q_unit)

        def residual(x):
            r = respond(m0, x, 0.0, p)
            return r.R - (1.0 - lam) * CENTRIFUGAL_LOAD, r.J

        qn, res, _ = newton(residual, q0, max_newton)
        r = respond(m0, qn, 0.0, p)
        return (qn, r.p, lam), res <= NEWTON_TOL

    lams = jnp.arange(1, n_load + 1, dtype=float) / n_load
    (q, p, _), conv = jax.lax.scan(level, (jnp.zeros(3), z, jnp.asarray(0.0)), lams)
    r = respond(m0, q, 0.0, p)
    _, _, vel, _ = force_rates(m0, r)
    return m0, MarchState(q, jnp.zeros(()), r.p, r.N, r.T, vel), jnp.all(conv)


class AmplitudeMarch(NamedTuple):
    """A steady cycle at a prescribed amplitude psi_a (mrad) by time marching (see
    `march_amplitude`): k_Re, k_Im in N mm/mrad, energy in N mm per cycle, flags and status."""

    k_re: jnp.ndarray  # N mm/mrad, first harmonic of the sampled moment loop of the last pair
    k_im: jnp.ndarray
    work_contacts: jnp.ndarray  # (3,) N mm per cycle, sum of T d(slip) over the steps
    work_moment: jnp.ndarray  # pi psi_a^2 k_Im, N mm
    closure: jnp.ndarray  # (max_pairs,) max force change over each pair (units of F_D)
    N_start: jnp.ndarray  # forces at the forward extreme before the last pair
    T_start: jnp.ndarray
    newton_failures: jnp.ndarray
    M_forward: jnp.ndarray  # (n_steps + 1,) moment samples of the last pair, N mm
    M_backward: jnp.ndarray
    # RESULTS code: liftoff (a contact opened), else not_converged (a Newton iteration failed), else
    # ok; the cycle's closure is in `closure`
    status: jnp.ndarray


@partial(jax.jit, static_argnames=("initial", "n_steps", "max_pairs", "n_load", "max_newton"))
def _march_amplitude(shape, mu, contacts, load, psi_a_mrad, N_init, T_init, initial: str,
                     n_steps: int, max_pairs: int, n_load: int, max_newton: int = MAX_NEWTON,
                     motion=None):
    m, lift0 = march_model(shape, mu, contacts, load, motion)
    a_dv = travel_mm(psi_a_mrad, m.q_star)
    h = 2.0 * a_dv / n_steps
    fails = jnp.array(0)
    lift = lift0
    if initial == "gross_slip":
        s = initial_state(m)
    elif initial == "explicit":
        m = model_from_state(m, N_init, T_init)
        s = initial_state(m)
        lift = jnp.min(m.N_ref) <= 0.0
    else:  # assembly: load at mid travel, a quarter travel forward, a backward half to the top
        m, s, ok = assemble(m, n_load, max_newton)
        lift = jnp.array(False)
        fails = fails + jnp.where(ok, 0, 1)
        s, q1 = march_half(m, s, -1.0, h, n_steps // 2, max_newton)
        s, q2 = march_half(m, s, 1.0, h, n_steps, max_newton)
        for hm in (q1, q2):
            fails = fails + jnp.sum(~hm.samples.newton_ok)
            lift = lift | jnp.any(hm.samples.code == 3)

    def pair(s, _):
        s1, fwd = march_half(m, s, -1.0, h, n_steps, max_newton)
        s2, bwd = march_half(m, s1, 1.0, h, n_steps, max_newton)
        gap = jnp.maximum(jnp.max(jnp.abs(s2.N - s.N)), jnp.max(jnp.abs(s2.T - s.T)))
        # Restart the next pair exactly at the top: dv drifts by rounding otherwise.
        return s2, (gap, fwd, bwd, s.N, s.T)

    _, (gaps, fwd, bwd, Ns, Ts) = jax.lax.scan(pair, s, None, length=max_pairs)
    last = lambda t: jax.tree_util.tree_map(lambda x: x[-1], t)  # noqa: E731
    fwd, bwd = last(fwd), last(bwd)
    k_re, k_im, work_m = loop_harmonics(fwd.samples.M, bwd.samples.M, float(n_steps), psi_a_mrad)
    work_c = _dissipated(fwd.samples, n_steps, m.F_D) + _dissipated(bwd.samples, n_steps, m.F_D)
    fails = fails + jnp.sum(~fwd.samples.newton_ok) + jnp.sum(~bwd.samples.newton_ok)
    lift = lift | jnp.any(fwd.samples.code == 3) | jnp.any(bwd.samples.code == 3)
    return AmplitudeMarch(k_re, k_im, work_c, work_m, gaps, Ns[-1], Ts[-1], fails,
                          fwd.samples.M, bwd.samples.M, RESULTS.first({RESULTS.liftoff: lift, RESULTS.not_converged: fails != 0}))


def march_amplitude(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                    load: LoadCase = LoadCase(), *, initial="gross_slip", n_steps: int,
                    max_pairs: int = 6, n_load: int = 16,
                    max_newton: int = MAX_NEWTON, motion=None) -> AmplitudeMarch:
    """The steady cycle at amplitude psi_a (mrad) by time marching, for checking
    `jaxdamp.amplitude` independently.

    The relative platform motion runs between the two extremes in n_steps uniform steps per half
    (exact reversals: the last step of a half lands on the extreme), forward half (dv decreasing)
    first, max_pairs pairs; k from the first harmonic of the last pair's moment samples joined
    linearly (`loop_harmonics`). initial: "gross_slip" (state 0 at the forward extreme), "assembly"
    (F_D applied in n_load steps at mid travel from zero forces, then a quarter travel forward in
    n_steps/2 steps and a backward half), or an explicit (N, T) pair at the forward extreme (units
    of F_D, in equilibrium with F_D). Newton failures and liftoff are reported, never NaN.
    motion: None (in-phase) or a straight `jaxdamp.Motion`, with "assembly" or an explicit start
    (the marcher has no gross-slip start on a path).
    """
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, np.inf, lo_open=True, unit="mrad")
    n_steps = check_int("n_steps", n_steps, 2)
    if n_steps % 2:
        raise ValueError(f"n_steps must be an even integer in [2, inf); got {n_steps}")
    N_init = T_init = None
    if isinstance(initial, str):
        if initial not in ("gross_slip", "assembly"):
            raise ValueError(f"initial must be gross_slip, assembly or an (N, T) pair; got {initial!r}")
        mode = initial
    else:
        N_init, T_init = (jnp.asarray(v, float) for v in initial)
        mode = "explicit"
    if motion is not None:
        motion = validate_motion(motion)
        if mode == "gross_slip":
            raise ValueError("initial must be assembly or an (N, T) pair on a path (motion given); "
                             "got 'gross_slip'")
    return _march_amplitude(shape, mu, contacts, load, jnp.asarray(psi_a_mrad, float), N_init,
                            T_init, mode, n_steps, check_int("max_pairs", max_pairs, 1),
                            check_int("n_load", n_load, 1), check_int("max_newton", max_newton, 1),
                            motion=motion)


__all__ = ["time_march", "TimeMarchResult", "march_model", "march", "march_half", "step", "newton", "respond",
           "loop_harmonics", "MarchModel", "MarchState", "Sample", "initial_state", "march_amplitude",
           "AmplitudeMarch", "assemble", "model_from_state"]
