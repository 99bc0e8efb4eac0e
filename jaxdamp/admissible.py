"""The statically admissible initial states of the in-phase damper at the forward extreme, and
samples of them: the band's search space (`jaxdamp.band`).

The state is parameterised by the tangential forces T (3,) (units of F_D); the normal forces follow
from the damper's equilibrium, N = P T + n0, and the admissible set

    N >= 0,   mu N - T >= 0,   mu N + T >= 0          (9 linear inequalities G T + h >= 0)

is a polyhedron in R^3: a polytope, plus a recession cone where the wedge self-locks
(`recession_rays`). Its vertices are found exactly (every triple of active constraints). Unchecked
and traceable (jit, vmap, grad): the band's entry points check their inputs.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ._validate import traced
from .geometry import DamperShape
from .linalg import solve3
from .params import check_shape_and_mu
from .qp3 import row_subsets
from .statics import contact_columns

_TRIPLES = row_subsets(9, 3)  # of the 9 constraints: a vertex is where 3 meet
_PAIRS = row_subsets(9, 2)  # an edge direction (a recession ray) where 2 meet
VERTEX_SLOTS = 24  # of the 84 triples, the feasible ones first (a polytope in R^3 cut by 9 planes
# has at most 14 vertices; the rest of the slots repeat degenerate ones)


def admissible_polytope(shape: DamperShape, mu):
    """(P, n0, G, h): N = P T + n0 and the constraints G T + h >= 0 (9,), for T (3,).
    Unchecked, traceable (jit, vmap, grad): the band kernel's building block (`amplitude_band`
    checks its inputs). Concrete inputs are checked as one design's (`params.check_shape_and_mu`)."""
    if not traced(shape, mu):
        check_shape_and_mu(shape, mu)
    a, c, _ = contact_columns(shape)
    mu = jnp.asarray(mu, float)
    # A^T N = C^T T + e_y  ->  N = A^-T C^T T + A^-T e_y (A^T is invertible for a real damper).
    cols, _ = jax.vmap(solve3, in_axes=(None, 0))(a.T, jnp.concatenate([c, jnp.eye(3)[1:2]]))
    P = cols[:3].T  # column j: N per unit T_j
    n0 = cols[3]
    eye = jnp.eye(3)
    G = jnp.concatenate([P, mu * P - eye, mu * P + eye])
    h = jnp.concatenate([n0, mu * n0, mu * n0])
    return P, n0, G, h


def polytope_vertices(G, h, tol=1e-12):
    """Vertices (84, 3) of {T: G T + h >= 0} from every triple of active constraints, and a mask of
    the feasible, non-degenerate ones. Unchecked, traceable (jit, vmap, grad): G, h as
    `admissible_polytope` returns them."""
    G, h = jnp.asarray(G, float), jnp.asarray(h, float)

    def one(idx):
        T, ok = solve3(G[idx], -h[idx])
        return T, ok & jnp.all(G @ T + h >= -tol)

    return jax.vmap(one)(jnp.asarray(_TRIPLES))


def recession_rays(G, tol=1e-12):
    """Unit extreme rays (72, 3) of the recession cone {r: G r >= 0} (in R^3 each is where two
    constraint planes meet, either sign) and a mask of the admissible ones. Where any is, the
    admissible set is unbounded: a self-locking wedge holds states with arbitrarily large forces
    (at mu >= 0.5 for 90L and 90R, at 0.7 for most paper shapes), and far along a ray every contact
    sticks (the cycle is the stuck elastic line: k_Re = k_Re,fs, k_Im = 0)."""
    G = jnp.asarray(G, float)
    a, b = G[_PAIRS[:, 0]], G[_PAIRS[:, 1]]
    r = jnp.cross(a, b)
    n = jnp.linalg.norm(r, axis=1)
    ok = n > 1e-9 * jnp.linalg.norm(a, axis=1) * jnp.linalg.norm(b, axis=1)
    r = r / jnp.where(ok, n, 1.0)[:, None]
    R = jnp.concatenate([r, -r])
    ok = jnp.concatenate([ok, ok]) & jnp.all(R @ G.T >= -tol * jnp.linalg.norm(G, axis=1)[None, :], axis=1)
    return jnp.where(ok[:, None], R, 0.0), ok


def box_extent(X, mask):
    """The largest side of the bounding box of the rows of X (n, 3) where mask (1 where none)."""
    lo = jnp.min(jnp.where(mask[:, None], X, jnp.inf), axis=0)
    hi = jnp.max(jnp.where(mask[:, None], X, -jnp.inf), axis=0)
    return jnp.where(jnp.any(mask), jnp.max(hi - lo), 1.0)


def _uniform_states(key, V, ok, G, h, n):
    """n states uniform in the polytope: rejection from the vertices' bounding box in their
    principal axes (the polytope is thin and oblique: about 15 % of that box is admissible, under
    2 % of the axis-aligned one), 16 n draws; where fewer are admissible the rest are the centroid
    of the vertices."""
    centre = jnp.sum(jnp.where(ok[:, None], V, 0.0), axis=0) / jnp.maximum(jnp.sum(ok, dtype=float), 1.0)
    D = jnp.where(ok[:, None], V - centre[None, :], 0.0)
    _, _, axes = jnp.linalg.svd(D, full_matrices=False)  # rows: principal directions
    Y = D @ axes.T
    lo = jnp.min(jnp.where(ok[:, None], Y, jnp.inf), axis=0)
    hi = jnp.max(jnp.where(ok[:, None], Y, -jnp.inf), axis=0)
    lo, hi = jnp.where(jnp.any(ok), lo, 0.0), jnp.where(jnp.any(ok), hi, 0.0)
    X = centre[None, :] + (lo[None, :] + (hi - lo)[None, :] * jax.random.uniform(key, (16 * n, 3))) @ axes
    inside = jnp.all(X @ G.T + h[None, :] >= 0.0, axis=1)
    first = jnp.argsort(~inside, stable=True)[:n]
    return jnp.where(inside[first][:, None], X[first], centre[None, :])


def sparse_weights(key, alpha, mask, n):
    """(n, m) random convex weights on the slots where mask, few of them large for a small alpha:
    E U^(1/alpha) normalised (E exponential, U uniform), Dirichlet(alpha) but for E, which there is
    Gamma(1 + alpha). jax.random.dirichlet's rejection-sampled Gamma is ~2000 HLO instructions a
    call: without it the band program has 28.9k instead of 33.2k and XLA compiles it in
    9.6-11.1 s instead of 12.4-12.8 s (fast-compiled, 2-core VM, two runs each;
    docs/performance-history.md)."""
    ke, ku = jax.random.split(key)
    shape = (n, mask.shape[0])
    log_w = jnp.log(jax.random.exponential(ke, shape)) + jnp.log(
        jax.random.uniform(ku, shape, minval=1e-300)) / alpha
    log_w = jnp.where(mask[None, :], log_w, -jnp.inf)
    top = jnp.max(log_w, axis=1, keepdims=True)
    w = jnp.exp(log_w - jnp.where(jnp.isfinite(top), top, 0.0))
    return w / jnp.maximum(jnp.sum(w, axis=1, keepdims=True), 1e-300)


def admissible_samples(shape, mu, key, n_samples: int):
    """(T (VERTEX_SLOTS + n_samples, 3), real (same,), P, n0): the polytope's vertices (real: the
    feasible, non-degenerate ones), then n_samples random admissible states: half uniform in the
    polytope (its interior, where the extremes of k_Im often sit), a quarter sparse convex
    combinations of the vertices (alpha 0.15: near faces, edges and vertices), a quarter far out
    along the recession cone where the set is unbounded (else more sparse ones)."""
    P, n0, G, h = admissible_polytope(shape, mu)
    V, ok = polytope_vertices(G, h)
    order = jnp.argsort(~ok, stable=True)[:VERTEX_SLOTS]
    V, ok = V[order], ok[order]
    k1, k2, k3, k4, k5 = jax.random.split(key, 5)
    half, quarter = n_samples // 2, n_samples // 4
    rest = n_samples - half - quarter
    Vm = jnp.where(ok[:, None], V, 0.0)

    def sparse(k, n):
        return sparse_weights(k, 0.15, ok, n) @ Vm

    uniform = _uniform_states(k1, V, ok, G, h, half)
    R, ray_ok = recession_rays(G)
    ray = sparse_weights(k3, 0.5, ray_ok, rest) @ R
    ray = ray / jnp.maximum(jnp.linalg.norm(ray, axis=1, keepdims=True), 1e-300)
    spread = box_extent(V, ok)
    # distances from a quarter of the polytope's size to 64 times it (log-uniform)
    dist = spread * 2.0 ** jax.random.uniform(k4, (rest, 1), minval=-2.0, maxval=6.0)
    far = jnp.where(jnp.any(ray_ok), uniform[jnp.arange(rest) % half] + dist * ray, sparse(k5, rest))
    T = jnp.concatenate([Vm, uniform, sparse(k2, quarter), far])
    valid_point = jnp.concatenate([ok, jnp.full(n_samples, jnp.any(ok))])
    return T, valid_point, P, n0


__all__ = ["VERTEX_SLOTS", "admissible_polytope", "polytope_vertices", "recession_rays", "box_extent",
           "sparse_weights", "admissible_samples"]
