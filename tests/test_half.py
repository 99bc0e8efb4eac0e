"""The tract engine (`jaxdamp.half`): one half of a cycle, run to gross slip or over a travel.

References: equilibrium of the rigid damper and the friction cone at every tract (physics), the
unreduced 3x3 solve of each tract's state set (`tract.plain_tract_rates`, the formulation the engine's
reduced solve replaces), and the identity that stopping a half earlier or later does not change the
path it has run."""

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import tract
from jaxdamp.amplitude import gross_slip_state
from jaxdamp.cycle import equilibrium_residual, mechanics
from jaxdamp.half import run_half
from jaxdamp.params import Contacts, LoadCase

from helpers import assert_tree_allclose

MAX_TRACTS = 8
CASES = [("60sym", 0.5), ("74R", 0.3), ("90L", 0.7)]


@partial(jax.jit, static_argnames=("loop",))
def to_gross_slip(mech, N, T, loop="scan"):
    return run_half(mech, N, T, -1.0, max_tracts=MAX_TRACTS, loop=loop)


@partial(jax.jit, static_argnames=("loop",))
def over_travel(mech, N, T, travel, loop="scan"):
    return run_half(mech, N, T, -1.0, travel, max_tracts=MAX_TRACTS, loop=loop)


def start(name, mu):
    shape = jd.family_shape(name)
    N, T, ok = gross_slip_state(shape, mu)
    assert bool(ok)
    return mechanics(shape, mu, Contacts(), LoadCase()), N, T


@pytest.mark.parametrize("name, mu", CASES)
def test_a_half_stopped_later_runs_the_same_path_then_a_constant_force_stretch(name, mu):
    mech, N, T = start(name, mu)
    g = to_gross_slip(mech, N, T)
    assert jd.RESULTS.name_of(g.status) == "ok" and bool(g.gross_slip)
    n = int(np.sum(g.active))
    assert n >= 2 and not np.any(g.stretch)
    extra = 0.5 * float(g.span)
    lim = over_travel(mech, N, T, g.span + extra)
    assert jd.RESULTS.name_of(lim.status) == "ok" and bool(lim.gross_slip)
    assert np.array_equal(np.asarray(lim.active), np.arange(MAX_TRACTS) <= n)
    assert np.array_equal(np.asarray(lim.stretch), np.arange(MAX_TRACTS) == n)
    head = lambda h: (h.dv[:n], h.N0[:n], h.T0[:n], h.dN[:n], h.dT[:n], h.state[:n])  # noqa: E731
    assert_tree_allclose(head(lim), head(g), rtol=1e-12, atol=1e-15)
    assert_tree_allclose(np.asarray(float(lim.dv[n]), float),
                         np.asarray(extra, float),
                         rtol=1e-12, atol=0.0)
    assert np.all(np.asarray(lim.dN[n]) == 0.0) and np.all(np.asarray(lim.dT[n]) == 0.0)
    assert_tree_allclose((lim.N_end, lim.T_end, lim.gross_dslip), (g.N_end, g.T_end, g.gross_dslip),
                         rtol=1e-12, atol=1e-15)
    assert_tree_allclose(np.asarray(float(lim.span), float),
                         np.asarray(float(g.span) + extra, float),
                         rtol=1e-12, atol=0.0)
    # Stopped earlier, inside the second tract: the first tract whole, then part of the second.
    cut = float(g.dv[0]) + 0.25 * float(g.dv[1])
    early = over_travel(mech, N, T, cut)
    assert int(np.sum(early.active)) == 2 and not bool(early.gross_slip)
    assert_tree_allclose(np.asarray(np.asarray(early.dv[:2]), float),
                         np.asarray([float(g.dv[0]), 0.25 * float(g.dv[1])], float),
                         rtol=1e-12, atol=0.0)
    assert_tree_allclose(np.asarray(np.asarray(early.N_end), float),
                         np.asarray(np.asarray(g.N0[1] + 0.25 * g.dv[1] * g.dN[1]), float),
                         rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("name, mu", CASES)
def test_every_tract_balances_the_damper_and_keeps_the_cone(name, mu):
    mech, N, T = start(name, mu)
    for half in (to_gross_slip(mech, N, T), over_travel(mech, N, T, 0.7e-3)):
        assert float(equilibrium_residual(mech, half)) <= 1e-12
        act = np.asarray(half.active)
        N0, T0 = np.asarray(half.N0)[act], np.asarray(half.T0)[act]
        N1 = N0 + np.asarray(half.dN)[act] * np.asarray(half.dv)[act, None]
        T1 = T0 + np.asarray(half.dT)[act] * np.asarray(half.dv)[act, None]
        for Nx, Tx in ((N0, T0), (N1, T1)):
            assert np.all(Nx > 0.0)
            assert np.all(np.abs(Tx) <= mu * Nx + 1e-12)
        state = np.asarray(half.state)[act]
        sliding = (state == tract.SLIP) | (state == tract.BACKSLIDE)
        assert_tree_allclose(np.asarray(np.abs(T1[sliding]), float),
                             np.asarray(mu * N1[sliding], float),
                             rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("name, mu", CASES)
def test_tract_rates_are_those_of_the_unreduced_solve_of_their_state_set(name, mu):
    mech, N, T = start(name, mu)
    half = to_gross_slip(mech, N, T)
    for k in np.flatnonzero(np.asarray(half.active)):
        state = np.asarray(half.state[k])
        slipping = jnp.asarray((state == tract.SLIP) | (state == tract.BACKSLIDE))
        signs = jnp.where(half.T0[k] >= 0.0, 1.0, -1.0)
        r = tract.plain_tract_rates(mech, slipping, signs, -1.0)
        scale = float(jnp.max(jnp.abs(r.dN)))
        assert_tree_allclose((half.dN[k], half.dT[k]), (r.dN, r.dT), rtol=1e-9, atol=1e-12 * scale)


def ran(half):
    """The tracts a half ran and where it ended (the rows after its last tract are whatever the
    loop left there: zeros for "while", the masked steps' inputs for "scan")."""
    rows = ("dv", "N0", "T0", "dN", "dT", "dslip", "state", "stretch", "slack")
    act = np.asarray(half.active)
    return ({f: np.asarray(getattr(half, f))[act] for f in rows},
            half._replace(**{f: half.active for f in rows}))


def test_while_and_scan_run_the_same_halves():
    mech, N, T = start("74R", 0.3)
    assert_tree_allclose(ran(to_gross_slip(mech, N, T, "while")), ran(to_gross_slip(mech, N, T, "scan")),
                         rtol=1e-13, atol=1e-16)
    assert_tree_allclose(ran(over_travel(mech, N, T, 0.9e-3, "while")),
                         ran(over_travel(mech, N, T, 0.9e-3, "scan")), rtol=1e-13, atol=1e-16)


def test_an_open_start_is_liftoff_with_no_tract():
    mech, N, T = start("60sym", 0.5)
    N = N.at[1].set(0.0)
    T = T.at[1].set(0.0)
    for half in (to_gross_slip(mech, N, T), over_travel(mech, N, T, 1e-3)):
        assert jd.RESULTS.name_of(half.status) == "liftoff"
        assert not np.any(half.active) and float(half.span) == 0.0
    assert "status=liftoff" in repr(half)
