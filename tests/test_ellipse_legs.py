"""The legs of an elliptic cycle (`jaxdamp.ellipse_legs`): assembly's straight move, run on an
ellipse of zero width, against the same move on a `Line` (the straight engine's path).

The two parametrise one straight path differently (travel s on the line; on the ellipse
s = -2 s_a cos tau from tau = pi/2 to 2 pi/3), and each finds its events in closed form, so the
same tracts must come out: the same states tract by tract, the events at the same travel, the
same forces at the end."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.conventions import CENTRIFUGAL_LOAD, travel_mm
from jaxdamp.ellipse import along_line, path_pads
from jaxdamp.ellipse_legs import MOVE_TAU, leg_runs
from jaxdamp.engine import assemble, run
from jaxdamp.motion import path_parts
from jaxdamp.paths import Line
from jaxdamp.tract import STICK

from helpers import assert_tree_allclose

jd.enable_x64()

CONTACTS = jd.Contacts(17900.0, 3580.0)


def _designs(n, seed):
    rng = np.random.default_rng(seed)
    for i in range(n):
        tl, tr, bl2 = rng.uniform([45.0, 45.0, 0.5], [80.0, 80.0, 0.9])
        wedge = i % 2 == 1
        shape = (jd.DamperShape(tl, tr, 0.0, bl2, None, rng.uniform(0.5, 0.9)) if wedge
                 else jd.DamperShape(tl, tr, rng.uniform(-0.2, 0.3), bl2))
        phi, h_c, psi = rng.uniform([-179.0, 10.0, 1.0], [179.0, 40.0, 25.0])
        yield shape, float(rng.uniform(0.3, 0.7)), float(psi), jd.interblade_motion(phi, h_c,
                                                                                    100.0, 10.0)


@jax.jit
def _both_moves(shape, mu, psi, motion):
    load = jd.LoadCase()
    pads = path_pads(shape, mu, CONTACTS, load, path_parts(motion))
    N, T, ok = assemble(pads, CENTRIFUGAL_LOAD)
    s_a = travel_mm(psi, load.q_star)
    n_pads = N.shape[0]
    stuck = (jnp.full(n_pads, STICK), jnp.array(True))
    line = run(along_line(pads, -1.0), Line(), N, T, 0.0, s_a, max_tracts=32, loop="while",
               start_set=stuck)
    leg_pads, path, start, end = leg_runs(2)(pads, s_a, jnp.array(-2))
    leg = run(leg_pads, path, N, T, start, end, max_tracts=32, loop="while", start_set=stuck)
    return ok, s_a, line, leg


@pytest.mark.parametrize("seed", [0, 1])
def test_the_move_on_an_ellipse_of_zero_width_is_the_move_on_a_line(seed):
    compared = 0
    for shape, mu, psi, motion in _designs(12, seed):
        ok, s_a, line, leg = _both_moves(shape, mu, psi, motion)
        if not bool(ok):
            continue
        assert int(leg.status) == int(line.status)
        active = np.asarray(line.active)
        np.testing.assert_array_equal(np.asarray(leg.active), active)
        np.testing.assert_array_equal(np.asarray(leg.state)[active], np.asarray(line.state)[active])
        # Each tract's end, in travel along the line: s = -2 s_a cos tau on the ellipse.
        s_line = np.asarray(line.p0 + line.dp)[active]
        s_leg = -2.0 * float(s_a) * np.cos(np.asarray(leg.p0 + leg.dp)[active])
        assert_tree_allclose(s_leg, s_line, rtol=0.0, atol=1e-12 * float(s_a))
        assert_tree_allclose((np.asarray(leg.N_end), np.asarray(leg.T_end)),
                             (np.asarray(line.N_end), np.asarray(line.T_end)), rtol=0.0,
                             atol=1e-12)
        assert float(leg.p_end) == pytest.approx(MOVE_TAU[1], abs=1e-15)
        compared += 1
    assert compared >= 8


def test_leg_runs_refuse_a_count_of_preliminary_legs_they_do_not_know():
    with pytest.raises(ValueError, match="pre_legs must be 0 or 2"):
        leg_runs(1)
