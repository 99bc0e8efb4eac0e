import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd

from helpers import assert_tree_allclose


def test_family_angles_follow_vertex_steps():
    # The family keeps base B and height H = B*sqrt(3)/2 and moves the vertex by B/4 (MODEL.md).
    for k, name in zip(range(-2, 3), ["90L", "74L", "60sym", "74R", "90R"]):
        x_v = 0.5 + k / 4.0
        h = np.sqrt(3) / 2
        tl = np.degrees(np.arctan2(h, x_v))
        tr = np.degrees(np.arctan2(h, 1 - x_v))
        s = jd.family_shape(name)
        assert abs(s.theta_l - tl) < 0.05 and abs(s.theta_r - tr) < 0.05


def test_pads_lie_on_flanks_and_reference_points_align():
    g = jd.blocks.section_geometry(jd.family_shape("60sym"))
    # L, D and R on one horizontal line (the paper's reference line through L).
    assert_tree_allclose(np.array([g.L[1], g.D[1], g.R[1]]), np.full(3, 0.5), rtol=1e-5, atol=1e-8)
    # L1 above L2 on the left flank, 2 b_L = 0.8 h_L apart.
    r1, l1, l2 = np.asarray(g.points)
    assert l1[1] > l2[1]
    assert np.isclose(np.linalg.norm(l1 - l2), 0.8 * float(g.h_l))
    # R1 = R + b_R e_R with b_R = 0.14 h_R, on the right flank.
    assert np.isclose(np.linalg.norm(r1 - np.asarray(g.R)), 0.14 * float(g.h_r))
    # normals are unit and orthogonal to tangents
    n, t = np.asarray(g.normals), np.asarray(g.tangents)
    assert_tree_allclose(np.sum(n * n, 1), np.ones(3), rtol=1e-5, atol=1e-8)
    assert_tree_allclose(np.sum(n * t, 1), np.zeros(3), rtol=1e-5, atol=1e-8)


def test_centroid_default_and_override():
    s = jd.family_shape("74R")
    g = jd.blocks.section_geometry(s)
    assert np.isclose(g.D[0], (g.A[0] + g.B[0] + g.V[0]) / 3)
    g2 = jd.blocks.section_geometry(s._replace(x_d=0.3))
    assert np.isclose(g2.D[0], 0.3)


def test_vertical_flank_is_finite_and_differentiable():
    def f(tl):
        return jnp.sum(jd.blocks.section_geometry(jd.DamperShape(tl, 40.9, 0.15)).points)

    assert np.isfinite(f(90.0))
    assert np.isfinite(jax.grad(f)(90.0))


@pytest.mark.parametrize("kw,name", [
    (dict(theta_l=0.0), "theta_l"), (dict(theta_l=95.0), "theta_l"), (dict(theta_r=-3.0), "theta_r"),
    (dict(bl2_over_hl=1.2), "bl2_over_hl"), (dict(bl2_over_hl=0.0), "bl2_over_hl"),
    (dict(theta_r=float("nan")), "theta_r"),
])
def test_bad_shape_names_parameter_and_range(kw, name):
    base = dict(theta_l=60.0, theta_r=60.0, br_over_hr=0.14)
    base.update(kw)
    with pytest.raises(ValueError, match=name):
        jd.full_slip_statics(jd.DamperShape(**base), 0.5)


def test_unknown_family_name():
    with pytest.raises(ValueError, match="shape must be one of"):
        jd.family_shape("61sym")
