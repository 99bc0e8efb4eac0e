"""No-liftoff margins: against the paper's Table 1 and §4, and against dense sampling of the cycle."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp_optimize.constraints import (KINDS, LOCATIONS, cycle_points, margins, point_constraints,
                                  resultant_distances_pct, select_min)


def _margins(name_or_shape, mu, margin=5.0):
    shape = jd.family_shape(name_or_shape) if isinstance(name_or_shape, str) else name_or_shape
    st = jd.full_slip_statics(shape, mu)
    bc = jd.base_cycle(shape, mu)
    return margins(st, bc, margin), st, bc


@pytest.mark.parametrize("row", [0, 1, 2])
def test_60sym_distances_match_table_1(paper, row):
    ref = paper["table_1_60sym_resultant_distance"]["rows"][row]
    m, _, _ = _margins("60sym", ref["mu"])
    start = LOCATIONS.index("start")
    mid = LOCATIONS.index("mid")
    # printed to 0.1 % (one unit of the last digit, as in test_statics): cycle start is nearest
    # L1, mid-cycle nearest L2
    assert float(m.dist_pct[start, 0]) == pytest.approx(ref["dist_L1"], abs=0.1)
    assert float(m.dist_pct[mid, 1]) == pytest.approx(ref["dist_L2"], abs=0.1)
    assert np.all(np.asarray(m.g) >= 0)  # 60sym is feasible with the 5 % margin at every mu


def test_45sym_section_4(paper):
    ref = paper["section_4_45sym"]
    shape = jd.family_shape("45sym")._replace(br_over_hr=ref["br_over_hr"])
    m, _, _ = _margins(shape, ref["mu"])
    start, mid = LOCATIONS.index("start"), LOCATIONS.index("mid")
    assert float(m.dist_pct[start, 0]) == pytest.approx(ref["cycle_start_dist_L1"], abs=0.006)
    # "the left resultant at mid-cycle is completely out of segment L1-L2, over 3.8 times L1-L2"
    assert -float(m.dist_pct[mid, 1]) / 100.0 > ref["mid_cycle_outside_segment_times_L1L2"]
    assert float(m.g[start, KINDS.index("L1")]) < 0  # inside, but closer than 5 % to L1
    assert float(m.g[mid, KINDS.index("L2")]) < 0


def test_74L_lifts_off_at_mu_07():
    m, st, bc = _margins("74L", 0.7)
    assert jd.RESULTS.name_of(st.status) == jd.RESULTS.name_of(bc.status) == "liftoff"
    assert np.any(np.asarray(m.g) < 0)
    assert float(m.min_normal[LOCATIONS.index("start")]) < 0


def test_division_free_constraints_have_the_sign_of_distance_minus_margin():
    rng = np.random.default_rng(0)
    N = rng.uniform(-0.2, 1.0, (2000, 3))
    g = np.asarray(point_constraints(jnp.asarray(N), 0.05, 0.0))
    d = np.asarray(resultant_distances_pct(jnp.asarray(N)))
    left_ok = N[:, 1] + N[:, 2] > 0
    assert np.all(np.sign(g[left_ok, :2]) == np.sign(d[left_ok] - 5.0))
    assert np.all(np.min(g[~left_ok, :2], axis=1) < 0)  # both pads unloaded: always violating
    np.testing.assert_array_equal(g[:, 2], N.min(1))


@pytest.mark.parametrize("name, mu", [("60sym", 0.5), ("74R", 0.7), ("90L", 0.3)])
def test_cycle_extremes_are_at_tract_end_points(name, mu):
    """Dense sampling inside every tract (forces are linear in dv) never beats the end points."""
    m, _, bc = _margins(name, mu)
    assert jd.RESULTS.name_of(bc.status) != "liftoff"
    dense = []
    for half in (bc.forward, bc.backward):
        for k in np.nonzero(np.asarray(half.active))[0]:
            s = np.linspace(0.0, float(half.dv[k]), 101)[:, None]
            dense.append(np.asarray(half.N0[k]) + s * np.asarray(half.dN[k]))
    dense = np.concatenate(dense)
    cyc = LOCATIONS.index("cycle")
    d = np.asarray(resultant_distances_pct(jnp.asarray(dense)))
    assert float(m.dist_pct[cyc, 0]) == pytest.approx(d[:, 0].min(), abs=1e-9)
    assert float(m.dist_pct[cyc, 1]) == pytest.approx(d[:, 1].min(), abs=1e-9)
    assert float(m.min_normal[cyc]) == pytest.approx(dense.min(), abs=1e-12)
    N, mask = cycle_points(bc)
    assert np.asarray(mask).sum() >= 3


def test_select_min_gradient_is_finite_under_jit():
    a = jnp.array([[0.3, 0.1, 0.1], [0.2, 0.5, 0.2]])

    def f(x):
        return jnp.sum(select_min(x * jnp.array([[1.0, 1.0, 1.0]]), -1))

    g = jax.jit(jax.grad(f))(a)
    assert np.all(np.isfinite(np.asarray(g)))
    np.testing.assert_array_equal(np.asarray(g).sum(-1), [1.0, 1.0])
