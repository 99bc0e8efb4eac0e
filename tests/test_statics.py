import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd

from helpers import assert_tree_allclose


@pytest.mark.parametrize("row", [0, 1, 2])
def test_table1_distances(paper, row):
    ref = paper["table_1_60sym_resultant_distance"]["rows"][row]
    st = jd.full_slip_statics(jd.family_shape("60sym"), ref["mu"])
    assert abs(float(st.start.resultant_pos_pct) - ref["dist_L1"]) <= 0.1
    assert abs((100.0 - float(st.mid.resultant_pos_pct)) - ref["dist_L2"]) <= 0.1
    assert jd.RESULTS.name_of(st.status) == "ok"


def test_45sym_section4(paper):
    ref = paper["section_4_45sym"]
    st = jd.full_slip_statics(jd.DamperShape(45.0, 45.0, ref["br_over_hr"]), ref["mu"])
    assert abs(float(st.start.resultant_pos_pct) - 2.94) < 0.005
    beyond_l2 = (float(st.mid.resultant_pos_pct) - 100.0) / 100.0
    assert abs(beyond_l2 - 3.83) < 0.005
    assert jd.RESULTS.name_of(st.status) == "liftoff"
    assert float(st.min_normal_over_fd) < 0


@pytest.mark.parametrize("mu", [0.7, 0.5, 0.3])
def test_60sym_full_slip_energy_split(mu):
    w = np.asarray(jd.full_slip_work_shape_factors(jd.family_shape("60sym"), mu))
    w_r1, w_l1, w_l2, w_m = w
    assert np.isclose(w_r1 / w_m, 0.5, atol=1e-12)  # R1 takes exactly half (paper §10.1)
    rest = w_l1 + w_l2
    assert abs(w_l1 / rest - 2 / 3) < 0.01 and abs(w_l2 / rest - 1 / 3) < 0.01
    assert np.isclose(w_r1 + w_l1 + w_l2, w_m, rtol=1e-12)  # Appendix C identity


def test_full_slip_forces_balance_F_D():
    shape = jd.family_shape("74R")
    st = jd.full_slip_statics(shape, 0.5)
    g = jd.blocks.section_geometry(shape)
    for end in (st.start, st.mid):
        f = -end.N[:, None] * g.normals + end.T[:, None] * g.tangents
        total = np.asarray(jnp.sum(f, 0)) + np.array([0.0, 1.0])
        assert_tree_allclose(total, np.zeros(2), rtol=1e-5, atol=1e-13)
        r = np.asarray(g.points) - np.asarray(g.D)
        mom = np.sum(r[:, 0] * np.asarray(f[:, 1]) - r[:, 1] * np.asarray(f[:, 0]))
        assert abs(mom) < 1e-13
        assert_tree_allclose(jnp.abs(end.T), 0.5 * end.N, rtol=1e-5, atol=1e-8)


@pytest.mark.parametrize("name,expected", [("60sym", 0.14), ("74R", 0.08), ("90R", 0.00)])
def test_design_rule(name, expected):
    res = jd.design_br(jd.family_shape(name), 0.7)
    assert bool(res.found) and bool(res.inside)
    assert abs(float(res.br_over_hr) - expected) <= 0.01


def test_design_rule_45sym_no_valid_br_at_0p7_and_marginal_0p20_at_0p5():
    assert not bool(jd.design_br(jd.family_shape("45sym"), 0.7).inside)
    # §4: b_R/h = 0.20 is the optimum for mu = 0.5 but "at high risk of rolling": the centred
    # resultant sits on the pads themselves (zero margin).
    res = jd.design_br(jd.family_shape("45sym"), 0.5)
    assert abs(float(res.br_over_hr) - 0.20) <= 0.01
    assert abs(float(res.margin_pct)) < 0.5


def test_statics_is_jitted_and_vmaps():
    shapes = jd.DamperShape(jnp.array([60.0, 49.1, 40.9]), jnp.array([60.0, 73.9, 90.0]),
                            jnp.array([0.14, 0.08, 0.0]), jnp.full(3, 0.8))
    from jaxdamp.statics import statics_kernel

    batched = jax.vmap(statics_kernel, in_axes=(0, None))(shapes, 0.5)
    for i in range(3):
        one = jd.full_slip_statics(jd.DamperShape(*(float(x[i]) for x in shapes[:3])), 0.5)
        assert_tree_allclose(batched.start.N[i], one.start.N, rtol=1e-13, atol=1e-8)
    assert batched.start.N.dtype == jnp.float64


def test_bad_mu():
    with pytest.raises(ValueError, match=r"mu must be in \(0"):
        jd.full_slip_statics(jd.family_shape("60sym"), 0.0)
    with pytest.raises(ValueError, match="mu"):
        jd.full_slip_statics(jd.family_shape("60sym"), -0.3)


def test_design_rule_refuses_a_bracket_out_of_range_or_order():
    shape = jd.family_shape("60sym")
    with pytest.raises(ValueError, match=r"^lo must be in \[-0.5, 0.5\]; got -5$"):
        jd.design_br(shape, lo=-5.0)
    with pytest.raises(ValueError, match=r"^lo must be below hi \(b_R/h_R\); got lo 0.4, hi -0.4$"):
        jd.design_br(shape, lo=0.4, hi=-0.4)
