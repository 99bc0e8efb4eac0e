"""PHR augmented Lagrangian on problems with known KKT points (independent of the damper)."""

import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp_optimize.augmented import ALConfig, al_init, al_update, al_value_and_grad

from helpers import assert_tree_allclose


def _problem(x):
    """min (x1-2)^2 + (x2-1)^2  s.t.  g = 1 - x1 - x2 >= 0: KKT x* = (1, 0), lambda* = 2."""
    f = (x[:, 0] - 2) ** 2 + (x[:, 1] - 1) ** 2
    df = np.stack([2 * (x[:, 0] - 2), 2 * (x[:, 1] - 1)], -1)
    g = (1 - x[:, 0] - x[:, 1])[:, None]
    dg = np.broadcast_to(np.array([[-1.0, -1.0]]), (len(x), 1, 2))
    return f, df, g, dg


def test_gradient_matches_finite_differences():
    state = al_init(1, 1)._replace(lam=jnp.array([[0.7]]), rho=jnp.array([3.0]))
    x = np.array([[0.8, 0.6]])  # violated: g = -0.4
    _, grad = al_value_and_grad(*_problem(x), state)
    h = 1e-6
    for k in range(2):
        e = np.zeros((1, 2))
        e[0, k] = h
        fp, _ = al_value_and_grad(*_problem(x + e), state)
        fm, _ = al_value_and_grad(*_problem(x - e), state)
        assert float(grad[0, k]) == pytest.approx(float((fp - fm)[0]) / (2 * h), rel=1e-7)


def test_outer_loop_converges_to_the_kkt_point_and_multiplier():
    cfg = ALConfig(rho0=1.0, rho_growth=2.0)
    state = al_init(1, 1, cfg)
    x = np.array([[0.0, 0.0]])
    for _ in range(25):
        for _ in range(40):  # inner minimisation by gradient descent (the AL is smooth)
            _, grad = al_value_and_grad(*_problem(x), state)
            x = x - 0.5 / (1 + float(state.rho[0])) * np.asarray(grad)
        state = al_update(state, _problem(x)[2], cfg)
    assert_tree_allclose(x[0], np.array([1.0, 0.0]), rtol=1e-7, atol=1e-6)
    assert float(state.lam[0, 0]) == pytest.approx(2.0, abs=1e-5)


def test_inactive_constraint_keeps_zero_multiplier_and_penalty():
    state = al_init(2, 1)
    g = jnp.array([[0.3], [0.0]])
    new = al_update(state, g)
    np.testing.assert_array_equal(np.asarray(new.lam), 0.0)
    np.testing.assert_array_equal(np.asarray(new.rho), 1.0)
    value, grad = al_value_and_grad(jnp.zeros(2), jnp.zeros((2, 1)), g, jnp.ones((2, 1, 1)), new)
    np.testing.assert_array_equal(np.asarray(value), 0.0)
    np.testing.assert_array_equal(np.asarray(grad), 0.0)


def test_penalty_grows_only_when_the_violation_stalls():
    cfg = ALConfig(rho0=1.0, rho_growth=4.0, violation_decrease=0.25)
    state = al_update(al_init(1, 1, cfg), jnp.array([[-1.0]]), cfg)  # first: no growth
    assert float(state.rho[0]) == 1.0 and float(state.lam[0, 0]) == 1.0
    slow = al_update(state, jnp.array([[-0.5]]), cfg)  # 0.5 > 0.25 * 1.0
    assert float(slow.rho[0]) == 4.0
    fast = al_update(state, jnp.array([[-0.1]]), cfg)  # 0.1 <= 0.25
    assert float(fast.rho[0]) == 1.0
