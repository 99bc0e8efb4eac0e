"""The feasible descent shared by the response and robust optimisers, on problems whose optimum is
known in closed form (independent of the damper)."""

import numpy as np

from jaxdamp_optimize.descent import descend_from_best, feasible_descent

from helpers import assert_tree_allclose


def _quadratic(centre):
    centre = np.asarray(centre, float)
    return (lambda z: 2.0 * (z - centre)), (lambda z: (float(np.sum((z - centre) ** 2)), True))


def test_reaches_an_interior_minimum_and_values_only_fall():
    gradient, evaluate = _quadratic([0.3, 0.7])
    out = feasible_descent(np.array([0.9, 0.1]), evaluate(np.array([0.9, 0.1]))[0], gradient,
                           evaluate, steps=60, step_size=0.1, tries=6)
    assert_tree_allclose(out.z, np.array([0.3, 0.7]), rtol=1e-7, atol=1e-3)
    values = [v for _, v in out.accepted]
    assert values == sorted(values, reverse=True) and len(values) > 3


def test_a_minimum_outside_the_box_ends_on_its_face():
    gradient, evaluate = _quadratic([1.4, 0.5])  # the box optimum is (1, 0.5)
    out = feasible_descent(np.array([0.2, 0.2]), evaluate(np.array([0.2, 0.2]))[0], gradient,
                           evaluate, steps=80, step_size=0.1, tries=6)
    assert np.all((out.z >= 0.0) & (out.z <= 1.0))
    assert_tree_allclose(out.z, np.array([1.0, 0.5]), rtol=1e-7, atol=2e-3)


def test_never_accepts_an_infeasible_design():
    centre = np.array([0.2, 0.2])
    infeasible = lambda z: z[0] + z[1] < 0.8  # noqa: E731  (the optimum is cut off)
    gradient = lambda z: 2.0 * (z - centre)  # noqa: E731
    seen = []

    def evaluate(z):
        seen.append(z)
        return float(np.sum((z - centre) ** 2)), not infeasible(z)

    z0 = np.array([0.9, 0.9])
    out = feasible_descent(z0, evaluate(z0)[0], gradient, evaluate, steps=40, step_size=0.2,
                           tries=8)
    assert not infeasible(out.z)
    assert out.z.sum() < 1.2  # it did move towards the cut
    assert out.evaluations == len(seen) - 1


def test_zero_gradient_stops_at_once():
    out = feasible_descent(np.array([0.5]), 1.0, lambda z: np.zeros(1),
                           lambda z: (0.0, True), steps=10, step_size=0.1, tries=3)
    assert out.evaluations == 0 and out.accepted == [] and out.value == 1.0


def test_descents_start_from_the_best_finite_points_and_keep_the_best_end():
    """Two basins: f = min of two quadratics, the deeper one at (0.8, 0.8); an infinite value
    (an infeasible grid point) is never a start."""
    a, b = np.array([0.2, 0.2]), np.array([0.8, 0.8])

    def evaluate(z):
        return float(min(np.sum((z - a) ** 2) + 0.1, np.sum((z - b) ** 2))), True

    def gradient(z):
        return 2.0 * (z - (a if np.sum((z - a) ** 2) + 0.1 < np.sum((z - b) ** 2) else b))

    Z = np.array([[0.3, 0.1], [0.6, 0.9], [0.5, 0.5], [0.0, 0.0]])
    values = np.array([evaluate(z)[0] for z in Z])
    values[2] = np.inf
    ticks = []
    z, value, n, hist = descend_from_best(Z, values, gradient, evaluate, starts=4, steps=40,
                                          step_size=0.1, tries=6, tick=ticks.append)
    assert_tree_allclose(z, b, rtol=0, atol=2e-3)
    assert value == min(v for _, _, v in hist) and len(ticks) == 3 and n > 0
    none = descend_from_best(Z, np.full(4, np.inf), gradient, evaluate, starts=2, steps=5,
                             step_size=0.1, tries=2)
    assert none[0] is None and none[2] == 0


def test_lbfgs_directions_reach_an_ill_scaled_minimum_in_fewer_steps():
    """With optax's L-BFGS as the direction (`transform`), an ill-scaled quadratic (curvatures 1
    and 50, minimum known) is reached to 1e-3 in fewer accepted steps than along the gradient,
    and the values only fall."""
    import optax

    centre, scale = np.array([0.3, 0.6]), np.array([1.0, 50.0])

    def gradient(z):
        return 2.0 * scale * (z - centre)

    def evaluate(z):
        return float(np.sum(scale * (z - centre) ** 2)), True

    z0 = np.array([0.9, 0.1])
    runs = [feasible_descent(z0, evaluate(z0)[0], gradient, evaluate, steps=200, step_size=0.1,
                             tries=8, min_step=1e-9, transform=t)
            for t in (None, optax.scale_by_lbfgs(memory_size=4))]
    for run in runs:
        values = [v for _, v in run.accepted]
        assert values == sorted(values, reverse=True)
    steps_to = [next((k for k, (_, v) in enumerate(r.accepted) if v < 1e-6), np.inf) for r in runs]
    assert_tree_allclose(runs[1].z, centre, rtol=0.0, atol=1e-3)
    assert steps_to[1] < steps_to[0]
