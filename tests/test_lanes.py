"""Every tract of a cycle in one loop, and a batch's cycles on a pool of lanes (`jaxdamp.lanes`).

The pool's bookkeeping on a toy lane whose steps are counted (every cycle its own count of steps,
cycles that end before their first step, more cycles than lanes, a batch smaller than the pool);
the elliptic kernel's values through the one loop against the same kernel's nested loops (its
recording pass: periods of tract runs, choosing among every set), one design and batched; and the
pooled batch against the plain vmap of the same cycles, with statuses, periods and k."""

from __future__ import annotations

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
import jaxdamp.lanes as lanes
from helpers import assert_tree_allclose
from jaxdamp.ellipse import elliptic_impl
from jaxdamp.lanes import iterate_lanes, pool_width

jd.enable_x64()


class _Countdown:
    """A lane that steps data["n"] times, adding data["x"] each step (a cycle's length and its
    work); its result is (steps, sum)."""

    def init(self, data):
        return dict(left=data["n"], steps=jnp.array(0), total=jnp.zeros(()), rows=jnp.zeros(2))

    def going(self, c):
        return c["left"] > 0

    def step(self, c, data):
        go = self.going(c)
        return dict(left=c["left"] - go, steps=c["steps"] + go, total=c["total"] + go * data["x"],
                    rows=c["rows"])

    def result(self, c, data):
        return c["steps"], c["total"]


@pytest.mark.parametrize("width", [None, 3, 8])
def test_the_pool_runs_every_cycle_its_own_steps(width):
    rng = np.random.default_rng(1)
    n = rng.integers(0, 9, 37)
    n[[0, 5, 6, 36]] = 0  # cycles that end before their first step, first and last among them
    x = rng.normal(size=37)
    data = dict(n=jnp.asarray(n), x=jnp.asarray(x))
    steps, total = jax.jit(jax.vmap(lambda d: iterate_lanes(_Countdown(), d, width=width)))(data)
    np.testing.assert_array_equal(np.asarray(steps), n)
    assert_tree_allclose(np.asarray(total), n * x, rtol=1e-15, atol=0.0)


def test_the_pool_with_shared_data_and_unbatched():
    data = dict(n=jnp.asarray(4), x=jnp.asarray(0.5))
    steps, total = iterate_lanes(_Countdown(), data)
    assert (int(steps), float(total)) == (4, 2.0)
    f = jax.vmap(lambda n: iterate_lanes(_Countdown(), dict(n=n, x=jnp.asarray(0.5)), width=2))
    steps, total = f(jnp.arange(7))
    np.testing.assert_array_equal(np.asarray(steps), np.arange(7))
    assert_tree_allclose(np.asarray(total), 0.5 * np.arange(7), rtol=1e-15, atol=0.0)


class _Legs(_Countdown):
    """A countdown whose steps come in two parts, as `lanes.Legs`' do: advance every step, close
    where a leg of data["leg"] steps ended (counted, and the leg's work moved to "closed")."""

    def init(self, data):
        return dict(super().init(data), leg=data["leg"], legs=jnp.array(0),
                    closed_at=jnp.array(0), closed=jnp.zeros(()))

    def advance(self, c, data):
        return dict(c, **super().step(c, data))

    def ends(self, c):
        return (c["steps"] > 0) & (c["steps"] % c["leg"] == 0) & (c["closed_at"] < c["steps"])

    def close(self, c, data):
        over = self.ends(c)
        return dict(c, legs=c["legs"] + over, closed_at=jnp.where(over, c["steps"], c["closed_at"]),
                    closed=jnp.where(over, c["total"], c["closed"]))

    def step(self, c, data):
        return self.close(self.advance(c, data), data)

    def result(self, c, data):
        return c["steps"], c["legs"], c["closed"]


def test_lanes_stepping_in_two_parts_close_their_own_legs():
    """A batch too small for the pool (one loop, its lanes together; the closing part runs only in
    steps where some lane's leg ended): every lane its own steps, legs and work at its last leg's
    end."""
    rng = np.random.default_rng(2)
    n, leg = rng.integers(0, 12, 9), rng.integers(1, 5, 9)
    x = rng.normal(size=9)
    lane = _Legs()
    data = dict(n=jnp.asarray(n), x=jnp.asarray(x), leg=jnp.asarray(leg))
    steps, legs, closed = jax.jit(jax.vmap(lambda d: iterate_lanes(lane, d)))(data)
    np.testing.assert_array_equal(np.asarray(steps), n)
    np.testing.assert_array_equal(np.asarray(legs), n // leg)
    assert_tree_allclose(np.asarray(closed), (n // leg) * leg * x, rtol=1e-14, atol=0.0)


def test_pool_width_plain_vmap_for_small_batches():
    assert pool_width(16) is None
    assert pool_width(127) is None
    assert pool_width(256) == lanes.POOL_WIDTH
    assert pool_width(4096) == 4096 // lanes.POOL_SHARE


CONTACTS = jd.Contacts(jnp.asarray(17900.0), jnp.asarray(3580.0))
LOAD = jd.LoadCase(*(jnp.asarray(float(v)) for v in jd.LoadCase(1000.0, 100.0, 0.0)))


def _designs(n, seed=3):
    """n random shapes and mu (benchmarks/ellipse_cost.py's ranges); a wedge of the same angles."""
    rng = np.random.default_rng(seed)
    tl, tr, bl2 = rng.uniform([45.0, 45.0, 0.5], [80.0, 80.0, 0.9], (n, 3)).T
    br, br2, mu = rng.uniform([-0.2, 0.5, 0.3], [0.3, 0.9, 0.7], (n, 3)).T
    curved = jd.DamperShape(*(jnp.asarray(v) for v in (tl, tr, br, bl2)))
    return curved, curved._replace(br_over_hr=jnp.zeros(n), br2_over_hr=jnp.asarray(br2)), mu


def _numbers(cycle):
    return dict(status=cycle.status, periods=cycle.periods, k_re=cycle.k_re, k_im=cycle.k_im,
                energy=cycle.energy, slip=cycle.slip_fraction, open=cycle.open_fraction)


def _kernel(initial, loop, record=False):
    def f(shape, mu, amplitude, motion):
        got = elliptic_impl(shape, mu, CONTACTS, LOAD, amplitude, motion, None, None,
                            initial=initial, max_tracts=32, max_periods=16, loop=loop,
                            record=record)
        return _numbers(got[0] if record else got)
    return f


@pytest.mark.parametrize("initial", ["assembly", "gross_slip"])
def test_one_loop_gives_the_nested_loops_cycles(initial):
    """The values (one loop over the tracts, each tract's proposed set first) against the
    recording pass (periods of runs, each tract choosing among every set): by the proposal's
    contract the same sets, so the same cycles to rounding."""
    curved, wedge, mu = _designs(24)
    motion = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    amplitude = jnp.asarray(np.r_[np.full(12, 2.0), np.full(12, 10.0)])
    for shapes in (curved, wedge):
        got = jax.jit(jax.vmap(_kernel(initial, "while"), (0, 0, 0, None)))(
            shapes, jnp.asarray(mu), amplitude, motion)
        ref = jax.jit(jax.vmap(_kernel(initial, "while", record=True), (0, 0, 0, None)))(
            shapes, jnp.asarray(mu), amplitude, motion)
        assert_tree_allclose(got, ref, rtol=0.0, atol=1e-9)
        one = jax.tree_util.tree_map(lambda x: x[3], shapes)
        single = jax.jit(_kernel(initial, "while"))(one, jnp.asarray(mu[3]), amplitude[3], motion)
        assert_tree_allclose(single, jax.tree_util.tree_map(lambda x: x[3], ref),
                             rtol=0.0, atol=1e-9)


def test_a_pooled_batch_gives_every_cycle_as_its_own_lane(monkeypatch):
    """48 cycles on 8 lanes (a zero amplitude among them: nothing to iterate) against plain vmap,
    every cycle its own lane: the same statuses and periods, k within rounding."""
    curved, wedge, mu = _designs(48, seed=5)
    amplitude = np.linspace(1.0, 12.0, 48)
    amplitude[7] = 0.0
    motion = jd.interblade_motion(45.0, 20.0, 100.0, 10.0)
    for shapes in (curved, wedge):
        monkeypatch.setattr(lanes, "POOL_WIDTH", 10 ** 6)  # no pool: plain vmap
        plain = jax.jit(jax.vmap(_kernel("assembly", "while"), (0, 0, 0, None)))(
            shapes, jnp.asarray(mu), jnp.asarray(amplitude), motion)
        monkeypatch.setattr(lanes, "POOL_WIDTH", 8)
        monkeypatch.setattr(lanes, "POOL_SHARE", 10 ** 6)
        assert pool_width(48) == 8
        pooled = jax.jit(jax.vmap(_kernel("assembly", "while"), (0, 0, 0, None)))(
            shapes, jnp.asarray(mu), jnp.asarray(amplitude), motion)
        np.testing.assert_array_equal(np.asarray(pooled["status"]), np.asarray(plain["status"]))
        np.testing.assert_array_equal(np.asarray(pooled["periods"]), np.asarray(plain["periods"]))
        assert int(plain["status"][7]) == int(jd.RESULTS.singular)  # a = 0: no cycle
        assert len(set(np.asarray(plain["periods"]).tolist())) > 2  # cycles of unequal length
        assert_tree_allclose(pooled, plain, rtol=0.0, atol=1e-9)


def test_a_pooled_curve_of_one_design(monkeypatch):
    """Shared design, batched amplitudes (the data broadcast to every cycle): the pool against
    one call per amplitude."""
    monkeypatch.setattr(lanes, "POOL_WIDTH", 4)
    monkeypatch.setattr(lanes, "POOL_SHARE", 10 ** 6)
    shape = jd.DamperShape(*(None if v is None else jnp.asarray(float(v))
                             for v in jd.family_shape("60sym")))
    motion = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    amplitudes = jnp.linspace(0.5, 20.0, 16)
    f = _kernel("assembly", "while")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        curve = jax.jit(jax.vmap(f, (None, None, 0, None)))(shape, jnp.asarray(0.5), amplitudes,
                                                            motion)
        one = jax.jit(f)
        each = [one(shape, jnp.asarray(0.5), a, motion) for a in amplitudes]
    ref = jax.tree_util.tree_map(lambda *x: jnp.stack(x), *each)
    assert_tree_allclose(curve, ref, rtol=0.0, atol=1e-9)


def test_a_small_batch_s_loop_holds_no_scatter_sort_or_dot(monkeypatch):
    """Where XLA_FLAGS holds `runtime.SMALL_LOOP_FLAG`, a batch of 16 elliptic cycles (lockstep
    lanes; 60sym and a wedge, whose second look retries) lowers with no scatter, sort, dot or
    custom call anywhere in its program, so that XLA's CPU backend compiles its loop as one kernel
    (docs/motions.md, "Against harmonic balance"); without the flag its rows keep their scatter.
    Both give the same cycles (statuses and periods equal; XLA fuses the two programs apart, so
    the numbers may differ in their last bit)."""
    from jaxdamp.runtime import SMALL_LOOP_FLAG

    contacts = jd.Contacts(jnp.asarray(17900.0), jnp.asarray(3580.0))
    load = jd.LoadCase(*(jnp.asarray(float(v)) for v in jd.LoadCase()))
    motion = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    amplitudes = jnp.linspace(1.8, 2.2, 16)
    for shape in (jd.family_shape("60sym"), jd.DamperShape(60.0, 60.0, 0.0, 0.8, None, 0.8)):
        sh = jd.DamperShape(*(None if v is None else jnp.asarray(float(v)) for v in shape))
        cycles = []
        for flagged in (True, False):
            monkeypatch.setenv("XLA_FLAGS", SMALL_LOOP_FLAG if flagged else "")
            f = jax.vmap(lambda a: jd.elliptic_kernel(sh, jnp.asarray(0.5), contacts, load, a,
                                                      motion, initial="assembly"))
            program = jax.jit(f).lower(amplitudes)
            text = program.as_text()
            assert "stablehlo.while" in text
            assert ("stablehlo.scatter" in text) != flagged
            if flagged:
                for op in ("stablehlo.sort", "stablehlo.dot_general", "stablehlo.custom_call"):
                    assert op not in text, (shape, op)
            c = program.compile()(amplitudes)
            cycles.append([np.asarray(x) for x in (c.k_re, c.k_im, c.energy, c.status, c.periods)])
        assert_tree_allclose(cycles[0], cycles[1], rtol=1e-14, atol=0.0)
        for a, b in zip(cycles[0][3:], cycles[1][3:]):
            np.testing.assert_array_equal(a, b)
