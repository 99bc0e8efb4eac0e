"""The loop forms of the two kernels: "scan" (masked, every slot), "while" (stops when done) and
"auto" (values by "while", derivatives by the scan program through a custom JVP rule).

Reference: the "scan" program, which is the form every earlier result was computed with. The forms
run the same tract arithmetic, so values agree to rounding and statuses exactly; "auto"
derivatives, forward and reverse, are the scan program's.
"""

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
