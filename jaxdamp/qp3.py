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
is enumerated too). m rows give sum_{k<=3} C(m, k) solves of a 6 x 6 system (m = 15: 576).
The polytope must be bounded (a box row set does it); an empty polytope returns ok = False.
"""

from __future__ import annotations

import itertools
from functools import lru_cache

import jax
import jax.numpy as jnp
import numpy as np

__all__ = ["minimise_quadratic", "FEASIBLE_TOL"]

FEASIBLE_TOL = 1e-12  # a candidate may violate a row by this (relative to the row's scale)


@lru_cache(maxsize=None)
def _subsets(m: int) -> np.ndarray:
    """(n, 3) active sets of at most 3 of m rows, padded with -1."""
    rows = [(-1, -1, -1)]
    for k in (1, 2, 3):
        rows += [tuple(c) + (-1,) * (3 - k) for c in itertools.combinations(range(m), k)]
    return np.array(rows, np.int32)


def minimise_quadratic(g, H, A, b):
    """(d, q(d), ok): the global minimiser of g.d + d^T H d / 2 subject to A d + b >= 0.

    g (3,), H (3, 3) symmetric, A (m, 3), b (m,). ok is False where no candidate is feasible (then
    d = 0, q = 0). Values only (the band's refinement needs no derivative through it)."""
    g, H, A, b = (jnp.asarray(v, float) for v in (g, H, A, b))
    m = A.shape[0]
    sets = jnp.asarray(_subsets(m))
    scale = jnp.maximum(jnp.linalg.norm(A, axis=1), 1e-300)

    def candidate(s):
        used = s >= 0
        rows = jnp.where(used[:, None], A[jnp.maximum(s, 0)], 0.0)  # (3, 3) A_S, zero rows unused
        rhs_b = jnp.where(used, -b[jnp.maximum(s, 0)], 0.0)
        top = jnp.concatenate([H, -rows.T], axis=1)
        bottom = jnp.concatenate([rows, jnp.diag(jnp.where(used, 0.0, 1.0))], axis=1)
        K = jnp.concatenate([top, bottom])
        x = jnp.linalg.solve(K, jnp.concatenate([-g, rhs_b]))
        d = x[:3]
        finite = jnp.all(jnp.isfinite(x))
        # a (near-)singular system solves to garbage: check the residual, not just finiteness
        resid = jnp.max(jnp.abs(K @ jnp.where(finite, x, 0.0) - jnp.concatenate([-g, rhs_b])))
        regular = finite & (resid <= 1e-9 * (1.0 + jnp.max(jnp.abs(K)) * jnp.max(jnp.abs(
            jnp.where(finite, x, 0.0)))))
        d = jnp.where(regular, d, 0.0)
        feasible = regular & jnp.all(A @ d + b >= -FEASIBLE_TOL * scale * (1.0 + jnp.max(jnp.abs(d))))
        q = g @ d + 0.5 * d @ H @ d
        return d, jnp.where(feasible, q, jnp.inf)

    d, q = jax.vmap(candidate)(sets)
    best = jnp.argmin(q)
    ok = jnp.isfinite(q[best])
    return jnp.where(ok, d[best], 0.0), jnp.where(ok, q[best], 0.0), ok
