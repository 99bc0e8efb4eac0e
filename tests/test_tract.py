"""The reduced tract solve against the plain one: build K_S and its load for each state set and
solve the 3x3 system (the formulation the reduction replaces), on the paper's shapes and random
ones, every candidate set and both friction signs."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import tract
from jaxdamp.cycle import mechanics
from jaxdamp.params import Contacts, LoadCase

from helpers import assert_tree_allclose


def plain_rates(mech, slipping, signs, direction):
    """The unreduced solve, and the condition number of its K_S."""
    K = jax.jacfwd(lambda q: _stiffness_action(mech, slipping, signs, q))(jnp.zeros(3))
    r = tract.plain_tract_rates(mech, slipping, signs, direction)
    return r.dN, r.dT, r.dslip, jnp.linalg.cond(K)


def _stiffness_action(mech, slipping, signs, dq):
    """-(sum of contact force increments on the damper) for a damper motion dq, platforms fixed:
    K_S dq, from the contact laws alone (no assembled matrix)."""
    dN = mech.kn * (mech.a @ dq)
    dT = jnp.where(slipping, signs * mech.mu * dN, -mech.kt * (mech.c @ dq))
    return jnp.sum(dN[:, None] * mech.a - dT[:, None] * mech.c, axis=0)


# Units of round-off of one 3x3 tract solve with its assembly and recovery (see the test).
ROUNDOFF_UNITS = 32


def cases():
    rng = np.random.default_rng(3)
    out = [(jd.family_shape(n), 0.5, 1.0) for n in ("60sym", "74R", "74L", "90L")]
    for _ in range(12):
        shape = jd.DamperShape(*rng.uniform([35, 35, -0.3], [89, 89, 0.4]), rng.uniform(0.3, 1.0))
        out.append((shape, rng.uniform(0.1, 0.9), rng.uniform(0.05, 10.0)))
    return out


@pytest.mark.slow  # 42 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("shape, mu, kt_over_kn", cases())
def test_reduced_solve_matches_plain_solve(shape, mu, kt_over_kn):
    contacts = Contacts(jd.REFERENCE_KN, kt_over_kn * jd.REFERENCE_KN)
    mech = mechanics(jax.tree_util.tree_map(jnp.asarray, shape), jnp.asarray(mu), contacts, LoadCase())
    rng = np.random.default_rng(int(1e3 * mu))
    for direction in (-1.0, 1.0):
        signs = jnp.asarray(rng.choice([-1.0, 1.0], 3))
        every = tract.candidate_rates(mech, signs, direction)
        for k, slipping in enumerate(tract.CANDIDATE_SETS):
            dN, dT, dslip, cond = plain_rates(mech, slipping, signs, direction)
            assert bool(every.ok[k])
            # Round-off from the problem's magnitudes. The rates are forces per mm of travel
            # (units of F_D), each the difference of contact-stiffness terms k * (platform travel
            # - damper motion): their scale before cancellation is the stiffest contact's k_max
            # per mm, not the (possibly cancelled) rates themselves (a rate of 1e-15 has the
            # rounding of 20 F_D/mm). A 3x3 solve loses cond(K_S) times the unit round-off, with
            # a factor of a few tens for its 3n-operation LU, assembling K_S and its load, and
            # recovering dN, dT from dq: ROUNDOFF_UNITS. A slip rate adds dT / kt (k_max / kt_min
            # of that force round-off) to the travel's unit scale and its own size.
            k_max = float(max(np.max(mech.kn), np.max(mech.kt)))
            unit = ROUNDOFF_UNITS * np.finfo(float).eps * float(cond)
            tol = unit * k_max
            slip_tol = unit * (1.0 + float(jnp.max(jnp.abs(dslip))) + k_max / float(np.min(mech.kt)))
            got = jax.tree_util.tree_map(lambda x, k=k: x[k], every)
            assert_tree_allclose(got.dN, dN, rtol=0, atol=tol)
            assert_tree_allclose(got.dT, dT, rtol=0, atol=tol)
            assert_tree_allclose(got.dslip, dslip, rtol=0, atol=slip_tol)


def test_singular_set_is_flagged_not_nan():
    # Parallel vertical flanks: all-slip leaves the damper free to slide vertically.
    shape = jax.tree_util.tree_map(jnp.asarray, jd.DamperShape(90.0, 90.0, 0.0, 0.8))
    mech = mechanics(shape, jnp.asarray(0.5), Contacts(), LoadCase())
    signs = jnp.array([1.0, -1.0, -1.0])
    every = tract.candidate_rates(mech, signs, 1.0)
    for leaf in every:
        assert np.all(np.isfinite(np.asarray(leaf)))
    conds = [float(plain_rates(mech, s, signs, 1.0)[3]) for s in tract.CANDIDATE_SETS]
    singular = np.array(conds) > 1e12
    assert singular[7] and not singular[:7].any()
    np.testing.assert_array_equal(np.asarray(every.ok), ~singular)
