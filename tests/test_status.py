"""RESULTS: codes, messages, promotion order, and the statuses the solver reports."""

import jax.numpy as jnp
import numpy as np

import jaxdamp as jd
from jaxdamp.status import RESULTS, ok_status


def test_promote_keeps_the_first_problem():
    s = ok_status((3,))
    s = RESULTS.promote(s, jnp.array([True, False, False]), RESULTS.liftoff)
    s = RESULTS.promote(s, jnp.array([True, True, False]), RESULTS.not_converged)
    assert list(np.asarray(s)) == [RESULTS.liftoff, RESULTS.not_converged, RESULTS.ok]


def test_every_code_has_a_name_and_a_message():
    for code in RESULTS:
        assert RESULTS.name_of(jnp.int32(code)) == code.name
        assert RESULTS.message(code)
    assert bool(RESULTS.valid(RESULTS.shakedown)) and not bool(RESULTS.valid(RESULTS.liftoff))


def test_solver_statuses():
    ok = jd.base_cycle(jd.family_shape("60sym"), 0.5)
    lift = jd.base_cycle(jd.family_shape("74L"), 0.7)  # the left resultant leaves L1-L2
    assert RESULTS.name_of(ok.status) == "ok" and bool(ok.converged)
    assert RESULTS.name_of(lift.status) == "liftoff" and bool(lift.liftoff)
