"""Record and replay (`engine.Tape`, `loops.values_by_replay`): the derivatives of a path cycle
differentiate a replay of the choices its value pass made, so the replay must be the same cycle.
Here the replay of a recorded tape reproduces the value pass's cycle (both pad sets, pads that
open and close, both histories), and the derivatives of the replay agree with those of the masked
scan that chooses among every set (the program they replace) and with central differences; the
forward-mode replay in while loops (loop="forward") gives the same derivatives."""

from __future__ import annotations

import functools
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from helpers import assert_tree_allclose
from jaxdamp.ellipse import elliptic_impl
from jaxdamp.params import prepare_inputs

jd.enable_x64()

CONTACTS = jd.Contacts(17900.0, 3580.0)
WEDGE = jd.DamperShape(70.0, 50.0, 0.0, 0.6, None, 0.8)  # pads open at phi 120 deg, 20 mrad


def _impl(shape, phi, psi, initial):
    sh, mu, c, load = prepare_inputs(shape, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)
    motion = jd.interblade_motion(phi, 20.0, 100.0, 10.0)
    run = functools.partial(elliptic_impl, initial=initial, max_tracts=32, max_periods=16)
    return run, (sh, mu, c, load, jnp.asarray(psi), motion, None, None)


@pytest.mark.parametrize("shape,phi,psi,initial", [
    (jd.family_shape("60sym"), 90.0, 2.0, "assembly"),
    (WEDGE, 120.0, 20.0, "gross_slip"),
])
def test_a_replay_of_the_recorded_choices_is_the_value_pass_s_cycle(shape, phi, psi, initial):
    run, args = _impl(shape, phi, psi, initial)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        cycle, tape = jax.jit(lambda *a: run(*a, loop="while", record=True))(*args)
        # The replay as a masked scan (loop="auto"'s derivatives) and in while loops that stop
        # where the recorded run did (loop="forward"'s).
        replays = [jax.jit(lambda *a, t, loop=loop: run(*a, loop=loop, tape=t))(*args, t=tape)
                   for loop in ("scan", "while")]
    scale = max(abs(float(cycle.k_re)), abs(float(cycle.k_im)))
    for again in replays:
        assert jd.RESULTS.name_of(cycle.status) == jd.RESULTS.name_of(again.status) == "ok"
        assert int(again.periods) == int(cycle.periods)
        assert_tree_allclose((again.k_re, again.k_im), (cycle.k_re, cycle.k_im), rtol=0,
                             atol=1e-9 * scale)
        assert_tree_allclose(again.energy, cycle.energy, rtol=0,
                             atol=1e-9 * float(jnp.sum(cycle.energy)))
        assert_tree_allclose((again.open_fraction, again.slip_fraction),
                             (cycle.open_fraction, cycle.slip_fraction), rtol=0, atol=1e-9)
    # What the tape holds: per tract the event that ended it (kind * P + pad) or -1 (the
    # period's end), consistent choices wherever a tract ran.
    n_pads = cycle.energy.shape[0]
    events = np.asarray(tape["legs"].event)
    assert events.min() >= -1 and events.max() < 5 * n_pads
    active = np.asarray(cycle.period.active)
    assert np.sum(events[int(cycle.periods) - 1 + (initial == "assembly")][active] == -1) == 1
    if phi == 120.0:
        assert float(np.max(cycle.open_fraction)) > 0.1  # pads do open: the case means it


@pytest.mark.slow  # two derivative programs of the elliptic kernel (scan and replay)
def test_the_replay_s_derivatives_are_the_choosing_scan_s_and_central_differences():
    """d k / d(mu, F_D) through the replay (loop="auto") against the masked scan that chooses
    among every set (loop="scan", the derivatives' program before the replay) and against
    central differences, on the wedge whose pads open."""
    sh, _, c, load = prepare_inputs(WEDGE, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)
    motion = jd.interblade_motion(120.0, 20.0, 100.0, 10.0)

    def k(x, loop):
        cyc = jd.elliptic_kernel(sh, x[0], c, load._replace(F_D=x[1]), jnp.asarray(20.0), motion,
                                 initial="gross_slip", loop=loop)
        return jnp.stack([cyc.k_re, cyc.k_im])

    x0 = jnp.array([0.5, 1000.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        replay = jax.jit(jax.jacfwd(lambda x: k(x, "auto")))(x0)
        scan = jax.jit(jax.jacfwd(lambda x: k(x, "scan")))(x0)
        reverse = jax.jit(jax.jacrev(lambda x: k(x, "auto")))(x0)
        forward = jax.jit(jax.jacfwd(lambda x: k(x, "forward")))(x0)  # the replay's while loops
        with pytest.raises(ValueError, match="Reverse-mode differentiation does not work"):
            jax.jacrev(lambda x: k(x, "forward"))(x0)
        value = jax.jit(lambda x: k(x, "while"))
        h = np.array([1e-6, 1e-3])
        central = np.stack([(np.asarray(value(x0.at[i].add(h[i])))
                             - np.asarray(value(x0.at[i].add(-h[i])))) / (2 * h[i])
                            for i in range(2)], axis=1)
    scale = float(np.max(np.abs(central)))
    assert_tree_allclose(replay, scan, rtol=0, atol=1e-9 * scale)
    assert_tree_allclose(reverse, replay, rtol=0, atol=1e-12 * scale)
    assert_tree_allclose(forward, replay, rtol=0, atol=1e-12 * scale)
    assert_tree_allclose(replay, central, rtol=0, atol=1e-6 * scale)


@pytest.mark.slow  # one derivative program of the elliptic kernel
@pytest.mark.parametrize("shape,phi,psi,initial", [
    (jd.family_shape("60sym"), 90.0, 3.0, "assembly"),
    (WEDGE, 120.0, 20.0, "gross_slip"),
])
def test_derivatives_with_respect_to_the_path_itself(shape, phi, psi, initial):
    """d(k_re, k_im, energy per pad, work) / dX_hat (the path's direction and quadrature: six
    numbers, so that a modal file's platform motions are differentiable too) through the replay,
    forward and reverse, against central differences of the value pass."""
    sh, mu, c, load = prepare_inputs(shape, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)
    motion = jd.interblade_motion(phi, 20.0, 100.0, 10.0)

    def numbers(x, loop):
        path = motion._replace(direction=x[:3], quadrature=x[3:])
        cyc = jd.elliptic_kernel(sh, mu, c, load, jnp.asarray(psi), path, initial=initial,
                                 loop=loop)
        assert cyc.energy.ndim == 1
        return jnp.concatenate([jnp.stack([cyc.k_re, cyc.k_im, cyc.work]), cyc.energy]), cyc.status

    x0 = jnp.concatenate([jnp.asarray(motion.direction, float),
                          jnp.asarray(motion.quadrature, float)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        assert jd.RESULTS.name_of(jax.jit(lambda x: numbers(x, "while")[1])(x0)) == "ok"
        fwd = jax.jit(jax.jacfwd(lambda x: numbers(x, "auto")[0]))(x0)
        rev = jax.jit(jax.jacrev(lambda x: numbers(x, "auto")[0]))(x0)
        value = jax.jit(lambda x: numbers(x, "while")[0])
        h = 1e-7 * float(jnp.max(jnp.abs(x0)))
        central = np.stack([(np.asarray(value(x0.at[i].add(h))) - np.asarray(value(x0.at[i].add(-h))))
                            / (2 * h) for i in range(6)], axis=1)
    scale = np.max(np.abs(central), axis=1, keepdims=True)  # per output: k, work, energies
    assert np.all(scale[:3] > 0)
    # A pad that never slips (the wedge's fourth here) dissipates nothing whatever the path: its
    # derivatives are held to the other pads' scale.
    scale = np.where(scale > 0, scale, np.max(scale[3:]))
    assert_tree_allclose(rev, fwd, rtol=0, atol=1e-10 * scale)
    assert_tree_allclose(fwd, central, rtol=0, atol=1e-6 * scale)
