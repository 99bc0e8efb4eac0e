"""The one iteration to a periodic cycle (`jaxdamp.periodic`), on maps whose fixed point is known:
its acceleration lands on it, its closure stops there, a failed leg stops it (at once, or at the
end of its round), and a round budget caps it."""

import jax.numpy as jnp
import numpy as np

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.periodic import CLOSE_TOL, MODES, accelerate, iterate_to_periodic

jd.enable_x64()

FIXED = jnp.array([1.0, 0.8, 0.6, 0.2, -0.1, 0.3])  # N > 0, |T| <= 0.5 N: admissible


def _accelerated(mu, states, plain):
    """accelerate() on successive states (the last one where the last round ended)."""
    starts = jnp.stack(states[:-1])[-2 * MODES:]
    starts = jnp.concatenate([jnp.broadcast_to(starts[0], (2 * MODES - starts.shape[0], 6)),
                              starts])
    return accelerate(mu, starts, states[-1], plain)


def test_acceleration_lands_on_the_fixed_point_of_a_geometric_iteration():
    d = jnp.array([0.01, -0.02, 0.005, 0.003, 0.001, -0.002])
    rho = 0.6
    s0, s1, s2 = (FIXED + rho ** k * d for k in range(3))
    guess, jumped = _accelerated(0.5, [s0, s1, s2], 2)
    assert bool(jumped)
    assert_tree_allclose(np.asarray(guess, float), np.asarray(FIXED, float), rtol=1e-12,
                         atol=1e-14)
    # Not geometric along one direction (and no third start), no history, a ratio too close to
    # one, or an inadmissible guess: the plain iterate.
    bent = s2.at[0].add(1e-3)
    slow = [FIXED + 0.97 ** k * d for k in range(3)]
    for mu, states, plain in ((0.5, [s0, s1, bent], 2), (0.5, [s0, s1, s2], 1),
                              (0.5, slow, 2), (0.05, [s0, s1, s2], 2)):
        guess, jumped = _accelerated(mu, states, plain)
        assert not bool(jumped) and np.array_equal(np.asarray(guess), np.asarray(states[-1]))


def test_two_contracting_modes_are_extrapolated_from_five_states():
    """s_k = FIXED + 0.6^k d + (-0.3)^k e: four differences, each the same combination of the two
    before it, and the extrapolation is the fixed point; with four states only, or a third mode,
    it is not (one difference in the span of two is no proof)."""
    d = jnp.array([0.01, -0.02, 0.005, 0.003, 0.001, -0.002])
    e = jnp.array([-0.004, 0.001, 0.006, -0.002, 0.003, 0.001])
    states = [FIXED + 0.6 ** k * d + (-0.3) ** k * e for k in range(5)]
    guess, jumped = _accelerated(0.5, states, 4)
    assert bool(jumped)
    assert_tree_allclose(np.asarray(guess, float), np.asarray(FIXED, float), rtol=1e-12,
                         atol=1e-14)
    assert not bool(_accelerated(0.5, states, 3)[1])
    f = jnp.array([0.001, 0.002, -0.003, 0.001, -0.001, 0.002])
    three = [s + 0.1 ** k * f for k, s in enumerate(states)]
    assert not bool(_accelerated(0.5, three, 4)[1])


def _affine_leg(ratios, fail_at=None):
    """A leg that contracts the state towards FIXED by `ratios` (per component), counting the legs
    run in its records; it fails at leg fail_at."""
    ratios = jnp.asarray(ratios, float)

    def leg(count, N, T, j, k, idle):
        x = FIXED + ratios * (jnp.concatenate([N, T]) - FIXED)
        bad = jnp.array(False) if fail_at is None else j == fail_at
        return x[:3], x[3:], bad, count + 1

    return leg


def _run(leg, *, legs_per_round=1, pre_legs=0, max_rounds=12, loop="while", **kw):
    start = FIXED + jnp.array([0.02, -0.01, 0.01, 0.01, 0.005, -0.01])
    return iterate_to_periodic(leg, start[:3], start[3:], 0.5, jnp.array(0),
                               legs_per_round=legs_per_round, pre_legs=pre_legs,
                               max_rounds=max_rounds, loop=loop, stop0=jnp.array(False), **kw)


def test_a_geometric_iteration_closes_on_its_fixed_point_in_three_rounds():
    """One contraction ratio: rounds 1 and 2 give the history, the accelerated start of round 3
    is the fixed point, which round 3 then repeats (closure). Both loop forms agree."""
    for loop in ("while", "scan"):
        end = _run(_affine_leg(jnp.full(6, 0.5)), loop=loop)
        assert bool(end["closed"]) and int(end["rounds"]) == 3, loop
        assert float(end["gap"]) <= CLOSE_TOL
        assert_tree_allclose(np.asarray(end["top"]), np.asarray(FIXED), rtol=0, atol=1e-14)


def test_two_ratios_close_in_five_rounds():
    """Two ratios (0.9 and 0.5): rounds 1-4 give four differences in two directions, the start
    of round 5 is the fixed point, which round 5 repeats."""
    end = _run(_affine_leg(jnp.array([0.9, 0.5, 0.5, 0.5, 0.5, 0.5])))
    assert bool(end["closed"]) and int(end["rounds"]) == 5
    # The extrapolation divides the iterates' rounding (1e-16 of 1) by 1 - 0.9.
    assert_tree_allclose(np.asarray(end["top"]), np.asarray(FIXED), rtol=0, atol=1e-13)


def test_with_three_ratios_it_iterates_plainly_and_may_not_close():
    """Three ratios: more modes than MODES, so no acceleration (the 0.5 mode is still 1e-3 of
    the 0.9 one after 12 rounds); at 0.9 per round the state is 1e-3 F_D away after 12 rounds
    (0.9^12 of 0.02), which is not periodic."""
    ratios = jnp.array([0.9, 0.7, 0.5, 0.5, 0.5, 0.5])
    end = _run(_affine_leg(ratios), max_rounds=12)
    assert not bool(end["closed"]) and int(end["rounds"]) == 12 and int(end["records"]) == 12
    assert float(end["gap"]) > 1e-4


def test_a_failed_leg_stops_at_once_or_at_the_end_of_its_round():
    leg = _affine_leg(jnp.full(6, 0.5), fail_at=2)  # the first leg of the second pair
    at_once = _run(leg, legs_per_round=2)
    assert int(at_once["records"]) == 3 and not bool(at_once["closed"])
    whole = _run(leg, legs_per_round=2, whole_rounds=True)
    assert int(whole["records"]) == 4 and int(whole["rounds"]) == 2 and not bool(whole["closed"])


def test_preliminary_legs_run_first_and_a_budget_caps_the_rounds():
    ratios = jnp.array([0.9, 0.7, 0.5, 0.5, 0.5, 0.5])
    end = _run(_affine_leg(ratios), pre_legs=2, round_budget=jnp.array(3))
    assert int(end["records"]) == 2 + 3 and int(end["rounds"]) == 3
