"""Named objectives and their aggregation over the mu set (synthetic metrics, exact answers)."""

import numpy as np
import pytest

from jaxdamp_optimize.objectives import (aggregate, combined_refs, mu_index, parse_objective,
                                 per_mu_scores, reported_value, score)

from helpers import assert_tree_allclose

MUS = (0.3, 0.5, 0.7)
# metrics (n_mu, 3): k_im_bc, psi_bc, w_m
M = np.array([[5000.0, 1.5, 1.2], [4900.0, 2.2, 1.8], [4600.0, 2.6, 2.2]])


def test_default_is_the_robust_worst_case_k_im():
    obj = parse_objective()
    assert obj.name == "k_im_bc:worst" and obj.sense == 1.0 and obj.units == "N mm/mrad"
    assert float(score(obj, M, MUS)) == 4600.0


def test_worst_case_of_a_minimised_metric_is_its_maximum():
    obj = parse_objective("psi_bc")
    s = float(score(obj, M, MUS))
    assert s == -2.6 and float(reported_value(obj, s)) == 2.6


def test_mean_and_single_mu():
    assert float(score(parse_objective("w_m:mean"), M, MUS)) == pytest.approx(5.2 / 3, rel=1e-15)
    obj = parse_objective("k_im_bc:mu=0.5")
    assert obj.name == "k_im_bc:mu=0.5" and mu_index(obj, MUS) == 1
    assert float(score(obj, M, MUS)) == 4900.0
    with pytest.raises(ValueError, match="one of the mu set"):
        mu_index(parse_objective("k_im_bc:mu=0.4"), MUS)


def test_combined_is_the_weighted_sum_of_normalised_metrics():
    refs = combined_refs(M)
    assert_tree_allclose(refs, M.mean(0), rtol=1e-7, atol=0.0)
    obj = parse_objective("combined:worst", {"k_im_bc": 2.0, "psi_bc": 1.0, "w_m": 0.0})
    per_mu = np.asarray(per_mu_scores(obj, M, refs))
    expect = 2.0 * M[:, 0] / refs[0] - M[:, 1] / refs[1]
    assert_tree_allclose(per_mu, expect, rtol=1e-15, atol=0.0)
    assert float(aggregate(obj, per_mu, MUS)) == pytest.approx(expect.min(), rel=1e-15)
    # the baseline itself scores sum_i w_i s_i on average
    mean_obj = parse_objective("combined:mean", {"k_im_bc": 2.0, "psi_bc": 1.0, "w_m": 0.0})
    assert float(score(mean_obj, M, MUS, refs)) == pytest.approx(1.0, rel=1e-14)


def test_scores_are_linear_so_the_chain_rule_applies_to_jacobians():
    obj = parse_objective("combined:mean")
    refs = combined_refs(M)
    dM = np.random.default_rng(1).normal(size=M.shape)
    lhs = np.asarray(per_mu_scores(obj, M + dM, refs)) - np.asarray(per_mu_scores(obj, M, refs))
    assert_tree_allclose(lhs, per_mu_scores(obj, dM, refs), rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("name, match", [
    ("k_re_bc", "NAME must be one of"), ("k_im_bc:best", "aggregate must be"),
    ("k_im_bc:mu=abc", "needs a number"), ("k_im_bc:mu=-1", "X > 0"), ("", "NAME"),
])
def test_bad_objective_names_raise(name, match):
    with pytest.raises(ValueError, match=match):
        parse_objective(name)


def test_bad_weights_raise():
    with pytest.raises(ValueError, match="weights apply to the combined"):
        parse_objective("k_im_bc", {"k_im_bc": 1.0})
    with pytest.raises(ValueError, match="weight psi_bc"):
        parse_objective("combined", {"psi_bc": -1.0})
    with pytest.raises(ValueError, match="at least one positive"):
        parse_objective("combined", {"psi_bc": 0.0})
    with pytest.raises(ValueError, match="name metrics"):
        parse_objective("combined", {"k_re": 1.0})
