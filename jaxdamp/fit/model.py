"""The model's side of a loop (pure JAX, differentiable): the moment of an AmplitudeCycle's exact
steady loop at a travel phase, and one contact's force at a measured displacement along either
half. Exact: the cycle is piecewise linear in the travel."""

from __future__ import annotations

import jax.numpy as jnp

from ..conventions import travel_mm
from ..geometry import platform_moment

__all__ = ["loop_model_moment", "contact_path", "contact_loop_force"]


def loop_model_moment(ac, forward, u):
    """The moment (N mm) of an AmplitudeCycle's steady loop at travel phase (forward, u): u in
    [0, 1] the fraction of the half's travel 2 psi_a q* / 1e3 (mm) from the half's start. The loop is
    piecewise linear in travel, so this is exact; differentiable in every input of the cycle."""
    travel = 2.0 * travel_mm(ac.psi_a, ac.load.q_star)
    t = u * travel

    def on(half, t):
        m0 = platform_moment(ac.shape, ac.load, half.N0, half.T0)
        dm = platform_moment(ac.shape, ac.load, half.dN, half.dT)
        dv = jnp.where(half.active, half.dv, 0.0)
        start = jnp.cumsum(dv) - dv
        # tract j holds t when start_j <= t (the last active one that does)
        j = jnp.sum((start[None, :] <= t[:, None]) & half.active[None, :], axis=1) - 1
        j = jnp.clip(j, 0, dv.shape[0] - 1)
        return m0[j] + dm[j] * (t - start[j])

    return jnp.where(forward, on(ac.forward, t), on(ac.backward, t))


# Per-contact loops.
def _half_states(half, kt_i, kn_i, i, s_start):
    """Contact i at the vertices of a half (its start, every tract start, its end): (d_t, d_n, T, N,
    slip at the end). d_t = T / kt - slip (mm: the platform's tangential displacement relative to
    the damper at the contact, T = -kt (gt - slip) with gt = -d_t + const), d_n = N / kn (mm, the
    normal approach); forces in units of F_D; s_start the slip at the half's start (mm)."""
    dv = jnp.where(half.active, half.dv, 0.0)
    start = jnp.cumsum(dv) - dv
    t = jnp.concatenate([start, jnp.sum(dv)[None]])
    j = jnp.sum((start[None, :] <= t[:, None]) & half.active[None, :], axis=1) - 1
    j = jnp.clip(j, 0, dv.shape[0] - 1)
    h = t - start[j]
    T = half.T0[j, i] + half.dT[j, i] * h
    N = half.N0[j, i] + half.dN[j, i] * h
    ds = jnp.where(half.active, half.dslip[:, i], 0.0) * dv
    s = s_start + (jnp.cumsum(ds) - ds)[j] + half.dslip[j, i] * h
    return T / kt_i - s, N / kn_i, T, N, s[-1], half.active


def contact_path(ac, i, normal):
    """Contact i's (displacement mm, force in units of F_D) at the vertices of each half of an
    AmplitudeCycle's steady loop: ((d_fwd, f_fwd), (d_bwd, f_bwd), active tracts fwd, bwd), with
    d the tangential d_t = T / kt - slip or (normal) d_n = N / kn; exact (piecewise linear between
    the vertices in the travel, hence in d)."""
    kt_i = ac.contacts.kt[i] / ac.load.F_D if jnp.ndim(ac.contacts.kt) else ac.contacts.kt / ac.load.F_D
    kn_i = ac.contacts.kn[i] / ac.load.F_D if jnp.ndim(ac.contacts.kn) else ac.contacts.kn / ac.load.F_D
    dtf, dnf, Tf, Nf, sf, af = _half_states(ac.forward, kt_i, kn_i, i, 0.0)
    dtb, dnb, Tb, Nb, _, ab = _half_states(ac.backward, kt_i, kn_i, i, sf)
    pick = lambda a, b: jnp.where(normal, a, b)  # noqa: E731
    return (pick(dnf, dtf), pick(Nf, Tf)), (pick(dnb, dtb), pick(Nb, Tb)), af, ab


def _safe_div(a, b):
    ok = b != 0.0
    return jnp.where(ok, a / jnp.where(ok, b, 1.0), 0.0)


def _force_at(d, f, active, xq):
    """f at displacement xq along one half's vertices (d, f): piecewise linear; the segment is the
    last non-degenerate one starting at or before xq in the half's direction (the first one before
    the start, the last one carried on past the end)."""
    sgn = jnp.where(d[-1] >= d[0], 1.0, -1.0)
    z = sgn * d
    zq = sgn * xq
    dz = z[1:] - z[:-1]
    tol = 1e-12 * (jnp.max(jnp.abs(d)) + 1e-300)
    valid = active & (dz > tol)
    k = jnp.arange(dz.shape[0])
    cand = valid[None, :] & (z[None, :-1] <= zq[:, None])
    first = jnp.argmax(valid)
    kk = jnp.max(jnp.where(cand, k[None, :], -1), axis=1)
    kk = jnp.where(kk < 0, first, kk)
    slope = _safe_div(f[1:] - f[:-1], dz)
    return f[kk] + slope[kk] * (zq - z[kk])


def contact_loop_force(ac, i, normal, decreasing, x):
    """The model force (units of F_D) of contact i (tangential, or normal where `normal`) at the
    measured displacement x (mm, relative to the loop's centre: 0.5 (max + min) of the model's d
    over the cycle) on the half along which d decreases (`decreasing`) or increases. Exact,
    differentiable. Also returns whether d is monotone along both halves (else a force is not a
    function of d on a half, and the loop cannot be compared this way)."""
    (df, ff), (db, fb), af, ab = contact_path(ac, i, normal)
    allv = jnp.concatenate([df, db])
    centre = 0.5 * (jnp.max(allv) + jnp.min(allv))
    xq = x + centre
    fwd_dec = df[-1] < df[0]
    use_fwd = decreasing == fwd_dec
    F = jnp.where(use_fwd, _force_at(df, ff, af, xq), _force_at(db, fb, ab, xq))

    def mono(d, a):
        s = jnp.where(d[-1] >= d[0], 1.0, -1.0)
        dz = s * (d[1:] - d[:-1])
        return jnp.all(~a | (dz >= -1e-9 * (jnp.max(allv) - jnp.min(allv) + 1e-300)))

    return F, mono(df, af) & mono(db, ab)
