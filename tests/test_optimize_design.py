"""Design variables: bounds, unit box, projection, embedding into complete shapes."""

import numpy as np
import pytest

from jaxdamp_optimize.design import (DEFAULT_BOUNDS, VARIABLES, design_space, embed, family_start,
                             from_unit, in_bounds, project, shape_dict, shape_of, to_unit)

from helpers import assert_tree_allclose


def test_default_space_has_the_issue_bounds():
    s = design_space()
    assert s.free == ("theta_l", "theta_r", "br_over_hr")
    assert s.bounds() == {"theta_l": (35.0, 90.0), "theta_r": (35.0, 90.0),
                          "br_over_hr": (-0.3, 0.4)}
    assert dict(s.fixed) == {"bl2_over_hl": 0.8}
    assert DEFAULT_BOUNDS["bl2_over_hl"] == (0.5, 0.9)


def test_unit_box_round_trip_and_corners():
    s = design_space(VARIABLES)
    x = np.array([[35.0, 90.0, -0.3, 0.9], [62.5, 40.0, 0.05, 0.8]])
    z = np.asarray(to_unit(s, x))
    assert_tree_allclose(z[0], np.array([0.0, 1.0, 0.0, 1.0]), rtol=1e-7, atol=1e-15)
    assert_tree_allclose(from_unit(s, z), x, rtol=0, atol=1e-12)


def test_projection_is_the_euclidean_projection_onto_the_box():
    z = np.array([[-0.2, 0.5, 1.7], [0.3, 1.0, 0.0]])
    p = np.asarray(project(z))
    np.testing.assert_array_equal(p, [[0.0, 0.5, 1.0], [0.3, 1.0, 0.0]])
    # projection property: <z - p, q - p> <= 0 for every q in the box
    rng = np.random.default_rng(0)
    for q in rng.uniform(0, 1, (50, 3)):
        assert np.all(np.sum((z - p) * (q - p), -1) <= 1e-15)


def test_fixed_variables_and_embedding():
    s = design_space(("br_over_hr",), fixed={"theta_l": 45.0, "theta_r": 45.0})
    assert s.dim == 1
    v = embed(s, np.array([[0.2], [-0.1]]))
    np.testing.assert_array_equal(v, [[45.0, 45.0, 0.2, 0.8], [45.0, 45.0, -0.1, 0.8]])
    shape = shape_of(s, np.array([0.2]))
    assert float(shape.theta_l) == 45.0 and float(shape.br_over_hr) == 0.2 and shape.x_d is None
    assert shape_dict(s, [0.2]) == {"theta_l": 45.0, "theta_r": 45.0, "br_over_hr": 0.2,
                                    "bl2_over_hl": 0.8}


def test_family_starts_are_projected_into_the_bounds():
    s = design_space(bounds={"theta_r": (45.0, 90.0)})
    x = family_start(s, "90L")  # theta_r = 40.9 lies below the narrowed bound
    assert_tree_allclose(x, np.array([90.0, 45.0, 0.15]), rtol=1e-7, atol=0.0)
    assert in_bounds(s, x)


@pytest.mark.parametrize("kwargs, match", [
    (dict(free=("theta_x",)), "free variables"),
    (dict(free=()), "at least one"),
    (dict(free=("theta_l", "theta_l")), "each once"),
    (dict(bounds={"theta_l": (30.0, 20.0)}), "bounds of theta_l"),
    (dict(bounds={"theta_l": (10.0, 95.0)}), "bounds of theta_l"),
    (dict(bounds={"bl2_over_hl": (0.5, 0.9)}), "not a free variable"),
    (dict(fixed={"theta_l": 50.0}), "both free and fixed"),
    (dict(free=("theta_l",), fixed={"br_over_hr": 0.9}), "fixed br_over_hr"),
])
def test_bad_design_spaces_raise_naming_the_parameter(kwargs, match):
    with pytest.raises(ValueError, match=match):
        design_space(**kwargs)
