"""Two stages inside one program (`jaxdamp.stages.second_look`): the fast result where it holds,
the full one where the fast one asks for a second look, unbatched, batched (more flagged lanes
than a chunk, none, all), with shared arguments, nested vmap and forward mode; and the tract
engine's use of it (each tract's state choice proposes the previous tract's set with the event
pads changed first), against the choice among every set."""

from __future__ import annotations

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.params import prepare_inputs
from jaxdamp.stages import second_look

jd.enable_x64()


def _fast(x, scale):
    return {"y": x * scale, "again": x > 0.5}


def _full(x, scale):
    # Marks what it computed, so that a lane run in full cannot pass for a fast one.
    return {"y": 100.0 * x * scale + 1.0, "again": x > 0.5}


def _expected(x, scale):
    x = np.asarray(x, float)
    return np.where(x > 0.5, 100.0 * x * scale + 1.0, x * scale)


F = second_look(_fast, _full, lambda out: out["again"], chunk=4)


def test_unbatched_it_is_the_fast_result_or_the_full_one_where_asked():
    for x in (0.2, 0.9):
        assert float(F(jnp.asarray(x), 2.0)["y"]) == pytest.approx(float(_expected(x, 2.0)))


@pytest.mark.parametrize("xs", [np.linspace(0.0, 1.0, 11),  # 5 flagged: two chunks of 4
                                np.linspace(0.0, 0.4, 7),  # none flagged
                                np.linspace(0.6, 1.0, 9),  # all flagged, past a whole chunk
                                np.array([0.9])])
def test_batched_the_flagged_lanes_and_only_they_run_in_full(xs):
    got = jax.jit(jax.vmap(F, in_axes=(0, None)))(jnp.asarray(xs), 2.0)
    np.testing.assert_array_equal(np.asarray(got["y"]), _expected(xs, 2.0))
    np.testing.assert_array_equal(np.asarray(got["again"]), xs > 0.5)


def _retry(out, x, scale):
    # A second try that holds where x < 0.8 (it marks itself: 10 x scale), asks again above.
    return {"y": 10.0 * x * scale, "again": x >= 0.8}


G = second_look(_fast, _full, lambda out: out["again"], chunk=4, retry=_retry)


def test_batched_a_retry_is_kept_where_it_holds_and_the_full_one_runs_where_not():
    xs = np.linspace(0.0, 1.0, 11)
    got = jax.jit(jax.vmap(G, in_axes=(0, None)))(jnp.asarray(xs), 2.0)
    want = np.where(xs <= 0.5, xs * 2.0, np.where(xs < 0.8, 10.0 * xs * 2.0,
                                                   100.0 * xs * 2.0 + 1.0))
    np.testing.assert_array_equal(np.asarray(got["y"]), want)
    # Unbatched there is no retry: the fast result or the full one, as without it.
    for x in (0.2, 0.6, 0.9):
        assert float(G(jnp.asarray(x), 2.0)["y"]) == pytest.approx(float(_expected(x, 2.0)))


@pytest.mark.parametrize("n_low, n_high, small_loops", [
    (20, 40, True),  # 60 lanes: the sort and the scatter
    (8, 22, True),  # 30 lanes (SMALL_LANES) under runtime.SMALL_LOOP_FLAG: neither
    (8, 22, False)])  # without the flag: the sort and the scatter
def test_a_wide_batch_retries_only_its_first_flagged_lanes_and_the_rest_run_in_full(
        monkeypatch, n_low, n_high, small_loops):
    # Lanes flagged (x > 0.5) in a shuffled order: the retry runs on the first RETRY_LANES
    # flagged lanes (lane order) and holds there where x < 0.8; every other flagged lane runs in
    # full, the unflagged keep the fast result.
    from jaxdamp.runtime import SMALL_LOOP_FLAG
    from jaxdamp.stages import RETRY_LANES, SMALL_LANES

    monkeypatch.setenv("XLA_FLAGS", SMALL_LOOP_FLAG if small_loops else "")
    assert (n_low + n_high <= SMALL_LANES) == (n_high < 40)
    xs = np.random.default_rng(5).permutation(np.concatenate([np.linspace(0.0, 0.5, n_low),
                                                              np.linspace(0.51, 1.0, n_high)]))
    program = jax.jit(jax.vmap(G, in_axes=(0, None))).lower(jnp.asarray(xs), 2.0)
    assert ("stablehlo.sort" in program.as_text()) != (small_loops and len(xs) <= SMALL_LANES)
    got = program.compile()(jnp.asarray(xs), 2.0)
    flagged = xs > 0.5
    first = flagged & (np.cumsum(flagged) <= RETRY_LANES)
    want = np.where(~flagged, xs * 2.0, np.where(first & (xs < 0.8), 10.0 * xs * 2.0,
                                                 100.0 * xs * 2.0 + 1.0))
    assert np.sum(first & (xs < 0.8)) >= 4 and np.sum(flagged & ~first) >= 5
    np.testing.assert_array_equal(np.asarray(got["y"]), want)
    np.testing.assert_array_equal(np.asarray(got["again"]), flagged & ~(first & (xs < 0.8)))


def test_batched_shared_and_batched_arguments_nested_vmap_and_forward_mode():
    xs = jnp.asarray(np.linspace(0.0, 1.0, 6))
    scales = jnp.asarray([1.0, 3.0, 5.0])
    both = jax.vmap(jax.vmap(F, in_axes=(0, None)), in_axes=(None, 0))(xs, scales)
    np.testing.assert_array_equal(np.asarray(both["y"]),
                                  np.stack([_expected(xs, s) for s in (1.0, 3.0, 5.0)]))
    # d y / d scale: x (fast) or 100 x (full), lane by lane.
    _, dy = jax.jvp(lambda s: jax.vmap(F, in_axes=(0, None))(xs, s)["y"], (2.0,), (1.0,))
    assert_tree_allclose(np.asarray(dy), np.where(xs > 0.5, 100.0 * xs, xs), rtol=1e-15, atol=0.0)


def test_the_engine_s_first_look_gives_the_choice_among_every_set_in_a_mixed_batch():
    """45sym at 5 mrad: at phi 30 and 90 deg a pad opens for 40 % of the period, at 150 deg none
    does. In one batch the lanes whose proposed set is not consistent choose again among every
    set (second look), the others keep the proposal; every lane equals the masked scan's cycle
    (which always chooses among every set, and is the derivatives' program)."""
    shape = jd.family_shape("45sym")
    contacts = jd.Contacts(17900.0, 3580.0)
    phis = [30.0, 150.0, 90.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        batch = jd.interblade_sweep(shape, 0.5, 5.0, phis, 20.0, 10.0, contacts)
    opened = np.max(np.asarray(batch.open_fraction), axis=1)
    assert np.any(opened > 0.3) and np.any(opened == 0.0)  # both kinds of lane: the test means it
    sh, mu, c, load = prepare_inputs(shape, 0.5, contacts, jd.LoadCase())
    every_set = jax.jit(jd.elliptic_kernel, static_argnames=("initial", "loop"))
    for i, phi in enumerate(phis):
        motion = jax.tree_util.tree_map(lambda x, i=i: x[i], batch.motion)
        ref = every_set(sh, mu, c, load, jnp.asarray(5.0), motion, loop="scan")
        assert jd.RESULTS.name_of(batch.status[i]) == jd.RESULTS.name_of(ref.status) == "ok"
        scale = max(abs(float(ref.k_re)), abs(float(ref.k_im)))
        assert_tree_allclose((batch.k_re[i], batch.k_im[i]), (ref.k_re, ref.k_im), rtol=0,
                             atol=1e-9 * scale)
        assert_tree_allclose(batch.open_fraction[i], ref.open_fraction, rtol=0, atol=1e-9)
        assert_tree_allclose(batch.slip_fraction[i], ref.slip_fraction, rtol=0, atol=1e-9)


@pytest.mark.slow
def test_random_designs_batched_give_the_cycles_of_the_choice_among_every_set():
    """Random curved-flat dampers and wedges (pads_vs_marcher.py's ranges, and wider base angles,
    whose dampers are often unseated: a batch with lanes that stop at once) on random ellipses:
    the batched while loops (proposed sets first, lanes whose iteration stopped idle) give each
    design the masked scan's cycle (every set chosen in every tract), status, periods and k."""
    rng = np.random.default_rng(11)
    n = 12
    # Scalar stiffnesses (a wedge has four pads); the kernel takes inputs as prepared arrays.
    c = jd.Contacts(jnp.asarray(17900.0), jnp.asarray(3580.0))
    load = jd.LoadCase(*(jnp.asarray(float(v)) for v in jd.LoadCase()))
    tl, tr = rng.uniform(40.0, 80.0, (2, n))
    br, bl2, br2 = rng.uniform([-0.2, 0.5, 0.5], [0.3, 0.9, 0.9], (n, 3)).T
    mu, phi, psi = rng.uniform([0.3, 20.0, 1.0], [0.7, 160.0, 12.0], (n, 3)).T
    motions = [jd.interblade_motion(float(f), 20.0, 100.0, 10.0) for f in phi]
    motion = jax.tree_util.tree_map(lambda *x: jnp.stack(x), *motions)
    kernel = lambda loop: lambda s, m, a, mot: jd.elliptic_kernel(  # noqa: E731
        s, m, c, load, a, mot, initial="assembly", loop=loop)
    every_set = jax.jit(kernel("scan"))
    for wedge in (False, True):
        shape = jd.DamperShape(*(jnp.asarray(v) for v in (tl, tr, br, bl2)), None,
                               jnp.asarray(br2) if wedge else None)
        batch = jax.jit(jax.vmap(kernel("while")))(shape, jnp.asarray(mu), jnp.asarray(psi), motion)
        statuses = set()
        for i in range(n):
            one = jax.tree_util.tree_map(lambda x, i=i: x[i], (shape, mu, psi, motion))
            ref = every_set(*one)
            statuses.add(jd.RESULTS.name_of(ref.status))
            assert int(batch.status[i]) == int(ref.status), (wedge, i)
            assert int(batch.periods[i]) == int(ref.periods), (wedge, i)
            scale = max(abs(float(ref.k_re)), abs(float(ref.k_im)), 1e-300)
            assert_tree_allclose((batch.k_re[i], batch.k_im[i]), (ref.k_re, ref.k_im), rtol=0,
                                 atol=1e-9 * scale)
        assert "ok" in statuses, wedge  # the test compares cycles, not only failures
