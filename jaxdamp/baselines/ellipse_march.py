"""The steady cycle on an elliptic platform path by quasi-static time marching: the independent
reference for `jaxdamp.elliptic_cycle`.

The path X(tau) = a (X_r cos tau - X_i sin tau) is marched in n_steps uniform steps of tau per
period. At each step the platform displacement is imposed on every pad (both components of the
path), and the damper's position solves equilibrium by Newton iterations with the contacts'
return mapping (`timemarch.respond`, `timemarch.newton`): no tracts, no event logic, no closed
forms. The first harmonics come from the uniform samples of the modal forces (the rectangle rule,
exact for trigonometric polynomials and second order for the loop's kinks), the energies from the
trapezoid rule on T d(slip). Histories, as `elliptic_cycle`'s: assembly (`timemarch.assemble`),
a straight move to X(pi) = -a X_r in n_steps/2 steps, then the path from tau = pi; or gross
slip: from assembly a straight move along +X_r of GROSS_SLIP_TRAVEL_MM beyond a (n_steps/2
steps; every pad that can slip does long before), then the path shifted by that travel so that
its tau = 0 point is where the move ended (a constant shift of the platforms changes nothing
but where the pads' anchors sit).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
from .._validate import check_int, check_range
from ..conventions import travel_mm
from ..geometry import is_wedge
from ..motion import (Motion, as_ellipse, motion_moment_coefficients, pad_motion, path_parts,
                      validate_motion)
from ..params import Contacts, LoadCase, prepare_inputs
from ..statics import contact_columns
from ..status import RESULTS, number_repr, status_repr
from .timemarch import MAX_NEWTON, NEWTON_TOL, MarchModel, assemble, newton, respond, step


HISTORIES = ("assembly", "gross_slip")
GROSS_SLIP_TRAVEL_MM = 5.0  # mm of s beyond a; a pad's stick range is mu F_D / kt ~ 0.1 mm


class EllipseMarch(NamedTuple):
    """k (N mm/mrad) and energies (N mm per cycle) of the last period marched, the fractions of
    its samples in which each pad slips and is open, the forces' change over it (units of F_D),
    Newton failures and the status (singular where Newton failed: no equilibrium found). Per-pad
    arrays in `geometry.pad_names` order."""

    k_re: jnp.ndarray
    k_im: jnp.ndarray
    energy: jnp.ndarray  # (P,) sum of T d(slip) per pad
    slip_fraction: jnp.ndarray  # (P,) of the last period's samples
    open_fraction: jnp.ndarray  # (P,)
    closure: jnp.ndarray
    newton_failures: jnp.ndarray
    status: jnp.ndarray

    def __repr__(self) -> str:
        return (f"EllipseMarch(status={status_repr(self.status)}, "
                f"k_re={number_repr(self.k_re, 'N mm/mrad')}, k_im={number_repr(self.k_im, 'N mm/mrad')})")


class PathModel(NamedTuple):
    """The marcher's constants on a path (a pytree): the damper's `MarchModel` from zero
    reference forces (its nw, tw are set per step), each pad's platform motion along the path's
    two basis directions X_r and X_i per mm of the path parameter s, and the modal forces' (fn,
    ft) per unit pad force along each."""

    m: MarchModel
    nw_r: jnp.ndarray
    tw_r: jnp.ndarray
    nw_i: jnp.ndarray
    tw_i: jnp.ndarray
    fn_r: jnp.ndarray
    ft_r: jnp.ndarray
    fn_i: jnp.ndarray
    ft_i: jnp.ndarray


def path_model(shape, mu, contacts, load, motion: Motion) -> PathModel:
    """The marcher's constants of one design on an elliptic (or zero-width) path. Unchecked,
    traceable."""
    along_r, along_i = path_parts(motion)
    # The model's platform motion is set per step below; its pads are the damper's (any pad set),
    # from the section's geometry and the motion's kinematics (MODEL.md), not from the engine's
    # constants (`ellipse.path_pads`) that this marcher checks.
    a, c, _ = contact_columns(shape)
    (nw_r, tw_r), (nw_i, tw_i) = (pad_motion(shape, m, load.q_star) for m in (along_r, along_i))
    per_pad = lambda k: jnp.broadcast_to(jnp.asarray(k, float), (a.shape[0],)) / load.F_D  # noqa: E731
    kn, kt = per_pad(contacts.kn), per_pad(contacts.kt)
    zero = jnp.zeros_like(kn)
    m = MarchModel(a, c, nw_r, tw_r, kn, kt, jnp.asarray(mu, float), zero, zero, zero, zero,
                   jnp.asarray(load.q_star, float), jnp.asarray(load.F_D, float))
    return PathModel(m, nw_r, tw_r, nw_i, tw_i, *motion_moment_coefficients(nw_r, tw_r, load),
                     *motion_moment_coefficients(nw_i, tw_i, load))


def path_start(pm: PathModel, s_a, initial: str, n_steps, n_load: int,
               max_newton: int = MAX_NEWTON):
    """The history before the path (module docstring): assembly in n_load levels, then the
    straight move in n_steps // 2 steps (n_steps may be traced). Returns (model at full load,
    state, shift of the path in mm of s, Newton failures). Unchecked, traceable."""
    m0, s, ok = assemble(pm.m, n_load, max_newton)
    gross = initial == "gross_slip"
    shift = GROSS_SLIP_TRAVEL_MM if gross else 0.0  # mm of s: where the path's tau = 0 point sits
    move = (s_a + shift) if gross else s_a
    n_move = n_steps // 2
    h, direction, dv0 = move / n_move, 1.0 if gross else -1.0, s.dv

    def one(k, carry):  # timemarch.march_half's steps, for a count that may be traced
        s, fails = carry
        s, smp = step(m0, s, dv0 + direction * h * k, max_newton)
        return s, fails + jnp.where(smp.newton_ok, 0, 1)

    s, fails = jax.lax.fori_loop(1, n_move + 1, one, (s, jnp.where(ok, 0, 1)))
    return m0, s, shift, fails


def path_step(pm: PathModel, m0: MarchModel, s_a, shift, carry, tau, max_newton: int = MAX_NEWTON):
    """One step of the path to tau from carry = (q, p): Newton with return mapping with the
    platforms at X(tau). Returns ((q, p), (N, T, p, M_r, M_i, converged, open, slipping)).
    Unchecked, traceable."""
    q, p = carry
    # The pads' platform displacement at tau: both components of the path at once (the
    # model's dv = 1 then carries it).
    u1, u2 = s_a * jnp.cos(tau) + shift, -s_a * jnp.sin(tau)
    here = m0._replace(nw=u1 * pm.nw_r + u2 * pm.nw_i, tw=u1 * pm.tw_r + u2 * pm.tw_i)

    def residual(x):
        r = respond(here, x, 1.0, p)
        return r.R, r.J

    q, res, _ = newton(residual, q, max_newton)
    r = respond(here, q, 1.0, p)
    sample = (r.N, r.T, r.p, r.N @ pm.fn_r + r.T @ pm.ft_r, r.N @ pm.fn_i + r.T @ pm.ft_i,
              res <= NEWTON_TOL, ~r.closed, r.slip)
    return (q, r.p), sample


@partial(jax.jit, static_argnames=("n_steps", "periods", "n_load", "max_newton", "initial"))
def _march_ellipse(shape, mu, contacts, load, amplitude, motion, n_steps: int, periods: int,
                   n_load: int, max_newton: int, initial: str):
    pm = path_model(shape, mu, contacts, load, motion)
    s_a = travel_mm(amplitude, load.q_star)
    m0, s, shift, fails = path_start(pm, s_a, initial, n_steps, n_load, max_newton)
    gross = initial == "gross_slip"

    def advance(carry, tau):
        return path_step(pm, m0, s_a, shift, carry, tau, max_newton)

    h = 2.0 * jnp.pi / n_steps
    if gross:  # the period starts where the straight move ended
        carry = (s.q, s.p)
        first = jax.eval_shape(lambda c: jax.lax.scan(advance, c, h * jnp.arange(1, 2))[1], carry)
    else:
        carry, first = jax.lax.scan(advance, (s.q, s.p), jnp.pi + h * jnp.arange(1, n_steps // 2 + 1))
        fails = fails + jnp.sum(~first[5])
    taus = h * jnp.arange(1, n_steps + 1)

    def period(c, _):
        carry, _ = c
        carry, smp = jax.lax.scan(advance, carry, taus)
        return (carry, smp), (smp[0][-1], smp[1][-1], smp[2][-1])  # forces and slips at tau = 2 pi

    init_smp = jax.tree_util.tree_map(lambda x: jnp.zeros((n_steps,) + x.shape[1:], x.dtype), first)
    (carry, smp), (N_end, T_end, p_end) = jax.lax.scan(period, (carry, init_smp), None,
                                                       length=periods)
    N, T, p, M_r, M_i, newton_ok, opened, slipping = smp
    fails = fails + jnp.sum(~newton_ok)
    # First harmonics of the periodic samples at tau_k = k h (k = 1..n: the same as 0..n-1).
    e = jnp.exp(-1j * taus)
    m_r, m_i = jnp.sum(M_r * e) * h, jnp.sum(M_i * e) * h
    k = (m_r - 1j * m_i) / (jnp.pi * amplitude)
    # Energy of the last period: trapezoids of T d(slip), from the previous period's last sample.
    T_prev = jnp.concatenate([T_end[-2][None], T[:-1]])
    p_prev = jnp.concatenate([p_end[-2][None], p[:-1]])
    energy = -load.F_D * jnp.sum(0.5 * (T + T_prev) * (p - p_prev), axis=0)
    closure = jnp.maximum(jnp.max(jnp.abs(N_end[-1] - N_end[-2])), jnp.max(jnp.abs(T_end[-1] - T_end[-2])))
    return EllipseMarch(jnp.real(k), jnp.imag(k), energy, jnp.mean(slipping.astype(float), axis=0),
                        jnp.mean(opened.astype(float), axis=0), closure, fails,
                        RESULTS.first({RESULTS.singular: fails > 0}))


def march_ellipse(shape, mu, amplitude_mrad, motion: Motion, contacts: Contacts = Contacts(),
                  load: LoadCase = LoadCase(), *, n_steps: int, periods: int = 4, n_load: int = 16,
                  max_newton: int = MAX_NEWTON, initial: str = "assembly") -> EllipseMarch:
    """The steady cycle on an elliptic path by time marching (module docstring), for checking
    `jaxdamp.elliptic_cycle` independently: n_steps (even) steps of tau per period, `periods`
    periods after the history ("assembly" or "gross_slip"); k and energies from the last one."""
    if initial not in HISTORIES:
        raise ValueError(f"initial must be one of {', '.join(HISTORIES)}; got {initial!r}")
    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load, wedge_ok=True)
    check_range("amplitude_mrad", amplitude_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    n_steps = check_int("n_steps", n_steps, 2)
    if n_steps % 2:
        raise ValueError(f"n_steps must be an even integer in [2, inf); got {n_steps}")
    motion = validate_motion(motion)
    if motion.quadrature is None:
        if not is_wedge(shape):
            raise ValueError("motion must be elliptic for march_ellipse (a straight path: "
                             "timemarch.march_amplitude)")
        motion = as_ellipse(motion)
    return _march_ellipse(shape, mu, contacts, load, jnp.asarray(float(amplitude_mrad)), motion,
                          n_steps, check_int("periods", periods, 2), check_int("n_load", n_load, 1),
                          check_int("max_newton", max_newton, 1), initial)


__all__ = ["EllipseMarch", "march_ellipse", "PathModel", "path_model", "path_start", "path_step",
           "HISTORIES", "GROSS_SLIP_TRAVEL_MM"]
