"""The exact minimum of a quadratic in R^3 over a polytope (pure JAX, vmap-able).

    minimise  q(d) = g . d + 1/2 d^T H d     subject to  A d + b >= 0     (m rows)

H may be indefinite (the band's k_Im is a quadratic of the initial state within one tract sequence,
of either curvature). On a bounded polytope the minimum sits on some face, and there it is a
stationary point of q restricted to the face's affine hull: a face of dimension 3 - |S| is the set
where a subset S of at most 3 constraints is active. So every subset S (|S| <= 3) gives one
candidate from the KKT system

    [ H    -A_S^T ] [d]   [  -g  ]
    [ A_S    0    ] [l] = [ -b_S ]

and the minimum is the smallest q among the candidates that satisfy every constraint (a singular
system, a face where q has no stationary point, gives none: its minimum is on a lower face, which
is enumerated too). m rows give sum_{k<=3} C(m, k) candidates (m = 15: 576), each in closed form.
The polytope must be bounded (a box row set does it); an empty polytope returns ok = False.
"""

from __future__ import annotations

import functools
import itertools

import jax.numpy as jnp
import numpy as np

from .linalg import solve3

__all__ = ["minimise_quadratic", "row_subsets", "FEASIBLE_TOL"]

FEASIBLE_TOL = 1e-12  # a candidate may violate a row by this (relative to the row's scale)


@functools.cache
def row_subsets(m: int, k: int) -> np.ndarray:
    """(n, k) subsets of exactly k of m rows, in itertools.combinations order."""
    return np.array(list(itertools.combinations(range(m), k)), np.int32).reshape(-1, k)


def _unit(v):
    n = jnp.linalg.norm(v, axis=-1, keepdims=True)
    return v / jnp.where(n > 0.0, n, 1.0)


def minimise_quadratic(g, H, A, b):
    """(d, q(d), ok): the global minimiser of g.d + d^T H d / 2 subject to A d + b >= 0.

    g (3,), H (3, 3) symmetric, A (m, 3), b (m,). ok is False where no candidate is feasible (then
    d = 0, q = 0). Values only (the band's refinement needs no derivative through it).

    Each face's stationary point in closed form (XLA on CPU runs a batch of small LU solves as a
    loop; these are elementwise): on a face of one active row a, d = d0 + Z y with Z an orthonormal
    basis of a's null space and a 2 x 2 solve for y; on an edge (rows a1, a2), d = d0 + y z along
    z = a1 x a2; at a vertex, the 3 x 3 solve of the three rows (Cramer's rule, `linalg.solve3`)."""
    g, H, A, b = (jnp.asarray(v, float) for v in (g, H, A, b))
    m = A.shape[0]
    scale = jnp.maximum(jnp.linalg.norm(A, axis=1), 1e-300)
    hscale = jnp.maximum(jnp.max(jnp.abs(H)), 1e-300)
    cands, oks = [], []

    # interior: H d = -g
    d, ok = solve3(H, -g)
    cands.append(d[None, :])
    oks.append(ok[None])

    # faces: a.d + beta = 0
    a, beta = A, b
    aa = jnp.sum(a * a, axis=1)
    d0 = -(beta / jnp.maximum(aa, 1e-300))[:, None] * a
    axis = jnp.eye(3)[jnp.argmin(jnp.abs(a), axis=1)]  # the axis least aligned with a
    u = _unit(jnp.cross(a, axis))
    v = _unit(jnp.cross(a, u))
    Hu, Hv = u @ H, v @ H  # H symmetric: rows of Z^T H
    m00, m01, m11 = jnp.sum(Hu * u, 1), jnp.sum(Hu * v, 1), jnp.sum(Hv * v, 1)
    r = g[None, :] + d0 @ H
    r0, r1 = -jnp.sum(u * r, 1), -jnp.sum(v * r, 1)
    det = m00 * m11 - m01 * m01
    ok = jnp.abs(det) > 1e-12 * hscale * hscale
    sdet = jnp.where(ok, det, 1.0)
    y0, y1 = (m11 * r0 - m01 * r1) / sdet, (m00 * r1 - m01 * r0) / sdet
    cands.append(d0 + y0[:, None] * u + y1[:, None] * v)
    oks.append(ok & (aa > 0.0))

    # edges: a1.d + b1 = 0 = a2.d + b2, free along z = a1 x a2
    if m >= 2:
        ij = row_subsets(m, 2)
        a1, a2, b1, b2 = A[ij[:, 0]], A[ij[:, 1]], b[ij[:, 0]], b[ij[:, 1]]
        z = jnp.cross(a1, a2)
        zn = jnp.linalg.norm(z, axis=1)
        g11, g12, g22 = jnp.sum(a1 * a1, 1), jnp.sum(a1 * a2, 1), jnp.sum(a2 * a2, 1)
        gdet = g11 * g22 - g12 * g12
        ok = zn > 1e-12 * scale[ij[:, 0]] * scale[ij[:, 1]]
        sg = jnp.where(ok, gdet, 1.0)
        l1, l2 = (-b1 * g22 + b2 * g12) / sg, (-b2 * g11 + b1 * g12) / sg
        d0 = l1[:, None] * a1 + l2[:, None] * a2
        z = _unit(z)
        zHz = jnp.sum((z @ H) * z, 1)
        curved = jnp.abs(zHz) > 1e-12 * hscale
        y = -jnp.sum(z * (g[None, :] + d0 @ H), 1) / jnp.where(curved, zHz, 1.0)
        cands.append(d0 + y[:, None] * z)
        oks.append(ok & curved)

    # vertices: three active rows
    if m >= 3:
        ijk = row_subsets(m, 3)
        d, ok = solve3(A[ijk], -b[ijk])
        cands.append(d)
        oks.append(ok)

    d = jnp.concatenate(cands)
    ok = jnp.concatenate(oks)
    d = jnp.where(ok[:, None], d, 0.0)
    feasible = ok & jnp.all(d @ A.T + b[None, :] >= -FEASIBLE_TOL * scale[None, :] * (
        1.0 + jnp.max(jnp.abs(d), axis=1, keepdims=True)), axis=1)
    q = d @ g + 0.5 * jnp.sum((d @ H) * d, axis=1)
    q = jnp.where(feasible, q, jnp.inf)
    best = jnp.argmin(q)
    found = jnp.isfinite(q[best])
    return jnp.where(found, d[best], 0.0), jnp.where(found, q[best], 0.0), found
