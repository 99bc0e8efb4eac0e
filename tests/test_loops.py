"""The loop forms of the two kernels: "scan" (masked, every slot), "while" (stops when done) and
"auto" (values by "while", derivatives by the scan program through a custom JVP rule).

Reference: the "scan" program, which is the form every earlier result was computed with. The forms
run the same tract arithmetic, so values agree to rounding and statuses exactly; "auto"
derivatives, forward and reverse, are the scan program's.
"""

import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.amplitude import amplitude_kernel
from jaxdamp.cycle import base_cycle_kernel
from jaxdamp.harmonics import five_numbers_kernel

from helpers import assert_tree_allclose

AMPLITUDES = np.geomspace(0.2, 12.0, 24)  # mrad: stick, microslip and gross slip


def _design(name, mu):
    return jd.params.prepare_inputs(jd.family_shape(name), mu, jd.Contacts(), jd.LoadCase())


@pytest.mark.slow  # 130 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("name,mu,initial", [("74R", 0.5, "gross_slip"), ("90R", 0.5, "assembly"),
                                             ("60sym", 0.3, "assembly"), ("74L", 0.5, "gross_slip")])
def test_amplitude_loop_forms_agree(name, mu, initial):
    s, m, c, ld = _design(name, mu)
    out = {}
    for loop in ("scan", "while", "auto"):
        f = jax.jit(jax.vmap(lambda p, loop=loop: amplitude_kernel(s, m, c, ld, p, initial=initial,
                                                                   loop=loop)))
        out[loop] = f(jnp.asarray(AMPLITUDES))
    ref = out["scan"]
    scale = float(jnp.max(jnp.abs(ref.k_re)))
    for loop in ("while", "auto"):
        got = out[loop]
        np.testing.assert_array_equal(got.status, ref.status)
        np.testing.assert_array_equal(got.cycles, ref.cycles)
        assert_tree_allclose(got.k_re, ref.k_re, rtol=1e-12, atol=1e-12 * scale)
        assert_tree_allclose(got.k_im, ref.k_im, rtol=1e-12, atol=1e-12 * scale)
    assert np.sum(np.asarray(ref.k_im) > 0) >= 8  # dissipative cycles are part of the comparison


@pytest.mark.slow  # 198 worker-s eager (2026-11-25); jitted, still over 10
def test_amplitude_auto_derivatives_are_the_scan_programs():
    s, m, c, ld = _design("74R", 0.5)
    psi = jnp.asarray(AMPLITUDES[8:20:3])

    def total_k_im(theta_l, loop):
        run = lambda p: amplitude_kernel(s._replace(theta_l=theta_l), m, c, ld, p,  # noqa: E731
                                         loop=loop).k_im
        return jnp.sum(jax.vmap(run)(psi))

    # Each derivative is one jitted program: applied eagerly, every loop primitive compiles on
    # its own, slower, and where jaxlib aborted twice (docs/performance.md, "Worker crashes").
    rev = jax.jit(jax.grad(total_k_im), static_argnums=1)
    fwd = jax.jit(jax.jacfwd(total_k_im), static_argnums=1)
    ref = rev(s.theta_l, "scan")
    assert abs(float(ref)) > 1.0
    assert_tree_allclose(rev(s.theta_l, "auto"), ref, rtol=1e-10, atol=0.0)
    assert_tree_allclose(fwd(s.theta_l, "auto"), ref, rtol=1e-10, atol=0.0)
    assert_tree_allclose(fwd(s.theta_l, "while"), ref, rtol=1e-10, atol=0.0)


@pytest.mark.slow  # over 100 worker-s in the fresh-clone run of 2026-11-25
def test_base_cycle_auto_derivatives_are_the_scan_programs():
    s, m, c, ld = _design("60sym", 0.5)

    def k_im(theta_r, loop):
        return five_numbers_kernel(base_cycle_kernel(s._replace(theta_r=theta_r), m, c, ld,
                                                     loop=loop)).k_im_bc

    rev = jax.jit(jax.grad(k_im), static_argnums=1)
    ref = rev(s.theta_r, "scan")
    assert abs(float(ref)) > 1.0
    assert_tree_allclose(rev(s.theta_r, "auto"), ref, rtol=1e-10, atol=0.0)
    assert_tree_allclose(jax.jit(jax.jacfwd(k_im), static_argnums=1)(s.theta_r, "auto"), ref,
                         rtol=1e-10, atol=0.0)
    batched = jax.jit(jax.vmap(jax.grad(k_im), in_axes=(0, None)), static_argnums=1)(
        s.theta_r + jnp.array([0.0, 1.0]), "auto")
    assert_tree_allclose(batched[0], ref, rtol=1e-10, atol=0.0)


def test_unknown_loop_is_refused():
    s, m, c, ld = _design("60sym", 0.5)
    with pytest.raises(ValueError, match="loop must be one of auto, scan, while"):
        amplitude_kernel(s, m, c, ld, 1.0, loop="fori")
    with pytest.raises(ValueError, match="loop must be one of auto, scan, while"):
        base_cycle_kernel(s, m, c, ld, loop="fori")


def test_batched_together_keeps_values_and_batches_every_leaf_with_any():
    """`loops.batched_together`: the carry unchanged (inf, NaN, integers and booleans included),
    and under vmap a leaf that does not depend on the mapped input comes out batched as soon as
    another leaf does (out_axes=None then refuses it), so that a loop's carries are batched from
    its first pass; with no batched leaf nothing is."""
    from jaxdamp.loops import batched_together

    carry = (jnp.array([1.0, jnp.inf, jnp.nan]), jnp.array(3, jnp.int32), jnp.array([True, False]))
    out = batched_together(carry)
    np.testing.assert_array_equal(out[0], carry[0])
    assert out[1].dtype == jnp.int32 and int(out[1]) == 3 and out[2].tolist() == [True, False]

    xs = jnp.arange(4.0)
    alone = jax.vmap(lambda x: batched_together((jnp.ones(2), jnp.zeros(())))[0], out_axes=None)(xs)
    np.testing.assert_array_equal(alone, np.ones(2))  # nothing batched: stays unbatched
    with pytest.raises(ValueError):
        jax.vmap(lambda x: batched_together((x, jnp.ones(2)))[1], out_axes=None)(xs)
    tied = jax.vmap(lambda x: batched_together((x, jnp.ones(2)))[1])(xs)
    np.testing.assert_array_equal(tied, np.ones((4, 2)))


def test_batched_together_ties_the_carry_to_the_loop_inputs():
    """`like`: a carry that starts from values the batch shares (a row's design, vmapped over its
    paths) comes out batched where one of the loop's inputs is, and stays as it is (unbatched,
    unchanged) where none is; `like` itself is not returned."""
    from jaxdamp.loops import batched_together

    xs = jnp.arange(4.0)
    shared = (jnp.ones(2), jnp.array(0, jnp.int32))
    tied = jax.vmap(lambda x: batched_together(shared, like=x))(xs)
    np.testing.assert_array_equal(tied[0], np.ones((4, 2)))
    np.testing.assert_array_equal(tied[1], np.zeros(4, np.int32))
    with pytest.raises(ValueError):
        jax.vmap(lambda x: batched_together(shared, like=x)[0], out_axes=None)(xs)
    alone = jax.vmap(lambda x: batched_together(shared, like=jnp.zeros(3))[0], out_axes=None)(xs)
    np.testing.assert_array_equal(alone, np.ones(2))
    single = batched_together(jnp.ones(2), like=jnp.array(jnp.nan))  # one leaf, NaN input
    np.testing.assert_array_equal(single, np.ones(2))


def test_a_tract_loop_on_batched_paths_is_batched_in_one_pass(monkeypatch):
    """The engine's tract loop from a shared start (one design's statics) on a batch of paths:
    JAX's batching rule finds the loop's batched carries in one pass, since the carry is tied to
    the path (`batched_together(like=...)`), so the body is batched once (the predicate's
    batching of it is the same and cached) instead of once per pass of a fixpoint (three here
    without the tie, each batching every loop nested in the body). The same tracts as each
    path run alone, to rounding (the rates are O(1-100) per mm; a lane's vectorised solve rounds
    differently from a single run's, and a rate that is zero alone may come out as 1e-15)."""
    from jax._src.interpreters import batching
    from jaxdamp.conventions import CENTRIFUGAL_LOAD, travel_mm
    from jaxdamp.ellipse import path_pads
    from jaxdamp.engine import assemble, run
    from jaxdamp.motion import path_parts
    from jaxdamp.paths import Ellipse

    shape, mu, contacts, load = _design("60sym", 0.5)
    motion = jd.interblade_motion(90.0, 25.0, float(load.q_star), 10.0)
    pads = path_pads(shape, mu, contacts, load, path_parts(motion))
    N0, T0, _ = assemble(pads, CENTRIFUGAL_LOAD)
    travel = travel_mm(jnp.array([1.0, 4.0, 10.0]), load.q_star)

    def tracts(s_a):
        return run(pads, Ellipse(s_a), N0, T0, 0.0, 2.0 * jnp.pi, max_tracts=24, loop="while")

    calls = []
    original = batching.batch_jaxpr
    monkeypatch.setattr(batching, "batch_jaxpr",
                        lambda jaxpr, *a, **k: (calls.append(jaxpr), original(jaxpr, *a, **k))[1])
    batched = jax.jit(jax.vmap(tracts))(travel)
    loop_bodies = [j for j in calls if len(j.jaxpr.eqns) > 50]
    assert len(loop_bodies) == 1
    monkeypatch.undo()
    for i, s_a in enumerate(travel):
        assert_tree_allclose(jax.tree_util.tree_map(lambda x: x[i], batched), tracts(s_a),
                             rtol=1e-12, atol=1e-13)


def test_looped_together_gives_every_float_a_tangent_from_the_first_pass(monkeypatch):
    """A while loop whose carry starts from constants, with a body that reads the differentiated
    input: under jvp its JVP rule finds the carries with tangents in one pass (the float carries
    tied to the input, `loops.looped_together`), where the untied carry takes two (one finds
    the floats the input reaches, one checks); its derivatives are the masked scan's, forward
    and vmapped (jacfwd), and the integer and boolean carries pass."""
    from jax._src.interpreters import ad
    from jaxdamp.loops import bounded_loop

    rows = {"b": jax.ShapeDtypeStruct((), float)}

    def run(theta, loop, tie=True):
        def step(c, _):
            a = jnp.where(c["done"], c["a"], c["a"] + theta * c["n"])
            b = jnp.where(c["done"], c["b"], c["b"] + a * a)
            # a finished step's row is inactive (zero), as bounded_loop's masked scan needs
            return (dict(a=a, b=b, n=c["n"] + 1, done=c["done"] | (c["n"] >= 4)),
                    dict(b=jnp.where(c["done"], 0.0, b)))

        init = dict(a=jnp.array(0.0), b=jnp.array(0.0), n=jnp.array(1), done=jnp.array(False))
        end, acc = bounded_loop(step, init, 8, loop, rows, like=theta if tie else None)
        return end["b"] + jnp.sum(acc["b"])

    def passes(tie):  # the JVP rule's passes over the body (not the jnp functions' own JVPs)
        calls = []
        original = ad.jvp_jaxpr

        def counted(jaxpr, *a, **k):
            calls.append(sys._getframe(1).f_code.co_name == "_while_loop_jvp")
            return original(jaxpr, *a, **k)

        monkeypatch.setattr(ad, "jvp_jaxpr", counted)
        jax.jvp(lambda t: run(t, "while", tie), (jnp.array(0.7),), (jnp.array(1.0),))
        monkeypatch.undo()
        return sum(calls)

    assert passes(tie=True) == 1 and passes(tie=False) == 2
    thetas = jnp.array([0.3, 0.7, 1.1])
    assert_tree_allclose(jax.vmap(jax.grad(lambda t: run(t, "scan")))(thetas),
                         jax.jit(jax.vmap(jax.jacfwd(lambda t: run(t, "while"))))(thetas),
                         rtol=1e-14, atol=0)
