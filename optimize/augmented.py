"""PHR augmented Lagrangian for inequality constraints g(z) >= 0 (optax style: NamedTuple state,
pure init / value_and_grad / update functions, batched over starts on the leading axis).

    L(z; lam, rho) = f(z) + 1/(2 rho) sum_j [max(0, lam_j - rho g_j(z))^2 - lam_j^2]

(Rockafellar's form; f is minimised.) Used by the shape optimiser (`solver.py`) only, so it lives
here, on top of the library, not in its core. L is continuously differentiable; its gradient is
grad f - sum_j max(0, lam_j - rho g_j) grad g_j. After an (approximate) minimisation over z the
multipliers follow lam_j <- max(0, lam_j - rho g_j), and rho grows while the violation does not
fall fast enough.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp


class ALState(NamedTuple):
    lam: jnp.ndarray  # (B, m) multipliers, >= 0
    rho: jnp.ndarray  # (B,) penalty parameters
    violation: jnp.ndarray  # (B,) max violation at the last update (inf before the first)


class ALConfig(NamedTuple):
    rho0: float = 1.0
    rho_growth: float = 4.0
    rho_max: float = 1e4
    violation_decrease: float = 0.25  # rho grows unless the violation fell below this fraction


def al_init(batch: int, n_constraints: int, config: ALConfig = ALConfig()) -> ALState:
    return ALState(jnp.zeros((batch, n_constraints)), jnp.full((batch,), float(config.rho0)),
                   jnp.full((batch,), jnp.inf))


def al_value_and_grad(f, d_f, g, d_g, state: ALState):
    """Augmented Lagrangian value (B,) and gradient (B, d).

    f (B,), d_f (B, d): objective to minimise and its gradient; g (B, m), d_g (B, m, d).
    """
    f, d_f, g, d_g = (jnp.asarray(a) for a in (f, d_f, g, d_g))
    shifted = jnp.maximum(0.0, state.lam - state.rho[:, None] * g)
    value = f + jnp.sum(shifted ** 2 - state.lam ** 2, axis=-1) / (2.0 * state.rho)
    grad = d_f - jnp.einsum("bm,bmd->bd", shifted, d_g)
    return value, grad


def al_update(state: ALState, g, config: ALConfig = ALConfig()) -> ALState:
    """First-order multiplier update and penalty increase."""
    g = jnp.asarray(g)
    lam = jnp.maximum(0.0, state.lam - state.rho[:, None] * g)
    violation = jnp.max(jnp.maximum(-g, 0.0), axis=-1)
    slow = (violation > 0.0) & (violation > config.violation_decrease * state.violation)
    rho = jnp.where(slow, jnp.minimum(state.rho * config.rho_growth, config.rho_max), state.rho)
    return ALState(lam, rho, violation)


__all__ = ["ALState", "ALConfig", "al_init", "al_value_and_grad", "al_update"]
