"""The tract engine on any pad set, with pads that open and close (jaxdamp.engine).

References: the time marcher (`baselines.march_ellipse`: Newton with return mapping and gaps at
every step, no event logic), physics identities (equilibrium and the friction cone in every tract,
the work of the modal forces against the energy at the pads, mirror symmetry) and central
differences.
"""

from __future__ import annotations

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp.conventions import CENTRIFUGAL_LOAD
from jaxdamp.ellipse import elliptic_kernel, path_pads
from jaxdamp.engine import candidate_table
from jaxdamp.geometry import pad_names
from jaxdamp.motion import path_parts
from jaxdamp.params import prepare_inputs
from jaxdamp.tract import OPEN, SLIP

from helpers import assert_tree_allclose

CONTACTS = jd.Contacts(17900.0, 3580.0)
# An asymmetric wedge whose pads open on these paths (R1, L1 and L2 at phi = 120 deg, 20 mrad).
WEDGE = jd.DamperShape(70.0, 50.0, 0.0, 0.6, None, 0.8)
PATH = jd.interblade_motion(120.0, 20.0, 100.0, 10.0)


def cycle(shape=WEDGE, mu=0.5, psi=20.0, motion=PATH, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        return jd.elliptic_cycle(shape, mu, psi, motion, CONTACTS, **kw)


def forces_at(period, s_a, tau):
    """(N, T) of the period's tract that holds tau (virtual N of open pads included)."""
    starts, ends = np.asarray(period.p0), np.asarray(period.p0 + period.dp)
    k = int(np.flatnonzero((starts <= tau) & (ends >= tau) & np.asarray(period.active))[0])
    d = s_a * np.array([np.cos(tau) - np.cos(starts[k]), -(np.sin(tau) - np.sin(starts[k]))])
    return (np.asarray(period.N0[k]) + d @ np.asarray(period.dN[k]),
            np.asarray(period.T0[k]) + d @ np.asarray(period.dT[k]), np.asarray(period.state[k]))


def test_the_candidate_table_has_every_weak_and_strong_choice():
    weak = candidate_table(4)
    assert weak.shape == (16, 4)
    assert len({tuple(w) for w in weak}) == 16  # no repeats: every choice per pad, once


def _wedge_tract_starts():
    """(the wedge's cycle, its pads, its ellipse, the 81 stick/slip/open sets, no event): what
    the proposals' contracts are checked on at every tract start of the cycle."""
    from itertools import product

    from jaxdamp.conventions import travel_mm
    from jaxdamp.paths import Ellipse
    from jaxdamp.tract import STICK

    sh, mu, contacts, load = prepare_inputs(WEDGE, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)
    pads = path_pads(sh, mu, contacts, load, path_parts(PATH))
    path = Ellipse(travel_mm(jnp.asarray(20.0), load.q_star))
    sets = jnp.asarray(list(product((STICK, SLIP, OPEN), repeat=4)))
    return cycle(), pads, path, sets, jnp.full(4, -1)


def test_a_consistent_proposal_is_the_choice_among_every_set():
    """`propose`'s contract, which lets the engine skip the choice among every set: at every
    tract start of the wedge's cycle (its pads open, close, stick and slip), each of the 81
    stick/slip/open sets, proposed unchanged, is either not consistent or exactly `choose`'s
    choice; and the chosen set itself is a consistent proposal, except where a pad closes
    slipping (not proposed: its slip direction is not T's; the choice among every set takes
    those). An event changes its pad as its kind says (slips, opens, sticks where it closed or
    its slip reversed)."""
    from jaxdamp.choice import choose, propose
    from jaxdamp.tract import STICK

    c, pads, path, sets, no_event = _wedge_tract_starts()

    @jax.jit
    def judged(N, T, p0):
        heading, ahead = path.heading(pads, p0), path.ahead(p0)
        full = choose(pads, N, T, heading, ahead)
        prop = jax.vmap(lambda st: propose(pads, N, T, heading, ahead,
                                           (st, no_event, jnp.array(True))))(sets)
        same = ((prop.closed == full.closed[None]) & (prop.slipping == full.slipping[None])).all(1)
        closing_slip = jnp.any(full.slipping & (jnp.abs(N) <= 1e-10))
        return prop.consistent, same & full.consistent, closing_slip

    period = c.period
    starts = np.flatnonzero(np.asarray(period.active))
    closing = 0
    for k in starts:
        ok, same, closing_slip = (np.asarray(x) for x in judged(period.N0[k], period.T0[k],
                                                                  period.p0[k]))
        assert not np.any(ok & ~same), k
        assert np.any(ok & same) or closing_slip, k
        closing += int(closing_slip)
    assert closing < len(starts) // 4  # most tracts are proposed right
    state = jnp.asarray([STICK, SLIP, STICK, OPEN])
    kinds = jnp.asarray([0, 4, 2, 3])  # slips up, slip reverses, opens, closes
    heading = path.heading(pads, 0.0)
    got = propose(pads, period.N0[0], period.T0[0], heading, None, (state, kinds, jnp.array(True)))
    assert np.array_equal(np.asarray(got.closed), [True, True, False, True])
    assert np.array_equal(np.asarray(got.slipping), [True, False, False, False])


def test_a_consistent_second_proposal_is_the_choice_among_every_set():
    """`propose_again`'s contract, as `propose`'s: at every tract start of the wedge's cycle, from
    each of the 81 stick/slip/open sets proposed first and not consistent, the second proposal
    (the failing pads changed) is either not consistent or exactly `choose`'s choice; and it
    finds the choice where a pad closes slipping, which no first proposal does."""
    from jaxdamp.choice import choose, propose, propose_again

    c, pads, path, sets, no_event = _wedge_tract_starts()

    @jax.jit
    def judged(N, T, p0):
        heading, ahead = path.heading(pads, p0), path.ahead(p0)
        full = choose(pads, N, T, heading, ahead)

        def second(st):
            first = propose(pads, N, T, heading, ahead, (st, no_event, jnp.array(True)))
            return first.consistent, propose_again(pads, N, T, heading, ahead, first, True)

        first_ok, again = jax.vmap(second)(sets)
        same = ((again.closed == full.closed[None])
                & (again.slipping == full.slipping[None])).all(1)
        closing_slip = jnp.any(full.slipping & (jnp.abs(N) <= 1e-10))
        return again.consistent & ~first_ok, same & full.consistent, closing_slip

    period = c.period
    found = closing_found = 0
    for k in np.flatnonzero(np.asarray(period.active)):
        ok, same, closing_slip = (np.asarray(x) for x in judged(period.N0[k], period.T0[k],
                                                                  period.p0[k]))
        assert not np.any(ok & ~same), k
        found += int(np.sum(ok))
        closing_found += int(closing_slip and np.any(ok))
    assert found > 0 and closing_found > 0  # the second proposal does find sets, closing ones too


def test_a_wedge_with_opening_pads_agrees_with_the_time_marcher():
    from jaxdamp.baselines import march_ellipse

    ec = cycle()
    assert jd.RESULTS.name_of(ec.status) == "ok"
    opened = np.asarray(ec.open_fraction)
    assert np.sum(opened > 0.1) >= 2  # pads do open: the case tests what it claims
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        tm = march_ellipse(WEDGE, 0.5, 20.0, PATH, CONTACTS, n_steps=4000, periods=3)
    assert jd.RESULTS.name_of(tm.status) == "ok" and float(tm.closure) < 1e-9
    scale = max(abs(float(ec.k_re)), abs(float(ec.k_im)))
    # The tolerances: k within 1e-4 of its scale, fractions within the marcher's step
    # (two steps of 1/4000: a sample counts as open or not).
    assert_tree_allclose((tm.k_re, tm.k_im), (ec.k_re, ec.k_im), rtol=0, atol=1e-4 * scale)
    assert_tree_allclose(tm.open_fraction, ec.open_fraction, rtol=0, atol=2 / 4000)
    assert_tree_allclose(tm.slip_fraction, ec.slip_fraction, rtol=0, atol=2 / 4000)


def test_a_wedge_started_from_its_steady_state_repeats_it_at_once():
    """An explicit start (N, T of the four pads at tau = 0) taken from the steady cycle is its
    fixed point: the same cycle, pads opening and closing included, after one period."""
    ec = cycle()
    start = (np.asarray(ec.period.N0[0]), np.asarray(ec.period.T0[0]))
    assert np.all(start[0] > 0.0)  # every pad closed at tau = 0, as an explicit start must be
    ex = cycle(initial=start)
    assert jd.RESULTS.name_of(ex.status) == "ok" and int(ex.periods) == 1
    assert_tree_allclose((ex.k_re, ex.k_im, ex.open_fraction, ex.slip_fraction),
                         (ec.k_re, ec.k_im, ec.open_fraction, ec.slip_fraction), rtol=1e-12,
                         atol=1e-12)
    with pytest.raises(ValueError, match=r"one force per pad \(R1, R2, L1, L2\), shape \(4,\)"):
        cycle(initial=(start[0][:3], start[1][:3]))


def test_open_pads_carry_nothing_and_every_tract_balances_the_damper():
    ec = cycle()
    sh, mu, c, load = prepare_inputs(WEDGE, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)
    pads = path_pads(sh, mu, c, load, path_parts(ec.motion))
    a, cc = np.asarray(pads.a), np.asarray(pads.c)
    s_a = 20.0 * 100.0 / 1e3
    period = ec.period
    act = np.asarray(period.active)
    assert abs(float(np.sum(np.asarray(period.dp)[act])) - 2 * np.pi) < 1e-12
    seen_open = False
    for k in np.flatnonzero(act):
        t0, t1 = float(period.p0[k]), float(period.p0[k] + period.dp[k])
        for t in (t0, 0.5 * (t0 + t1), t1):
            N, T, state = forces_at(period, s_a, t)
            is_open = state == OPEN
            seen_open |= bool(np.any(is_open))
            assert np.all(N[is_open] <= 1e-10) and np.all(T[is_open] == 0.0)  # a gap, no force
            assert np.all(N[~is_open] >= -1e-10)
            assert np.all(np.abs(T) <= 0.5 * np.maximum(N, 0.0) + 1e-10)
            N_on = np.where(is_open, 0.0, N)
            residual = -N_on @ a + T @ cc + CENTRIFUGAL_LOAD
            assert np.max(np.abs(residual)) <= 1e-12
            slipping = state == SLIP
            assert_tree_allclose(np.abs(T[slipping]), 0.5 * N[slipping], rtol=1e-12, atol=1e-14)
    assert seen_open


@pytest.mark.parametrize("phi,psi", [(120.0, 20.0), (180.0, 20.0), (30.0, 20.0)])
def test_work_per_cycle_is_the_energy_dissipated_at_the_pads_with_pads_open(phi, psi):
    ec = cycle(psi=psi, motion=jd.interblade_motion(phi, 20.0, 100.0, 10.0))
    assert jd.RESULTS.name_of(ec.status) == "ok" and float(np.max(ec.open_fraction)) > 0.0
    assert_tree_allclose(jnp.sum(ec.energy), ec.work, rtol=1e-9, atol=0.0)
    assert np.all(np.asarray(ec.energy) >= -1e-9 * float(ec.work))


def test_a_mirror_symmetric_wedge_on_the_in_phase_path_has_mirror_symmetric_forces():
    """Mirroring the damper about the vertical through D swaps R1 <-> L1 and R2 <-> L2 and turns
    the relative platform motion dv into -dv: the in-phase cycle at tau is the mirror of the
    cycle at tau + pi."""
    shape = jd.DamperShape(60.0, 60.0, 0.0, 0.8, None, 0.8)
    ec = cycle(shape, psi=10.0, motion=jd.in_phase_motion(100.0), initial="gross_slip")
    assert jd.RESULTS.name_of(ec.status) == "ok" and float(ec.k_im) > 0.0
    assert pad_names(shape) == ("R1", "R2", "L1", "L2")
    swap = [2, 3, 0, 1]
    for tau in np.linspace(0.1, np.pi - 0.1, 7):
        N, T, _ = forces_at(ec.period, 1.0, tau)
        N_m, T_m, _ = forces_at(ec.period, 1.0, tau + np.pi)
        assert_tree_allclose((N, T), (N_m[swap], T_m[swap]), rtol=0, atol=1e-10)


@pytest.mark.slow  # 22 worker-s (2026-11-26); the in-phase mirror test above stays by default
def test_a_mirror_symmetric_wedge_runs_plus_and_minus_phi_as_mirror_images():
    """The mirror about the vertical through D maps the path at +phi onto the path at -phi (shifted
    in time), R1 <-> L1 and R2 <-> L2: in gross slip, where the history is forgotten, k is the same
    and the open fractions swap flanks (the table of docs/motions.md shows it at 10 mrad)."""
    shape = jd.DamperShape(60.0, 60.0, 0.0, 0.8, None, 0.8)
    r = jd.interblade_sweep(shape, 0.5, 10.0, [90.0, -90.0, 45.0], 20.0, 10.0, CONTACTS)
    assert [jd.RESULTS.name_of(s) for s in r.status[:2]] == ["ok", "ok"]
    opened = np.asarray(r.open_fraction)
    assert opened[0, 0] > 0.3  # R1 opens for a third of the period: the check means something
    assert_tree_allclose((r.k_re[1], r.k_im[1]), (r.k_re[0], r.k_im[0]), rtol=1e-9, atol=0.0)
    assert_tree_allclose(opened[1], opened[0][[2, 3, 0, 1]], rtol=0, atol=1e-9)


def test_the_curved_flat_damper_on_the_engine_keeps_its_straight_path_numbers():
    """The same engine runs the paper's damper: in-phase as an ellipse of zero width, it gives the
    straight-path solver's k (jaxdamp.amplitude) to 1e-10 of its scale."""
    shape = jd.family_shape("74R")
    sh, mu, c, load = prepare_inputs(shape, 0.3, CONTACTS, jd.LoadCase())
    line = jd.in_phase_motion(100.0)
    flat = line._replace(quadrature=jnp.zeros(3))
    got = jax.jit(elliptic_kernel, static_argnames="initial")(sh, mu, c, load, jnp.asarray(3.0), flat,
                                                             initial="gross_slip")
    ref = jd.amplitude_cycle(shape, 0.3, 3.0, CONTACTS, initial="gross_slip")
    scale = max(abs(float(ref.k_re)), abs(float(ref.k_im)))
    assert_tree_allclose((got.k_re, got.k_im), (ref.k_re, ref.k_im), rtol=0, atol=1e-10 * scale)
    assert float(jnp.max(got.open_fraction)) == 0.0


def test_a_wedge_is_refused_where_only_the_curved_flat_damper_is_computed():
    for refuses in (lambda: jd.base_cycle(WEDGE, 0.5), lambda: jd.full_slip_statics(WEDGE, 0.5),
                    lambda: jd.stack_designs([WEDGE, WEDGE], 0.5),
                    lambda: jd.amplitude_curves(WEDGE, 0.5, [1.0, 2.0])):
        with pytest.raises(ValueError, match=r"^br2_over_hr: this function computes the curved-flat"):
            refuses()
    with pytest.raises(ValueError, match=r"^br2_over_hr must be in \(0, 1\]"):
        jd.elliptic_cycle(WEDGE._replace(br2_over_hr=1.5), 0.5, 2.0, PATH)
    with pytest.raises(ValueError, match=r"^kn: one value, or one per pad \(4 for this damper\)"):
        jd.elliptic_cycle(WEDGE, 0.5, 2.0, PATH, jd.Contacts(np.ones(3) * 2e4, 3580.0))


def test_the_interblade_sweep_is_one_program_of_the_per_angle_cycles():
    phis = [0.0, 60.0, 180.0]
    sweep = jd.interblade_sweep(WEDGE, 0.5, 10.0, phis, 20.0, 10.0, CONTACTS)
    assert sweep.k_im.shape == (3,) and sweep.open_fraction.shape == (3, 4)
    for i, phi in enumerate(phis):
        one = cycle(psi=10.0, motion=jd.interblade_motion(phi, 20.0, 100.0, 10.0))
        assert jd.RESULTS.name_of(sweep.status[i]) == jd.RESULTS.name_of(one.status)
        scale = max(abs(float(one.k_re)), abs(float(one.k_im)))
        assert_tree_allclose((sweep.k_re[i], sweep.k_im[i]), (one.k_re, one.k_im), rtol=0,
                             atol=1e-12 * scale)
        assert_tree_allclose(sweep.open_fraction[i], one.open_fraction, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match=r"^phis_deg must be in \[-360, 360\]"):
        jd.interblade_sweep(WEDGE, 0.5, 10.0, [0.0, 400.0], 20.0, 10.0, CONTACTS)
    for text in ("x", ["x", 1.0]):  # numpy's "could not convert string to float" before
        with pytest.raises(ValueError, match=r"^phis_deg must be a finite number in \[-360, 360\]"):
            jd.interblade_sweep(WEDGE, 0.5, 10.0, text, 20.0, 10.0, CONTACTS)


@pytest.mark.slow  # the forward derivative program of the wedge's elliptic kernel
def test_derivatives_through_opening_pads_match_central_differences():
    """d k / d(phi, mu) by forward mode through the events (opening and closing included),
    against central differences of the same program, away from switches."""
    sh, _, c, load = prepare_inputs(WEDGE, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)

    def k_of(x):
        phi, mu = x[0], x[1]
        e = jnp.exp(1j * jnp.deg2rad(phi))
        direction = jnp.stack([20.0e-3 * (e - 1.0), 50e-3 * (e + 1.0), -(e - 1.0)])
        motion = jd.Motion(jnp.real(direction), jnp.asarray(10.0), jnp.imag(direction))
        ec = elliptic_kernel(sh, mu, c, load, jnp.asarray(20.0), motion)
        return jnp.stack([ec.k_re, ec.k_im])

    x = jnp.array([120.0, 0.5])
    f = jax.jit(k_of)
    jac = jax.jit(jax.jacfwd(k_of))(x)
    assert np.all(np.isfinite(np.asarray(jac)))
    for i, h in enumerate((1e-4, 1e-6)):
        e = jnp.zeros(2).at[i].set(h)
        fd = (f(x + e) - f(x - e)) / (2 * h)
        assert_tree_allclose(jac[:, i], fd, rtol=1e-5, atol=1e-6 * float(jnp.max(jnp.abs(f(x)))))


@pytest.mark.slow  # the reverse derivative program of the wedge's elliptic kernel
def test_reverse_mode_through_opening_pads_matches_central_differences():
    """d k_Im / d(theta_L, kn, kt) by reverse mode (the masked scans' transpose) for the wedge with
    pads that open, against central differences, away from switches."""
    _, mu, c, load = prepare_inputs(WEDGE, 0.5, CONTACTS, jd.LoadCase(), wedge_ok=True)

    def k_im(x):
        shape = jd.DamperShape(x[0], 50.0, 0.0, 0.6, None, 0.8)
        contacts = jd.Contacts(x[1] * jnp.ones(4), x[2] * jnp.ones(4))
        return elliptic_kernel(shape, mu, contacts, load, jnp.asarray(20.0), PATH).k_im

    x = jnp.array([70.0, 17900.0, 3580.0])
    grad = jax.jit(jax.grad(k_im))(x)
    f = jax.jit(k_im)
    assert np.all(np.isfinite(np.asarray(grad)))
    for i, h in enumerate((1e-4, 1e-1, 1e-2)):
        e = jnp.zeros(3).at[i].set(h)
        fd = (f(x + e) - f(x - e)) / (2 * h)
        assert_tree_allclose(grad[i], fd, rtol=1e-5, atol=1e-9 * float(abs(f(x))))
