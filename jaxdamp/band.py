"""The band of responses at an amplitude: min and max of k_Re and k_Im over every statically
admissible initial state (the paper's ref. [32]: the limits of the response by constrained
optimisation over the initial states).

The initial state sits at the forward extreme (see `jaxdamp.amplitude`). It is parameterised by the
tangential forces T (3,) (units of F_D); the normal forces follow from the damper's equilibrium,
-A^T N + C^T T + e_y = 0, so N = P T + n0 is affine in T, and the admissible set

    N >= 0,   mu N - T >= 0,   mu N + T >= 0          (9 linear inequalities G T + h >= 0)

is a polytope in R^3. Its vertices are found exactly (every triple of active constraints), the
polytope is sampled by random convex combinations of them (vmap over the samples), and the four
extremes are refined by gradient-based constrained optimisation: optax's Adam on the PHR augmented
Lagrangian (`jaxdamp.augmented`) of +-k with the 9 linear constraints. The band is the min / max
over the valid cycles (status ok or shakedown) among the samples and the refined, admissible states.
"""

from __future__ import annotations

import itertools
from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .linalg import solve3
from .amplitude import amplitude_kernel
from .geometry import DamperShape
from .params import Contacts, LoadCase, prepare_inputs
from .statics import contact_columns
from .status import RESULTS, number_repr, status_repr

BOUNDS = ("k_re_min", "k_re_max", "k_im_min", "k_im_max")
_TRIPLES = np.array(list(itertools.combinations(range(9), 3)))
ADMISSIBLE_TOL = 1e-10  # units of F_D: a refined state must satisfy the constraints to this


class Band(NamedTuple):
    """The band at one amplitude (k in N mm/mrad); arrays of 4 follow BOUNDS."""

    psi_a: float
    bounds: np.ndarray  # (4,) k_re_min, k_re_max, k_im_min, k_im_max (zero where status is not ok)
    N: np.ndarray  # (4, 3) initial normal forces attaining each bound (units of F_D)
    T: np.ndarray  # (4, 3) initial tangential forces
    refined: np.ndarray  # (4,) bool: the bound was improved by the optimiser beyond the samples
    n_valid: int  # valid cycles among the samples
    status: int  # RESULTS.ok if any admissible state gives a valid cycle, else the first problem

    def as_dict(self) -> dict:
        """The bounds by name; None where no admissible state gives a valid cycle (status)."""
        exists = int(self.status) == RESULTS.ok
        return {name: (float(v) if exists else None) for name, v in zip(BOUNDS, self.bounds)}

    def __repr__(self) -> str:
        bounds = ", ".join(f"{n}={number_repr(v, 'N mm/mrad')}" for n, v in zip(BOUNDS, self.bounds))
        return (f"Band(status={status_repr(self.status)}, psi_a={number_repr(self.psi_a, 'mrad')}, "
                f"{bounds}, n_valid={self.n_valid})")


def admissible_polytope(shape: DamperShape, mu):
    """(P, n0, G, h): N = P T + n0 and the constraints G T + h >= 0 (9,), for T (3,)."""
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
    the feasible, non-degenerate ones."""
    G, h = jnp.asarray(G, float), jnp.asarray(h, float)

    def one(idx):
        T, ok = solve3(G[idx], -h[idx])
        return T, ok & jnp.all(G @ T + h >= -tol)

    return jax.vmap(one)(jnp.asarray(_TRIPLES))


def _k_of_state(shape, mu, contacts, load, psi, T, P, n0):
    N = P @ T + n0
    ac = amplitude_kernel(shape, mu, contacts, load, psi, N, T, initial="explicit")
    return ac.k_re, ac.k_im, ac.status


@partial(jax.jit, static_argnames=("n_samples",))
def _sample(shape, mu, contacts, load, psi, key, n_samples):
    P, n0, G, h = admissible_polytope(shape, mu)
    V, ok = polytope_vertices(G, h)
    nv = V.shape[0]
    k1, k2 = jax.random.split(key)
    # Dense (alpha 1) and sparse (alpha 0.15: near faces, edges and vertices) convex combinations.
    half = n_samples // 2
    w = jnp.concatenate([jax.random.dirichlet(k1, jnp.ones(nv), (half,)),
                         jax.random.dirichlet(k2, jnp.full(nv, 0.15), (n_samples - half,))])
    w = jnp.where(ok[None, :], w, 0.0)
    w = w / jnp.maximum(jnp.sum(w, axis=1, keepdims=True), 1e-300)
    T = jnp.concatenate([jnp.where(ok[:, None], V, 0.0), w @ jnp.where(ok[:, None], V, 0.0)])
    valid_point = jnp.concatenate([ok, jnp.full(n_samples, jnp.any(ok))])
    k_re, k_im, status = jax.vmap(lambda t: _k_of_state(shape, mu, contacts, load, psi, t, P, n0))(T)
    status = jnp.where(valid_point, status, jnp.int32(RESULTS.singular))
    return T, P @ T.T + n0[:, None], k_re, k_im, status


@partial(jax.jit, static_argnames=("steps",))
def _refine(shape, mu, contacts, load, psi, T0, sign, which, lam, rho, lr, scale, steps):
    """`steps` Adam steps on the augmented Lagrangian of sign * k_which / scale, batched over starts."""
    import optax

    from .augmented import ALState, al_value_and_grad

    P, n0, G, h = admissible_polytope(shape, mu)

    def objective(T, s, wh):
        k_re, k_im, _ = _k_of_state(shape, mu, contacts, load, psi, T, P, n0)
        return s * jnp.where(wh == 0, k_re, k_im) / scale

    opt = optax.adam(lr)
    state = ALState(lam, rho, jnp.full(rho.shape, jnp.inf))

    def step(carry, _):
        T, ost = carry
        f, df = jax.vmap(jax.value_and_grad(objective))(T, sign, which)
        g = T @ G.T + h[None]
        dg = jnp.broadcast_to(G, (T.shape[0],) + G.shape)
        _, grad = al_value_and_grad(f, df, g, dg, state)
        upd, ost = opt.update(grad, ost, T)
        return (T + upd, ost), None

    (T, _), _ = jax.lax.scan(step, (T0, opt.init(T0)), None, length=steps)
    return T, T @ G.T + h[None]


def amplitude_band(shape: DamperShape, mu, psi_a_mrad, contacts: Contacts = Contacts(),
                   load: LoadCase = LoadCase(), *, n_samples: int = 512, refine: bool = True,
                   outer: int = 4, inner: int = 40, seed: int = 0) -> Band:
    """min / max of k_Re and k_Im (N mm/mrad) at psi_a (mrad) over the statically admissible
    initial states at the forward extreme, with the states that attain them.

    n_samples random admissible states (plus the polytope's vertices) are run with vmap; the best
    sample of each bound then starts `outer` augmented-Lagrangian rounds of `inner` Adam steps
    (refine=False skips this). States giving liftoff or no periodic cycle are left out.
    """
    from ._validate import check_int, check_range
    from .augmented import ALConfig, ALState, al_update

    shape, mu, contacts, load = prepare_inputs(shape, mu, contacts, load)
    check_range("psi_a_mrad", psi_a_mrad, 0.0, 1e4, lo_open=True, unit="mrad")
    check_int("n_samples", n_samples, 2)
    psi = jnp.asarray(float(psi_a_mrad))
    T, N, k_re, k_im, status = jax.device_get(
        _sample(shape, mu, contacts, load, psi, jax.random.PRNGKey(seed), n_samples))
    N = N.T
    valid = np.asarray(RESULTS.valid(status))
    if not valid.any():
        first = int(status[np.argmax(status != RESULTS.ok)]) if np.any(status) else int(RESULTS.singular)
        # No valid cycle: the bounds do not exist, which the status says (zeros, never NaN).
        return Band(float(psi_a_mrad), np.zeros(4), np.zeros((4, 3)), np.zeros((4, 3)),
                    np.zeros(4, bool), 0, first)
    values = np.stack([k_re, k_re, k_im, k_im])  # (4, samples)
    signs = np.array([1.0, -1.0, 1.0, -1.0])  # minimise sign * k
    score = np.where(valid[None, :], signs[:, None] * values, np.inf)
    best = np.argmin(score, axis=1)
    bounds = values[np.arange(4), best]
    T_at, N_at = T[best], N[best]
    improved = np.zeros(4, bool)
    if refine:
        scale = max(float(np.max(np.abs(values[:, valid]))), 1e-300)
        spread = float(np.max(np.ptp(T[valid], axis=0))) if valid.sum() > 1 else 1e-3
        lr = 0.02 * max(spread, 1e-6)
        cfg = ALConfig(rho0=10.0, rho_growth=4.0, rho_max=1e6)
        al = ALState(jnp.zeros((4, 9)), jnp.full(4, cfg.rho0), jnp.full(4, jnp.inf))
        Tr = jnp.asarray(T_at)
        which = jnp.array([0, 0, 1, 1])
        for _ in range(outer):
            Tr, g = _refine(shape, mu, contacts, load, psi, Tr, jnp.asarray(signs), which, al.lam,
                            al.rho, lr, scale, inner)
            al = al_update(al, g, cfg)
        Tr = np.asarray(Tr)
        P, n0, G, h = (np.asarray(v) for v in admissible_polytope(shape, mu))
        ok_state = np.all(Tr @ G.T + h[None] >= -ADMISSIBLE_TOL, axis=1)
        kr, ki, st = jax.device_get(jax.vmap(lambda t: _k_of_state(
            shape, mu, contacts, load, psi, t, jnp.asarray(P), jnp.asarray(n0)))(jnp.asarray(Tr)))
        got = np.where(which == 0, kr, ki)
        # Improvements at the rounding level (the optimiser returning to the sampled state) are
        # not counted: the bound keeps the sampled state.
        margin = 1e-9 * scale
        better = ok_state & np.asarray(RESULTS.valid(st)) & (signs * got < signs * bounds - margin)
        bounds = np.where(better, got, bounds)
        T_at = np.where(better[:, None], Tr, T_at)
        N_at = np.where(better[:, None], Tr @ P.T + n0, N_at)
        improved = better
    return Band(float(psi_a_mrad), bounds, N_at, T_at, improved, int(valid.sum()), int(RESULTS.ok))


__all__ = ["Band", "BOUNDS", "amplitude_band", "admissible_polytope", "polytope_vertices"]
