"""Robust response objective: the F_D spread folded into the force range agrees with F_D applied
explicitly (the scaling law, an independent evaluation), the smooth maximum bounds the true one,
its gradient matches central differences, the certification grid, one-line spec errors."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp import LoadCase
from jaxdamp.uncertainty import Scenarios, peak_distribution
from jaxdamp_optimize.problem import make_problem
from jaxdamp_optimize.robust_objective import (RobustSpec, dense_scenarios, descent_forces,
                                               objective_args, objective_programs,
                                               reference_shapes, robust_values, validate_spec)

from helpers import assert_tree_allclose

PROBLEM = make_problem(mus=(0.4, 0.6))
SPEC = RobustSpec(force_range_n=(4.0, 12.0), fd_spread=0.2, kn_factor=1.0, kt_factor=1.0,
                  n_forces=2)
V60 = np.asarray(reference_shapes()["60sym"], float)


@pytest.mark.slow  # 187 worker-s (run of 2026-11-25)
def test_the_fd_spread_as_a_force_range_matches_fd_applied_explicitly():
    assert_tree_allclose(descent_forces(SPEC), np.array([4.0 / 1.2, 12.0 / 0.8]), rtol=1e-7, atol=0.0)
    val, feas = robust_values(V60, PROBLEM, SPEC, objective_args(PROBLEM, SPEC))
    assert feas[0]
    # independent: the exact curve recomputed at F_D = 1.2 F_D0 (F = 4 N) and 0.8 F_D0 (F = 12 N),
    # under the spec's own history (its default is "band", the larger of the two histories'
    # peaks: the recomputation must take the same history, not peak_distribution's default)
    worst = 0.0
    for fd, force in ((1200.0, 4.0), (800.0, 12.0)):
        scen = Scenarios(jnp.array([0.4, 0.6]), jnp.full((2, 3), PROBLEM.kn),
                         jnp.full((2, 3), PROBLEM.kt), jnp.full(2, fd))
        d = peak_distribution(V60_shape(), scen, force_n=force, load=LoadCase(),
                              history=SPEC.history)
        worst = max(worst, float(np.max(d.magnification)))
    assert val[0] == pytest.approx(worst, rel=1e-7)


def V60_shape():
    from jaxdamp import family_shape

    return family_shape("60sym")


@pytest.mark.slow  # 508 worker-s (run of 2026-11-25)
def test_smooth_maximum_bounds_the_true_maximum_and_its_gradient_matches_differences():
    spec = SPEC._replace(kn_factor=2.0, kt_factor=2.0, history="band")
    args = objective_args(PROBLEM, spec)
    _, grad = objective_programs(spec.objective, spec.history)
    (g, (hard, status)) = grad(jnp.asarray(V60), spec.temperature, *args)
    n_scores = 2 * len(PROBLEM.mus) * 5 * spec.n_forces  # histories x mu x corners x forces

    s0 = _smooth(V60, spec, args)
    assert int(status) == 0
    assert float(hard) <= s0 <= float(hard) * np.exp(spec.temperature * np.log(n_scores))
    for i, h in ((1, 1e-4), (2, 1e-6)):  # theta_r (deg), b_R/h_R
        e = np.zeros(4)
        e[i] = h
        fd = (_smooth(V60 + e, spec, args) - _smooth(V60 - e, spec, args)) / (2 * h)
        assert abs(float(g[i])) > 0
        assert float(g[i]) == pytest.approx(fd, rel=1e-4)


def _smooth(v, spec, args):
    from jaxdamp_optimize.robust_objective import smooth_objective

    return float(jax.jit(smooth_objective, static_argnums=(1, 2))(
        jnp.asarray(v), spec.objective, spec.history, spec.temperature, *args)[0])


def test_the_certification_grid_spans_every_range_at_its_ends():
    spec = RobustSpec(fd_spread=0.1, kn_factor=2.0, kt_factor=3.0)
    s = dense_scenarios(make_problem(mus=(0.3, 0.5, 0.7)), spec)
    assert s.mu.shape == (9 * 3 * 3 * 3,) and s.kn.shape == (243, 3)
    assert_tree_allclose(np.array([s.mu.min(), s.mu.max()]), np.array([0.3, 0.7]), rtol=1e-7, atol=0.0)
    assert_tree_allclose(np.array([s.fd_n.min(), s.fd_n.max()]), np.array([900.0, 1100.0]), rtol=1e-7,
                         atol=0.0)
    kn0, kt0 = make_problem().kn, make_problem().kt
    assert_tree_allclose(np.array([s.kn.min(), s.kn.max()]), np.array([kn0 / 2, kn0 * 2]), rtol=1e-7,
                         atol=0.0)
    assert_tree_allclose(np.array([s.kt.min(), s.kt.max()]), np.array([kt0 / 3, kt0 * 3]), rtol=1e-7,
                         atol=0.0)


@pytest.mark.parametrize("change, flag", [({"force_range_n": (5.0, 2.0)}, "--force-n"),
                                          ({"fd_spread": 1.0}, "--fd-spread"),
                                          ({"kn_factor": 0.5}, "--kn-range"),
                                          ({"kt_factor": 200.0}, "--kt-range"),
                                          ({"history": "assembly"}, "--history"),
                                          ({"objective": "mean"}, "--objective")])
def test_bad_spec_is_refused_naming_the_flag(change, flag):
    with pytest.raises(ValueError, match=flag):
        validate_spec(RobustSpec()._replace(**change))


def test_a_design_that_is_not_certified_says_why_in_status_names():
    """The reason names the statuses the scenarios gave: a non-converged cycle is not a liftoff."""
    from jaxdamp import RESULTS
    from jaxdamp_optimize.robust_objective import uncertified_reason

    status = [RESULTS.ok, RESULTS.not_converged, RESULTS.ok, RESULTS.liftoff, RESULTS.liftoff]
    reason = uncertified_reason(True, status)
    assert reason == "liftoff in 2 of 5 scenarios; not_converged in 1 of 5 scenarios"
    assert uncertified_reason(False, [RESULTS.ok]).startswith("margins")
    assert uncertified_reason(True, [RESULTS.ok, RESULTS.ok]) == "ok"
