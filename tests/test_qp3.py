"""The exact small quadratic program in R^3 (jaxdamp.qp3) against independent references."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from jaxdamp.qp3 import minimise_quadratic

from helpers import assert_tree_allclose


def _box(r, extra_A=None, extra_b=None):
    A = np.concatenate([-np.eye(3), np.eye(3)])
    b = np.full(6, float(r))
    if extra_A is not None:
        A, b = np.concatenate([A, extra_A]), np.concatenate([b, extra_b])
    return A, b


def test_interior_minimum_of_a_convex_quadratic_is_newtons_step():
    H = np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 2.0]])
    g = np.array([0.3, -0.2, 0.1])
    A, b = _box(10.0)
    d, q, ok = minimise_quadratic(g, H, A, b)
    expected = -np.linalg.solve(H, g)
    assert bool(ok)
    assert_tree_allclose(d, expected, rtol=1e-12, atol=0.0)
    assert float(q) == pytest.approx(0.5 * g @ expected, rel=1e-12)


def test_concave_quadratic_on_a_box_has_its_minimum_at_the_best_vertex():
    H = -np.diag([1.0, 2.0, 3.0])
    g = np.array([0.1, -0.2, 0.05])
    A, b = _box(1.0)
    d, q, ok = minimise_quadratic(g, H, A, b)
    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=3)))
    values = corners @ g + 0.5 * np.einsum("ni,ij,nj->n", corners, H, corners)
    assert bool(ok)
    assert_tree_allclose(d, corners[np.argmin(values)], rtol=1e-7, atol=1e-12)
    assert float(q) == pytest.approx(values.min(), rel=1e-12)


def test_linear_objective_on_a_box_goes_to_a_vertex():
    """H = 0 (k linear in T within a sequence): every face system is singular except the vertices."""
    g = np.array([1.0, -2.0, 0.5])
    A, b = _box(0.5)
    d, _, ok = minimise_quadratic(g, np.zeros((3, 3)), A, b)
    assert bool(ok)
    assert_tree_allclose(d, -0.5 * np.sign(g), rtol=1e-7, atol=1e-12)


def test_an_empty_polytope_is_reported():
    A = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]] + list(np.eye(3)) + list(-np.eye(3)))
    b = np.array([-1.0, -1.0] + [1.0] * 6)  # x >= 1 and x <= -1
    d, q, ok = minimise_quadratic(np.ones(3), np.eye(3), A, b)
    assert not bool(ok) and np.all(np.asarray(d) == 0.0) and float(q) == 0.0


@pytest.mark.slow  # 10 worker-s (run of 2026-11-25)
@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000))
def test_never_above_dense_feasible_samples(seed):
    """Random indefinite quadratics on random polytopes (a box cut by 4 random half-spaces through
    points near the origin): the QP's value is feasible and no denser-sampled feasible point is
    lower (independent reference: 20 000 random points in the box)."""
    rng = np.random.default_rng(seed)
    M = rng.normal(size=(3, 3))
    H = M + M.T
    g = rng.normal(size=3)
    cuts = rng.normal(size=(4, 3))
    A, b = _box(1.0, cuts, rng.uniform(0.05, 1.0, 4))
    d, q, ok = minimise_quadratic(g, H, A, b)
    assert bool(ok)
    d = np.asarray(d)
    assert np.all(A @ d + b >= -1e-9)
    assert float(q) == pytest.approx(g @ d + 0.5 * d @ H @ d, abs=1e-12)
    X = rng.uniform(-1.0, 1.0, (20_000, 3))
    X = X[np.all(X @ A.T + b >= 0.0, axis=1)]
    values = X @ g + 0.5 * np.einsum("ni,ij,nj->n", X, H, X)
    assert float(q) <= values.min() + 1e-12
